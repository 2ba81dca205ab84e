#!/usr/bin/env python
"""A/B of the DEM step loop between two source trees (benchmark, not a test): is a change as fast as before it?

usage: python bench/dem_ab.py BEFORE_TREE [AFTER_TREE] [--pairs 5] [--cpu C] [--steps S] [--only 2d|3d]
                              [--label NAME] [--no-record]

Runs `bench/dem_vs_lammps.py --ours-only --repeat 1` (our engine on its 2D and 3D states: N = 2000 disks,
N = 4000 spheres, Hertz, flat walls moving inward) alternately with each tree's src/ on PYTHONPATH, A B A B …,
`--pairs` times, every run pinned to the same core (`taskset -c C`) and at this process's priority; `--only` runs one
case (a change that touches one dimension's loop, and twice the pairs in the same time). A tree is a
checkout, e.g. `git worktree add /tmp/before <commit>`; AFTER_TREE defaults to this one. Each tree compiles its
own kernels once (numba's cache folder is named after the kernel sources), before the first timed run.

Prints, per case, the throughput of each run (particle-steps per CPU-second) and after/before per pair; the last
line is one JSON object with, per case, the median ratio and its range over the pairs. The record lands in
bench/results/dem_ab-<label>.json (bench/records.py), with both trees' commits.
"""
from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
from pathlib import Path

import records  # bench/records.py

HERE = Path(__file__).resolve().parent


def tree_commit(tree: Path) -> str:
    return subprocess.run(["git", "-C", str(tree), "rev-parse", "HEAD"], capture_output=True, text=True,
                          check=True).stdout.strip()


def run_tree(tree: Path, cpu: int, steps: int | None, only: str | None = None) -> dict:
    """{"ours_2d": …, "ours_3d": …} (or the `only` case's) particle-steps per CPU-second of one run of our engine
    from `tree`'s src/."""
    command = ["taskset", "-c", str(cpu), sys.executable, str(HERE / "dem_vs_lammps.py"), "--ours-only",
               "--repeat", "1", "--cpu", str(cpu), "--no-record"]
    if steps:
        command += ["--steps", str(steps)]
    if only:
        command += ["--only", only]
    env = dict(os.environ, PYTHONPATH=str(tree / "src"))
    result = subprocess.run(command, capture_output=True, text=True, env=env, check=True)
    return json.loads(result.stdout.strip().splitlines()[-1])


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("before", type=Path)
    ap.add_argument("after", type=Path, nargs="?", default=HERE.parent)
    ap.add_argument("--pairs", type=int, default=5)
    ap.add_argument("--cpu", type=int, default=max(os.sched_getaffinity(0)))
    ap.add_argument("--steps", type=int, help="override the states' 20000 steps")
    ap.add_argument("--only", choices=("2d", "3d"), help="run one case only")
    ap.add_argument("--label", default="step_loop")
    records.add_no_record(ap)
    args = ap.parse_args(argv)
    trees = {"before": args.before.resolve(), "after": args.after.resolve()}
    commits = {side: tree_commit(tree) for side, tree in trees.items()}
    run = records.Run("dem_ab", variant=args.label, enabled=records.wanted(args, argv),
                      settings=dict(pairs=args.pairs, cpu=args.cpu, steps=args.steps, only=args.only, before=commits["before"],
                                    after=commits["after"], after_dirty=records.git_state(trees["after"])[1]))
    for side, tree in trees.items():  # compile each tree's kernels outside the timed runs
        run_tree(tree, args.cpu, 200, args.only)
    rates = {side: [] for side in trees}
    for pair in range(args.pairs):
        for side, tree in trees.items():
            rates[side].append(run_tree(tree, args.cpu, args.steps, args.only))
            print(json.dumps({"pair": pair, "side": side, **rates[side][-1]}), flush=True)
    summary = {}
    for case in [args.only] if args.only else ["2d", "3d"]:
        key = f"ours_{case}"
        ratios = [a[key] / b[key] for a, b in zip(rates["after"], rates["before"])]
        summary[case] = dict(ratio_median=statistics.median(ratios), ratio_min=min(ratios), ratio_max=max(ratios),
                             ratios=ratios, before=[r[key] for r in rates["before"]],
                             after=[r[key] for r in rates["after"]])
        print(f"{case}: after/before {summary[case]['ratio_median']:.4f} (pairs {min(ratios):.4f}–{max(ratios):.4f})",
              flush=True)
    run.write(measured=summary)
    print(json.dumps({case: {k: v for k, v in values.items() if k.startswith("ratio_")}
                      for case, values in summary.items()}))
    return 0


if __name__ == "__main__":
    sys.exit(main())
