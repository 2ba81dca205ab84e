"""P2's claims about friction (§IV C, Fig. 9) and its conclusions (§V): the second half of `CLAIMS`, in the order of
the table, after `forcenet.report.p2_claims` (§III D, §IV A, §IV B); judged the same way, on the realization-mean
distance curves of the frictional and the frictionless system (`forcenet.report.p2_judging.Context`)."""
from __future__ import annotations

import math
from typing import Callable

import numpy as np
import pandas as pd

from forcenet.report.claims import (Claim, ClaimTolerances, Judgement, NotEvaluated, claim_register,
                                    contrast_margin, ratio_margin, relative_margin, smallest_margin)
from forcenet.report.p2 import (METRIC_SYMBOLS, METRICS, P2_HOMOLOGY_DIMS, diagram_point_counts,
                                jamming_density_per_realization)
from forcenet.report.p2_judging import (B, NORMAL, W1, W2, Context, Curves, fmt, median_quotient, on_grid,
                                        per_metric_text, rate_quotient, within_factor, within_factor_margin)
from forcenet.report.realizations import realization_mean


CLAIMS: list[Claim] = []  # in the order of the table, after forcenet.report.p2_claims.CLAIMS
claim = claim_register(CLAIMS)


@claim("IV.C-1", "§IV C, Fig. 9",
       "The frictionless system jams at larger rho",
       lambda t: "rho where the mean Z reaches d+1 is larger for mu = 0",
       paper="rho_J(mu=0) > rho_J(mu=0.5)", scope="both")
def _c_jams_later(ctx: Context) -> Judgement:
    """Judge of claim IV.C-1 by its criterion."""
    f, n = ctx.both()
    rf, rn = f.jammed(), n.jammed()
    pf = jamming_density_per_realization(f.ds, f.dimension)
    pn = jamming_density_per_realization(n.ds, n.dimension)
    spread = (f"per realization {ctx.frictional} [{fmt(np.nanmin(pf))}, {fmt(np.nanmax(pf))}], "
              f"{ctx.frictionless} [{fmt(np.nanmin(pn))}, {fmt(np.nanmax(pn))}]")
    return Judgement(rn - rf, f"rho_J (mean Z = d+1): {ctx.frictional} {fmt(rf)}, {ctx.frictionless} {fmt(rn)}; "
                              f"{spread}", rn > rf, grid_step=f.by_one_step(rn - rf, 0.0))


def _peak_quotient(ctx: Context, dim: int, bounds: Callable[[Curves], tuple[float, float]], *,
                   numerator: str) -> dict[str, float]:
    """{metric: largest value of one system's curve / largest value of the other's} (normal forces, PD_dim), each
    over its own closed rho range ``bounds(curves)``; `numerator` is ``"frictional"`` or ``"frictionless"``."""
    f, n = ctx.both()
    quotient = {}
    for m in METRICS:
        peak_f, peak_n = (c.window(c.mean(NORMAL, dim, m), *bounds(c), closed_hi=True).max() for c in (f, n))
        what = f"beta{dim} {METRIC_SYMBOLS[m]} peaks of both systems"
        quotient[m] = (rate_quotient(peak_f, peak_n, what) if numerator == "frictional"
                       else rate_quotient(peak_n, peak_f, what))
    return quotient


@claim("IV.C-2", "§IV C, Fig. 9(a)",
       "For rho < 0.65, d_B and d_W2 (beta0) are about the same with and without friction; d_W1 is ≈ 40 % smaller "
       "for mu = 0",
       lambda t: f"ratios of medians within a factor {t.value_factor} of 1 (d_B, d_W2) and 0.6 (d_W1)",
       paper="mu=0/mu=0.5: 1, 1, 0.6", scope="both")
def _c_low_density(ctx: Context) -> Judgement:
    """Judge of claim IV.C-2 by its criterion."""
    ratio = median_quotient(ctx, 0, METRICS, hi=0.65)
    tol = ctx.tol.value_factor
    ok = within_factor(ratio[B], 1.0, tol) and within_factor(ratio[W2], 1.0, tol) and within_factor(ratio[W1], 0.6, tol)
    margin = smallest_margin(within_factor_margin(ratio[B], 1.0, tol), within_factor_margin(ratio[W2], 1.0, tol),
                             within_factor_margin(ratio[W1], 0.6, tol))
    return Judgement(ratio[W1], f"median over rho < 0.65, mu=0 / mu=0.5 (beta0): {per_metric_text(ratio)}", ok,
                     margin=margin)


def _shifted_comparison(ctx: Context, dim: int, denominator: str) -> tuple[np.ndarray, np.ndarray]:
    """mu = 0 ratio and the mu = 0.5 ratio interpolated at the same rho - rho_J."""
    f, n = ctx.both()
    rf, rn = f.jammed(), n.jammed()
    sf, sn = (c.window(c.ratio(NORMAL, dim, denominator)) for c in (f, n))
    sf = pd.Series(sf.values, index=sf.index.values - rf)
    x = sn.index.values - rn
    other = on_grid(sf, x)
    ok = np.isfinite(other) & (other > 0)
    if ok.sum() < ctx.tol.min_points:
        raise NotEvaluated("the two systems' rho - rho_J ranges overlap at too few points")
    return sn.values[ok], other[ok]


@claim("IV.C-3", "§IV C, Figs 7(a), 10(a)",
       "At equal rho - rho_J, d_B/d_W1 (beta0) is consistently larger for mu = 0 while d_B/d_W2 is roughly "
       "the same",
       lambda t: (f"mu=0 ratio larger at >= {100 * t.consistently:.0f} % of the points; median d_B/d_W2 quotient "
                  f"within a factor {t.value_factor} of 1"),
       paper="larger / same", scope="both")
def _c_ratios_adjusted(ctx: Context) -> Judgement:
    """Judge of claim IV.C-3 by its criterion."""
    mu0, mu05 = _shifted_comparison(ctx, 0, W1)
    larger = float(np.mean(mu0 > mu05))
    a, b = _shifted_comparison(ctx, 0, W2)
    same = 10 ** float(np.median(np.log10(a / b)))
    ok = larger >= ctx.tol.consistently and within_factor(same, 1.0, ctx.tol.value_factor)
    return Judgement(larger, f"at equal rho - rho_J (beta0): d_B/d_W1 larger for mu=0 at {fmt(100 * larger, 2)} % of "
                             f"{len(mu0)} points; median (d_B/d_W2 at mu=0) / (at mu=0.5) = {fmt(same, 2)}", ok,
                     margin=smallest_margin(relative_margin(larger, ctx.tol.consistently),
                                            within_factor_margin(same, 1.0, ctx.tol.value_factor)))


@claim("IV.C-4", "§IV C, Figs 6(a), 9(a)",
       "d_B and d_W2 (beta0) begin slowing down at a much lower rho relative to rho_J in the frictional system",
       lambda t: ("argmax(rho) - rho_J of mean d_B and d_W2 smaller for mu = 0.5 than for mu = 0; marginal where the "
                  "lead lies within two sampling steps"),
       paper="earlier peak with friction", scope="both")
def _c_slowing_earlier(ctx: Context) -> Judgement:
    """Judge of claim IV.C-4 by its criterion."""
    f, n = ctx.both()
    rf, rn = f.jammed(), n.jammed()
    peaks = {m: (f.argmax(f.mean(NORMAL, 0, m)) - rf, n.argmax(n.mean(NORMAL, 0, m)) - rn) for m in (B, W2)}
    lead = min(b - a for a, b in peaks.values())
    # the lead is the difference of two maxima, each on its system's sampling grid: it is resolved to two steps
    resolution = 2 * max(f.step, n.step)
    return Judgement(lead, "argmax(rho) - rho_J (beta0), mu=0.5 vs mu=0: "
                     + ", ".join(f"{METRIC_SYMBOLS[m]} {fmt(a, 2)} vs {fmt(b, 2)}" for m, (a, b) in peaks.items())
                     + f"; lead {fmt(lead, 2)}, two sampling steps {fmt(resolution, 2)}",
                     lead > 0, margin=relative_margin(abs(lead), resolution),
                     grid_step=bool(abs(lead) < resolution - 1e-12))


@claim("IV.C-5", "§IV C, Figs 6(b), 9(b)",
       "For rho well below rho_J the loop structure (beta1) changes much less for mu = 0 (d_B and d_W2)",
       lambda t: (f"medians over rho < min(rho_J) - {t.well_below}: mu=0 / mu=0.5 <= 1/{t.value_factor} for d_B "
                  "and d_W2"),
       paper="smaller", scope="both")
def _c_loops_below_jamming(ctx: Context) -> Judgement:
    """Judge of claim IV.C-5 by its criterion."""
    f, n = ctx.both()
    hi = min(f.jammed(), n.jammed()) - ctx.tol.well_below
    ratio = median_quotient(ctx, 1, (B, W2), hi=hi)
    largest = max(ratio.values())
    loops = {m: float(n.window(n.mean(NORMAL, 1, m), hi=hi).abs().max()) for m in (B, W2)}
    return Judgement(largest, f"median over rho < {fmt(hi)} (beta1), mu=0 / mu=0.5: {per_metric_text(ratio)}; "
                              f"largest mu=0 value there: {per_metric_text(loops)}",
                     largest <= 1 / ctx.tol.value_factor,
                     margin=relative_margin(largest, 1 / ctx.tol.value_factor),
                     vacuous=all(v == 0 for v in loops.values()))


@claim("IV.C-6", "§IV C, Figs 6(b), 9(b)",
       "Close to jamming the loop structure (beta1) changes much more dramatically for mu = 0 "
       "(all three distances)",
       lambda t: f"largest value within ±{t.peak_window} of each rho_J: mu=0 / mu=0.5 >= {t.value_factor}",
       paper="larger", scope="both")
def _c_loops_near_jamming(ctx: Context) -> Judgement:
    """Judge of claim IV.C-6 by its criterion."""
    w = ctx.tol.peak_window
    peak = _peak_quotient(ctx, 1, lambda c: (c.jammed() - w, c.jammed() + w), numerator="frictionless")
    smallest = min(peak.values())
    return Judgement(smallest, f"largest value within ±{w} of each system's rho_J (beta1), mu=0 / mu=0.5: "
                               f"{per_metric_text(peak)}", smallest >= ctx.tol.value_factor,
                     margin=ratio_margin(smallest, ctx.tol.value_factor))


def _quotient_after_jamming(dim: int, reference: float):
    """(criterion, evaluate) of "after jamming the PD_dim rates of mu = 0 are `reference` times those of
    mu = 0.5": medians over rho above both rho_J, every metric, within a factor value_factor of `reference`."""
    def criterion(t: ClaimTolerances) -> str:
        """The criterion with the tolerances `t` filled in."""
        return (f"median over rho > both rho_J, mu=0 / mu=0.5 within a factor {t.value_factor} of {fmt(reference)}, "
                "every metric")

    def evaluate(ctx: Context) -> Judgement:
        """The medians' quotients over rho above both rho_J (the key number: their median)."""
        f, n = ctx.both()
        ratio = median_quotient(ctx, dim, METRICS, lo=max(f.jammed(), n.jammed()), closed_lo=False)
        return Judgement(float(np.median(list(ratio.values()))),
                         f"median over rho > both rho_J (beta{dim}), mu=0 / mu=0.5: {per_metric_text(ratio)}",
                         all(within_factor(v, reference, ctx.tol.value_factor) for v in ratio.values()),
                         margin=smallest_margin(*(within_factor_margin(v, reference, ctx.tol.value_factor)
                                                  for v in ratio.values())))
    return criterion, evaluate


_criterion, _judge = _quotient_after_jamming(1, 2.0)
claim("IV.C-7", "§IV C, Figs 6(b), 9(b)",
      "After jamming the loop structure (beta1) changes about twice as fast for mu = 0 as for mu = 0.5",
      _criterion, paper="2", scope="both")(_judge)


def _more_loops_without_friction(regime: str):
    """The judge of IV.C-8 ("more points in PD1 for mu = 0 than for mu = 0.5") in one `regime`: ``"below"`` both
    rho_J (rho < the smaller) or ``"above"`` both (rho > the larger). Without friction loops exist only from jamming
    on, and the frictionless system jams later, so the two regimes answer differently (split after the verdicts
    were read: `forcenet.report.judge_changes`)."""
    def evaluate(ctx: Context) -> Judgement:
        """Median over the regime's states of the realization-mean number of normal-force PD1 points."""
        f, n = ctx.both()
        rf, rn = f.jammed(), n.jammed()
        medians = {}
        for name in (ctx.frictional, ctx.frictionless):
            if name in ctx.point_counts:
                counts = realization_mean(ctx.point_counts[name])
            elif name in ctx.diagrams:
                counts = realization_mean(diagram_point_counts(ctx.diagrams[name], NORMAL, 1))
            else:
                raise NotEvaluated(f"{name}: no persistence diagrams (diagrams.nc) to count PD1 points in")
            rho = np.asarray(counts["rho"].values, dtype=float)
            inside = rho < min(rf, rn) if regime == "below" else rho > max(rf, rn)
            values = np.asarray(counts.values, dtype=float)[inside]
            values = values[np.isfinite(values)]
            if values.size < ctx.tol.min_points:
                raise NotEvaluated(f"{name}: {values.size} state(s) {regime} both rho_J (need {ctx.tol.min_points})")
            medians[name] = float(np.median(values))
        without, with_ = medians[ctx.frictionless], medians[ctx.frictional]
        where = f"rho < {fmt(min(rf, rn))}" if regime == "below" else f"rho > {fmt(max(rf, rn))}"
        return Judgement(without / with_ if with_ > 0 else math.inf,
                         f"median number of PD1 points per state over {where} ({regime} both rho_J): "
                         f"{ctx.frictionless} {fmt(without)}, {ctx.frictional} {fmt(with_)}", without > with_,
                         margin=contrast_margin(without, with_))
    return evaluate


for suffix, regime in (("a", "below"), ("b", "above")):
    claim(f"IV.C-8{suffix}", "§IV C",
          f"There are more points in PD1 (loops) for mu = 0 than for mu = 0.5 ({regime} both rho_J)",
          f"median over the states {regime} both rho_J of the realization-mean number of normal-force PD1 points: "
          "mu = 0 > mu = 0.5", paper="more PD1 points for mu = 0", scope="both")(_more_loops_without_friction(regime))


@claim("IV.C-9", "§IV C",
       "After jamming the influence of friction is much more obvious for loops (beta1) than for components (beta0)",
       "median over d_B, d_W1, d_W2 of |log10(median mu=0 / median mu=0.5)| over rho > both rho_J: beta1 > beta0",
       paper="loops more than components", scope="both")
def _c_friction_matters_more_for_loops(ctx: Context) -> Judgement:
    """Judge of claim IV.C-9 by its criterion."""
    f, n = ctx.both()
    lo = max(f.jammed(), n.jammed())
    influence = {dim: float(np.median([abs(math.log10(v)) if 0 < v < math.inf else math.inf for v in
                                       median_quotient(ctx, dim, METRICS, lo=lo, closed_lo=False).values()]))
                 for dim in P2_HOMOLOGY_DIMS}
    return Judgement(influence[1] - influence[0],
                     f"median |log10(mu=0 / mu=0.5)| over rho > {fmt(lo)}: beta0 {fmt(influence[0], 2)}, beta1 "
                     f"{fmt(influence[1], 2)} decades", influence[1] > influence[0],
                     margin=contrast_margin(influence[1], influence[0]))


@claim("V-1", "§V (conclusions)",
       "Peak rates of evolution of the components (beta0) before jamming are 20-40 % higher with friction",
       lambda t: f"peak over rho <= rho_J, mu=0.5 / mu=0 in (max(1, 1.2/{t.value_factor}), 1.4·{t.value_factor}], "
                  "every metric",
       paper="1.2-1.4", scope="both")
def _v_peak_components(ctx: Context) -> Judgement:
    """Judge of claim V-1 by its criterion."""
    ratio = _peak_quotient(ctx, 0, lambda c: (-np.inf, c.jammed()), numerator="frictional")
    lo, hi = max(1.0, 1.2 / ctx.tol.value_factor), 1.4 * ctx.tol.value_factor
    margin = smallest_margin(*(min(relative_margin(v, lo), relative_margin(v, hi)) for v in ratio.values()))
    return Judgement(min(ratio.values()), f"peak over rho <= rho_J (beta0), mu=0.5 / mu=0: {per_metric_text(ratio)}",
                     all(lo < v <= hi for v in ratio.values()), margin=margin)


_criterion, _judge = _quotient_after_jamming(0, 1.0)
claim("V-2", "§V (conclusions)",
      "After jamming the component (beta0) rates become quite similar with and without friction",
      _criterion, paper="1", scope="both")(_judge)
