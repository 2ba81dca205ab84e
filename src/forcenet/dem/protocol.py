"""Compression protocols (P1 §3 quasi-static, P2 App. A continuous), snapshots and checkpoints.

`run_compression` is the one entry point the workflow calls: it validates the system, builds (or resumes) the
simulation, compresses it through `system.rho_grid` and writes one snapshot per grid value.

* quasi-static (P1): the walls move inward at `wall_speed` until ρ reaches the next grid value (the walls stop
  exactly there); then the packing relaxes with the walls fixed, in windows of `relaxation.window_steps`
  steps, until std/mean of the kinetic energy over a window is below `relaxation.tolerance` (P1: 0.1 over
  1.5·10⁵ steps), or `relaxation.max_steps` is reached (logged as a warning); then the snapshot is taken.
* continuous (P2): the walls never stop; a snapshot is taken at the first step at which ρ ≥ the grid value.

Both start compressing at t = 0 from the lattice (the initial kinetic energy dissipates during the dilute part
of the compression, below the first grid value).

Pressure (snapshot `pressure`): the mean over the 2d walls of the wall's normal load (sum over its contacts of
the force component along the wall's inward normal) divided by the wall's current length (2D) or area (3D).

Checkpoints: after every snapshot the full state (Gear derivatives, tangential springs of every pair and wall
contact, wall positions, step, the RNG state, the next grid index and a fingerprint of system + seed) is saved
with `np.savez` to a temporary file renamed over `checkpoint_path`. A rerun resumes from it; snapshots with an
index below the checkpoint's next index are kept. Right after each checkpoint the Verlet list is rebuilt in
the uninterrupted run too, so that both continue from identical arrays: resumed snapshots are bit-identical.
"""
from __future__ import annotations

import hashlib
import json
import logging
import math
import os
import time
from pathlib import Path
from typing import Sequence

import numpy as np

from forcenet import datasets
from forcenet.dem import calibration, packing, stability
from forcenet.dem.engine import ContactLaw, Simulation, SimulationBlowUp
from forcenet.systems import MIN_STEPS_PER_COLLISION, ConfigError, SystemSpec, check_system

__all__ = ["run_compression", "SimulationBlowUp", "validate_system", "build_simulation", "contact_law_for_system",
           "CHECKPOINT_FORMAT"]

#: bump when the checkpoint layout or the engine's arithmetic changes (old checkpoints are then ignored)
CHECKPOINT_FORMAT = 3
#: seconds of wall time between progress log lines
LOG_INTERVAL_S = 10.0
#: steps per call into the engine between progress checks
CHUNK_STEPS = 5000

_LOG = logging.getLogger(__name__)


# --- set-up ------------------------------------------------------------------------------------------------

def contact_law_for_system(system: SystemSpec) -> ContactLaw:
    """P1 Eq. 1–3 with γ_n from restitution e_n under the system's damping model
    (`calibration.normal_damping_for_system`), γ_t = γ_n."""
    gamma_n = calibration.normal_damping_for_system(system)
    return ContactLaw(normal_stiffness=system.normal_stiffness, tangential_stiffness=system.tangential_stiffness,
                      normal_damping=gamma_n, tangential_damping=gamma_n, friction=system.friction,
                      beta=system.beta)


def validate_system(system: SystemSpec) -> packing.InitialPacking:
    """Check what can be checked before running; raise ConfigError naming the parameter. Returns a trial
    initial packing (seed 0) for the geometric checks."""
    key = f"systems.{system.name}"
    positive = {"box_length": system.box_length, "time_step": system.time_step, "wall_speed": system.wall_speed,
                "normal_stiffness": system.normal_stiffness}
    if system.size_distribution == "bidisperse":
        positive.update(diameter_ratio=system.diameter_ratio, small_to_large=system.small_to_large)
    for name, value in positive.items():
        if not (math.isfinite(value) and value > 0):
            raise ConfigError(f"{key}.{name}", f"must be positive, got {value}")
    for name, value in {"initial_speed": system.initial_speed, "friction": system.friction,
                        "tangential_stiffness": system.tangential_stiffness,
                        "polydispersity": system.polydispersity}.items():
        if not (math.isfinite(value) and value >= 0):
            raise ConfigError(f"{key}.{name}", f"must be non-negative, got {value}")
    if not 0.0 < system.restitution <= 1.0:
        raise ConfigError(f"{key}.restitution", f"must lie in (0, 1], got {system.restitution}")
    if system.protocol == "quasistatic" and system.relaxation is None:
        raise ConfigError(f"{key}.relaxation", "the quasi-static protocol needs a relaxation rule")
    check_system(system, key)
    trial = packing.initial_packing(system, np.random.default_rng(0))
    n = len(trial.radius)
    if n < 2:
        raise ConfigError(f"{key}.box_length", f"a box of {system.box_length} d_ave holds {n} particle(s); need ≥ 2")
    # the time step must resolve the shortest collision: two of the lightest particles at the fastest speed
    lightest = float(trial.mass.min())
    speed = 2.0 * max(system.initial_speed, system.wall_speed)
    shortest = calibration.minimum_collision_time(system, lightest, speed)
    if system.time_step > shortest / MIN_STEPS_PER_COLLISION:
        raise ConfigError(f"{key}.time_step",
                          f"Δt = {system.time_step} τ_c is too large: the shortest collision (two particles of mass "
                          f"{lightest:.3f} m̄ at relative speed {speed:g}) lasts {shortest:.4g} τ_c, which needs "
                          f"Δt ≤ {shortest / MIN_STEPS_PER_COLLISION:.4g} τ_c")
    rho0 = trial.packing_fraction
    if system.rho_grid[0] <= rho0:
        raise ConfigError(f"{key}.rho", f"the first ρ = {system.rho_grid[0]} is not above the initial (lattice) "
                                        f"packing fraction {rho0:.4f}")
    final_length = system.box_length * (rho0 / system.rho_grid[-1]) ** (1.0 / system.dimension)
    if system.rho_grid[-1] >= 1.0 or final_length < 2.0 * packing.largest_diameter(system):
        raise ConfigError(f"{key}.rho", f"ρ = {system.rho_grid[-1]} needs a box of {final_length:.3f} d_ave, "
                                        f"which the walls cannot reach")
    return trial


def build_simulation(system: SystemSpec, seed: int) -> tuple[Simulation, np.random.Generator]:
    """Initial state of one realization (lattice + random velocities from default_rng(seed))."""
    rng = np.random.default_rng(seed)
    initial = packing.initial_packing(system, rng)
    sim = Simulation(position=initial.position, radius=initial.radius, mass=initial.mass,
                     law=contact_law_for_system(system), time_step=system.time_step, box_lo=initial.box_lo,
                     box_hi=initial.box_hi, velocity=initial.velocity, walls=system.walls,
                     wall_particles=initial.walls)
    return sim, rng


def wall_shift_for(sim: Simulation, rho: float) -> float:
    """Inward shift of every wall at which the packing fraction is rho [d_ave]."""
    dim = sim.dimension
    volume = float(packing.particle_volume(2.0 * sim.radius[:sim.n_mobile], dim).sum())
    span0 = sim.box_hi - sim.box_lo
    # Π (span0_k − 2 s) = volume / ρ; cubic boxes (the only ones built here) give a closed form
    side = (volume / rho) ** (1.0 / dim)
    return 0.5 * (float(span0[0]) - side)


def _fingerprint(system: SystemSpec, seed: int) -> str:
    text = json.dumps({"system": repr(system), "seed": int(seed), "format": CHECKPOINT_FORMAT}, sort_keys=True)
    return hashlib.sha256(text.encode()).hexdigest()


# --- snapshots and checkpoints -------------------------------------------------------------------------------

def snapshot_arrays(sim: Simulation, relaxation_steps: int) -> dict:
    """The keyword arrays of `forcenet.datasets.write_snapshot` for the current state."""
    forces = sim.contact_forces()
    return dict(
        position=sim.positions(), radius=sim.radii(), velocity=sim.velocities(),
        angular_velocity=sim.angular_velocities(),
        contact_i=forces.contact_i, contact_j=forces.contact_j,
        force_normal=forces.force_normal, force_tangential=forces.force_tangential,
        wall_contact_particle=forces.wall_contact_particle, wall_contact_wall=forces.wall_contact_wall,
        wall_contact_force=forces.wall_contact_force,
        box_lo=sim.walls_lo.copy(), box_hi=sim.walls_hi.copy(), rho=sim.packing_fraction,
        Z=2.0 * len(forces.contact_i) / sim.n_mobile, kinetic_energy=sim.kinetic_energy(),
        pressure=sim.wall_pressure(forces.wall_normal_load), time=sim.time, step=sim.step,
        relaxation_steps=int(relaxation_steps))


def save_checkpoint(path: Path, sim: Simulation, *, next_index: int, fingerprint: str,
                    rng: np.random.Generator, cpu_seconds: float = 0.0) -> None:
    """Atomic np.savez of everything needed to continue (temp file + rename); cpu_seconds is the run's CPU time
    so far (all sessions), so a resumed run still reports what the whole run cost."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = path.with_name(path.name + f".tmp{os.getpid()}")
    with open(tmp, "wb") as handle:
        np.savez(handle, **sim.state_dict(), next_index=next_index, fingerprint=fingerprint,
                 rng_state=json.dumps(rng.bit_generator.state), cpu_seconds=float(cpu_seconds))
        handle.flush()
        os.fsync(handle.fileno())
    os.replace(tmp, path)


def load_checkpoint(path: Path, fingerprint: str, snapshot_paths: Sequence[Path], log: logging.Logger):
    """(Simulation, rng, next_index, cpu_seconds so far) from a checkpoint that matches, else None (and the reason
    is logged)."""
    path = Path(path)
    if not path.exists():
        return None
    try:
        with np.load(path, allow_pickle=False) as data:
            state = {key: data[key] for key in data.files}
    except (OSError, ValueError, EOFError) as err:
        log.warning("ignoring unreadable checkpoint %s (%s); starting from scratch", path, err)
        return None
    if str(state.get("fingerprint")) != fingerprint:
        log.warning("checkpoint %s belongs to another system, seed or engine version; starting from scratch", path)
        return None
    next_index = int(state["next_index"])
    missing = [str(p) for p in snapshot_paths[:next_index] if not Path(p).exists()]
    if missing:
        log.warning("checkpoint %s is past snapshots that are missing (%s); starting from scratch", path, missing[0])
        return None
    rng = np.random.default_rng()
    rng.bit_generator.state = json.loads(str(state["rng_state"]))
    return Simulation.from_state_dict(state), rng, next_index, float(state.get("cpu_seconds", 0.0))


# --- the driver ------------------------------------------------------------------------------------------------

class _Progress:
    """Logs ρ, Z, E_kin, steps/s and the estimated time left at most every LOG_INTERVAL_S seconds."""

    def __init__(self, log: logging.Logger, system: SystemSpec, sim: Simulation, start_index: int):
        self.log, self.system = log, system
        self.start_clock = self.last_clock = time.monotonic()
        self.last_step = sim.step
        self.start_index = start_index
        self.relaxation_steps_done: list[int] = []

    def maybe_log(self, sim: Simulation, index: int, kinetic_energy: float, remaining_steps: float) -> None:
        now = time.monotonic()
        if now - self.last_clock < LOG_INTERVAL_S:
            return
        rate = (sim.step - self.last_step) / max(now - self.last_clock, 1e-9)
        if self.system.protocol == "quasistatic":
            per_point = (np.mean(self.relaxation_steps_done) if self.relaxation_steps_done
                         else self.system.relaxation.window_steps)
            remaining_steps += per_point * (len(self.system.rho_grid) - index)
        eta = remaining_steps / rate if rate > 0 else float("inf")
        self.log.info("%s: step %d, ρ = %.4f (next %.3f), Z = %.3f, E_kin = %.3e, %.0f steps/s, ~%s left",
                      self.system.name, sim.step, sim.packing_fraction, self.system.rho_grid[min(index, len(self.system.rho_grid) - 1)],
                      2.0 * sim.contact_count() / sim.n_mobile, kinetic_energy, rate, _duration(eta))
        self.last_clock, self.last_step = now, sim.step


def _duration(seconds: float) -> str:
    if not math.isfinite(seconds):
        return "?"
    seconds = int(seconds)
    return f"{seconds // 3600}h{seconds % 3600 // 60:02d}m{seconds % 60:02d}s"


def _compress_to(sim: Simulation, target_shift: float, index: int, progress: _Progress, speed: float,
                 stop_walls: bool) -> None:
    """Move the walls at `speed` until their shift reaches target_shift (stopping there if stop_walls)."""
    sim.set_walls(speed, target_shift if stop_walls else np.inf)
    while sim.wall_shift < target_shift:
        steps = math.ceil((target_shift - sim.wall_shift) / (speed * sim.time_step) - 1e-9)
        steps = max(1, min(steps, CHUNK_STEPS))
        energy = sim.advance(steps)
        remaining = max(0.0, (target_shift - sim.wall_shift) / (speed * sim.time_step))
        progress.maybe_log(sim, index, float(energy[-1]), remaining)


def _relax(sim: Simulation, system: SystemSpec, index: int, progress: _Progress, log: logging.Logger) -> int:
    """P1 §3 relaxation with fixed walls; returns the number of relaxation steps."""
    rule = system.relaxation
    sim.set_walls(0.0, sim.wall_shift)
    window = np.empty(rule.window_steps)
    done = 0
    while True:
        filled = 0
        while filled < rule.window_steps and done < rule.max_steps:
            steps = min(CHUNK_STEPS, rule.window_steps - filled, rule.max_steps - done)
            sim.advance(steps, window[filled:filled + steps])
            filled += steps
            done += steps
            progress.maybe_log(sim, index, float(window[filled - 1]), 0.0)
        if filled == rule.window_steps:
            mean = float(np.mean(window))
            fluctuation = float(np.std(window)) / mean if mean > 0 else 0.0
            if fluctuation < rule.tolerance:
                return done
        if done >= rule.max_steps:
            log.warning("%s: relaxation at ρ = %.3f hit the cap of %d steps (E_kin fluctuation still ≥ %g)",
                        system.name, system.rho_grid[index], rule.max_steps, rule.tolerance)
            return done


def check_damping_is_integrable(sim: Simulation, system: SystemSpec) -> float:
    """Raise SimulationBlowUp when the fastest damped mode of the current contacts is faster than the Gear
    corrector can integrate at Δt (`forcenet.dem.stability`): the state would be a numerical artefact (energy
    pumped into that mode and held by the Coulomb cap), not a packing. Returns rate · Δt."""
    fastest = stability.fastest_damping_rate_of(sim)
    product = fastest.rate * sim.time_step
    if product > stability.GEAR_DAMPING_BOUND:
        raise SimulationBlowUp(
            f"the contact damping is too fast for the time step: its fastest mode decays at "
            f"{fastest.rate:.4g}/τ_c, and rate · Δt = {product:.2f} exceeds the Gear corrector's stability bound "
            f"{stability.GEAR_DAMPING_BOUND}, so each step amplifies that mode instead of damping it; set "
            f"systems.{system.name}.time_step ≤ {stability.stable_time_step(fastest.rate):.3g} "
            f"(or weaker damping)", step=sim.step, particle=int(sim.particle_id[fastest.particle]),
            rho=sim.packing_fraction)
    return product


def run_compression(system: SystemSpec, *, seed: int, snapshot_paths: Sequence[str | os.PathLike],
                    checkpoint_path: str | os.PathLike, attrs: dict, log: logging.Logger | None = None) -> float:
    """Compress one realization of `system` through its ρ grid, writing one snapshot per grid value.

    snapshot_paths: one path per `system.rho_grid` value, same order. checkpoint_path: resumable state
    (written after each snapshot). attrs: provenance stored in every snapshot. Raises ConfigError for bad
    input (before any work) and SimulationBlowUp when the dynamics become unphysical (no snapshot is written
    for the failed grid value; earlier ones are complete and the checkpoint allows a rerun from the last one).
    Each snapshot records λΔt (`dem_damping_rate_time_step`, the stability check's margin). Returns the CPU
    seconds the whole run took, over every session that resumed it.
    """
    log = log or _LOG
    paths = [Path(p) for p in snapshot_paths]
    if len(paths) != len(system.rho_grid):
        raise ValueError(f"{len(paths)} snapshot paths for {len(system.rho_grid)} ρ values of {system.name}")
    validate_system(system)
    fingerprint = _fingerprint(system, seed)
    resumed = load_checkpoint(Path(checkpoint_path), fingerprint, paths, log)
    cpu_before = 0.0
    if resumed is not None:
        sim, rng, start, cpu_before = resumed
        log.info("%s: resuming from %s at step %d (snapshot %d of %d)", system.name, checkpoint_path, sim.step,
                 start + 1, len(paths))
    else:
        sim, rng = build_simulation(system, seed)
        start = 0
        log.info("%s: N = %d particles, initial ρ = %.4f, γ_n = %.6g, %d snapshots (%s)", system.name,
                 sim.n_mobile, sim.packing_fraction, sim.law[2], len(paths), system.protocol)
    file_attrs = dict(attrs)
    file_attrs.setdefault("dem_normal_damping", float(sim.law[2]))
    progress = _Progress(log, system, sim, start)
    cpu_start = time.process_time()
    for index in range(start, len(paths)):
        rho = system.rho_grid[index]
        target = wall_shift_for(sim, rho)
        if system.protocol == "quasistatic":
            _compress_to(sim, target, index, progress, system.wall_speed, stop_walls=True)
            relaxation_steps = _relax(sim, system, index, progress, log)
            progress.relaxation_steps_done.append(relaxation_steps)
        else:
            _compress_to(sim, target, index, progress, system.wall_speed, stop_walls=False)
            relaxation_steps = -1
        damping_dt = check_damping_is_integrable(sim, system)
        datasets.write_snapshot(paths[index], attrs={**file_attrs, "dem_damping_rate_time_step": damping_dt},
                                **snapshot_arrays(sim, relaxation_steps))
        cpu_seconds = cpu_before + time.process_time() - cpu_start
        save_checkpoint(Path(checkpoint_path), sim, next_index=index + 1, fingerprint=fingerprint, rng=rng,
                        cpu_seconds=cpu_seconds)
        sim.rebuild()  # the resumed run rebuilds here too (Simulation.from_state_dict): identical arrays
        log.info("%s: snapshot ρ = %.3f written (step %d, Z = %.3f, fastest damping rate × Δt = %.2f of %.2f)",
                 system.name, rho, sim.step, 2.0 * sim.contact_count() / sim.n_mobile, damping_dt,
                 stability.GEAR_DAMPING_BOUND)
    return cpu_before + time.process_time() - cpu_start
