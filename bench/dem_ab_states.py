#!/usr/bin/env python
"""A/B of the DEM step kernels of two source trees on the states of a paper-size run, in one process (benchmark,
not a test): is a kernel change faster where the campaign spends its CPU time, and are its trajectories the same?

usage: python bench/dem_ab_states.py BEFORE_TREE [AFTER_TREE] [--record 3d_hertz/r00] [--states 3,8,12,20]
                                     [--steps 300] [--repeat 20] [--cpu C] [--label NAME] [--no-record]

Each tree's kernels (`src/forcenet/dem/_kernels`) are loaded as a package of their own (copied, under a name made
from a digest of their sources, to a folder in the temporary directory that is kept for numba's cache), so both
step in this one process: the engine (`forcenet.dem.engine`, this checkout's)
calls one tree's `stepping.advance` or the other's. A tree is a checkout, e.g. `git worktree add /tmp/before
<commit>`, whose kernels take the arguments this checkout's engine passes; AFTER_TREE defaults to this one.

The states are snapshots of a committed campaign record (`data/validation/<system>/<rNN>/states.nc`; default the
4096-sphere run of P1, 3d_hertz r00): by default ρ = 0.53 and 0.58 (loose, Z ≈ 0.01 and 0.2) and 0.62 and 0.70
(jammed, Z ≈ 5 and 6.6). A record keeps no velocities, so each state starts from small random velocities (normal,
10⁻³ d_ave/τ_c per axis, seeded by the state index) with the walls at rest where the record has them: the
relaxation windows in which a quasi-static run spends most of its steps. Per state, one Simulation per tree starts
from the same arrays; they then take turns of --steps steps (--repeat turns each, the order alternating: A B B A
A B …), timed in CPU seconds. The ratio before/after of each pair of turns is the speed-up; because the two are in
the same process, on the same core, a few hundred milliseconds apart, the machine's drift cancels far better than
between processes (`bench/dem_ab.py`). After the turns it compares the two Simulations' Gear state, springs and
wall springs bit for bit: a change that alters the arithmetic shows up as "differ".

Prints one line per state; the record lands in bench/results/dem_ab_states-<label>.json (bench/records.py), with
both trees' commits.
"""
from __future__ import annotations

import argparse
import hashlib
import importlib
import os
import statistics
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
import xarray as xr

import records  # bench/records.py
from dem_ab import tree_commit
from forcenet.campaign_cli import load_config
from forcenet.dem import engine, packing
from forcenet.dem.engine import Simulation
from forcenet.dem.protocol import contact_law_for_system
from forcenet.systems import system_from_config

HERE = Path(__file__).resolve().parent
REPO = HERE.parent
KERNELS = Path("src/forcenet/dem/_kernels")
#: the speed of the random velocities a state starts from [d_ave/τ_c, per axis]
START_SPEED = 1e-3
#: where the trees' kernels are copied to (one folder per version of the kernel sources, kept for numba's cache)
COPIES = Path(tempfile.gettempdir()) / "forcenet-dem-ab-states"


def load_kernels(tree: Path):
    """The `stepping` module of `tree`'s kernels, imported from a copy under COPIES as package
    ``forcenet_ab_<digest of the kernel sources>``: the same sources, the same folder, so numba's disk cache
    compiles each version once."""
    sources = sorted((tree / KERNELS).glob("*.py"))
    digest = hashlib.sha256(b"".join(s.name.encode() + s.read_bytes() for s in sources)).hexdigest()[:16]
    name = f"forcenet_ab_{digest}"
    package = COPIES / name
    if not package.exists():
        staging = Path(tempfile.mkdtemp(dir=COPIES))
        for source in sources:
            (staging / source.name).write_text(source.read_text().replace("forcenet.dem._kernels", name))
        os.replace(staging, package)
    return importlib.import_module(f"{name}.stepping")


def simulation_at(record: xr.Dataset, index: int, config: dict, system: str) -> Simulation:
    """A Simulation of `system` at state `index` of its record: the recorded positions and walls (at rest), small
    random velocities (START_SPEED, seeded by index)."""
    spec = system_from_config(system, config)
    radius = record["radius"].values
    position = record["position"].values[index]
    shift = float(record["box_lo"].values[index][0])
    velocity = np.random.default_rng(index).normal(0.0, START_SPEED, position.shape)
    sim = Simulation(position=position, radius=radius, mass=packing.particle_masses(2.0 * radius, spec.dimension),
                     law=contact_law_for_system(spec), time_step=spec.time_step, box_lo=np.zeros(spec.dimension),
                     box_hi=np.full(spec.dimension, spec.box_length), velocity=velocity, walls=spec.walls)
    sim.walls.wall_state[0] = shift
    sim.set_walls(0.0, shift)
    return sim


def same_state(first: Simulation, second: Simulation) -> bool:
    """Whether two Simulations hold the same Gear values, springs and wall springs, bit for bit: every Gear row but
    the rotation's row 0, the angle. It enters no force; the time step no longer integrates it
    (`forcenet.dem._kernels.gear`), while a tree from before that change still does."""
    pairs = [(first.particles.gear_position, second.particles.gear_position),
             (first.particles.gear_rotation[1:], second.particles.gear_rotation[1:]),
             (first.contacts.spring, second.contacts.spring), (first.walls.wall_spring, second.walls.wall_spring)]
    return all(a.shape == b.shape and np.array_equal(a.view(np.int64), b.view(np.int64)) for a, b in pairs)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("before", type=Path)
    ap.add_argument("after", type=Path, nargs="?", default=REPO)
    ap.add_argument("--record", default="3d_hertz/r00", help="SYSTEM/rNN of a committed record of the campaign")
    ap.add_argument("--states", default="3,8,12,20", help="state indices of the record")
    ap.add_argument("--steps", type=int, default=300, help="steps per turn")
    ap.add_argument("--repeat", type=int, default=20, help="turns per tree and state")
    ap.add_argument("--cpu", type=int, default=max(os.sched_getaffinity(0)))
    ap.add_argument("--label", default="step_kernels")
    records.add_no_record(ap)
    args = ap.parse_args(argv)
    os.sched_setaffinity(0, {args.cpu})
    trees = {"before": args.before.resolve(), "after": args.after.resolve()}
    commits = {side: tree_commit(tree) for side, tree in trees.items()}
    system, realization = args.record.split("/")
    config = load_config(str(REPO / "config" / "validation.yaml"))
    states = [int(s) for s in args.states.split(",")]
    run = records.Run("dem_ab_states", variant=args.label, enabled=records.wanted(args, argv),
                      settings=dict(record=args.record, states=states, steps=args.steps, repeat=args.repeat,
                                    cpu=args.cpu, before=commits["before"], after=commits["after"],
                                    after_dirty=records.git_state(trees["after"])[1]))
    COPIES.mkdir(parents=True, exist_ok=True)
    sys.path.insert(0, str(COPIES))
    original = engine.stepping
    try:
        kernels = {side: load_kernels(tree) for side, tree in trees.items()}
        measured = {}
        with xr.open_dataset(REPO / "data" / "validation" / system / realization / "states.nc") as record:
            for index in states:
                sims = {}
                for side in trees:
                    sims[side] = simulation_at(record, index, config, system)
                    engine.stepping = kernels[side]
                    sims[side].advance(20)  # JIT compilation (cached on disk after the first run), a first rebuild
                times = {side: [] for side in trees}
                for turn in range(args.repeat):
                    order = list(trees) if turn % 2 == 0 else list(trees)[::-1]
                    for side in order:
                        engine.stepping = kernels[side]
                        start = time.process_time()
                        sims[side].advance(args.steps)
                        times[side].append((time.process_time() - start) / args.steps)
                ratios = [b / a for b, a in zip(times["before"], times["after"])]
                label = f"{float(record['rho'].values[index]):.2f}"
                measured[label] = dict(
                    state=index, Z=float(record["Z"].values[index]), N=int(sims["after"].n_mobile),
                    before_us_per_step=1e6 * statistics.median(times["before"]),
                    after_us_per_step=1e6 * statistics.median(times["after"]),
                    speedup_median=statistics.median(ratios), speedup_quartiles=list(np.percentile(ratios, [25, 75])),
                    speedups=ratios, identical=same_state(sims["before"], sims["after"]))
                row = measured[label]
                print(f"ρ = {label} (Z = {row['Z']:.2f}): before {row['before_us_per_step']:.1f} µs/step, after "
                      f"{row['after_us_per_step']:.1f}, before/after {row['speedup_median']:.3f} (quartiles "
                      f"{row['speedup_quartiles'][0]:.3f}–{row['speedup_quartiles'][1]:.3f}), trajectories "
                      f"{'identical' if row['identical'] else 'differ'}", flush=True)
    finally:
        engine.stepping = original
    run.write(measured=measured)
    return 0


if __name__ == "__main__":
    sys.exit(main())
