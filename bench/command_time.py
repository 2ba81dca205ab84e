#!/usr/bin/env python
"""How long the project's everyday commands take (benchmark, not a test): wall and CPU time of one run.

usage: python bench/command_time.py NAME [--no-record]        (NAME: one of COMMANDS below; --list shows them)

Runs the command with bash, from the repository root or, for the commands a newcomer runs first, in a fresh clone
of this checkout's HEAD in a temporary folder (deleted afterwards); {scratch} in a command is an empty temporary
folder, {venv} this checkout's venv (for a fresh clone that needs no install of its own). numba's cache starts
empty for a fresh clone: it gets a cache folder of its own (NUMBA_CACHE_DIR in the temporary folder), as compiled
kernels are otherwise shared by every checkout of the same kernel sources (`forcenet._numba.kernel_cache_dir`). Measures the wall time and the CPU time of the command
and its children, keeps pytest's or Snakemake's summary line, and leaves the record in
bench/results/command_time-NAME.json (bench/records.py); a command that fails leaves a record that says so. Run it
on a machine that is otherwise idle: the record notes the load average before and after.
"""
from __future__ import annotations

import argparse
import os
import re
import resource
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import records  # bench/records.py

def _from_records(what: str, targets: str) -> dict:
    """A command that makes `targets` of config/validation.yaml in a fresh clone from the committed campaign records
    alone, with no results/ (data/validation/README.md)."""
    return dict(what=f"{what} from the campaign records alone, no results/", fresh_clone=True,
                command=f"PYTHONPATH=$PWD/src {{venv}}/bin/snakemake {targets} --cores 2 "
                        "--configfile config/validation.yaml")


#: name → what it is, the command (bash, {scratch}: an empty temporary folder), whether it runs in a fresh clone
COMMANDS = {
    "main_build": dict(what="the main job, venv and install included (README)", fresh_clone=True,
                       command="python3 -m venv .venv && .venv/bin/pip install -q -r environment.txt && "
                               ".venv/bin/snakemake --cores 2"),
    "main_build_again": dict(what="the main job again with nothing to do (after a build)", fresh_clone=False,
                             command=".venv/bin/snakemake --cores 2"),
    "test_suite": dict(what="the README's test command, every tier, venv and install included", fresh_clone=True,
                       command="bash .ci/run"),
    "unit_tests": dict(what="the unit tier (plain pytest) in a fresh clone, numba's cache empty (the clone's sources "
                            "first on the path, this checkout's venv)", fresh_clone=True,
                       command="PYTHONPATH=$PWD/src {venv}/bin/python -m pytest -q -p no:cacheprovider"),
    "example_import": dict(what="the shipped imports (config/example_import.yaml)", fresh_clone=True,
                           command="PYTHONPATH=$PWD/src {venv}/bin/snakemake --cores 2 "
                                   "--configfile config/example_import.yaml"),
    "example_sequence": dict(what="the shipped imported sequence (config/example_sequence.yaml)", fresh_clone=True,
                             command="PYTHONPATH=$PWD/src {venv}/bin/snakemake --cores 2 "
                                     "--configfile config/example_sequence.yaml"),
    "validation_tables_p1": _from_records("P1's validation tables (docs/validation/p1.{md,csv})",
                                          "validation_report_p1"),
    "validation_tables": _from_records("both studies' validation tables (docs/validation/{p1,p2}.{md,csv})",
                                       "validation_report"),
    "validation_p1": _from_records("P1's validation tables and every P1 figure at paper size",
                                   "validation_report_p1 figures_p1"),
    "validation_all": _from_records("both studies' validation tables and every figure at paper size",
                                    "validation_report figures"),
    "smoke_build": dict(what="smoke config, full build in an empty folder", fresh_clone=False,
                        command=".venv/bin/snakemake --cores 2 --configfile config/smoke.yaml --directory {scratch}"),
}
SUMMARY = (re.compile(r"^=* ?(\d+ passed.*?) in [\d.]+s", re.M), re.compile(r"^(\d+ of \d+ steps \(100%\) done)", re.M))


def summary_line(output: str) -> str | None:
    """pytest's "N passed, M skipped" or Snakemake's "N of N steps (100%) done", the last one printed."""
    for pattern in SUMMARY:
        found = pattern.findall(output)
        if found:
            return found[-1].strip("= ")
    return None


def cpu_children() -> float:
    usage = resource.getrusage(resource.RUSAGE_CHILDREN)
    return usage.ru_utime + usage.ru_stime


def run_command(name: str, repo: Path = records.REPO) -> dict:
    """Run COMMANDS[name] once; its wall and CPU seconds, exit status and summary line."""
    spec = COMMANDS[name]
    with tempfile.TemporaryDirectory(prefix=f"forcenet-{name}-") as tmp:
        tmp = Path(tmp)
        scratch = tmp / "scratch"
        scratch.mkdir()
        cwd = repo
        if spec["fresh_clone"]:
            cwd = tmp / "clone"
            subprocess.run(["git", "clone", "-q", str(repo), str(cwd)], check=True)
        command = spec["command"].format(scratch=scratch, venv=repo / ".venv")
        env = dict(os.environ, NUMBA_CACHE_DIR=str(tmp / "numba")) if spec["fresh_clone"] else None
        cpu0, wall0 = cpu_children(), time.perf_counter()
        result = subprocess.run(["bash", "-c", command], cwd=cwd, capture_output=True, text=True, env=env)
        wall, cpu = time.perf_counter() - wall0, cpu_children() - cpu0
        shutil.rmtree(tmp, ignore_errors=True)
    output = result.stdout + result.stderr
    # the command's own report (pytest's failures, Snakemake's error) is at the end of its stdout; pip's warnings
    # fill stderr
    return dict(wall_s=round(wall, 1), cpu_s=round(cpu, 1), returncode=result.returncode,
                summary=summary_line(output),
                output_tail=result.stdout[-6000:] + ("\n--- stderr ---\n" + result.stderr[-1500:] if result.stderr else ""))


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("name", nargs="?", choices=tuple(COMMANDS))
    ap.add_argument("--list", action="store_true", help="list the commands")
    records.add_no_record(ap)
    args = ap.parse_args(argv)
    if args.list or not args.name:
        for name, spec in COMMANDS.items():
            print(f"{name:18s} {spec['what']}: {spec['command']}{' (fresh clone)' if spec['fresh_clone'] else ''}")
        return 0
    spec = COMMANDS[args.name]
    run = records.Run("command_time", variant=args.name, enabled=records.wanted(args, argv), settings=dict(spec))
    result = run_command(args.name)
    print(f"{args.name}: {result['wall_s']} s wall, {result['cpu_s']} s CPU, exit status {result['returncode']}"
          f"{'; ' + result['summary'] if result['summary'] else ''}")
    if result["returncode"] != 0:
        print(result["output_tail"], file=sys.stderr)
        run.not_measured(f"the command failed (exit status {result['returncode']})")
        return 1
    run.write(measured={k: v for k, v in result.items() if k != "output_tail"})
    return 0


if __name__ == "__main__":
    sys.exit(main())
