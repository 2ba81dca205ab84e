#!/usr/bin/env python
"""Where a DEM time step spends its time (benchmark, not a test): the kernels of one step timed apart on a frozen
state, beside the whole step.

usage: python bench/dem_profile.py [--only 2d|3d] [--steps 2000] [--repeat 3] [--cpu C] [--no-record]
       python bench/dem_profile.py --record 3d_hertz/r00 [--states 3,8,12,20] [--steps 2000] [--repeat 3] …

On the states of bench/dem_vs_lammps.py (bench/out/{2d,3d}_state.npz: N = 2000 disks, 4000 spheres, Hertz, near
jamming; made by that benchmark's harness) it times, per step and in CPU seconds (median of --repeat runs):

* the whole step: `Simulation.advance` over --steps steps, the neighbour-list rebuilds it triggers included;
* the pair forces (`contacts.pair_forces_{2d,3d}`: the contact law, the tangential springs, the force sums);
* the flat walls (`contacts.flat_wall_forces`, the candidate entries the step visits);
* the fused Gear corrector–predictor of positions and rotations (`gear.gear_correct_predict`, twice a step);
* the displacement and escape check (`stepping.check_positions`);
* a neighbour-list rebuild (`Simulation.rebuild`), and how many the whole-step run made;

each kernel called --steps times, from one compiled loop, on copies of the state's arrays. "other" is the whole
step less the parts: the wall motion, the step status, the calls into numba. The record (bench/records.py) lands in
bench/results/dem_profile-<case>.json and the table in docs/performance.md (bench/report.py).

With --record, the states are snapshots of a committed campaign record instead (default indices: ρ = 0.53, 0.58,
0.62, 0.70 of the 4096-sphere run of P1, 3d_hertz r00), set up as `bench/dem_ab_states.py` sets them up: the
recorded positions and walls at rest, small random velocities; one record for all of them,
bench/results/dem_profile-<system>-<rNN>.json. A quasi-static paper run spends its steps in such states, loose ones and jammed ones.
"""
from __future__ import annotations

import argparse
import os
import statistics
import sys
import time
from pathlib import Path

import numba
import numpy as np
import xarray as xr

import records  # bench/records.py
from dem_ab_states import simulation_at
from dem_vs_lammps import CASES, OUT, build_engine
from forcenet.campaign_cli import load_config
from forcenet.dem._kernels import contacts, gear, stepping
from forcenet.dem.kernel_arguments import Loads, Motion

HERE = Path(__file__).resolve().parent


@numba.njit
def _pairs_2d(n, motion, bodies, pairs, law, dt, loads):
    for _ in range(n):
        contacts.pair_forces_2d(motion, bodies, pairs, law, dt, loads, None)


@numba.njit
def _pairs_3d(n, motion, bodies, pairs, law, dt, loads):
    block = contacts.new_pair_block()  # as the step: its scratch made once
    for _ in range(n):
        contacts.pair_forces_3d(motion, bodies, pairs, law, dt, loads, None, block)


@numba.njit
def _walls(n, motion, bodies, walls, lo, hi, dt, loads):
    for _ in range(n):
        contacts.flat_wall_forces(motion, bodies, walls, lo, hi, dt, loads, None)


@numba.njit
def _gear(n, position, rotation, force, torque, accel_position, accel_rotation, half_mass, half_inertia, n_mobile,
          velocity, spin):
    block = gear.new_gear_block()  # as the step: its scratch made once
    for _ in range(n):
        gear.gear_correct_predict(position, force, accel_position, half_mass, n_mobile, velocity, block)
        gear.gear_correct_predict(rotation, torque, accel_rotation, half_inertia, n_mobile, spin, block, False)


@numba.njit
def _check(n, position, reference, n_mobile, lo, hi, margin, limit_sq):
    total = 0.0  # used, so that the compiler keeps the loop
    for _ in range(n):
        n_far, bad = stepping.check_positions(position, reference, n_mobile, lo, hi, margin, limit_sq)
        total += n_far + bad
        reference[0, 0] += 1e-300 * total  # a value the next call reads: no call can be hoisted out of the loop
    return total


def timed(call, n: int, warm: bool = True) -> float:
    """CPU seconds per call of `call` over n calls (after one call that compiles it, unless `warm` is False)."""
    if warm:
        call()
    start = time.process_time()
    for _ in range(n):
        call()
    return (time.process_time() - start) / n


def profile(make_sim, steps: int) -> dict:
    """{part: CPU seconds per step} and the rebuild count of `steps` whole steps from the state of the Simulation
    that make_sim() returns."""
    sim = make_sim()
    sim.advance(20)  # JIT compilation (cached on disk after the first run) and a first rebuild
    rebuilds = [0]
    original = sim.rebuild

    def counted() -> None:
        rebuilds[0] += 1
        original()

    sim.rebuild = counted
    whole = timed(lambda: sim.advance(steps), 1, warm=False) / steps
    sim.rebuild = original
    dim, dt = sim.dimension, sim.time_step
    position, rotation = sim.particles.gear_position.copy(), sim.particles.gear_rotation.copy()
    motion = Motion(position[0], position[1].copy(), rotation[1].copy(), 1.0 / dt)
    loads = Loads(np.zeros_like(sim.work.loads.force), np.zeros_like(sim.work.loads.torque))
    pairs = sim.kernel_pairs(sim.contacts.spring.copy())
    walls = sim.kernel_walls(sim.walls.wall_spring.copy())
    bodies = sim.kernel_bodies()
    law_values = tuple(float(v) for v in sim.contacts.law[:7])
    lo = sim.walls.box_lo + sim.walls.wall_state[0]
    hi = sim.walls.box_hi - sim.walls.wall_state[0]
    pair_loop = _pairs_2d if dim == 2 else _pairs_3d
    # each kernel called `steps` times from one compiled loop: no Python call in between (the step's own calls
    # come from compiled code too)
    parts = {
        "pair forces": timed(lambda: pair_loop(steps, motion, bodies, pairs, law_values, dt, loads), 1) / steps,
        "flat walls": timed(lambda: _walls(steps, motion, bodies, walls, lo, hi, dt, loads), 1) / steps,
    }
    loads.force[:] = 0.0
    loads.torque[:] = 0.0
    work = sim.work
    parts["Gear corrector-predictor"] = timed(lambda: _gear(
        steps, position, rotation, loads.force, loads.torque, work.accel_position, work.accel_rotation,
        work.half_mass, work.half_inertia, sim.n_mobile, motion.velocity, motion.spin), 1) / steps
    reference = position[0].copy()
    half_skin = 0.5 * sim.contacts.skin
    parts["displacement check"] = timed(lambda: _check(steps, position[0], reference, sim.n_mobile, lo, hi,
                                                       sim.walls.escape_margin, half_skin * half_skin), 1) / steps
    rebuild = timed(sim.rebuild, max(3, steps // 200), warm=False)
    parts["neighbour-list rebuilds"] = rebuild * rebuilds[0] / steps
    parts["other"] = whole - sum(parts.values())
    return {"whole step": whole, "parts": parts, "rebuilds": rebuilds[0], "rebuild_s": rebuild,
            "pairs": int(len(sim.contacts.pair_i)), "N": int(sim.n_mobile)}


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--only", choices=sorted(CASES))
    ap.add_argument("--steps", type=int, default=2000)
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--cpu", type=int, help="pin the run to this CPU")
    ap.add_argument("--record", help="SYSTEM/rNN: profile states of this committed campaign record instead")
    ap.add_argument("--states", default="3,8,12,20", help="with --record: its state indices")
    records.add_no_record(ap)
    args = ap.parse_args(argv)
    if args.cpu is not None:
        os.sched_setaffinity(0, {args.cpu})
    if args.record:
        return profile_record(args, argv)
    for case in [args.only] if args.only else sorted(CASES):
        path = OUT / f"{case}_state.npz"
        run = records.Run("dem_profile", variant=case, settings={"steps": args.steps, "repeat": args.repeat,
                                                                  "cpu": args.cpu},
                          enabled=records.wanted(args, argv))
        if not path.exists():
            run.not_measured(f"{path} is missing: make it with bench/dem_vs_lammps.py")
            print(f"{case}: {path} missing (bench/dem_vs_lammps.py makes it)")
            continue
        with np.load(path, allow_pickle=False) as z:
            state = {k: z[k] for k in z.files}
        measured = summary([profile(lambda: build_engine(state), args.steps) for _ in range(args.repeat)], args.steps)
        run.write(measured=measured, peer=None)
        show(case, measured)
    return 0


def summary(runs: list[dict], steps: int) -> dict:
    """The record's figures from --repeat profiles of one state: medians of each part and of the whole step."""
    median = {part: statistics.median(r["parts"][part] for r in runs) for part in runs[0]["parts"]}
    whole = statistics.median(r["whole step"] for r in runs)
    return {"whole_step_cpu_s": whole, "parts_cpu_s": median,
            "shares": {part: value / whole for part, value in median.items()},
            "rebuilds": runs[0]["rebuilds"], "rebuild_cpu_s": statistics.median(r["rebuild_s"] for r in runs),
            "N": runs[0]["N"], "pairs": runs[0]["pairs"], "steps": steps}


def show(label: str, measured: dict) -> None:
    whole = measured["whole_step_cpu_s"]
    print(f"{label}: N = {measured['N']}, {measured['pairs']} listed pairs, whole step {whole * 1e3:.3f} ms "
          f"(CPU), {measured['rebuilds']} rebuilds in {measured['steps']} steps")
    for part, value in measured["parts_cpu_s"].items():
        print(f"  {part:28s} {value * 1e3:8.3f} ms  {100 * value / whole:5.1f} %")


def profile_record(args, argv) -> int:
    """--record: the states of a committed campaign record (`dem_ab_states.simulation_at`: the recorded positions
    and walls at rest, small random velocities), one record file for all of them."""
    system, realization = args.record.split("/")
    config = load_config(str(HERE.parent / "config" / "validation.yaml"))
    states = [int(s) for s in args.states.split(",")]
    run = records.Run("dem_profile", variant=f"{system}-{realization}", enabled=records.wanted(args, argv),
                      settings={"record": args.record, "states": states, "steps": args.steps, "repeat": args.repeat,
                                "cpu": args.cpu})
    measured = {}
    with xr.open_dataset(HERE.parent / "data" / "validation" / system / realization / "states.nc") as record:
        for index in states:
            label = f"{float(record['rho'].values[index]):.2f}"
            runs = [profile(lambda: simulation_at(record, index, config, system), args.steps)
                    for _ in range(args.repeat)]
            measured[label] = dict(summary(runs, args.steps), state=index, Z=float(record["Z"].values[index]))
            show(f"{args.record} ρ = {label}", measured[label])
    run.write(measured=measured, peer=None)
    return 0


if __name__ == "__main__":
    sys.exit(main())
