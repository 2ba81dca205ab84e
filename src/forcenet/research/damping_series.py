"""The Hertz damping series (docs/validation/damping.md): one paper-protocol run per normal damping γ_n, and what
each gives for the rule of docs/decisions.md ("The Hertz damping rule") and for P1's Hertz claims.

A series run is realization 0 of a system of `config/damping/systems.yaml` (2d_hertz or 3d_hertz with another
`normal_damping`), made by a run config of `config/damping/`. `series_row` reads its snapshots (`sim/`), its stacked
analysis (`network_measures.nc`, or the run's own analyses while that is not written: `run_network_measures`) and
its run cost, and returns one row:

* the rule's test: whether the run completed its ρ grid, how many relaxations hit `relaxation.max_steps` (a
  runaway: P1's E_kin criterion never met), the largest λΔt over the snapshots against 0.8 × the Gear bound;
* the restitution of two mean particles colliding head-on (m_eff = m̄/2, `dem.calibration`) at P1's v0 and at
  the median approach speed of near-contact pairs in the relaxed snapshots around jamming (pairs closer than
  `NEAR_CONTACT_GAP` and approaching; the snapshots hold the velocities at the end of each relaxation, so this
  is the speed at which particles still meet when the relaxation criterion is met; NaN for a run restored from
  its campaign record, which keeps no velocities: the run's own snapshots give them);
* ρ_J of the box and of the bulk (the inner box 1 d_ave from the walls), from the logistic fit of Z(ρ);
* the particles with ≥ 2 contacts (P1's non-rattlers) in the last two grid states before the jump: below ρ_J
  and with Z < `UNJAMMED_Z` (clusters below jamming, P1 §3; the inflection of Z(ρ) can fall just above a
  state that is already half jammed);
* near ρ_J (|ρ − ρ_J| ≤ `NEAR_JAMMING`): the largest B0/N at F_th < 0.5 ⟨F⟩ and, for the same curve, its
  mean beyond ρ_J + 0.03 (P1 §5.1's ridge is a within-curve peak); the largest weak- and strong-bin N0/N
  (P1 §5.3); the largest ⟨S⟩/N at the smallest F_th (P1 §6);
* the CPU-hours of the run.
"""
from __future__ import annotations

import json
import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import xarray as xr

from forcenet.datasets import read_snapshot
from forcenet.datasets.paths import (STAGING_DIR, network_measures, realization_name, rho_file, run_cost,
                                     run_dir)
from forcenet.dem import calibration, stability
from forcenet.measures.jamming import jamming_point as inflection

#: a pair counts as near contact when its surface gap is below this [d_ave]
NEAR_CONTACT_GAP = 0.1
#: states within this distance in ρ of ρ_J count as "near jamming" [-]
NEAR_JAMMING = 0.02
#: the ridge's "beyond jamming" reference starts this far above ρ_J [-]
BEYOND_JAMMING = 0.03
#: B0/N ridge thresholds: F_th below this [⟨F⟩] (P1 §5.1: "small F_th")
SMALL_THRESHOLD = 0.5
#: a state before the jump has fewer contacts per particle than this (every run jumps from Z < 0.4) [-]
UNJAMMED_Z = 1.0
#: the rule's margin on λΔt: at most this share of the Gear corrector's bound (docs/decisions.md)
DAMPING_MARGIN = 0.8


def approach_speeds(position: np.ndarray, velocity: np.ndarray, radius: np.ndarray,
                    gap: float = NEAR_CONTACT_GAP) -> np.ndarray:
    """Normal approach speeds [d_ave/τ_c] of the pairs whose surfaces are closer than `gap` [d_ave] and that move
    towards each other: −(v_j − v_i)·n_ij for n_ij the unit vector from i to j, kept where positive.

    position, velocity (N, d); radius (N,). Brute force over pairs in blocks (N of a few thousand)."""
    speeds = []
    n = len(radius)
    for start in range(0, n, 256):
        rows = slice(start, min(n, start + 256))
        offset = position[None, :, :] - position[rows, None, :]              # (b, N, d): j − i
        distance = np.linalg.norm(offset, axis=-1)
        index_i = np.arange(rows.start, rows.stop)[:, None]
        near = (distance - radius[rows, None] - radius[None, :] < gap) & (np.arange(n)[None, :] > index_i)
        bi, j = np.nonzero(near)
        normal = offset[bi, j] / distance[bi, j, None]
        closing = -np.einsum("kd,kd->k", velocity[j] - velocity[bi + rows.start], normal)
        speeds.append(closing[closing > 0])
    return np.concatenate(speeds) if speeds else np.empty(0)


@dataclass
class SeriesRun:
    """Where a series run lives: its results folder, system and realization."""

    results: Path
    system: str
    realization: int = 0

    @property
    def sim(self) -> Path:
        return Path(run_dir(str(self.results), self.system, realization_name(self.realization)))

    @classmethod
    def parse(cls, text: str) -> "SeriesRun":
        """`FOLDER`, `FOLDER:SYSTEM` or `FOLDER:SYSTEM:REALIZATION` (an index, `3` or `r03`); a bare folder is a
        series folder named `{system}_g{gamma_n}…`, realization 0."""
        folder, system, realization = (text.split(":") + ["", ""])[:3]
        if not system:
            system = Path(folder).name.split("_g")[0]
        index = int(realization.removeprefix("r")) if realization else 0
        return cls(Path(folder), system, index)


def median_approach_speed(states: list[tuple[np.ndarray, np.ndarray | None, np.ndarray]]) -> float:
    """The median `approach_speeds` over the near-contact pairs of `states`, each (position (N, d), velocity
    (N, d) or None, radius (N,)) [d_ave/τ_c]; NaN when there is no such pair or a state has no velocities (a run
    restored from its campaign record)."""
    if not states or any(velocity is None for _, velocity, _ in states):
        return math.nan
    speeds = np.concatenate([approach_speeds(*state) for state in states])
    return float(np.median(speeds)) if speeds.size else math.nan


def _snapshot_states(run: SeriesRun) -> list[dict]:
    """`survey.snapshot_row` of every snapshot of the run, in grid order: the published ones, or, for a run that
    stopped (a blow-up publishes nothing), the ones it left in its staging folder."""
    from forcenet.research.survey import snapshot_row

    states = []
    paths = sorted(run.sim.glob(rho_file("*"))) or sorted((run.sim / STAGING_DIR).glob(rho_file("*")))
    for path in paths:
        with read_snapshot(path) as snap:
            row = snapshot_row(snap)
            row["path"] = path
            row["grid_rho"] = float(path.stem.removeprefix("rho"))
            row["config"] = json.loads(snap.attrs["config"])
            row["normal_damping"] = float(snap.attrs["dem_normal_damping"])
            # a snapshot restored from a campaign record keeps no velocities: no approach speeds from it
            velocity = snap["velocity"].values if "velocity" in snap else None
            row["arrays"] = (snap.position.values, velocity, snap.radius.values)
            states.append(row)
    return sorted(states, key=lambda row: row["grid_rho"])


def _fit(rho, z) -> float:
    try:
        return float(inflection(np.asarray(rho), np.asarray(z)[None, :]))
    except (ValueError, ArithmeticError):
        return math.nan


def series_row(run: SeriesRun) -> dict:
    """One row of the series table (module docstring) for a finished or stopped series run."""
    from forcenet.checks import checked_system

    states = _snapshot_states(run)
    if not states:
        return {"system": run.system, "results": str(run.results), "status": "no snapshot"}
    config = states[0]["config"]
    spec = checked_system(run.system, config)
    gamma = states[0]["normal_damping"]
    grid = np.array(spec.rho_grid)
    done = np.array([s["grid_rho"] for s in states])
    completed = len(done) == len(grid)
    capped = sum(s["relaxation_steps"] >= spec.relaxation.max_steps for s in states) if spec.relaxation else 0
    damping_dt = max(s["damping_dt"] for s in states)
    rho = np.array([s["rho"] for s in states])
    z = np.array([s["Z"] for s in states])
    rho_j = _fit(rho, z)
    rho_j_bulk = _fit([s["rho_bulk"] for s in states], z)
    below = [s for s in states if s["rho"] < rho_j and s["Z"] < UNJAMMED_Z] if math.isfinite(rho_j) else []
    n = len(states[0]["arrays"][2])
    near = [s for s in states if math.isfinite(rho_j) and abs(s["rho"] - rho_j) <= NEAR_JAMMING + 1e-9]
    median_speed = median_approach_speed([s["arrays"] for s in near])

    def restitution(speed: float) -> float:
        if not math.isfinite(speed) or speed <= 0:
            return math.nan
        return calibration.collision_restitution(spec.normal_stiffness, spec.beta, gamma,
                                                 calibration.MEAN_PAIR_EFFECTIVE_MASS, speed)

    row = {
        "system": run.system, "realization": realization_name(run.realization), "N": n, "gamma_n": gamma,
        "results": str(run.results),
        "e_at_v0": restitution(spec.wall_speed), "median_approach_speed": median_speed,
        "e_at_median_speed": restitution(median_speed),
        "completed": bool(completed), "top_rho": float(done[-1]), "capped_relaxations": int(capped),
        "max_damping_dt": damping_dt,
        "passes_rule": bool(completed and capped == 0
                            and damping_dt <= DAMPING_MARGIN * stability.GEAR_DAMPING_BOUND),
        "rho_J": rho_j, "rho_J_bulk": rho_j_bulk,
        "connected_below_rho_J": [int(s["connected"]) for s in below[-2:]],
        "rho_below_rho_J": [round(s["grid_rho"], 3) for s in below[-2:]],
        "cpu_hours": _cpu_hours(run),
    }
    row.update(network_readings(run, rho_j))
    return row


def _cpu_hours(run: SeriesRun) -> float:
    path = Path(run_cost(str(run.results), run.system, realization_name(run.realization)))
    if not path.exists():
        return math.nan
    return float(json.loads(path.read_text())["cpu_seconds"]) / 3600.0


def run_network_measures(run: SeriesRun) -> xr.Dataset | None:
    """The run's network measures over ρ (the `network_measures` variables without the realization dimension):
    from its system's stacked `network_measures.nc` when that holds the realization, else stacked from the
    run's own per-snapshot analyses when every published snapshot has one (a campaign whose other realizations
    have not finished, so that its aggregate is not written yet); None when neither is there."""
    from forcenet.datasets import read_dataset
    from forcenet.datasets.aggregate import stack_network_measures
    from forcenet.datasets.paths import analysis

    path = Path(network_measures(str(run.results), run.system))
    if path.exists():
        with xr.open_dataset(path) as ds:
            if run.realization in ds.realization.values:
                return ds.sel(realization=run.realization).load()
    name = realization_name(run.realization)
    snapshots = sorted(run.sim.glob(rho_file("*")))
    analyses = [Path(analysis(str(run.results), run.system, name, p.stem.removeprefix("rho"))) for p in snapshots]
    if not analyses or not all(p.exists() for p in analyses):
        return None
    datasets = [read_dataset(p, "analysis") for p in analyses]
    try:
        rhos = [float(p.stem.removeprefix("rho")) for p in analyses]
        stacked = stack_network_measures(datasets, [run.realization] * len(datasets), rhos, {})
        return stacked.sel(realization=run.realization).load()
    finally:
        for ds in datasets:
            ds.close()


def network_readings(run: SeriesRun, rho_j: float) -> dict:
    """The P1 network readings of the module docstring from the run's network measures (`run_network_measures`,
    total force; NaN where they or the states near ρ_J are missing)."""
    empty = dict(b0_small_near_jamming=math.nan, b0_small_beyond=math.nan, weak_bin_near_jamming=math.nan,
                 strong_bin_near_jamming=math.nan, cluster_size_near_jamming=math.nan)
    measures = run_network_measures(run) if math.isfinite(rho_j) else None
    if measures is None:
        return empty
    ds = measures.sel(force_kind="total")
    n = ds.n_particles
    rho = ds.rho_measured.values
    near = np.abs(rho - rho_j) <= NEAR_JAMMING + 1e-9
    beyond = rho >= rho_j + BEYOND_JAMMING
    small = ds.threshold.values < SMALL_THRESHOLD
    b0 = (ds.betti.sel(homology_dim=0) / n).values  # (rho, threshold)
    bins = ds.persistence_bin_count / n
    size = (ds.cluster_mean_size / n).isel(threshold=0).values

    def largest(values):
        return float(np.nanmax(values)) if np.size(values) else math.nan

    return dict(
        b0_small_near_jamming=largest(b0[near][:, small]),
        b0_small_beyond=float(np.nanmean(np.nanmax(b0[beyond][:, small], axis=1))) if beyond.any() else math.nan,
        weak_bin_near_jamming=largest(bins.sel(persistence_bin="weak").values[near]),
        strong_bin_near_jamming=largest(bins.sel(persistence_bin="strong").values[near]),
        cluster_size_near_jamming=largest(size[near]),
    )


__all__ = ["SeriesRun", "series_row", "approach_speeds", "network_readings", "run_network_measures",
           "NEAR_CONTACT_GAP", "NEAR_JAMMING", "DAMPING_MARGIN"]
