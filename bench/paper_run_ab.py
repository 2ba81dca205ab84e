#!/usr/bin/env python
"""One paper-size compression run made by two source trees side by side (benchmark, not a test): the CPU time of
the whole run, before and after a change, on the same machine at the same time.

usage: python bench/paper_run_ab.py BEFORE_TREE [AFTER_TREE] [--system 3d_hertz] [--realization r00]
                                    [--config config/validation.yaml] [--out DIR] [--cpus 0,1] [--no-record]

Each tree makes the same run of its --config (its own copy of it, with `records_dir: null`, so that
the run is simulated rather than restored from its committed record, and `results_dir` under --out), through the
workflow as `forcenet-campaign run` makes it: `nice -n 10 snakemake <run>/run_cost.json --cores 1`, with the
tree's src/ on PYTHONPATH, BEFORE on the first CPU of --cpus and AFTER on the second, both at once. A tree is a
checkout, e.g. `git worktree add /tmp/before <commit>`; AFTER_TREE defaults to this one. The default run,
3d_hertz r00, is the 4096-sphere run of P1 (about an hour of CPU on a development machine).

When both have finished it reports each run's CPU time (its `run_cost.json`: every job of the run, the JIT
compilation included), after / before, and whether the two runs' snapshots are the same in every variable, and
the same as the run's committed record in every variable the record keeps (under the config's `records_dir`, if
the run has one there).
Progress lines (each run's log) every --poll seconds. The record lands in bench/results/paper_run_ab-<system>.json
(bench/records.py) with both trees' commits. Nothing is written into either tree but Snakemake's own .snakemake/.
"""
from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import xarray as xr
import yaml

import records  # bench/records.py
from dem_ab import tree_commit
from forcenet.datasets import paths
from forcenet.datasets.records import record_differences

HERE = Path(__file__).resolve().parent


def run_config(tree: Path, config_name: str, results: Path) -> Path:
    """The tree's config (`config_name`, relative to it) with the run simulated into `results` (no records
    folder)."""
    config = yaml.safe_load((tree / config_name).read_text())
    config["results_dir"] = str(results)
    config["records_dir"] = None
    target = results.parent / "validation.yaml"
    target.parent.mkdir(parents=True, exist_ok=True)
    target.write_text(yaml.safe_dump(config, sort_keys=False))
    return target


def start_run(tree: Path, config_name: str, results: Path, system: str, realization: str, cpu: int,
              log: Path) -> subprocess.Popen:
    """Snakemake making the run's cost record (so the run itself), niced, on one CPU, from `tree`."""
    configfile = run_config(tree, config_name, results)
    target = paths.run_cost(str(results), system, realization)
    command = ["taskset", "-c", str(cpu), "nice", "-n", "10", sys.executable, "-m", "snakemake", target,
               "--configfile", str(configfile), "--cores", "1", "--snakefile", str(tree / "Snakefile"),
               "--directory", str(tree), "--nolock"]
    env = dict(os.environ, PYTHONPATH=str(tree / "src"))
    return subprocess.Popen(command, env=env, stdout=log.open("w"), stderr=subprocess.STDOUT)


def snapshot_files(results: Path, system: str, realization: str) -> list[Path]:
    """The run's published snapshots, in ρ order (their names sort so)."""
    return sorted(Path(paths.run_dir(str(results), system, realization)).glob("*.nc"))


def differing_variables(first: list[Path], second: list[Path]) -> list[str]:
    """'state: variable' for every data variable that differs between two runs' snapshots (empty: the same)."""
    if len(first) != len(second):
        return [f"{len(first)} snapshots against {len(second)}"]
    problems = []
    for a_path, b_path in zip(first, second):
        with xr.open_dataset(a_path) as a, xr.open_dataset(b_path) as b:
            for name in sorted(set(a.data_vars) | set(b.data_vars)):
                if name not in a or name not in b or not np.array_equal(a[name].values, b[name].values,
                                                                         equal_nan=True):
                    problems.append(f"{a_path.name}: {name}")
    return problems


def differences_from_record(snapshots: list[Path], record_path: Path | None) -> list[str] | None:
    """Where a run's snapshots differ from its committed record in a variable the record keeps
    (`forcenet.datasets.records.record_differences`, less the global attributes: another run has its own commit
    and date); None when there is no record."""
    if record_path is None or not record_path.exists():
        return None
    with xr.open_dataset(record_path) as record:
        opened = [xr.open_dataset(path) for path in snapshots]
        try:
            problems = record_differences(record, opened)
        finally:
            for dataset in opened:
                dataset.close()
    return [problem for problem in problems if not problem.endswith("global attributes differ")]


def last_progress(log: Path) -> str:
    """The last line of a run's own log (its progress: ρ, Z, steps/s, time left), or '' before it has one."""
    if not log.exists():
        return ""
    lines = log.read_text(errors="replace").strip().splitlines()
    return lines[-1][-160:] if lines else ""


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("before", type=Path)
    ap.add_argument("after", type=Path, nargs="?", default=HERE.parent)
    ap.add_argument("--config", default="config/validation.yaml", help="the config, relative to each tree")
    ap.add_argument("--system", default="3d_hertz")
    ap.add_argument("--realization", default="r00")
    ap.add_argument("--out", type=Path, default=Path("/tmp/forcenet-paper-run-ab"))
    ap.add_argument("--cpus", default="0,1", help="CPU of the before run, CPU of the after run")
    ap.add_argument("--poll", type=float, default=300.0, help="seconds between progress lines")
    records.add_no_record(ap)
    args = ap.parse_args(argv)
    trees = {"before": args.before.resolve(), "after": args.after.resolve()}
    cpus = dict(zip(trees, (int(c) for c in args.cpus.split(","))))
    commits = {side: tree_commit(tree) for side, tree in trees.items()}
    run = records.Run("paper_run_ab", variant=args.system, enabled=records.wanted(args, argv),
                      settings=dict(config=args.config, system=args.system, realization=args.realization,
                                    cpus=args.cpus, before=commits["before"], after=commits["after"],
                                    after_dirty=records.git_state(trees["after"])[1]))
    results = {side: (args.out / side / "results").resolve() for side in trees}
    for side, folder in results.items():
        if Path(paths.run_cost(str(folder), args.system, args.realization)).exists():
            sys.exit(f"{folder} already holds the finished run: choose another --out")
    job_logs = {side: args.out / side / "snakemake.log" for side in trees}
    run_logs = {side: Path(paths.run_log(str(results[side]), "simulate", args.system, args.realization))
                for side in trees}
    start = time.time()
    jobs = {side: start_run(tree, args.config, results[side], args.system, args.realization, cpus[side], job_logs[side])
            for side, tree in trees.items()}
    try:
        while any(job.poll() is None for job in jobs.values()):
            time.sleep(min(args.poll, 10.0) if time.time() - start < 60 else args.poll)
            for side in trees:
                print(f"[{(time.time() - start) / 60:6.1f} min] {side}: {last_progress(run_logs[side])}", flush=True)
    except KeyboardInterrupt:
        for job in jobs.values():
            job.terminate()
        for job in jobs.values():
            job.wait(timeout=60)
        raise
    failed = [side for side, job in jobs.items() if job.returncode != 0]
    if failed:
        sys.exit(f"the {' and '.join(failed)} run failed: see {', '.join(str(job_logs[s]) for s in failed)}")
    cost = {side: json.loads(Path(paths.run_cost(str(folder), args.system, args.realization)).read_text())
            for side, folder in results.items()}
    snapshots = {side: snapshot_files(folder, args.system, args.realization) for side, folder in results.items()}
    records_dir = yaml.safe_load((trees["after"] / args.config).read_text()).get("records_dir")
    record_path = (trees["after"] / paths.record_file(records_dir, args.system, args.realization) if records_dir
                   else None)
    measured = {
        "cpu_hours": {side: cost[side]["cpu_seconds"] / 3600 for side in trees},
        "after_over_before_cpu": cost["after"]["cpu_seconds"] / cost["before"]["cpu_seconds"],
        "particles": cost["after"]["particles"], "snapshots": cost["after"]["snapshots"],
        "wall_hours": (time.time() - start) / 3600,
        "snapshots_differ": differing_variables(snapshots["before"], snapshots["after"]),
        "record_differs": {side: differences_from_record(snapshots[side], record_path) for side in trees},
    }
    run.write(measured=measured)
    print(json.dumps(measured, indent=1))
    return 0


if __name__ == "__main__":
    sys.exit(main())
