"""Compression surveys: run one system under config overrides and tabulate each snapshot's state.

The measurements behind `docs/decisions.md` (damping model and time step), `docs/fidelity.md` (which quick setting
moves ρ_J most per CPU-second) and the 3D overlap report come from here, through `scripts/compression_survey.py`:
a system of a config, with some of its keys replaced (``time_step=0.005``, ``relaxation.window_steps=4000``),
compressed through its ρ grid in a temporary folder, and per snapshot

* ρ, ρ over the region the centres can reach (box side − d_ave per axis), and ρ of the bulk: the inner box at
  least `BULK_MARGIN` d_ave from every wall (`forcenet.dem.packing.bulk_packing_fraction`), where the walls'
  own packing no longer counts,
* Z (2 × contacts / N, rattlers included), kinetic energy E_kin [m̄ d_ave² τ_c⁻²], pressure,
* λΔt: the fastest damping rate times Δt (`forcenet.dem.stability`; the run stops above the Gear bound),
* the largest and mean pair overlap, x / min(d_i, d_j) (the engine's blow-up measure) [-],
* relaxation steps,

with the CPU-seconds of the run and ρ_J from the logistic fit of Z(ρ) (`forcenet.measures.jamming`).

`snapshot_row` is that per-snapshot state, also for runs that have finished (`run_states`, through
`scripts/run_states.py`): with the particles that have at least two particle contacts (P1's non-rattlers) and the
mean contact force ⟨|F_n + F_t|⟩, in dyn where the system has a material — the measurements behind
docs/validation/README.md (the unjammed states' contacts, the force scales behind ρ_max).
"""
from __future__ import annotations

import copy
import logging
import tempfile
import time
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Mapping, Sequence

import numpy as np
import yaml

from forcenet.checks import checked_system
from forcenet.systems import run_seed

#: distance from the walls [d_ave] beyond which a snapshot's packing counts as bulk (`snapshot_row`'s rho_bulk)
BULK_MARGIN = 1.0

__all__ = ["BULK_MARGIN", "apply_overrides", "pair_overlap_fractions", "snapshot_row", "run_states", "SurveyRun",
           "run_survey"]


def apply_overrides(config: Mapping[str, Any], system: str, overrides: Sequence[str]) -> dict[str, Any]:
    """A deep copy of `config` with ``key=value`` items set in ``systems.<system>`` (dotted keys reach into
    nested entries, values are parsed as YAML: ``rho={start: 0.7, stop: 0.9, step: 0.01}``)."""
    result = copy.deepcopy(dict(config))
    entry = result["systems"][system]
    for item in overrides:
        key, _, text = item.partition("=")
        if not key or not _:
            raise ValueError(f"override {item!r} is not key=value")
        *parents, leaf = key.split(".")
        target = entry
        for parent in parents:
            target = target.setdefault(parent, {})
        target[leaf] = yaml.safe_load(text)
    return result


def pair_overlap_fractions(position: np.ndarray, radius: np.ndarray, contact_i: np.ndarray,
                           contact_j: np.ndarray) -> np.ndarray:
    """Overlap of each contact over the smaller diameter, x / (2 min(r_i, r_j)) [-].

    position (N, d) [d_ave], radius (N,) [d_ave], contact_i/contact_j (C,) particle indices. Returns (C,)."""
    separation = np.linalg.norm(position[contact_i] - position[contact_j], axis=1)
    overlap = radius[contact_i] + radius[contact_j] - separation
    return overlap / (2.0 * np.minimum(radius[contact_i], radius[contact_j]))


def snapshot_row(snap, force_unit_dyn: float = float("nan"), bulk_margin: float = BULK_MARGIN) -> dict[str, float]:
    """The state of one snapshot (an opened snapshot dataset), as listed in the module docstring.

    Keys: rho, rho_centres, rho_bulk (at least `bulk_margin` d_ave from every wall) [-]; Z, connected (particles
    with ≥ 2 particle contacts) [-]; kinetic_energy [m̄ d_ave² τ_c⁻²]; pressure [m̄ d_ave⁻¹ τ_c⁻² in 2D]; damping_dt
    [-]; overlap_max, overlap_mean (x / min(d_i, d_j)) [-]; mean_force (⟨|F_n + F_t|⟩ over the particle contacts)
    [m̄ d_ave τ_c⁻²] and mean_force_dyn (the same times `force_unit_dyn`, one reduced force unit in dyn; NaN
    without); relaxation_steps.
    """
    from forcenet.dem.packing import bulk_packing_fraction
    from forcenet.network.force_network import force_magnitude, rattler_free_mask

    contact_i, contact_j = snap.contact_i.values, snap.contact_j.values
    fractions = pair_overlap_fractions(snap.position.values, snap.radius.values, contact_i, contact_j)
    # P1's non-rattlers (≥ 2 particle contacts, one pass) and P1's total force |F_n + F_t|, from their one home
    connected = rattler_free_mask(snap.sizes["particle"], contact_i, contact_j, "once")
    force = force_magnitude(snap.force_normal.values, snap.force_tangential.values, "total")
    mean_force = float(force.mean()) if force.size else 0.0
    span = snap.box_hi.values - snap.box_lo.values
    # ρ over the region the centres of mean particles can reach (one d_ave less per axis): a candidate
    # reading of P1's "domain volume" (docs/validation/README.md)
    rho_centres = float(snap.rho) * float(np.prod(span / (span - 1.0)))
    rho_bulk = bulk_packing_fraction(snap.position.values, snap.radius.values, snap.box_lo.values,
                                     snap.box_hi.values, bulk_margin)
    return dict(rho=float(snap.rho), rho_centres=rho_centres, rho_bulk=rho_bulk, Z=float(snap.Z),
                connected=int(connected.sum()),
                kinetic_energy=float(snap.kinetic_energy), pressure=float(snap.pressure),
                damping_dt=float(snap.attrs["dem_damping_rate_time_step"]),
                overlap_max=float(fractions.max()) if fractions.size else 0.0,
                overlap_mean=float(fractions.mean()) if fractions.size else 0.0,
                mean_force=mean_force, mean_force_dyn=mean_force * force_unit_dyn,
                relaxation_steps=int(snap.relaxation_steps))


def run_states(run_dir: str | Path, force_unit_dyn: float = float("nan"), bulk_margin: float = BULK_MARGIN
               ) -> list[dict[str, float]]:
    """`snapshot_row` of every snapshot of a finished run folder (`forcenet.datasets.paths.run_dir`), in ρ order."""
    from forcenet.datasets import read_snapshot
    from forcenet.datasets.paths import rho_file

    rows = []
    for path in sorted(Path(run_dir).glob(rho_file("*"))):
        with read_snapshot(path) as snap:
            rows.append(snapshot_row(snap, force_unit_dyn, bulk_margin))
    return sorted(rows, key=lambda row: row["rho"])


@dataclass
class SurveyRun:
    """One compression run: per-snapshot rows, CPU time, ρ_J (also with ρ over the centres' domain and with the
    bulk ρ), and the blow-up message if it stopped."""

    rows: list[dict[str, float]]
    cpu_seconds: float
    rho_j: float
    rho_j_centres: float
    rho_j_bulk: float
    failure: str | None


def run_survey(config: Mapping[str, Any], system: str, realization: int = 0, log: logging.Logger | None = None,
               bulk_margin: float = BULK_MARGIN) -> SurveyRun:
    """Compress realization `realization` of `system` through its grid (snapshots in a temporary folder)."""
    from forcenet.datasets import read_snapshot
    from forcenet.datasets.paths import CHECKPOINT, rho_file
    from forcenet.dem.protocol import SimulationBlowUp, run_compression
    from forcenet.measures.jamming import jamming_point
    from forcenet.pipeline import run_attrs

    spec = checked_system(system, config)
    seed = run_seed(config, system, realization)
    log = log or logging.getLogger(f"forcenet.research.survey.{system}")
    failure = None
    with tempfile.TemporaryDirectory(prefix="forcenet-survey-") as folder:
        paths = [Path(folder) / rho_file(label) for label in spec.rho_labels]
        start = time.process_time()
        try:
            cpu = run_compression(spec, seed=seed, snapshot_paths=paths, checkpoint_path=Path(folder) / CHECKPOINT,
                            attrs=run_attrs(config, system, realization, f"forcenet survey, {system}"), log=log)
        except SimulationBlowUp as error:
            failure = str(error)
            cpu = time.process_time() - start
        rows = []
        for path in paths:
            if not path.exists():
                break
            with read_snapshot(path) as snap:
                rows.append(snapshot_row(snap, bulk_margin=bulk_margin))
    rho_j = rho_j_centres = rho_j_bulk = np.nan
    if len(rows) >= 4:
        z = [r["Z"] for r in rows]
        rho_j, rho_j_centres, rho_j_bulk = (float(jamming_point([r[key] for r in rows], z))
                                            for key in ("rho", "rho_centres", "rho_bulk"))
    return SurveyRun(rows=rows, cpu_seconds=cpu, rho_j=rho_j, rho_j_centres=rho_j_centres, rho_j_bulk=rho_j_bulk,
                     failure=failure)
