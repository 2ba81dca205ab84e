#!/usr/bin/env python
"""What a dry run costs with a large imported source in the config (benchmark, not a test): wall time and peak
memory of ``snakemake -n`` on a config importing one generated LAMMPS run, the first call (no source records yet)
and a later one.

usage: python bench/import_dry_run.py [--timesteps 20] [--atoms 100000] [--undeclared] [--repo PATH]
                                     [--baseline PATH] [--no-record]

Writes a 2D run of `--timesteps` frames of `--atoms` disks (a square lattice of diameter-1 disks, each touching its
right-hand neighbour, the box shrinking from frame to frame so that ρ rises) as an atoms dump (``dump custom``: id
type x y z radius) and a pairs dump (``dump local``: the shipped example's columns) into a temporary folder, then a
config that imports it, and times ``snakemake -n`` twice in an empty working folder (so the first call finds no
source records under .snakemake/). The config declares the states' ρ (``systems.<name>.rho``) unless
`--undeclared` (a config as written before imported systems declared their states). `--repo` runs another
checkout's Snakefile and sources with this checkout's venv; `--baseline` measures another checkout too, with the
config undeclared, on the same files (a before/after comparison, kept as the record's peer). Peak memory is the largest
resident set of the snakemake process (getrusage of the children). The config's parse alone (`checked_config`, as
the workflow calls it, in a fresh Python, the first call and a later one) is timed too: the part of a dry run that
the source can make grow, without Snakemake's own start. Leaves the record in
bench/results/import_dry_run.json (bench/records.py).
"""
from __future__ import annotations

import argparse
import math
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

import records  # bench/records.py

HEAD = "ITEM: TIMESTEP\n{}\nITEM: NUMBER OF {}\n{}\nITEM: BOX BOUNDS ff ff pp\n0 {:.6f}\n0 {:.6f}\n-0.5 0.5\n"
ATOM_COLUMNS = "id type x y z radius"
PAIR_COLUMNS = "c_pid[1] c_pid[2] c_pf[1] c_pf[2] c_pf[3] c_pf[4]"
#: runs the command given as its arguments, prints the largest resident set of its children (KB), exits with its status
PEAK = ("import resource, subprocess, sys; r = subprocess.run(sys.argv[1:], stdout=subprocess.DEVNULL, "
        "stderr=sys.stderr).returncode; print(resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss); sys.exit(r)")


def write_run(folder: Path, timesteps: int, atoms: int) -> tuple[Path, Path, list[str]]:
    """The atoms and pairs dumps of a generated run, and the ρ label of each of its states."""
    side = int(math.isqrt(atoms))
    n = side * side
    ids = np.arange(1, n + 1)
    grid = np.stack(np.meshgrid(np.arange(side), np.arange(side), indexing="xy"), axis=-1).reshape(-1, 2) + 0.5
    right = np.flatnonzero((ids - 1) % side < side - 1)  # each disk and its right-hand neighbour: one contact
    labels = []
    with open(folder / "atoms.dump", "w") as a, open(folder / "pairs.dump", "w") as p:
        for step in range(timesteps):
            box = side * (1.0 + 0.2 * (timesteps - step) / timesteps)  # shrinks: ρ rises from frame to frame
            labels.append(f"{n * math.pi * 0.25 / box ** 2:.3f}")
            scale = box / side
            a.write(HEAD.format(100 * step, "ATOMS", n, box, box) + f"ITEM: ATOMS {ATOM_COLUMNS}\n")
            rows = np.column_stack([ids, np.ones(n), grid * scale, np.zeros(n), np.full(n, 0.5)])
            np.savetxt(a, rows, fmt=["%d", "%d", "%.6f", "%.6f", "%g", "%g"])
            p.write(HEAD.format(100 * step, "ENTRIES", len(right), box, box) + f"ITEM: ENTRIES {PAIR_COLUMNS}\n")
            pairs = np.column_stack([ids[right], ids[right] + 1, np.ones(len(right)), np.zeros((len(right), 3))])
            np.savetxt(p, pairs, fmt=["%d", "%d", "%g", "%g", "%g", "%g"])
    return folder / "atoms.dump", folder / "pairs.dump", labels


def write_config(folder: Path, atoms: Path, pairs: Path, labels: list[str], declared: bool) -> Path:
    rho = f"    rho: [{', '.join(labels)}]\n" if declared else ""
    path = folder / "config.yaml"
    path.write_text(f"""results_dir: {folder / 'results'}
seed: 0
realizations: 1
studies: {{p1: {{systems: []}}}}
analysis:
  thresholds: {{start: 0.0, stop: 3.0, step: 0.05}}
  remove_rattlers: true
  force_pdf: {{max: 6.0, bins: 30}}
  fill_tetrahedra: true
  essential_convention: minus_one
  p1_force_unit: reduced
systems:
  big:
    dimension: 2
{rho}    source:
      format: lammps
      runs: [{{atoms: {atoms}, pairs: {pairs}}}]
""")
    return path


def dry_run(repo: Path, config: Path, workdir: Path) -> dict:
    """One ``snakemake -n`` in `workdir`: wall seconds, peak resident memory (MB) and exit status."""
    command = [str(records.REPO / ".venv" / "bin" / "snakemake"), "-n", "--cores", "1", "--snakefile",
               str(repo / "Snakefile"), "--configfile", str(config), "--directory", str(workdir)]
    start = time.perf_counter()
    # a Python of its own runs snakemake, so that its children's peak is this call's alone
    result = subprocess.run([sys.executable, "-c", PEAK, *command], capture_output=True, text=True)
    wall = time.perf_counter() - start
    if result.returncode:
        print(result.stdout[-3000:] + result.stderr[-3000:], file=sys.stderr)
    peak_kb = int(result.stdout.strip().splitlines()[-1]) if result.returncode == 0 else 0
    return dict(wall_s=round(wall, 2), peak_mb=round(peak_kb / 1024), returncode=result.returncode)


#: parses the config (argv[1]) as the workflow does, in a fresh Python on the checkout's sources (PYTHONPATH):
#: prints the seconds of `checked_config` and the process's peak resident set (KB)
PARSE = ("import resource, sys, time; from pathlib import Path; "
         "from forcenet.workflow_io import CONFIG_SCHEMA, checked_config, read_config_file; "
         "config = read_config_file(sys.argv[1]); start = time.perf_counter(); "
         "checked_config(config, Path(sys.argv[2]) / CONFIG_SCHEMA); "
         "print(time.perf_counter() - start, resource.getrusage(resource.RUSAGE_SELF).ru_maxrss)")


def config_parse(repo: Path, config: Path, records_dir: Path) -> dict:
    """The workflow's parse of `config` alone (`checked_config`, the source records in `records_dir`): its seconds
    and the peak memory (MB) of a Python that ran it."""
    env = dict(os.environ, PYTHONPATH=str(repo / "src"), FORCENET_SOURCE_RECORDS=str(records_dir))
    result = subprocess.run([sys.executable, "-c", PARSE, str(config), str(repo)], capture_output=True, text=True,
                            env=env)
    if result.returncode:
        print(result.stderr[-3000:], file=sys.stderr)
        return dict(seconds=None, peak_mb=None, returncode=result.returncode)
    seconds, peak_kb = result.stdout.split()[-2:]
    return dict(seconds=round(float(seconds), 3), peak_mb=round(int(peak_kb) / 1024), returncode=0)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--timesteps", type=int, default=20)
    ap.add_argument("--atoms", type=int, default=100_000)
    ap.add_argument("--undeclared", action="store_true", help="leave systems.<name>.rho out of the config")
    ap.add_argument("--repo", type=Path, default=records.REPO, help="the checkout whose Snakefile runs")
    ap.add_argument("--baseline", type=Path, help="another checkout measured the same way with the config "
                                                  "undeclared (one from before imported systems declared their "
                                                  "states), kept in the record as its peer")
    records.add_no_record(ap)
    args = ap.parse_args(argv)
    run = records.Run("import_dry_run", enabled=records.wanted(args, argv),
                      settings=dict(timesteps=args.timesteps, atoms=args.atoms, declared=not args.undeclared))
    with tempfile.TemporaryDirectory(prefix="forcenet-import-dry-run-") as tmp:
        tmp = Path(tmp)
        atoms, pairs, labels = write_run(tmp, args.timesteps, args.atoms)
        lines = sum(1 for _ in open(atoms))
        size_mb = atoms.stat().st_size / 2 ** 20
        measured = dict(atoms_dump_lines=lines, atoms_dump_mb=round(size_mb, 1),
                        **measure(args.repo.resolve(), tmp / "this", atoms, pairs, labels, not args.undeclared))
        peer = (None if args.baseline is None else
                dict(repo=str(args.baseline), commit=records.git_state(args.baseline.resolve())[0],
                     **measure(args.baseline.resolve(), tmp / "baseline", atoms, pairs, labels, False)))
    print(f"atoms dump: {lines} lines, {size_mb:.0f} MB")
    for name, result in (("this checkout", measured), ("baseline", peer)):
        if result is None:
            continue
        first, later, parse_first, parse_later = (result[key] for key in ("first_call", "later_call", "parse_first",
                                                                          "parse_later"))
        print(f"{name}: snakemake -n: first call {first['wall_s']} s, {first['peak_mb']} MB peak; later call "
              f"{later['wall_s']} s, {later['peak_mb']} MB; the config's parse alone: first {parse_first['seconds']} "
              f"s, {parse_first['peak_mb']} MB; later {parse_later['seconds']} s, {parse_later['peak_mb']} MB")
    failed = [result for result in (measured, peer) if result is not None and result["failed"]]
    if failed:
        run.not_measured("snakemake -n or the config's parse failed")
        return 1
    run.write(measured=measured, peer=peer)
    return 0


def measure(repo: Path, folder: Path, atoms: Path, pairs: Path, labels: list[str], declared: bool) -> dict:
    """Two dry runs and two parses of a config importing the run (`folder`: its config, working folder and records)."""
    folder.mkdir()
    config = write_config(folder, atoms, pairs, labels, declared)
    (folder / "work").mkdir()
    result = dict(first_call=dry_run(repo, config, folder / "work"), later_call=dry_run(repo, config, folder / "work"),
                  parse_first=config_parse(repo, config, folder / "records"),
                  parse_later=config_parse(repo, config, folder / "records"))
    result["failed"] = any(part["returncode"] for part in result.values())
    return result


if __name__ == "__main__":
    sys.exit(main())
