"""The claims framework of both papers' validation tables (P1: `forcenet.report.p1_validation`, P2:
`forcenet.report.p2_validation`).

A **claim** (`Claim`) is one statement a paper makes about its results: an id, the paper's section, the statement,
the paper's value (a number, per system role or one for all, or the paper's words), the criterion it is judged by
(text with the tolerances filled in) and the function that judges it. Judging it on our data gives a `Judgement`
(our key number, the evidence, holds or not) or raises `NotEvaluated` (the data cannot decide: a system, a ρ range,
a quantity is missing; the message says which). A judged claim (`JudgedClaim`) is one row of a validation table:
id, section, statement, system, paper value, criterion, our value, evidence, verdict (`HOLDS`, `FAILS`,
`NOT_EVALUATED`) and, where a paper records one, why it does not hold.

`claims_frame` turns judged claims into a table whose columns each paper names its own way (`TableLayout`), and
`write_validation_table` writes that table as CSV and Markdown for either paper. `with_paper_size` sets, next to
each paper value, our value at the papers' sizes from the committed tables of the validation campaign
(``docs/validation/p1.csv``, ``p2.csv``; `forcenet.report.validation`), rows matched by claim id and system.
"""
from __future__ import annotations

import math
import os
from dataclasses import asdict, dataclass, field, is_dataclass
from pathlib import Path
from typing import Any, Callable, Mapping, Sequence

import numpy as np
import pandas as pd

__all__ = ["HOLDS", "FAILS", "NOT_EVALUATED", "IMPORTED_NOT_EVALUATED", "NotEvaluated", "Judgement", "Claim",
           "claim_register", "JudgedClaim", "judge_claim", "verdict_counts", "TableLayout", "TableSection",
           "claims_frame", "markdown_table",
           "validation_markdown", "write_validation_table", "PAPER_SIZE", "PAPER_SIZE_HEADER", "with_paper_size",
           "paper_size_placeholder"]

HOLDS, FAILS, NOT_EVALUATED = "holds", "does not hold", "not evaluated"

#: why a claim about the papers' compression protocol is not judged on imported states (`forcenet.importers`)
IMPORTED_NOT_EVALUATED = ("imported states: the claim is about the paper's compression protocol (walls, speed, "
                          "relaxation, sampling through jamming), which an import does not record")


class NotEvaluated(Exception):
    """Raised by a judge when the claim cannot be judged from the data; the message says why."""


@dataclass(frozen=True)
class Judgement:
    """What a judge found: the key number (NaN where the evidence is the whole answer), the evidence (the numbers
    behind the verdict, as text) and whether the claim holds."""

    measured: float
    evidence: str
    holds: bool


@dataclass(frozen=True)
class Claim:
    """One claim a paper makes about its results.

    id : stable identifier (P1 ``p1-<section>-<topic>``, P2 ``<section>-<n>``); section : the paper's section;
    statement : the claim in short (the paper's words where possible); criterion : how it is judged here, either
    a template whose ``{tolerance}`` fields `criterion_text` fills from the paper's tolerance record, or a function
    of that record; judge : the function judging it (its arguments are the paper's: P1 (SystemData, tolerances) or
    (ClaimContext); P2 (context)); paper : the paper's value, one for all, per system role (a mapping), NaN when
    the claim is qualitative, or the paper's words; scope : whom the claim is about, in the paper's terms (P1: the
    system roles, None for every system; P2: "frictional", "frictionless", "both", "tables"); per_system : one row
    per system of the scope (else one row across systems); needs_rho_j : the judge needs the system's ρ_J.
    """

    id: str
    section: str
    statement: str
    criterion: str | Callable[[Any], str]
    judge: Callable = field(repr=False)
    paper: float | str | Mapping[Any, float] = math.nan
    scope: Any = None
    per_system: bool = True
    needs_rho_j: bool = True

    def paper_value(self, key: Any = None) -> float | str:
        """The paper's value for the system role `key` (NaN where a mapping has none), or its one value."""
        if isinstance(self.paper, Mapping):
            return float(self.paper.get(key, math.nan))
        return self.paper if isinstance(self.paper, str) else float(self.paper)

    def criterion_text(self, tolerances: Any) -> str:
        """The criterion with the tolerances filled in (a field that is None reads "per system")."""
        if callable(self.criterion):
            return self.criterion(tolerances)
        values = asdict(tolerances) if is_dataclass(tolerances) else dict(tolerances)
        return self.criterion.format(**{k: ("per system" if v is None else v) for k, v in values.items()})


def claim_register(claims: list[Claim]) -> Callable[..., Callable]:
    """A decorator factory ``claim(id, section, statement, criterion, **fields)`` that appends the decorated judge
    as a `Claim` to `claims` (in definition order) and returns the judge unchanged."""
    def claim(id: str, section: str, statement: str, criterion: str | Callable, **options) -> Callable:
        """The decorator registering one claim (the fields of `Claim` besides the judge)."""
        def register(judge: Callable) -> Callable:
            """Append `judge` as the claim's `Claim` and return it unchanged."""
            claims.append(Claim(id=id, section=section, statement=statement, criterion=criterion, judge=judge,
                                **options))
            return judge
        return register
    return claim


@dataclass(frozen=True)
class JudgedClaim:
    """One row of a validation table. kind : ``"claim"``, or ``"value"`` for a number set beside the paper's without
    a criterion (P1's ρ_J, ρ_max …); system : the system(s) judged; paper : the paper's value (number or words);
    measured : our key number (NaN if none); evidence : what was measured; verdict : `HOLDS`, `FAILS`,
    `NOT_EVALUATED` (or "" for a value row with a value); explanation : why it does not hold (P2)."""

    id: str
    section: str
    statement: str
    system: str
    paper: float | str
    criterion: str
    measured: float
    evidence: str
    verdict: str
    kind: str = "claim"
    explanation: str = ""

    @property
    def difference(self) -> float:
        """measured − paper where both are finite numbers, else NaN."""
        if isinstance(self.paper, str):
            return math.nan
        measured, paper = float(self.measured), float(self.paper)
        return measured - paper if np.isfinite(measured) and np.isfinite(paper) else math.nan


def judge_claim(claim: Claim, system: str, paper: float | str, criterion: str, judge: Callable[[], Judgement],
                explain: Callable[[str], str] | None = None) -> JudgedClaim:
    """Run `judge` and record its verdict: `HOLDS` / `FAILS` from the `Judgement`, `NOT_EVALUATED` (the reason as
    evidence) when it raises `NotEvaluated`. `explain(verdict)` gives the explanation of a verdict (P2)."""
    try:
        judgement = judge()
        measured, evidence, verdict = judgement.measured, judgement.evidence, HOLDS if judgement.holds else FAILS
    except NotEvaluated as reason:
        measured, evidence, verdict = math.nan, str(reason), NOT_EVALUATED
    return JudgedClaim(id=claim.id, section=claim.section, statement=claim.statement, system=system, paper=paper,
                       criterion=criterion, measured=float(measured), evidence=evidence, verdict=verdict,
                       explanation=explain(verdict) if explain else "")


def verdict_counts(table: pd.DataFrame) -> dict[str, int]:
    """How many claim rows (all rows of a table without a ``kind`` column) hold, do not hold, are not evaluated."""
    claims = table[table["kind"] == "claim"] if "kind" in table else table
    return {verdict: int((claims["verdict"] == verdict).sum()) for verdict in (HOLDS, FAILS, NOT_EVALUATED)}


# =============================================================================================================
# The table: CSV and Markdown, either paper
# =============================================================================================================
@dataclass(frozen=True)
class TableLayout:
    """How a paper names the columns of its validation table.

    columns : CSV column → `JudgedClaim` field, in CSV order (``difference`` is the property of that name);
    headers : CSV column → Markdown header where they differ; id_column, system_column, measured_column,
    paper_column : the CSV columns holding the claim id, the system, our value and the paper's value (the
    paper-size column goes right after the paper's).
    """

    columns: Mapping[str, str]
    headers: Mapping[str, str] = field(default_factory=dict)
    id_column: str = "id"
    system_column: str = "system"
    measured_column: str = "measured"
    paper_column: str = "paper"


@dataclass(frozen=True)
class TableSection:
    """One Markdown section of a validation table: a heading, lines of text, then the table of the rows of `kind`
    (None: every row) with `columns` (CSV names; the paper-size column is added after the paper's when present)."""

    heading: str
    text: Sequence[str]
    columns: Sequence[str]
    kind: str | None = None


def claims_frame(claims: Sequence[JudgedClaim], layout: TableLayout) -> pd.DataFrame:
    """The judged claims as a table, one row each, the columns of `layout`."""
    rows = [{column: getattr(claim, name) for column, name in layout.columns.items()} for claim in claims]
    return pd.DataFrame(rows, columns=list(layout.columns))


def _cell(value: Any) -> str:
    """A Markdown table cell: a float to 4 significant digits ("–" if not finite), text with ``|`` escaped (GFM)."""
    if isinstance(value, (float, np.floating)):
        return "–" if not np.isfinite(value) else f"{value:.4g}"
    return str(value).replace("|", "\\|")


def markdown_table(frame: pd.DataFrame, columns: Sequence[str], headers: Mapping[str, str] | None = None) -> list[str]:
    """Lines of a GitHub-flavoured Markdown table of `columns` of `frame`, headed by `headers` (default: the names)."""
    headers = headers or {}
    lines = ["| " + " | ".join(headers.get(c, c) for c in columns) + " |", "|" + "|".join("---" for _ in columns) + "|"]
    for _, row in frame.iterrows():
        lines.append("| " + " | ".join(_cell(row[c]) for c in columns) + " |")
    return lines


def _shown(frame: pd.DataFrame, columns: Sequence[str], layout: TableLayout) -> list[str]:
    """`columns` with the paper-size column after the paper's, when the frame has one."""
    shown = list(columns)
    if PAPER_SIZE in frame and layout.paper_column in shown and PAPER_SIZE not in shown:
        shown.insert(shown.index(layout.paper_column) + 1, PAPER_SIZE)
    return shown


def validation_markdown(frame: pd.DataFrame, layout: TableLayout, head: Sequence[str],
                        sections: Sequence[TableSection]) -> str:
    """The Markdown document of a validation table: the `head` lines, then each section's heading, text and table."""
    headers = {PAPER_SIZE: PAPER_SIZE_HEADER, **layout.headers}
    lines = list(head)
    if PAPER_SIZE in frame:
        lines += [f"The column '{PAPER_SIZE_HEADER}' is our value (and verdict) at the papers' sizes, from the "
                  f"validation campaign's committed table {frame.attrs.get(PAPER_SIZE, 'docs/validation')}: set "
                  "beside this build's value, it shows which differences from the paper come from the small "
                  "systems.", ""]
    for section in sections:
        rows = frame if section.kind is None else frame[frame["kind"] == section.kind]
        lines += [f"## {section.heading}", "", *section.text]
        lines += markdown_table(rows, _shown(frame, section.columns, layout), headers)
        lines.append("")
    return "\n".join(lines[:-1] if lines and lines[-1] == "" else lines) + "\n"


def write_validation_table(frame: pd.DataFrame, layout: TableLayout, csv_path: str | os.PathLike | None,
                           md_path: str | os.PathLike, head: Sequence[str], sections: Sequence[TableSection]) -> None:
    """Write a validation table as CSV (every column, `frame`'s order; skipped when `csv_path` is None) and as the
    Markdown of `validation_markdown`."""
    for path in (csv_path, md_path):
        if path is not None:
            Path(path).parent.mkdir(parents=True, exist_ok=True)
    if csv_path is not None:
        frame.to_csv(csv_path, index=False)
    Path(md_path).write_text(validation_markdown(frame, layout, head, sections))


# =============================================================================================================
# Our value at the papers' sizes, from the committed campaign tables (docs/validation/, issue: a user sees which
# differences come from the small systems)
# =============================================================================================================
PAPER_SIZE = "paper_size"  # CSV column: our value and verdict at the papers' sizes
PAPER_SIZE_HEADER = "ours, paper size"  # its Markdown header


def paper_size_placeholder(path: str | os.PathLike) -> str:
    """What the paper-size column says when the campaign table `path` does not exist (not yet run)."""
    return f"not yet run ({path} missing)"


def with_paper_size(frame: pd.DataFrame, layout: TableLayout, campaign_csv: str | os.PathLike) -> pd.DataFrame:
    """`frame` with the column `PAPER_SIZE` right after the paper's value: for each row our value at the papers'
    sizes, read from `campaign_csv` (a committed table of `forcenet.report.validation`: ``# `` provenance lines,
    then the rows with the same columns as `frame`), matched by claim id and system: its value and, where it has
    one, its verdict in brackets ("0.805", "0.27 (holds)"). A row the campaign table lacks reads "not in <path>";
    every row reads `paper_size_placeholder` when the file does not exist."""
    path = Path(campaign_csv)
    out = frame.copy()
    if path.exists():
        campaign = pd.read_csv(path, comment="#", dtype=str, keep_default_na=False)
        missing = {layout.id_column, layout.system_column, layout.measured_column} - set(campaign)
        if missing:
            raise ValueError(f"{path}: no column(s) {sorted(missing)}: not a validation table of the campaign")
        verdicts = campaign["verdict"] if "verdict" in campaign else pd.Series("", index=campaign.index)
        found = {}
        for key, measured, verdict in zip(zip(campaign[layout.id_column], campaign[layout.system_column]),
                                          campaign[layout.measured_column], verdicts):
            if key[0]:
                found.setdefault(key, _paper_size_text(measured, verdict))
        keys = zip(frame[layout.id_column].astype(str), frame[layout.system_column].astype(str))
        values = [found.get(key, f"not in {campaign_csv}") for key in keys]
    else:
        values = [paper_size_placeholder(campaign_csv)] * len(frame)
    out.insert(list(out.columns).index(layout.paper_column) + 1, PAPER_SIZE, values)
    out.attrs = {**frame.attrs, PAPER_SIZE: str(campaign_csv)}
    return out


def _paper_size_text(measured: str, verdict: str) -> str:
    """A campaign row's value as the paper-size cell: numbers to 4 significant digits, the verdict in brackets."""
    try:
        number = float(measured)
        measured = "–" if not np.isfinite(number) else f"{number:.4g}"
    except ValueError:
        pass
    measured = measured or "–"
    return f"{measured} ({verdict})" if verdict else measured
