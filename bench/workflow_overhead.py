"""Benchmark (not a test): Snakemake's cost around the kernels for the paper config.

Measures
  (a) dry-run time of config/paper.yaml (all jobs, empty working directory), with the default profile and with
      the Slurm profile (which also forms the analysis groups). Target ≤ 30 s.
  (b) per-snapshot-job wall time outside the kernels, at paper size (2D, N = 2025, config/paper.yaml's
      2d_linear with only the compression sped up, seven ρ from 0.78 to 0.84, so that the inputs take a minute):
      - analysis job: wall time of the `analyze_2d_linear` job of that run, run by Snakemake (local: `--cores 1`;
        Slurm: the grouped cluster job, through workflow/profiles/slurm), divided by its snapshots, minus the kernels' time (build_force_network +
        compute_snapshot_measures for the three networks, timed in a warm process). Overhead = process start,
        imports, Snakemake bookkeeping, reading the snapshot and writing the analysis netCDF.
      - simulation job: wall time of the `simulate_2d_linear` job minus the time spent inside
        `forcenet.pipeline.simulate` (from its log), plus the snapshot writes; compared with the kernel time of
        the paper's run from forcenet.cost (measured throughput × N × steps), per snapshot.
      Target: overhead ≤ 10 % of the kernels' time.
Prints a table, then one JSON object on the last line. The Slurm part runs when `sinfo` shows this node taking
jobs (scripts/slurm_cluster.sh up), else it is reported as skipped.

The run's record goes to bench/results/workflow_overhead.json (bench/records.py; not with ``--no-record``).

Run: ``.venv/bin/python bench/workflow_overhead.py [--no-slurm] [--no-dry-run] [--keep DIR] [--no-record]``
"""
from __future__ import annotations

import argparse
import json
import re
import shutil
import subprocess
import sys
import tempfile
import time
from datetime import datetime
from pathlib import Path

import yaml

REPO = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(REPO / "src"))
from forcenet.catalog import load_run_config  # noqa: E402
import records  # noqa: E402  (bench/records.py)

PYTHON = sys.executable
SYSTEM = "2d_linear"
RHOS = [0.78, 0.79, 0.80, 0.81, 0.82, 0.83, 0.84]  # jammed-ish; faster compression blows up above ~0.85
DRY_RUN_TARGET_S = 30.0
OVERHEAD_TARGET = 0.10


def snakemake(workdir: Path, configfile: Path, *args: str, timeout: float = 1800) -> tuple[float, str]:
    command = [PYTHON, "-m", "snakemake", "--snakefile", str(REPO / "Snakefile"), "--directory", str(workdir),
               "--configfile", str(configfile), *args]
    start = time.perf_counter()
    result = subprocess.run(command, capture_output=True, text=True, timeout=timeout, cwd=workdir)
    elapsed = time.perf_counter() - start
    if result.returncode != 0:
        raise RuntimeError(f"{' '.join(command)} failed:\n{result.stderr[-4000:]}")
    return elapsed, result.stdout + result.stderr


def dry_run(workdir: Path, *profile: str) -> tuple[float, int]:
    elapsed, output = snakemake(workdir, REPO / "config/paper.yaml", "-n", *profile)
    jobs = re.search(r"^total\s+(\d+)", output, re.M)
    return elapsed, int(jobs.group(1)) if jobs else -1


def bench_config(path: Path) -> Path:
    """config/paper.yaml's 2d_linear (paper N) compressed 100× faster, seven snapshots, one realization."""
    config = load_run_config(REPO / "config/paper.yaml")
    config["realizations"] = 1
    config["studies"] = {"p1": {"systems": [SYSTEM]}}
    entry = config["systems"][SYSTEM]
    entry["wall_speed"] = 0.005
    entry["rho"] = RHOS
    entry["relaxation"] = {"window_steps": 200, "tolerance": 0.2, "max_steps": 1000}
    path.write_text(yaml.safe_dump(config))
    return path


def log_span_s(log: Path) -> float:
    """Seconds between the first and last timestamp of a job log (1 s resolution)."""
    stamps = [datetime.strptime(line[:19], "%Y-%m-%d %H:%M:%S") for line in log.read_text().splitlines()
              if re.match(r"\d{4}-\d\d-\d\d \d\d:\d\d:\d\d", line)]
    return (stamps[-1] - stamps[0]).total_seconds()


def kernel_and_io_times(snapshots: list[Path], analysis: dict, scratch: Path) -> dict:
    """In one warm process: per snapshot, read / kernels / write seconds (medians), and the write of a snapshot."""
    import numpy as np

    from forcenet.datasets import open_dataset, read_snapshot, write_netcdf
    from forcenet.datasets.analysis import analysis_dataset
    from forcenet.pipeline import analysis_attrs, snapshot_measures

    rows = []
    for index, path in enumerate([snapshots[0], *snapshots]):  # the first one again: warm-up, not counted
        t0 = time.perf_counter()
        snap = read_snapshot(path)
        t1 = time.perf_counter()
        measures = snapshot_measures(snap, analysis)
        t2 = time.perf_counter()
        attrs = analysis_attrs(snap, path, analysis)
        write_netcdf(analysis_dataset(measures, rho=float(snap.rho), attrs=attrs), scratch / f"a{index}.nc")
        t3 = time.perf_counter()
        write_netcdf(open_dataset(path), scratch / f"s{index}.nc")
        t4 = time.perf_counter()
        if index:
            rows.append((t1 - t0, t2 - t1, t3 - t2, t4 - t3, int(snap.sizes.get("contact", len(snap.contact_i)))))
    med = lambda k: float(np.median([r[k] for r in rows]))  # noqa: E731
    return {"read_s": med(0), "kernels_s": med(1), "write_s": med(2), "snapshot_write_s": med(3),
            "contacts": int(np.median([r[4] for r in rows]))}


def node_takes_jobs() -> bool:
    """`scripts/slurm_cluster.sh status` exits 0 when this node takes jobs (the one definition of that)."""
    script = REPO / "scripts/slurm_cluster.sh"
    try:
        return subprocess.run([str(script), "status"], capture_output=True, timeout=60).returncode == 0
    except (OSError, subprocess.SubprocessError):
        return False


def slurm_job_seconds(workdir: Path) -> list[float]:
    """Elapsed seconds of this run's Slurm jobs (scontrol keeps finished jobs for MinJobAge)."""
    ids = [p.stem for p in (workdir / ".snakemake/slurm_logs").rglob("*.log")]
    seconds = []
    for job in ids:
        info = subprocess.run(["scontrol", "show", "job", job], capture_output=True, text=True).stdout
        start, end = re.search(r"StartTime=(\S+)", info), re.search(r"EndTime=(\S+)", info)
        if start and end:
            seconds.append((datetime.fromisoformat(end.group(1)) - datetime.fromisoformat(start.group(1)))
                           .total_seconds())
    return seconds


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--no-slurm", action="store_true", help="skip the Slurm measurement")
    parser.add_argument("--no-dry-run", action="store_true", help="skip the paper dry-runs")
    parser.add_argument("--keep", type=Path, help="work in this directory and keep it")
    records.add_no_record(parser)
    args = parser.parse_args(argv)
    run = records.Run("workflow_overhead", enabled=records.wanted(args, argv),
                      settings=dict(system=SYSTEM, rho=RHOS, slurm=not args.no_slurm, dry_run=not args.no_dry_run,
                                    targets=dict(dry_run_s=DRY_RUN_TARGET_S, overhead_ratio=OVERHEAD_TARGET)))
    root = args.keep or Path(tempfile.mkdtemp(prefix="forcenet-overhead-"))
    root.mkdir(parents=True, exist_ok=True)
    result: dict = {}

    # (a) dry-runs of the paper config
    if not args.no_dry_run:
        for name, profile in (("default", ()), ("slurm", ("--workflow-profile", str(REPO / "workflow/profiles/slurm")))):
            workdir = root / f"dry_{name}"
            workdir.mkdir(exist_ok=True)
            seconds, jobs = dry_run(workdir, *profile)
            result[f"dry_run_s_{name}"] = round(seconds, 2)
            result["paper_jobs"] = jobs
            print(f"dry-run {name}: {seconds:.1f} s, {jobs} jobs", flush=True)

    # (b) inputs: paper-size snapshots through the workflow's own simulate job
    from forcenet.checks import validate_config
    from forcenet.cost import simulation_cost
    from forcenet.datasets import paths

    local = root / "local"
    local.mkdir(exist_ok=True)
    config_path = bench_config(root / "bench.yaml")
    config = load_run_config(config_path)
    labels = validate_config(config)[SYSTEM].rho_labels
    snapshots = [paths.snapshot("results", SYSTEM, "r00", label) for label in labels]
    analyses = [paths.analysis("results", SYSTEM, "r00", label) for label in labels]
    for path in analyses + snapshots:
        (local / path).unlink(missing_ok=True)
    sim_wall, _ = snakemake(local, config_path, "--cores", "1", snapshots[0])
    sim_inside = log_span_s(local / paths.run_log("results", "simulate", SYSTEM, "r00"))
    dry_wall, _ = snakemake(local, config_path, "--cores", "1", "-n", *analyses)
    ana_wall, _ = snakemake(local, config_path, "--cores", "1", *analyses)
    per_job_local = (ana_wall - dry_wall) / len(analyses)

    times = kernel_and_io_times([local / p for p in snapshots], config["analysis"], root)
    kernels = times["kernels_s"]
    paper = validate_config(load_run_config(REPO / "config/paper.yaml"))[SYSTEM]
    paper_kernel_per_snapshot = simulation_cost(paper).core_hours * 3600 / len(paper.rho_grid)
    # a simulation job's overhead: start, imports, Snakemake (job wall minus its time inside simulate()), and the
    # snapshot writes (inside simulate(), but I/O)
    sim_overhead = sim_wall - sim_inside + len(snapshots) * times["snapshot_write_s"]
    sim_overhead_paper_per_snapshot = (sim_wall - sim_inside) / len(paper.rho_grid) + times["snapshot_write_s"]
    result.update({
        "particles": simulation_cost(paper).particles, "contacts": times["contacts"],
        "analysis_kernels_s": round(kernels, 3), "analysis_read_s": round(times["read_s"], 3),
        "analysis_write_s": round(times["write_s"], 3),
        "analysis_job_wall_local_s": round(per_job_local, 2),
        "analysis_overhead_local_s": round(per_job_local - kernels, 2),
        "analysis_overhead_ratio_local": round((per_job_local - kernels) / kernels, 2),
        "simulation_job_wall_s": round(sim_wall, 1), "simulation_inside_s": sim_inside,
        "simulation_overhead_s": round(sim_overhead, 2),
        "paper_simulation_kernel_per_snapshot_s": round(paper_kernel_per_snapshot, 1),
        "simulation_overhead_ratio_paper": round(sim_overhead_paper_per_snapshot / paper_kernel_per_snapshot, 4),
    })

    # per snapshot of each paper system: everything outside the kernels (its share of the simulation job's start and
    # bookkeeping, its write, its analysis job's overhead) over its kernels (its share of the DEM run from
    # forcenet.cost, plus the analysis kernels measured here on 2D N = 2025; 3D analyses are costlier, which only
    # lowers the 3D ratio)
    def per_snapshot_ratio(job_wall: float) -> dict:
        ratios = {}
        for name, spec in validate_config(load_run_config(REPO / "config/paper.yaml")).items():
            n = len(spec.rho_grid)
            overhead = (sim_wall - sim_inside) / n + times["snapshot_write_s"] + (job_wall - kernels)
            ratios[name] = round(overhead / (simulation_cost(spec).core_hours * 3600 / n + kernels), 4)
        return ratios

    result["snapshot_overhead_ratio_local"] = per_snapshot_ratio(per_job_local)

    # Slurm: the same analyses as one grouped cluster job
    if args.no_slurm or not node_takes_jobs():
        result["slurm"] = "skipped (--no-slurm)" if args.no_slurm else "skipped (no Slurm node; scripts/slurm_cluster.sh up)"
    else:
        cluster = root / "slurm"
        shutil.rmtree(cluster, ignore_errors=True)
        (cluster / paths.run_dir("results", SYSTEM, "r00")).mkdir(parents=True)
        for path in snapshots:
            shutil.copy2(local / path, cluster / path)
        slurm_wall, _ = snakemake(cluster, config_path, "--workflow-profile", str(REPO / "workflow/profiles/slurm"),
                                  "--slurm-keep-successful-logs",
                                  "--slurm-init-seconds-before-status-checks", "5", *analyses)
        allocation = sum(slurm_job_seconds(cluster))
        per_job_slurm = allocation / len(analyses)
        result.update({
            "slurm_run_wall_s": round(slurm_wall, 1), "slurm_allocation_s": allocation,
            "analysis_job_wall_slurm_s": round(per_job_slurm, 2),
            "analysis_overhead_ratio_slurm": round((per_job_slurm - kernels) / kernels, 2),
            "snapshot_overhead_ratio_slurm": per_snapshot_ratio(per_job_slurm),
        })

    rows = [
        ("paper dry-run, default profile [s]", result.get("dry_run_s_default"), f"≤ {DRY_RUN_TARGET_S:.0f}"),
        ("paper dry-run, Slurm profile [s]", result.get("dry_run_s_slurm"), f"≤ {DRY_RUN_TARGET_S:.0f}"),
        ("paper jobs", result.get("paper_jobs"), ""),
        ("analysis kernels per snapshot [s]", result["analysis_kernels_s"], ""),
        ("  read snapshot / write analysis [s]", f"{result['analysis_read_s']} / {result['analysis_write_s']}", ""),
        ("analysis job wall, local [s]", result["analysis_job_wall_local_s"], ""),
        ("analysis overhead / kernels, local", result["analysis_overhead_ratio_local"], f"≤ {OVERHEAD_TARGET}"),
        ("analysis job wall in allocation, Slurm [s]", result.get("analysis_job_wall_slurm_s", result.get("slurm")), ""),
        ("analysis overhead / kernels, Slurm", result.get("analysis_overhead_ratio_slurm", "-"), f"≤ {OVERHEAD_TARGET}"),
        ("simulation job overhead (start+imports+writes) [s]", result["simulation_overhead_s"], ""),
        ("paper simulation kernel per snapshot [s]", result["paper_simulation_kernel_per_snapshot_s"], ""),
        ("simulation overhead / kernel, paper", result["simulation_overhead_ratio_paper"], f"≤ {OVERHEAD_TARGET}"),
    ]
    for where in ("local", "slurm"):
        for name, ratio in result.get(f"snapshot_overhead_ratio_{where}", {}).items():
            rows.append((f"per snapshot (sim+analysis), {where}, {name}", ratio, f"≤ {OVERHEAD_TARGET}"))
    print(f"{'quantity':52s} {'value':>14s} {'target':>8s}")
    for name, value, target in rows:
        print(f"{name:52s} {str(value):>14s} {target:>8s}")
    if not args.keep:
        shutil.rmtree(root, ignore_errors=True)
    run.write(measured=result)
    print(json.dumps(result))


if __name__ == "__main__":
    main()
