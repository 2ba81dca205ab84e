#!/usr/bin/env python
"""How the DEM engine's throughput changes with N (benchmark, not a test): particle-steps per CPU-second.

usage: python bench/dem_scaling.py [--dim 2] [--sizes 500 1000 2000 4000 8000] [--steps 2000] [--rho 0.82]
                                  [--cpu C] [--no-record]

Each size: the P1 bidisperse system (2D linear or 3D Hertz, P1 units, quick-config Δt and wall speed) with
N ≈ size particles, compressed by our engine from the lattice to ρ (fast, not timed), relaxed briefly, then timed
for --steps steps with the walls moving at the quick-config speed. With a cell/Verlet list the cost per particle-step should stay flat. One JSON line per size;
the run's record (all sizes) goes to bench/results/dem_scaling-<dim>d.json (bench/records.py).
"""
from __future__ import annotations

import argparse
import dataclasses
import json
import math
import os
import time

from forcenet.checks import checked_system
from forcenet.dem import packing, protocol
from forcenet.systems import Relaxation

import records  # bench/records.py


def system_for(dim: int, n: int, config: dict):
    base = checked_system("2d_linear" if dim == 2 else "3d_hertz", config)
    spacing = packing.largest_diameter(base) + packing.LATTICE_GAP
    side = math.ceil(n ** (1.0 / dim)) * spacing + 1e-6
    return dataclasses.replace(base, box_length=side, relaxation=Relaxation(1000, 0.1, 1000))


def dim_is_2d(sim) -> bool:
    return sim.dimension == 2


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--dim", type=int, choices=(2, 3), default=2)
    ap.add_argument("--sizes", type=int, nargs="+", default=[500, 1000, 2000, 4000, 8000])
    ap.add_argument("--steps", type=int, default=1000)
    ap.add_argument("--rho", type=float, default=None, help="packing fraction of the timed state")
    ap.add_argument("--cpu", type=int, help="pin the run to this CPU")
    records.add_no_record(ap)
    args = ap.parse_args(argv)
    if args.cpu is not None:
        os.sched_setaffinity(0, {args.cpu})
    from forcenet.catalog import load_run_config
    from pathlib import Path
    config = load_run_config(Path(__file__).resolve().parents[1] / "config" / "config.yaml")
    rho = args.rho or (0.75 if args.dim == 2 else 0.50)
    run = records.Run("dem_scaling", variant=f"{args.dim}d", enabled=records.wanted(args, argv),
                      settings=dict(dim=args.dim, sizes=args.sizes, steps=args.steps, rho=rho, cpu=args.cpu,
                                    system="2d_linear" if args.dim == 2 else "3d_hertz"))
    rows = []
    for size in args.sizes:
        system = system_for(args.dim, size, config)
        sim, _ = protocol.build_simulation(system, seed=1)
        target = protocol.wall_shift_for(sim, rho)
        sim.set_walls(0.03, target)  # fast preparation (not timed), then relax
        while sim.wall_shift < target:
            sim.advance(1000)
        sim.set_walls(0.0, target)
        sim.advance(2000)
        sim.set_walls(system.wall_speed)
        start = time.process_time()
        sim.advance(args.steps)
        cpu = time.process_time() - start
        rows.append(dict(dim=args.dim, N=sim.n_mobile, rho=round(sim.packing_fraction, 4), steps=args.steps,
                          cpu_s=round(cpu, 3), particle_steps_per_cpu_s=sim.n_mobile * args.steps / cpu,
                          contacts_per_particle=2.0 * sim.contact_count() / sim.n_mobile))
        print(json.dumps(rows[-1]), flush=True)
    run.write(measured=dict(sizes=rows))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
