"""Which run a file belongs to: the system, dimension and simulation settings a snapshot (or the analysis made
from it) records, compared with those of the run it is read for (issue 27: a 2d_linear snapshot copied over a
2d_hertz one is refused, naming the file and the attribute). Files written before this check existed are checked
too: the fingerprint is computed from the `config` attribute every file records."""
from __future__ import annotations

import json
from typing import TYPE_CHECKING, Any, Mapping

if TYPE_CHECKING:  # annotations only: the workflow imports this module when it is parsed (no xarray there)
    import xarray as xr

#: the attributes `run_expectation` gives and `run_mismatch` compares, in that order
RUN_ATTRS = ("system", "dimension", "simulation_sha256")


def simulation_sha256(config: Mapping[str, Any], system: str) -> str:
    """The fingerprint of what a system's snapshots depend on (`forcenet.systems.simulation_params`: its own
    entry, the seed and the material it uses; not the analysis keys or other systems)."""
    from forcenet.systems import config_sha256, simulation_params

    return config_sha256(simulation_params(config, system))


def run_expectation(config: Mapping[str, Any], system: str) -> dict[str, Any]:
    """What a snapshot of `system` under `config` must record: its system, dimension and `simulation_sha256`."""
    return {"system": system, "dimension": int(config["systems"][system]["dimension"]),
            "simulation_sha256": simulation_sha256(config, system)}


def run_mismatch(ds: xr.Dataset, expect: Mapping[str, Any]) -> str:
    """Why snapshot `ds` does not belong to the run `expect` describes ("" when it does): its recorded `system`,
    `dimension`, or the fingerprint of the simulation settings in its recorded `config` (`simulation_sha256`,
    computed from the recorded config, so snapshots written before this check existed are checked too)."""
    recorded_system = str(ds.attrs.get("system"))
    if recorded_system != expect["system"]:
        return f"global attribute 'system' is '{recorded_system}', but this run is '{expect['system']}'"
    if int(ds.attrs.get("dimension", -1)) != int(expect["dimension"]):
        return (f"global attribute 'dimension' is {ds.attrs.get('dimension')}, but system '{expect['system']}' "
                f"has dimension {expect['dimension']}")
    try:
        recorded = simulation_sha256(json.loads(ds.attrs["config"]), recorded_system)
    except (KeyError, TypeError, ValueError):
        recorded = "unreadable"
    if recorded != expect["simulation_sha256"]:
        return (f"global attribute 'config' records other settings for system '{recorded_system}' than this run's "
                f"config (simulation fingerprint {recorded[:12]}, expected {expect['simulation_sha256'][:12]}): "
                "the snapshot belongs to another run")
    return ""

