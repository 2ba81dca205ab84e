"""The validation tables of both papers (P1: `forcenet.report.p1_validation`, P2: `forcenet.report.p2_validation`),
made of judged claims (`forcenet.report.claims.JudgedClaim`).

`claims_frame` turns judged claims into a table whose columns each paper names its own way (`TableLayout`), and
`write_validation_table` writes that table as CSV and Markdown for either paper. `with_paper_size` sets, next to
each paper value, our value at the papers' sizes from the committed tables of the validation campaign
(``docs/validation/p1.csv``, ``p2.csv``; `forcenet.report.validation`), rows matched by claim id and system.
`read_validation_csv` reads a table back (its provenance lines skipped) and `verdict_changes` compares two.
"""
from __future__ import annotations

import io
import os
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Mapping, Sequence

import numpy as np
import pandas as pd

from forcenet.errors import ForcenetError
from forcenet.report.claims import MARGINAL, MARGINAL_FRACTION, VACUOUS, JudgedClaim

#: the columns both papers' tables end with, the same names and fields (CSV name → `JudgedClaim` field)
VERDICT_COLUMNS = {"verdict": "verdict", "marker": "marker", "states": "states", "robustness": "robustness",
                   "reading": "reading", "explanation": "explanation", "explanation_basis": "explanation_basis",
                   "judge_changed_after_reading": "judge_changed_after_reading"}


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


class TableAttributeError(ForcenetError, ValueError):
    """A report table without an attribute its reader needs: one line naming the attribute and what sets it."""


def table_attribute(frame: pd.DataFrame, key: str, made_by: str) -> Any:
    """``frame.attrs[key]``, which `made_by` sets on every table it builds (a P1 or P2 validation table, a P2
    Table I–III). A table without it (read back from its CSV, which keeps no attributes, or built by hand) raises
    `TableAttributeError` naming the key and its maker: a reader never falls back on a default."""
    if key not in frame.attrs:
        raise TableAttributeError(f"the table has no attribute '{key}' (set by {made_by}, which every reader of "
                                  f"it needs): use the table {made_by} returns, not one read from its CSV")
    return frame.attrs[key]


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


#: what the columns every validation table shares mean (set under each table's head)
VERDICT_NOTE = (
    f"marker: '{MARGINAL}' where the verdict was decided within {100 * MARGINAL_FRACTION:.0f} % of its threshold "
    f"or turns if one state moves by one grid step; '{VACUOUS}' where the claim holds only because its quantity is "
    "zero everywhere it is judged; both are counted apart from the fair verdicts. robustness: the share of "
    "bootstrap resamples of the realizations (seeded) under which the claim holds, so that a verdict carried by one "
    "realization shows; 'one run: <systems>' where the verdict rests on a single run that no resample varies. "
    "states: the states (rho) that carry the verdict. reading: empty for the table's own "
    "conventions, else the other reading the row is judged under, beside the primary row of the same claim. "
    "explanation_basis: 'measured: <command>' where the cause of a miss was measured, 'hypothesis' where it was not. "
    "judge_changed_after_reading: where the claim's judge was changed after its verdicts had been read, the date, "
    "the rule now applied and the verdict the row had before.")


def validation_markdown(frame: pd.DataFrame, layout: TableLayout, head: Sequence[str],
                        sections: Sequence[TableSection]) -> str:
    """The Markdown document of a validation table: the `head` lines, `VERDICT_NOTE`, then each section's heading,
    text and table."""
    headers = {PAPER_SIZE: PAPER_SIZE_HEADER, **layout.headers}
    lines = [*head, VERDICT_NOTE, ""]
    if PAPER_SIZE in frame:
        lines += [f"The column '{PAPER_SIZE_HEADER}' is our value (and verdict) at the papers' sizes, from the "
                  f"validation campaign's committed table {table_attribute(frame, PAPER_SIZE, 'with_paper_size')}: set "
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
        campaign = read_validation_csv(path)
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


def read_validation_csv(source: str | os.PathLike | Any, as_text: bool = True) -> pd.DataFrame:
    """A validation table's CSV (a path or an open text stream) as written by `write_validation_table` or the
    campaign (`forcenet.report.validation`), its leading ``#`` provenance lines skipped: every cell text, empty
    cells "" (`as_text`), else pandas' own types and NaN.

    Only the leading lines are skipped, not every "#" (pandas' ``comment``): a cell may hold one ("issue #24")."""
    text = source.read() if hasattr(source, "read") else Path(source).read_text()
    lines = text.splitlines(keepends=True)
    heading = next((i for i, line in enumerate(lines) if not line.startswith("#")), len(lines))
    body = io.StringIO("".join(lines[heading:]))
    return pd.read_csv(body, dtype=str, keep_default_na=False) if as_text else pd.read_csv(body)


# =============================================================================================================
# Two tables of one paper, verdict by verdict (a campaign regenerated, a setting changed)
# =============================================================================================================
#: the columns that, where a table has them, tell its rows apart beside the claim id (P2's Tables I–III rows
#: differ by pair and quadrant, P1's and P2's claims by system and reading)
ROW_KEY_COLUMNS = ("table", "system", "reading", "pair", "quadrant")
#: what is compared row by row: a change in any of these is reported; `measured` is shown beside, not compared
#: (it moves with every new realization)
COMPARED_COLUMNS = ("verdict", "marker", "robustness")


def verdict_changes(before: pd.DataFrame, after: pd.DataFrame, id_column: str = "id",
                    compared: Sequence[str] = COMPARED_COLUMNS) -> pd.DataFrame:
    """The rows of two validation tables of one paper (claims and P1's values: every row with a claim id) that
    differ in verdict, marker or robustness (or whichever `compared` columns; add "measured" to see every value
    that moved, as text), and the rows only one table has.

    before, after : tables read by `read_validation_csv`; rows are matched by `id_column` and whichever of
    `ROW_KEY_COLUMNS` both tables have. Returns one row per change, in `after`'s order (rows only `before` has
    last): the key columns, ``<column> before`` and ``<column> after`` for measured, verdict, marker and
    robustness ("" where the table has no such row), and ``change``: the compared columns that differ, joined
    by ", ", or "only before" / "only after"."""
    keys = [id_column] + [c for c in ROW_KEY_COLUMNS if c in before and c in after]
    shown = ["measured", *COMPARED_COLUMNS]
    unknown = set(compared) - set(shown)
    if unknown:
        raise ValueError(f"cannot compare {sorted(unknown)}: only {shown}")

    def judged(table: pd.DataFrame, name: str) -> pd.DataFrame:
        """The rows with a claim id, indexed by the key; every shown column (missing ones empty)."""
        if id_column not in table:
            raise ValueError(f"the {name} table has no column {id_column!r}: not a validation table of this paper")
        rows = table.reindex(columns=keys + shown, fill_value="").fillna("").astype(str)
        rows = rows[rows[id_column] != ""]  # P2's Tables I–III rows have none: they are not claims
        duplicated = rows.duplicated(keys)
        if duplicated.any():
            raise ValueError(f"the {name} table has rows with the same {keys}: "
                             f"{rows.loc[duplicated, keys].iloc[0].tolist()}")
        return rows.set_index(keys)

    old, new = judged(before, "before"), judged(after, "after")
    changes = []
    for key in [*new.index, *(k for k in old.index if k not in new.index)]:
        in_old, in_new = key in old.index, key in new.index
        if in_old and in_new:
            differs = [c for c in shown if c in compared and old.at[key, c] != new.at[key, c]]
            if not differs:
                continue
            change = ", ".join(differs)
        else:
            change = "only after" if in_new else "only before"
        row = dict(zip(keys, key if isinstance(key, tuple) else (key,)))
        for column in shown:
            row[f"{column} before"] = old.at[key, column] if in_old else ""
            row[f"{column} after"] = new.at[key, column] if in_new else ""
        row["change"] = change
        changes.append(row)
    columns = keys + [f"{c} {when}" for c in shown for when in ("before", "after")] + ["change"]
    return pd.DataFrame(changes, columns=columns)


def printed_value(measured: str) -> str:
    """A table cell's value as the tables print it: a number to 4 significant digits ("–" when not finite or
    empty), words unchanged."""
    try:
        number = float(measured)
        measured = "–" if not np.isfinite(number) else f"{number:.4g}"
    except ValueError:
        pass
    return measured or "–"


def _paper_size_text(measured: str, verdict: str) -> str:
    """A campaign row's value as the paper-size cell: `printed_value`, the verdict in brackets."""
    measured = printed_value(measured)
    return f"{measured} ({verdict})" if verdict else measured
