#!/usr/bin/env python3
"""Compare two builds' results folders value by value (forcenet.datasets.compare).

    git worktree add /tmp/before HEAD~1 && (cd /tmp/before && snakemake --cores 2 --configfile config/smoke.yaml)
    snakemake --cores 2 --configfile config/smoke.yaml
    .venv/bin/python scripts/compare_builds.py /tmp/before/results results

Snapshots (under sim/) must agree bit for bit, every other netCDF variable and CSV cell within --rtol/--atol;
attributes (commit, date, config) are ignored. Prints one line per difference and exits 1 if there is any.
"""
from __future__ import annotations

import argparse
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "src"))

from forcenet.datasets.compare import DEFAULT_ATOL, DEFAULT_RTOL, compare_trees  # noqa: E402


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("before", type=Path)
    parser.add_argument("after", type=Path)
    parser.add_argument("--rtol", type=float, default=DEFAULT_RTOL)
    parser.add_argument("--atol", type=float, default=DEFAULT_ATOL)
    args = parser.parse_args()
    for folder in (args.before, args.after):
        if not folder.is_dir():
            parser.error(f"{folder} is not a folder")
    problems = compare_trees(args.before, args.after, args.rtol, args.atol)
    for line in problems:
        print(line)
    print(f"{len(problems)} difference(s) between {args.before} and {args.after}", file=sys.stderr)
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
