"""P2's data product ``results/{system}/distances.nc`` and the adapters every P2 distance goes through.

- Adapters to `forcenet.network` / `forcenet.topology` (the only places the P2 report calls them): a snapshot's
  force network (`p2_network`), its persistence diagrams, whole box and per quadrant, the diagram stored in
  an analysis file (`analysis_diagram`), distances between two diagrams (`pair_distances`),
  edge forces and their changes for P2 Fig. 1 (`contact_forces`, `force_differences`).
- `consecutive_distances` / `stack_distances` — d_B, d_W1, d_W2 between consecutive snapshots of each realization,
  dims (realization, rho, force_kind, homology_dim, metric), with Z(ρ). ``rho`` is the packing fraction of the
  *later* snapshot of each pair (P2 Figs 6–10 plot the distance between consecutive samples against ρ).
- `lagged_distances`, `lagged_distance_summary` — distances between states k samples apart, per P2 regime: how
  the sampling step and the wall speed change the distances (docs/p2_sampling.md, scripts/p2_sampling.py).
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, Mapping, Sequence

import numpy as np
import pandas as pd
import xarray as xr

from forcenet.datasets.schema import DIMENSIONLESS, NETWORK_FORCE_UNITS
from forcenet.datasets.snapshot import box_tilt
from forcenet.report.p2 import (METRIC_LONG_NAMES, METRICS, P2_FORCE_KINDS, P2_HOMOLOGY_DIMS, format_number,
                                pretty_column, rho_at_isostatic_crossing, table_column)

ESSENTIAL_CONVENTIONS_DOC = {
    "minus_one": "never-dying classes are given death = -1 <F> before matching (P2 §III B, Fig. 5)",
    "zero": "never-dying classes are given death = 0 before matching",
    "drop": "never-dying classes are left out of the matching",
    "apart": "never-dying classes are matched only with each other, by birth (infinite when their numbers differ)",
}


# =============================================================================================================
# Adapters to forcenet.network / forcenet.topology (the only places the P2 report calls them)
# =============================================================================================================
def diagram_from_points(birth: np.ndarray, death: np.ndarray, essential: np.ndarray, homology_dim: int):
    """A `forcenet.topology.PersistenceDiagrams` holding one homology dimension's points (never-dying ones at
    death −inf, whatever death the file gave them)."""
    from forcenet.topology import PersistenceDiagrams

    n = len(birth)
    death = np.where(np.asarray(essential, dtype=bool), -np.inf, np.asarray(death, dtype=float))
    return PersistenceDiagrams(homology_dim=np.full(n, homology_dim, dtype=np.int64),
                               birth=np.asarray(birth, dtype=float), death=death)


def pair_distances(pd_a, pd_b, homology_dim: int, essential_convention: str) -> dict[str, float]:
    """{metric: value} between the PD_k of two networks (`forcenet.topology.diagram_distances`, exact solver)."""
    from forcenet.topology import diagram_distances

    result = diagram_distances(pd_a, pd_b, homology_dim, essential_convention)
    return {metric: float(result[metric]) for metric in METRICS}


def _consecutive_distances(diagrams: Sequence, homology_dim: int, essential_convention: str) -> np.ndarray:
    """Distances between the PD_k of consecutive networks (`forcenet.topology.consecutive_diagram_distances`):
    array of shape (len(diagrams) - 1, len(METRICS))."""
    from forcenet.topology import consecutive_diagram_distances

    result = consecutive_diagram_distances(diagrams, (homology_dim,), essential_convention)
    return np.stack([result[metric][:, 0] for metric in METRICS], axis=-1)


def p2_network(snapshot: xr.Dataset, kind: str, remove_rattlers: bool | str):
    """P2's force network of one snapshot (`forcenet.network.snapshot_network` with P2's choices: wall contacts
    ignored, the study's rattler rule), forces in units of that network's mean (P2 §II)."""
    from forcenet.network import snapshot_network

    return snapshot_network(snapshot, kind, rattler_rule=remove_rattlers, wall_contacts="ignored")


@dataclass(frozen=True)
class EdgeValues:
    """A value per network edge: ``i < j`` particle ids [shape (E,)] and the value [⟨F⟩] (P2 Fig. 1)."""

    i: np.ndarray
    j: np.ndarray
    force: np.ndarray


def contact_forces(snapshot: xr.Dataset, kind: str = "normal", *, remove_rattlers: bool | str = False) -> EdgeValues:
    """Edge forces of one snapshot's network in units of its own mean (P2 Fig. 1(a–c))."""
    net = p2_network(snapshot, kind, remove_rattlers)
    return EdgeValues(np.asarray(net.edge_i), np.asarray(net.edge_j), np.asarray(net.force, dtype=float))


def force_differences(snapshot_a: xr.Dataset, snapshot_b: xr.Dataset, kind: str = "normal", *,
                      remove_rattlers: bool | str = False) -> EdgeValues:
    """|F_b − F_a| on every pair that is an edge of either network, each force in units of its own snapshot's
    mean (P2 Fig. 1(d–e)); an edge missing from one network has force 0 there. Particle ids must refer to the
    same particles in both snapshots (one realization)."""
    a = contact_forces(snapshot_a, kind, remove_rattlers=remove_rattlers)
    b = contact_forces(snapshot_b, kind, remove_rattlers=remove_rattlers)
    return edge_differences(a, b, int(max(snapshot_a.sizes["particle"], snapshot_b.sizes["particle"])))


def edge_differences(a: EdgeValues, b: EdgeValues, n_particles: int) -> EdgeValues:
    """|F_b − F_a| on every pair that is an edge of a or b (F = 0 where the edge is missing); ids < n_particles."""
    key_a, key_b = a.i * n_particles + a.j, b.i * n_particles + b.j
    keys = np.union1d(key_a, key_b)
    fa, fb = np.zeros(keys.size), np.zeros(keys.size)
    fa[np.searchsorted(keys, key_a)] = a.force
    fb[np.searchsorted(keys, key_b)] = b.force
    return EdgeValues(keys // n_particles, keys % n_particles, np.abs(fb - fa))


def network_diagrams(network):
    """PD0, PD1 (and PD2 in 3D) of one force network (`forcenet.topology.persistence_diagrams`)."""
    from forcenet.topology import persistence_diagrams

    return persistence_diagrams(network)


def quadrant_diagrams(network, snapshot: xr.Dataset) -> dict:
    """Diagrams of each quarter of the snapshot's own box (P2 Tables II–III): {quadrant: PersistenceDiagrams}."""
    from forcenet.topology import quadrant_persistence_diagrams

    return quadrant_persistence_diagrams(network, snapshot["box_lo"].values, snapshot["box_hi"].values,
                                         box_tilt(snapshot))


# =============================================================================================================
# Distances between consecutive snapshots (P2 §IV, Figs 6–10)
# =============================================================================================================
def analysis_diagram(analysis: xr.Dataset, kind: str, homology_dim: int):
    """The `PersistenceDiagrams` of one force kind and homology dimension of an analysis dataset (read by the one
    reader of diagram points, `forcenet.datasets.diagram_points`)."""
    from forcenet.datasets import diagram_points

    points = diagram_points(analysis, kind, homology_dim)
    return diagram_from_points(points.birth, points.death, points.essential, homology_dim)


def consecutive_distances(analyses: Sequence[xr.Dataset], essential_convention: str = "minus_one", *,
                          force_kinds: Sequence[str] = P2_FORCE_KINDS,
                          homology_dims: Sequence[int] = P2_HOMOLOGY_DIMS, sequence: bool = False) -> xr.Dataset:
    """d_B, d_W1, d_W2 between the diagrams of consecutive snapshots of ONE realization.

    Parameters
    ----------
    analyses : per-snapshot analysis datasets (``results/analysis/{system}/r{NN}/rho{ρ}.nc``) in increasing ρ, or
        with `sequence` in the order of a sequence's coordinate (an imported run at any ρ, ``state{k}.nc``)
    essential_convention : how never-dying classes enter the matching (see `forcenet.topology.diagram_distances`);
        default ``"minus_one"``: death −1 ⟨F⟩, as P2 §III B. Distances come from forcenet's exact solver.

    Returns
    -------
    Dataset with ``distance(rho, force_kind, homology_dim, metric)`` [⟨F⟩], ``Z(rho)``, ``rho_previous(rho)``;
    ``rho`` is the later snapshot's packing fraction of each pair, so n snapshots give n − 1 values.
    """
    if len(analyses) < 2:
        raise ValueError(f"need at least two snapshots for a consecutive distance, got {len(analyses)}")
    rho = np.array([float(ds["rho"]) for ds in analyses])
    if not sequence and np.any(np.diff(rho) <= 0):
        raise ValueError(f"analyses must be in strictly increasing rho, got {rho.tolist()}")
    force_kinds, homology_dims = tuple(force_kinds), tuple(int(h) for h in homology_dims)
    values = np.full((len(analyses) - 1, len(force_kinds), len(homology_dims), len(METRICS)), np.nan)
    for a, kind in enumerate(force_kinds):
        for b, dim in enumerate(homology_dims):
            diagrams = [analysis_diagram(ds, kind, dim) for ds in analyses]
            values[:, a, b] = _consecutive_distances(diagrams, dim, essential_convention)
    z = np.array([float(ds["Z"]) if "Z" in ds else math.nan for ds in analyses[1:]])
    return _pair_dataset(values, rho, z, force_kinds, homology_dims, essential_convention)


def _pair_dataset(values: np.ndarray, rho: np.ndarray, z: np.ndarray, force_kinds: Sequence[str],
                  homology_dims: Sequence[int], essential_convention: str) -> xr.Dataset:
    """The `consecutive_distances` dataset of one run: `values` (pair, force_kind, homology_dim, metric), the
    measured ρ of every state and the Z of each pair's later state."""
    return xr.Dataset(
        {
            "distance": (("rho", "force_kind", "homology_dim", "metric"), values, _distance_attrs()),
            "Z": (("rho",), z, {"units": DIMENSIONLESS,
                                "long_name": "mean contacts per particle Z of the later snapshot (all particles)"}),
            "rho_previous": (("rho",), rho[:-1], {"units": DIMENSIONLESS,
                                                  "long_name": "packing fraction of the earlier snapshot"}),
        },
        coords=_distance_coords(rho[1:], force_kinds, homology_dims),
        attrs=_convention_attrs(essential_convention),
    )


def stack_distances(per_realization: Sequence[xr.Dataset], realizations: Sequence[int],
                    attrs: Mapping[str, Any], *, rho_tolerance: float = 5e-3) -> xr.Dataset:
    """Stack `consecutive_distances` results of several realizations: ``results/{system}/distances.nc``.

    The realizations must cover the same ρ grid (the same number of snapshots, each ρ within `rho_tolerance`
    of the others); the ``rho`` coordinate is the mean over realizations and each realization's own values are
    kept in ``rho_measured(realization, rho)``. `attrs` (provenance) are added to the never-dying convention,
    which must be the same for every realization.
    """
    per_realization = list(per_realization)
    realizations = [int(r) for r in realizations]
    if not per_realization or len(per_realization) != len(realizations):
        raise ValueError(f"{len(per_realization)} datasets for {len(realizations)} realizations")
    if len(set(realizations)) != len(realizations):
        raise ValueError(f"duplicate realizations: {realizations}")
    sizes = {ds.sizes["rho"] for ds in per_realization}
    if len(sizes) != 1:
        raise ValueError(f"realizations have different numbers of snapshot pairs: {sorted(sizes)}")
    conventions = {ds.attrs["essential_convention"] for ds in per_realization}
    if len(conventions) != 1:
        raise ValueError(f"realizations use different never-dying conventions: {conventions}")
    rho = np.stack([ds["rho"].values for ds in per_realization])
    if np.nanmax(np.abs(rho - rho.mean(axis=0))) > rho_tolerance:
        raise ValueError(f"realizations' rho grids differ by more than {rho_tolerance}")
    first = per_realization[0]
    aligned = [ds.assign_coords(rho=first["rho"].values) for ds in per_realization]
    stacked = xr.concat(aligned, dim="realization", combine_attrs="drop", coords="minimal", compat="override")
    stacked = stacked.assign_coords(
        realization=xr.Variable(("realization",), np.array(realizations, dtype=np.int32),
                                attrs={"units": DIMENSIONLESS, "long_name": "realization index"}),
        rho=xr.Variable(("rho",), rho.mean(axis=0), attrs=_rho_attrs()),
    )
    stacked["rho_measured"] = xr.Variable(("realization", "rho"), rho, attrs={
        "units": DIMENSIONLESS, "long_name": "packing fraction of the later snapshot, per realization"})
    for name in first.variables:  # concat keeps values; restore every variable's and coordinate's attrs
        if name in stacked.variables and name != "rho":
            stacked[name].attrs = dict(first[name].attrs)
    stacked.attrs = {**first.attrs, **dict(attrs)}
    return stacked


def run_summary(analyses: Sequence[xr.Dataset], conventions: Sequence[str], grid_rhos: Sequence[float],
                attrs: Mapping[str, Any], sequence: bool = False) -> xr.Dataset:
    """What P2's products read from ONE run, its diagrams apart (kind "p2_run", `schema.P2_RUN_VARIABLES`): per
    state of its grid (`grid_rhos`, the analyses in the same order) the measured ρ, Z, the never-dying class and point
    counts of each P2 diagram and the total point count, and the `consecutive_distances` of the run under every
    never-dying `conventions`; `attrs` are the file's global attributes. A `sequence` gives the coordinate of each
    state as `grid_rhos` and its analyses in that order, at any ρ."""
    from forcenet.datasets.io import dataset_from_specs
    from forcenet.datasets.schema import P2_RUN_VARIABLES

    if len(analyses) != len(grid_rhos):
        raise ValueError(f"{len(analyses)} analyses for {len(grid_rhos)} grid states")
    conventions = list(dict.fromkeys(conventions))
    distances = [consecutive_distances(analyses, convention, sequence=sequence) for convention in conventions]
    essential = np.zeros((len(analyses), len(P2_FORCE_KINDS), len(P2_HOMOLOGY_DIMS)), dtype=np.int64)
    points = np.zeros_like(essential)
    for s, ds in enumerate(analyses):
        kinds = [str(k) for k in ds["force_kind"].values]
        for a, kind in enumerate(P2_FORCE_KINDS):
            essential[s, a] = ds["essential_count"].sel(force_kind=kind, homology_dim=list(P2_HOMOLOGY_DIMS)).values
            for b, dim in enumerate(P2_HOMOLOGY_DIMS):  # as forcenet.report.p2.diagram_point_counts counts them
                points[s, a, b] = int(np.count_nonzero((ds["diagram_force_kind"].values == kinds.index(kind))
                                                       & (ds["diagram_homology_dim"].values == dim)))
    values = {
        "state_rho": np.array([float(ds["rho"]) for ds in analyses]),
        "state_Z": np.array([float(ds["Z"]) for ds in analyses]),
        "essential_count": essential, "point_count": points,
        "point_total": np.array([ds.sizes.get("point", 0) for ds in analyses], dtype=np.int64),
        "distance": np.stack([d["distance"].values for d in distances]),
    }
    coords = _distance_coords(np.zeros(0), P2_FORCE_KINDS, P2_HOMOLOGY_DIMS)
    del coords["rho"]
    coords["grid_state"] = xr.Variable(("grid_state",), np.asarray(grid_rhos, dtype=float), attrs={
        "units": DIMENSIONLESS, "long_name": "packing fraction of the state on the config's grid (systems.<name>.rho)"})
    coords["essential_convention"] = xr.Variable(("essential_convention",), conventions, attrs={
        "units": DIMENSIONLESS, "long_name": "how never-dying classes enter the distances (forcenet.topology)"})
    return dataset_from_specs(P2_RUN_VARIABLES, values, attrs, coords=coords)


def summary_distances(summary: xr.Dataset, convention: str) -> xr.Dataset:
    """The `consecutive_distances` of the run a `run_summary` (or a P2 run record) holds, under `convention`: the
    same dataset, value for value, as computed from the run's analyses. KeyError naming the conventions it holds
    when it lacks `convention`."""
    held = [str(c) for c in summary["essential_convention"].values]
    if convention not in held:
        raise KeyError(f"no distances under the never-dying convention '{convention}' (it holds {', '.join(held)})")
    return _pair_dataset(summary["distance"].values[held.index(convention)], summary["state_rho"].values,
                         summary["state_Z"].values[1:], [str(k) for k in summary["force_kind"].values],
                         [int(k) for k in summary["homology_dim"].values], convention)


def summary_point_counts(summaries: Mapping[int, xr.Dataset], kind: str = "normal",
                         homology_dim: int = 1) -> xr.DataArray:
    """The number of points of each PD_k (force kind `kind`) of every state of the runs `summaries`
    ({realization: `run_summary`}), dims (realization, rho): the same array `forcenet.report.p2.diagram_point_counts`
    gives from the runs' stacked diagrams.nc (only realizations and grid ρ at which some diagram has a point)."""
    realizations = sorted(int(r) for r in summaries)
    rhos = summaries[realizations[0]]["grid_state"].values
    total = np.stack([summaries[r]["point_total"].values for r in realizations])
    counts = np.stack([summaries[r]["point_count"].sel(force_kind=kind, homology_dim=homology_dim).values
                       for r in realizations]).astype(float)
    rows, columns = total.sum(axis=1) > 0, total.sum(axis=0) > 0
    return xr.DataArray(counts[rows][:, columns], dims=("realization", "rho"),
                        coords={"realization": np.array(realizations)[rows], "rho": rhos[columns]})


def summary_essential_counts(summaries: Mapping[int, xr.Dataset]) -> xr.Dataset:
    """The never-dying class counts of the runs `summaries` ({realization: `run_summary`}) as network_measures.nc
    holds them: ``essential_count(realization, rho, force_kind, homology_dim)``, ρ the grid's."""
    realizations = sorted(int(r) for r in summaries)
    first = summaries[realizations[0]]
    stacked = xr.concat([summaries[r]["essential_count"] for r in realizations], dim="realization")
    return xr.Dataset({"essential_count": stacked.rename(grid_state="rho")}).assign_coords(
        realization=np.array(realizations, dtype=np.int32), rho=first["grid_state"].values)


def _distance_attrs() -> dict:
    """units and long_name of the ``distance`` variable of distances.nc."""
    return {"units": NETWORK_FORCE_UNITS,
            "long_name": "distance between the persistence diagrams of consecutive snapshots "
                         "(super-level filtration, L-infinity ground metric)"}


def _rho_attrs() -> dict:
    """units and long_name of the ``rho`` coordinate of distances.nc."""
    return {"units": DIMENSIONLESS, "long_name": "packing fraction of the later snapshot of each pair"}


def _distance_coords(rho, force_kinds, homology_dims) -> dict:
    """The coordinates of distances.nc (rho, force_kind, homology_dim, metric), each with units and long_name."""
    return {
        "rho": xr.Variable(("rho",), np.asarray(rho, dtype=float), attrs=_rho_attrs()),
        "force_kind": xr.Variable(("force_kind",), list(force_kinds), attrs={
            "units": DIMENSIONLESS, "long_name": "contact force component whose network is analysed"}),
        "homology_dim": xr.Variable(("homology_dim",), np.asarray(homology_dims, dtype=np.int32), attrs={
            "units": DIMENSIONLESS, "long_name": "homology dimension k of the diagram PD_k (0: components, 1: loops)"}),
        "metric": xr.Variable(("metric",), list(METRICS), attrs={
            "units": DIMENSIONLESS, "long_name": "distance between persistence diagrams: "
                                                 + "; ".join(f"{m}: {METRIC_LONG_NAMES[m]}" for m in METRICS)}),
    }


def _convention_attrs(essential_convention: str) -> dict:
    """The global attributes that say how the distances were computed (never-dying classes, metric, solver)."""
    return {
        "essential_convention": essential_convention,
        "essential_convention_description": ESSENTIAL_CONVENTIONS_DOC.get(
            essential_convention, f"never-dying classes: forcenet.topology convention '{essential_convention}'"),
        "ground_metric": "L-infinity",
        "distance_solver": "forcenet.topology exact optimal matching (float64)",
        "matching": "optimal matching of points and diagonal, points with birth == death left out",
        "rho_convention": "rho is the packing fraction of the later snapshot of each consecutive pair",
    }


# =============================================================================================================
# Sampling: distances between states k samples apart (docs/p2_sampling.md)
# =============================================================================================================
#: ρ windows of the sampling summary: P2's regimes (§IV A: before 0.75, from 0.75 to ρ_J, after ρ_J)
SAMPLING_WINDOWS = ("rho < 0.75", "0.75 <= rho < rho_J", "rho > rho_J")


def snapshot_diagrams(snapshot: xr.Dataset, kind: str = "normal", rattler_rule: bool | str = "none"):
    """PD0 and PD1 of one snapshot's force network of `kind` (forces in units of its own mean) built with
    `rattler_rule` (P2: ``"none"``, rattlers kept as components born at 0)."""
    return network_diagrams(p2_network(snapshot, kind, rattler_rule))


def lagged_distances(diagrams: Sequence, rho: Sequence[float], lag: int, *, essential_convention: str = "minus_one",
                     homology_dims: Sequence[int] = P2_HOMOLOGY_DIMS) -> pd.DataFrame:
    """d_B, d_W1, d_W2 between the diagrams of states `lag` samples apart (lag 1: P2's consecutive states).

    Returns one row per pair (s, s + lag): columns ``rho_previous``, ``rho`` (the later state) and
    `table_column` names (``beta0_d_B`` …) [⟨F⟩].
    """
    if lag < 1:
        raise ValueError(f"lag must be >= 1, got {lag}")
    rows = []
    for s in range(len(diagrams) - lag):
        row = {"rho_previous": float(rho[s]), "rho": float(rho[s + lag])}
        for h in homology_dims:
            d = pair_distances(diagrams[s], diagrams[s + lag], h, essential_convention)
            row.update({table_column(h, m): d[m] for m in METRICS})
        rows.append(row)
    columns = ["rho_previous", "rho"] + [table_column(h, m) for h in homology_dims for m in METRICS]
    return pd.DataFrame(rows, columns=columns)


def lagged_distance_summary(runs: Mapping[float, tuple], lags: Sequence[int], *, dimension: int = 2,
                            essential_convention: str = "minus_one") -> pd.DataFrame:
    """Median distances between states k samples apart, per wall speed, lag and P2 regime.

    Parameters
    ----------
    runs : ``{wall_speed: (rho, Z, diagrams, simulation_seconds)}``: one compression run per wall speed,
        states in increasing ρ.
    lags : k values.

    Returns
    -------
    DataFrame with columns wall_speed, lag, delta_rho (mean ρ step of a pair), window (`SAMPLING_WINDOWS`,
    both states of a pair inside it; ρ_J where Z first reaches d + 1), pairs, rho_J, simulation_s and the
    medians of every `table_column` [⟨F⟩].
    """
    rows = []
    for speed, (rho, z, diagrams, seconds) in runs.items():
        rho_j = rho_at_isostatic_crossing(np.asarray(rho), np.asarray(z), dimension)
        bounds = dict(zip(SAMPLING_WINDOWS, ((-np.inf, 0.75), (0.75, rho_j), (rho_j, np.inf))))
        for lag in lags:
            pairs = lagged_distances(diagrams, rho, lag, essential_convention=essential_convention)
            values = [c for c in pairs.columns if c.startswith("beta")]
            for window, (lo, hi) in bounds.items():
                inside = pairs[(pairs["rho_previous"] >= lo) & (pairs["rho"] < hi)] if np.isfinite(rho_j) else pairs[:0]
                rows.append({"wall_speed": speed, "lag": lag,
                             "delta_rho": float((pairs["rho"] - pairs["rho_previous"]).mean()) if len(pairs) else np.nan,
                             "window": window, "pairs": len(inside), "rho_J": rho_j, "simulation_s": seconds,
                             **{c: float(inside[c].median()) if len(inside) else np.nan for c in values}})
    return pd.DataFrame(rows)


def lagged_distance_markdown(summary: pd.DataFrame) -> str:
    """`lagged_distance_summary` as one Markdown table (medians, 2 significant digits)."""
    values = [c for c in summary.columns if c.startswith("beta")]
    header = ["v_c [d/τ_c]", "k", "Δρ", "window", "pairs"] + [pretty_column(c) for c in values]
    lines = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    for _, r in summary.iterrows():
        window = r["window"].replace("rho_J", f"ρ_J = {r['rho_J']:.3f}").replace("rho", "ρ")
        lines.append("| " + " | ".join([f"{r['wall_speed']:g}", str(int(r["lag"])), f"{r['delta_rho']:.4f}", window,
                                        str(int(r["pairs"]))] + [format_number(r[c], 2) for c in values]) + " |")
    return "\n".join(lines) + "\n"
