#!/usr/bin/env python3
"""Judge P1's claims on some systems of a build only (the others' rows "not evaluated"), from their aggregates.

    .venv/bin/python scripts/p1_subset_table.py --results results/validation --systems 2d_linear 2d_hertz \
        --realizations 5 --csv /tmp/p1_2d.csv --md /tmp/p1_2d.md
    .venv/bin/python scripts/p1_subset_table.py --results results/validation --systems 2d_linear 2d_hertz 3d_hertz \
        --realizations 5 3d_hertz=3 --csv /tmp/p1_3sys.csv --md /tmp/p1_3sys.md
    .venv/bin/python scripts/compare_verdicts.py --measured HEAD:docs/validation/p1.csv /tmp/p1_2d.csv

For checking part of a campaign when not all of it is on disk (docs/validation/README.md, "Regenerate"): the same
judging as the table job (`forcenet.pipeline.p1_validation_table`, force unit `dyn` as config/validation.yaml),
on `{results}/{system}/network_measures.nc` and `diagrams.nc` (or those under `--aggregates`) and the overlaps of
each realization's snapshot at the largest ρ, for realizations 0 … N − 1 of each system (`--realizations`): an
aggregate holding more realizations is judged on its first N only (so that five runs on disk can be read as the
first three were), one holding fewer is refused. No counterparts and no readings beside: rows that need them, or
a system left out, are "not evaluated".
"""
from __future__ import annotations

import argparse
import sys
import tempfile
from pathlib import Path

import numpy as np
import xarray as xr

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "src"))

from forcenet import pipeline  # noqa: E402
from forcenet.datasets import paths, write_netcdf  # noqa: E402


def first_realizations(aggregates: str, system: str, count: int, folder: str) -> tuple[str, str]:
    """(network_measures.nc, diagrams.nc) of `system` holding its realizations 0 … `count` − 1 only: the files
    under `aggregates` when they hold exactly those, else copies cut to them under `folder`. ValueError when
    the aggregate lacks one of them."""
    measures_path, diagrams_path = paths.network_measures(aggregates, system), paths.diagrams(aggregates, system)
    wanted = np.arange(count)
    with xr.open_dataset(measures_path) as measures, xr.open_dataset(diagrams_path) as diagrams:
        held = measures["realization"].values
        missing = sorted(set(wanted.tolist()) - set(held.tolist()))
        if missing:
            raise ValueError(f"{measures_path} holds realizations {held.tolist()}, not {missing}")
        if np.array_equal(np.sort(held), wanted):
            return measures_path, diagrams_path
        cut_measures = measures.sel(realization=wanted).load()
        cut_diagrams = diagrams.isel(point=np.flatnonzero(diagrams["point_realization"].values < count)).load()
    out_measures, out_diagrams = paths.network_measures(folder, system), paths.diagrams(folder, system)
    Path(out_measures).parent.mkdir(parents=True, exist_ok=True)
    write_netcdf(cut_measures, out_measures, "network_measures")
    write_netcdf(cut_diagrams, out_diagrams, "diagrams")
    return out_measures, out_diagrams


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
    with tempfile.TemporaryDirectory(prefix="p1_subset_") as folder:
        try:
            files = [first_realizations(aggregates, s, counts.get(s, counts.get("")), folder) for s in args.systems]
        except ValueError as error:
            print(error, file=sys.stderr)
            return 2
        pipeline.p1_validation_table(
            measures=[m for m, _ in files], systems=args.systems, csv=args.csv, md=args.md,
            force_unit=args.force_unit, snapshots=snapshots, diagrams=[d for _, d in files])
    return 0


if __name__ == "__main__":
    sys.exit(main())
