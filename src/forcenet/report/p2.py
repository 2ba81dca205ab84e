"""P2 (evolution of force networks): distances between consecutive states, Tables I–III, validation.

Everything P2 measures is a distance between persistence diagrams (P2 §III D): the bottleneck distance d_B
and the Wasserstein distances d_W1, d_W2 with the L∞ ground metric, for PD0 (β0, components) and PD1 (β1,
loops) of the normal- and the tangential-force networks, each normalised by its own mean force. The diagrams
and the distances themselves come from `forcenet.topology`; this module only decides *which* diagrams are
compared and how the results are labelled, stacked, tabulated and judged.

Products
--------
- `consecutive_distances` / `stack_distances` — ``results/{system}/distances.nc``: d_B, d_W1, d_W2 between
  consecutive snapshots of each realization, dims (realization, rho, force_kind, homology_dim, metric), with
  Z(ρ). ``rho`` is the packing fraction of the *later* snapshot of each pair (P2 Figs 6–10 plot the distance
  between consecutive samples against ρ).
- `select_table_snapshots`, `table_state_candidates`, `chosen_states` — the states a, b, c of Tables I–III and
  Figs 1, 3: three consecutive samples around ``table_rho`` (P2: ρ ≈ 0.79) of the realization whose Z and ⟨F_n⟩
  change least over them (P2 Fig. 1: "almost identical").
- `p2_tables`, `write_table` — Tables I–III: distances (a,b) and (a,c) of the normal-force diagrams over the
  whole box (Table I) and per quadrant of the box (Tables II, III), β0 and β1 × d_B, d_W1, d_W2, as P2 prints
  them, with P2's printed values (`P2_TABLE_VALUES`) and ours / P2's beside them.
- `P2_QUOTED_LEVELS` — the levels P2 quotes in words for Figs 6–9 (drawn by `forcenet.plotting.p2`).
- `lagged_distances`, `lagged_distance_summary` — distances between states k samples apart, per P2 regime: how
  the sampling step and the wall speed change the distances (docs/p2_sampling.md, scripts/p2_sampling.py).
- `p2_validation`, `p2_validation_markdown`, `write_p2_validation` — each claim of P2 §III D–§IV (and the
  conclusions that summarise §IV) with the measured evidence, the criterion, a computed verdict and, where it
  does not hold, the explanation (`EXPLANATIONS`: the cause, measured in docs/p2_sampling.md, and diagnostics
  measured on the same data). The only numbers typed in are P2's own (the ``reference`` column, the ρ ranges it
  names, its printed tables) and, in the explanations, what docs/p2_sampling.md measured; the tolerances are
  fields of `ValidationTolerances`.
"""
from __future__ import annotations

import math
import os
import warnings
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Callable, Mapping, Sequence

import numpy as np
import pandas as pd
import xarray as xr

from forcenet.datasets.schema import DIMENSIONLESS, FORCE_KINDS, NETWORK_FORCE_UNITS
from forcenet.network.regions import QUADRANTS as _NETWORK_QUADRANTS
from forcenet.systems import select_table_snapshots  # noqa: F401 — part of this module's P2 API (Tables I–III)

# --- what P2 compares -------------------------------------------------------------------------------------------
P2_FORCE_KINDS = ("normal", "tangential")  # P2 §IV A (normal), §IV B (tangential)
P2_HOMOLOGY_DIMS = (0, 1)  # β0 components, β1 loops
METRICS = ("bottleneck", "wasserstein_1", "wasserstein_2")  # P2 §III D
METRIC_SYMBOLS = {"bottleneck": "d_B", "wasserstein_1": "d_W1", "wasserstein_2": "d_W2"}
METRIC_LONG_NAMES = {
    "bottleneck": "bottleneck distance d_B",
    "wasserstein_1": "degree-1 Wasserstein distance d_W1",
    "wasserstein_2": "degree-2 Wasserstein distance d_W2",
}
ESSENTIAL_CONVENTIONS_DOC = {
    "minus_one": "never-dying classes are given death = -1 <F> before matching (P2 §III B, Fig. 5)",
    "zero": "never-dying classes are given death = 0 before matching",
    "drop": "never-dying classes are left out of the matching",
}
QUADRANTS = tuple(_NETWORK_QUADRANTS)  # P2 Tables II–III row order: bottom left, bottom right, top right, top left
TABLE_PAIRS = ("(a,b)", "(a,c)")
TABLE_RHO_KEYS = ("rho_a", "rho_b", "rho_c")  # packing fractions of snapshots a, b, c (table attrs / CSV columns)
FRICTIONAL, FRICTIONLESS = "2d_poly_mu05", "2d_poly_mu0"

HOLDS, FAILS, NOT_EVALUATED = "holds", "does not hold", "not evaluated"
VALIDATION_COLUMNS = ("claim_id", "section", "system", "claim", "reference", "criterion", "measured", "verdict",
                      "explanation")


# =============================================================================================================
# Adapters to forcenet.network / forcenet.topology / forcenet.measures (the only places that call them)
# =============================================================================================================
def _diagram_from_points(birth: np.ndarray, death: np.ndarray, essential: np.ndarray, homology_dim: int):
    """A `forcenet.topology.PersistenceDiagrams` holding one homology dimension's points (never-dying ones at
    death −inf, whatever death the file gave them)."""
    from forcenet.topology import PersistenceDiagrams

    n = len(birth)
    death = np.where(np.asarray(essential, dtype=bool), -np.inf, np.asarray(death, dtype=float))
    return PersistenceDiagrams(homology_dim=np.full(n, homology_dim, dtype=np.int64),
                               birth=np.asarray(birth, dtype=float), death=death)


def _distances(pd_a, pd_b, homology_dim: int, essential_convention: str) -> dict[str, float]:
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


def _snapshot_network(snapshot: xr.Dataset, kind: str, remove_rattlers: bool | str):
    """The force network of one snapshot, forces in units of that network's mean (P2 §II)."""
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
    net = _snapshot_network(snapshot, kind, remove_rattlers)
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


def _network_diagrams(network):
    from forcenet.topology import persistence_diagrams

    return persistence_diagrams(network)


def _quadrant_diagrams(network, snapshot: xr.Dataset) -> dict:
    """Diagrams of each quarter of the snapshot's own box (P2 Tables II–III): {quadrant: PersistenceDiagrams}."""
    from forcenet.topology import quadrant_persistence_diagrams

    return quadrant_persistence_diagrams(network, snapshot["box_lo"].values, snapshot["box_hi"].values)


def _rho_at_isostatic_crossing(rho: np.ndarray, z: np.ndarray, dimension: int) -> float:
    """ρ where Z(ρ) first reaches d + 1 (P2 §IV A: ρ_J loosely where Z ≈ 3 in 2D)."""
    from forcenet.measures import isostatic_crossing

    return float(isostatic_crossing(rho, z, dimension))


# =============================================================================================================
# Distances between consecutive snapshots (P2 §IV, Figs 6–10)
# =============================================================================================================
def diagram_points(analysis: xr.Dataset, kind: str, homology_dim: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(birth, death, essential) of one diagram stored in a per-snapshot analysis dataset."""
    kind_index = FORCE_KINDS.index(kind)
    if "point" not in analysis.dims or analysis.sizes["point"] == 0:
        return np.empty(0), np.empty(0), np.empty(0, dtype=bool)
    mask = ((analysis["diagram_force_kind"].values == kind_index)
            & (analysis["diagram_homology_dim"].values == homology_dim))
    birth = analysis["birth"].values[mask].astype(float)
    death = analysis["death"].values[mask].astype(float)
    essential = analysis["essential"].values[mask].astype(bool) | ~np.isfinite(death)
    return birth, death, essential


def analysis_diagram(analysis: xr.Dataset, kind: str, homology_dim: int):
    """The `PersistenceDiagrams` of one force kind and homology dimension of an analysis dataset."""
    return _diagram_from_points(*diagram_points(analysis, kind, homology_dim), homology_dim)


def consecutive_distances(analyses: Sequence[xr.Dataset], essential_convention: str = "minus_one", *,
                          force_kinds: Sequence[str] = P2_FORCE_KINDS,
                          homology_dims: Sequence[int] = P2_HOMOLOGY_DIMS) -> xr.Dataset:
    """d_B, d_W1, d_W2 between the diagrams of consecutive snapshots of ONE realization.

    Parameters
    ----------
    analyses : per-snapshot analysis datasets (``results/analysis/{system}/r{NN}/rho{ρ}.nc``) in increasing ρ
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
    if np.any(np.diff(rho) <= 0):
        raise ValueError(f"analyses must be in strictly increasing rho, got {rho.tolist()}")
    force_kinds, homology_dims = tuple(force_kinds), tuple(int(h) for h in homology_dims)
    values = np.full((len(analyses) - 1, len(force_kinds), len(homology_dims), len(METRICS)), np.nan)
    for a, kind in enumerate(force_kinds):
        for b, dim in enumerate(homology_dims):
            diagrams = [analysis_diagram(ds, kind, dim) for ds in analyses]
            values[:, a, b] = _consecutive_distances(diagrams, dim, essential_convention)
    z = np.array([float(ds["Z"]) if "Z" in ds else math.nan for ds in analyses[1:]])
    out = xr.Dataset(
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
    return out


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
    conventions = {ds.attrs.get("essential_convention") for ds in per_realization}
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


def _distance_attrs() -> dict:
    return {"units": NETWORK_FORCE_UNITS,
            "long_name": "distance between the persistence diagrams of consecutive snapshots "
                         "(super-level filtration, L-infinity ground metric)"}


def _rho_attrs() -> dict:
    return {"units": DIMENSIONLESS, "long_name": "packing fraction of the later snapshot of each pair"}


def _distance_coords(rho, force_kinds, homology_dims) -> dict:
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
    return _network_diagrams(_snapshot_network(snapshot, kind, rattler_rule))


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
            d = _distances(diagrams[s], diagrams[s + lag], h, essential_convention)
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
        rho_j = _rho_at_isostatic_crossing(np.asarray(rho), np.asarray(z), dimension)
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
    header = ["v_c [d/τ_c]", "k", "Δρ", "window", "pairs"] + [_pretty_column(c) for c in values]
    lines = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    for _, r in summary.iterrows():
        window = r["window"].replace("rho_J", f"ρ_J = {r['rho_J']:.3f}").replace("rho", "ρ")
        lines.append("| " + " | ".join([f"{r['wall_speed']:g}", str(int(r["lag"])), f"{r['delta_rho']:.4f}", window,
                                        str(int(r["pairs"]))] + [_format(r[c], 2) for c in values]) + " |")
    return "\n".join(lines) + "\n"


# =============================================================================================================
# Reductions shared by the figures and the validation
# =============================================================================================================
def realization_mean(da: xr.DataArray) -> xr.DataArray:
    """Mean over realizations (NaN skipped); unchanged if there is no realization dimension."""
    return da.mean("realization", skipna=True) if "realization" in da.dims else da


def realization_band(da: xr.DataArray, low: float = 0.16, high: float = 0.84) -> tuple[xr.DataArray, xr.DataArray]:
    """The spread over realizations as the [low, high] quantile band (positive where the data are, so it
    can be drawn on a log axis); the band collapses to the value for a single realization."""
    if "realization" not in da.dims:
        return da, da
    with warnings.catch_warnings():  # a ρ where every realization is NaN (0/0 ratio) stays NaN, silently
        warnings.simplefilter("ignore", RuntimeWarning)
        return (da.quantile(low, "realization", skipna=True).drop_vars("quantile"),
                da.quantile(high, "realization", skipna=True).drop_vars("quantile"))


def _metric_ratio(distance: xr.DataArray, denominator: str, numerator: str = "bottleneck") -> xr.DataArray:
    """numerator / denominator along the ``metric`` dimension of `distance`, NaN where the denominator is not
    positive. The one place the ratios of P2 Figs 7, 10 are computed (figures and validation use it)."""
    den = distance.sel(metric=denominator)
    return (distance.sel(metric=numerator) / den.where(den > 0)).drop_vars("metric", errors="ignore")


def distance_ratio(distances: xr.Dataset, denominator: str, numerator: str = "bottleneck") -> xr.DataArray:
    """d_B / d_Wq per realization (P2 Figs 7, 10), NaN where the denominator is 0."""
    return _metric_ratio(distances["distance"], denominator, numerator)


def mean_distance_ratio(distances: xr.Dataset, denominator: str, numerator: str = "bottleneck") -> xr.DataArray:
    """Ratio of the realization-mean distances: the ratio of the curves P2 Figs 6 and 8 draw (Figs 7, 10)."""
    return _metric_ratio(realization_mean(distances["distance"]), denominator, numerator)


def jamming_density(distances: xr.Dataset, dimension: int = 2) -> float:
    """ρ_J: where the realization-mean Z(ρ) first reaches d + 1 (P2 §IV A); NaN if it never does."""
    z = realization_mean(distances["Z"])
    ok = np.isfinite(z.values)
    if ok.sum() < 2:
        return math.nan
    return _rho_at_isostatic_crossing(z["rho"].values[ok], z.values[ok], dimension)


def jamming_density_per_realization(distances: xr.Dataset, dimension: int = 2) -> np.ndarray:
    if "realization" not in distances.dims:
        return np.array([jamming_density(distances, dimension)])
    return np.array([jamming_density(distances.isel(realization=i), dimension)
                     for i in range(distances.sizes["realization"])])


@dataclass(frozen=True)
class QuotedLevel:
    """A level P2 quotes in words for one of its figures, drawn on ours over the ρ range it applies to.

    figure : P2's figure number (6–10); homology_dim : k of the panel; metric : the distance (Figs 6, 8, 9) or the
    denominator d_Wq of d_B/d_Wq (Figs 7, 10); value : P2's level; rho_below : upper end of the ρ range, a number
    or ``"rho_J"``; text : P2's statement (legend label).
    """

    figure: int
    homology_dim: int
    metric: str
    value: float
    rho_below: float | str
    text: str


#: P2's quoted levels (§IV A, B, C); Fig. 10 gets none: P2 only says its d_B/d_W2 is "roughly the same" as Fig. 7's
P2_QUOTED_LEVELS = (
    QuotedLevel(6, 0, "bottleneck", 10.0, "rho_J", r"P2 §IV A: $d_B \approx 10$ ($\gg 1$) before $\rho_J$"),
    QuotedLevel(7, 0, "wasserstein_2", 0.75, 0.75, r"P2 §IV A: $d_B/d_{W2} \approx 0.75$ for $\rho < 0.75$"),
    QuotedLevel(7, 0, "wasserstein_1", 0.2, 0.75, r"P2 §IV A: $d_B/d_{W1} \approx 0.2$ for $\rho < 0.75$"),
    QuotedLevel(8, 0, "bottleneck", 10.0, "rho_J", r"P2 §IV B: $d_B$ as for normal forces ($\approx 10$ before $\rho_J$)"),
    QuotedLevel(9, 0, "bottleneck", 10.0, 0.65, r"P2 §IV C: $d_B$ as with friction ($\approx 10$) for $\rho < 0.65$"),
)


def quoted_levels(figure: int, homology_dim: int) -> list[QuotedLevel]:
    """P2's quoted levels for one panel of one of its figures (`P2_QUOTED_LEVELS`)."""
    return [q for q in P2_QUOTED_LEVELS if q.figure == figure and q.homology_dim == homology_dim]


# =============================================================================================================
# Tables I–III (P2 §III D): three nearby snapshots, whole box and quadrants
# =============================================================================================================
def p2_tables(snapshots: Sequence[xr.Dataset], *, kind: str = "normal", remove_rattlers: bool | str = True,
              essential_convention: str = "minus_one") -> dict[str, pd.DataFrame]:
    """P2 Tables I–III from three nearby snapshots (a, b, c) of one realization, in increasing ρ.

    Table I: distances (PD^a, PD^b) and (PD^a, PD^c) over the whole box. Tables II and III: the same for each
    quarter of the box (bottom left, bottom right, top right, top left, as P2), the quarters taken at each
    snapshot's own walls. Columns: β0 and β1 × d_B, d_W1, d_W2 (``beta0_d_B`` …), normal forces as P2.

    Returns ``{"table1": …, "table2": …, "table3": …}``; each DataFrame's ``attrs`` holds the caption and ρ_a,
    ρ_b, ρ_c.
    """
    if len(snapshots) != 3:
        raise ValueError(f"Tables I-III need three snapshots a, b, c; got {len(snapshots)}")
    rho = [float(s["rho"]) for s in snapshots]
    if not rho[0] < rho[1] < rho[2]:
        raise ValueError(f"snapshots a, b, c must be in increasing rho, got {rho}")
    networks = [_snapshot_network(s, kind, remove_rattlers) for s in snapshots]
    whole = [_network_diagrams(n) for n in networks]
    parts = [_quadrant_diagrams(n, s) for n, s in zip(networks, snapshots)]

    def row(pd_x, pd_y) -> dict[str, float]:
        out = {}
        for h in P2_HOMOLOGY_DIMS:
            d = _distances(pd_x, pd_y, h, essential_convention)
            out.update({table_column(h, m): d[m] for m in METRICS})
        return out

    table1 = pd.DataFrame([row(whole[0], whole[1]), row(whole[0], whole[2])],
                          index=pd.Index(TABLE_PAIRS, name="pair"))
    quadrants = pd.Index(QUADRANTS, name="quadrant")
    table2 = pd.DataFrame([row(parts[0][q], parts[1][q]) for q in QUADRANTS], index=quadrants)
    table3 = pd.DataFrame([row(parts[0][q], parts[2][q]) for q in QUADRANTS], index=quadrants)
    meta = {**dict(zip(TABLE_RHO_KEYS, rho)), "force_kind": kind, "essential_convention": essential_convention,
            "rattler_rule": networks[0].rattler_rule, "realization": int(snapshots[0].attrs.get("realization", -1))}
    captions = {
        "table1": "Table I: distances between the persistence diagrams of the force networks of snapshots a, b, c",
        "table2": "Table II: distances (PD^a, PD^b) between corresponding quarters of the box",
        "table3": "Table III: distances (PD^a, PD^c) between corresponding quarters of the box",
    }
    tables = {"table1": table1, "table2": table2, "table3": table3}
    for name, table in tables.items():
        table.attrs.update(meta, caption=captions[name])
    return tables


# --- which realization gives the states a, b, c ---------------------------------------------------------------
TABLE_STATE_CRITERION = (
    "P2 Fig. 1: the three states look alike and 'both the average contact number Z and the average force are almost "
    "identical'. Among the realizations, the one whose states a, b, c (consecutive samples around table_rho) change "
    "Z and the mean normal force <F_n> least: score = the larger of max(|Z_x - Z_a|)/Z_a and "
    "max(|<F_n>_x - <F_n>_a|)/<F_n>_a over x = b, c; the lowest score is chosen, the lowest index on ties")
TABLE_STATE_COLUMNS = ("realization", *TABLE_RHO_KEYS, "Z_a", "Z_b", "Z_c", "mean_normal_force_a",
                       "mean_normal_force_b", "mean_normal_force_c", "Z_change", "force_change", "score", "chosen")


def table_state_candidates(analyses: Sequence[xr.Dataset]) -> pd.DataFrame:
    """The candidate states a, b, c of Tables I–III and Figs 1, 3: one row per realization (`TABLE_STATE_COLUMNS`).

    Parameters
    ----------
    analyses : per-snapshot analysis files of states a, b, c of every realization (three per realization, told
        apart by their ``realization`` attribute): Z and the mean normal force ⟨F_n⟩ [m̄ d_ave τ_c⁻²] are read.

    Returns
    -------
    DataFrame with ρ, Z, ⟨F_n⟩ of a, b, c, the relative changes, the score and ``chosen`` (one True row) by
    `TABLE_STATE_CRITERION`.
    """
    by_realization: dict[int, list[xr.Dataset]] = {}
    for ds in analyses:
        by_realization.setdefault(int(ds.attrs["realization"]), []).append(ds)
    normal = FORCE_KINDS.index("normal")
    rows = []
    for realization, states in sorted(by_realization.items()):
        if len(states) != 3:
            raise ValueError(f"realization {realization}: {len(states)} states, need a, b, c")
        states = sorted(states, key=lambda ds: float(ds["rho"]))
        z = [float(ds["Z"]) for ds in states]
        force = [float(ds["mean_force"].values[normal]) for ds in states]
        z_change = max(abs(z[1] - z[0]), abs(z[2] - z[0])) / z[0] if z[0] > 0 else math.inf
        force_change = max(abs(force[1] - force[0]), abs(force[2] - force[0])) / force[0] if force[0] > 0 else math.inf
        rows.append({"realization": realization, **{k: float(ds["rho"]) for k, ds in zip(TABLE_RHO_KEYS, states)},
                     "Z_a": z[0], "Z_b": z[1], "Z_c": z[2], "mean_normal_force_a": force[0],
                     "mean_normal_force_b": force[1], "mean_normal_force_c": force[2], "Z_change": z_change,
                     "force_change": force_change, "score": max(z_change, force_change)})
    if not rows:
        raise ValueError("no candidate states a, b, c")
    table = pd.DataFrame(rows, columns=list(TABLE_STATE_COLUMNS[:-1]))
    table["chosen"] = False
    table.loc[table["score"].idxmin(), "chosen"] = True  # idxmin: first (lowest realization) on ties
    table.attrs["criterion"] = TABLE_STATE_CRITERION
    return table


def chosen_states(datasets: Sequence[xr.Dataset], candidates: pd.DataFrame) -> list[xr.Dataset]:
    """The datasets (snapshots or analyses) of the chosen realization of `candidates`, in increasing ρ."""
    chosen = candidates[candidates["chosen"].astype(bool)]
    if len(chosen) != 1:
        raise ValueError(f"{len(chosen)} chosen realizations in the table-state candidates, need one")
    realization = int(chosen["realization"].iloc[0])
    picked = sorted((ds for ds in datasets if int(ds.attrs.get("realization", -1)) == realization),
                    key=lambda ds: float(ds["rho"]))
    if not picked:
        raise ValueError(f"no dataset of the chosen realization {realization}")
    expected = chosen[list(TABLE_RHO_KEYS)].to_numpy(dtype=float)[0][:len(picked)]
    if not np.allclose([float(ds["rho"]) for ds in picked], expected, atol=1e-9):
        raise ValueError(f"realization {realization}: states at rho {[float(ds['rho']) for ds in picked]}, "
                         f"expected {expected.tolist()}")
    return picked


def table_column(homology_dim: int, metric: str) -> str:
    """Column name of a table entry: ``beta0_d_B``, ``beta1_d_W2`` …"""
    return f"beta{homology_dim}_{METRIC_SYMBOLS[metric]}"


# P2's printed Tables I–III (μ = 0.5, normal forces, three nearby states at ρ ≈ 0.79), columns β0 then β1 ×
# d_B, d_W1, d_W2 as `table_column` orders them: printed beside ours, and the reference of the III.D claims
P2_TABLE_VALUES = {
    "table1": {"(a,b)": (0.089, 4.18, 0.50, 0.081, 3.8, 0.57),
               "(a,c)": (0.12, 14.0, 0.89, 0.15, 19.2, 0.99)},
    "table2": {"bottom left": (0.12, 3.6, 0.50, 0.16, 3.66, 0.95),
               "bottom right": (0.014, 0.40, 0.070, 0.014, 0.43, 0.037),
               "top right": (0.0046, 0.58, 0.35, 0.0055, 0.29, 0.024),
               "top left": (0.0076, 0.56, 0.31, 0.0045, 0.23, 0.019)},
    "table3": {"bottom left": (0.16, 4.1, 0.53, 0.13, 5.8, 0.59),
               "bottom right": (0.18, 5.2, 0.67, 0.14, 5.6, 0.50),
               "top right": (0.10, 5.1, 0.69, 0.12, 5.5, 0.51),
               "top left": (0.11, 4.3, 0.53, 0.087, 5.1, 0.87)},
}
P2_PREFIX, RATIO_PREFIX = "p2_", "ratio_"  # CSV columns of P2's value and of ours / P2's


def p2_reference_table(name: str) -> pd.DataFrame:
    """P2's printed Table I, II or III (``"table1"`` …) with our row labels and `table_column` columns."""
    rows = P2_TABLE_VALUES[name]
    columns = [table_column(h, m) for h in P2_HOMOLOGY_DIMS for m in METRICS]
    index = pd.Index(list(rows), name="pair" if name == "table1" else "quadrant")
    return pd.DataFrame([rows[label] for label in index], index=index, columns=columns)


def table_markdown(table: pd.DataFrame, digits: int = 3, reference: pd.DataFrame | None = None) -> str:
    """One table as Markdown, with P2's header (β0/β1 × d_B, d_W1, d_W2) and a caption with ρ_a, ρ_b, ρ_c.

    With `reference` (P2's printed table, `p2_reference_table`), each row of ours is followed by P2's row and
    the row of ratios ours / P2's."""
    header = [table.index.name or ""] + [_pretty_column(c) for c in table.columns]
    lines = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    for label, values in table.iterrows():
        lines.append("| " + " | ".join([str(label)] + [_format(v, digits) for v in values]) + " |")
        if reference is not None and label in reference.index:
            paper = reference.loc[label, table.columns]
            lines.append("| " + " | ".join([f"{label}, P2"] + [_format(float(v), digits) for v in paper]) + " |")
            lines.append("| " + " | ".join([f"{label}, ours / P2"] + [_format(float(v), 2) for v in
                                                                      values / paper]) + " |")
    caption = table.attrs.get("caption", "")
    rhos = ", ".join(f"{key} = {table.attrs[key]:.4f}" for key in TABLE_RHO_KEYS if key in table.attrs)
    kind = table.attrs.get("force_kind")
    realization = table.attrs.get("realization", -1)
    rule = table.attrs.get("rattler_rule")
    note = "; ".join(x for x in (rhos, f"realization {realization}" if realization >= 0 else "",
                                 f"{kind} forces" if kind else "", f"rattler rule '{rule}'" if rule else "",
                                 "distances in units of <F>") if x)
    return "\n".join(([f"{caption} ({note}).", ""] if caption else []) + lines) + "\n"


def write_table(table: pd.DataFrame, csv_path: str | os.PathLike, md_path: str | os.PathLike,
                reference: pd.DataFrame | None = None) -> None:
    """Write one of Tables I–III as CSV (machine-readable, flat columns: ours, then with `reference` P2's values
    ``p2_*`` and ours / P2's ``ratio_*``) and Markdown (P2's layout, P2's rows beside ours)."""
    for path in (csv_path, md_path):
        Path(path).parent.mkdir(parents=True, exist_ok=True)
    frame = table.copy()
    if reference is not None:
        paper = reference.loc[table.index, table.columns]
        frame = frame.join(paper.add_prefix(P2_PREFIX)).join((table / paper).add_prefix(RATIO_PREFIX))
    for key in TABLE_RHO_KEYS:
        if key in table.attrs:
            frame[key] = table.attrs[key]
    frame.to_csv(csv_path)
    Path(md_path).write_text(table_markdown(table, reference=reference))


def write_p2_tables(tables: Mapping[str, pd.DataFrame], directory: str | os.PathLike,
                    prefix: str = "p2_") -> list[Path]:
    """Write every table of `p2_tables` as ``{directory}/{prefix}{name}.csv`` and ``.md``
    (``results/tables/p2_table1.csv`` …); returns the paths written."""
    written = []
    for name, table in tables.items():
        csv_path, md_path = Path(directory) / f"{prefix}{name}.csv", Path(directory) / f"{prefix}{name}.md"
        write_table(table, csv_path, md_path, p2_reference_table(name) if name in P2_TABLE_VALUES else None)
        written += [csv_path, md_path]
    return written


def read_table(csv_path: str | os.PathLike) -> pd.DataFrame:
    """Read a table written by `write_table`: our values (ρ_a, ρ_b, ρ_c go back into ``attrs``; P2's values and
    the ratios are left out)."""
    frame = pd.read_csv(csv_path, index_col=0)
    frame = frame.drop(columns=[c for c in frame.columns if c.startswith((P2_PREFIX, RATIO_PREFIX))])
    for key in TABLE_RHO_KEYS:
        if key in frame:
            frame.attrs[key] = float(frame[key].iloc[0])
            frame = frame.drop(columns=key)
    return frame


def _pretty_column(column: str) -> str:
    beta, _, symbol = column.partition("_")
    return f"β{beta[-1]} {symbol}" if beta.startswith("beta") else column


def _format(value: Any, digits: int = 3) -> str:
    if isinstance(value, (float, np.floating)):
        if not np.isfinite(value):
            return "n/a"
        return f"{value:.{digits}g}"
    return str(value)


# =============================================================================================================
# Validation: each claim of P2 §III D–§IV with its evidence and a computed verdict
# =============================================================================================================
@dataclass(frozen=True)
class ValidationTolerances:
    """How P2's qualitative words are turned into tests. Every verdict uses these and nothing else."""

    value_factor: float = 1.5  # "≈ x", "roughly the same", "similar": measured within [x / f, x · f]
    max_cv: float = 0.5  # "roughly / essentially constant": coefficient of variation over the ρ range ≤ this
    fall_factor: float = 10.0  # "slows dramatically" after ρ_J: median after ≤ median before / this
    drop_factor: float = 2.0  # "decreases dramatically" / "plunges" inside the unjammed regime
    decades: float = 0.5  # "n orders of magnitude smaller": measured log10 drop within n ± this
    trend: float = 0.5  # "increases" / "decreases" with ρ: Spearman rank correlation ≥ this / ≤ −this
    correlation: float = 0.7  # "tracks" / "follows": Pearson correlation of the log10 curves ≥ this
    near_jamming: float = 0.02  # "near / close to ρ_J": |ρ − ρ_J| ≤ this
    peak_window: float = 0.03  # "at ρ ≈ x" for an extremum: it lies within x ± this
    well_below: float = 0.05  # "ρ significantly less than ρ_J": ρ < ρ_J − this
    consistently: float = 0.8  # "consistently larger": true at this fraction of the compared ρ values
    dominance: float = 2.0  # "concentrated in one quadrant": largest ≥ this × second largest (median over columns)
    spread: float = 2.0  # "distributed evenly": largest / smallest quadrant ≤ this (median over columns)
    min_points: int = 2  # fewer ρ values than this in a range: the claim is not evaluated
    correlation_points: int = 3  # fewer ρ values than this: no correlation is computed (2 points always give ±1)


class _NotEvaluated(Exception):
    """Raised inside a claim when the data cannot decide it (missing system, empty ρ range, no ρ_J)."""


@dataclass
class _Curves:
    """Realization-mean curves of one system, as pandas Series over ρ (NaN dropped)."""

    name: str
    ds: xr.Dataset
    dimension: int
    tol: ValidationTolerances
    rho_j: float = field(init=False)

    def __post_init__(self):
        self.rho_j = jamming_density(self.ds, self.dimension)
        mean = realization_mean(self.ds["distance"])
        self._curves = {(k, int(h), m): _series(mean.sel(force_kind=k, homology_dim=h, metric=m))
                        for k in mean["force_kind"].values for h in mean["homology_dim"].values
                        for m in mean["metric"].values}

    @property
    def n_realizations(self) -> int:
        return int(self.ds.sizes.get("realization", 1))

    def mean(self, kind: str, dim: int, metric: str) -> pd.Series:
        """Realization-mean distance curve over ρ."""
        try:
            return self._curves[kind, dim, metric]
        except KeyError:
            raise _NotEvaluated(f"{self.name}: no {kind} PD{dim} {metric} distances") from None

    def ratio(self, kind: str, dim: int, denominator: str) -> pd.Series:
        """d_B / d_Wq of the realization-mean curves where d_Wq > 0: `mean_distance_ratio`, the curves the
        figures draw (P2 Figs 7, 10)."""
        for metric in (B, denominator):
            self.mean(kind, dim, metric)  # not evaluated unless both curves exist
        return _series(mean_distance_ratio(self.ds, denominator).sel(force_kind=kind, homology_dim=dim))

    def jammed(self) -> float:
        if not np.isfinite(self.rho_j):
            raise _NotEvaluated(f"{self.name}: the mean Z does not rise through d+1 = {self.dimension + 1} "
                                "inside the rho range")
        return self.rho_j

    def window(self, s: pd.Series, lo: float = -np.inf, hi: float = np.inf, *, closed_lo: bool = True,
               closed_hi: bool = False) -> pd.Series:
        """The finite values of curve `s` with ρ between `lo` and `hi` ([lo, hi) unless `closed_lo` /
        `closed_hi` say otherwise); not evaluated when fewer than `min_points` are left (an empty or all-NaN
        curve included)."""
        rho = s.index.values
        inside = ((rho >= lo) if closed_lo else (rho > lo)) & ((rho <= hi) if closed_hi else (rho < hi))
        part = s[inside & np.isfinite(s.values)]
        if len(part) < self.tol.min_points:
            interval = f"{'[' if closed_lo else '('}{lo:.3f}, {hi:.3f}{']' if closed_hi else ')'}"
            raise _NotEvaluated(f"{self.name}: {len(part)} rho value(s) in {interval} (need {self.tol.min_points})")
        return part

    def argmax(self, s: pd.Series, lo: float = -np.inf, hi: float = np.inf, **closed: bool) -> float:
        """ρ of the largest value of `s` in a `window` (not evaluated if the window has too few values)."""
        return float(self.window(s, lo, hi, **closed).idxmax())


def _series(da: xr.DataArray) -> pd.Series:
    s = pd.Series(np.asarray(da.values, dtype=float), index=np.asarray(da["rho"].values, dtype=float))
    return s[np.isfinite(s.values)]


def _cv(s: pd.Series) -> float:
    mean = float(np.mean(s.values))
    return float(np.std(s.values) / abs(mean)) if mean != 0 else math.inf


def _ranks(x: np.ndarray) -> np.ndarray:
    return pd.Series(x).rank(method="average").to_numpy()


def _pearson(x: np.ndarray, y: np.ndarray) -> float:
    x, y = np.asarray(x, float), np.asarray(y, float)
    if len(x) < 2 or np.std(x) == 0 or np.std(y) == 0:
        return math.nan
    return float(np.corrcoef(x, y)[0, 1])


def _spearman(s: pd.Series) -> float:
    """Rank correlation of a curve with ρ (+1: increases monotonically, −1: decreases)."""
    return _pearson(_ranks(s.index.values), _ranks(s.values))


def _within(value: float, reference: float, factor: float) -> bool:
    return bool(np.isfinite(value) and reference / factor <= value <= reference * factor)


def _log_ratio(num: pd.Series, den: pd.Series) -> pd.Series:
    """log10(num/den) at the ρ both curves share (positive values only)."""
    common = num.index.intersection(den.index)
    n, d = num[common], den[common]
    ok = (n > 0) & (d > 0)
    return np.log10(n[ok] / d[ok])


def _on_grid(s: pd.Series, x: np.ndarray) -> np.ndarray:
    """Linear interpolation of a curve onto x (NaN outside its range)."""
    return np.interp(x, s.index.values, s.values, left=np.nan, right=np.nan)


def _f(value: float, digits: int = 3) -> str:
    return _format(float(value), digits)


def _per_metric(values: Mapping[str, float]) -> str:
    """``d_B 1.2, d_W1 0.34, …`` for {metric: value}."""
    return ", ".join(f"{METRIC_SYMBOLS[m]} {_f(v, 2)}" for m, v in values.items())


def _per_dim_metric(values: Mapping[tuple[int, str], float]) -> str:
    """``beta0 d_B 1.2, …`` for {(homology_dim, metric): value}."""
    return ", ".join(f"beta{h} {METRIC_SYMBOLS[m]} {_f(v, 2)}" for (h, m), v in values.items())


def _quotient(numerator: float, denominator: float, what: str = "") -> float:
    """numerator / denominator of two non-negative values, inf where only the denominator is 0. Both 0 (no
    change at all in either curve, e.g. no loops yet) cannot be compared: the claim is not evaluated."""
    if denominator > 0:
        return float(numerator) / float(denominator)
    if numerator > 0:
        return math.inf
    raise _NotEvaluated(f"both rates are 0{' (' + what + ')' if what else ''}: nothing to compare")


@dataclass
class _Context:
    curves: dict[str, _Curves]
    tables: Mapping[str, pd.DataFrame] | None
    tol: ValidationTolerances
    frictional: str
    frictionless: str
    measures: Mapping[str, xr.Dataset] = field(default_factory=dict)
    states: pd.DataFrame | None = None

    def system(self, name: str) -> _Curves:
        if name not in self.curves:
            raise _NotEvaluated(f"system {name} not in the results")
        return self.curves[name]

    def both(self) -> tuple[_Curves, _Curves]:
        """(frictional, frictionless) curves; not evaluated unless both systems are in the results."""
        return self.system(self.frictional), self.system(self.frictionless)

    def table(self, name: str) -> pd.DataFrame:
        if not self.tables or name not in self.tables:
            raise _NotEvaluated(f"{name} not given")
        return self.tables[name]


# Each claim: (id, section, system role, claim text, reference, criterion builder, evaluation) --------------------
@dataclass(frozen=True)
class _Claim:
    claim_id: str
    section: str
    system: str  # "frictional", "frictionless", "both", or "tables"
    text: str
    reference: str
    criterion: Callable[[ValidationTolerances], str]
    evaluate: Callable[[_Context], tuple[str, bool]]  # → (measured, holds)


NORMAL, TANGENTIAL = "normal", "tangential"
B, W1, W2 = "bottleneck", "wasserstein_1", "wasserstein_2"


def _a_peak_near_jamming(ctx: _Context) -> tuple[str, bool]:
    c = ctx.system(ctx.frictional)
    rho_j = c.jammed()
    peaks = {h: c.argmax(c.mean(NORMAL, h, W1)) for h in P2_HOMOLOGY_DIMS}
    ok = all(abs(p - rho_j) <= ctx.tol.peak_window for p in peaks.values())
    return (f"rho_J = {_f(rho_j)}; argmax of mean d_W1: beta0 at {_f(peaks[0])}, beta1 at {_f(peaks[1])}", ok)


def _a_db_large_before(ctx: _Context) -> tuple[str, bool]:
    c = ctx.system(ctx.frictional)
    s = c.window(c.mean(NORMAL, 0, B), hi=c.jammed())
    median = float(s.median())
    return f"median d_B(beta0) over rho < rho_J = {_f(c.rho_j)}: {_f(median)} <F>", median >= 10 / ctx.tol.value_factor


def _ratio_constant(denominator: str, reference: float):
    """(criterion, evaluate) of "for rho < 0.75, d_B/d_Wq (beta0) is roughly constant and ≈ `reference`"."""
    def criterion(t: ValidationTolerances) -> str:
        return f"median within a factor {t.value_factor} of {_f(reference)} and CV <= {t.max_cv}"

    def evaluate(ctx: _Context) -> tuple[str, bool]:
        c = ctx.system(ctx.frictional)
        s = c.window(c.ratio(NORMAL, 0, denominator), hi=0.75)
        median, cv = float(s.median()), _cv(s)
        ok = _within(median, reference, ctx.tol.value_factor) and cv <= ctx.tol.max_cv
        return (f"median d_B/{METRIC_SYMBOLS[denominator]} = {_f(median)}, CV = {_f(cv, 2)} over {len(s)} rho values "
                f"< 0.75 (rho_J = {_f(c.rho_j)})", ok)
    return criterion, evaluate


def _a_db_drops_at_075(ctx: _Context) -> tuple[str, bool]:
    c = ctx.system(ctx.frictional)
    s = c.mean(NORMAL, 0, B)
    before, after = c.window(s, hi=0.75), c.window(s, 0.75, c.jammed())
    m0, m1 = float(before.median()), float(after.median())
    return (f"median d_B(beta0): {_f(m0)} for rho < 0.75, {_f(m1)} for 0.75 <= rho < rho_J = {_f(c.rho_j)}",
            m1 <= m0 / ctx.tol.drop_factor)


def _a_w1_grows_before_jamming(ctx: _Context) -> tuple[str, bool]:
    c = ctx.system(ctx.frictional)
    w1 = c.window(c.mean(NORMAL, 0, W1), 0.75, c.jammed())
    r1 = c.window(c.ratio(NORMAL, 0, W1), 0.75, c.jammed())
    s_w1, s_r1 = _spearman(w1), _spearman(r1)
    return (f"Spearman(rho, d_W1) = {_f(s_w1, 2)}, Spearman(rho, d_B/d_W1) = {_f(s_r1, 2)} over "
            f"0.75 <= rho < rho_J = {_f(c.rho_j)} ({len(w1)} values)", s_w1 >= ctx.tol.trend and s_r1 <= -ctx.tol.trend)


def _a_w2_ratio_plunges(ctx: _Context) -> tuple[str, bool]:
    c = ctx.system(ctx.frictional)
    rho_j, near = c.jammed(), ctx.tol.near_jamming
    r2 = c.ratio(NORMAL, 0, W2)
    plateau = c.window(r2, 0.75, rho_j - near)
    before_jamming = c.window(r2, rho_j - near, rho_j, closed_hi=True)
    cv, median, low = _cv(plateau), float(plateau.median()), float(before_jamming.min())
    ok = cv <= ctx.tol.max_cv and low <= median / ctx.tol.drop_factor
    return (f"d_B/d_W2 over [0.75, rho_J - {near}): median {_f(median)}, CV {_f(cv, 2)}; minimum over "
            f"[rho_J - {near}, rho_J = {_f(rho_j)}]: {_f(low)}", ok)


def _a_loops_increase(ctx: _Context) -> tuple[str, bool]:
    c = ctx.system(ctx.frictional)
    hi = min(0.77, c.jammed())
    rhos = {m: _spearman(c.window(c.mean(NORMAL, 1, m), hi=hi)) for m in METRICS}
    median = float(np.nanmedian(list(rhos.values())))
    return f"Spearman(rho, d) for beta1 over rho < {_f(hi)}: {_per_metric(rhos)}", median >= ctx.tol.trend


def _a_loops_db_peak(ctx: _Context) -> tuple[str, bool]:
    c = ctx.system(ctx.frictional)
    peak = c.argmax(c.mean(NORMAL, 1, B))
    return (f"argmax of mean d_B(beta1): rho = {_f(peak)} (rho_J = {_f(c.rho_j)})",
            abs(peak - 0.77) <= ctx.tol.peak_window)


def _a_loop_ratios_decrease(ctx: _Context) -> tuple[str, bool]:
    c = ctx.system(ctx.frictional)
    hi = c.jammed()
    s = {d: _spearman(c.window(c.ratio(NORMAL, 1, d), 0.76, hi, closed_hi=True)) for d in (W2, W1)}
    return (f"Spearman(rho, ratio) for beta1 over 0.76 <= rho <= rho_J = {_f(hi)}: d_B/d_W2 {_f(s[W2], 2)}, "
            f"d_B/d_W1 {_f(s[W1], 2)}", all(v <= -ctx.tol.trend for v in s.values()))


def _fall_after_jamming(role: str):
    def evaluate(ctx: _Context) -> tuple[str, bool]:
        c = ctx.system(ctx.frictional if role == "frictional" else ctx.frictionless)
        rho_j = c.jammed()
        factors = {}
        for h in P2_HOMOLOGY_DIMS:
            for m in METRICS:
                s = c.mean(NORMAL, h, m)
                before, after = c.window(s, hi=rho_j).median(), c.window(s, lo=rho_j, closed_lo=False).median()
                factors[h, m] = _quotient(before, after, f"beta{h} {METRIC_SYMBOLS[m]} median before and after rho_J")
        worst = min(factors.values())
        text = f"rho_J = {_f(rho_j)}; median(rho < rho_J) / median(rho > rho_J): {_per_dim_metric(factors)}"
        return text, worst >= ctx.tol.fall_factor
    return evaluate


def _ratios_after_jamming(dim: int):
    def evaluate(ctx: _Context) -> tuple[str, bool]:
        c = ctx.system(ctx.frictional)
        rho_j = c.jammed()
        parts, ok = [], True
        for den, decades in ((W2, 1.0), (W1, 3.0)):
            r = c.ratio(NORMAL, dim, den)
            before = c.window(r, hi=min(0.75, rho_j))
            after = c.window(r, lo=rho_j, closed_lo=False)
            drop = math.log10(float(before.median()) / float(after.median()))
            cv = _cv(after)
            ok &= abs(drop - decades) <= ctx.tol.decades and cv <= ctx.tol.max_cv
            parts.append(f"d_B/{METRIC_SYMBOLS[den]}: drop {_f(drop, 2)} decades, CV after {_f(cv, 2)}")
        return f"beta{dim}, rho_J = {_f(rho_j)}: " + "; ".join(parts), ok
    return evaluate


def _near(c: _Curves, s: pd.Series, tol: ValidationTolerances) -> pd.Series:
    return s[np.abs(s.index.values - c.jammed()) <= tol.near_jamming]


def _away(c: _Curves, s: pd.Series, tol: ValidationTolerances) -> pd.Series:
    return s[np.abs(s.index.values - c.jammed()) > tol.near_jamming]


def _tangential_log_ratios(c: _Curves, metrics: Sequence[str]) -> pd.Series:
    """log10(tangential / normal) of the mean curves of beta0 and beta1 for each of `metrics`, stacked into one
    Series over rho (one entry per dimension, metric and rho where both curves are positive)."""
    parts = [_log_ratio(c.mean(TANGENTIAL, h, m), c.mean(NORMAL, h, m)) for h in P2_HOMOLOGY_DIMS for m in metrics]
    return pd.Series(np.concatenate([p.values for p in parts]), index=np.concatenate([p.index.values for p in parts]),
                     dtype=float)


def _b_tracks(ctx: _Context) -> tuple[str, bool]:
    c = ctx.system(ctx.frictional)
    c.jammed()
    corr = {}
    for h in P2_HOMOLOGY_DIMS:
        for m in METRICS:
            n, t = c.mean(NORMAL, h, m), c.mean(TANGENTIAL, h, m)
            common = n.index.intersection(t.index)
            n, t = _away(c, n[common], ctx.tol), _away(c, t[common], ctx.tol)
            ok = (n > 0) & (t > 0)
            if ok.sum() < ctx.tol.correlation_points:
                raise _NotEvaluated(f"fewer than {ctx.tol.correlation_points} rho values away from rho_J")
            corr[h, m] = _pearson(np.log10(n[ok].values), np.log10(t[ok].values))
    median = float(np.nanmedian(list(corr.values())))
    return ("Pearson correlation of log10 normal vs tangential curves, |rho - rho_J| > "
            f"{ctx.tol.near_jamming}: {_per_dim_metric(corr)}; median {_f(median, 2)}", median >= ctx.tol.correlation)


def _b_deviation_near_jamming(ctx: _Context) -> tuple[str, bool]:
    c = ctx.system(ctx.frictional)
    c.jammed()
    dev = _tangential_log_ratios(c, METRICS).abs()
    near, away = _near(c, dev, ctx.tol).values, _away(c, dev, ctx.tol).values
    if not len(near) or len(away) < ctx.tol.min_points:
        raise _NotEvaluated(f"no rho value within {ctx.tol.near_jamming} of rho_J, or too few away from it")
    m_near, m_away = float(np.median(near)), float(np.median(away))
    return (f"median |log10(tangential/normal)|: {_f(m_near, 2)} within ±{ctx.tol.near_jamming} of rho_J = "
            f"{_f(c.rho_j)}, {_f(m_away, 2)} away from it", m_near > m_away)


def _b_wasserstein_smaller_near_jamming(ctx: _Context) -> tuple[str, bool]:
    c = ctx.system(ctx.frictional)
    c.jammed()
    medians = {}
    for m in (W1, W2):
        values = _near(c, _tangential_log_ratios(c, (m,)), ctx.tol).values
        if not len(values):
            raise _NotEvaluated(f"no rho value within {ctx.tol.near_jamming} of rho_J")
        medians[m] = 10 ** float(np.median(values))
    return (f"median tangential/normal within ±{ctx.tol.near_jamming} of rho_J = {_f(c.rho_j)}: "
            + _per_metric(medians),
            all(v <= 1 / ctx.tol.value_factor for v in medians.values()))


def _b_bottleneck_similar(ctx: _Context) -> tuple[str, bool]:
    c = ctx.system(ctx.frictional)
    c.jammed()
    dev = _tangential_log_ratios(c, (B,))
    everywhere, near = dev.values, _near(c, dev, ctx.tol).values
    if len(everywhere) < ctx.tol.min_points or not len(near):
        raise _NotEvaluated("too few rho values with both curves positive")
    f_all, f_near = 10 ** float(np.median(np.abs(everywhere))), 10 ** float(np.median(np.abs(near)))
    limit = ctx.tol.value_factor
    return (f"median factor between tangential and normal d_B: {_f(f_all, 2)} over all rho, {_f(f_near, 2)} "
            f"within ±{ctx.tol.near_jamming} of rho_J = {_f(c.rho_j)}", f_all <= limit and f_near <= limit)


def _c_jams_later(ctx: _Context) -> tuple[str, bool]:
    f, n = ctx.both()
    rf, rn = f.jammed(), n.jammed()
    pf = jamming_density_per_realization(f.ds, f.dimension)
    pn = jamming_density_per_realization(n.ds, n.dimension)
    spread = (f"per realization {ctx.frictional} [{_f(np.nanmin(pf))}, {_f(np.nanmax(pf))}], "
              f"{ctx.frictionless} [{_f(np.nanmin(pn))}, {_f(np.nanmax(pn))}]")
    return f"rho_J (mean Z = d+1): {ctx.frictional} {_f(rf)}, {ctx.frictionless} {_f(rn)}; {spread}", rn > rf


def _median_quotient(ctx: _Context, dim: int, metrics: Sequence[str], lo: float = -np.inf, hi: float = np.inf, *,
                     closed_lo: bool = True) -> dict[str, float]:
    """{metric: median of the mu = 0 curve / median of the mu = 0.5 curve} (normal forces, PD_dim), both over
    the same rho `window`."""
    f, n = ctx.both()

    def median(c: _Curves, metric: str) -> float:
        return float(c.window(c.mean(NORMAL, dim, metric), lo, hi, closed_lo=closed_lo).median())

    return {m: _quotient(median(n, m), median(f, m), f"beta{dim} {METRIC_SYMBOLS[m]} medians of both systems")
            for m in metrics}


def _peak_quotient(ctx: _Context, dim: int, bounds: Callable[[_Curves], tuple[float, float]], *,
                   numerator: str) -> dict[str, float]:
    """{metric: largest value of one system's curve / largest value of the other's} (normal forces, PD_dim), each
    over its own closed rho range ``bounds(curves)``; `numerator` is ``"frictional"`` or ``"frictionless"``."""
    f, n = ctx.both()
    quotient = {}
    for m in METRICS:
        peak_f, peak_n = (c.window(c.mean(NORMAL, dim, m), *bounds(c), closed_hi=True).max() for c in (f, n))
        what = f"beta{dim} {METRIC_SYMBOLS[m]} peaks of both systems"
        quotient[m] = _quotient(peak_f, peak_n, what) if numerator == "frictional" else _quotient(peak_n, peak_f, what)
    return quotient


def _c_low_density(ctx: _Context) -> tuple[str, bool]:
    ratio = _median_quotient(ctx, 0, METRICS, hi=0.65)
    tol = ctx.tol.value_factor
    ok = _within(ratio[B], 1.0, tol) and _within(ratio[W2], 1.0, tol) and _within(ratio[W1], 0.6, tol)
    return f"median over rho < 0.65, mu=0 / mu=0.5 (beta0): {_per_metric(ratio)}", ok


def _shifted_comparison(ctx: _Context, dim: int, denominator: str) -> tuple[np.ndarray, np.ndarray]:
    """mu = 0 ratio and the mu = 0.5 ratio interpolated at the same rho - rho_J."""
    f, n = ctx.both()
    rf, rn = f.jammed(), n.jammed()
    sf, sn = (c.window(c.ratio(NORMAL, dim, denominator)) for c in (f, n))
    sf = pd.Series(sf.values, index=sf.index.values - rf)
    x = sn.index.values - rn
    other = _on_grid(sf, x)
    ok = np.isfinite(other) & (other > 0)
    if ok.sum() < ctx.tol.min_points:
        raise _NotEvaluated("the two systems' rho - rho_J ranges overlap at too few points")
    return sn.values[ok], other[ok]


def _c_ratios_adjusted(ctx: _Context) -> tuple[str, bool]:
    mu0, mu05 = _shifted_comparison(ctx, 0, W1)
    larger = float(np.mean(mu0 > mu05))
    a, b = _shifted_comparison(ctx, 0, W2)
    same = 10 ** float(np.median(np.log10(a / b)))
    ok = larger >= ctx.tol.consistently and _within(same, 1.0, ctx.tol.value_factor)
    return (f"at equal rho - rho_J (beta0): d_B/d_W1 larger for mu=0 at {_f(100 * larger, 2)} % of {len(mu0)} points; "
            f"median (d_B/d_W2 at mu=0) / (at mu=0.5) = {_f(same, 2)}", ok)


def _c_slowing_earlier(ctx: _Context) -> tuple[str, bool]:
    f, n = ctx.both()
    rf, rn = f.jammed(), n.jammed()
    peaks = {m: (f.argmax(f.mean(NORMAL, 0, m)) - rf, n.argmax(n.mean(NORMAL, 0, m)) - rn) for m in (B, W2)}
    return ("argmax(rho) - rho_J (beta0), mu=0.5 vs mu=0: "
            + ", ".join(f"{METRIC_SYMBOLS[m]} {_f(a, 2)} vs {_f(b, 2)}" for m, (a, b) in peaks.items()),
            all(a < b for a, b in peaks.values()))


def _c_loops_below_jamming(ctx: _Context) -> tuple[str, bool]:
    f, n = ctx.both()
    hi = min(f.jammed(), n.jammed()) - ctx.tol.well_below
    ratio = _median_quotient(ctx, 1, (B, W2), hi=hi)
    return (f"median over rho < {_f(hi)} (beta1), mu=0 / mu=0.5: {_per_metric(ratio)}",
            all(v <= 1 / ctx.tol.value_factor for v in ratio.values()))


def _c_loops_near_jamming(ctx: _Context) -> tuple[str, bool]:
    w = ctx.tol.peak_window
    peak = _peak_quotient(ctx, 1, lambda c: (c.jammed() - w, c.jammed() + w), numerator="frictionless")
    return (f"largest value within ±{w} of each system's rho_J (beta1), mu=0 / mu=0.5: {_per_metric(peak)}",
            all(v >= ctx.tol.value_factor for v in peak.values()))


def _quotient_after_jamming(dim: int, reference: float):
    """(criterion, evaluate) of "after jamming the PD_dim rates of mu = 0 are `reference` times those of
    mu = 0.5": medians over rho above both rho_J, every metric, within a factor value_factor of `reference`."""
    def criterion(t: ValidationTolerances) -> str:
        return (f"median over rho > both rho_J, mu=0 / mu=0.5 within a factor {t.value_factor} of {_f(reference)}, "
                "every metric")

    def evaluate(ctx: _Context) -> tuple[str, bool]:
        f, n = ctx.both()
        ratio = _median_quotient(ctx, dim, METRICS, lo=max(f.jammed(), n.jammed()), closed_lo=False)
        return (f"median over rho > both rho_J (beta{dim}), mu=0 / mu=0.5: {_per_metric(ratio)}",
                all(_within(v, reference, ctx.tol.value_factor) for v in ratio.values()))
    return criterion, evaluate


def _v_peak_components(ctx: _Context) -> tuple[str, bool]:
    ratio = _peak_quotient(ctx, 0, lambda c: (-np.inf, c.jammed()), numerator="frictional")
    lo, hi = max(1.0, 1.2 / ctx.tol.value_factor), 1.4 * ctx.tol.value_factor
    return (f"peak over rho <= rho_J (beta0), mu=0.5 / mu=0: {_per_metric(ratio)}",
            all(lo < v <= hi for v in ratio.values()))


def _t_bottleneck_small(ctx: _Context) -> tuple[str, bool]:
    t = ctx.table("table1")
    values = {(pair, h): float(t.loc[pair, table_column(h, B)]) for pair in TABLE_PAIRS for h in P2_HOMOLOGY_DIMS}
    limits = {"(a,b)": 0.10, "(a,c)": 0.15}
    ok = all(v <= limits[pair] * ctx.tol.value_factor for (pair, _), v in values.items())
    return "Table I d_B: " + ", ".join(f"{p} beta{h} {_f(v, 2)}" for (p, h), v in values.items()), ok


def _t_relative_w1(ctx: _Context) -> tuple[str, bool]:
    t = ctx.table("table1")
    growth = {}
    for h in P2_HOMOLOGY_DIMS:
        for m in (W1, W2):
            col = table_column(h, m)
            growth[h, m] = float(t.loc["(a,c)", col]) / float(t.loc["(a,b)", col])
    ok = all(growth[h, W1] > growth[h, W2] for h in P2_HOMOLOGY_DIMS)
    return f"Table I (a,c)/(a,b): {_per_dim_metric(growth)}", ok


def quadrant_dominance(table: pd.DataFrame) -> pd.DataFrame:
    """Per column of a quadrant table: the largest quadrant, largest/second largest, largest/smallest."""
    rows = {}
    for col in table.columns:
        values = table[col].astype(float).sort_values(ascending=False)
        first, second, last = values.iloc[0], values.iloc[1], values.iloc[-1]
        rows[col] = {"largest": values.index[0],
                     "dominance": first / second if second > 0 else math.inf,
                     "max_over_min": first / last if last > 0 else math.inf}
    return pd.DataFrame.from_dict(rows, orient="index")


def _t_localised(ctx: _Context) -> tuple[str, bool]:
    stats = quadrant_dominance(ctx.table("table2"))
    top = stats["largest"].value_counts()
    quadrant, count = str(top.index[0]), int(top.iloc[0])
    median = float(stats["dominance"].median())
    ok = count > len(stats) / 2 and median >= ctx.tol.dominance
    return (f"Table II: '{quadrant}' is largest in {count} of {len(stats)} columns; median largest/second largest "
            f"= {_f(median, 2)}", ok)


def _t_spread(ctx: _Context) -> tuple[str, bool]:
    stats = quadrant_dominance(ctx.table("table3"))
    median = float(stats["max_over_min"].median())
    return f"Table III: median over columns of largest/smallest quadrant = {_f(median, 2)}", median <= ctx.tol.spread


CLAIMS: tuple[_Claim, ...] = (
    _Claim("III.D-1", "§III D, Table I", "tables",
           "No single dramatic change between nearby states: d_B(a,b) and d_B(a,c) are small",
           "< 0.10 and < 0.15 <F>",
           lambda t: f"d_B(a,b) <= 0.10·{t.value_factor} and d_B(a,c) <= 0.15·{t.value_factor} for beta0 and beta1",
           _t_bottleneck_small),
    _Claim("III.D-2", "§III D, Table I", "tables",
           "c differs from a by many more small changes than b does: d_W1 grows from (a,b) to (a,c) relatively more "
           "than d_W2", "beta0: 14.0/4.18 vs 0.89/0.50; beta1: 19.2/3.8 vs 0.99/0.57",
           lambda t: "d_W1(a,c)/d_W1(a,b) > d_W2(a,c)/d_W2(a,b) for beta0 and beta1", _t_relative_w1),
    _Claim("III.D-3", "§III D, Table II", "tables",
           "The (a,b) differences are concentrated in one quadrant (bottom left in P2)",
           "bottom left largest in every column",
           lambda t: f"one quadrant largest in most columns and median largest/second largest >= {t.dominance}",
           _t_localised),
    _Claim("III.D-4", "§III D, Table III", "tables",
           "The (a,c) differences are distributed evenly over the domain", "similar values in all quadrants",
           lambda t: f"median over columns of largest/smallest quadrant <= {t.spread}", _t_spread),
    _Claim("IV.A-1", "§IV A, Fig. 6", "frictional",
           "The most pronounced feature is the dramatic change around rho_J (Z ≈ 3)", "rate of change peaks at rho_J",
           lambda t: f"argmax of mean d_W1 (beta0 and beta1) within ±{t.peak_window} of rho_J", _a_peak_near_jamming),
    _Claim("IV.A-2", "§IV A, Fig. 6(a)", "frictional",
           "Before jamming d_B (beta0) is an order of magnitude greater than one for most of the regime", "≈ 10 <F>",
           lambda t: f"median of mean d_B over rho < rho_J >= 10/{t.value_factor}", _a_db_large_before),
    _Claim("IV.A-3", "§IV A, Fig. 7(a)", "frictional",
           "For rho < 0.75, d_B/d_W2 (beta0) is roughly constant and ≈ 0.75", "0.75",
           *_ratio_constant(W2, 0.75)),
    _Claim("IV.A-4", "§IV A, Fig. 7(a)", "frictional",
           "For rho < 0.75, d_B/d_W1 (beta0) is roughly constant and ≈ 0.2", "0.2", *_ratio_constant(W1, 0.2)),
    _Claim("IV.A-5", "§IV A, Fig. 6(a)", "frictional",
           "At rho ≈ 0.75 the rate of change measured by d_B (beta0) decreases dramatically", "drop at 0.75",
           lambda t: f"median d_B over [0.75, rho_J) <= median over rho < 0.75 / {t.drop_factor}", _a_db_drops_at_075),
    _Claim("IV.A-6", "§IV A, Figs 6(a), 7(a)", "frictional",
           "For 0.75 < rho < rho_J, d_W1 (beta0) increases dramatically and d_B/d_W1 decreases", "increase / decrease",
           lambda t: f"Spearman(rho, d_W1) >= {t.trend} and Spearman(rho, d_B/d_W1) <= -{t.trend}",
           _a_w1_grows_before_jamming),
    _Claim("IV.A-7", "§IV A, Fig. 7(a)", "frictional",
           "For 0.75 < rho < rho_J, d_B/d_W2 (beta0) stays roughly constant until just before jamming, "
           "where it plunges",
           "constant, then plunge",
           lambda t: (f"CV <= {t.max_cv} over [0.75, rho_J - {t.near_jamming}) and the minimum over [rho_J - "
                      f"{t.near_jamming}, rho_J] <= plateau median / {t.drop_factor}"), _a_w2_ratio_plunges),
    _Claim("IV.A-8", "§IV A, Fig. 6(b)", "frictional",
           "Before jamming the rate of change of the loop structure (beta1) generally increases with rho", "increase",
           lambda t: f"median over d_B, d_W1, d_W2 of Spearman(rho, d) over rho < min(0.77, rho_J) >= {t.trend}",
           _a_loops_increase),
    _Claim("IV.A-9", "§IV A, Fig. 6(b)", "frictional",
           "At rho ≈ 0.77 d_B (beta1) starts decreasing", "peak at 0.77",
           lambda t: f"argmax of mean d_B(beta1) within 0.77 ± {t.peak_window}", _a_loops_db_peak),
    _Claim("IV.A-10", "§IV A, Fig. 7(b)", "frictional",
           "Both ratios d_B/d_W2 and d_B/d_W1 (beta1) decrease from rho ≈ 0.76 on", "decrease",
           lambda t: f"Spearman(rho, ratio) <= -{t.trend} over 0.76 <= rho <= rho_J for both ratios",
           _a_loop_ratios_decrease),
    *(_Claim(f"IV.A-11{suffix}", f"§IV A, Fig. {figure}; §V", role,
             "After jamming the rate of change slows dramatically (distances fall sharply)", "much smaller",
             lambda t: (f"median over rho > rho_J <= median over rho < rho_J / {t.fall_factor}, every metric, "
                        "beta0 and beta1"),
             _fall_after_jamming(role))
      for suffix, figure, role in (("a", 6, "frictional"), ("b", 9, "frictionless"))),
    *(_Claim(f"IV.A-12{panel}", f"§IV A, Fig. 7({panel})", "frictional",
             f"After jamming d_B/d_W2 and d_B/d_W1 (beta{dim}) are essentially constant and about one and three "
             "orders of magnitude smaller than before", "1 and 3 decades",
             lambda t: (f"log10(median before / median after) within ±{t.decades} of 1 and 3 (before: rho < "
                        f"min(0.75, rho_J)); CV after <= {t.max_cv}"), _ratios_after_jamming(dim))
      for panel, dim in (("a", 0), ("b", 1))),
    _Claim("IV.B-1", "§IV B, Fig. 8", "frictional",
           "Tangential-force distances track the normal-force ones (beta0 and beta1) away from rho_J", "similar curves",
           lambda t: (f"median Pearson correlation of log10 curves with |rho - rho_J| > {t.near_jamming} "
                      f">= {t.correlation}"),
           _b_tracks),
    _Claim("IV.B-2", "§IV B, Fig. 8", "frictional",
           "Normal and tangential distances deviate more near rho_J than elsewhere", "larger deviation near rho_J",
           lambda t: f"median |log10(tangential/normal)| within ±{t.near_jamming} of rho_J > away from it",
           _b_deviation_near_jamming),
    _Claim("IV.B-3", "§IV B, Fig. 8", "frictional",
           "Near rho_J, d_W1 and d_W2 are significantly smaller for tangential forces", "smaller",
           lambda t: (f"median tangential/normal within ±{t.near_jamming} of rho_J <= 1/{t.value_factor} "
                      "for d_W1 and d_W2"),
           _b_wasserstein_smaller_near_jamming),
    _Claim("IV.B-4", "§IV B, Fig. 8", "frictional",
           "d_B is similar for normal and tangential forces throughout, including near rho_J", "similar",
           lambda t: f"median factor between the d_B curves <= {t.value_factor}, over all rho and near rho_J",
           _b_bottleneck_similar),
    _Claim("IV.C-1", "§IV C, Fig. 9", "both",
           "The frictionless system jams at larger rho", "rho_J(mu=0) > rho_J(mu=0.5)",
           lambda t: "rho where the mean Z reaches d+1 is larger for mu = 0", _c_jams_later),
    _Claim("IV.C-2", "§IV C, Fig. 9(a)", "both",
           "For rho < 0.65, d_B and d_W2 (beta0) are about the same with and without friction; d_W1 is ≈ 40 % smaller "
           "for mu = 0", "mu=0/mu=0.5: 1, 1, 0.6",
           lambda t: f"ratios of medians within a factor {t.value_factor} of 1 (d_B, d_W2) and 0.6 (d_W1)",
           _c_low_density),
    _Claim("IV.C-3", "§IV C, Figs 7(a), 10(a)", "both",
           "At equal rho - rho_J, d_B/d_W1 (beta0) is consistently larger for mu = 0 while d_B/d_W2 is roughly "
           "the same",
           "larger / same",
           lambda t: (f"mu=0 ratio larger at >= {100 * t.consistently:.0f} % of the points; median d_B/d_W2 quotient "
                      f"within a factor {t.value_factor} of 1"), _c_ratios_adjusted),
    _Claim("IV.C-4", "§IV C, Figs 6(a), 9(a)", "both",
           "d_B and d_W2 (beta0) begin slowing down at a much lower rho relative to rho_J in the frictional system",
           "earlier peak with friction",
           lambda t: "argmax(rho) - rho_J of mean d_B and d_W2 smaller for mu = 0.5 than for mu = 0",
           _c_slowing_earlier),
    _Claim("IV.C-5", "§IV C, Figs 6(b), 9(b)", "both",
           "For rho well below rho_J the loop structure (beta1) changes much less for mu = 0 (d_B and d_W2)", "smaller",
           lambda t: (f"medians over rho < min(rho_J) - {t.well_below}: mu=0 / mu=0.5 <= 1/{t.value_factor} for d_B "
                      "and d_W2"), _c_loops_below_jamming),
    _Claim("IV.C-6", "§IV C, Figs 6(b), 9(b)", "both",
           "Close to jamming the loop structure (beta1) changes much more dramatically for mu = 0 "
           "(all three distances)",
           "larger",
           lambda t: f"largest value within ±{t.peak_window} of each rho_J: mu=0 / mu=0.5 >= {t.value_factor}",
           _c_loops_near_jamming),
    _Claim("IV.C-7", "§IV C, Figs 6(b), 9(b)", "both",
           "After jamming the loop structure (beta1) changes about twice as fast for mu = 0 as for mu = 0.5", "2",
           *_quotient_after_jamming(1, 2.0)),
    _Claim("V-1", "§V (conclusions)", "both",
           "Peak rates of evolution of the components (beta0) before jamming are 20-40 % higher with friction",
           "1.2-1.4",
           lambda t: f"peak over rho <= rho_J, mu=0.5 / mu=0 in (max(1, 1.2/{t.value_factor}), 1.4·{t.value_factor}], "
                     "every metric", _v_peak_components),
    _Claim("V-2", "§V (conclusions)", "both",
           "After jamming the component (beta0) rates become quite similar with and without friction", "1",
           *_quotient_after_jamming(0, 1.0)),
)


# --- why a claim does not hold: diagnostics measured on the same data ------------------------------------------
def _never_dying_events(name_of: Callable[[_Context], str], dim: int, where: str) -> Callable[[_Context], str]:
    """Diagnostic: how often consecutive states differ in their number of never-dying PD_dim classes (normal forces)
    in a ρ window (`where`: "after" ρ > ρ_J, "dense" 0.75 <= ρ < ρ_J). Under P2's death −1 each such pair has
    d_B >= 1/2 (the extra class, born at b >= 0, goes to the diagonal at (b + 1)/2 or to a finite point at >= 1),
    whatever else changed; the median d_B of the other pairs is what the forces alone give."""
    def diagnostic(ctx: _Context) -> str:
        name = name_of(ctx)
        c = ctx.system(name)
        measures = ctx.measures.get(name)
        if measures is None or "essential_count" not in measures or "realization" not in c.ds.dims:
            raise _NotEvaluated(f"{name}: no never-dying class counts (network_measures.nc) to compare")
        count = measures["essential_count"].sel(force_kind=NORMAL, homology_dim=dim)
        count = count.sel(realization=c.ds["realization"].values).transpose("realization", "rho").values
        d_b = c.ds["distance"].sel(force_kind=NORMAL, homology_dim=dim, metric=B).transpose("realization", "rho")
        changed = np.diff(count, axis=1) != 0
        if changed.shape != d_b.shape:
            raise _NotEvaluated(f"{name}: network measures and distances cover different states")
        rho, rho_j = c.ds["rho"].values, c.jammed()
        inside = rho > rho_j if where == "after" else (rho >= 0.75) & (rho < rho_j)
        changed, d_b = changed[:, inside], d_b.values[:, inside]
        if not changed.size:
            raise _NotEvaluated(f"{name}: no pairs {where} rho_J")
        quiet = d_b[~changed]
        window = f"rho > rho_J = {_f(rho_j)}" if where == "after" else f"0.75 <= rho < rho_J = {_f(rho_j)}"
        return (f"{name}: {100 * changed.mean():.0f} % of the {changed.size} consecutive pairs with {window} change "
                f"the number of never-dying beta{dim} classes (rattlers joining or leaving, loops opening or "
                f"closing), each d_B >= 0.5 under P2's death -1; median d_B of the other pairs "
                f"{_f(np.median(quiet), 2) if quiet.size else 'n/a'}")
    return diagnostic


def _argmax_per_realization(name_of: Callable[[_Context], str], dim: int, metric: str) -> Callable[[_Context], str]:
    """Diagnostic: where each realization's curve peaks, next to ρ_J of its own Z (the spread that a mean over
    3 realizations keeps, and P2's 20 average out)."""
    def diagnostic(ctx: _Context) -> str:
        name = name_of(ctx)
        c = ctx.system(name)
        if "realization" not in c.ds.dims:
            raise _NotEvaluated(f"{name}: one realization")
        da = c.ds["distance"].sel(force_kind=NORMAL, homology_dim=dim, metric=metric)
        peaks = [float(da.isel(realization=i).idxmax("rho")) for i in range(da.sizes["realization"])]
        rho_js = jamming_density_per_realization(c.ds, c.dimension)
        return (f"{name}: argmax of beta{dim} {METRIC_SYMBOLS[metric]} per realization at rho "
                + ", ".join(f"{_f(p)} (rho_J {_f(j)})" for p, j in zip(peaks, rho_js)))
    return diagnostic


def _table_state_diagnostic(ctx: _Context) -> str:
    """Diagnostic: where the states a, b, c of Tables I–III sit relative to their realization's ρ_J, and how much
    Z and ⟨F_n⟩ change over them (P2 Fig. 1: 'almost identical')."""
    if ctx.states is None:
        raise _NotEvaluated("no table-state candidates given")
    row = ctx.states[ctx.states["chosen"].astype(bool)].iloc[0]
    c = ctx.system(ctx.frictional)
    realizations = list(c.ds["realization"].values) if "realization" in c.ds.dims else [int(row["realization"])]
    rho_js = jamming_density_per_realization(c.ds, c.dimension)
    rho_j = rho_js[realizations.index(int(row["realization"]))] if int(row["realization"]) in realizations else np.nan
    return (f"states a, b, c of realization {int(row['realization'])} (the quietest of {len(ctx.states)} by P2 Fig. 1's "
            f"criterion) at rho {row['rho_a']:.4f}-{row['rho_c']:.4f}, its rho_J = {_f(rho_j)}: Z {row['Z_a']:.2f} -> "
            f"{row['Z_c']:.2f}, <F_n> x {row['mean_normal_force_c'] / row['mean_normal_force_a']:.2f} from a to c "
            "(P2: Z and <F> almost identical)")


def explain(claim_id: str, ctx: _Context) -> str:
    """Why a claim does not hold on these data: `EXPLANATIONS`' verdict on the cause, then its diagnostics measured
    here (a diagnostic the data cannot give says why)."""
    cause, diagnostics = EXPLANATIONS.get(claim_id, ("No explanation recorded.", ()))
    measured = []
    for diagnostic in diagnostics:
        try:
            measured.append(diagnostic(ctx))
        except _NotEvaluated as reason:
            measured.append(f"({reason})")
    return cause + (" Measured here: " + "; ".join(measured) + "." if measured else "")


def _frictional(ctx: _Context) -> str:
    return ctx.frictional


def _frictionless(ctx: _Context) -> str:
    return ctx.frictionless


# Causes, measured in docs/p2_sampling.md: the distances at four wall speeds and five sampling steps (one
# realization of 400 disks), and P2's own setting run once per system ("paper size": 2025 disks, v_c = 2.5e-5,
# 100 samples; config/paper.yaml with one realization). "Small system" means the claim holds at paper size;
# "not a small-system effect" that it fails there too.
_PAPER = "docs/p2_sampling.md, paper size"
_AT_JAMMING = ("Not a small-system effect: a, b, c (consecutive samples at rho ~ 0.79) lie at this system's jamming "
               f"transition, also at paper size (rho_J 0.80; {_PAPER}), where P2's look alike ('Z and the average "
               "force almost identical'), i.e. P2's rho = 0.79 is jammed and ours is not; and each new or lost "
               "never-dying class (a rattler joining, a defect loop opening) costs d_B >= 0.5 under P2's death -1.")
_NEVER_DYING = ("Not a small-system effect: after rho_J most consecutive pairs change the number of never-dying "
                "classes (rattlers joining, defect loops opening or closing as contacts form), and under P2's death "
                "-1 each costs d_B >= 0.5, a floor the force changes alone (d_B ~ 0.03-0.1) stay far below; at paper "
                f"size such changes are more frequent, not less ({_PAPER}).")
#: why each claim may not hold on the quick default: {claim id: (cause, diagnostics measured on the data)}
EXPLANATIONS: dict[str, tuple[str, tuple[Callable[[_Context], str], ...]]] = {
    "III.D-1": (_AT_JAMMING, (_table_state_diagnostic,)),
    "III.D-2": (_AT_JAMMING, (_table_state_diagnostic,)),
    "III.D-3": (_AT_JAMMING + " At the transition the (a,b) changes are system-wide, not in one quadrant.",
                (_table_state_diagnostic,)),
    "III.D-4": (_AT_JAMMING, (_table_state_diagnostic,)),
    "IV.A-1": ("Few realizations: each realization's d_W1 peaks near its own rho_J, but the rho_J scatter and the "
               f"peak of a mean of 3 blurs; one paper-size realization holds ({_PAPER}).",
               (_argmax_per_realization(_frictional, 0, W1), _argmax_per_realization(_frictional, 1, W1))),
    "IV.A-2": ("Small system: the largest single change before jamming grows with the number of contacts, d_B "
               f"(beta0) ~ 3 <F> with 400 disks and 8.8 <F> with 2025 (holds at paper size; {_PAPER}).", ()),
    "IV.A-3": ("Sampling: the ratio needs P2's rule (rattlers kept) and step; with rattlers removed d_B/d_W1 is "
               "~0.5 and d_B/d_W2 ~0.8 (docs/p2_sampling.md, rattler rule).", ()),
    "IV.A-4": ("Sampling and realizations: the ratio scatters from state to state (at paper size its median is "
               f"0.17 but CV 0.64 > 0.5; {_PAPER}); with rattlers removed it is ~0.5 (docs/p2_sampling.md).", ()),
    "IV.A-5": (f"Not a small-system effect (paper size: d_B 9.7 -> 6.8, needs a factor 2; {_PAPER}). It holds "
               "at paper size if rho is measured in the box between the wall-particle centres (rho_J would read "
               "0.767; docs/p2_sampling.md, rho scale): P2 does not say how it measures rho between rough walls.",
               (_argmax_per_realization(_frictional, 0, B),)),
    "IV.A-6": ("Not a small-system effect (paper size: Spearman 0.38; "
               f"{_PAPER}): d_W1 rises from 0.75 but peaks up to 0.03 before rho_J and falls into it.",
               (_argmax_per_realization(_frictional, 0, W1),)),
    "IV.A-7": ("Few realizations: the plateau and the plunge hold at paper size (one realization; "
               f"{_PAPER}).", ()),
    "IV.A-8": ("Small system and slow compression: with 400 disks there are no loops before rho ~ 0.75 (beta1 "
               "distances 0) and single events decide the trend; at paper size the early loops come and go without "
               f"trend (Spearman ~0; {_PAPER}).", (_argmax_per_realization(_frictional, 1, B),)),
    "IV.A-9": ("Few realizations: single early loop events can make the largest beta1 d_B of a 3-realization mean; "
               f"paper size peaks at 0.791 (holds; {_PAPER}).", (_argmax_per_realization(_frictional, 1, B),)),
    "IV.A-10": (f"Few realizations: holds at paper size ({_PAPER}).", ()),
    "IV.A-11a": (_NEVER_DYING + " beta0 falls by > 10x; beta1 does not, also because loops hardly exist before "
                 "jamming (beta1 distances 0 below rho ~ 0.75 with 400 disks).",
                 (_never_dying_events(_frictional, 1, "after"),)),
    "IV.A-11b": (_NEVER_DYING + " Without friction loops exist only from jamming on (beta1 distances 0 before "
                 f"rho_J, also at paper size), and beta0 d_W1 falls only 2.5-3x ({_PAPER}).",
                 (_never_dying_events(_frictionless, 0, "after"), _never_dying_events(_frictionless, 1, "after"))),
    "IV.A-12a": (_NEVER_DYING + " d_B after jamming sits on that floor, so d_B/d_W1 cannot fall 3 decades.",
                 (_never_dying_events(_frictional, 0, "after"),)),
    "IV.A-12b": (_NEVER_DYING + " d_B after jamming sits on that floor, so d_B/d_W1 cannot fall 3 decades.",
                 (_never_dying_events(_frictional, 1, "after"),)),
    "IV.B-1": (f"Few realizations: holds at paper size ({_PAPER}).", ()),
    "IV.B-2": ("Not a small-system effect: at paper size the tangential and normal curves differ as little near "
               f"rho_J as elsewhere ({_PAPER}); not reproduced.", ()),
    "IV.B-3": ("Not a small-system effect: at paper size tangential/normal d_W1 and d_W2 near rho_J are 1.0 "
               f"({_PAPER}); not reproduced.", ()),
    "IV.B-4": (f"Few realizations: holds at paper size ({_PAPER}).", ()),
    "IV.C-1": (f"Holds at every size and speed measured ({_PAPER}).", ()),
    "IV.C-2": ("Sampling: below rho = 0.65 there are 7 states with almost no contacts (Z < 0.4), so the distances "
               "count single collisions and rattlers joining and leaving; also fails at paper size (d_B 1.7, d_W1 "
               f"0.36, d_W2 1.1; {_PAPER}).", ()),
    "IV.C-3": ("Not a small-system effect: at paper size d_B/d_W1 is larger without friction at 43 % of the "
               f"points, as here ({_PAPER}); not reproduced.", ()),
    "IV.C-4": ("Not a small-system effect: at paper size both systems' d_B and d_W2 peak 0.035 below their "
               f"rho_J ({_PAPER}); not reproduced.",
               (_argmax_per_realization(_frictional, 0, B), _argmax_per_realization(_frictionless, 0, B))),
    "IV.C-5": ("Small system: with 400 disks neither system has loops well before jamming (beta1 distances 0: "
               f"nothing to compare); holds at paper size ({_PAPER}).", ()),
    "IV.C-6": ("Not a small-system effect: at paper size the largest beta1 changes near rho_J are alike with and "
               f"without friction (0.93-1.3; {_PAPER}); not reproduced.", ()),
    "IV.C-7": (_NEVER_DYING + " d_B after jamming is that floor in both systems, so its ratio is ~1; the d_W1 and "
               f"d_W2 ratios are 2-3.4 (paper size 2.8 and 2.2; {_PAPER}).",
               (_never_dying_events(_frictional, 1, "after"), _never_dying_events(_frictionless, 1, "after"))),
    "V-1": (f"Few realizations: holds at paper size ({_PAPER}).", ()),
    "V-2": ("Not a small-system effect: after jamming the frictionless packing keeps changing 2-4x more (d_W1, "
            f"d_W2; paper size 3.1 and 2.2, d_B 1.0; {_PAPER}); not reproduced.",
            (_never_dying_events(_frictional, 0, "after"), _never_dying_events(_frictionless, 0, "after"))),
}


def p2_validation(distances: Mapping[str, xr.Dataset], tables: Mapping[str, pd.DataFrame] | None = None, *,
                  frictional: str = FRICTIONAL, frictionless: str = FRICTIONLESS,
                  tolerances: ValidationTolerances | None = None, measures: Mapping[str, xr.Dataset] | None = None,
                  states: pd.DataFrame | None = None) -> pd.DataFrame:
    """Judge each claim of P2 §III D–§IV (and §V's summary of them) on the measured data.

    Parameters
    ----------
    distances : ``{system: distances.nc dataset}`` (`stack_distances`); the frictional (μ = 0.5) and the
        frictionless (μ = 0) system under the names `frictional`, `frictionless`. A missing system leaves its
        claims "not evaluated".
    tables : ``{"table1": …, "table2": …, "table3": …}`` from `p2_tables` or `read_table` (frictional system).
    tolerances : how "≈", "roughly constant", "dramatically" … are tested (`ValidationTolerances`).
    measures : ``{system: network_measures.nc dataset}`` (never-dying class counts) and `states` (the
        `table_state_candidates` of Tables I–III): what the explanations of failed claims measure (optional).

    Returns
    -------
    DataFrame with columns ``VALIDATION_COLUMNS``: claim id, section, system, claim, P2's reference, the
    criterion, the measured evidence, the verdict ("holds", "does not hold", "not evaluated") and, for a claim
    that does not hold, the explanation (`EXPLANATIONS`: why, measured on these data where it can be). Curves
    are realization means; ρ_J is where the mean Z(ρ) first reaches d + 1 (P2 §IV A).
    """
    tol = tolerances or ValidationTolerances()
    curves = {name: _Curves(name, ds, _dimension(ds), tol) for name, ds in distances.items()
              if name in (frictional, frictionless)}
    ctx = _Context(curves, tables, tol, frictional, frictionless, dict(measures or {}), states)
    systems = {"frictional": frictional, "frictionless": frictionless, "both": f"{frictional} vs {frictionless}",
               "tables": f"{frictional} (one realization)"}
    rows = []
    for claim in CLAIMS:
        try:
            measured, holds = claim.evaluate(ctx)
            verdict = HOLDS if holds else FAILS
        except _NotEvaluated as reason:
            measured, verdict = str(reason), NOT_EVALUATED
        rows.append({"claim_id": claim.claim_id, "section": claim.section, "system": systems[claim.system],
                     "claim": claim.text, "reference": claim.reference, "criterion": claim.criterion(tol),
                     "measured": measured, "verdict": verdict,
                     "explanation": explain(claim.claim_id, ctx) if verdict != HOLDS else ""})
    table = pd.DataFrame(rows, columns=list(VALIDATION_COLUMNS))
    table.attrs["systems"] = {name: {"rho_J": c.rho_j, "realizations": c.n_realizations,
                                     "rho_range": (float(c.ds["rho"].min()), float(c.ds["rho"].max())),
                                     "snapshot_pairs": int(c.ds.sizes["rho"]),
                                     "essential_convention": c.ds.attrs.get("essential_convention", ""),
                                     "rattler_rule": c.ds.attrs.get("rattler_rule", "")}
                              for name, c in curves.items()}
    table.attrs["tolerances"] = tol
    return table


def _dimension(ds: xr.Dataset) -> int:
    return int(ds.attrs.get("dimension", 2))


def p2_validation_markdown(table: pd.DataFrame) -> str:
    """The validation table as Markdown: the systems measured, the tolerances, one row per claim."""
    lines = ["# P2 validation", "",
             "Each claim of P2 (evolution of force networks) §III D–§IV, judged on the measured distances between "
             "consecutive persistence diagrams (realization means) and on Tables I–III. rho_J is where the mean "
             "Z(rho) first reaches d + 1 (P2 §IV A). The reference column is P2's statement; verdicts are computed "
             "from the criterion column.", ""]
    systems = table.attrs.get("systems", {})
    if systems:
        lines += ["## Systems", "",
                  "| system | realizations | snapshot pairs | rho range | rho_J | never-dying classes | rattler rule |",
                  "|---|---|---|---|---|---|---|"]
        for name, info in systems.items():
            lo, hi = info["rho_range"]
            lines.append(f"| {name} | {info['realizations']} | {info['snapshot_pairs']} | {lo:.3f}–{hi:.3f} | "
                         f"{_format(info['rho_J'], 4)} | {info['essential_convention']} | "
                         f"{info.get('rattler_rule', '')} |")
        lines.append("")
    tol = table.attrs.get("tolerances")
    if tol is not None:
        lines += ["## Tolerances", "", ", ".join(f"{k} = {v}" for k, v in vars(tol).items()), ""]
    counts = table["verdict"].value_counts()
    lines += ["## Claims", "", "; ".join(f"{v}: {int(counts.get(v, 0))}" for v in (HOLDS, FAILS, NOT_EVALUATED)), "",
              "| id | section | system | claim | P2 | criterion | measured | verdict |",
              "|---|---|---|---|---|---|---|---|"]
    for _, r in table.iterrows():
        cells = [str(r[c]).replace("|", "\\|") for c in VALIDATION_COLUMNS]  # GFM escape inside a table
        lines.append("| " + " | ".join(cells) + " |")
    return "\n".join(lines) + "\n"


def write_p2_validation(table: pd.DataFrame, md_path: str | os.PathLike,
                        csv_path: str | os.PathLike | None = None) -> None:
    """Write ``results/tables/p2_validation.md`` (and optionally the same rows as CSV)."""
    Path(md_path).parent.mkdir(parents=True, exist_ok=True)
    Path(md_path).write_text(p2_validation_markdown(table))
    if csv_path is not None:
        Path(csv_path).parent.mkdir(parents=True, exist_ok=True)
        table.to_csv(csv_path, index=False)
