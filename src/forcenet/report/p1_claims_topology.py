"""P1's claims about the topology of the force networks (§5): Betti numbers (§5.1), the shape of the clusters
(§5.2), persistence diagrams and total persistence (§5.3); one `forcenet.report.claims.Claim` record and one
judging function each, registered in `CLAIMS` in definition order. Judges, criteria and tolerances work as in
`forcenet.report.p1_claims`.
"""
from __future__ import annotations

import math
from typing import Callable

import numpy as np
import xarray as xr

from forcenet.report.claims import (Claim, ClaimTolerances, Judgement, NotEvaluated, claim_register,
                                    contrast_margin, ratio_margin, relative_margin, smallest_margin)
from forcenet.report.p1 import (HERTZ_2D, HERTZ_3D, LINEAR_2D, P1_LARGE_THRESHOLD, P1_OPEN_PATH_MIN, P1_SHAPE_BOUNDS,
                                P1_SMALL_THRESHOLD, PAPER_CLUSTER_SIZE_PEAK, finite_max, finite_min, first_max_index,
                                rho_values)
from forcenet.report.p1_judging import (ALL_2D, ClaimContext, Peak, SystemData, betti_curve, bin_curve,
                                        expected_for_law, find_peak, finite_values, fmt_values, grows_beyond, interp_at,
                                        near_by_one_step, peak_near, peak_verdict, persistence_curve, require,
                                        zero_below)

CLAIMS: list[Claim] = []
claim = claim_register(CLAIMS)


# --- §5.1 Betti numbers -----------------------------------------------------------------------------------------
def _ridge(system: SystemData) -> tuple[Peak, float] | None:
    """P1 §5.1's ridge: among the B0/N curves at F_th < 0.5, the highest point within tol of ρ_J with its
    prominence within its own curve (`peak_near`); the curve whose peak is most prominent, and its F_th (None when
    no curve has a positive value near ρ_J)."""
    b0 = system.mean("betti", homology_dim=0)
    small = system.thresholds[system.thresholds < P1_SMALL_THRESHOLD]
    if small.size == 0 or system.data.sizes["rho"] < 3:
        raise NotEvaluated("no F_th < 0.5 or fewer than 3 rho")
    best = None
    for threshold in small:
        peak = peak_near(b0.sel(threshold=threshold).transpose("rho").values, system.rho, system.rho_j,
                         system.tolerance)
        if peak is not None and (best is None or peak.relative_prominence > best[0].relative_prominence):
            best = (peak, float(threshold))
    return best


@claim("p1-5.1-b0-ridge", "5.1",
       "for F_th < 0.5 the non-linear systems develop a B0/N peak (ridge) near rho_J, against the same curve beyond "
       "it (Figs. 2, 6; 6d zooms in on 3D)",
       "some mean B0/N(rho) curve at F_th < 0.5 has its highest point within tol of rho_J with prominence >= "
       "{min_prominence} of its own height (within the curve)", scope=(HERTZ_2D, HERTZ_3D))
def b0_ridge(system: SystemData, tolerances: ClaimTolerances) -> Judgement:
    """Judge of claim p1-5.1-b0-ridge (per system): the peak within its curve."""
    found = _ridge(system)
    if found is None:
        raise NotEvaluated("B0/N at F_th < 0.5 is NaN or zero near rho_J")
    peak, threshold = found
    present = peak.relative_prominence >= tolerances.min_prominence
    evidence = (f"highest B0/N near rho_J at F_th={threshold:.3g}: {peak.value:.3g} at rho={peak.rho:.3f} "
                f"({system.label()}, tolerance {system.tolerance:.3g}), prominence {peak.relative_prominence:.2f} of "
                f"its height; peak {'present' if present else 'absent'}")
    return Judgement(peak.relative_prominence, evidence, present,
                     margin=relative_margin(peak.relative_prominence, tolerances.min_prominence),
                     grid_step=near_by_one_step(peak, system), states=f"rho {peak.rho:.3f}")


def _on_one_scale(system: SystemData, peak: Peak | None, scale: float, what: str, where: str = "") -> tuple[float, str]:
    """A peak near ρ_J found within its own curve (`peak_near`) measured on a scale shared by several systems: its
    prominence in the curve's own units divided by `scale`, and a text (0 where there is no peak)."""
    if peak is None:
        return 0.0, f"{system.name} no {what} near rho_J"
    share = peak.relative_prominence * peak.value / scale
    return share, f"{system.name} {share:.3g} (peak {peak.value:.3g} at rho={peak.rho:.3f}{where})"


def _ridge_height(system: SystemData) -> tuple[float, str]:
    """The ridge's prominence in B0/N itself (one scale for every system of a dimension) and a text."""
    found = _ridge(system)
    peak, threshold = found if found else (None, math.nan)
    return _on_one_scale(system, peak, 1.0, "B0/N", f", F_th={threshold:.3g}")


@claim("p1-5.1-b0-ridge-law-contrast", "5.1",
       "the B0/N ridge is pronounced for the non-linear law and rather insignificant for the linear one (§5.1, §6: "
       "'one of the prominent results')",
       "prominence of the B0/N ridge (F_th < 0.5, within tol of rho_J) in B0/N itself, one scale for the 2D laws: "
       "2D Hertz >= {contrast_factor} x 2D linear", per_system=False)
def b0_ridge_law_contrast(context: ClaimContext) -> Judgement:
    """Judge of claim p1-5.1-b0-ridge-law-contrast (across systems)."""
    hertz, hertz_text = _ridge_height(context.role(HERTZ_2D))
    linear, linear_text = _ridge_height(context.role(LINEAR_2D))
    ratio = hertz / linear if linear > 0 else (math.inf if hertz > 0 else 0.0)
    factor = context.tolerances.contrast_factor
    return Judgement(ratio, f"ridge prominence in B0/N: {hertz_text}; {linear_text}; ratio {ratio:.3g}",
                     ratio >= factor, margin=ratio_margin(ratio, factor))


def _b0_maximum_threshold(system: SystemData) -> tuple[float, np.ndarray]:
    """Median over ρ > ρ_J + tol of the F_th [⟨F⟩] maximising the mean B0/N, and those F_th per ρ."""
    beyond = require(system.beyond, "rho beyond rho_J")
    b0 = system.mean("betti", homology_dim=0).transpose("rho", "threshold").values[beyond]
    rows = [row for row in b0 if np.isfinite(row).any() and np.nanmax(row) > 0]
    if not rows:
        raise NotEvaluated("no clusters beyond rho_J")
    best = np.array([system.thresholds[first_max_index(row)] for row in rows])
    return float(np.median(best)), best


def _b0_maximum_criterion(t: ClaimTolerances) -> str:
    """The criterion of p1-1-b0-maximum-above-mean-force with the tolerances `t` filled in."""
    return (f"median over rho > rho_J + tol of the F_th maximising mean B0/N: 2D in (1, 1 + 2 x "
            f"{t.threshold_tolerance}] <F>; 3D within {t.threshold_tolerance} of P1's own 3D F_th ~ "
            f"{PAPER_CLUSTER_SIZE_PEAK[HERTZ_3D]:g} (§4.2: 3D networks peak at larger forces)")


@claim("p1-1-b0-maximum-above-mean-force", "1",
       "beyond jamming the B0 maximum lies at a force threshold slightly larger than the average contact force",
       _b0_maximum_criterion, paper={HERTZ_3D: PAPER_CLUSTER_SIZE_PEAK[HERTZ_3D]})
def b0_maximum_above_mean_force(system: SystemData, tolerances: ClaimTolerances) -> Judgement:
    """Judge of claim p1-1-b0-maximum-above-mean-force (per system): P1 §1's "slightly larger" read as above 1 by
    at most two of P1's threshold steps (0.25) in 2D; in 3D against P1's own 3D statement (§4.2: "in the 3D system
    the largest values ... are observed for F_th ≈ 2.0", the 3D networks holding more clusters of large forces),
    within one threshold step of P1's (0.25)."""
    median, best = _b0_maximum_threshold(system)
    evidence = (f"F_th of the largest B0/N at each rho beyond rho_J: {fmt_values(best)}; median {median:.3g} "
                f"({system.label()})")
    if system.dimension == 3:
        paper = PAPER_CLUSTER_SIZE_PEAK[HERTZ_3D]
        distance = abs(median - paper)
        return Judgement(median, f"{evidence}; P1 (3D) ~ {paper:g}",
                         bool(distance <= tolerances.threshold_tolerance + 1e-12),
                         margin=relative_margin(distance, tolerances.threshold_tolerance))
    upper = 1.0 + 2 * tolerances.threshold_tolerance
    return Judgement(median, evidence, bool(1.0 < median <= upper + 1e-12),
                     margin=smallest_margin(relative_margin(median, 1.0), relative_margin(median, upper)))


@claim("p1-5.1-b0-interior-maximum", "5.1",
       "beyond jamming B0/N first grows with F_th, then falls as F_th -> max (arrows of Fig. 6)",
       "median over rho > rho_J + tol of the F_th maximising mean B0/N lies strictly inside the F_th grid")
def b0_interior_maximum(system: SystemData, tolerances: ClaimTolerances) -> Judgement:
    """Judge of claim p1-5.1-b0-interior-maximum (per system)."""
    median, best = _b0_maximum_threshold(system)
    lo, hi = system.thresholds.min(), system.thresholds.max()
    holds = lo < median < hi
    evidence = (f"F_th of the largest B0/N at each rho beyond rho_J: {fmt_values(best)}; grid "
                f"[{lo:.3g}, {hi:.3g}] ({system.label()})")
    edge = min(abs(median - lo), abs(hi - median))  # how far inside the grid, as a share of its span
    step = float(np.median(np.diff(system.thresholds))) if system.thresholds.size > 1 else 0.0
    return Judgement(median, evidence, bool(holds), margin=edge / (hi - lo) if hi > lo else math.nan,
                     grid_step=bool(holds and edge <= step + 1e-12))


@claim("p1-5.1-b1-zero-below", "5.1", "no loops below jamming: B1 = 0 for rho < rho_J (Fig. 7)",
       "max over {below_cut} of the mean (over realizations) of max over F_th of B1/N <= "
       "{negligible_fraction} x its maximum")
def b1_zero_below(system: SystemData, tolerances: ClaimTolerances) -> Judgement:
    """Judge of claim p1-5.1-b1-zero-below (per system)."""
    return zero_below(betti_curve(system, 1), system, tolerances, "B1/N")


@claim("p1-5.1-b1-rises", "5.1", "beyond jamming B1/N starts to rise (Fig. 7)",
       "max of B1/N (max over F_th) over rho > rho_J + tol minus its value at the last state below jamming "
       "({below_cut}) > {negligible_fraction} x its maximum")
def b1_rises(system: SystemData, tolerances: ClaimTolerances) -> Judgement:
    """Judge of claim p1-5.1-b1-rises (per system): the rise from the last state below jamming (`SystemData.below`,
    the last unjammed state), not from a state the jump of Z has already jammed."""
    curve = np.asarray(betti_curve(system, 1).values, dtype=float)
    beyond = require(system.beyond, "rho beyond rho_J")
    below = require(system.below, f"states below jamming ({system.below_text})")
    start = float(curve[np.flatnonzero(below)[-1]])
    rise = finite_max(curve[beyond]) - start
    limit = tolerances.negligible_fraction * finite_max(curve)
    evidence = (f"B1/N {fmt_values(curve)} at rho {fmt_values(system.rho)} ({system.label()}); rise {rise:.3g} from "
                f"rho={system.rho[below][-1]:.3f}")
    return Judgement(rise, evidence, bool(rise > limit), margin=relative_margin(rise, limit))


@claim("p1-5.1-b1-plateau", "5.1", "B1/N plateaus for rho close to rho_max (Fig. 7)",
       "B1/N (max over F_th) changes over [rho_max - window, rho_max] by <= {plateau_fraction} of its rise from "
       "its minimum to rho_max; the window must lie beyond rho_J + tol")
def b1_plateau(system: SystemData, tolerances: ClaimTolerances) -> Judgement:
    """Judge of claim p1-5.1-b1-plateau (per system)."""
    if not np.isfinite(system.rho_max):
        raise NotEvaluated("rho_max undefined")
    start = system.rho_max - system.window
    if start < system.rho_j + system.tolerance - 1e-12:
        raise NotEvaluated(f"rho_max={system.rho_max:.3f} is within tol + window of {system.label()}")
    curve = betti_curve(system, 1, full=True)
    shown = curve.isel(rho=np.flatnonzero(rho_values(curve) <= system.rho_max + 1e-12))
    top = interp_at(shown, system.rho_max)
    change, rise = top - interp_at(shown, start), top - finite_min(shown.values)
    if not np.isfinite(rise) or rise <= 0:
        return Judgement(math.nan, f"B1/N does not rise up to rho_max ({fmt_values(shown.values)})", False)
    relative = change / rise
    evidence = (f"B1/N {top:.3g} at rho_max={system.rho_max:.3f}, {top - change:.3g} at {start:.3f}; rise {rise:.3g}"
                f" ({system.label()})")
    return Judgement(relative, evidence, abs(relative) <= tolerances.plateau_fraction,
                     margin=relative_margin(abs(relative), tolerances.plateau_fraction))


@claim("p1-5.1-b1-larger-in-3d", "5.1", "the only visible difference in B1/N: larger magnitude in 3D (Fig. 7)",
       "max over rho of B1/N (max over F_th): 3D > each 2D system", per_system=False)
def b1_larger_in_3d(context: ClaimContext) -> Judgement:
    """Judge of claim p1-5.1-b1-larger-in-3d (across systems)."""
    three = finite_max(betti_curve(context.role(HERTZ_3D), 1).values)
    two = {context.role(r).name: finite_max(betti_curve(context.role(r), 1).values) for r in ALL_2D}
    largest = max(two.values())
    evidence = f"max B1/N: 3D {three:.3g}; " + ", ".join(f"{n} {v:.3g}" for n, v in two.items())
    return Judgement(three / largest if largest > 0 else math.inf, evidence, three > largest,
                     margin=contrast_margin(three, largest))


def _claim_absent_then_growing(section: str, quantity: str, curve: Callable[[SystemData], xr.DataArray],
                               absent: tuple[str, str, str], growing: tuple[str, str, str]) -> None:
    """Register P1's pair of claims about a quantity only 3D networks have (B2, TP2): `absent` below ρ_J and
    `growing` monotonically beyond it, each (id, statement, criterion), judged on `curve(system)` (realization mean
    of `quantity` versus ρ) of the 3D system."""
    def vanishes(system: SystemData, tolerances: ClaimTolerances) -> Judgement:
        """`quantity` ≈ 0 below ρ_J (`zero_below`)."""
        return zero_below(curve(system), system, tolerances, quantity)

    def grows(system: SystemData, tolerances: ClaimTolerances) -> Judgement:
        """`quantity` grows monotonically beyond ρ_J (`grows_beyond`)."""
        return grows_beyond(curve(system), system, tolerances, quantity)

    claim(absent[0], section, absent[1], absent[2], scope=(HERTZ_3D,))(vanishes)
    claim(growing[0], section, growing[1], growing[2], scope=(HERTZ_3D,))(grows)


_claim_absent_then_growing(
    "5.1", "B2/N", lambda system: betti_curve(system, 2),
    ("p1-5.1-b2-zero-below", "in 3D B2 vanishes for rho < rho_J",
     "max over {below_cut} of the mean of max over F_th of B2/N <= {negligible_fraction} x its maximum"),
    ("p1-5.1-b2-grows", "in 3D B2 grows monotonically as rho increases beyond rho_J",
     "B2/N (max over F_th) over rho >= rho_J - tol rises by > {negligible_fraction} of its maximum, never drops "
     "between consecutive rho by more than {monotone_tolerance} of it, and is > 0 at every rho > rho_J + tol"))


# --- §5.2 Shape of the clusters ----------------------------------------------------------------------------------
def _shape(system: SystemData, rho_mask: np.ndarray, threshold_mask: np.ndarray, what: str) -> np.ndarray:
    """The nonzero S_p (P1's averaging rule) in the selected (ρ, F_th) cells."""
    shape, _ = system.shape_average()
    values = shape.transpose("rho", "threshold").values[np.ix_(rho_mask, threshold_mask)]
    values = values[np.isfinite(values) & (values != 0)]
    if values.size == 0:
        raise NotEvaluated(f"no clusters ({what}) in {system.name}")
    return values


def _small_thresholds(system: SystemData) -> np.ndarray:
    """Mask of F_th < 2 (below twice the mean force, P1 §5.2), (n_threshold,)."""
    return system.thresholds < P1_LARGE_THRESHOLD - 1e-12


def _large_thresholds(system: SystemData) -> np.ndarray:
    """Mask of F_th > 2 (P1 §5.2's large thresholds), (n_threshold,)."""
    return system.thresholds > P1_LARGE_THRESHOLD + 1e-12


@claim("p1-5.2-shape-open-paths-below-jamming", "5.2",
       "in 2D below jamming S_p ~ 1 for both laws: the clusters are open paths (Figs. 8, 9)",
       "|median of the nonzero S_p over {below_cut}, all F_th - 1| <= {unity_tolerance}", scope=ALL_2D)
def shape_open_paths_below(system: SystemData, tolerances: ClaimTolerances) -> Judgement:
    """Judge of claim p1-5.2-shape-open-paths-below-jamming (per system)."""
    below = require(system.below, "rho below rho_J")
    values = _shape(system, below, np.ones(system.thresholds.size, bool), "below rho_J")
    median = float(np.median(values))
    evidence = f"S_p below rho_J over {values.size} cells: median {median:.3g}, range [{values.min():.3g}, " \
               f"{values.max():.3g}] ({system.label()})"
    return Judgement(median, evidence, abs(median - 1) <= tolerances.unity_tolerance,
                     margin=relative_margin(abs(median - 1), tolerances.unity_tolerance), states=system.states(below))


def _mean_shape(system: SystemData, rho_mask: np.ndarray, what: str) -> float:
    """Mean of the nonzero S_p over the ρ of `rho_mask` and F_th < 2."""
    return float(np.mean(_shape(system, rho_mask, _small_thresholds(system), what)))


@claim("p1-5.2-shape-linear-above-hertz-below-jamming", "5.2",
       "below jamming S_p is consistently larger for the linear law than for the non-linear one, in particular "
       "at smaller F_th (Fig. 9a, b)",
       "mean nonzero S_p over {below_cut} and F_th < 2: 2D linear > 2D Hertz", per_system=False)
def shape_linear_above_hertz_below(context: ClaimContext) -> Judgement:
    """Judge of claim p1-5.2-shape-linear-above-hertz-below-jamming (across systems)."""
    linear, hertz = context.role(LINEAR_2D), context.role(HERTZ_2D)
    a = _mean_shape(linear, require(linear.below, "rho below rho_J (2D linear)"), "below rho_J, F_th < 2")
    b = _mean_shape(hertz, require(hertz.below, "rho below rho_J (2D Hertz)"), "below rho_J, F_th < 2")
    return Judgement(a - b, f"mean S_p below rho_J, F_th < 2: 2D linear {a:.3g}, 2D Hertz {b:.3g}", a > b,
                     margin=contrast_margin(a, b),
                     states=f"{linear.name} {linear.states(linear.below)}; {hertz.name} {hertz.states(hertz.below)}")


@claim("p1-5.2-shape-open-paths-large-threshold", "5.2",
       "beyond jamming, for large F_th (> 2) S_p ~ 1 in every system: open paths (also 3D and §5.2 summary)",
       "|median of the nonzero S_p over rho > rho_J + tol and F_th > 2 - 1| <= {unity_tolerance}")
def shape_open_paths_large_threshold(system: SystemData, tolerances: ClaimTolerances) -> Judgement:
    """Judge of claim p1-5.2-shape-open-paths-large-threshold (per system)."""
    values = _shape(system, require(system.beyond, "rho beyond rho_J"), _large_thresholds(system),
                    "beyond rho_J, F_th > 2")
    median = float(np.median(values))
    evidence = f"S_p beyond rho_J at F_th > 2 over {values.size} cells: median {median:.3g}, range " \
               f"[{values.min():.3g}, {values.max():.3g}] ({system.label()})"
    return Judgement(median, evidence, abs(median - 1) <= tolerances.unity_tolerance,
                     margin=relative_margin(abs(median - 1), tolerances.unity_tolerance))


def _jammed_shapes(context: ClaimContext, *roles) -> dict[str, float]:
    """{system name: mean nonzero S_p over ρ > ρ_J + tol and F_th < 2} for the systems of `roles`."""
    means = {}
    for role in roles:
        system = context.role(role)
        means[system.name] = _mean_shape(system, require(system.beyond, f"rho beyond rho_J ({system.name})"),
                                         "beyond rho_J, F_th < 2")
    return means


@claim("p1-5.2-shape-linear-above-hertz", "5.2",
       "beyond jamming, for F_th around the mean force, S_p is significantly larger for the linear law than the "
       "non-linear one in 2D: more complex clusters",
       "mean nonzero S_p over rho > rho_J + tol and F_th < 2: 2D linear - 2D Hertz >= {shape_difference}",
       per_system=False)
def shape_linear_above_hertz(context: ClaimContext) -> Judgement:
    """Judge of claim p1-5.2-shape-linear-above-hertz (across systems)."""
    means = _jammed_shapes(context, LINEAR_2D, HERTZ_2D)
    (linear, a), (hertz, b) = means.items()
    return Judgement(a - b, f"mean S_p beyond rho_J, F_th < 2: {linear} {a:.3g}, {hertz} {b:.3g}",
                     a - b >= context.tolerances.shape_difference,
                     margin=relative_margin(a - b, context.tolerances.shape_difference))


@claim("p1-5.2-shape-3d-above-2d-hertz", "5.2",
       "3D clusters are more complex than 2D non-linear ones, but less than geometry suggests (S_p bounds 7 vs 4)",
       "mean nonzero S_p over rho > rho_J + tol and F_th < 2: 3D > 2D Hertz, and 3D / 2D Hertz < 7/4",
       per_system=False)
def shape_3d_above_2d_hertz(context: ClaimContext) -> Judgement:
    """Judge of claim p1-5.2-shape-3d-above-2d-hertz (across systems)."""
    means = _jammed_shapes(context, HERTZ_3D, HERTZ_2D)
    (three, a), (two, b) = means.items()
    bound = P1_SHAPE_BOUNDS[3] / P1_SHAPE_BOUNDS[2]
    return Judgement(a - b, f"mean S_p beyond rho_J, F_th < 2: {three} {a:.3g}, {two} {b:.3g}; ratio {a / b:.3g} "
                            f"(geometric {bound:.3g})", bool(b < a < bound * b),
                     margin=smallest_margin(contrast_margin(a, b), relative_margin(a / b, bound)))


@claim("p1-5.2-shape-linear-above-3d", "5.2",
       "for F_th below twice the mean force the non-linear systems, whatever the dimension, hold less complex "
       "clusters than the linear one (§5.2 summary)",
       "mean nonzero S_p over rho > rho_J + tol and F_th < 2: 2D linear > 3D", per_system=False)
def shape_linear_above_3d(context: ClaimContext) -> Judgement:
    """Judge of claim p1-5.2-shape-linear-above-3d (across systems)."""
    means = _jammed_shapes(context, LINEAR_2D, HERTZ_3D)
    (linear, a), (three, b) = means.items()
    return Judgement(a - b, f"mean S_p beyond rho_J, F_th < 2: {linear} {a:.3g}, {three} {b:.3g}", a > b,
                     margin=contrast_margin(a, b))


def _relative_shape_spread(system: SystemData) -> float:
    """Mean over ρ > ρ_J + tol and F_th < 1 of (spread over realizations / S_p) of one system."""
    shape, spread = system.shape_average()
    beyond = require(system.beyond, f"rho beyond rho_J ({system.name})")
    small = system.thresholds < 1.0
    s = shape.transpose("rho", "threshold").values[np.ix_(beyond, small)]
    d = spread.transpose("rho", "threshold").values[np.ix_(beyond, small)]
    ok = np.isfinite(s) & (s != 0)
    if not ok.any():
        raise NotEvaluated(f"no clusters at F_th < 1 beyond rho_J in {system.name}")
    return float(np.mean(d[ok] / s[ok]))


@claim("p1-5.2-shape-noisier-in-3d", "5.2", "S_p is noisier in 3D, particularly for small F_th",
       "mean over rho > rho_J + tol and F_th < 1 of (spread over realizations / S_p): 3D > 2D Hertz",
       per_system=False)
def shape_noisier_in_3d(context: ClaimContext) -> Judgement:
    """Judge of claim p1-5.2-shape-noisier-in-3d (across systems)."""
    compared = context.role(HERTZ_3D), context.role(HERTZ_2D)
    if min(s.data.sizes.get("realization", 1) for s in compared) < 2:
        raise NotEvaluated("needs at least 2 realizations of each")
    three, two = (_relative_shape_spread(s) for s in compared)
    return Judgement(three / two if two > 0 else math.inf,
                     f"relative spread of S_p at F_th < 1 beyond rho_J: 3D {three:.3g}, 2D Hertz {two:.3g}",
                     three > two, margin=contrast_margin(three, two))


@claim("p1-5.2-shape-bounds", "5.2",
       "S_p lies in [0.5, 4] in 2D and [0.5, 7] in 3D (open paths >= 0.5, bound from the largest contact number)",
       "every nonzero S_p (P1's averaging rule) within those bounds", needs_rho_j=False)
def shape_bounds(system: SystemData, tolerances: ClaimTolerances) -> Judgement:
    """Judge of claim p1-5.2-shape-bounds (per system)."""
    every = np.ones(system.rho.size, bool), np.ones(system.thresholds.size, bool)
    values = _shape(system, *every, "any rho")
    upper = P1_SHAPE_BOUNDS.get(system.dimension, math.nan)
    holds = values.min() >= P1_OPEN_PATH_MIN - 1e-12 and values.max() <= upper + 1e-12
    return Judgement(float(values.max()), f"S_p in [{values.min():.3g}, {values.max():.3g}] over {values.size} "
                                          f"cells; bounds [{P1_OPEN_PATH_MIN}, {upper:g}] ({system.name})", bool(holds),
                     # a two-particle path has S_p = 0.5 exactly: the lower bound is met by construction and
                     # decides only when broken; the upper bound (from the largest contact number) gives the margin
                     margin=(relative_margin(values.max(), upper) if values.min() >= P1_OPEN_PATH_MIN - 1e-12
                             else relative_margin(values.min(), P1_OPEN_PATH_MIN)))


# --- §5.3 Persistence diagrams and total persistence ----------------------------------------------------------
@claim("p1-5.3-rough-similar-near-jamming", "5.3",
       "near jamming the roughness (rough-bin N0/N) is very similar for all systems (Fig. 11a, b)",
       "mean rough-bin N0/N at rho_J (interpolated): largest / smallest over the systems <= {similar_ratio}",
       per_system=False)
def rough_similar_near_jamming(context: ClaimContext) -> Judgement:
    """Judge of claim p1-5.3-rough-similar-near-jamming (across systems)."""
    values = {name: interp_at(bin_curve(system, "rough"), system.rho_j) for name, system in context.own.items()
              if np.isfinite(system.rho_j)}
    values = {name: value for name, value in values.items() if np.isfinite(value)}
    if len(values) < 2:
        raise NotEvaluated("fewer than 2 systems with rho_J and rough-bin counts")
    ratio = max(values.values()) / min(values.values()) if min(values.values()) > 0 else math.inf
    evidence = "rough N0/N at rho_J: " + ", ".join(f"{n} {v:.3g}" for n, v in values.items())
    return Judgement(ratio, evidence, ratio <= context.tolerances.similar_ratio,
                     margin=ratio_margin(ratio, context.tolerances.similar_ratio))


def _fewer_for_nonlinear(context: ClaimContext, bin_name: str) -> Judgement:
    """P1: the non-linear systems have fewer `bin_name`-bin points (mean N0/N beyond ρ_J below 2D linear's)."""
    def jammed_mean(system: SystemData) -> float:
        """Mean over ρ > ρ_J + tol of the system's N0/N in the bin."""
        beyond = require(system.beyond, f"rho beyond rho_J ({system.name})")
        return float(np.nanmean(finite_values(bin_curve(system, bin_name).values[beyond], f"{bin_name} N0/N")))

    linear = jammed_mean(context.role(LINEAR_2D))
    others = {system.name: jammed_mean(system) for system in context.nonlinear()}
    evidence = (f"mean {bin_name} N0/N beyond rho_J: 2D linear {linear:.3g}; "
                + ", ".join(f"{n} {v:.3g}" for n, v in others.items()))
    return Judgement(max(others.values()) / linear if linear > 0 else math.inf, evidence,
                     max(others.values()) < linear, margin=contrast_margin(max(others.values()), linear))


@claim("p1-5.3-rough-fewer-nonlinear", "5.3", "the non-linear systems have fewer rough-bin points (Fig. 11a, b)",
       "mean rough-bin N0/N over rho > rho_J + tol: every non-linear system < 2D linear", per_system=False)
def rough_fewer_nonlinear(context: ClaimContext) -> Judgement:
    """Judge of claim p1-5.3-rough-fewer-nonlinear (across systems)."""
    return _fewer_for_nonlinear(context, "rough")


@claim("p1-5.3-medium-fewer-nonlinear", "5.3", "the non-linear systems have fewer medium-bin points (Fig. 11e, f)",
       "mean medium-bin N0/N over rho > rho_J + tol: every non-linear system < 2D linear", per_system=False)
def medium_fewer_nonlinear(context: ClaimContext) -> Judgement:
    """Judge of claim p1-5.3-medium-fewer-nonlinear (across systems)."""
    return _fewer_for_nonlinear(context, "medium")


@claim("p1-5.3-medium-jump", "5.3", "the medium-bin N0/N increases suddenly beyond jamming (Fig. 11e, f)",
       "medium N0/N at the first rho > rho_J + tol >= {jump_factor} x its value at the last state below jamming "
       "({below_cut}), and > 0")
def medium_jump(system: SystemData, tolerances: ClaimTolerances) -> Judgement:
    """Judge of claim p1-5.3-medium-jump (per system): from the last state below jamming (`SystemData.below`, the
    last unjammed state) to the first beyond ρ_J + tol."""
    curve = bin_curve(system, "medium").values
    below = require(system.below, f"states below jamming ({system.below_text})")
    before = curve[np.flatnonzero(below)[-1]]
    after = curve[np.flatnonzero(require(system.beyond, "rho beyond rho_J"))[0]]
    if not (np.isfinite(before) and np.isfinite(after)):
        raise NotEvaluated("medium-bin count NaN next to rho_J")
    ratio = after / before if before > 0 else (math.inf if after > 0 else math.nan)
    evidence = (f"medium N0/N {fmt_values(curve)} at rho {fmt_values(system.rho)} ({system.label()}): "
                f"{before:.3g} -> {after:.3g}")
    return Judgement(ratio, evidence, bool(after > 0 and after >= tolerances.jump_factor * before),
                     margin=ratio_margin(ratio, tolerances.jump_factor))


def _bin_peak(system: SystemData, tolerances: ClaimTolerances, bin_name: str, nonlinear: bool) -> Judgement:
    """The peak of a persistence bin's N0/N(ρ) near ρ_J, expected for the non-linear laws if `nonlinear`,
    else for the linear law."""
    expected = expected_for_law(system, nonlinear)
    curve = bin_curve(system, bin_name).values
    return peak_verdict(find_peak(curve, system.rho, system.rho_j, system.tolerance, finite_max(curve)),
                         f"{bin_name}-bin N0/N", system, tolerances, expected)


@claim("p1-5.3-strong-peak-linear-only", "5.3",
       "the strong-bin N0/N peaks during jamming for the 2D linear law only; the non-linear systems stay high "
       "beyond jamming (Fig. 11g, h)",
       "the maximum of strong-bin N0/N(rho) lies within tol of rho_J with prominence >= {min_prominence} of it; "
       "present for linear, absent for Hertz")
def strong_peak_linear_only(system: SystemData, tolerances: ClaimTolerances) -> Judgement:
    """Judge of claim p1-5.3-strong-peak-linear-only (per system)."""
    return _bin_peak(system, tolerances, "strong", nonlinear=False)


def _weak_peak_on(system: SystemData, scale: float) -> tuple[float, str]:
    """The weak-bin N0/N peak near ρ_J of `system` on the shared `scale` (`_on_one_scale`)."""
    peak = peak_near(bin_curve(system, "weak").values, system.rho, system.rho_j, system.tolerance)
    return _on_one_scale(system, peak, scale, "weak-bin points")


@claim("p1-5.3-weak-peak-nonlinear-only", "5.3",
       "the weak-bin N0/N shows a pronounced peak around jamming for the non-linear law, not for the linear one "
       "(Fig. 11c: both 2D laws on one panel)",
       "prominence of the weak-bin N0/N peak within tol of rho_J, on one scale (the larger maximum of the two 2D "
       "curves): 2D Hertz >= {min_prominence}, 2D linear < {min_prominence}", per_system=False)
def weak_peak_nonlinear_only(context: ClaimContext) -> Judgement:
    """Judge of claim p1-5.3-weak-peak-nonlinear-only (across the 2D systems, one scale)."""
    hertz_system, linear_system = context.role(HERTZ_2D), context.role(LINEAR_2D)
    scale = max(finite_max(bin_curve(hertz_system, "weak").values), finite_max(bin_curve(linear_system, "weak").values))
    if not np.isfinite(scale) or scale <= 0:
        raise NotEvaluated("no weak-bin points in either 2D system")
    hertz, hertz_text = _weak_peak_on(hertz_system, scale)
    linear, linear_text = _weak_peak_on(linear_system, scale)
    threshold = context.tolerances.min_prominence
    return Judgement(hertz - linear, f"weak-bin peak prominence on one scale ({scale:.3g}): {hertz_text}; "
                                     f"{linear_text}", hertz >= threshold > linear,
                     margin=smallest_margin(relative_margin(hertz, threshold), relative_margin(linear, threshold)))


@claim("p1-5.3-weak-peak-3d", "5.3",
       "in 3D the weak-bin N0/N also peaks around jamming (Fig. 11d, its own panel)",
       "the maximum of weak-bin N0/N(rho) lies within tol of rho_J with prominence >= {min_prominence} of it",
       scope=(HERTZ_3D,))
def weak_peak_3d(system: SystemData, tolerances: ClaimTolerances) -> Judgement:
    """Judge of claim p1-5.3-weak-peak-3d (per system)."""
    return _bin_peak(system, tolerances, "weak", nonlinear=True)


@claim("p1-5.3-linear-medium-over-strong", "5.3",
       "for the linear law beyond jamming most clusters remain in the medium bin (Fig. 11e)",
       "mean over rho > rho_J + tol: medium-bin N0/N > strong-bin N0/N", scope=(LINEAR_2D,))
def linear_medium_over_strong(system: SystemData, tolerances: ClaimTolerances) -> Judgement:
    """Judge of claim p1-5.3-linear-medium-over-strong (per system)."""
    beyond = require(system.beyond, "rho beyond rho_J")
    medium = float(np.nanmean(finite_values(bin_curve(system, "medium").values[beyond], "medium N0/N")))
    strong = float(np.nanmean(finite_values(bin_curve(system, "strong").values[beyond], "strong N0/N")))
    return Judgement(medium / strong if strong > 0 else math.inf,
                     f"mean N0/N beyond rho_J: medium {medium:.3g}, strong {strong:.3g} ({system.label()})",
                     medium > strong, margin=contrast_margin(medium, strong))


@claim("p1-5.3-weak-peak-at-ridge", "5.3",
       "(conjecture) the B0/N ridge is formed by weak interactions: the weak-bin peak sits at the ridge",
       "|rho of the weak-bin N0/N peak - rho of the B0/N ridge peak (F_th < 0.5)| <= tol, both the highest point "
       "within tol of rho_J with prominence >= {min_prominence} of its own height; judged where both are found",
       scope=(HERTZ_2D, HERTZ_3D))
def weak_peak_at_ridge(system: SystemData, tolerances: ClaimTolerances) -> Judgement:
    """Judge of claim p1-5.3-weak-peak-at-ridge (per system). P1's conjecture ties the ridge to the weak-bin peak
    "around jamming", so both peaks are found as p1-5.3-weak-peak-nonlinear-only and p1-5.1-b0-ridge find them
    (`peak_near`), not as the curve's global maximum, which below jamming can sit on a few stray points."""
    weak = peak_near(bin_curve(system, "weak").values, system.rho, system.rho_j, system.tolerance)
    ridge = _ridge(system)
    found = [p for p in (weak, ridge[0] if ridge else None)
             if p is not None and p.relative_prominence >= tolerances.min_prominence]
    if len(found) < 2:
        raise NotEvaluated("the weak-bin peak or the B0/N ridge is not found near rho_J")
    distance = abs(found[0].rho - found[1].rho)
    return Judgement(distance, f"weak-bin peak at rho={found[0].rho:.3f}, B0/N ridge at rho={found[1].rho:.3f} "
                               f"(tolerance {system.tolerance:.3g})", distance <= system.tolerance + 1e-12,
                     margin=relative_margin(distance, system.tolerance),
                     grid_step=bool(abs(distance - system.tolerance) < system.step - 1e-12))


def _persistence_rise(system: SystemData, k: int) -> float:
    """Rise of the mean TP_k/N over ρ_J ± window (interpolated, clipped to the sampled ρ)."""
    curve = persistence_curve(system, k)
    return interp_at(curve, system.rho_j + system.window) - interp_at(curve, system.rho_j - system.window)


def _steeper_in_3d(context: ClaimContext, k: int) -> Judgement:
    """P1: TP_k rises much more close to ρ_J in 3D (3D rise over ρ_J ± window against the larger 2D rise)."""
    three = _persistence_rise(context.role(HERTZ_3D), k)
    two = {context.role(r).name: _persistence_rise(context.role(r), k) for r in ALL_2D}
    largest = max(two.values())
    ratio = three / largest if largest > 0 else math.inf
    evidence = (f"rise of TP{k}/N over rho_J +- window: 3D {three:.3g}; "
                + ", ".join(f"{n} {v:.3g}" for n, v in two.items()))
    return Judgement(ratio, evidence, bool(three > 0 and three >= context.tolerances.steeper_factor * largest),
                     margin=ratio_margin(ratio, context.tolerances.steeper_factor))


@claim("p1-5.3-tp0-steeper-in-3d", "5.3", "TP0 increases much more prominently close to rho_J in 3D than in 2D "
       "(Fig. 12)", "rise of mean TP0/N over rho_J +- window: 3D >= {steeper_factor} x the larger 2D rise",
       per_system=False)
def tp0_steeper_in_3d(context: ClaimContext) -> Judgement:
    """Judge of claim p1-5.3-tp0-steeper-in-3d (across systems)."""
    return _steeper_in_3d(context, 0)


@claim("p1-5.3-tp1-steeper-in-3d", "5.3", "TP1 increases much more prominently close to rho_J in 3D than in 2D "
       "(Fig. 12)", "rise of mean TP1/N over rho_J +- window: 3D >= {steeper_factor} x the larger 2D rise",
       per_system=False)
def tp1_steeper_in_3d(context: ClaimContext) -> Judgement:
    """Judge of claim p1-5.3-tp1-steeper-in-3d (across systems)."""
    return _steeper_in_3d(context, 1)


_claim_absent_then_growing(
    "5.3", "TP2/N", lambda system: persistence_curve(system, 2),
    ("p1-5.3-tp2-zero-below", "in 3D TP2 ~ 0 for rho < rho_J",
     "max over {below_cut} of mean TP2/N <= {negligible_fraction} x its maximum"),
    ("p1-5.3-tp2-grows", "in 3D TP2 increases monotonically for rho > rho_J",
     "mean TP2/N over rho >= rho_J - tol rises by > {negligible_fraction} of its maximum, never drops between "
     "consecutive rho by more than {monotone_tolerance} of it, and is > 0 at every rho > rho_J + tol"))
