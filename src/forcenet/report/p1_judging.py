"""What P1's claims are judged on (with the tolerances of the one record both papers share,
`forcenet.report.claims.ClaimTolerances`): one system as a judge sees it
(`SystemData`), every system for the claims that compare them (`ClaimContext`), and the helpers the judges of
`forcenet.report.p1_claims` and `forcenet.report.p1_claims_topology` share (peaks, "≈ 0 below ρ_J", "grows beyond
ρ_J"). Curves are realization means (`forcenet.report.realizations`) of the total-force network measures, versus ρ.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Callable, Mapping

import numpy as np
import xarray as xr

from forcenet.report.claims import (BELOW_BEFORE_JUMP, BELOW_TOLERANCE, ClaimTolerances, Judgement, NotEvaluated,
                                    relative_margin, smallest_margin)
from forcenet.report.p1 import (HERTZ_2D, HERTZ_3D, LINEAR_2D, finite_max, first_max_index, force_pdf_width,
                                per_particle, percolating_size_mean, rho_values, shape_parameter_average,
                                system_order)
from forcenet.report.realizations import realization_mean

@dataclass(frozen=True)
class SystemData:
    """One system as the judges see it.

    data : total-force measures over the judged ρ range (all ρ, or ρ ≤ ρ_max with ``judge_up_to_rho_max``);
    full : total-force measures over every simulated ρ; rho_j : ρ_J (inflection of Z, from every ρ); `jump`: the
    two states the mean Z jumps between (the last unjammed and the first jammed state); rho_max :
    ρ_max under the table's force unit; tolerance, window : `ClaimTolerances.rho_tolerance`/`rho_window` resolved
    for this system; below_cut : `ClaimTolerances.below_cut`; overlaps : the largest overlap of two particles
    relative to the sum of their radii in its snapshots, {ρ: overlap} (P1 §3; empty when not given).

    The curves the judges share (`mean`, `percolating_size`, `shape_average`, `pdf_width`) are computed once per
    SystemData and handed out read-only: one table asks for the same curve of a system many times, in every
    bootstrap resample.
    """

    name: str
    dimension: int
    force_law: str
    data: xr.Dataset
    full: xr.Dataset
    rho_j: float
    rho_max: float
    tolerance: float
    window: float
    below_cut: str = BELOW_BEFORE_JUMP
    overlaps: Mapping[float, float] = field(default_factory=dict, compare=False)
    _computed: dict = field(default_factory=dict, init=False, repr=False, compare=False)

    @property
    def role(self) -> tuple[int, str]:
        """(dimension, force law): how P1 tells its systems apart."""
        return (self.dimension, self.force_law)

    @property
    def rho(self) -> np.ndarray:
        """The judged packing fractions ρ, (n_rho,)."""
        return self.computed(("rho",), lambda: rho_values(self.data).copy())  # a copy: the dataset is left as it is

    @property
    def jump(self) -> tuple[float, float]:
        """(last unjammed ρ, first jammed ρ): the two consecutive states of the largest rise of the realization-mean
        Z (every simulated ρ), the jump the jamming transition is crossed in (NaN, NaN with fewer than 2 states)."""
        def compute() -> tuple[float, float]:
            z = realization_mean(self.full["Z"]).transpose("rho").values.astype(float)
            rho = rho_values(self.full)
            rise = np.diff(z)
            if rise.size == 0 or not np.isfinite(rise).any():
                return math.nan, math.nan
            k = int(np.nanargmax(rise))
            return float(rho[k]), float(rho[k + 1])
        return self.computed(("jump",), compute)

    @property
    def below(self) -> np.ndarray:
        """The states below jamming (mask over `data`'s ρ), by `below_cut`: `BELOW_BEFORE_JUMP`, the states up to
        the last one before the jump of Z (`jump`), never at or above ρ_J (in 3D ρ_J = 0.595 falls between 0.59
        and 0.60, but Z jumps between 0.58 and 0.59: 0.59 is jammed); `BELOW_TOLERANCE`, ρ < ρ_J − tolerance."""
        if self.below_cut == BELOW_TOLERANCE:
            return self.rho < self.rho_j - self.tolerance - 1e-12
        last_unjammed = self.jump[0]
        before_jump = self.rho <= last_unjammed + 1e-12 if np.isfinite(last_unjammed) else True
        return (self.rho < self.rho_j - 1e-12) & before_jump

    @property
    def below_text(self) -> str:
        """What `below` is, for the evidence texts: ``rho <= 0.580 (before the jump of Z)`` or ``rho < 0.575``."""
        mask = self.below
        if self.below_cut == BELOW_TOLERANCE or not mask.any():
            return f"rho < {self.rho_j - (self.tolerance if self.below_cut == BELOW_TOLERANCE else 0.0):.3f}"
        return f"rho <= {self.rho[mask][-1]:.3f} (before the jump of Z)"

    @property
    def first_jammed(self) -> float:
        """The first state after the jump of Z (`jump`): the first jammed state."""
        return self.jump[1]

    @property
    def step(self) -> float:
        """The system's ρ grid step (median spacing; 0 with one ρ)."""
        return float(np.median(np.diff(self.rho))) if self.rho.size > 1 else 0.0

    def states(self, mask: np.ndarray) -> str:
        """The states of `mask` as text for the table's states column: ``rho 0.780-0.800 (3 states)``."""
        rho = self.rho[np.asarray(mask, bool)]
        if rho.size == 0:
            return "no state"
        span = f"{rho[0]:.3f}" if rho.size == 1 else f"{rho[0]:.3f}-{rho[-1]:.3f}"
        return f"rho {span} ({rho.size} state{'s' if rho.size > 1 else ''})"

    @property
    def beyond(self) -> np.ndarray:
        """ρ > ρ_J + tolerance (mask over `data`'s ρ)."""
        return self.rho > self.rho_j + self.tolerance + 1e-12

    @property
    def thresholds(self) -> np.ndarray:
        """The force thresholds F_th [⟨F⟩], (n_threshold,)."""
        return np.asarray(self.data["threshold"].values, dtype=float)

    @property
    def lowest_threshold(self) -> float:
        """The smallest F_th of the grid [⟨F⟩] (P1's "F_th = min", the whole network)."""
        return float(self.thresholds.min())

    def computed(self, key: tuple, compute: Callable[[], object]):
        """`compute()` the first time `key` is asked for, the same (read-only) value after that; a key that cannot
        be hashed is computed every time."""
        try:
            hash(key)
        except TypeError:  # an unhashable selection (an array of ρ): nothing to share
            return read_only(compute())
        if key not in self._computed:
            self._computed[key] = read_only(compute())
        return self._computed[key]

    def mean(self, name: str, per_n: bool = True, full: bool = False, **selection) -> xr.DataArray:
        """Realization mean of ``name`` (divided by N when `per_n`), with `selection` applied."""
        def compute() -> xr.DataArray:
            ds = self.full if full else self.data
            values = per_particle(ds, name) if per_n else ds[name]
            return realization_mean(values.sel(**selection))
        return self.computed(("mean", name, per_n, full, tuple(sorted(selection.items()))), compute)

    def percolating_size(self) -> xr.DataArray:
        """N_per/N (ρ, F_th) where ≥ 50 % of the realizations percolate (P1 §4.3, `percolating_size_mean`), NaN
        elsewhere."""
        return self.computed(("percolating_size",),
                             lambda: percolating_size_mean(self.data)[0].transpose("rho", "threshold"))

    def pdf_width(self, full: bool = False) -> xr.DataArray:
        """Std of F/⟨F⟩ of each snapshot (`force_pdf_width`) [⟨F⟩], dims (realization, rho), over the judged ρ
        (`full`: every simulated ρ)."""
        widths = self.computed(("pdf_width",), lambda: force_pdf_width(self.full))
        return widths if full else widths.sel(rho=self.data["rho"])

    def shape_average(self, name: str = "shape_parameter") -> tuple[xr.DataArray, xr.DataArray]:
        """(S_p, spread) of the shape-parameter variable `name` over (ρ, F_th), averaged over the realizations by
        P1 §5.2's rule (`shape_parameter_average`)."""
        return self.computed(("shape_average", name), lambda: shape_parameter_average(self.data[name]))

    def label(self) -> str:
        """``name (rho_J=…)`` for the evidence texts."""
        return f"{self.name} (rho_J={self.rho_j:.3f})"


def read_only(value):
    """`value` with its arrays and the arrays of its DataArrays (also inside a tuple) made read-only, so that a
    judge that writes into a shared curve fails instead of changing what the next judge reads."""
    for item in value if isinstance(value, tuple) else (value,):
        if isinstance(item, xr.DataArray):
            item.values.flags.writeable = False  # numpy-backed: the DataArray's own array
        elif isinstance(item, np.ndarray):
            item.flags.writeable = False
    return value


@dataclass(frozen=True)
class ClaimContext:
    """Every system present, for claims that compare systems; `counterparts` are the runs (μ = 0, other boxes) that
    only the claims comparing a P1 system with another run of its role see (`studies.p1.counterparts`)."""

    systems: Mapping[str, SystemData]
    tolerances: ClaimTolerances
    counterparts: frozenset[str] = frozenset()
    #: every claim being judged (`forcenet.report.p1_validation.CLAIMS`): P1 §3's "qualitatively the same" judges
    #: each per-system claim on both runs of a pair, so the context hands the list down instead of being imported
    claims: tuple = ()

    @property
    def own(self) -> dict[str, SystemData]:
        """The systems that are not counterparts: those P1's claims about "all systems" compare."""
        return {name: system for name, system in self.systems.items() if name not in self.counterparts}

    def role(self, role: tuple[int, str]) -> SystemData:
        """The first system (P1's order) with this role, never a counterpart; NotEvaluated when none is present or
        its ρ_J is NaN."""
        for name in system_order(self.own):
            system = self.systems[name]
            if system.role == role:
                if not np.isfinite(system.rho_j):
                    raise NotEvaluated(f"rho_J of {name} could not be located")
                return system
        raise NotEvaluated(f"no {role[0]}D {role[1]} system in the results")

    def nonlinear(self) -> list[SystemData]:
        """The non-linear (Hertzian) systems present, one per dimension, each with a located ρ_J."""
        found = []
        for role in (HERTZ_2D, HERTZ_3D):
            try:
                found.append(self.role(role))
            except NotEvaluated:
                pass
        if not found:
            raise NotEvaluated("no non-linear system with a located rho_J in the results")
        return found


ALL_2D = (HERTZ_2D, LINEAR_2D)


# --- helpers the judges share ---------------------------------------------------------------------------------
@dataclass(frozen=True)
class Peak:
    """The highest point of a curve versus ρ: where, how high, its topographic prominence relative to a scale,
    and whether it lies within the tolerance of ρ_J."""

    rho: float
    value: float
    relative_prominence: float
    near: bool


def find_peak(curve, rho: np.ndarray, rho_j: float, tolerance: float, scale: float) -> Peak | None:
    """The maximum of `curve` (ρ,) and its prominence: height above the higher of the lowest points on its two
    sides (0 when the maximum is at an end of a monotonic curve), divided by `scale`. None if all NaN.

    A maximum shared by several ρ is the first of them (`first_max_index`)."""
    curve = np.asarray(curve, dtype=float)
    if not np.isfinite(curve).any() or not np.isfinite(scale) or scale <= 0:
        return None
    k = first_max_index(curve)
    prominence = curve[k] - max(np.nanmin(curve[:k + 1]), np.nanmin(curve[k:]))
    return Peak(float(rho[k]), float(curve[k]), float(prominence / scale),
                bool(abs(rho[k] - rho_j) <= tolerance + 1e-12))


def peak_near(curve, rho: np.ndarray, rho_j: float, tolerance: float) -> Peak | None:
    """The highest point of `curve` (ρ,) within `tolerance` of ρ_J and its prominence within the curve itself
    (P1 §5.1 compares the small-F_th B0/N near ρ_J with the same curve beyond it, Fig. 6d zooming in): its height
    above the higher of the lowest points reached on either side before the curve rises above it again, divided
    by its own height. 0 where it is not a local maximum (the curve rises on past the window) or lies at the end
    of the grid. None when the window holds no finite positive value."""
    curve = np.asarray(curve, dtype=float)
    window = np.flatnonzero((np.abs(rho - rho_j) <= tolerance + 1e-12) & np.isfinite(curve))
    if window.size == 0 or not (curve[window] > 0).any():
        return None
    k = int(window[first_max_index(curve[window])])
    top = curve[k]

    def lowest(indices) -> float:
        """The lowest point walking away from the peak along `indices`, until the curve rises above the peak."""
        low, walked = top, False
        for i in indices:
            if not np.isfinite(curve[i]):
                continue
            if curve[i] > top:
                break
            low, walked = min(low, curve[i]), True
        return low if walked else top

    prominence = top - max(lowest(range(k - 1, -1, -1)), lowest(range(k + 1, curve.size)))
    return Peak(float(rho[k]), float(top), float(prominence / top), True)


def strongest_peak(values: xr.DataArray, system: SystemData, thresholds: np.ndarray,
                    scale: float) -> tuple[Peak, float] | None:
    """Among the curves values(ρ) at each F_th in `thresholds`, the peak that is near ρ_J with the largest
    prominence (else the most prominent one); returns (peak, its F_th) or None."""
    best = None
    for threshold in thresholds:
        peak = find_peak(values.sel(threshold=threshold).transpose("rho").values, system.rho, system.rho_j,
                     system.tolerance, scale)
        if peak is not None and (best is None or (peak.near, peak.relative_prominence)
                                 > (best[0].near, best[0].relative_prominence)):
            best = (peak, float(threshold))
    return best


def near_by_one_step(peak: Peak, system: SystemData) -> bool:
    """True when the peak's "near ρ_J" turns if it moves by one grid step (it lies within one step of the
    tolerance's edge): a verdict that rests on it is marginal."""
    return abs(abs(peak.rho - system.rho_j) - system.tolerance) < system.step - 1e-12


def peak_verdict(peak: Peak | None, what: str, system: SystemData, tolerances: ClaimTolerances,
                  expected: bool, threshold: float | None = None) -> Judgement:
    """A peak near ρ_J is present iff near and relative prominence ≥ min_prominence; holds iff as expected.
    Marginal when the prominence is within 10 % of min_prominence or "near" turns by one grid step."""
    if peak is None:
        raise NotEvaluated(f"{what} is NaN or zero everywhere")
    present = peak.near and peak.relative_prominence >= tolerances.min_prominence
    at = f" at F_th={threshold:.3g}" if threshold is not None else ""
    evidence = (f"highest {what}{at}: {peak.value:.3g} at rho={peak.rho:.3f} ({system.label()}, tolerance "
                f"{system.tolerance:.3g}), relative prominence {peak.relative_prominence:.2f}; peak "
                f"{'present' if present else 'absent'}, expected {'present' if expected else 'absent'} for a "
                f"{system.force_law} law")
    # near ρ_J the prominence decides, else the distance from ρ_J against the tolerance
    margin = (relative_margin(peak.relative_prominence, tolerances.min_prominence) if peak.near
              else relative_margin(abs(peak.rho - system.rho_j), system.tolerance))
    return Judgement(peak.relative_prominence, evidence, present == expected, margin=margin,
                     grid_step=near_by_one_step(peak, system), states=f"rho {peak.rho:.3f}")


def expected_for_law(system: SystemData, nonlinear: bool) -> bool:
    """True where P1 expects the feature: for the non-linear (Hertz) laws if `nonlinear`, else for the linear law."""
    if system.force_law not in ("hertz", "linear"):
        raise NotEvaluated(f"force law '{system.force_law}' unknown")
    return (system.force_law == "hertz") == nonlinear


def betti_curve(system: SystemData, k: int, full: bool = False) -> xr.DataArray:
    """Realization mean of max over F_th of B_k/N, versus ρ."""
    ds = system.full if full else system.data
    if k not in ds["homology_dim"].values:
        raise NotEvaluated(f"no B{k} in the results")
    return realization_mean(per_particle(ds, "betti").sel(homology_dim=k).max("threshold", skipna=True))


def persistence_curve(system: SystemData, k: int) -> xr.DataArray:
    """Realization mean of TP_k/N versus ρ."""
    if k not in system.data["homology_dim"].values:
        raise NotEvaluated(f"no TP{k} in the results")
    return system.mean("total_persistence", homology_dim=k)


def bin_curve(system: SystemData, bin_name: str) -> xr.DataArray:
    """Realization mean of the PD0 points per particle in a P1 §5.3 persistence bin, versus ρ."""
    return system.mean("persistence_bin_count", persistence_bin=bin_name)


def require(mask: np.ndarray, what: str) -> np.ndarray:
    """`mask` (boolean, any shape) when any entry is set; NotEvaluated("no <what>") otherwise."""
    if not np.any(mask):
        raise NotEvaluated(f"no {what}")
    return mask


def finite_values(values, what: str) -> np.ndarray:
    """The finite entries of `values` (any shape) as a flat array; NotEvaluated when there are none."""
    values = np.asarray(values, dtype=float).ravel()
    values = values[np.isfinite(values)]
    if values.size == 0:
        raise NotEvaluated(f"{what}: no finite values")
    return values


def interp_at(curve: xr.DataArray, rho: float) -> float:
    """Linear interpolation of a curve versus ρ at `rho`, clipped to its finite range."""
    grid, values = rho_values(curve), np.asarray(curve.values, dtype=float)
    ok = np.isfinite(values)
    if not ok.any():
        return math.nan
    return float(np.interp(np.clip(rho, grid[ok].min(), grid[ok].max()), grid[ok], values[ok]))


def fmt_values(values, digits: int = 3) -> str:
    """``[v0, v1, …]`` to `digits` significant digits ("nan" where not finite), for the evidence texts."""
    return "[" + ", ".join("nan" if not np.isfinite(v) else f"{v:.{digits}g}" for v in np.asarray(values, float)) + "]"


def zero_below(curve: xr.DataArray, system: SystemData, tolerances: ClaimTolerances, what: str) -> Judgement:
    """`what` ≈ 0 below ρ_J: its largest value over the states `below` ≤ negligible_fraction × its maximum.

    Vacuous (issue 25) when `what` is zero below ρ_J and also at more than half of the states beyond ρ_J + tol:
    P1's "vanishes below, grows beyond" then has nothing to contrast (B2 with filled tetrahedra)."""
    below = require(system.below, f"states below jamming ({system.below_text})")
    values = np.asarray(curve.values, dtype=float)
    below_max, overall = finite_max(values[below]), finite_max(values)
    if not np.isfinite(overall):
        raise NotEvaluated(f"{what} is NaN everywhere")
    limit = tolerances.negligible_fraction * overall
    holds = below_max == 0 or below_max <= limit
    beyond = values[system.beyond]
    zero_beyond = int(np.count_nonzero(beyond == 0))
    vacuous = bool(below_max == 0 and beyond.size > 0 and zero_beyond > beyond.size / 2)
    evidence = (f"max {what} for {system.below_text}: {below_max:.3g}; max over all rho "
                f"{overall:.3g} ({system.label()}); zero at {zero_beyond} of {beyond.size} rho beyond rho_J + tol")
    margin = relative_margin(below_max, limit)  # 1 for a quantity that is zero below ρ_J
    return Judgement(below_max, evidence, bool(holds), margin=margin, vacuous=vacuous, states=system.states(below))


def grows_beyond(curve: xr.DataArray, system: SystemData, tolerances: ClaimTolerances, what: str) -> Judgement:
    """`what` grows monotonically beyond ρ_J: over ρ ≥ ρ_J − tolerance it rises by more than negligible_fraction
    of its maximum and never drops between consecutive ρ by more than monotone_tolerance of it, and it is present
    (> 0) at every ρ > ρ_J + tolerance — a quantity that stays zero until the top of the grid has not grown "as ρ
    increases beyond ρ_J", however monotone its last step."""
    require(system.beyond, "rho beyond rho_J")
    from_jamming = system.rho >= system.rho_j - system.tolerance - 1e-12
    all_values = np.asarray(curve.values, dtype=float)
    values = all_values[from_jamming]
    values = values[np.isfinite(values)]
    if values.size < 2:
        raise NotEvaluated(f"fewer than 2 rho from rho_J - {system.tolerance:.3g} on")
    beyond = all_values[system.beyond]
    absent = int(np.count_nonzero(~(beyond > 0)))
    top = float(values.max())
    growth = float(values[-1] - values[0])
    drop = float(max(0.0, np.max(values[:-1] - values[1:])))
    holds = (top > 0 and growth > tolerances.negligible_fraction * top and drop <= tolerances.monotone_tolerance * top
             and absent == 0)
    evidence = (f"{what} from rho={system.rho[from_jamming][0]:.3f} on: {fmt_values(values)} ({system.label()}); "
                "growth "
                f"{growth:.3g}, largest drop {drop:.3g}, max {top:.3g}; zero at {absent} of {beyond.size} rho beyond "
                "rho_J + tol")
    margin = smallest_margin(relative_margin(growth, tolerances.negligible_fraction * top),
                             relative_margin(drop, tolerances.monotone_tolerance * top) if drop > 0 else math.nan)
    return Judgement(growth, evidence, bool(holds), margin=margin, states=system.states(from_jamming))
