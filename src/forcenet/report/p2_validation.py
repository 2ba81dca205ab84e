"""P2's validation table (``results/tables/p2_validation.{md,csv}``): each claim of `forcenet.report.p2_claims` and `p2_claims_friction`
with the measured evidence, the criterion, a computed verdict and, where it does not hold, the explanation of
`forcenet.report.p2_explanations`; judged and written with the framework of `forcenet.report.claims`. In the
default build a column beside P2's values gives our value at P2's size from the committed campaign table
``docs/validation/p2.csv`` (`write_p2_validation`).
"""
from __future__ import annotations

import math
import os
from typing import Any, Mapping, Sequence

import pandas as pd
import xarray as xr

from forcenet.report.claims import (HOLDS, IMPORTED_NOT_EVALUATED, ClaimTolerances, Explanation, JudgedClaim,
                                    Judgement, NotEvaluated, judge_claim, rows_beside, verdict_summary)
from forcenet.report.claims_table import (VERDICT_COLUMNS, TableLayout, TableSection, claims_frame,
                                          table_attribute, validation_markdown, with_paper_size,
                                          write_validation_table)
from forcenet.report.p1 import system_dimension
from forcenet.report import p2_claims, p2_claims_friction
from forcenet.report.p2 import FRICTIONAL, FRICTIONLESS, format_number
from forcenet.report.judge_changes import P2_CHANGES
from forcenet.report.p2_explanations import explain
from forcenet.report.p2_judging import Context, Curves
from forcenet.report.realizations import bootstrap_draws, resample_realizations
from forcenet.systems import IMPORTED_FORCE_LAW

#: every claim of P2, in the order of the table: §III D, §IV A, §IV B, then §IV C and §V
CLAIMS = [*p2_claims.CLAIMS, *p2_claims_friction.CLAIMS]

#: the table's columns (CSV names → `JudgedClaim` fields); the Markdown heads claim_id "id" and reference "P2"
P2_LAYOUT = TableLayout(columns={"claim_id": "id", "section": "section", "system": "system", "claim": "statement",
                                 "reference": "paper", "criterion": "criterion", "measured": "measured",
                                 "evidence": "evidence", **VERDICT_COLUMNS},
                        headers={"claim_id": "id", "reference": "P2"}, id_column="claim_id",
                        paper_column="reference")
VALIDATION_COLUMNS = tuple(P2_LAYOUT.columns)


def p2_validation(distances: Mapping[str, xr.Dataset], tables: Mapping[str, pd.DataFrame] | None = None, *,
                  frictional: str = FRICTIONAL, frictionless: str = FRICTIONLESS,
                  tolerances: ClaimTolerances | None = None, measures: Mapping[str, xr.Dataset] | None = None,
                  states: pd.DataFrame | None = None, resamples: int = 0, seed: int = 0,
                  diagrams: Mapping[str, xr.Dataset] | None = None,
                  point_counts: Mapping[str, xr.DataArray] | None = None,
                  beside: Mapping[str, Mapping[str, Any]] | None = None) -> pd.DataFrame:
    """Judge each claim of P2 §III D–§IV (and §V's summary of them) on the measured data.

    Parameters
    ----------
    distances : ``{system: distances.nc dataset}`` (`forcenet.report.p2_distances.stack_distances`); the
        frictional (μ = 0.5) and the frictionless (μ = 0) system under the names `frictional`, `frictionless`. A
        missing system leaves its claims "not evaluated".
    tables : ``{"table1": …, "table2": …, "table3": …}`` from `forcenet.report.p2_tables.p2_tables` or
        `read_table` (frictional system).
    tolerances : how "≈", "roughly constant", "dramatically" … are tested (`ClaimTolerances`).
    measures : ``{system: network_measures.nc dataset}`` (never-dying class counts) and `states` (the
        `table_state_candidates` of Tables I–III): what the explanations of failed claims measure (optional).
    diagrams : ``{system: diagrams.nc dataset}``: the number of PD points per state (IV.C-8; optional);
        `point_counts` (``{system: counts (realization, rho)}`` of normal-force PD1 points, as
        `forcenet.report.p2.diagram_point_counts` gives them) in their place.
    beside : other readings judged beside P2's conventions, ``{name: {"distances": …, "tables": …}}`` (either
        key may be left out: the primary's is used), e.g. the distances with never-dying classes matched only
        with each other (``essential_convention: apart``) or Tables I–III of the literal states at ρ = 0.79; a
        row of a reading is set beside a claim wherever it changes the verdict, marker or key number.
    resamples, seed : each claim on the realizations (not Tables I–III, one realization, whose robustness says "one
        run") is judged again on `resamples` bootstrap resamples of every system's realizations (seeded by `seed`);
        its robustness is the share under which it holds (NaN with 0 resamples or one realization). A claim whose
        judge changed after its verdicts were read (`forcenet.report.judge_changes.P2_CHANGES`) says so in the
        column ``judge_changed_after_reading``.

    Returns
    -------
    DataFrame with columns ``VALIDATION_COLUMNS`` (`P2_LAYOUT`): claim id, section, system, claim, P2's reference, the
    criterion, the measured evidence, the verdict ("holds", "does not hold", "not evaluated") and, for a claim
    that does not hold, the explanation (`EXPLANATIONS`: why, measured on these data where it can be). Curves
    are realization means; ρ_J is where the mean Z(ρ) first reaches d + 1 (P2 §IV A).
    """
    tol = tolerances or ClaimTolerances()

    def context(distances: Mapping[str, xr.Dataset], tables: Mapping[str, pd.DataFrame] | None) -> Context:
        """The claims' view of `distances` (the two judged systems) and `tables`."""
        curves = {name: Curves(name, ds, _dimension(ds), tol) for name, ds in distances.items()
                  if name in (frictional, frictionless)}
        return Context(curves, tables, tol, frictional, frictionless, dict(measures or {}), states,
                       dict(diagrams or {}), dict(point_counts or {}))

    judged_systems = {name: ds for name, ds in distances.items() if name in (frictional, frictionless)}
    ctx = context(distances, tables)
    resampled = [context({name: resample_realizations(ds, draw[name]) for name, ds in judged_systems.items()},
                         tables) for draw in bootstrap_draws(judged_systems, resamples, seed)]
    others = [(name, context(reading.get("distances", distances), reading.get("tables", tables)))
              for name, reading in (beside or {}).items()]
    systems = {"frictional": frictional, "frictionless": frictionless, "both": f"{frictional} vs {frictionless}",
               "tables": f"{frictional} (one realization)"}
    # P2's claims are about its compression (wall speed, sampling step, the regimes around ρ_J): not judged on
    # imported states, whose protocol is not recorded
    imported = sorted(name for name, ds in distances.items() if name in (frictional, frictionless)
                      and ds.attrs["force_law"] == IMPORTED_FORCE_LAW)
    judged = []
    if imported:  # no claim of P2 applies: one row says so instead of a "not evaluated" row per claim
        judged.append(JudgedClaim(id=LEFT_OUT_ID, section="", statement=imported_note(imported), system="all",
                                  paper="", criterion="", measured=math.nan, evidence="", verdict=""))
    for claim in CLAIMS if not imported else ():
        def judge(within: Context, claim=claim) -> Judgement:
            """The claim judged on the data of `within` (not on imported states: their protocol is not recorded)."""
            if imported:
                raise NotEvaluated(f"{', '.join(imported)}: {IMPORTED_NOT_EVALUATED}")
            try:
                return claim.judge(within)
            except ZeroDivisionError:  # a ratio of distances, one of them 0 (no never-dying class under `drop`, …)
                raise NotEvaluated("a distance its criterion divides by is 0 here, so the ratio is undefined") from None

        changed = P2_CHANGES.get(claim.id)
        beside_rows = [judge_claim(claim, systems[claim.scope], claim.paper_value(), claim.criterion_text(tol),
                                   lambda judge=judge, o=other: judge(o), reading=name, changed=changed)
                       for name, other in others]
        # the control of the never-dying floor (docs/validation/controls.md §3): the claim under `drop`, if built
        drop = next((row for row, (_, other) in zip(beside_rows, others) if _convention(other) == "drop"), None)

        def explanation(verdict: str, claim=claim, drop=drop) -> Explanation | None:
            """Why the claim does not hold (nothing where it does, or where it is not judged on imported states)."""
            return explain(claim.id, ctx, drop) if verdict != HOLDS and not imported else None

        # Tables I–III are one realization's: the verdict rests on that one run, and says so
        on_resamples = [] if claim.scope == "tables" else [lambda c=c, judge=judge: judge(c) for c in resampled]
        row = judge_claim(claim, systems[claim.scope], claim.paper_value(), claim.criterion_text(tol),
                          lambda judge=judge: judge(ctx), explanation, resampled=on_resamples, changed=changed,
                          one_run=(frictional,) if claim.scope == "tables" else ())
        judged.append(row)
        judged += rows_beside([row] * len(beside_rows), beside_rows)
    curves = ctx.curves
    table = claims_frame(judged, P2_LAYOUT)
    table.attrs["systems"] = {name: {"rho_J": c.rho_j, "realizations": c.n_realizations,
                                     "rho_range": (float(c.ds["rho"].min()), float(c.ds["rho"].max())),
                                     "snapshot_pairs": int(c.ds.sizes["rho"]),
                                     "essential_convention": c.ds.attrs["essential_convention"],
                                     "rattler_rule": c.ds.attrs["rattler_rule"]}
                              for name, c in curves.items()}
    table.attrs["tolerances"] = tol
    return table


def _convention(within: Context) -> str:
    """The never-dying convention of the distances a context judges (every distances.nc records it)."""
    return next((str(c.ds.attrs.get("essential_convention", "")) for c in within.curves.values()), "")


def _dimension(ds: xr.Dataset) -> int:
    """The spatial dimension of a distances dataset (its ``dimension`` attribute, which every distances.nc records)."""
    return system_dimension(ds)


#: the `claim_id` of the one row of a table of imported systems, saying why it lists no claim (`imported_note`)
LEFT_OUT_ID = "left_out"


def imported_note(imported: Sequence[str]) -> str:
    """Why a P2 table of the `imported` systems lists no claim."""
    return (f"No claim listed: the judged systems ({', '.join(imported)}) are imported, and every claim of P2 is "
            f"about its compression (wall speed, sampling step, the regimes around rho_J): {IMPORTED_NOT_EVALUATED}.")


def _markdown_head(table: pd.DataFrame) -> list[str]:
    """The lines above the claims: what is judged, the systems measured and the tolerances; the row of a table of
    imported systems saying why it lists no claim (`imported_note`)."""
    notes = ([str(note) for note in table.loc[table["claim_id"] == LEFT_OUT_ID, "claim"]]
             if "claim_id" in table else [])
    lines = ["# P2 validation", "", *[line for note in notes for line in (note, "")],
             "Each claim of P2 (evolution of force networks) §III D–§IV, judged on the measured distances between "
             "consecutive persistence diagrams (realization means) and on Tables I–III. rho_J is where the mean "
             "Z(rho) first reaches d + 1 (P2 §IV A). The reference column is P2's statement; verdicts are computed "
             "from the criterion column. The explanation of a claim that does not hold gives the cause measured in "
             "docs/p2_sampling.md (400 disks at several wall speeds and sampling steps, and one realization at "
             "P2's size, 'paper size' there: 'holds at paper size' means it held in that one realization), then "
             "'Measured here:' the same diagnostics on the data of this table.", ""]
    systems = table_attribute(table, "systems", "p2_validation")
    if systems:
        lines += ["## Systems", "",
                  "| system | realizations | snapshot pairs | rho range | rho_J | never-dying classes | rattler rule |",
                  "|---|---|---|---|---|---|---|"]
        for name, info in systems.items():
            lo, hi = info["rho_range"]
            lines.append(f"| {name} | {info['realizations']} | {info['snapshot_pairs']} | {lo:.3f}–{hi:.3f} | "
                         f"{format_number(info['rho_J'], 4)} | {info['essential_convention']} | "
                         f"{info.get('rattler_rule', '')} |")
        lines.append("")
    tol = table_attribute(table, "tolerances", "p2_validation")
    lines += ["## Tolerances", "", ", ".join(f"{k} = {v}" for k, v in vars(tol).items()), ""]
    return lines


def _markdown_sections(table: pd.DataFrame) -> list[TableSection]:
    """One section: the verdict counts, then one row per claim."""
    return [TableSection("Claims", [verdict_summary(table), ""], list(VALIDATION_COLUMNS))]


def p2_validation_markdown(table: pd.DataFrame) -> str:
    """The validation table as Markdown: the systems measured, the tolerances, one row per claim."""
    return validation_markdown(table, P2_LAYOUT, _markdown_head(table), _markdown_sections(table))


def write_p2_validation(table: pd.DataFrame, csv_path: str | os.PathLike | None, md_path: str | os.PathLike, *,
                        paper_size: str | os.PathLike | None = None) -> None:
    """Write the validation table as CSV (skipped when `csv_path` is None) and Markdown (the arguments of
    `write_p1_validation`); with `paper_size` (the campaign's ``docs/validation/p2.csv``) a column beside P2's
    values gives our value at P2's size (`forcenet.report.claims_table.with_paper_size`)."""
    if paper_size is not None:
        table = with_paper_size(table, P2_LAYOUT, paper_size)
    write_validation_table(table, P2_LAYOUT, csv_path, md_path, _markdown_head(table), _markdown_sections(table))
