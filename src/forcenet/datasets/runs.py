"""Which run a file belongs to: the system, dimension and simulation settings a snapshot (or the analysis made
from it) records, compared with those of the run it is read for (issue 27: a 2d_linear snapshot copied over a
2d_hertz one is refused, naming the file and the attribute). Files written before this check existed are checked
too: the fingerprint is computed from the `config` attribute every file records."""
from __future__ import annotations

import hashlib
import json
import os
import re
from pathlib import Path
from typing import TYPE_CHECKING, Any, Mapping

from forcenet.datasets.paths import RHO_DECIMALS, realization_index

if TYPE_CHECKING:  # annotations only: the workflow imports this module when it is parsed (no xarray there)
    import xarray as xr

#: the attributes `run_expectation` gives and `run_mismatch` compares, in that order
RUN_ATTRS = ("system", "dimension", "simulation_sha256")
#: a snapshot's file name and its run's folder (`forcenet.datasets.paths.snapshot`)
RHO_FILE = re.compile(r"rho(\d+\.\d+)\.nc")
REALIZATION_DIR = re.compile(r"r\d\d+")


def config_sha256(config: Mapping[str, Any]) -> str:
    """A stable hash of the whole config (sorted JSON), stored in every output file."""
    return hashlib.sha256(json.dumps(config, sort_keys=True, default=str).encode()).hexdigest()


def simulation_params(config: Mapping[str, Any], system: str) -> dict[str, Any]:
    """What a compression run depends on: its own system entry, the seed and (P1 units) the material — not the
    analysis keys or other systems. Snakemake reruns a simulation when these change; a staged run resumes only
    under the same ones."""
    entry = config["systems"][system]
    params = {"system": entry, "seed": config["seed"]}
    if entry.get("stiffness") == "material":
        params["material"] = config["material"]
    return params


def simulation_sha256(config: Mapping[str, Any], system: str) -> str:
    """The fingerprint of what a system's snapshots depend on (`simulation_params`: its own entry, the seed and the
    material it uses; not the analysis keys or other systems)."""
    return config_sha256(simulation_params(config, system))


def run_expectation(spec: Any, config: Mapping[str, Any]) -> dict[str, Any]:
    """What a snapshot of the system `spec` (a `forcenet.systems.SystemSpec` or `ImportedSystem`: its `name`,
    `dimension` and `rho_grid`) under `config` must record: its system, dimension and `simulation_sha256`; and how
    far a state's measured ρ may lie from the grid ρ in its file name (`rho_tolerance`: half the smallest step of
    the system's grid, at least the rounding of a file label; `state_expectation`)."""
    grid = sorted(spec.rho_grid)
    steps = [b - a for a, b in zip(grid, grid[1:]) if b > a]
    rounding = 0.5 * 10.0 ** -RHO_DECIMALS
    return {"system": spec.name, "dimension": int(spec.dimension),
            "simulation_sha256": simulation_sha256(config, spec.name),
            "rho_tolerance": max(0.5 * min(steps), rounding) + 1e-12 if steps else 1.0}


def run_mismatch(ds: xr.Dataset, expect: Mapping[str, Any]) -> str:
    """Why snapshot `ds` does not belong to the run `expect` describes ("" when it does): its recorded `system`,
    `dimension`, or the fingerprint of the simulation settings in its recorded `config` (`simulation_sha256`,
    computed from the recorded config, so snapshots written before this check existed are checked too)."""
    recorded_system = str(ds.attrs["system"])
    if recorded_system != expect["system"]:
        return f"global attribute 'system' is '{recorded_system}', but this run is '{expect['system']}'"
    if int(ds.attrs["dimension"]) != int(expect["dimension"]):
        return (f"global attribute 'dimension' is {ds.attrs['dimension']}, but system '{expect['system']}' "
                f"has dimension {expect['dimension']}")
    try:
        recorded = simulation_sha256(json.loads(ds.attrs["config"]), recorded_system)
    except (KeyError, TypeError, ValueError):
        recorded = "unreadable"
    if recorded != expect["simulation_sha256"]:
        return (f"global attribute 'config' records other settings for system '{recorded_system}' than this run's "
                f"config (simulation fingerprint {recorded[:12]}, expected {expect['simulation_sha256'][:12]}): "
                "the snapshot belongs to another run")
    if "realization" in expect and int(ds.attrs["realization"]) != int(expect["realization"]):
        return (f"global attribute 'realization' is {ds.attrs['realization']}, but this file is of realization "
                f"{expect['realization']}: the snapshot belongs to another run")
    if "rho_label" in expect and abs(float(ds["rho"]) - float(expect["rho_label"])) > expect["rho_tolerance"]:
        return (f"its packing fraction is {float(ds['rho']):.4f}, but this file is the state at rho = "
                f"{expect['rho_label']}: the snapshot is another state of the run")
    return ""


def state_expectation(expect: Mapping[str, Any], path: str | os.PathLike) -> dict[str, Any]:
    """`expect` (`run_expectation`) for the snapshot file at `path` (``…/r{NN}/rho{ρ}.nc``, as
    `forcenet.datasets.paths.snapshot` names it): also its realization and the ρ its name gives, so that another
    realization's snapshot or another state of the run copied in its place is refused. A path named otherwise is
    checked as the run's only."""
    path = Path(path)
    match = RHO_FILE.fullmatch(path.name)
    if match is None or not REALIZATION_DIR.fullmatch(path.parent.name):
        return dict(expect)
    return {**expect, "realization": realization_index(path.parent.name), "rho_label": match.group(1)}

