#!/usr/bin/env python
"""The shipped LAMMPS examples of `forcenet.importers.lammps` (data/examples/lammps_2d/, lammps_3d/): LAMMPS dumps
of states our engine made, and those states themselves, so that a test can check that the imported network is the
one our engine evaluates on the same state.

usage: python bench/lammps/make_import_example.py [--dim 2|3] [--out DIR] [--box L] [--rho R1 R2 ...]

Our engine compresses the 2d_linear (--dim 2: box 24 d_ave, ρ 0.82, 0.84, 0.86) or the 3d_hertz (--dim 3: box 7,
ρ 0.58, 0.60, 0.62) system of config/smoke.yaml (flat walls, seed 7) and stops at each ρ of --rho; at each stop the walls rest for a while, random velocities of 0.05 d_ave/τ_c are added
(so that the damping matters) and the state is saved. LAMMPS (bench/lammps/setup.sh) then evaluates each state
without an integrator for one step, with the input `bench/lammps_same_state.py` writes for its `damping` probe (one
spring increment, γ_t = γ_n, limit_damping, Hertz with every term × √R_eff, walls through LAMMPS's granular model),
and writes

- ``atoms.dump`` — ``dump custom``: id type x y z radius (and the wall force on each atom, f_walls[1..3]: the
  per-atom contact force of fix wall/gran/region's ``contacts`` option), one timestep per state;
- ``pairs.dump`` — ``dump local``: c_pid[1] c_pid[2] (property/local patom1 patom2), c_pf[1] (pair/local force:
  the normal force's magnitude) and c_pf[2..4] (pair/local p1 p2 p3 of gran/hooke/history: the tangential force
  on the first atom);
- ``states.npz`` — every state as our engine had it (positions, velocities, radii, masses, walls, time step, law),
  read by tests/test_importers.py to evaluate the same state with our engine.

Both dumps print 10 significant digits (``modify format float %.10g``): the precision to which the imported
network equals our engine's. The simulation box is the walls (the dump's box bounds are the walls, so ρ comes from
the dump). Takes ~20 s.
"""
from __future__ import annotations

import argparse
import math
import sys
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
sys.path.insert(0, str(HERE.parent))
from lammps_same_state import (COMPRESSION_SPEED, PROBE_SPEED, RELAX_STEPS, LammpsUnavailable,  # noqa: E402
                               find_lammps, lammps_input as same_state_input, probe_law)
from run_lammps import num, run_lmp  # noqa: E402

REPO = HERE.parent.parent
#: --dim → (config/smoke.yaml system, box [d_ave], packing fractions, output folder)
CASES = {2: ("2d_linear", 24.0, (0.82, 0.84, 0.86), "lammps_2d"), 3: ("3d_hertz", 7.0, (0.58, 0.60, 0.62), "lammps_3d")}
SEED = 7
#: the LAMMPS timestep given to state k (distinct, increasing: the dumps' TIMESTEP items)
TIMESTEP_STRIDE = 1000


def make_states(system: str, box: float, rhos, seed: int = SEED) -> list[dict]:
    """Our engine's states at each ρ of `rhos` (module docstring)."""
    from forcenet.catalog import load_run_config
    from forcenet.checks import checked_system
    from forcenet.dem.protocol import build_simulation, contact_law_for_system, wall_shift_for

    config = load_run_config(REPO / "config" / "smoke.yaml")
    entry = dict(config["systems"][system], box_length=box, rho=list(rhos))
    spec = checked_system(system, dict(config, systems={system: entry}))
    sim, _ = build_simulation(spec, seed)
    rng = np.random.default_rng(seed)
    law = contact_law_for_system(spec)
    states, done = [], 0.0
    for rho in rhos:
        shift = wall_shift_for(sim, rho)
        sim.set_walls(COMPRESSION_SPEED, shift)
        sim.advance(math.ceil((shift - done) / (COMPRESSION_SPEED * spec.time_step)) + 10)
        done = shift
        sim.set_walls(0.0)
        sim.advance(RELAX_STEPS)
        velocities = sim.velocities() + PROBE_SPEED * rng.normal(size=sim.velocities().shape)
        states.append(dict(dim=spec.dimension, positions=sim.positions(), radii=sim.radii(),
                           masses=sim.masses(), velocities=velocities,
                           box_lo=sim.walls_lo.copy(), box_hi=sim.walls_hi.copy(), dt=spec.time_step, law=law,
                           rho=sim.packing_fraction))
    return states


def data_file(state: dict) -> str:
    """LAMMPS data (atom_style sphere) whose box is the walls."""
    n, dim = len(state["radii"]), state["dim"]
    x, v = np.zeros((n, 3)), np.zeros((n, 3))
    x[:, :dim], v[:, :dim] = state["positions"], state["velocities"]
    density = state["masses"] / (4.0 / 3.0 * np.pi * state["radii"] ** 3)
    lines = ["LAMMPS data file: forcenet import example", "", f"{n} atoms", "1 atom types", ""]
    for k, ax in enumerate("xyz"):
        lo, hi = (state["box_lo"][k], state["box_hi"][k]) if k < dim else (-0.5, 0.5)
        lines.append(f"{num(lo)} {num(hi)} {ax}lo {ax}hi")
    lines += ["", "Atoms # sphere", ""]
    lines += [f"{i + 1} 1 {num(2 * state['radii'][i])} {num(density[i])} " + " ".join(map(num, x[i])) for i in range(n)]
    lines += ["", "Velocities", ""]
    lines += [f"{i + 1} " + " ".join(map(num, (*v[i], 0.0, 0.0, 0.0))) for i in range(n)]
    return "\n".join(lines) + "\n"


def lammps_input(states: list[dict]) -> str:
    """One input: per state, `bench/lammps_same_state.py`'s input of its `damping` probe (read the state, one step
    without an integrator) with the state's timestep, the per-atom wall contacts (fix wall/gran/region `contacts`)
    and both dumps appended instead of its force dump."""
    commands = []
    for k, state in enumerate(states):
        append = " append yes" if k else ""
        for line in same_state_input(state, probe_law(state, "damping"), 1).splitlines():
            if line.startswith("read_data"):
                commands += [f"read_data state{k}.data", f"reset_timestep {(k + 1) * TIMESTEP_STRIDE - 1}"]
            elif line.startswith("fix walls"):
                commands.append(f"{line} contacts")
            elif line.startswith("run"):
                commands += ["compute pid all property/local patom1 patom2", "compute pf all pair/local force p1 p2 p3",
                             line]
            elif line.startswith("write_dump"):
                commands += [
                    "write_dump all custom atoms.dump id type x y z radius f_walls[2] f_walls[3] f_walls[4] "
                    f"modify format float %.10g{append}",
                    "write_dump all local pairs.dump c_pid[1] c_pid[2] c_pf[1] c_pf[2] c_pf[3] c_pf[4] "
                    f"modify format float %.10g{append}"]
            else:
                commands.append(line if line != "units lj" else "clear\nunits lj")
    return "\n".join(commands) + "\n"


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--dim", type=int, choices=sorted(CASES), default=2)
    ap.add_argument("--out", help="default data/examples/lammps_{2d,3d}")
    ap.add_argument("--box", type=float, help="box side [d_ave] (default: 24 in 2D, 7 in 3D)")
    ap.add_argument("--rho", type=float, nargs="+", help="packing fractions (default: 0.82 0.84 0.86 / 0.58 0.60 0.62)")
    args = ap.parse_args(argv)
    system, box, rhos, folder = CASES[args.dim]
    try:
        lmp = find_lammps()
    except LammpsUnavailable as error:
        print(f"error: LAMMPS is not available: {error}", file=sys.stderr)
        return 3
    out = Path(args.out or REPO / "data" / "examples" / folder)
    out.mkdir(parents=True, exist_ok=True)
    states = make_states(system, args.box or box, args.rho or rhos)
    for k, state in enumerate(states):
        (out / f"state{k}.data").write_text(data_file(state))
    (out / "in.example").write_text(lammps_input(states))
    for name in ("atoms.dump", "pairs.dump"):
        (out / name).unlink(missing_ok=True)
    run_lmp(str(lmp), out / "in.example", out / "log.lammps")
    for k in range(len(states)):
        (out / f"state{k}.data").unlink()
    (out / "log.lammps").unlink()
    law = states[0]["law"]
    np.savez_compressed(out / "states.npz", **{f"{key}{k}": np.asarray(s[key]) for k, s in enumerate(states)
                                               for key in ("positions", "radii", "masses", "velocities", "box_lo",
                                                           "box_hi")},
                        dt=states[0]["dt"], normal_stiffness=law.normal_stiffness,
                        tangential_stiffness=law.tangential_stiffness, normal_damping=law.normal_damping,
                        tangential_damping=law.tangential_damping, friction=law.friction, beta=law.beta,
                        radius_scaled=probe_law(states[0], "damping").radius_scaled,
                        timesteps=np.array([(k + 1) * TIMESTEP_STRIDE for k in range(len(states))]))
    print(f"{out}: {len(states)} states of {len(states[0]['radii'])} {'disks' if args.dim == 2 else 'spheres'}, rho "
          + ", ".join(f"{s['rho']:.4f}" for s in states))
    return 0


if __name__ == "__main__":
    sys.exit(main())
