#!/usr/bin/env python3
"""Ctrl-C at random moments of a build (docs/reliability.md, "Ctrl-C loop"): a clean build of a config, then
builds each interrupted by one SIGINT to the whole process group (as a terminal's Ctrl-C) at a random moment,
resumed to completion and compared with the clean build value by value (`forcenet.datasets.compare.compare_trees`).

    .venv/bin/python scripts/interrupt_loop.py --builds 50 --workdir /tmp/interrupts [--config config/smoke.yaml]

Each build runs in its own folder under --workdir; a line per build: when the Ctrl-C came, how long the build took
to exit after it (a hang is a build still running --hang seconds after), its exit status, the temporary files it
left, the resume's exit status and time, and how many values differ from the clean build. The last line is one
JSON object with the counts: hung, left temporary files, resumes that failed, builds that differ.
"""
from __future__ import annotations

import argparse
import json
import os
import random
import signal
import subprocess
import sys
import time
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(REPO / "src"))

from forcenet.datasets.compare import compare_trees  # noqa: E402


def build(folder: Path, config: Path, cores: int) -> subprocess.Popen:
    """`snakemake` on `config` in `folder`, in a process group of its own (so one SIGINT reaches every process of it,
    as a terminal's Ctrl-C does); SIGINT restored to its default in the child (a background shell starts it ignored)."""
    folder.mkdir(parents=True, exist_ok=True)
    command = [str(REPO / ".venv/bin/snakemake"), "--snakefile", str(REPO / "Snakefile"), "--directory", str(folder),
               "--cores", str(cores), "--configfile", str(config)]
    log = open(folder / "build.log", "a")
    return subprocess.Popen(command, cwd=REPO, stdout=log, stderr=subprocess.STDOUT, start_new_session=True,
                            preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL))


def temporary_files(folder: Path) -> list[str]:
    """Files a write left half-done: forcenet's temporary names (`*.tmp*`) under the results."""
    return sorted(str(p.relative_to(folder)) for p in (folder / "results").rglob("*.tmp*"))


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--builds", type=int, default=50)
    parser.add_argument("--workdir", type=Path, required=True)
    parser.add_argument("--config", type=Path, default=REPO / "config/smoke.yaml")
    parser.add_argument("--cores", type=int, default=2)
    parser.add_argument("--earliest", type=float, default=2.0, help="earliest Ctrl-C after the start [s]")
    parser.add_argument("--latest", type=float, help="latest Ctrl-C [s] (default: 90 %% of the clean build's time)")
    parser.add_argument("--hang", type=float, default=10.0, help="a build still running this long after is hung [s]")
    parser.add_argument("--seed", type=int, default=1)
    args = parser.parse_args()
    rng = random.Random(args.seed)
    config = args.config.resolve()
    clean = args.workdir / "clean"
    if not (clean / "done").exists():
        start = time.monotonic()
        code = build(clean, config, args.cores).wait()
        if code != 0:
            print(f"the clean build failed (exit {code}): {clean / 'build.log'}")
            return 1
        (clean / "done").write_text(f"{time.monotonic() - start:.1f}\n")
    clean_seconds = float((clean / "done").read_text())
    latest = args.latest or 0.9 * clean_seconds
    counts = {"builds": 0, "hung": 0, "temporary_files_left": 0, "resume_failed": 0, "differ": 0}
    print("| build | Ctrl-C at [s] | exit after it [s] | exit status | temporary files | resume | differences |")
    print("|---|---|---|---|---|---|---|")
    for index in range(1, args.builds + 1):
        folder = args.workdir / f"build{index:02d}"
        moment = rng.uniform(args.earliest, latest)
        process = build(folder, config, args.cores)
        time.sleep(moment)
        if process.poll() is not None:  # finished before its Ctrl-C: nothing was interrupted
            print(f"| {index} | {moment:.1f} | – (finished first) | {process.returncode} | – | – | – |")
            continue
        os.killpg(process.pid, signal.SIGINT)
        sent = time.monotonic()
        try:
            code = process.wait(timeout=args.hang)
            exit_after = f"{time.monotonic() - sent:.2f}"
        except subprocess.TimeoutExpired:
            counts["hung"] += 1
            exit_after, code = f"hung > {args.hang:g}", "killed"
            os.killpg(process.pid, signal.SIGKILL)
            process.wait()
        left = temporary_files(folder)
        counts["temporary_files_left"] += bool(left)
        start = time.monotonic()
        resume = build(folder, config, args.cores).wait()
        counts["resume_failed"] += resume != 0
        differences = compare_trees(clean / "results", folder / "results") if resume == 0 else ["resume failed"]
        counts["differ"] += bool(differences)
        counts["builds"] += 1
        print(f"| {index} | {moment:.1f} | {exit_after} | {code} | {len(left) or 'none'} | rc {resume}, "
              f"{time.monotonic() - start:.0f} s | {len(differences)} |", flush=True)
        if not differences:
            subprocess.run(["rm", "-rf", str(folder)], check=False)  # keep a failing build's folder to look into
    print(json.dumps(counts))
    return 0 if not (counts["hung"] or counts["temporary_files_left"] or counts["resume_failed"]
                     or counts["differ"]) else 1


if __name__ == "__main__":
    sys.exit(main())
