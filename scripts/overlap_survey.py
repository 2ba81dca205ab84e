#!/usr/bin/env python3
"""Where the largest overlaps of a campaign's last states sit (P1 §3: overlaps "up to 10 %" of the sum of the radii).

    .venv/bin/python scripts/overlap_survey.py --results results/validation --system 2d_hertz 3d_hertz

Per realization, at the system's largest ρ: the largest relative overlap, whether its pair touches a wall, the
largest one between particles that touch no wall, and the 99th percentile and median over all contacts
(`forcenet.report.p1.relative_overlaps`).
"""
from __future__ import annotations

import argparse
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "src"))

import numpy as np  # noqa: E402

from forcenet.datasets.paths import rho_file  # noqa: E402
from forcenet.datasets import read_snapshot  # noqa: E402
from forcenet.report.p1 import relative_overlaps  # noqa: E402


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--results", type=Path, default=Path("results/validation"))
    parser.add_argument("--system", nargs="+", required=True)
    args = parser.parse_args()
    print("| system | run | rho | largest | its pair touches a wall | largest away from the walls | 99th percentile "
          "| median |")
    print("|---|---|---|---|---|---|---|---|")
    for system in args.system:
        for run in sorted((args.results / "sim" / system).glob("r*")):
            last = sorted(run.glob(rho_file("*")))[-1]
            with read_snapshot(last) as snapshot:
                overlaps, at_wall = relative_overlaps(snapshot)
            k = int(np.argmax(overlaps))
            inner = overlaps[~at_wall].max() if (~at_wall).any() else float("nan")
            print(f"| {system} | {run.name} | {last.stem.removeprefix('rho')} | {overlaps[k]:.3f} | "
                  f"{'yes' if at_wall[k] else 'no'} | {inner:.3f} | {np.percentile(overlaps, 99):.3f} | "
                  f"{np.median(overlaps):.3f} |")


if __name__ == "__main__":
    main()
