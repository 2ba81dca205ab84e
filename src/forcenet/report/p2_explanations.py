"""Why a claim of P2 does not hold on our data: `EXPLANATIONS` gives each claim's cause, its basis — the command
that measured it (docs/p2_sampling.md: distances at several wall speeds and sampling steps, and P2's own setting
run at paper size; the validation campaign; the diagnostics of this table) or none, when the cause is a hypothesis
— and the diagnostics that measure it again on the data judged (`explain`, a
`forcenet.report.claims.Explanation`).
"""
from __future__ import annotations

from typing import Callable

import numpy as np

from forcenet.report.claims import FAILS, HOLDS, Explanation, JudgedClaim, NotEvaluated
from forcenet.report.p2 import METRIC_SYMBOLS, jamming_density_per_realization
from forcenet.report.p2_judging import B, NORMAL, W1, W2, Context, fmt, median_quotient
from forcenet.report.p2_tables import state_mean_force


# --- why a claim does not hold: diagnostics measured on the same data ------------------------------------------
def _never_dying_events(name_of: Callable[[Context], str], dim: int, where: str) -> Callable[[Context], str]:
    """Diagnostic: how often consecutive states differ in their number of never-dying PD_dim classes (normal forces)
    in a ρ window (`where`: "after" ρ > ρ_J, "dense" 0.75 <= ρ < ρ_J). Under P2's death −1 each such pair has
    d_B >= 1/2 (the extra class, born at b >= 0, goes to the diagonal at (b + 1)/2 or to a finite point at >= 1),
    whatever else changed; the median d_B of the other pairs is what the forces alone give."""
    def diagnostic(ctx: Context) -> str:
        """The share of pairs that change the never-dying class count, and the median d_B of the others."""
        name = name_of(ctx)
        c = ctx.system(name)
        measures = ctx.measures.get(name)
        if measures is None or "essential_count" not in measures or "realization" not in c.ds.dims:
            raise NotEvaluated(f"{name}: no never-dying class counts (network_measures.nc) to compare")
        count = measures["essential_count"].sel(force_kind=NORMAL, homology_dim=dim)
        count = count.sel(realization=c.ds["realization"].values).transpose("realization", "rho").values
        d_b = c.ds["distance"].sel(force_kind=NORMAL, homology_dim=dim, metric=B).transpose("realization", "rho")
        changed = np.diff(count, axis=1) != 0
        if changed.shape != d_b.shape:
            raise NotEvaluated(f"{name}: network measures and distances cover different states")
        rho, rho_j = c.ds["rho"].values, c.jammed()
        inside = rho > rho_j if where == "after" else (rho >= 0.75) & (rho < rho_j)
        changed, d_b = changed[:, inside], d_b.values[:, inside]
        if not changed.size:
            raise NotEvaluated(f"{name}: no pairs {where} rho_J")
        quiet = d_b[~changed]
        window = f"rho > rho_J = {fmt(rho_j)}" if where == "after" else f"0.75 <= rho < rho_J = {fmt(rho_j)}"
        return (f"{name}: {100 * changed.mean():.0f} % of the {changed.size} consecutive pairs with {window} change "
                f"the number of never-dying beta{dim} classes (rattlers joining or leaving, loops opening or "
                f"closing), each d_B >= 0.5 under P2's death -1; median d_B of the other pairs "
                f"{fmt(np.median(quiet), 2) if quiet.size else 'n/a'}")
    return diagnostic


def _argmax_per_realization(name_of: Callable[[Context], str], dim: int, metric: str) -> Callable[[Context], str]:
    """Diagnostic: where each realization's curve peaks, next to ρ_J of its own Z (the spread that a mean over
    3 realizations keeps, and P2's 20 average out)."""
    def diagnostic(ctx: Context) -> str:
        """Each realization's argmax over rho beside its own rho_J."""
        name = name_of(ctx)
        c = ctx.system(name)
        if "realization" not in c.ds.dims:
            raise NotEvaluated(f"{name}: one realization")
        da = c.ds["distance"].sel(force_kind=NORMAL, homology_dim=dim, metric=metric)
        peaks = [float(da.isel(realization=i).idxmax("rho")) for i in range(da.sizes["realization"])]
        rho_js = jamming_density_per_realization(c.ds, c.dimension)
        return (f"{name}: argmax of beta{dim} {METRIC_SYMBOLS[metric]} per realization at rho "
                + ", ".join(f"{fmt(p)} (rho_J {fmt(j)})" for p, j in zip(peaks, rho_js)))
    return diagnostic


def _at_equal_depth(dim: int) -> Callable[[Context], str]:
    """Diagnostic: μ = 0 / μ = 0.5 quotients of the median normal-force rates after jamming, taken at equal depth
    above each system's own ρ_J (0 < ρ − ρ_J <= the depth both reach) instead of at equal ρ beyond both ρ_J: the
    frictionless system jams later, so at a given ρ it lies closer to its jamming, where the rates are higher."""
    def diagnostic(ctx: Context) -> str:
        """The three quotients at equal depth, and the depth range."""
        depth = min(float(c.ds["rho"].max()) - c.jammed() for c in ctx.both())
        # (rho_J, rho_J + depth]; 1e-12 keeps the limiting system's last state whatever the rounding of the sum
        quotient = median_quotient(ctx, dim, (B, W1, W2), closed_lo=False, closed_hi=True,
                                   bounds=lambda c: (c.jammed(), c.jammed() + depth + 1e-12))
        return (f"beta{dim} at equal depth above each system's own rho_J (0 < rho - rho_J <= {fmt(depth, 3)}), median "
                "mu=0 / mu=0.5: " + ", ".join(f"{METRIC_SYMBOLS[m]} {fmt(q, 2)}" for m, q in quotient.items()))
    return diagnostic


def _table_state_diagnostic(ctx: Context) -> str:
    """Diagnostic: where the states a, b, c of Tables I–III sit relative to their realization's ρ_J, and how much
    Z and ⟨F_n⟩ change over them (P2 Fig. 1: 'almost identical')."""
    if ctx.states is None:
        raise NotEvaluated("no table-state candidates given")
    row = ctx.states[ctx.states["chosen"].astype(bool)].iloc[0]
    c = ctx.system(ctx.frictional)
    realizations = list(c.ds["realization"].values) if "realization" in c.ds.dims else [int(row["realization"])]
    rho_js = jamming_density_per_realization(c.ds, c.dimension)
    rho_j = rho_js[realizations.index(int(row["realization"]))] if int(row["realization"]) in realizations else np.nan
    return (f"states a, b, c of realization {int(row['realization'])} (the quietest of {len(ctx.states)} by P2 Fig. 1's "
            f"criterion) at rho {row['rho_a']:.4f}-{row['rho_c']:.4f}, its rho_J = {fmt(rho_j)}: Z {row['Z_a']:.2f} -> "
            f"{row['Z_c']:.2f}, <F_n> x {state_mean_force(row, 'c') / state_mean_force(row, 'a'):.2f} from a to c "
            "(P2: Z and <F> almost identical)")


def explain(claim_id: str, ctx: Context, drop: JudgedClaim | None = None) -> Explanation:
    """Why a claim does not hold on these data: `EXPLANATIONS`' verdict on the cause, then its diagnostics measured
    here (a diagnostic the data cannot give says why), then what the control of the never-dying floor found: the
    same claim judged with never-dying classes left out of the distances (`drop`, its row under that reading;
    docs/validation/controls.md §3). Its basis is the command that measured the cause, or none (a hypothesis); a
    claim that holds under `drop` has the floor as its measured cause, and one whose cause put to the test was the
    floor (`_NEVER_DYING`) and that fails under `drop` too is left with none (a hypothesis)."""
    cause, command, diagnostics = EXPLANATIONS.get(claim_id, ("No explanation recorded.", HYPOTHESIS_ONLY, ()))
    measured = []
    for diagnostic in diagnostics:
        try:
            measured.append(diagnostic(ctx))
        except NotEvaluated as reason:
            measured.append(f"({reason})")
    text = cause + (" Measured here: " + "; ".join(measured) + "." if measured else "")
    if drop is None:
        return Explanation(text, command)
    control = "Control, never-dying classes left out of the distances (docs/validation/controls.md §3): "
    if drop.verdict == HOLDS:
        return Explanation(f"{text} {control}it holds (measured {fmt(drop.measured, 4)}, its row beside), so "
                           "the floor of P2's death -1 is its demonstrated cause.", DROP_CONTROL)
    if drop.verdict == FAILS and cause.startswith(_NEVER_DYING):  # the cause put to the test above is refuted
        return Explanation(f"{text} {control}it does not hold either (measured {fmt(drop.measured, 4)}): the floor "
                           "of P2's death -1 is ruled out as its only cause, and no other cause is measured.",
                           HYPOTHESIS_ONLY)
    if drop.verdict == FAILS:
        return Explanation(f"{text} {control}it does not hold either (measured {fmt(drop.measured, 4)}): the floor "
                           "of P2's death -1 is not all that makes it fail.", command)
    return Explanation(f"{text} {control}not evaluated ({drop.evidence}).", command)


def _frictional(ctx: Context) -> str:
    """The frictional system's name (for a diagnostic of that system)."""
    return ctx.frictional


def _frictionless(ctx: Context) -> str:
    """The frictionless system's name (for a diagnostic of that system)."""
    return ctx.frictionless


# Causes, measured in docs/p2_sampling.md: the distances at four wall speeds and five sampling steps (one
# realization of 400 disks), and P2's own setting run once per system ("paper size": 2025 disks, v_c = 2.5e-5,
# 100 samples; config/paper.yaml with one realization). "Small system" means the claim holds at paper size;
# "not a small-system effect" that it fails there too.
_PAPER = "docs/p2_sampling.md, paper size"
_AT_JAMMING = ("Not a small-system effect: P2's states near rho = 0.79 look alike ('Z and the average force almost "
               "identical'), i.e. they are jammed, and ours at 0.79 are not (rho_J 0.80, also at paper size; "
               f"{_PAPER}); the first three jammed samples (the table's states a, b, c) lie at the transition itself, "
               "where Z and the forces still change fast.")
# the floor as the cause put to the test: the control of docs/validation/controls.md §3 demonstrates or refutes it
_NEVER_DYING = ("The never-dying floor, put to the test by the control below: after rho_J most consecutive pairs "
                "change the number of never-dying classes (rattlers joining, defect loops opening or closing as "
                "contacts form), and under P2's death -1 each costs d_B >= 0.5, a floor the force changes alone "
                f"(d_B ~ 0.03-0.1) stay far below; at paper size such changes are more frequent, not less ({_PAPER}).")
# without the never-dying classes there is no finite loop before jamming (scripts/p2_finite_loops.py)
_NO_FINITE_LOOPS = (" Without the never-dying classes there is almost no finite loop before jamming "
                    "(docs/validation/controls.md §3), so the control tests the beta0 part alone.")
# The commands that measured a cause (the basis column of the table); a cause with none is a hypothesis.
SAMPLING = "python scripts/p2_sampling.py (docs/p2_sampling.md)"
CAMPAIGN = "snakemake validation_report --configfile config/validation.yaml (docs/validation/p2.md)"
THIS_TABLE = "snakemake p2_validation (its diagnostics, 'Measured here')"
DROP_CONTROL = "snakemake p2_validation (the rows of the reading with never-dying classes left out)"
HYPOTHESIS_ONLY = ""
#: why each claim may not hold: {claim id: (cause, the command that measured it or HYPOTHESIS_ONLY, diagnostics
#: measured on the data)}
EXPLANATIONS: dict[str, tuple[str, str, tuple[Callable[[Context], str], ...]]] = {
    "III.D-1": (_AT_JAMMING, THIS_TABLE, (_table_state_diagnostic,)),
    "III.D-2": (_AT_JAMMING, THIS_TABLE, (_table_state_diagnostic,)),
    "III.D-3": (_AT_JAMMING + " At the transition the (a,b) changes are system-wide, not in one quadrant.",
                THIS_TABLE, (_table_state_diagnostic,)),
    "III.D-4": (_AT_JAMMING, THIS_TABLE, (_table_state_diagnostic,)),
    "IV.A-1": ("Few realizations: each realization's d_W1 peaks near its own rho_J, but the rho_J scatter and the "
               f"peak of a mean of 3 blurs; one paper-size realization holds ({_PAPER}).",
               HYPOTHESIS_ONLY,
               (_argmax_per_realization(_frictional, 0, W1), _argmax_per_realization(_frictional, 1, W1))),
    "IV.A-2": ("Small system: the largest single change before jamming grows with the number of contacts, d_B "
               f"(beta0) ~ 3 <F> with 400 disks and 8.8 <F> with 2025 (holds at paper size; {_PAPER}).", SAMPLING, ()),
    "IV.A-3": ("Sampling: the ratio needs P2's rule (rattlers kept) and step; with rattlers removed d_B/d_W1 is "
               "~0.5 and d_B/d_W2 ~0.8 (docs/p2_sampling.md, rattler rule).", SAMPLING, ()),
    "IV.A-4": ("Sampling and realizations: the ratio scatters from state to state (at paper size its median is "
               f"0.17 but CV 0.64 > 0.5 in one realization; {_PAPER}); with rattlers removed it is ~0.5 "
               "(docs/p2_sampling.md).", SAMPLING, ()),
    "IV.A-5": (f"Not a small-system effect (paper size: d_B 9.7 -> 6.8, needs a factor 2; {_PAPER}). It holds "
               "at paper size if rho is measured in the box between the wall-particle centres (rho_J would read "
               "0.767; docs/p2_sampling.md, rho scale): P2 does not say how it measures rho between rough walls.",
               SAMPLING, (_argmax_per_realization(_frictional, 0, B),)),
    "IV.A-6": ("Not a small-system effect (paper size: Spearman 0.38; "
               f"{_PAPER}): d_W1 rises from 0.75 but peaks up to 0.03 before rho_J and falls into it.",
               SAMPLING, (_argmax_per_realization(_frictional, 0, W1),)),
    "IV.A-7": ("Few realizations: the plateau and the plunge hold at paper size (one realization; "
               f"{_PAPER}).", HYPOTHESIS_ONLY, ()),
    "IV.A-8": ("Small system and slow compression: with 400 disks there are no loops before rho ~ 0.75 (beta1 "
               "distances 0) and single events decide the trend; one paper-size realization shows no trend either "
               f"(Spearman ~0; {_PAPER}).",
               SAMPLING, (_argmax_per_realization(_frictional, 1, B),)),
    "IV.A-9": ("Few realizations: single early loop events can make the largest beta1 d_B of a 3-realization mean; "
               f"paper size peaks at 0.791 (holds; {_PAPER}).", HYPOTHESIS_ONLY,
               (_argmax_per_realization(_frictional, 1, B),)),
    "IV.A-10": (f"Few realizations: holds at paper size ({_PAPER}).", HYPOTHESIS_ONLY, ()),
    "IV.A-11a": (_NEVER_DYING + " The rates are compared with those just before jamming ([rho_J - 0.05, rho_J)), "
                 "where the loops already change; the beta1 d_B after jamming sits on that floor." + _NO_FINITE_LOOPS,
                 THIS_TABLE, (_never_dying_events(_frictional, 1, "after"),)),
    "IV.A-11b": (_NEVER_DYING + " Without friction the beta1 d_W1 and d_W2 rise after jamming instead of "
                 "falling: before it almost every loop is a never-dying class, after it finite loops form and fill; "
                 "beta0 d_W1 falls less than the judge's 10x (this row's evidence)." + _NO_FINITE_LOOPS,
                 THIS_TABLE,
                 (_never_dying_events(_frictionless, 0, "after"), _never_dying_events(_frictionless, 1, "after"))),
    "IV.A-12a": (_NEVER_DYING + " d_B after jamming sits on that floor, so d_B/d_W1 cannot fall 3 decades.",
                 THIS_TABLE, (_never_dying_events(_frictional, 0, "after"),)),
    "IV.A-12b": ("Both sides of the quotient are the floor's: after jamming the beta1 d_B sits on it (measured "
                 "below), and before jamming almost every loop is a never-dying class (docs/validation/controls.md "
                 "§3), so the control leaves no finite beta1 ratio below rho = 0.75 to compare; what the ratio would "
                 "do without the floor is not measured.",
                 HYPOTHESIS_ONLY, (_never_dying_events(_frictional, 1, "after"),)),
    "IV.B-1": (f"Few realizations: holds at paper size ({_PAPER}).", HYPOTHESIS_ONLY, ()),
    "IV.B-2": ("Not a small-system effect: at paper size the tangential and normal curves differ as little near "
               f"rho_J as elsewhere ({_PAPER}); not reproduced.", SAMPLING, ()),
    "IV.B-3": ("Not a small-system effect: at paper size tangential/normal d_W1 and d_W2 near rho_J are 1.0 "
               f"({_PAPER}). No cause measured.", HYPOTHESIS_ONLY, ()),
    "IV.B-4": (f"Few realizations: holds at paper size ({_PAPER}).", HYPOTHESIS_ONLY, ()),
    "IV.C-1": (f"Holds at every size and speed measured ({_PAPER}).", SAMPLING, ()),
    "IV.C-2": ("Sampling: below rho = 0.65 there are 7 states with almost no contacts (Z < 0.4), so the distances "
               "count single collisions and rattlers joining and leaving; also fails at paper size (d_B 1.7, d_W1 "
               f"0.36, d_W2 1.1; {_PAPER}).", SAMPLING, ()),
    "IV.C-3": ("Not a small-system effect: at paper size d_B/d_W1 is larger without friction at 43 % of the "
               f"points, as here ({_PAPER}).", SAMPLING, ()),
    "IV.C-4": ("Not a small-system effect: at paper size both systems' d_B and d_W2 peak 0.035 below their "
               f"rho_J ({_PAPER}).",
               SAMPLING, (_argmax_per_realization(_frictional, 0, B), _argmax_per_realization(_frictionless, 0, B))),
    "IV.C-5": ("Small system: with 400 disks neither system has loops well before jamming (beta1 distances 0: "
               f"nothing to compare); holds at paper size ({_PAPER}).", SAMPLING, ()),
    "IV.C-6": ("Not a small-system effect: at paper size the largest beta1 changes near rho_J are alike with and "
               f"without friction (0.93-1.3; {_PAPER}).", SAMPLING, ()),
    "IV.C-7": ("Two parts, each measured. d_B: after jamming nearly every consecutive pair of both systems changes "
               "its number of never-dying loops, each costing d_B >= 0.5 under P2's death -1, so both d_B sit on "
               "that floor and their quotient is ~1 (measured below; the control's row beside gives it without the "
               "never-dying classes). d_W1: the judge compares at equal rho beyond both rho_J, where the "
               "frictionless system, jamming later, is still nearer its transition; at equal depth above each "
               "system's own rho_J its d_W1 and d_W2 quotients are about P2's 2 (measured below).",
               THIS_TABLE,
               (_never_dying_events(_frictional, 1, "after"), _never_dying_events(_frictionless, 1, "after"),
                _at_equal_depth(1))),
    "IV.C-8a": ("Without friction loops exist only from jamming on, and the frictionless system jams later (rho_J "
                "0.832 against 0.803): over all states its median PD1 count is 1.1 against 7.2, while over the states "
                "beyond both rho_J it has more loops (IV.C-8b: median 1350 against 1293 normal-force PD1 points per "
                "state), as P2 says (forcenet.report.p2.diagram_point_counts on the campaign's diagrams.nc).",
                CAMPAIGN, ()),
    "IV.C-8b": ("Over all states the frictionless system's median PD1 count is 1.1 against 7.2, over the states beyond "
                "both rho_J 1350 against 1293 normal-force PD1 points per state (forcenet.report.p2.diagram_point_"
                "counts on the campaign's diagrams.nc); a miss beyond both rho_J is not measured.", HYPOTHESIS_ONLY,
                ()),
    "IV.C-9": (_NEVER_DYING + " The d_B part of both quotients sits on that floor; not measured further.",
               HYPOTHESIS_ONLY, ()),
    "V-1": ("Not a few-realization effect: it fails with 2, 3, 5 and 20 paper-size realizations (robustness 0.2 with 5, "
            "0.01 with P2's 20); "
            "the d_B and d_W2 peaks before jamming are as high or higher without friction (docs/validation/p2.md); "
            "no cause measured.", HYPOTHESIS_ONLY, ()),
    "V-2": ("Not a small-system effect: after jamming the frictionless packing keeps changing 2-4x more (d_W1, "
            f"d_W2; paper size 3.1 and 2.2, d_B 1.0; {_PAPER}). Part of it is where the judge compares, at equal rho "
            "beyond both rho_J, where the frictionless system is nearer its later jamming: at equal depth above each "
            "system's own rho_J the quotients come closer to 1 (measured below); what keeps d_W1 apart is not "
            "measured.",
            HYPOTHESIS_ONLY, (_never_dying_events(_frictional, 0, "after"), _never_dying_events(_frictionless, 0, "after"),
                              _at_equal_depth(0))),
}
