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
from typing import Mapping

import numpy as np
import pandas as pd
import xarray as xr

from forcenet.report import p1_claims, p1_claims_topology
from forcenet.report.claims import (FAILS, HOLDS, IMPORTED_NOT_EVALUATED, NOT_EVALUATED, Claim, JudgedClaim,
                                    Judgement, NotEvaluated, TableLayout, TableSection, claims_frame, judge_claim,
                                    validation_markdown, verdict_counts, with_paper_size, write_validation_table)
from forcenet.report.p1 import (DEFAULT_P1_FORCE_UNIT, P1_FORCE_UNITS, P1_RHO_STEP, P1_ROLES, P1_SYSTEMS,
                                PAPER_PHI_C, PAPER_RHO_J, PAPER_RHO_MAX, PAPER_Z_AT_JAMMING, FMaxCut, cut_at_rho_max,
                                f_max_cut, isostatic_crossing, jamming_point, rho_values, select_total,
                                system_dimension, system_force_law, system_order, value_at)
from forcenet.report.p1_judging import ClaimContext, ClaimTolerances, SystemData
from forcenet.systems import IMPORTED_FORCE_LAW

#: every claim of P1 §3–6, in the order the table lists them within a section
CLAIMS: list[Claim] = [*p1_claims.CLAIMS, *p1_claims_topology.CLAIMS]

#: the table's columns (CSV names → `JudgedClaim` fields)
P1_LAYOUT = TableLayout(columns={"kind": "kind", "id": "id", "section": "section", "item": "statement",
                                 "system": "system", "measured": "measured", "paper": "paper",
                                 "difference": "difference", "criterion": "criterion", "evidence": "evidence",
                                 "verdict": "verdict"})
COLUMNS = tuple(P1_LAYOUT.columns)


def p1_validation(measures: Mapping[str, xr.Dataset], *, force_unit: str = DEFAULT_P1_FORCE_UNIT,
                  judge_up_to_rho_max: bool = False, **tolerances) -> pd.DataFrame:
    """P1's numbers and claims beside what `measures` (system → network_measures dataset) shows.

    Rows of kind ``"value"``: F_max and per system ρ_max under each unit of `P1_FORCE_UNITS` (the one the figures
    use, `force_unit` = ``analysis.p1_force_unit``, is marked "[figures]"), ρ_J (inflection of mean Z), Z at ρ_J
    (all particles, and rattlers excluded), φ_c = 1/(Z(ρ_J) − 1) of P1 Eq. 6, ρ where Z = d + 1; with P1's value
    and measured − paper. Rows of kind ``"claim"``: one per claim of `CLAIMS` and system it is about (or one
    for a claim comparing systems), with P1's section, statement, the criterion, the key number (``measured``),
    the evidence and a verdict: ``holds`` / ``does not hold`` / ``not evaluated`` (a system, a quantity or a ρ
    range is missing; the evidence says which).

    Claims are judged over every simulated ρ, or over ρ ≤ ρ_max (P1's shown range) with `judge_up_to_rho_max`;
    those P1 states at ρ_max (PDF order, B1 plateau) use ρ_max either way. `tolerances`: the fields of
    `ClaimTolerances` (documented there), e.g. ``rho_tolerance=0.03``.
    """
    tolerances_ = ClaimTolerances(**tolerances)
    present = {name: ds for name, ds in measures.items() if ds is not None}
    cuts = _cuts(present)
    if force_unit not in P1_FORCE_UNITS:
        raise ValueError(f"unknown P1 force unit {force_unit!r}; known: {', '.join(P1_FORCE_UNITS)}")
    cut = cuts.get(force_unit)
    systems = {name: system_data(name, ds, cut if isinstance(cut, FMaxCut) else None, tolerances_,
                                 judge_up_to_rho_max) for name, ds in present.items()}
    rows = _force_rows(cuts, force_unit)
    for name in system_order(set(P1_SYSTEMS) | set(present)):
        rows.extend(_value_rows(name, systems.get(name), cuts, force_unit))
    context = ClaimContext(systems, tolerances_)
    for claim_ in sorted(CLAIMS, key=lambda c: tuple(int(part) for part in c.section.split("."))):
        rows.extend(_claim_rows(claim_, context, set(P1_SYSTEMS) | set(present)))
    return claims_frame(rows, P1_LAYOUT)


def _cuts(present: Mapping[str, xr.Dataset]) -> dict[str, FMaxCut | str]:
    """The F_max cut under every unit, or the reason it cannot be made."""
    cuts: dict[str, FMaxCut | str] = {}
    for unit in P1_FORCE_UNITS:
        try:
            cuts[unit] = f_max_cut(present, unit) if present else "no system in the results"
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
                      rho_j=jamming_point(ds), rho_max=rho_max, tolerance=tolerance, window=window)


def _claim_rows(claim_: Claim, context: ClaimContext, names: set[str]) -> list[JudgedClaim]:
    """The rows of one claim: one across systems (``per_system=False``), else one per system of its scope among
    `names` (a system of P1 missing from the results is "not evaluated")."""
    criterion = claim_.criterion_text(context.tolerances)
    if not claim_.per_system:
        return [judge_claim(claim_, "all", claim_.paper_value(None), criterion, lambda: claim_.judge(context))]
    rows = []
    for name in system_order(names):
        system = context.systems.get(name)
        role = system.role if system else P1_ROLES.get(name)
        if claim_.scope is not None and role not in claim_.scope:
            continue

        def judge(system=system) -> Judgement:
            """The claim judged on this system, after the checks every per-system claim shares."""
            if system is None:
                raise NotEvaluated("system not in the results")
            if claim_.needs_rho_j and system.force_law == IMPORTED_FORCE_LAW:
                raise NotEvaluated(IMPORTED_NOT_EVALUATED)  # ρ_J and the regimes around it: P1's compression
            if claim_.needs_rho_j and not np.isfinite(system.rho_j):
                raise NotEvaluated("rho_J could not be located")
            return claim_.judge(system, context.tolerances)

        rows.append(judge_claim(claim_, name, claim_.paper_value(role), criterion, judge))
    return rows


def _force_rows(cuts: Mapping[str, FMaxCut | str], force_unit: str) -> list[JudgedClaim]:
    """F_max under each force unit (P1 §3), the unit of the figures marked "[figures]"."""
    rows = []
    for unit, cut in cuts.items():
        item = f"F_max (min over systems of max_rho <F>, <F> in {unit})" + (" [figures]" if unit == force_unit else "")
        if isinstance(cut, FMaxCut):
            evidence = ("F'_max: " + ", ".join(f"{n} {v:.4g}" for n, v in cut.f_prime_max.items())
                        + f" [{cut.force_units}]")
            rows.append(_value(f"f_max.{unit}", "3", item, "all", cut.f_max, math.nan, evidence, ""))
        else:
            rows.append(_value(f"f_max.{unit}", "3", item, "all", math.nan, math.nan, cut, NOT_EVALUATED))
    return rows


def _value_rows(name: str, system: SystemData | None, cuts: Mapping[str, FMaxCut | str],
                force_unit: str) -> list[JudgedClaim]:
    """P1's numbers of one system beside ours: ρ_J, ρ_max under each force unit, Z at ρ_J (with and without
    rattlers), φ_c of P1 Eq. 6 and ρ at Z = d + 1; every one "not evaluated" when the system is not in the results."""
    dimension = system.dimension if system else P1_ROLES.get(name, (2, ""))[0]
    paper_z, paper_phi = PAPER_Z_AT_JAMMING.get(dimension, math.nan), PAPER_PHI_C.get(dimension, math.nan)
    rho_max_items = [(unit, f"rho_max (F_max rule, <F> in {unit})" + (" [figures]" if unit == force_unit else ""))
                     for unit in P1_FORCE_UNITS]
    if system is None:
        items = [("rho_J", "rho_J (inflection of Z)", PAPER_RHO_J.get(name, math.nan), "4")]
        items += [(f"rho_max.{unit}", item, PAPER_RHO_MAX.get(name, math.nan), "3") for unit, item in rho_max_items]
        items += [("Z_at_rho_J", "Z at rho_J", paper_z, "4.3"), ("phi_c", "phi_c = 1/(Z(rho_J) - 1)", paper_phi, "4.3")]
        return [_value(id_, section, item, name, math.nan, paper, "system not in the results", NOT_EVALUATED)
                for id_, item, paper, section in items]
    ds, rho_j = system.full, system.rho_j
    realizations = ds.sizes.get("realization", 1)
    rows = [_value("rho_J", "4", "rho_J (inflection of Z)", name, rho_j, PAPER_RHO_J.get(name, math.nan),
                   f"inflection of the mean Z(rho) over {realizations} realizations")]
    for unit, item in rho_max_items:
        cut = cuts[unit]
        if isinstance(cut, FMaxCut):
            evidence = (f"every rho has mean <F> > F_max: rho_max lies below the grid (<F> in {cut.force_units})"
                        if cut.below_grid(name) else f"largest rho with mean <F> <= F_max, <F> in {cut.force_units}")
            rows.append(_value(f"rho_max.{unit}", "3", item, name, cut.rho_max.get(name, math.nan),
                               PAPER_RHO_MAX.get(name, math.nan), evidence))
        else:
            rows.append(_value(f"rho_max.{unit}", "3", item, name, math.nan, PAPER_RHO_MAX.get(name, math.nan), cut,
                               NOT_EVALUATED))
    z_j = value_at(ds, "Z", rho_j)
    rows.append(_value("Z_at_rho_J", "4.3", "Z at rho_J", name, z_j, paper_z, "mean Z (all particles) at rho_J"))
    if "Z_no_rattlers" in ds:
        rows.append(_value("Z_no_rattlers_at_rho_J", "4.3", "Z at rho_J (rattlers excluded)", name,
                           value_at(ds, "Z_no_rattlers", rho_j), paper_z, "mean Z without rattlers at rho_J"))
    phi_c = 1.0 / (z_j - 1.0) if np.isfinite(z_j) and z_j > 1 else math.nan  # P1 Eq. 6 with <k^2> = <k>^2
    rows.append(_value("phi_c", "4.3", "phi_c = 1/(Z(rho_J) - 1)", name, phi_c, paper_phi,
                       "P1 Eq. 6 with <k^2> = <k>^2, <k> = mean Z at rho_J"))
    rows.append(_value("rho_at_Z_d+1", "4", "rho at Z = d+1", name, isostatic_crossing(ds), math.nan,
                       f"first rho where the mean Z reaches {system.dimension + 1} (P2's definition)"))
    return rows


def _value(id_: str, section: str, item: str, system: str, measured: float, paper: float, evidence: str,
           verdict: str | None = None) -> JudgedClaim:
    """A value row: our number beside P1's, no criterion; its verdict "" (or "not evaluated" when the number is
    NaN) unless given."""
    measured, paper = float(measured), float(paper)
    if verdict is None:
        verdict = "" if np.isfinite(measured) else NOT_EVALUATED
    return JudgedClaim(id=id_, section=section, statement=item, system=system, paper=paper, criterion="",
                       measured=measured, evidence=evidence, verdict=verdict, kind="value")


def _markdown_head(force_unit: str) -> list[str]:
    """The lines above the tables: what is compared, and which force unit the figures use."""
    return ["# P1 validation", "",
            "Measured from the aggregated network measures; paper values from P1 "
            "(compressed 2D/3D interaction networks). difference = measured − paper.", "",
            f"The figures mark rho_max of the F_max rule with <F> compared in {force_unit} "
            f"({P1_FORCE_UNITS.get(force_unit, '?')}; config key analysis.p1_force_unit); the rows marked "
            "[figures] are that unit.", ""]


def _markdown_sections(table: pd.DataFrame) -> list[TableSection]:
    """The table of values, then the table of claims headed by the verdict counts."""
    counts = verdict_counts(table)
    n_claims = int((table["kind"] == "claim").sum())
    return [TableSection("Values", [], ["item", "system", "measured", "paper", "difference", "evidence", "verdict"],
                         kind="value"),
            TableSection("Claims", [f"{n_claims} rows: {counts[HOLDS]} hold, {counts[FAILS]} do not hold, "
                                    f"{counts[NOT_EVALUATED]} not evaluated.", ""],
                         ["id", "section", "item", "system", "measured", "paper", "criterion", "evidence", "verdict"],
                         kind="claim")]


def p1_validation_markdown(table: pd.DataFrame, force_unit: str = DEFAULT_P1_FORCE_UNIT) -> str:
    """The validation table as Markdown: one table of values, one of claims, with the verdict counts."""
    return validation_markdown(table, P1_LAYOUT, _markdown_head(force_unit), _markdown_sections(table))


def write_p1_validation(table: pd.DataFrame, csv_path: str | os.PathLike, md_path: str | os.PathLike,
                        force_unit: str = DEFAULT_P1_FORCE_UNIT, paper_size: str | os.PathLike | None = None) -> None:
    """Write the validation table as CSV and Markdown; with `paper_size` (the campaign's ``docs/validation/p1.csv``)
    a column beside P1's values gives our value at P1's sizes (`forcenet.report.claims.with_paper_size`)."""
    if paper_size is not None:
        table = with_paper_size(table, P1_LAYOUT, paper_size)
    write_validation_table(table, P1_LAYOUT, csv_path, md_path, _markdown_head(force_unit), _markdown_sections(table))
