"""What P2's claims are judged on (with the tolerances of the one record both papers share,
`forcenet.report.claims.ClaimTolerances`): one system's realization-mean curves over ρ (`Curves`), everything a
claim may need (`Context`), and the statistics and
text helpers the judges of `forcenet.report.p2_claims` and the diagnostics of `forcenet.report.p2_explanations`
share. Curves are realization means (`forcenet.report.realizations`) of ``distances.nc``; ρ_J is where the mean Z(ρ)
first reaches d + 1 (P2 §IV A).
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Callable, Mapping, Sequence

import numpy as np
import pandas as pd
import xarray as xr

from forcenet.report.claims import ClaimTolerances, NotEvaluated
from forcenet.report.p2 import METRIC_SYMBOLS, format_number, jamming_density, mean_distance_ratio
from forcenet.report.realizations import realization_mean


@dataclass
class Curves:
    """Realization-mean curves of one system, as pandas Series over ρ (NaN dropped)."""

    name: str
    ds: xr.Dataset
    dimension: int
    tol: ClaimTolerances
    rho_j: float = field(init=False)

    def __post_init__(self):
        """ρ_J of the mean Z, and every realization-mean distance curve, keyed (force kind, k, metric)."""
        self.rho_j = jamming_density(self.ds, self.dimension)
        mean = realization_mean(self.ds["distance"])
        self._curves = {(k, int(h), m): as_series(mean.sel(force_kind=k, homology_dim=h, metric=m))
                        for k in mean["force_kind"].values for h in mean["homology_dim"].values
                        for m in mean["metric"].values}

    @property
    def n_realizations(self) -> int:
        """How many realizations the system's distances hold."""
        return int(self.ds.sizes.get("realization", 1))

    def mean(self, kind: str, dim: int, metric: str) -> pd.Series:
        """Realization-mean distance curve over ρ."""
        try:
            return self._curves[kind, dim, metric]
        except KeyError:
            raise NotEvaluated(f"{self.name}: no {kind} PD{dim} {metric} distances") from None

    def ratio(self, kind: str, dim: int, denominator: str) -> pd.Series:
        """d_B / d_Wq of the realization-mean curves where d_Wq > 0: `mean_distance_ratio`, the curves the
        figures draw (P2 Figs 7, 10)."""
        for metric in (B, denominator):
            self.mean(kind, dim, metric)  # not evaluated unless both curves exist
        return as_series(mean_distance_ratio(self.ds, denominator).sel(force_kind=kind, homology_dim=dim))

    @property
    def step(self) -> float:
        """The sampling step in ρ (median spacing of the distances' ρ; 0 with one ρ)."""
        rho = np.asarray(self.ds["rho"].values, dtype=float)
        return float(np.median(np.diff(rho))) if rho.size > 1 else 0.0

    def by_one_step(self, distance: float, limit: float) -> bool:
        """True when `distance` (a ρ offset) lies within one sampling step of the `limit` it is compared with: the
        verdict turns if a state moves by one step (marginal)."""
        return bool(np.isfinite(distance) and abs(abs(distance) - limit) < self.step - 1e-12)

    def jammed(self) -> float:
        """ρ_J; not evaluated when the mean Z never reaches d + 1 inside the ρ range."""
        if not np.isfinite(self.rho_j):
            raise NotEvaluated(f"{self.name}: the mean Z does not rise through d+1 = {self.dimension + 1} "
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
            infinite = int((inside & np.isinf(s.values)).sum())
            # an infinite distance: the two diagrams hold different numbers of never-dying classes, which the
            # 'apart' convention (analysis.essential_convention) never matches with finite points
            why = f"; {infinite} infinite there (different numbers of never-dying classes)" if infinite else ""
            raise NotEvaluated(f"{self.name}: {len(part)} finite rho value(s) in {interval} (need "
                               f"{self.tol.min_points}){why}")
        return part

    def argmax(self, s: pd.Series, lo: float = -np.inf, hi: float = np.inf, **closed: bool) -> float:
        """ρ of the largest value of `s` in a `window` (not evaluated if the window has too few values)."""
        return float(self.window(s, lo, hi, **closed).idxmax())


def as_series(da: xr.DataArray) -> pd.Series:
    """A curve over ρ (1-D DataArray with a ``rho`` coordinate) as a pandas Series indexed by ρ, NaN dropped."""
    s = pd.Series(np.asarray(da.values, dtype=float), index=np.asarray(da["rho"].values, dtype=float))
    return s[np.isfinite(s.values)]


def coefficient_of_variation(s: pd.Series) -> float:
    """std / |mean| of the values of `s` (population std), inf when the mean is 0."""
    mean = float(np.mean(s.values))
    return float(np.std(s.values) / abs(mean)) if mean != 0 else math.inf


def ranks(x: np.ndarray) -> np.ndarray:
    """Ranks of the values of `x` (n,), ties sharing their mean rank."""
    return pd.Series(x).rank(method="average").to_numpy()


def pearson(x: np.ndarray, y: np.ndarray) -> float:
    """Pearson correlation of x and y (both (n,)); NaN for fewer than 2 points or a constant input."""
    x, y = np.asarray(x, float), np.asarray(y, float)
    if len(x) < 2 or np.std(x) == 0 or np.std(y) == 0:
        return math.nan
    return float(np.corrcoef(x, y)[0, 1])


def spearman(s: pd.Series) -> float:
    """Rank correlation of a curve with ρ (+1: increases monotonically, −1: decreases)."""
    return pearson(ranks(s.index.values), ranks(s.values))


def within_factor(value: float, reference: float, factor: float) -> bool:
    """True when `value` is finite and within [reference / factor, reference · factor]."""
    return bool(np.isfinite(value) and reference / factor <= value <= reference * factor)


def within_factor_margin(value: float, reference: float, factor: float) -> float:
    """How far `value` lies from the nearer edge of [reference / factor, reference · factor], on a log scale
    relative to log(factor) (0 on an edge; NaN unless value, reference > 0)."""
    if not (np.isfinite(value) and value > 0 and reference > 0 and factor > 1):
        return math.nan
    return abs(abs(math.log(value / reference)) - math.log(factor)) / math.log(factor)


def log10_ratio(num: pd.Series, den: pd.Series) -> pd.Series:
    """log10(num/den) at the ρ both curves share (positive values only)."""
    common = num.index.intersection(den.index)
    n, d = num[common], den[common]
    ok = (n > 0) & (d > 0)
    return np.log10(n[ok] / d[ok])


def on_grid(s: pd.Series, x: np.ndarray) -> np.ndarray:
    """Linear interpolation of a curve onto x (NaN outside its range)."""
    return np.interp(x, s.index.values, s.values, left=np.nan, right=np.nan)


def fmt(value: float, digits: int = 3) -> str:
    """A number for the evidence texts: `digits` significant digits (`format_number`: "inf", "n/a")."""
    return format_number(float(value), digits)


def per_metric_text(values: Mapping[str, float]) -> str:
    """``d_B 1.2, d_W1 0.34, …`` for {metric: value}."""
    return ", ".join(f"{METRIC_SYMBOLS[m]} {fmt(v, 2)}" for m, v in values.items())


def per_dim_metric_text(values: Mapping[tuple[int, str], float]) -> str:
    """``beta0 d_B 1.2, …`` for {(homology_dim, metric): value}."""
    return ", ".join(f"beta{h} {METRIC_SYMBOLS[m]} {fmt(v, 2)}" for (h, m), v in values.items())


def rate_quotient(numerator: float, denominator: float, what: str = "") -> float:
    """numerator / denominator of two non-negative values, inf where only the denominator is 0. Both 0 (no
    change at all in either curve, e.g. no loops yet) cannot be compared: the claim is not evaluated."""
    if denominator > 0:
        return float(numerator) / float(denominator)
    if numerator > 0:
        return math.inf
    raise NotEvaluated(f"both rates are 0{' (' + what + ')' if what else ''}: nothing to compare")


@dataclass
class Context:
    """Everything P2's claims are judged on: the curves of each system present, Tables I–III (frictional system),
    the tolerances, the names of the frictional and frictionless systems, for the explanations the network
    measures (never-dying class counts) and the candidate states a, b, c, and each system's persistence diagrams
    (``diagrams.nc``) or their PD1 point counts (how many PD points a state has)."""

    curves: dict[str, Curves]
    tables: Mapping[str, pd.DataFrame] | None
    tol: ClaimTolerances
    frictional: str
    frictionless: str
    measures: Mapping[str, xr.Dataset] = field(default_factory=dict)
    states: pd.DataFrame | None = None
    diagrams: Mapping[str, xr.Dataset] = field(default_factory=dict)
    #: {system: normal-force PD1 point counts (realization, rho)}, as `forcenet.report.p2.diagram_point_counts`
    #: gives them from `diagrams` (`forcenet.report.p2_distances.summary_point_counts`); read before `diagrams`
    point_counts: Mapping[str, xr.DataArray] = field(default_factory=dict)

    def system(self, name: str) -> Curves:
        """The curves of system `name`; not evaluated when it is not in the results."""
        if name not in self.curves:
            raise NotEvaluated(f"system {name} not in the results")
        return self.curves[name]

    def both(self) -> tuple[Curves, Curves]:
        """(frictional, frictionless) curves; not evaluated unless both systems are in the results."""
        return self.system(self.frictional), self.system(self.frictionless)

    def table(self, name: str) -> pd.DataFrame:
        """Table I, II or III (``"table1"`` …); not evaluated when not given."""
        if not self.tables or name not in self.tables:
            raise NotEvaluated(f"{name} not given")
        return self.tables[name]


NORMAL, TANGENTIAL = "normal", "tangential"
B, W1, W2 = "bottleneck", "wasserstein_1", "wasserstein_2"


def median_quotient(ctx: Context, dim: int, metrics: Sequence[str], lo: float = -np.inf, hi: float = np.inf, *,
                    closed_lo: bool = True, closed_hi: bool = False,
                    bounds: Callable[[Curves], tuple[float, float]] | None = None) -> dict[str, float]:
    """{metric: median of the mu = 0 curve / median of the mu = 0.5 curve} (normal forces, PD_dim), both over the
    same rho window [lo, hi) (`closed_lo`, `closed_hi` as `Curves.window`), or each over its own window
    ``bounds(curves)`` (e.g. the same depth above each system's own rho_J); `rate_quotient` where a median is 0."""
    f, n = ctx.both()

    def median(c: Curves, metric: str) -> float:
        """Median of one system's curve over its window."""
        low, high = bounds(c) if bounds is not None else (lo, hi)
        return float(c.window(c.mean(NORMAL, dim, metric), low, high, closed_lo=closed_lo, closed_hi=closed_hi).median())

    return {m: rate_quotient(median(n, m), median(f, m), f"beta{dim} {METRIC_SYMBOLS[m]} medians of both systems")
            for m in metrics}
