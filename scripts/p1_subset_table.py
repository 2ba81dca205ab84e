#!/usr/bin/env python3
"""Judge P1's claims on some systems of a build only (the others' rows "not evaluated"), from their aggregates.

    .venv/bin/python scripts/p1_subset_table.py --results results/validation --systems 2d_linear 2d_hertz \
        --realizations 5 --csv /tmp/p1_2d.csv --md /tmp/p1_2d.md
    .venv/bin/python scripts/p1_subset_table.py --results results/validation --systems 2d_linear 2d_hertz 3d_hertz \
        --realizations 5 3d_hertz=3 --csv /tmp/p1_3sys.csv --md /tmp/p1_3sys.md
    .venv/bin/python scripts/compare_verdicts.py --measured 7d62395:docs/validation/p1.csv /tmp/p1_2d.csv

For checking part of a campaign when not all of it is on disk (docs/validation/README.md, session 41): the same
judging as the table job (`forcenet.pipeline.p1_validation_table`, force unit `dyn` as config/validation.yaml),
on `{results}/{system}/network_measures.nc` and `diagrams.nc` (or those under `--aggregates`) and the overlaps of
each realization's snapshot at the largest ρ (realizations 0 … N − 1 of each system, `--realizations`). No counterparts and no
readings beside: rows that need them, or a system left out, are "not evaluated".
"""
from __future__ import annotations

import argparse
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "src"))

from forcenet import pipeline  # noqa: E402
from forcenet.datasets import paths  # noqa: E402


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--results", default="results/validation", help="the build's results folder (its sim/)")
    parser.add_argument("--aggregates", help="folder holding {system}/network_measures.nc (default: --results)")
    parser.add_argument("--systems", nargs="+", required=True)
    parser.add_argument("--realizations", nargs="+", required=True, metavar="N or SYSTEM=N",
                        help="runs r00 … per system whose overlaps count: one count for every system, and/or "
                             "SYSTEM=N for one (e.g. 5 3d_hertz=3, as config/validation.yaml's realizations)")
    parser.add_argument("--force-unit", default="dyn", help="analysis.p1_force_unit (default dyn, as the campaign)")
    parser.add_argument("--csv", required=True)
    parser.add_argument("--md", required=True)
    args = parser.parse_args(argv)
    aggregates = args.aggregates or args.results
    counts = {}
    for item in args.realizations:
        system, _, count = item.rpartition("=")
        if not count.isdigit() or (system and system not in args.systems):
            parser.error(f"--realizations {item}: give N or SYSTEM=N with SYSTEM one of --systems")
        counts[system] = int(count)
    snapshots = []
    for system in args.systems:
        if system not in counts and "" not in counts:
            parser.error(f"--realizations: no count for {system} (give N or {system}=N)")
        for k in range(counts.get(system, counts.get(""))):
            run = Path(paths.run_dir(args.results, system, paths.realization_name(k)))
            largest = sorted(run.glob("rho*.nc"))  # the labels have one width, so the last name is the largest ρ
            if not largest:
                print(f"{run}: no snapshot", file=sys.stderr)
                return 2
            snapshots.append(str(largest[-1]))
    pipeline.p1_validation_table(
        measures=[paths.network_measures(aggregates, s) for s in args.systems], systems=args.systems,
        csv=args.csv, md=args.md, force_unit=args.force_unit, snapshots=snapshots,
        diagrams=[paths.diagrams(aggregates, s) for s in args.systems])
    return 0


if __name__ == "__main__":
    sys.exit(main())
