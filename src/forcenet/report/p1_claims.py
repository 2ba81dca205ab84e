"""P1's claims about its protocol (§3), the force distribution, percolation and jamming (§4, and what §6 concludes
from them): one `forcenet.report.claims.Claim` record and one judging function each, registered in `CLAIMS` in
definition order. The claims about the topology (§5) are in `forcenet.report.p1_claims_topology`; the table that
judges both lists is `forcenet.report.p1_validation`.

A per-system judge takes (`SystemData`, `ClaimTolerances`), a cross-system judge (``per_system=False``) the
`ClaimContext`; each returns a `Judgement` or raises `NotEvaluated`. Criteria are templates whose ``{field}`` names
are tolerances of `ClaimTolerances`.
"""
from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import xarray as xr

from forcenet.report.claims import (Claim, ClaimTolerances, Judgement, NotEvaluated, claim_register,
                                    contrast_margin, relative_margin, smallest_margin)
from forcenet.report.p1 import (HERTZ_2D, HERTZ_3D, LINEAR_2D, P1_HALF, P1_LARGE_THRESHOLD, P1_PERCOLATION_MAJORITY,
                                P1_SMALL_THRESHOLD, PAPER_CLUSTER_SIZE_PEAK, PAPER_PHI_C, PAPER_RHO_J_BY_ROLE,
                                PAPER_RHO_MAX_BY_ROLE,
                                PAPER_Z_AT_JAMMING, value_at, finite_max, force_bins, percolation_fraction,
                                rho_values, select_total, system_friction, system_particles,
                                system_relaxation_criterion, system_relaxation_tolerance, up_to_rho_max)
from forcenet.report.p1_diagnostics import size_peak_threshold_per_rho
from forcenet.report.p1_judging import (ALL_2D, ClaimContext, SystemData, expected_for_law, finite_values, fmt_values,
                                        peak_verdict, require, strongest_peak)
from forcenet.report.realizations import realization_mean
from forcenet.systems import KINETIC_ENERGY_FLUCTUATION

CLAIMS: list[Claim] = []
claim = claim_register(CLAIMS)


# --- §3 Protocol and methods ------------------------------------------------------------------------------------
@claim("p1-3-clusters-below-jamming", "3",
       "a relatively small but non-vanishing number of clusters below jamming, in particular in 2D (Figs. 2, 4, 6)",
       "at F_th = min: max over {below_cut} of the mean cluster count >= {min_clusters}, and its B0/N <= the "
       "largest mean B0/N (any F_th) beyond rho_J + tol", scope=ALL_2D)
def clusters_below_jamming(system: SystemData, tolerances: ClaimTolerances) -> Judgement:
    """Judge of claim p1-3-clusters-below-jamming (per system)."""
    below = require(system.below, "rho below rho_J")
    beyond = require(system.beyond, "rho beyond rho_J")
    count = system.mean("cluster_count", per_n=False, threshold=system.lowest_threshold).values
    share = system.mean("cluster_count", threshold=system.lowest_threshold).values
    most_below, share_below = finite_max(count[below]), finite_max(share[below])
    share_beyond = finite_max(system.mean("cluster_count").transpose("rho", "threshold").values[beyond])
    holds = most_below >= tolerances.min_clusters and share_below <= share_beyond
    evidence = (f"mean clusters at F_th={system.lowest_threshold:.3g} below rho_J: {fmt_values(count[below])} "
                f"(B0/N up to {share_below:.3g}); largest B0/N beyond rho_J {share_beyond:.3g} ({system.label()})")
    return Judgement(most_below, evidence, bool(holds),
                     margin=smallest_margin(relative_margin(most_below, tolerances.min_clusters),
                                            contrast_margin(share_below, share_beyond)),
                     states=system.states(below))


#: P1's own depth above jamming: the smallest of P1's ρ_max − ρ_J (0.890 − 0.834 = 0.056, 2D linear; 0.064 2D
#: Hertz, 0.14 3D), the depth every P1 system reaches; "at the largest ρ" (P1 §3) is judged there
P1_OVERLAP_DEPTH = round(min(PAPER_RHO_MAX_BY_ROLE[role] - PAPER_RHO_J_BY_ROLE[role]
                             for role in (LINEAR_2D, HERTZ_2D, HERTZ_3D)), 6)


@claim("p1-3-overlap", "3", "at the largest rho the particles overlap by up to 10 % of the sum of the radii",
       lambda t: (f"largest overlap / (r_i + r_j) over the snapshots at the state nearest P1's own depth above "
                  f"jamming, rho_J + {P1_OVERLAP_DEPTH if t.overlap_depth is None else t.overlap_depth:g} (P1's "
                  f"smallest rho_max - rho_J), within one grid step of it: <= {t.overlap_bound}"),
       needs_rho_j=False)
def overlap_up_to_bound(system: SystemData, tolerances: ClaimTolerances) -> Judgement:
    """Judge of claim p1-3-overlap (per system), on the overlaps measured in the snapshots (`SystemData.overlaps`,
    {ρ: largest relative overlap}): P1's "at the largest ρ" is the state P1's depth above jamming reaches
    (`P1_OVERLAP_DEPTH` above ρ_J, our grid going further), with the tolerance of one grid step: the measured state
    nearest ρ_J + depth, at most one step from it. Marginal also when another measured state within one step of
    it lies on the other side of the bound."""
    measured = {rho: value for rho, value in system.overlaps.items() if np.isfinite(value)}
    if not measured:
        raise NotEvaluated("no snapshot overlaps given (the overlaps are in the snapshots, not the network measures)")
    if not np.isfinite(system.rho_j):
        raise NotEvaluated("rho_J could not be located: P1's depth above jamming has no state")
    depth = P1_OVERLAP_DEPTH if tolerances.overlap_depth is None else tolerances.overlap_depth
    target, step = system.rho_j + depth, system.step
    nearest = min(measured, key=lambda rho: (abs(rho - target), rho))
    if abs(nearest - target) > step + 1e-9:
        raise NotEvaluated(f"overlaps measured at rho {fmt_values(sorted(measured))}; P1's depth above jamming puts "
                           f"the bound at rho {target:.3f} (rho_J + {depth:g}, {system.label()}): no measured state "
                           f"within one grid step ({step:.3g}) of it")
    value = measured[nearest]
    holds = value <= tolerances.overlap_bound
    turns = [rho for rho, other in measured.items() if rho != nearest and abs(rho - target) <= step + 1e-9
             and (other <= tolerances.overlap_bound) != holds]
    evidence = (f"largest overlap at rho={nearest:.3f} (rho_J + {depth:g} = {target:.3f}): {100 * value:.2f} % of the "
                f"sum of the radii ({system.name})"
                + "".join(f"; {100 * measured[rho]:.2f} % at rho={rho:.3f}" for rho in sorted(measured)
                          if rho != nearest))
    return Judgement(value, evidence, bool(holds), margin=relative_margin(value, tolerances.overlap_bound),
                     grid_step=bool(turns), states=f"rho {nearest:.3f}")


def _same_verdicts(context: ClaimContext, pairs: list[tuple[SystemData, SystemData]], what: str,
                   missing: str) -> Judgement:
    """P1 §3's "qualitatively the same": every per-system claim judged on both systems of each pair (each on its
    own ρ_J), the share with the same verdict ≥ same_verdicts; not evaluated, for the reason `missing`, without a
    pair."""
    if not pairs:
        raise NotEvaluated(missing)
    if not context.claims:
        raise NotEvaluated("no claims handed to the context to compare the runs with")
    same, differing = 0, []
    for reference, other in pairs:
        for judged in context.claims:
            if not judged.per_system or (judged.scope is not None and reference.role not in judged.scope):
                continue
            verdicts = []
            for system in (reference, other):
                try:
                    verdicts.append(judged.judge(system, context.tolerances).holds)
                except NotEvaluated:
                    break
            if len(verdicts) < 2:
                continue
            if verdicts[0] == verdicts[1]:
                same += 1
            else:
                differing.append(f"{judged.id} ({other.name})")
    compared = same + len(differing)
    if compared == 0:
        raise NotEvaluated(f"no claim judged on both runs of {what}")
    share = same / compared
    evidence = (f"{what}: " + ", ".join(f"{a.name} (rho_J={a.rho_j:.3f}) vs {b.name} (rho_J={b.rho_j:.3f})"
                                         for a, b in pairs)
                + f"; same verdict for {same} of {compared} per-system claims"
                + (f"; different: {', '.join(differing)}" if differing else ""))
    one_run = tuple(dict.fromkeys(other.name for _, other in pairs if other.full.sizes.get("realization", 1) == 1))
    return Judgement(share, evidence, share >= context.tolerances.same_verdicts,
                     margin=relative_margin(share, context.tolerances.same_verdicts), one_run=one_run)


def _counterparts(context: ClaimContext, roles, differs) -> list[tuple[SystemData, SystemData]]:
    """(P1's system, another run of the same role) for each role of `roles` present, the other run chosen by
    `differs(reference, other)` (a located ρ_J on both)."""
    pairs = []
    for role in roles:
        try:
            reference = context.role(role)
        except NotEvaluated:
            continue
        pairs += [(reference, other) for other in context.systems.values()
                  if other.name != reference.name and other.role == role and np.isfinite(other.rho_j)
                  and differs(reference, other)]
    return pairs


@claim("p1-3-system-size", "3",
       "the results stay qualitatively the same for 25x25 and 75x75 boxes (2D; one realization each at P1's "
       "protocol is within reach)",
       "for each 2D system with a run of another particle number (same friction): the same verdict for >= "
       "{same_verdicts} of the per-system claims judged on both", per_system=False, needs_rho_j=False)
def system_size(context: ClaimContext) -> Judgement:
    """Judge of claim p1-3-system-size (across systems): P1's 2D systems against runs of other sizes."""
    pairs = _counterparts(context, ALL_2D, lambda a, b: system_particles(a.full) != system_particles(b.full)
                          and system_friction(a.full, a.name) == system_friction(b.full, b.name))
    return _same_verdicts(context, pairs, "other box sizes", "needs a 25 x 25 or 75 x 75 run (one realization at "
                          "P1's protocol) of a 2D P1 system beside the 50 x 50 one: not in these results")


@claim("p1-3-system-size-3d", "3", "the results stay qualitatively the same for 10^3 and 30^3 spheres (3D)",
       "for 3D Hertz with runs of both fewer and more spheres beside it (same friction), as P1 names both: the same "
       "verdict for >= {same_verdicts} of the per-system claims judged on both runs of each pair",
       per_system=False, needs_rho_j=False)
def system_size_3d(context: ClaimContext) -> Judgement:
    """Judge of claim p1-3-system-size-3d (across systems): P1's 3D system against runs of fewer and of more
    spheres (P1 §3: 10³ and 30³); not evaluated until both sides exist."""
    pairs = _counterparts(context, (HERTZ_3D,), lambda a, b: system_particles(a.full) != system_particles(b.full)
                          and system_friction(a.full, a.name) == system_friction(b.full, b.name))
    sizes = sorted(system_particles(other.full) for _, other in pairs)
    if pairs:
        reference = system_particles(pairs[0][0].full)
        if not (sizes[0] < reference < sizes[-1]):
            raise NotEvaluated(f"P1 compares 10^3 and 30^3 spheres: needs runs of both fewer and more than "
                               f"{reference} spheres beside 3D Hertz; these results have N = "
                               f"{', '.join(str(n) for n in sizes)}")
    return _same_verdicts(context, pairs, "other numbers of spheres", "needs runs of 10^3 and 30^3 spheres (one "
                          "realization each at P1's protocol) beside the 3D Hertz one: not in these results")


@claim("p1-3-friction", "3",
       "friction (mu = 0, 0.03, 0.5) changes only rho_J and the precise values (also §6)",
       "for each P1 system with a mu = 0 run beside it (same N): the same verdict, each on its own rho_J, for "
       ">= {same_verdicts} of the per-system claims judged on both", per_system=False, needs_rho_j=False)
def friction_changes_only_rho_j(context: ClaimContext) -> Judgement:
    """Judge of claim p1-3-friction (across systems): P1's frictional systems against their μ = 0 runs."""
    pairs = _counterparts(context, (HERTZ_2D, LINEAR_2D, HERTZ_3D),
                          lambda a, b: system_friction(a.full, a.name) > 0 and system_friction(b.full, b.name) == 0
                          and system_particles(a.full) == system_particles(b.full))
    return _same_verdicts(context, pairs, "mu = 0 against mu > 0", "needs the mu = 0 run of a P1 system beside "
                          "the frictional one (the paper-size mu = 0 pair): not in these results")


@claim("p1-3-relaxation", "3", "stricter or other relaxation criteria change neither conclusions nor measured values",
       "for each P1 system with a run beside it (same N and mu) relaxed to a smaller kinetic-energy tolerance or by "
       "P1's contact-number criterion (the contact number unchanged over a window): the same verdict, each on its "
       "own rho_J, for >= {same_verdicts} of the per-system claims judged on both, and |rho_J(other) - rho_J| <= "
       "half the rho step (rho_j_shift)", per_system=False, needs_rho_j=False)
def stricter_relaxation_changes_nothing(context: ClaimContext) -> Judgement:
    """Judge of claim p1-3-relaxation (across systems): P1's systems against runs relaxed to a smaller tolerance
    on std(E_kin)/mean(E_kin) (P1 §3: "a more strict relaxation condition does not change our conclusions, nor
    ... the measured quantities significantly") or by the contact-number protocol P1 §3 also ran ("such a protocol
    does not influence the results presented in this paper")."""
    def relaxed(data: SystemData) -> tuple[str, float]:
        return (system_relaxation_criterion(data.full, data.name),
                system_relaxation_tolerance(data.full, data.name))

    def stricter_or_other(a: SystemData, b: SystemData) -> bool:
        (criterion_a, tolerance_a), (criterion_b, tolerance_b) = relaxed(a), relaxed(b)
        return ((criterion_b != criterion_a or tolerance_b < tolerance_a)
                and system_friction(a.full, a.name) == system_friction(b.full, b.name)
                and system_particles(a.full) == system_particles(b.full))

    def described(other: SystemData, reference: SystemData) -> str:
        (criterion, tolerance), (criterion_ref, tolerance_ref) = relaxed(other), relaxed(reference)
        if criterion == criterion_ref == KINETIC_ENERGY_FLUCTUATION:
            return f"tolerance {tolerance:g} against {tolerance_ref:g}"
        return " against ".join(f"tolerance {t:g}" if c == KINETIC_ENERGY_FLUCTUATION else c.replace("_", " ")
                                for c, t in ((criterion, tolerance), (criterion_ref, tolerance_ref)))

    pairs = _counterparts(context, (HERTZ_2D, LINEAR_2D, HERTZ_3D), stricter_or_other)
    verdicts = _same_verdicts(context, pairs, "stricter or other relaxation against P1's", "needs a run relaxed to "
                              "a smaller tolerance or by another criterion beside a P1 system (same N and mu): not "
                              "in these results")
    shifts, margins, within = [], [verdicts.margin], True
    for reference, other in pairs:
        allowed = context.tolerances.rho_j_shift
        allowed = reference.step / 2 if allowed is None else allowed
        shift = other.rho_j - reference.rho_j
        within = within and abs(shift) <= allowed + 1e-12
        margins.append(relative_margin(abs(shift), allowed))
        shifts.append(f"{other.name} ({described(other, reference)}) {shift:+.4f}, "
                      f"allowed {allowed:.4f}")
    return Judgement(verdicts.measured, f"{verdicts.evidence}; rho_J shift: {'; '.join(shifts)}",
                     verdicts.holds and within, margin=smallest_margin(*margins), one_run=verdicts.one_run)


# --- §4 Force distribution, percolation and jamming -------------------------------------------------------------
@claim("p1-4-percolation-at-jamming", "4",
       "a stable percolating cluster forms for any and only when rho > rho_J: rho_p = rho_J",
       "rho_p = first rho where >= 50 % of the realizations percolate at F_th = min; |rho_p - rho_J| <= tol and "
       "the majority percolates at every rho > rho_J + tol")
def percolation_at_jamming(system: SystemData, tolerances: ClaimTolerances) -> Judgement:
    """Judge of claim p1-4-percolation-at-jamming (per system)."""
    fraction = percolation_fraction(system.data).sel(threshold=system.lowest_threshold).values
    percolating = fraction >= P1_PERCOLATION_MAJORITY
    if not percolating.any():
        return Judgement(math.nan, f"no rho where >= 50 % of the realizations percolate at F_th="
                                   f"{system.lowest_threshold:.3g} ({system.label()})", False)
    rho_p = float(system.rho[percolating].min())
    gaps = system.rho[system.beyond & ~percolating]
    holds = abs(rho_p - system.rho_j) <= system.tolerance + 1e-12 and gaps.size == 0
    evidence = (f"rho_p={rho_p:.3f}, {system.label()}, tolerance {system.tolerance:.3g}; fraction percolating "
                f"{fmt_values(fraction, 2)} at rho {fmt_values(system.rho)}"
                + (f"; no majority at rho {fmt_values(gaps)}" if gaps.size else ""))
    distance = abs(rho_p - system.rho_j)
    return Judgement(rho_p, evidence, bool(holds), margin=relative_margin(distance, system.tolerance),
                     grid_step=bool(abs(distance - system.tolerance) < system.step - 1e-12))


def _pdf_order(context: ClaimContext, rho_max_of, what: str) -> Judgement:
    """P1 §4.1's order of the force-PDF widths (2D linear < 2D Hertz < 3D) at each system's largest ρ ≤
    ``rho_max_of(system)``: std of F/⟨F⟩, realization mean."""
    widths = []
    for role in (LINEAR_2D, HERTZ_2D, HERTZ_3D):
        system = context.role(role)
        rho_max = rho_max_of(system)
        if not np.isfinite(rho_max):
            raise NotEvaluated(f"{what} of {system.name} undefined")
        every_width = system.pdf_width(full=True)
        top = np.flatnonzero(up_to_rho_max(rho_values(every_width), rho_max))[-1]  # the largest rho <= rho_max
        reached = float(every_width["rho"].values[top])
        if rho_max - reached > system.step + 1e-9:
            raise NotEvaluated(f"{system.name}'s grid ends at rho={reached:.3f}, more than one step below {what} "
                               f"{rho_max:.3f}")
        width = float(realization_mean(every_width.isel(rho=top)))
        widths.append((system.name, reached, width))
    if not all(np.isfinite(w) for _, _, w in widths):
        raise NotEvaluated("PDF width undefined (empty PDF)")
    holds = widths[0][2] < widths[1][2] < widths[2][2]
    evidence = f"std of F/<F> at the largest rho <= {what}: " + "; ".join(
        f"{name} {w:.3g} (rho={r:.3f})" for name, r, w in widths)
    margin = min(contrast_margin(widths[0][2], widths[1][2]), contrast_margin(widths[1][2], widths[2][2]))
    return Judgement(widths[2][2] - widths[0][2], evidence, holds, margin=margin,
                     states="; ".join(f"{name} rho {r:.3f}" for name, r, _ in widths))


@claim("p1-4.1-pdf-order-at-rho-max", "4.1",
       "at rho ~ rho_max the force PDF is narrowest for 2D linear, wider for 2D Hertz, widest in 3D (Fig. 3)",
       "std of F/<F> (mean over realizations) at each system's largest rho <= P1's rho_max (0.890 2D linear, 0.906 "
       "2D Hertz, 0.710 3D; within one grid step of it): 2D linear < 2D Hertz < 3D; the same order at our rho_max "
       "(F_max rule) given beside it in the evidence", per_system=False)
def pdf_order_at_rho_max(context: ClaimContext) -> Judgement:
    """Judge of claim p1-4.1-pdf-order-at-rho-max (across systems): P1's one sentence judged once, at the states P1
    shows (its printed ρ_max; our ρ_max under the F_max rule depends on the force unit, p1-3's values) with the
    order at our ρ_max as evidence beside."""
    paper = _pdf_order(context, lambda system: PAPER_RHO_MAX_BY_ROLE.get(system.role, math.nan), "P1's rho_max")
    try:
        ours = _pdf_order(context, lambda system: system.rho_max, "our rho_max")
        beside = f"{ours.evidence}: {'in' if ours.holds else 'not in'} that order"
    except NotEvaluated as reason:
        beside = f"at our rho_max: {reason}"
    return replace(paper, evidence=f"{paper.evidence}; {beside}")


def _jammed_pdf_width(system: SystemData) -> float:
    """Mean over ρ > ρ_J + tol of the realization-mean std of F/⟨F⟩ of one system."""
    beyond = require(system.beyond, f"rho beyond rho_J for {system.name}")
    width = realization_mean(system.pdf_width()).values
    return float(np.nanmean(finite_values(width[beyond], f"PDF width of {system.name} beyond rho_J")))


@claim("p1-5.3-pdf-wider-nonlinear", "5.3",
       "beyond jamming the force PDFs of the non-linear systems are wider than the linear one, in 2D and 3D "
       "(§4.1, §5.3, §6)",
       "mean std of F/<F> over rho > rho_J + tol: every non-linear system > 2D linear", per_system=False)
def pdf_wider_nonlinear(context: ClaimContext) -> Judgement:
    """Judge of claim p1-5.3-pdf-wider-nonlinear (across systems)."""
    linear = _jammed_pdf_width(context.role(LINEAR_2D))
    widths = {system.name: _jammed_pdf_width(system) for system in context.nonlinear()}
    lead = min(widths.values()) - linear
    evidence = (f"mean std of F/<F> beyond rho_J: 2D linear {linear:.3g}; "
                + ", ".join(f"{name} {w:.3g}" for name, w in widths.items()))
    return Judgement(lead, evidence, lead > 0, margin=contrast_margin(min(widths.values()), linear))


def _mean_pdf_below(system: SystemData) -> tuple[np.ndarray, np.ndarray]:
    """Mean PDF of F/⟨F⟩ over the realizations and the ρ below ρ_J, normalised over the bins:
    (bin centres, probability per bin)."""
    below = require(system.below, f"rho below rho_J for {system.name}")
    pdf = system.data["force_pdf"].isel(rho=np.flatnonzero(below)).mean(("realization", "rho"), skipna=True)
    centres, widths = force_bins(system.data)
    mass = np.asarray(pdf.values, dtype=float) * widths
    if not np.isfinite(mass).all() or mass.sum() <= 0:
        raise NotEvaluated(f"no force PDF below rho_J for {system.name}")
    return centres, mass / mass.sum()


@claim("p1-6-pdf-2d-3d-differ-below-jamming", "6",
       "at small rho the force distributions differ significantly between 2D and 3D systems",
       "total-variation distance between the mean PDFs of F/<F> over {below_cut} of 3D and of each 2D "
       "system >= {pdf_distance}", per_system=False)
def pdf_2d_3d_differ(context: ClaimContext) -> Judgement:
    """Judge of claim p1-6-pdf-2d-3d-differ-below-jamming (across systems)."""
    centres_3d, pdf_3d = _mean_pdf_below(context.role(HERTZ_3D))
    distances = {}
    for role in ALL_2D:
        system = context.role(role)
        centres, pdf = _mean_pdf_below(system)
        if centres.shape != centres_3d.shape or not np.allclose(centres, centres_3d):
            raise NotEvaluated("the systems' force PDFs have different bins")
        distances[system.name] = 0.5 * float(np.abs(pdf - pdf_3d).sum())
    smallest = min(distances.values())
    evidence = "total-variation distance to 3D below rho_J: " + ", ".join(f"{n} {d:.3g}" for n, d in distances.items())
    states = "; ".join(f"{system.name} {system.states(system.below)}" for system in
                       (context.role(HERTZ_3D), *(context.role(role) for role in ALL_2D)))
    return Judgement(smallest, evidence, smallest >= context.tolerances.pdf_distance,
                     margin=relative_margin(smallest, context.tolerances.pdf_distance), states=states)


# --- §4.2 Non-percolating clusters ---------------------------------------------------------------------------
def _cluster_size_peak_threshold(system: SystemData) -> tuple[float, np.ndarray]:
    """Median over ρ > ρ_J + tol of the F_th where the mean ⟨S⟩/N is largest; and those F_th per ρ."""
    beyond = require(system.beyond, f"rho beyond rho_J for {system.name}")
    best = size_peak_threshold_per_rho(system).values[beyond]
    best = best[np.isfinite(best)]
    if best.size == 0:
        raise NotEvaluated(f"no clusters beyond rho_J for {system.name}")
    return float(np.median(best)), best


@claim("p1-4.2-cluster-size-peak-threshold", "4.2",
       "beyond jamming <S>/N is largest at F_th = 1.25 (2D linear), 1.5 (2D Hertz), ~2.0 (3D)",
       "median over rho > rho_J + tol of the F_th maximising the mean <S>/N within {threshold_tolerance} of P1's",
       paper=PAPER_CLUSTER_SIZE_PEAK)
def cluster_size_peak_threshold(system: SystemData, tolerances: ClaimTolerances) -> Judgement:
    """Judge of claim p1-4.2-cluster-size-peak-threshold (per system)."""
    paper = PAPER_CLUSTER_SIZE_PEAK.get(system.role, math.nan)
    if not np.isfinite(paper):
        raise NotEvaluated(f"P1 gives no value for a {system.dimension}D {system.force_law} system")
    median, best = _cluster_size_peak_threshold(system)
    evidence = (f"F_th of the largest <S>/N at each rho beyond rho_J: {fmt_values(best)} ({system.label()}); "
                f"P1 {paper:g}")
    distance = abs(median - paper)
    return Judgement(median, evidence, distance <= tolerances.threshold_tolerance + 1e-12,
                     margin=relative_margin(distance, tolerances.threshold_tolerance),
                     grid_step=_one_threshold_step(system, distance, tolerances.threshold_tolerance))


def _one_threshold_step(system: SystemData, distance: float, limit: float) -> bool:
    """True when an F_th `distance` lies within one step of the F_th grid of the `limit` it is compared with: the
    verdict turns if the maximum moves by one threshold (marginal)."""
    step = float(np.median(np.diff(system.thresholds))) if system.thresholds.size > 1 else 0.0
    return bool(abs(distance - limit) < step - 1e-12)


def _cluster_size_decay(system: SystemData) -> float:
    """Mean over ρ > ρ_J + tol of (mean ⟨S⟩/N over F_th ≥ 2) / (max ⟨S⟩/N over F_th)."""
    beyond = require(system.beyond, f"rho beyond rho_J for {system.name}")
    size = system.mean("cluster_mean_size").transpose("rho", "threshold").values[beyond]
    large = system.thresholds >= P1_LARGE_THRESHOLD - 1e-12
    if not large.any():
        raise NotEvaluated("no F_th >= 2")
    with np.errstate(invalid="ignore", divide="ignore"):
        ratios = np.nanmean(size[:, large], axis=1) / np.nanmax(size, axis=1)
    return float(np.nanmean(finite_values(ratios, f"<S>/N of {system.name} beyond rho_J")))


@claim("p1-4.2-cluster-size-decays-faster-linear", "4.2",
       "in 2D beyond jamming, for F_th >= 2, <S>/N decays faster for the linear law than for the non-linear one",
       "mean over rho > rho_J + tol of (mean <S>/N over F_th >= 2) / (max over F_th): 2D linear < 2D Hertz",
       per_system=False)
def cluster_size_decays_faster_linear(context: ClaimContext) -> Judgement:
    """Judge of claim p1-4.2-cluster-size-decays-faster-linear (across systems)."""
    linear, hertz = _cluster_size_decay(context.role(LINEAR_2D)), _cluster_size_decay(context.role(HERTZ_2D))
    evidence = f"<S>/N at F_th >= 2 relative to its maximum: 2D linear {linear:.3g}, 2D Hertz {hertz:.3g}"
    return Judgement(hertz - linear, evidence, linear < hertz, margin=contrast_margin(linear, hertz))


@claim("p1-4.2-cluster-size-3d-larger-forces", "4.2",
       "3D networks hold more clusters of large forces: <S>/N peaks at a larger F_th than in 2D (also §6)",
       "median F_th of the <S>/N maximum beyond rho_J: 3D > 2D Hertz", per_system=False)
def cluster_size_3d_larger_forces(context: ClaimContext) -> Judgement:
    """Judge of claim p1-4.2-cluster-size-3d-larger-forces (across systems)."""
    three, _ = _cluster_size_peak_threshold(context.role(HERTZ_3D))
    two, _ = _cluster_size_peak_threshold(context.role(HERTZ_2D))
    return Judgement(three - two, f"F_th of the <S>/N maximum: 3D {three:.3g}, 2D Hertz {two:.3g}", three > two,
                     margin=contrast_margin(three, two))


@claim("p1-6-cluster-size-peak-small-threshold", "6",
       "<S>/N peaks close to jamming for small F_th ~ 0, for the non-linear laws only",
       "the strongest peak of mean <S>/N(rho) over F_th < 0.5 lies within tol of rho_J with prominence >= "
       "{min_prominence} of the largest <S>/N; present for Hertz, absent for linear")
def cluster_size_peak_small_threshold(system: SystemData, tolerances: ClaimTolerances) -> Judgement:
    """Judge of claim p1-6-cluster-size-peak-small-threshold (per system)."""
    expected = expected_for_law(system, nonlinear=True)
    size = system.mean("cluster_mean_size")
    small = system.thresholds[system.thresholds < P1_SMALL_THRESHOLD]
    if small.size == 0:
        raise NotEvaluated("no F_th < 0.5")
    found = strongest_peak(size, system, small, finite_max(size.values))
    peak, threshold = found if found else (None, None)
    return peak_verdict(peak, "<S>/N", system, tolerances, expected, threshold)


# --- §4.3 The percolating cluster -----------------------------------------------------------------------------
def _onset_share(system: SystemData) -> tuple[float, float]:
    """(ρ, N_per/N) at the first ρ where N_per/N is shown at F_th = min."""
    share = system.percolating_size().sel(threshold=system.lowest_threshold).values
    shown = np.isfinite(share)
    if not shown.any():
        raise NotEvaluated(f"{system.name} never percolates in >= 50 % of the realizations")
    first = int(np.flatnonzero(shown)[0])
    return float(system.rho[first]), float(share[first])


@claim("p1-4.3-percolating-almost-all-2d", "4.3",
       "in 2D at F_th ~ 0 the percolating cluster contains almost all the particles",
       "median N_per/N at F_th = min over rho > rho_J + tol (where shown) >= {almost_all}", scope=ALL_2D)
def percolating_almost_all(system: SystemData, tolerances: ClaimTolerances) -> Judgement:
    """Judge of claim p1-4.3-percolating-almost-all-2d (per system)."""
    beyond = require(system.beyond, "rho beyond rho_J")
    share = system.percolating_size().sel(threshold=system.lowest_threshold).values[beyond]
    values = finite_values(share, "N_per/N beyond rho_J")
    median = float(np.median(values))
    evidence = f"N_per/N at F_th={system.lowest_threshold:.3g} beyond rho_J: {fmt_values(values)} ({system.label()})"
    return Judgement(median, evidence, median >= tolerances.almost_all,
                     margin=relative_margin(median, tolerances.almost_all))


@claim("p1-4.3-percolating-significant-2d", "4.3",
       "in 2D, whenever a percolating cluster exists it holds a significant share of the particles, often at "
       "least half (also §6)",
       "median of N_per/N over every shown (rho, F_th) >= 0.5 (P1: 'often at least half')", scope=ALL_2D)
def percolating_significant(system: SystemData, tolerances: ClaimTolerances) -> Judgement:
    """Judge of claim p1-4.3-percolating-significant-2d (per system)."""
    values = finite_values(system.percolating_size().values, "N_per/N")
    median = float(np.median(values))
    evidence = (f"N_per/N over {values.size} shown (rho, F_th): min {values.min():.3g}, median {median:.3g}, "
                f"max {values.max():.3g} ({system.label()})")
    return Judgement(median, evidence, median >= P1_HALF, margin=relative_margin(median, P1_HALF))


@claim("p1-4.3-percolating-small-3d-near-jamming", "4.3",
       "in 3D near rho_J the percolating cluster contains only a very small share of the particles (also §6)",
       "N_per/N at F_th = min at the first shown rho (<= rho_J + tol) <= {small_share}", scope=(HERTZ_3D,))
def percolating_small_near_jamming(system: SystemData, tolerances: ClaimTolerances) -> Judgement:
    """Judge of claim p1-4.3-percolating-small-3d-near-jamming (per system)."""
    rho, share = _onset_share(system)
    if rho > system.rho_j + system.tolerance + 1e-12:
        raise NotEvaluated(f"percolation first shown at rho={rho:.3f}, beyond rho_J + tol ({system.label()})")
    evidence = f"N_per/N={share:.3g} at F_th={system.lowest_threshold:.3g}, rho={rho:.3f} ({system.label()})"
    return Judgement(share, evidence, share <= tolerances.small_share,
                     margin=relative_margin(share, tolerances.small_share))


@claim("p1-4.3-percolating-small-3d-large-threshold", "4.3",
       "in 3D the percolating cluster is a very small share of the particles for F_th > 2 (also §6)",
       "median N_per/N over shown (rho, F_th > 2) <= {small_share}", scope=(HERTZ_3D,), needs_rho_j=False)
def percolating_small_large_threshold(system: SystemData, tolerances: ClaimTolerances) -> Judgement:
    """Judge of claim p1-4.3-percolating-small-3d-large-threshold (per system)."""
    large = system.thresholds > P1_LARGE_THRESHOLD + 1e-12
    values = finite_values(system.percolating_size().values[:, large], "N_per/N at F_th > 2 (no percolation shown)")
    median = float(np.median(values))
    evidence = f"N_per/N at F_th > 2 over {values.size} shown (rho, F_th): median {median:.3g}, max {values.max():.3g}"
    return Judgement(median, evidence, median <= tolerances.small_share,
                     margin=relative_margin(median, tolerances.small_share))


@claim("p1-4.3-percolating-smaller-in-3d", "4.3",
       "near rho_J the percolating cluster is smaller (relative to N) in 3D than in 2D (Eq. 6: phi_c ~ 0.2 vs 0.5)",
       "N_per/N at F_th = min at the first shown rho: 3D < each 2D system", per_system=False)
def percolating_smaller_in_3d(context: ClaimContext) -> Judgement:
    """Judge of claim p1-4.3-percolating-smaller-in-3d (across systems)."""
    three = _onset_share(context.role(HERTZ_3D))[1]
    two = {context.role(role).name: _onset_share(context.role(role))[1] for role in ALL_2D}
    evidence = f"N_per/N at the percolation onset: 3D {three:.3g}; " + ", ".join(f"{n} {v:.3g}" for n, v in two.items())
    return Judgement(three / min(two.values()) if min(two.values()) > 0 else math.inf, evidence,
                     three < min(two.values()), margin=contrast_margin(three, min(two.values())))


def _z_at_jamming(system: SystemData) -> tuple[float, str]:
    """The mean contact number of the network P1 analyses (rattlers removed, where the measures hold it) at ρ_J,
    and which one it is."""
    name = "Z_no_rattlers" if "Z_no_rattlers" in system.full else "Z"
    z = value_at(system.full, name, system.rho_j)
    if not np.isfinite(z):
        raise NotEvaluated(f"{name} at rho_J undefined")
    return z, "rattlers excluded" if name == "Z_no_rattlers" else "all particles"


@claim("p1-4.3-contact-number-at-jamming", "4.3", "close to jamming <k> ~ 3 in 2D and ~ 6 in 3D",
       "mean Z of the network (rattlers excluded) at rho_J within {approx_fraction} of P1's value, relative",
       paper={role: PAPER_Z_AT_JAMMING[role[0]] for role in (HERTZ_2D, LINEAR_2D, HERTZ_3D)})
def contact_number_at_jamming(system: SystemData, tolerances: ClaimTolerances) -> Judgement:
    """Judge of claim p1-4.3-contact-number-at-jamming (per system)."""
    paper = PAPER_Z_AT_JAMMING.get(system.dimension, math.nan)
    z, which = _z_at_jamming(system)
    deviation = abs(z - paper) / paper
    return Judgement(z, f"Z ({which}) at {system.label()}: {z:.3g}; P1 {paper:g}",
                     deviation <= tolerances.approx_fraction,
                     margin=relative_margin(deviation, tolerances.approx_fraction))


@claim("p1-4.3-phi-c-at-jamming", "4.3", "phi_c = 1/(<k> - 1) ~ 0.5 in 2D and ~ 0.2 in 3D at rho_J (Eq. 6)",
       "1/(Z - 1) with the mean Z of the network (rattlers excluded) at rho_J within {approx_fraction} of P1's "
       "value, relative", paper={role: PAPER_PHI_C[role[0]] for role in (HERTZ_2D, LINEAR_2D, HERTZ_3D)})
def phi_c_at_jamming(system: SystemData, tolerances: ClaimTolerances) -> Judgement:
    """Judge of claim p1-4.3-phi-c-at-jamming (per system)."""
    paper = PAPER_PHI_C.get(system.dimension, math.nan)
    z, which = _z_at_jamming(system)
    if z <= 1:
        return Judgement(math.inf, f"Z ({which}) at {system.label()}: {z:.3g} <= 1: phi_c unbounded", False)
    phi_c = 1.0 / (z - 1.0)  # P1 Eq. 6 with <k^2> = <k>^2
    deviation = abs(phi_c - paper) / paper
    # beside it, the first jammed state's: ρ_J interpolates across the one-step jump of Z
    name = "Z_no_rattlers" if "Z_no_rattlers" in system.full else "Z"
    first = system.first_jammed
    z_first = value_at(system.full, name, first) if np.isfinite(first) else math.nan
    beside = (f"; at the first jammed state (rho={first:.3f}, after the jump of Z) Z {z_first:.3g}, phi_c "
              f"{1.0 / (z_first - 1.0):.3g}" if np.isfinite(z_first) and z_first > 1 else "")
    return Judgement(phi_c, f"phi_c = 1/(Z - 1) with Z ({which}) {z:.3g} at {system.label()}: {phi_c:.3g}{beside}; "
                            f"P1 {paper:g}", deviation <= tolerances.approx_fraction,
                     margin=relative_margin(deviation, tolerances.approx_fraction))


@claim("p1-4.3-phi-c-lower-bound", "4.3",
       "phi_c of Eq. 6 (<k^2> ~ <k>^2, so phi_c = 1/(Z - 1)) is a lower bound for N_per/N",
       "at F_th = min and every shown rho: N_per/N >= 1/(Z - 1), both averaged over the realizations that "
       "percolate", needs_rho_j=False)
def phi_c_lower_bound(system: SystemData, tolerances: ClaimTolerances) -> Judgement:
    """Judge of claim p1-4.3-phi-c-lower-bound (per system). Eq. 6 bounds the network that percolates, so Z is
    averaged over the same realizations as N_per/N: at a ρ where one realization has jammed and another has not,
    the mean Z over all of them would set a bound (1/(Z - 1) > 1 for Z < 2) that no percolating network can meet."""
    share = system.percolating_size().sel(threshold=system.lowest_threshold).values
    percolates = select_total(system.data)["percolates"].sel(threshold=system.lowest_threshold) > 0
    z = realization_mean(system.data["Z"].where(percolates)).transpose("rho").values
    shown = np.isfinite(share) & np.isfinite(z)
    if not shown.any():
        raise NotEvaluated("no percolation shown")
    with np.errstate(divide="ignore"):
        phi_c = np.where(z[shown] > 1, 1.0 / (z[shown] - 1.0), np.inf)  # P1 Eq. 6 with <k^2> = <k>^2
    excess = share[shown] - phi_c
    tightest = int(np.argmin(excess))
    evidence = (f"at rho {fmt_values(system.rho[shown])}: N_per/N {fmt_values(share[shown])} vs phi_c "
                f"{fmt_values(phi_c)} "
                f"({system.name})")
    return Judgement(float(excess.min()), evidence, bool(excess.min() >= 0),
                     margin=relative_margin(share[shown][tightest], phi_c[tightest]))
