#!/usr/bin/env python
"""Does the order of the particles in memory matter to the DEM step? (benchmark, not a test)

usage: python bench/dem_particle_order.py [--repeat 3] [--steps S] [--cpu C] [--no-record]

Our engine on the two states of `bench/dem_vs_lammps.py` (2D: N = 2000 disks, 3D: N = 4000 spheres, Hertz, flat
walls moving inward), once in the order the states were made (LAMMPS inserts particles at random places, so
particles that touch lie anywhere in memory) and once with the same particles relabelled along a Morton
(Z-order) curve of their positions, so that particles close in space are close in memory: the candidate "particles
re-ordered along a space-filling curve" of the engine's speed issue. The two orders run alternately on one pinned
core, `--repeat` times each; the same physics either way (a permutation of the labels), so the ratio is the
cache's alone. The record lands in bench/results/dem_particle_order.json (bench/records.py).
"""
from __future__ import annotations

import argparse
import json
import os
import statistics
import sys
import time

import numpy as np

import records  # bench/records.py
from dem_vs_lammps import CASES, OUT, build_engine

#: the per-particle arrays of a bench state, permuted together
PARTICLE_KEYS = ("positions", "radii", "masses", "velocities", "angular_velocities")
MORTON_BITS = 10  # cells per axis 2^10: finer than a particle in every bench box


def morton_order(position: np.ndarray, lo: np.ndarray, hi: np.ndarray, bits: int = MORTON_BITS) -> np.ndarray:
    """The permutation (N,) that sorts particles by the Morton code of their cell (position (N, d) in the box
    [lo, hi]), ties in their given order."""
    dim = position.shape[1]
    cells = ((position - lo) / (hi - lo) * (2 ** bits - 1)).astype(np.int64).clip(0, 2 ** bits - 1)
    code = np.zeros(len(position), dtype=np.int64)
    for bit in range(bits):
        for k in range(dim):
            code |= ((cells[:, k] >> bit) & 1) << (bit * dim + k)
    return np.argsort(code, kind="stable")


def relabelled(state: dict, order: np.ndarray) -> dict:
    """The state with its particles in `order` (every per-particle array permuted alike)."""
    out = dict(state)
    for key in PARTICLE_KEYS:
        if key in out and np.ndim(out[key]) >= 1 and len(out[key]) == len(order):
            out[key] = np.asarray(out[key])[order]
    return out


def time_run(state: dict, steps: int) -> dict:
    """Particle-steps per CPU second of one run of `steps` steps, and the packing fraction it ends at."""
    sim = build_engine(state)
    start = time.process_time()
    sim.advance(steps)
    cpu = time.process_time() - start
    return dict(particle_steps_per_cpu_s=sim.n_mobile * steps / cpu, phi_end=sim.packing_fraction)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--steps", type=int, help="override the states' 20000 steps")
    ap.add_argument("--cpu", type=int, default=max(os.sched_getaffinity(0)))
    records.add_no_record(ap)
    args = ap.parse_args(argv)
    os.sched_setaffinity(0, {args.cpu})
    run = records.Run("dem_particle_order", enabled=records.wanted(args, argv),
                      settings=dict(repeat=args.repeat, steps=args.steps, cpu=args.cpu, morton_bits=MORTON_BITS))
    missing = [case for case in CASES if not (OUT / f"{case}_bench.npz").exists()]
    if missing:
        reason = f"no bench state {', '.join(missing)} in bench/out/: run bench/dem_vs_lammps.py once (with LAMMPS)"
        print(f"error: {reason}", file=sys.stderr)
        run.not_measured(reason)
        return 1
    measured = {}
    for case in CASES:
        with np.load(OUT / f"{case}_bench.npz", allow_pickle=False) as z:
            made = {k: z[k] for k in z.files}
        steps = int(args.steps or made["n_steps"])
        orders = {"as_made": made, "morton": relabelled(made, morton_order(made["positions"], made["box_lo"],
                                                                           made["box_hi"]))}
        for state in orders.values():  # JIT compilation outside the timed runs
            build_engine(state).advance(20)
        rates = {name: [] for name in orders}
        for rep in range(args.repeat):  # alternate, so that load changes hit both orders alike
            for name, state in orders.items():
                result = time_run(state, steps)
                rates[name].append(result["particle_steps_per_cpu_s"])
                print(json.dumps({"case": case, "repeat": rep, "order": name, **result}), flush=True)
        ratios = [m / a for m, a in zip(rates["morton"], rates["as_made"])]
        measured[case] = dict(N=len(made["radii"]), steps=steps, as_made=statistics.median(rates["as_made"]),
                              morton=statistics.median(rates["morton"]), ratio=statistics.median(ratios),
                              ratio_runs=ratios)
        print(f"{case}: Morton / as made {measured[case]['ratio']:.3f} (runs "
              + ", ".join(f"{r:.3f}" for r in ratios) + ")", flush=True)
    run.write(measured=measured)
    return 0


if __name__ == "__main__":
    sys.exit(main())
