"""P2's claims of §III D (Tables I–III), §IV A and §IV B: one `forcenet.report.claims.Claim` each in `CLAIMS` (those of
§IV C and §V follow in `forcenet.report.p2_claims_friction`; `forcenet.report.p2_validation.CLAIMS` is both), judged on
the realization-mean distance curves and Tables I–III (`forcenet.report.p2_judging.Context`).

A judge returns a `forcenet.report.claims.Judgement` (the key number, the evidence, holds, and how far the
deciding number lies from its threshold) or raises `NotEvaluated`; criteria are functions of
`forcenet.report.claims.ClaimTolerances`, so every verdict uses the documented tolerances and nothing else. The
only numbers typed in are P2's own: the
``paper`` column (its statement), the ρ ranges it names and its printed tables. Why a claim does not hold is
`forcenet.report.p2_explanations`; the table is `forcenet.report.p2_validation`.
"""
from __future__ import annotations

import math
from typing import Sequence

import numpy as np
import pandas as pd

from forcenet.report.claims import (Claim, ClaimTolerances, Judgement, NotEvaluated, claim_register,
                                    contrast_margin, ratio_margin, reference_margin, relative_margin, smallest_margin)
from forcenet.report.p2 import (METRIC_SYMBOLS, METRICS, P2_HOMOLOGY_DIMS, TABLE_PAIRS, table_column)
from forcenet.report.p2_tables import p2_reference_table
from forcenet.report.p2_judging import (B, NORMAL, TANGENTIAL, W1, W2, Context, Curves, coefficient_of_variation, fmt,
                                        log10_ratio, pearson, per_dim_metric_text, per_metric_text,
                                        rate_quotient, spearman, within_factor, within_factor_margin)


CLAIMS: list[Claim] = []  # in the order of the table
claim = claim_register(CLAIMS)


@claim("III.D-1", "§III D, Table I",
       "No single dramatic change between nearby states: d_B(a,b) and d_B(a,c) are small",
       lambda t: f"d_B(a,b) <= 0.10·{t.value_factor} and d_B(a,c) <= 0.15·{t.value_factor} for beta0 and beta1",
       paper="< 0.10 and < 0.15 <F>", scope="tables")
def _t_bottleneck_small(ctx: Context) -> Judgement:
    """Judge of claim III.D-1 by its criterion."""
    t = ctx.table("table1")
    values = {(pair, h): float(t.loc[pair, table_column(h, B)]) for pair in TABLE_PAIRS for h in P2_HOMOLOGY_DIMS}
    limits = {"(a,b)": 0.10, "(a,c)": 0.15}
    worst = max(v / (limits[pair] * ctx.tol.value_factor) for (pair, _), v in values.items())
    return Judgement(worst, "Table I d_B: " + ", ".join(f"{p} beta{h} {fmt(v, 2)}" for (p, h), v in values.items())
                     + f"; largest share of its limit {fmt(worst, 2)}", worst <= 1.0,
                     margin=relative_margin(worst, 1.0))


@claim("III.D-2", "§III D, Table I",
       "c differs from a by many more small changes than b does: d_W1 grows from (a,b) to (a,c) relatively more "
       "than d_W2",
       lambda t: ("d_W1(a,c)/d_W1(a,b) > d_W2(a,c)/d_W2(a,b) for beta0 and beta1; margin against P2's own quotients "
                  "(how far ours lies from 1 relative to P2's)"),
       paper="beta0: 14.0/4.18 vs 0.89/0.50; beta1: 19.2/3.8 vs 0.99/0.57", scope="tables")
def _t_relative_w1(ctx: Context) -> Judgement:
    """Judge of claim III.D-2 by its criterion."""
    t = ctx.table("table1")
    growth = {}
    for h in P2_HOMOLOGY_DIMS:
        for m in (W1, W2):
            col = table_column(h, m)
            growth[h, m] = float(t.loc["(a,c)", col]) / float(t.loc["(a,b)", col])
    quotient = {h: growth[h, W1] / growth[h, W2] for h in P2_HOMOLOGY_DIMS}
    lead = min(quotient.values())
    # P2's own quotients (its Table I): the margin says how far ours lies from 1 relative to how far P2's does
    own = _table1_quotients(p2_reference_table("table1"))
    margin = smallest_margin(*(reference_margin(quotient[h], 1.0, own[h]) for h in P2_HOMOLOGY_DIMS))
    return Judgement(lead, f"Table I (a,c)/(a,b): {per_dim_metric_text(growth)}; smallest d_W1/d_W2 growth quotient "
                           f"{fmt(lead, 2)}; P2's own quotients: "
                           + ", ".join(f"beta{h} {fmt(own[h], 3)}" for h in P2_HOMOLOGY_DIMS), lead > 1.0,
                     margin=margin)


def _table1_quotients(table: pd.DataFrame) -> dict[int, float]:
    """{homology dim: d_W1(a,c)/d_W1(a,b) over d_W2(a,c)/d_W2(a,b)} of a Table I (ours or P2's)."""
    def growth(h: int, m: str) -> float:
        col = table_column(h, m)
        return float(table.loc["(a,c)", col]) / float(table.loc["(a,b)", col])
    return {h: growth(h, W1) / growth(h, W2) for h in P2_HOMOLOGY_DIMS}


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


@claim("III.D-3", "§III D, Table II",
       "The (a,b) differences are concentrated in one quadrant (bottom left in P2)",
       lambda t: f"one quadrant largest in most columns and median largest/second largest >= {t.dominance}",
       paper="bottom left largest in every column", scope="tables")
def _t_localised(ctx: Context) -> Judgement:
    """Judge of claim III.D-3 by its criterion."""
    stats = quadrant_dominance(ctx.table("table2"))
    top = stats["largest"].value_counts()
    quadrant, count = str(top.index[0]), int(top.iloc[0])
    median = float(stats["dominance"].median())
    ok = count > len(stats) / 2 and median >= ctx.tol.dominance
    return Judgement(median, f"Table II: '{quadrant}' is largest in {count} of {len(stats)} columns; median "
                             f"largest/second largest = {fmt(median, 2)}", ok,
                     margin=relative_margin(median, ctx.tol.dominance))


@claim("III.D-4", "§III D, Table III",
       "The (a,c) differences are distributed evenly over the domain",
       lambda t: (f"median over columns of largest/smallest quadrant <= {t.spread}; margin against P2's own Table III "
                  "(how far ours lies from the limit relative to P2's)"),
       paper="similar values in all quadrants", scope="tables")
def _t_spread(ctx: Context) -> Judgement:
    """Judge of claim III.D-4 by its criterion."""
    stats = quadrant_dominance(ctx.table("table3"))
    median = float(stats["max_over_min"].median())
    # P2's own Table III gives 1.46: the margin says how far ours lies from the limit relative to how far P2's does
    own = float(quadrant_dominance(p2_reference_table("table3"))["max_over_min"].median())
    return Judgement(median, f"Table III: median over columns of largest/smallest quadrant = {fmt(median, 2)}; "
                             f"P2's own {fmt(own, 3)}", median <= ctx.tol.spread,
                     margin=reference_margin(median, ctx.tol.spread, own))


@claim("IV.A-1", "§IV A, Fig. 6",
       "The most pronounced feature is the dramatic change around rho_J (Z ≈ 3)",
       lambda t: f"argmax of mean d_W1 (beta0 and beta1) within ±{t.peak_window} of rho_J",
       paper="rate of change peaks at rho_J", scope="frictional")
def _a_peak_near_jamming(ctx: Context) -> Judgement:
    """Judge of claim IV.A-1 by its criterion."""
    c = ctx.system(ctx.frictional)
    rho_j = c.jammed()
    peaks = {h: c.argmax(c.mean(NORMAL, h, W1)) for h in P2_HOMOLOGY_DIMS}
    farthest = max(abs(p - rho_j) for p in peaks.values())
    return Judgement(farthest, f"rho_J = {fmt(rho_j)}; argmax of mean d_W1: beta0 at {fmt(peaks[0])}, beta1 at "
                               f"{fmt(peaks[1])}", farthest <= ctx.tol.peak_window,
                     grid_step=c.by_one_step(farthest, ctx.tol.peak_window))


@claim("IV.A-2", "§IV A, Fig. 6(a)",
       "Before jamming d_B (beta0) is an order of magnitude greater than one for most of the regime",
       lambda t: f"median of mean d_B over rho < rho_J >= 10/{t.value_factor}",
       paper="≈ 10 <F>", scope="frictional")
def _a_db_large_before(ctx: Context) -> Judgement:
    """Judge of claim IV.A-2 by its criterion."""
    c = ctx.system(ctx.frictional)
    s = c.window(c.mean(NORMAL, 0, B), hi=c.jammed())
    median = float(s.median())
    return Judgement(median, f"median d_B(beta0) over rho < rho_J = {fmt(c.rho_j)}: {fmt(median)} <F>",
                     median >= 10 / ctx.tol.value_factor, margin=relative_margin(median, 10 / ctx.tol.value_factor))


def _ratio_constant(denominator: str, reference: float):
    """(criterion, evaluate) of "for rho < 0.75, d_B/d_Wq (beta0) is roughly constant and ≈ `reference`"."""
    def criterion(t: ClaimTolerances) -> str:
        """The criterion with the tolerances `t` filled in."""
        return f"median within a factor {t.value_factor} of {fmt(reference)} and CV <= {t.max_cv}"

    def evaluate(ctx: Context) -> Judgement:
        """The median and CV of the ratio over rho < 0.75."""
        c = ctx.system(ctx.frictional)
        s = c.window(c.ratio(NORMAL, 0, denominator), hi=0.75)
        median, cv = float(s.median()), coefficient_of_variation(s)
        ok = within_factor(median, reference, ctx.tol.value_factor) and cv <= ctx.tol.max_cv
        return Judgement(median, f"median d_B/{METRIC_SYMBOLS[denominator]} = {fmt(median)}, CV = {fmt(cv, 2)} over "
                                 f"{len(s)} rho values < 0.75 (rho_J = {fmt(c.rho_j)})", ok,
                         margin=smallest_margin(within_factor_margin(median, reference, ctx.tol.value_factor),
                                                relative_margin(cv, ctx.tol.max_cv)))
    return criterion, evaluate


_criterion, _judge = _ratio_constant(W2, 0.75)
claim("IV.A-3", "§IV A, Fig. 7(a)",
      "For rho < 0.75, d_B/d_W2 (beta0) is roughly constant and ≈ 0.75",
      _criterion, paper="0.75", scope="frictional")(_judge)


_criterion, _judge = _ratio_constant(W1, 0.2)
claim("IV.A-4", "§IV A, Fig. 7(a)",
      "For rho < 0.75, d_B/d_W1 (beta0) is roughly constant and ≈ 0.2",
      _criterion, paper="0.2", scope="frictional")(_judge)


@claim("IV.A-5", "§IV A, Fig. 6(a)",
       "At rho ≈ 0.75 the rate of change measured by d_B (beta0) decreases dramatically",
       lambda t: f"median d_B over [0.75, rho_J) <= median over rho < 0.75 / {t.drop_factor}",
       paper="drop at 0.75", scope="frictional")
def _a_db_drops_at_075(ctx: Context) -> Judgement:
    """Judge of claim IV.A-5 by its criterion."""
    c = ctx.system(ctx.frictional)
    s = c.mean(NORMAL, 0, B)
    before, after = c.window(s, hi=0.75), c.window(s, 0.75, c.jammed())
    m0, m1 = float(before.median()), float(after.median())
    fall = rate_quotient(m0, m1, "d_B(beta0) medians before and after 0.75")
    return Judgement(fall, f"median d_B(beta0): {fmt(m0)} for rho < 0.75, {fmt(m1)} for 0.75 <= rho < rho_J = "
                           f"{fmt(c.rho_j)}", m1 <= m0 / ctx.tol.drop_factor,
                     margin=ratio_margin(fall, ctx.tol.drop_factor))


@claim("IV.A-6", "§IV A, Figs 6(a), 7(a)",
       "For 0.75 < rho < rho_J, d_W1 (beta0) increases dramatically and d_B/d_W1 decreases",
       lambda t: f"Spearman(rho, d_W1) >= {t.trend} and Spearman(rho, d_B/d_W1) <= -{t.trend}",
       paper="increase / decrease", scope="frictional")
def _a_w1_grows_before_jamming(ctx: Context) -> Judgement:
    """Judge of claim IV.A-6 by its criterion."""
    c = ctx.system(ctx.frictional)
    w1 = c.window(c.mean(NORMAL, 0, W1), 0.75, c.jammed())
    r1 = c.window(c.ratio(NORMAL, 0, W1), 0.75, c.jammed())
    s_w1, s_r1 = spearman(w1), spearman(r1)
    return Judgement(s_w1, f"Spearman(rho, d_W1) = {fmt(s_w1, 2)}, Spearman(rho, d_B/d_W1) = {fmt(s_r1, 2)} over "
                           f"0.75 <= rho < rho_J = {fmt(c.rho_j)} ({len(w1)} values)",
                     s_w1 >= ctx.tol.trend and s_r1 <= -ctx.tol.trend,
                     margin=smallest_margin(relative_margin(s_w1, ctx.tol.trend),
                                            relative_margin(-s_r1, ctx.tol.trend)))


@claim("IV.A-7", "§IV A, Fig. 7(a)",
       "For 0.75 < rho < rho_J, d_B/d_W2 (beta0) stays roughly constant until just before jamming, "
       "where it plunges",
       lambda t: (f"CV <= {t.max_cv} over [0.75, rho_J - {t.near_jamming}) and the minimum over [rho_J - "
                  f"{t.near_jamming}, rho_J] <= plateau median / {t.drop_factor}"),
       paper="constant, then plunge", scope="frictional")
def _a_w2_ratio_plunges(ctx: Context) -> Judgement:
    """Judge of claim IV.A-7 by its criterion."""
    c = ctx.system(ctx.frictional)
    rho_j, near = c.jammed(), ctx.tol.near_jamming
    r2 = c.ratio(NORMAL, 0, W2)
    plateau = c.window(r2, 0.75, rho_j - near)
    before_jamming = c.window(r2, rho_j - near, rho_j, closed_hi=True)
    cv, median, low = coefficient_of_variation(plateau), float(plateau.median()), float(before_jamming.min())
    ok = cv <= ctx.tol.max_cv and low <= median / ctx.tol.drop_factor
    plunge = rate_quotient(median, low, "d_B/d_W2 plateau and minimum")
    return Judgement(plunge, f"d_B/d_W2 over [0.75, rho_J - {near}): median {fmt(median)}, CV {fmt(cv, 2)}; minimum "
                             f"over [rho_J - {near}, rho_J = {fmt(rho_j)}]: {fmt(low)}", ok,
                     margin=smallest_margin(relative_margin(cv, ctx.tol.max_cv),
                                            ratio_margin(plunge, ctx.tol.drop_factor)))


@claim("IV.A-8", "§IV A, Fig. 6(b)",
       "Before jamming the rate of change of the loop structure (beta1) generally increases with rho",
       lambda t: f"median over d_B, d_W1, d_W2 of Spearman(rho, d) over rho < min(0.77, rho_J) >= {t.trend}",
       paper="increase", scope="frictional")
def _a_loops_increase(ctx: Context) -> Judgement:
    """Judge of claim IV.A-8 by its criterion."""
    c = ctx.system(ctx.frictional)
    hi = min(0.77, c.jammed())
    rhos = {m: spearman(c.window(c.mean(NORMAL, 1, m), hi=hi)) for m in METRICS}
    median = float(np.nanmedian(list(rhos.values())))
    return Judgement(median, f"Spearman(rho, d) for beta1 over rho < {fmt(hi)}: {per_metric_text(rhos)}",
                     median >= ctx.tol.trend, margin=relative_margin(median, ctx.tol.trend))


@claim("IV.A-9", "§IV A, Fig. 6(b)",
       "At rho ≈ 0.77 d_B (beta1) starts decreasing",
       lambda t: f"argmax of mean d_B(beta1) within 0.77 ± {t.peak_window}",
       paper="peak at 0.77", scope="frictional")
def _a_loops_db_peak(ctx: Context) -> Judgement:
    """Judge of claim IV.A-9 by its criterion."""
    c = ctx.system(ctx.frictional)
    peak = c.argmax(c.mean(NORMAL, 1, B))
    return Judgement(peak, f"argmax of mean d_B(beta1): rho = {fmt(peak)} (rho_J = {fmt(c.rho_j)})",
                     abs(peak - 0.77) <= ctx.tol.peak_window,
                     grid_step=c.by_one_step(abs(peak - 0.77), ctx.tol.peak_window))


@claim("IV.A-10", "§IV A, Fig. 7(b)",
       "Both ratios d_B/d_W2 and d_B/d_W1 (beta1) decrease from rho ≈ 0.76 on",
       lambda t: f"Spearman(rho, ratio) <= -{t.trend} over 0.76 <= rho <= rho_J for both ratios",
       paper="decrease", scope="frictional")
def _a_loop_ratios_decrease(ctx: Context) -> Judgement:
    """Judge of claim IV.A-10 by its criterion."""
    c = ctx.system(ctx.frictional)
    hi = c.jammed()
    s = {d: spearman(c.window(c.ratio(NORMAL, 1, d), 0.76, hi, closed_hi=True)) for d in (W2, W1)}
    weakest = max(s.values())
    return Judgement(weakest, f"Spearman(rho, ratio) for beta1 over 0.76 <= rho <= rho_J = {fmt(hi)}: d_B/d_W2 "
                              f"{fmt(s[W2], 2)}, d_B/d_W1 {fmt(s[W1], 2)}", weakest <= -ctx.tol.trend,
                     margin=relative_margin(-weakest, ctx.tol.trend))


def _fall_after_jamming(role: str):
    """The judge of "after jamming the rate of change slows dramatically" for the system of `role`: the rates after
    ρ_J against those just before it (P2 §IV A compares the two sides of the transition; the dilute regime far
    below, where β1 has hardly any loops to change, is not what slows)."""
    def evaluate(ctx: Context) -> Judgement:
        """Median over [rho_J - rate_window, rho_J) / median over rho > rho_J, every metric, beta0 and beta1."""
        c = ctx.system(ctx.frictional if role == "frictional" else ctx.frictionless)
        rho_j = c.jammed()
        factors = {}
        for h in P2_HOMOLOGY_DIMS:
            for m in METRICS:
                s = c.mean(NORMAL, h, m)
                before = c.window(s, rho_j - ctx.tol.rate_window, rho_j).median()
                after = c.window(s, lo=rho_j, closed_lo=False).median()
                factors[h, m] = rate_quotient(before, after,
                                              f"beta{h} {METRIC_SYMBOLS[m]} median before and after rho_J")
        worst = min(factors.values())
        text = (f"rho_J = {fmt(rho_j)}; median over [rho_J - {ctx.tol.rate_window}, rho_J) / median over rho > rho_J: "
                f"{per_dim_metric_text(factors)}")
        return Judgement(worst, text, worst >= ctx.tol.fall_factor, margin=ratio_margin(worst, ctx.tol.fall_factor))
    return evaluate


for suffix, figure, role in (("a", 6, "frictional"), ("b", 9, "frictionless")):
    claim(f"IV.A-11{suffix}", f"§IV A, Fig. {figure}; §V",
          "After jamming the rate of change slows dramatically (distances fall sharply)",
          lambda t: (f"median over rho > rho_J <= median over the rates just before jamming, [rho_J - "
                     f"{t.rate_window}, rho_J), / {t.fall_factor}, every metric, beta0 and beta1; the factor "
                     f"{t.fall_factor} is ours (P2 gives none): 'dramatically' read as one order of magnitude on "
                     "the log axes of P2 Figs 6, 9"),
          paper="much smaller", scope=role)(_fall_after_jamming(role))


def _ratios_after_jamming(dim: int):
    """The judge of "after jamming d_B/d_W2 and d_B/d_W1 (beta`dim`) are constant and 1 and 3 decades smaller"."""
    def evaluate(ctx: Context) -> Judgement:
        """The drop in decades and the CV after rho_J of both ratios."""
        c = ctx.system(ctx.frictional)
        rho_j = c.jammed()
        parts, ok, margins, drops = [], True, [], []
        for den, decades in ((W2, 1.0), (W1, 3.0)):
            r = c.ratio(NORMAL, dim, den)
            before = c.window(r, hi=min(0.75, rho_j))
            after = c.window(r, lo=rho_j, closed_lo=False)
            drop = math.log10(float(before.median()) / float(after.median()))
            cv = coefficient_of_variation(after)
            ok &= abs(drop - decades) <= ctx.tol.decades and cv <= ctx.tol.max_cv
            margins += [relative_margin(abs(drop - decades), ctx.tol.decades), relative_margin(cv, ctx.tol.max_cv)]
            drops.append(drop)
            parts.append(f"d_B/{METRIC_SYMBOLS[den]}: drop {fmt(drop, 2)} decades, CV after {fmt(cv, 2)}")
        return Judgement(drops[-1], f"beta{dim}, rho_J = {fmt(rho_j)}: " + "; ".join(parts), bool(ok),
                         margin=smallest_margin(*margins))
    return evaluate


for panel, dim in (("a", 0), ("b", 1)):
    claim(f"IV.A-12{panel}", f"§IV A, Fig. 7({panel})",
          f"After jamming d_B/d_W2 and d_B/d_W1 (beta{dim}) are essentially constant and about one and three "
          "orders of magnitude smaller than before",
          lambda t: (f"log10(median before / median after) within ±{t.decades} of 1 and 3 (before: rho < "
                     f"min(0.75, rho_J)); CV after <= {t.max_cv}"),
          paper="1 and 3 decades", scope="frictional")(_ratios_after_jamming(dim))


def _near(c: Curves, s: pd.Series, tol: ClaimTolerances) -> pd.Series:
    """The values of `s` with |rho - rho_J| <= near_jamming."""
    return s[np.abs(s.index.values - c.jammed()) <= tol.near_jamming]


def _away(c: Curves, s: pd.Series, tol: ClaimTolerances) -> pd.Series:
    """The values of `s` with |rho - rho_J| > near_jamming."""
    return s[np.abs(s.index.values - c.jammed()) > tol.near_jamming]


def _tangential_log_ratios(c: Curves, metrics: Sequence[str]) -> pd.Series:
    """log10(tangential / normal) of the mean curves of beta0 and beta1 for each of `metrics`, stacked into one
    Series over rho (one entry per dimension, metric and rho where both curves are positive)."""
    parts = [log10_ratio(c.mean(TANGENTIAL, h, m), c.mean(NORMAL, h, m)) for h in P2_HOMOLOGY_DIMS for m in metrics]
    return pd.Series(np.concatenate([p.values for p in parts]), index=np.concatenate([p.index.values for p in parts]),
                     dtype=float)


@claim("IV.B-1", "§IV B, Fig. 8",
       "Tangential-force distances track the normal-force ones (beta0 and beta1) away from rho_J",
       lambda t: (f"median Pearson correlation of log10 curves with |rho - rho_J| > {t.near_jamming} "
                  f">= {t.correlation}"),
       paper="similar curves", scope="frictional")
def _b_tracks(ctx: Context) -> Judgement:
    """Judge of claim IV.B-1 by its criterion."""
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
                raise NotEvaluated(f"fewer than {ctx.tol.correlation_points} rho values away from rho_J")
            corr[h, m] = pearson(np.log10(n[ok].values), np.log10(t[ok].values))
    median = float(np.nanmedian(list(corr.values())))
    return Judgement(median, "Pearson correlation of log10 normal vs tangential curves, |rho - rho_J| > "
                             f"{ctx.tol.near_jamming}: {per_dim_metric_text(corr)}; median {fmt(median, 2)}",
                     median >= ctx.tol.correlation, margin=relative_margin(median, ctx.tol.correlation))


@claim("IV.B-2", "§IV B, Fig. 8",
       "Normal and tangential distances deviate more near rho_J than elsewhere",
       lambda t: f"median |log10(tangential/normal)| within ±{t.near_jamming} of rho_J > away from it",
       paper="larger deviation near rho_J", scope="frictional")
def _b_deviation_near_jamming(ctx: Context) -> Judgement:
    """Judge of claim IV.B-2 by its criterion."""
    c = ctx.system(ctx.frictional)
    c.jammed()
    dev = _tangential_log_ratios(c, METRICS).abs()
    near, away = _near(c, dev, ctx.tol).values, _away(c, dev, ctx.tol).values
    if not len(near) or len(away) < ctx.tol.min_points:
        raise NotEvaluated(f"no rho value within {ctx.tol.near_jamming} of rho_J, or too few away from it")
    m_near, m_away = float(np.median(near)), float(np.median(away))
    return Judgement(m_near - m_away, f"median |log10(tangential/normal)|: {fmt(m_near, 2)} within "
                                      f"±{ctx.tol.near_jamming} of rho_J = {fmt(c.rho_j)}, {fmt(m_away, 2)} away "
                                      "from it", m_near > m_away, margin=contrast_margin(m_near, m_away))


@claim("IV.B-3", "§IV B, Fig. 8",
       "Near rho_J, d_W1 and d_W2 are significantly smaller for tangential forces",
       lambda t: (f"median tangential/normal within ±{t.near_jamming} of rho_J <= 1/{t.value_factor} "
                  "for d_W1 and d_W2"),
       paper="smaller", scope="frictional")
def _b_wasserstein_smaller_near_jamming(ctx: Context) -> Judgement:
    """Judge of claim IV.B-3 by its criterion."""
    c = ctx.system(ctx.frictional)
    c.jammed()
    medians = {}
    for m in (W1, W2):
        values = _near(c, _tangential_log_ratios(c, (m,)), ctx.tol).values
        if not len(values):
            raise NotEvaluated(f"no rho value within {ctx.tol.near_jamming} of rho_J")
        medians[m] = 10 ** float(np.median(values))
    largest = max(medians.values())
    return Judgement(largest, f"median tangential/normal within ±{ctx.tol.near_jamming} of rho_J = {fmt(c.rho_j)}: "
                              + per_metric_text(medians), largest <= 1 / ctx.tol.value_factor,
                     margin=relative_margin(largest, 1 / ctx.tol.value_factor))


@claim("IV.B-4", "§IV B, Fig. 8",
       "d_B is similar for normal and tangential forces throughout, including near rho_J",
       lambda t: f"median factor between the d_B curves <= {t.value_factor}, over all rho and near rho_J",
       paper="similar", scope="frictional")
def _b_bottleneck_similar(ctx: Context) -> Judgement:
    """Judge of claim IV.B-4 by its criterion."""
    c = ctx.system(ctx.frictional)
    c.jammed()
    dev = _tangential_log_ratios(c, (B,))
    everywhere, near = dev.values, _near(c, dev, ctx.tol).values
    if len(everywhere) < ctx.tol.min_points or not len(near):
        raise NotEvaluated("too few rho values with both curves positive")
    f_all, f_near = 10 ** float(np.median(np.abs(everywhere))), 10 ** float(np.median(np.abs(near)))
    limit, largest = ctx.tol.value_factor, max(f_all, f_near)
    return Judgement(largest, f"median factor between tangential and normal d_B: {fmt(f_all, 2)} over all rho, "
                              f"{fmt(f_near, 2)} within ±{ctx.tol.near_jamming} of rho_J = {fmt(c.rho_j)}",
                     largest <= limit, margin=ratio_margin(largest, limit))
