#!/usr/bin/env python3
"""The restitution of the damping control (docs/validation/controls.md, control 1 a): the column "e (median
approach speed near ρ_J)" of the damping series (`forcenet.research.damping_series`) for each run of a Hertz system,
their mean and the mean rounded to three decimals, the value `2d_linear_lightdamp` takes as its `restitution`.

    .venv/bin/python scripts/control_restitution.py results/validation:2d_hertz:r01 … results/rerun:2d_hertz:r00

Each run is FOLDER:SYSTEM:rNN, a results folder holding the run's own snapshots (the approach speeds need their
velocities, which a campaign record does not keep).
"""
from __future__ import annotations

import argparse
import math
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "src"))

from forcenet.research.damping_series import SeriesRun, series_row  # noqa: E402


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("runs", nargs="+", metavar="FOLDER:SYSTEM:rNN")
    args = parser.parse_args()
    values = []
    print("| run | results | e (median approach speed near ρ_J) | median approach speed [d_ave/τ_c] | whole grid |")
    print("|---|---|---|---|---|")
    for text in args.runs:
        row = series_row(SeriesRun.parse(text))
        if "e_at_median_speed" not in row:
            print(f"{text}: {row.get('status', 'no row')}", file=sys.stderr)
            return 1
        values.append(row["e_at_median_speed"])
        print(f"| {row['system']} {row['realization']} | {row['results']} | {row['e_at_median_speed']:.4f} | "
              f"{row['median_approach_speed']:.3g} | {'yes' if row['completed'] else 'no'} |")
    if any(not math.isfinite(v) for v in values):
        print("a run has no approach speed near its ρ_J: no value", file=sys.stderr)
        return 1
    mean = sum(values) / len(values)
    print(f"\nmean over {len(values)} runs: {mean:.5f}; restitution of the control: {round(mean, 3):.3f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
