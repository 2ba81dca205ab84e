#!/usr/bin/env python3
"""Compare two validation tables of one paper verdict by verdict (forcenet.report.claims_table.verdict_changes).

    .venv/bin/python scripts/compare_verdicts.py HEAD~1:docs/validation/p1.csv docs/validation/p1.csv
    .venv/bin/python scripts/compare_verdicts.py docs/validation/p2.csv results/validation_r3/tables/p2_validation.csv

Each table is a CSV path, or REV:PATH for the table as committed at a git revision (`git show REV:PATH`, run in the
repository). Prints each table's provenance (commit, date, realizations per system, where it has them) and its
verdict counts on the table's own reading, then one Markdown row per row (a claim's, or one of P1's values such as
rho_J) whose verdict, marker or robustness (share of bootstrap resamples under which it holds) changed, or that
only one table has; our measured value is shown beside (`--measured`: a change of it is listed too, e.g. to check
that runs made again from the same settings and seeds give the same table). `--csv FILE` also writes those rows.
Exit status 0 whatever changed (2: a table cannot be read).
"""
from __future__ import annotations

import argparse
import io
import subprocess
import sys
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(REPO / "src"))

from forcenet.report.claims import verdict_summary  # noqa: E402
from forcenet.report.claims_table import (COMPARED_COLUMNS, markdown_table, printed_value,  # noqa: E402
                                          read_validation_csv, verdict_changes)
from forcenet.report.p1_validation import P1_LAYOUT  # noqa: E402
from forcenet.report.p2_validation import P2_LAYOUT  # noqa: E402


def _text(source: str) -> str:
    """The CSV text of `source`: a file, or REV:PATH read from git (a path that exists wins over REV:PATH)."""
    path = Path(source)
    if path.is_file():
        return path.read_text()
    revision, separator, inside = source.partition(":")
    if not separator:
        raise FileNotFoundError(f"{source}: no such file (and not REV:PATH)")
    shown = subprocess.run(["git", "-C", str(REPO), "show", f"{revision}:{inside}"], capture_output=True, text=True)
    if shown.returncode != 0:
        raise FileNotFoundError(f"{source}: {shown.stderr.strip()}")
    return shown.stdout


def _provenance(text: str) -> list[str]:
    """The ``# key: value`` lines heading a campaign table, without the '# '."""
    return [line[2:] for line in text.splitlines() if line.startswith("# ")]


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("before", help="a table's CSV, or REV:PATH")
    parser.add_argument("after", help="a table's CSV, or REV:PATH")
    parser.add_argument("--csv", type=Path, help="also write the changed rows here")
    parser.add_argument("--measured", action="store_true",
                        help="also list the rows whose measured value changed (as written: the same runs give the "
                             "same text)")
    args = parser.parse_args()
    tables = {}
    for when, source in (("before", args.before), ("after", args.after)):
        try:
            text = _text(source)
            tables[when] = read_validation_csv(io.StringIO(text))
        except (OSError, ValueError) as error:
            print(f"compare_verdicts: {error}", file=sys.stderr)
            return 2
        print(f"## {when}: {source}")
        print("\n".join(f"- {line}" for line in _provenance(text)))
        print(f"- {verdict_summary(tables[when])}\n")
    layouts = [layout for layout in (P1_LAYOUT, P2_LAYOUT) if all(layout.id_column in t for t in tables.values())]
    if not layouts:
        print("compare_verdicts: the two tables are not validation tables of one paper (no common claim id column)",
              file=sys.stderr)
        return 2
    compared = ("measured", *COMPARED_COLUMNS) if args.measured else COMPARED_COLUMNS
    changes = verdict_changes(tables["before"], tables["after"], layouts[0].id_column, compared)
    if changes.empty:
        print(f"No {', '.join(compared[:-1])} or {compared[-1]} changed; both tables judge the same rows.")
    else:
        counts = changes["change"].value_counts()
        print(f"## {len(changes)} rows changed (" + ", ".join(f"{n} {what}" for what, n in counts.items()) + ")\n")
        shown = changes.copy()
        for column in ("measured before", "measured after"):
            shown[column] = [printed_value(value) if value else "" for value in shown[column]]
        print("\n".join(markdown_table(shown, list(shown.columns))))
    if args.csv:
        changes.to_csv(args.csv, index=False)
    return 0


if __name__ == "__main__":
    sys.exit(main())
