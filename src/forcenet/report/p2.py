"""P2 (evolution of force networks): what it compares, and the reductions its figures and claims share.

Everything P2 measures is a distance between persistence diagrams (P2 §III D): the bottleneck distance d_B and the
Wasserstein distances d_W1, d_W2 with the L∞ ground metric, for PD0 (β0, components) and PD1 (β1, loops) of the
normal- and the tangential-force networks, each normalised by its own mean force. This module names them
(`METRICS`, `table_column`) and reduces the ``distances.nc`` product over realizations and metrics:

- `distance_ratio`, `mean_distance_ratio` — d_B / d_Wq per realization and of the realization means (P2 Figs 7, 10).
- `jamming_density` — ρ_J where the realization-mean Z(ρ) first reaches d + 1 (P2 §IV A), and per realization.
- `P2_QUOTED_LEVELS` — the levels P2 quotes in words for Figs 6–9 (drawn by `forcenet.plotting.p2`).

Means and spreads over realizations follow `forcenet.report.realizations`. The rest of P2 is cut by job:
`forcenet.report.p2_distances` (diagram adapters, ``results/{system}/distances.nc``, lagged distances),
`forcenet.report.p2_tables` (Tables I–III and the states a, b, c), `forcenet.report.p2_judging`,
`forcenet.report.p2_claims`, `forcenet.report.p2_explanations` and `forcenet.report.p2_validation` (the claims of
§III D–§V and their table).
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np
import xarray as xr

from forcenet.network.regions import QUADRANTS as _NETWORK_QUADRANTS
from forcenet.report.realizations import realization_mean

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
QUADRANTS = tuple(_NETWORK_QUADRANTS)  # P2 Tables II–III row order: bottom left, bottom right, top right, top left
TABLE_PAIRS = ("(a,b)", "(a,c)")
TABLE_RHO_KEYS = ("rho_a", "rho_b", "rho_c")  # packing fractions of snapshots a, b, c (table attrs / CSV columns)
FRICTIONAL, FRICTIONLESS = "2d_poly_mu05", "2d_poly_mu0"


# =============================================================================================================
# Reductions shared by the figures and the validation
# =============================================================================================================
def rho_at_isostatic_crossing(rho: np.ndarray, z: np.ndarray, dimension: int) -> float:
    """ρ where Z(ρ) [both shape (n_rho,)] first reaches d + 1 (P2 §IV A: ρ_J loosely where Z ≈ 3 in 2D)."""
    from forcenet.measures import isostatic_crossing

    return float(isostatic_crossing(rho, z, dimension))


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
    return rho_at_isostatic_crossing(z["rho"].values[ok], z.values[ok], dimension)


def jamming_density_per_realization(distances: xr.Dataset, dimension: int = 2) -> np.ndarray:
    """ρ_J of each realization's own Z(ρ) (`jamming_density`), shape (n_realization,)."""
    if "realization" not in distances.dims:
        return np.array([jamming_density(distances, dimension)])
    return np.array([jamming_density(distances.isel(realization=i), dimension)
                     for i in range(distances.sizes["realization"])])


def diagram_point_counts(diagrams: xr.Dataset, kind: str = "normal", homology_dim: int = 1) -> xr.DataArray:
    """The number of points of each persistence diagram PD_k (force kind `kind`) of a ``diagrams.nc`` product
    (`forcenet.datasets.aggregate.stack_diagrams`), dims (realization, rho); 0 for a state without such points."""
    kinds = [str(k) for k in diagrams["force_kind"].values]
    selected = ((diagrams["diagram_force_kind"].values == kinds.index(kind))
                & (diagrams["diagram_homology_dim"].values == homology_dim))
    realization = np.asarray(diagrams["point_realization"].values, dtype=int)
    rho = np.asarray(diagrams["point_rho"].values, dtype=float)
    realizations, rhos = np.unique(realization), np.unique(rho)
    counts = np.zeros((realizations.size, rhos.size))
    np.add.at(counts, (np.searchsorted(realizations, realization[selected]), np.searchsorted(rhos, rho[selected])), 1)
    return xr.DataArray(counts, dims=("realization", "rho"), coords={"realization": realizations, "rho": rhos})


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


def table_column(homology_dim: int, metric: str) -> str:
    """Column name of a table entry: ``beta0_d_B``, ``beta1_d_W2`` …"""
    return f"beta{homology_dim}_{METRIC_SYMBOLS[metric]}"


def pretty_column(column: str) -> str:
    """A `table_column` name as printed: ``beta0_d_B`` → ``β0 d_B`` (other names unchanged)."""
    beta, _, symbol = column.partition("_")
    return f"β{beta[-1]} {symbol}" if beta.startswith("beta") else column


def format_number(value: Any, digits: int = 3) -> str:
    """A table cell: a float to `digits` significant digits ("inf" for +∞, as a distance between diagrams with
    different numbers of never-dying classes under the ``apart`` convention; "n/a" for NaN or −∞), anything else
    as text."""
    if isinstance(value, (float, np.floating)):
        if value == np.inf:
            return "inf"
        if not np.isfinite(value):
            return "n/a"
        return f"{value:.{digits}g}"
    return str(value)


# =============================================================================================================
# Validation: each claim of P2 §III D–§IV with its evidence and a computed verdict
