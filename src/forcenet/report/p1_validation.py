"""P1's validation table: its numbers and claims beside what our runs show (``results/tables/p1_validation.{csv,md}``).

Rows of kind ``"value"`` set a measured number beside P1's without a criterion (F_max, ρ_max under each force
unit, ρ_J, Z at ρ_J, φ_c of P1 Eq. 6); rows of kind ``"claim"`` judge every claim of `CLAIMS` (the lists of
`forcenet.report.p1_claims` and `forcenet.report.p1_claims_topology`) with the framework of
`forcenet.report.claims`, which also writes the table. In the default build a column beside P1's values gives our
value at P1's sizes from the committed campaign table ``docs/validation/p1.csv`` (`write_p1_validation`).
"""
from __future__ import annotations

import math
import os
from dataclasses import dataclass, field, replace
from typing import Any, Callable, Iterable, Mapping, Sequence

import numpy as np
import pandas as pd
import xarray as xr

from forcenet.report import p1_claims, p1_claims_topology
from forcenet.report.claims import (BELOW_TOLERANCE, FAILS, IMPORTED_NOT_EVALUATED, NOT_EVALUATED, Claim,
                                    ClaimTolerances, Explanation, JudgeChange, JudgedClaim, Judgement, NotEvaluated,
                                    judge_claim, rows_beside, verdict_summary)
from forcenet.report.claims_table import (VERDICT_COLUMNS, TableLayout, TableSection, claims_frame,
                                          table_attribute, validation_markdown, with_paper_size,
                                          write_validation_table)
from forcenet.report.p1 import (DEFAULT_P1_FORCE_UNIT, P1_FORCE_UNITS, P1_RHO_STEP, P1_ROLES, PAPER_PHI_C,
                                PAPER_RHO_J_BY_ROLE, PAPER_RHO_MAX_BY_ROLE, PAPER_Z_AT_JAMMING, file_role, FMaxCut, cut_at_rho_max, f_max_cut,
                                isostatic_crossing, jamming_point, rho_values, select_total, never_dying_at_minus_one,
                                system_dimension, system_force_law, system_order, value_at)
from forcenet.report.p1_diagnostics import SHAPE_READINGS, with_shape_reading
from forcenet.report.judge_changes import P1_CHANGES
from forcenet.report.p1_explanations import explain
from forcenet.report.p1_judging import ClaimContext, SystemData
from forcenet.report.realizations import REALIZATION, bootstrap_draws, resample_realizations
from forcenet.systems import IMPORTED_FORCE_LAW

#: every claim of P1 §3–6, in the order the table lists them within a section
CLAIMS: list[Claim] = [*p1_claims.CLAIMS, *p1_claims_topology.CLAIMS]

#: the table's columns (CSV names → `JudgedClaim` fields)
P1_LAYOUT = TableLayout(columns={"kind": "kind", "id": "id", "section": "section", "item": "statement",
                                 "system": "system", "measured": "measured", "paper": "paper",
                                 "difference": "difference", "criterion": "criterion", "evidence": "evidence",
                                 **VERDICT_COLUMNS})
COLUMNS = tuple(P1_LAYOUT.columns)


@dataclass(frozen=True)
class Reading:
    """Another reading of P1 that the table judges beside its own conventions (issue 25).

    name : its label in the ``reading`` column; tolerances : `ClaimTolerances` fields it changes; measures : how it
    changes the measures ({system: dataset} → {system: dataset}; None: unchanged). A row of this reading is set
    beside a claim's primary row wherever the reading changes the claim's verdict, marker or key number."""

    name: str
    tolerances: Mapping[str, Any] = field(default_factory=dict)
    measures: Callable[[Mapping[str, xr.Dataset]], Mapping[str, xr.Dataset]] | None = None


def _cluster_mean_shape(measures: Mapping[str, xr.Dataset]) -> Mapping[str, xr.Dataset]:
    """The measures with S_p the mean over clusters (P1 §5.2's other reading), where the measures hold it."""
    return {name: with_shape_reading(ds, "cluster_mean") if SHAPE_READINGS["cluster_mean"] in ds else ds
            for name, ds in measures.items()}


NEVER_DYING_LEFT_OUT = "never-dying classes left out of TP and bins"  # the reading beside death -1

#: the readings every table judges beside its own: the older cut of "below jamming" one tolerance lower, and
#: S_p as the mean over clusters (pooled is P1's definition and primary). Readings that need other analyses (the
#: filled tetrahedra, never-dying classes left out) are given to `p1_validation` as `beside`.
P1_READINGS = (Reading(BELOW_TOLERANCE, tolerances={"below_cut": BELOW_TOLERANCE}),
               Reading("S_p mean over clusters", measures=_cluster_mean_shape))


def p1_validation(measures: Mapping[str, xr.Dataset], *, force_unit: str = DEFAULT_P1_FORCE_UNIT,
                  judge_up_to_rho_max: bool = False, readings: Sequence[Reading] = P1_READINGS,
                  beside: Mapping[str, Mapping[str, xr.Dataset]] | None = None, resamples: int = 0, seed: int = 0,
                  overlaps: Mapping[str, float | Mapping[float, float]] | None = None,
                  diagrams: Mapping[str, xr.Dataset] | None = None,
                  beside_diagrams: Mapping[str, Mapping[str, xr.Dataset]] | None = None,
                  counterparts: Sequence[str] = (), **tolerances) -> pd.DataFrame:
    """P1's numbers and claims beside what `measures` (system → network_measures dataset) shows.

    Rows of kind ``"value"``: F_max and per system ρ_max under each unit of `P1_FORCE_UNITS` (the one the figures
    use, `force_unit` = ``analysis.p1_force_unit``, is marked "[figures]"), ρ_J (inflection of mean Z), Z at ρ_J
    (all particles, and rattlers excluded), φ_c = 1/(Z(ρ_J) − 1) of P1 Eq. 6, ρ where Z = d + 1; with P1's value
    and measured − paper. Rows of kind ``"claim"``: one per claim of `CLAIMS` and system it is about (or one
    for a claim comparing systems), with P1's section, statement, the criterion, the key number (``measured``),
    the evidence and a verdict: ``holds`` / ``does not hold`` / ``not evaluated`` (a system, a quantity or a ρ
    range is missing; the evidence says which), its marker, the states that carry it and its robustness: the
    share of `resamples` bootstrap resamples of the realizations (seeded by `seed`;
    `forcenet.report.realizations.bootstrap_resamples`) under which it holds (NaN with `resamples` = 0 or one
    realization).

    Beside a claim's row stands its row under each of `readings` (`P1_READINGS`) and under each measures set of
    `beside` ({reading name: {system: dataset}}, e.g. the 3D measures with filled tetrahedra), wherever that reading
    changes its verdict, marker or key number; the ``reading`` column names it. A system a reading leaves out is
    judged on its primary measures under that reading (filling tetrahedra changes nothing in 2D).

    `diagrams` ({system: diagrams.nc}): the never-dying classes then enter TP_k and the PD0 bins at death −1
    (`never_dying_at_minus_one`, the papers' convention), the measures as stored (classes left out) beside; the
    measures of a reading of `beside` likewise, with that reading's diagrams (`beside_diagrams`, {reading name:
    {system: diagrams.nc}}) where it has its own.
    `overlaps` ({system: {ρ: largest overlap / sum of radii}} of its snapshots, `overlaps_by_state`, or {system:
    that overlap at its largest ρ}) judges P1 §3's "overlaps up to 10 %" at P1's depth above jamming (ρ_J + 0.056,
    within one grid step); without it, or without a state there, that claim is not evaluated.

    A claim whose judge changed after its verdicts were read (`forcenet.report.judge_changes.P1_CHANGES`) says so
    in the column ``judge_changed_after_reading``. A verdict resting on one run (the counterparts of P1 §3, or a
    system with one realization) says so in its robustness.

    `counterparts` (``studies.p1.counterparts``: the μ = 0 and box-size runs) are systems of `measures` that only
    the claims comparing systems see (P1 §3's friction and system-size claims): they get no row of their own and
    count in no verdict total.

    Claims are judged over every simulated ρ, or over ρ ≤ ρ_max (P1's shown range) with `judge_up_to_rho_max`;
    those P1 states at ρ_max (PDF order, B1 plateau) use ρ_max either way. `tolerances`: the fields of
    `ClaimTolerances` (documented there), e.g. ``rho_tolerance=0.03``.
    """
    if force_unit not in P1_FORCE_UNITS:
        raise ValueError(f"unknown P1 force unit {force_unit!r}; known: {', '.join(P1_FORCE_UNITS)}")
    tolerances_ = ClaimTolerances(**tolerances)
    present = {name: ds for name, ds in measures.items() if ds is not None}
    beside = {name: {**present, **{n: ds for n, ds in sets.items() if ds is not None}}
              for name, sets in (beside or {}).items()}
    if diagrams:
        def at_minus_one(sets: Mapping[str, xr.Dataset], diagrams_: Mapping[str, xr.Dataset]):
            return {name: never_dying_at_minus_one(ds, diagrams_[name]) if name in diagrams_ else ds
                    for name, ds in sets.items()}

        beside = {name: at_minus_one(sets, {**diagrams, **(beside_diagrams or {}).get(name, {})})
                  for name, sets in beside.items()}
        beside = {NEVER_DYING_LEFT_OUT: present, **beside}
        present = at_minus_one(present, diagrams)
    # imported systems (another code's or an experiment's states): the claims about P1's compression protocol apply
    # to none of them, and a study of imports only has no P1 role nor counterpart to compare: such rows are left out,
    # the table's note row says which and why (`imported_left_out_note`)
    imported = [name for name in system_order(present) if name not in counterparts
                and system_force_law(present[name], name) == IMPORTED_FORCE_LAW]
    imported_study = bool(imported) and all(name in imported for name in present if name not in counterparts)
    # every P1 role gets rows: a role that no system of the results plays is listed under its shipped name
    played = {file_role(ds) for name, ds in present.items() if name not in counterparts}
    missing = {} if imported_study else {name: None for name, role in P1_ROLES.items()
                                         if role not in played and name not in present}
    names = {name: ds for name, ds in {**missing, **present}.items() if name not in counterparts}
    cuts = _cuts(present, counterparts)
    context = _context(present, tolerances_, force_unit, judge_up_to_rho_max, cuts, overlaps, counterparts)
    draws = bootstrap_draws(present, resamples, seed)
    resampled = [_context({name: resample_realizations(ds, draw[name]) for name, ds in present.items()},
                          tolerances_, force_unit, judge_up_to_rho_max, overlaps=overlaps, counterparts=counterparts)
                 for draw in draws]
    rows = _force_rows(cuts, force_unit, counterparts)
    for name in system_order(names):
        rows.extend(_value_rows(name, context.systems.get(name), cuts, force_unit))
    if imported_study:  # dyn and k_n d_ave^(1+beta) need P1's material and stiffness, which an import has not
        rows = [row for row in rows if row.id.split(".")[0] not in ("f_max", "rho_max")
                or row.id.split(".", 1)[1] in ("reduced", force_unit)]
    others = [(reading.name, _context(reading.measures(present) if reading.measures else present,
                                      replace(tolerances_, **reading.tolerances), force_unit, judge_up_to_rho_max,
                                      overlaps=overlaps, counterparts=counterparts))
              for reading in readings]
    others += [(name, _context(sets, tolerances_, force_unit, judge_up_to_rho_max, overlaps=overlaps,
                               counterparts=counterparts)) for name, sets in beside.items()]
    for claim_ in sorted(CLAIMS, key=lambda c: tuple(int(part) for part in c.section.split("."))):
        if imported_study and not claim_.per_system:
            continue  # it compares P1's systems or needs a counterpart run of P1's protocol
        primary = _claim_rows(claim_, context, names, resampled, left_out=imported)
        rows.extend(primary)
        for name, other in others:
            rows.extend(rows_beside(primary, _claim_rows(claim_, other, names, (), reading=name, left_out=imported)))
    note = imported_left_out_note(imported, imported_study) if imported else ""
    if note:
        rows.insert(0, JudgedClaim(id=LEFT_OUT_ID, section="", statement=note, system="all", paper=math.nan,
                                   criterion="", measured=math.nan, evidence="", verdict="", kind=NOTE_KIND))
    table = claims_frame(rows, P1_LAYOUT)
    table.attrs["force_unit"] = force_unit
    table.attrs["left_out"] = note
    return table


#: the row (kind `NOTE_KIND`, id `LEFT_OUT_ID`) of a table with imported systems saying which rows it leaves out
NOTE_KIND, LEFT_OUT_ID = "note", "left_out"


def imported_left_out_note(imported: Sequence[str], imported_study: bool) -> str:
    """The one line saying which rows a P1 table leaves out for its `imported` systems and why (`imported_study`:
    every system of the study is imported)."""
    line = (f"Left out for the imported systems ({', '.join(imported)}): the claims that need rho_J and the regimes "
            f"around it ({IMPORTED_NOT_EVALUATED})")
    if imported_study:
        line += ("; and, as the study imports every system, the claims comparing P1's systems or needing counterpart "
                 "runs of its protocol, the rows of P1's systems that it does not have, and F_max and rho_max in dyn "
                 "and k_n d_ave^(1+beta), which need P1's material and stiffness")
    return line + "."


def _context(present: Mapping[str, xr.Dataset], tolerances: ClaimTolerances, force_unit: str, up_to_rho_max: bool,
             cuts: Mapping[str, FMaxCut | str] | None = None,
             overlaps: Mapping[str, float | Mapping[float, float]] | None = None,
             counterparts: Sequence[str] = ()) -> ClaimContext:
    """Every system of `present` as the judges see it, under the F_max cut of `force_unit` (made by the systems
    that are not `counterparts`), with its snapshot overlaps from `overlaps` ({ρ: overlap}, or one number: at its
    largest ρ)."""
    cut = (cuts if cuts is not None else _cuts(present, counterparts)).get(force_unit)
    systems = {}
    for name, ds in present.items():
        system = system_data(name, ds, cut if isinstance(cut, FMaxCut) else None, tolerances, up_to_rho_max)
        given = (overlaps or {}).get(name)
        if given is not None and not isinstance(given, Mapping):  # one overlap: at the system's largest ρ
            given = {float(rho_values(system.full)[-1]): float(given)}
        systems[name] = replace(system, overlaps={float(rho): float(v) for rho, v in (given or {}).items()})
    return ClaimContext(systems, tolerances, frozenset(counterparts), claims=tuple(CLAIMS))


def overlaps_by_state(snapshots: Iterable[xr.Dataset]) -> dict[str, dict[float, float]]:
    """{system: {ρ: largest overlap / sum of radii over the snapshots at that ρ}} of `snapshots` (every realization
    of the states to judge; `forcenet.report.p1.largest_relative_overlap`): the `overlaps` of `p1_validation`,
    which judges P1 §3's bound at P1's depth above jamming."""
    from forcenet.report.p1 import largest_relative_overlap

    found: dict[str, dict[float, float]] = {}
    for snapshot in snapshots:
        by_rho = found.setdefault(str(snapshot.attrs["system"]), {})
        rho = round(float(snapshot["rho"]), 6)
        by_rho[rho] = max(by_rho.get(rho, 0.0), largest_relative_overlap(snapshot))
    return found


def _cuts(present: Mapping[str, xr.Dataset], counterparts: Sequence[str] = ()) -> dict[str, FMaxCut | str]:
    """The F_max cut under every unit, or the reason it cannot be made: F_max from the systems that are not
    `counterparts`, which get their ρ_max under that F_max (they must not move P1's own ρ_max)."""
    own = {name: ds for name, ds in present.items() if name not in counterparts} or dict(present)
    beside = {name: ds for name, ds in present.items() if name not in own}
    cuts: dict[str, FMaxCut | str] = {}
    for unit in P1_FORCE_UNITS:
        try:
            if not present:
                cuts[unit] = "no system in the results"
                continue
            cut = f_max_cut(own, unit)
            if beside:
                extra = f_max_cut(beside, unit, f_max=cut.f_max)
                cut = replace(cut, f_prime_max={**cut.f_prime_max, **extra.f_prime_max},
                              rho_max={**cut.rho_max, **extra.rho_max},
                              mean_force={**cut.mean_force, **extra.mean_force})
            cuts[unit] = cut
        except ValueError as error:
            cuts[unit] = str(error)
    return cuts


def system_data(name: str, ds: xr.Dataset, cut: FMaxCut | None = None, tolerances: ClaimTolerances | None = None,
                up_to_rho_max: bool = False) -> SystemData:
    """One system as the judges see it: its total-force measures (up to ρ_max with `up_to_rho_max`), ρ_J, ρ_max
    under the table's force unit (NaN without `cut`), and the ρ tolerance and window resolved for its ρ step
    (`tolerances` None: the defaults of `ClaimTolerances`)."""
    tolerances = tolerances if tolerances is not None else ClaimTolerances()
    full = select_total(ds)
    rho = rho_values(full)
    step = float(np.median(np.diff(rho))) if rho.size > 1 else 0.0
    tolerance = tolerances.rho_tolerance if tolerances.rho_tolerance is not None else max(P1_RHO_STEP, step)
    window = tolerances.rho_window if tolerances.rho_window is not None else 2.0 * tolerance
    rho_max = cut.rho_max.get(name, math.nan) if cut else math.nan
    return SystemData(name=name, dimension=system_dimension(ds, name), force_law=system_force_law(ds, name),
                      data=cut_at_rho_max(full, rho_max) if up_to_rho_max else full, full=full,
                      rho_j=jamming_point(ds), rho_max=rho_max, tolerance=tolerance, window=window,
                      below_cut=tolerances.below_cut)


def _claim_rows(claim_: Claim, context: ClaimContext, names: Mapping[str, xr.Dataset | None],
                resampled: Sequence[ClaimContext] = (), reading: str = "",
                left_out: Sequence[str] = ()) -> list[JudgedClaim]:
    """The rows of one claim: one across systems (``per_system=False``), else one per system of its scope among
    `names` (a system of P1 missing from the results is "not evaluated"); its robustness from the same claim
    judged in each of the `resampled` contexts; `reading` names the reading of `context`. A claim that needs ρ_J
    (P1's compression protocol) has no row for the imported systems `left_out`."""
    criterion = claim_.criterion_text(context.tolerances)
    changed = P1_CHANGES.get(claim_.id)
    if not claim_.per_system:
        return [judge_claim(claim_, "all", claim_.paper_value(None), criterion, lambda: claim_.judge(context),
                            explain=_explainer(claim_, "all", reading),
                            resampled=[lambda c=c: claim_.judge(c) for c in resampled], reading=reading,
                            changed=changed)]
    rows = []
    for name in system_order(names):
        system = context.systems.get(name)
        role = system.role if system else P1_ROLES.get(name)
        if claim_.scope is not None and role not in claim_.scope:
            continue
        if claim_.needs_rho_j and name in left_out:
            continue  # the note row of the table says why

        def judge(within: ClaimContext, name=name) -> Judgement:
            """The claim judged on this system of `within`, after the checks every per-system claim shares."""
            system = within.systems.get(name)
            if system is None:
                raise NotEvaluated("system not in the results")
            if claim_.needs_rho_j and system.force_law == IMPORTED_FORCE_LAW:
                raise NotEvaluated(IMPORTED_NOT_EVALUATED)  # ρ_J and the regimes around it: P1's compression
            if claim_.needs_rho_j and not np.isfinite(system.rho_j):
                raise NotEvaluated("rho_J could not be located")
            return claim_.judge(system, within.tolerances)

        # one realization is the same in every resample: no robustness to measure, the row says "one run"
        varies = system is not None and system.full.sizes.get(REALIZATION, 1) > 1
        rows.append(judge_claim(claim_, name, claim_.paper_value(role), criterion, lambda: judge(context),
                                explain=_explainer(claim_, name, reading),
                                resampled=[lambda c=c: judge(c) for c in resampled] if varies else [],
                                reading=reading, changed=changed,
                                one_run=(name,) if system is not None and not varies else ()))
    return rows


def _explainer(claim_: Claim, system: str, reading: str) -> Callable[[str], Explanation | None]:
    """Why the claim does not hold for `system` (`p1_explanations.explain`), on the table's own reading only."""
    return lambda verdict: explain(claim_.id, system) if verdict == FAILS and not reading else None


def _force_rows(cuts: Mapping[str, FMaxCut | str], force_unit: str,
                counterparts: Sequence[str] = ()) -> list[JudgedClaim]:
    """F_max under each force unit (P1 §3), the unit of the figures marked "[figures]"; the `counterparts`' F'_max
    are listed apart (they are not in the minimum)."""
    rows = []
    for unit, cut in cuts.items():
        item = f"F_max (min over systems of max_rho <F>, <F> in {unit})" + (" [figures]" if unit == force_unit else "")
        if isinstance(cut, FMaxCut):
            def listed(names):
                return ", ".join(f"{n} {cut.f_prime_max[n]:.4g}" for n in names)

            own = [n for n in cut.f_prime_max if n not in counterparts]
            beside = [n for n in cut.f_prime_max if n in counterparts]
            evidence = ("F'_max: " + listed(own) + (f"; counterparts (not in the min): {listed(beside)}" if beside
                                                    else "") + f" [{cut.force_units}]")
            rows.append(_value(f"f_max.{unit}", "3", item, "all", cut.f_max, math.nan, evidence, ""))
        else:
            rows.append(_value(f"f_max.{unit}", "3", item, "all", math.nan, math.nan, cut, NOT_EVALUATED))
    return rows


def _value_rows(name: str, system: SystemData | None, cuts: Mapping[str, FMaxCut | str],
                force_unit: str) -> list[JudgedClaim]:
    """P1's numbers of one system beside ours: ρ_J, ρ_max under each force unit, Z at ρ_J (with and without
    rattlers), φ_c of P1 Eq. 6 and ρ at Z = d + 1; every one "not evaluated" when the system is not in the results."""
    role = system.role if system else P1_ROLES.get(name)
    dimension = role[0] if role else 2
    paper_rho_j, paper_rho_max = PAPER_RHO_J_BY_ROLE.get(role, math.nan), PAPER_RHO_MAX_BY_ROLE.get(role, math.nan)
    paper_z, paper_phi = PAPER_Z_AT_JAMMING.get(dimension, math.nan), PAPER_PHI_C.get(dimension, math.nan)
    rho_max_items = [(unit, f"rho_max (F_max rule, <F> in {unit})" + (" [figures]" if unit == force_unit else ""))
                     for unit in P1_FORCE_UNITS]
    if system is None:
        items = [("rho_J", "rho_J (inflection of Z)", paper_rho_j, "4")]
        items += [(f"rho_max.{unit}", item, paper_rho_max, "3") for unit, item in rho_max_items]
        items += [("Z_at_rho_J", "Z at rho_J", paper_z, "4.3"), ("phi_c", "phi_c = 1/(Z(rho_J) - 1)", paper_phi, "4.3")]
        return [_value(id_, section, item, name, math.nan, paper, "system not in the results", NOT_EVALUATED)
                for id_, item, paper, section in items]
    ds, rho_j = system.full, system.rho_j
    realizations = ds.sizes.get("realization", 1)
    rows = [_value("rho_J", "4", "rho_J (inflection of Z)", name, rho_j, paper_rho_j,
                   f"inflection of the mean Z(rho) over {realizations} realizations")]
    for unit, item in rho_max_items:
        cut = cuts[unit]
        if isinstance(cut, FMaxCut):
            evidence = (f"every rho has mean <F> > F_max: rho_max lies below the grid (<F> in {cut.force_units})"
                        if cut.below_grid(name) else f"largest rho with mean <F> <= F_max, <F> in {cut.force_units}")
            rows.append(_value(f"rho_max.{unit}", "3", item, name, cut.rho_max.get(name, math.nan),
                               paper_rho_max, evidence))
        else:
            rows.append(_value(f"rho_max.{unit}", "3", item, name, math.nan, paper_rho_max, cut,
                               NOT_EVALUATED))
    z_j = value_at(ds, "Z", rho_j)
    rows.append(_value("Z_at_rho_J", "4.3", "Z at rho_J", name, z_j, paper_z, "mean Z (all particles) at rho_J"))
    if "Z_no_rattlers" in ds:
        rows.append(_value("Z_no_rattlers_at_rho_J", "4.3", "Z at rho_J (rattlers excluded)", name,
                           value_at(ds, "Z_no_rattlers", rho_j), paper_z, "mean Z without rattlers at rho_J"))
    phi_c = 1.0 / (z_j - 1.0) if np.isfinite(z_j) and z_j > 1 else math.nan  # P1 Eq. 6 with <k^2> = <k>^2
    rows.append(_value("phi_c", "4.3", "phi_c = 1/(Z(rho_J) - 1)", name, phi_c, paper_phi,
                       "P1 Eq. 6 with <k^2> = <k>^2, <k> = mean Z at rho_J"))
    # the same at the first jammed state (after the jump of Z), beside the value interpolated across the jump
    first = system.first_jammed
    z_first = value_at(ds, "Z", first) if np.isfinite(first) else math.nan
    phi_first = 1.0 / (z_first - 1.0) if np.isfinite(z_first) and z_first > 1 else math.nan
    rows.append(replace(_value("phi_c_first_jammed", "4.3", "phi_c = 1/(Z - 1) at the first jammed state", name,
                               phi_first, paper_phi, f"P1 Eq. 6 with <k> = mean Z (all particles) {z_first:.3g} at "
                               f"rho={first:.3f}, the first state after the jump of Z (rho_J={rho_j:.3f} lies in the "
                               "jump)"), judge_changed_after_reading=PHI_C_FIRST_JAMMED.text(name)))
    rows.append(_value("rho_at_Z_d+1", "4", "rho at Z = d+1", name, isostatic_crossing(ds), math.nan,
                       f"first rho where the mean Z reaches {system.dimension + 1} (P2's definition)"))
    return rows


#: the value row of φ_c at the first jammed state was added after the verdicts were read (issue 53)
PHI_C_FIRST_JAMMED = JudgeChange("row added: phi_c at the first jammed state beside the value interpolated at rho_J")


def _value(id_: str, section: str, item: str, system: str, measured: float, paper: float, evidence: str,
           verdict: str | None = None) -> JudgedClaim:
    """A value row: our number beside P1's, no criterion; its verdict "" (or "not evaluated" when the number is
    NaN) unless given."""
    measured, paper = float(measured), float(paper)
    if verdict is None:
        verdict = "" if np.isfinite(measured) else NOT_EVALUATED
    return JudgedClaim(id=id_, section=section, statement=item, system=system, paper=paper, criterion="",
                       measured=measured, evidence=evidence, verdict=verdict, kind="value")


def _markdown_head(force_unit: str, table: pd.DataFrame | None = None) -> list[str]:
    """The lines above the tables: what is compared, which force unit the figures use, and the note row of a table
    with imported systems (which rows it leaves out and why, `imported_left_out_note`)."""
    notes = ([str(note) for note in table.loc[table["kind"] == NOTE_KIND, "item"]]
             if table is not None and "kind" in table else [])
    return ["# P1 validation", "", *[line for note in notes for line in (note, "")],
            "Measured from the aggregated network measures; paper values from P1 "
            "(compressed 2D/3D interaction networks). difference = measured − paper.", "",
            f"The figures mark rho_max of the F_max rule with <F> compared in {force_unit} "
            f"({P1_FORCE_UNITS.get(force_unit, '?')}; config key analysis.p1_force_unit); the rows marked "
            "[figures] are that unit.", ""]


def _markdown_sections(table: pd.DataFrame) -> list[TableSection]:
    """The table of values, then the table of claims headed by the verdict counts."""
    return [TableSection("Values", [], ["item", "system", "measured", "paper", "difference", "evidence", "verdict",
                                        "judge_changed_after_reading"], kind="value"),
            TableSection("Claims", [verdict_summary(table), ""],
                         ["id", "section", "item", "system", "measured", "paper", "criterion", "evidence", "verdict",
                          "marker", "robustness", "states", "reading", "explanation", "explanation_basis",
                          "judge_changed_after_reading"],
                         kind="claim")]


def p1_validation_markdown(table: pd.DataFrame) -> str:
    """The validation table as Markdown: one table of values, one of claims, with the verdict counts; the force
    unit of the figures is the table's own (``table.attrs["force_unit"]``)."""
    force_unit = table_attribute(table, "force_unit", "p1_validation")
    return validation_markdown(table, P1_LAYOUT, _markdown_head(force_unit, table), _markdown_sections(table))


def write_p1_validation(table: pd.DataFrame, csv_path: str | os.PathLike | None, md_path: str | os.PathLike, *,
                        paper_size: str | os.PathLike | None = None) -> None:
    """Write the validation table as CSV and Markdown (the arguments of `write_p2_validation`); with `paper_size`
    (the campaign's ``docs/validation/p1.csv``) a column beside P1's values gives our value at P1's sizes
    (`forcenet.report.claims_table.with_paper_size`)."""
    force_unit = table_attribute(table, "force_unit", "p1_validation")
    if paper_size is not None:
        table = with_paper_size(table, P1_LAYOUT, paper_size)
    write_validation_table(table, P1_LAYOUT, csv_path, md_path, _markdown_head(force_unit, table),
                           _markdown_sections(table))
