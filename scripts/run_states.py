#!/usr/bin/env python3
"""Tabulate the snapshots of finished compression runs (forcenet.research.survey.run_states), one markdown table per run.

    .venv/bin/python scripts/run_states.py --results results/validation --system 2d_hertz --realizations 0 1

Per snapshot: ρ, the bulk ρ (the inner box at least `--bulk-margin` d_ave from every wall), Z (rattlers
included), the particles with at least two particle contacts (P1's non-rattlers),
⟨|F|⟩ over the contacts in dyn (the system's material, from the config the run recorded), the mean and largest
overlap over the smaller diameter, and the relaxation steps. `--below RHO` keeps the states up to RHO.
"""
from __future__ import annotations

import argparse
import json
import math
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "src"))

from forcenet.datasets import read_snapshot  # noqa: E402
from forcenet.datasets.paths import realization_name, rho_file, run_dir  # noqa: E402
from forcenet.pipeline import force_constants  # noqa: E402
from forcenet.research.survey import BULK_MARGIN, run_states  # noqa: E402


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--results", default="results/validation", help="the results_dir of the runs' config")
    parser.add_argument("--system", required=True)
    parser.add_argument("--realizations", type=int, nargs="+", default=[0])
    parser.add_argument("--below", type=float, default=math.inf, help="only the states with ρ <= this")
    parser.add_argument("--bulk-margin", type=float, default=BULK_MARGIN,
                        help="bulk ρ: the inner box at least this far from every wall [d_ave]")
    args = parser.parse_args()

    for realization in args.realizations:
        folder = Path(run_dir(args.results, args.system, realization_name(realization)))
        snapshots = sorted(folder.glob(rho_file("*")))
        if not snapshots:
            sys.exit(f"no snapshots in {folder}")
        with read_snapshot(snapshots[0]) as snap:  # the config the run was made with
            unit = force_constants(json.loads(snap.attrs["config"]), args.system)["force_unit_dyn"]
        print(f"\n{args.system} {realization_name(realization)} ({folder})")
        print("| ρ | bulk ρ | Z | particles with ≥ 2 contacts | ⟨F⟩ [dyn] | overlap mean | overlap max | "
              "relaxation steps |")
        print("|---|---|---|---|---|---|---|---|")
        for row in run_states(folder, unit, args.bulk_margin):
            if row["rho"] <= args.below + 1e-9:
                print(f"| {row['rho']:.3f} | {row['rho_bulk']:.4f} | {row['Z']:.2f} | {row['connected']} | "
                      f"{row['mean_force_dyn']:.4g} | "
                      f"{row['overlap_mean']:.4f} | {row['overlap_max']:.3f} | {row['relaxation_steps']} |")


if __name__ == "__main__":
    main()
