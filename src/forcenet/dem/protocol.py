"""Compression protocols (P1 §3 quasi-static, P2 App. A continuous), snapshots and checkpoints.

`run_compression` is the one entry point the workflow calls: given a checked system (`forcenet.checks.checked_system`
runs the physical checks of its config first), it builds (or resumes) the simulation, compresses it through
`system.rho_grid` and writes one snapshot per grid value.

* quasi-static (P1): the walls move inward at `wall_speed` until ρ reaches the next grid value (the walls stop
  exactly there); then the packing relaxes with the walls fixed, in windows of `relaxation.window_steps`
  steps, until std/mean of the kinetic energy over a window is below `relaxation.tolerance` (P1: 0.1 over
  1.5·10⁵ steps; with `relaxation.criterion: contact_number`, until the contact number is the same at every
  chunk end of a window), or `relaxation.max_steps` is reached (logged as a warning); then the snapshot is taken.
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

import dataclasses
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
from forcenet.boxes import P1_OVERLAP_BOUND, relative_overlaps
from forcenet.dem import calibration, packing, stability
from forcenet.dem.engine import ContactLaw, Simulation, SimulationBlowUp
from forcenet.systems import CONTACT_NUMBER, KINETIC_ENERGY_FLUCTUATION, SystemSpec

__all__ = ["run_compression", "SimulationBlowUp", "build_simulation", "contact_law_for_system",
           "blow_up_cause", "continue_with_damping", "CHECKPOINT_FORMAT"]

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
    (`calibration.normal_damping_for_system`), γ_t = γ_n; flat walls of their own material scale k_n and k_t of
    their contacts (`SystemSpec.wall_stiffness_factor`), the damping coefficients stay the pair's."""
    gamma_n = calibration.normal_damping_for_system(system)
    return ContactLaw(normal_stiffness=system.normal_stiffness, tangential_stiffness=system.tangential_stiffness,
                      normal_damping=gamma_n, tangential_damping=gamma_n, friction=system.friction,
                      beta=system.beta, wall_stiffness_factor=system.wall_stiffness_factor)


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
    volume = float(packing.particle_volume(2.0 * sim.particles.radius[:sim.n_mobile], dim).sum())
    span0 = sim.walls.box_hi - sim.walls.box_lo
    # Π (span0_k − 2 s) = volume / ρ; cubic boxes (the only ones built here) give a closed form
    side = (volume / rho) ** (1.0 / dim)
    return 0.5 * (float(span0[0]) - side)


def _fingerprint(system: SystemSpec, seed: int) -> str:
    identity = {"system": repr(system), "seed": int(seed), "format": CHECKPOINT_FORMAT}
    if system.initial_state is not None:  # not in the repr: runs without it keep their fingerprints
        identity["initial_state"] = repr(system.initial_state)
    if system.wall_stiffness_factor != 1.0:  # walls of their own material; likewise not in the repr
        identity["wall_stiffness_factor"] = repr(system.wall_stiffness_factor)
    # likewise not in the repr; the continuous protocol (P2) has no relaxation
    if system.relaxation is not None and system.relaxation.criterion != KINETIC_ENERGY_FLUCTUATION:
        identity["relaxation_criterion"] = system.relaxation.criterion
    text = json.dumps(identity, sort_keys=True)
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


def warn_of_overlaps(arrays: dict, system: str, log: logging.Logger) -> float:
    """Log a warning when a snapshot's largest particle overlap passes P1 §3's bound (`boxes.P1_OVERLAP_BOUND`, 10 %
    of the sum of the radii): a ρ grid compressed past where P1's protocol stops (the engine stops only at 20 %).
    `arrays`: the snapshot's (`snapshot_arrays`). Returns the largest overlap (0 without contacts)."""
    overlaps = relative_overlaps(arrays["position"], arrays["radius"], arrays["contact_i"], arrays["contact_j"])
    if not overlaps.size:
        return 0.0
    k = int(np.argmax(overlaps))
    if overlaps[k] > P1_OVERLAP_BOUND:
        log.warning("%s: overlaps up to %.1f %% of the sum of the radii at ρ = %.4f (particles %d and %d), past the "
                    "%.0f %% P1 §3 states: expect the overlap claims to fail from here on", system,
                    100 * overlaps[k], float(arrays["rho"]), int(arrays["contact_i"][k]), int(arrays["contact_j"][k]),
                    100 * P1_OVERLAP_BOUND)
    return float(overlaps[k])


def save_checkpoint(path: Path, sim: Simulation, *, next_index: int, fingerprint: str,
                    rng: np.random.Generator, cpu_seconds: float = 0.0) -> None:
    """Atomic np.savez of everything needed to continue (temp file + rename); cpu_seconds is the run's CPU time
    so far (every job that worked on the run), so a resumed run still reports what the whole run cost."""
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
    try:
        sim = Simulation.from_state_dict(state)
    except KeyError as err:  # a layout change bumps CHECKPOINT_FORMAT (in the fingerprint): another file, then
        log.warning("checkpoint %s has %s; starting from scratch", path, err.args[0])
        return None
    rng = np.random.default_rng()
    rng.bit_generator.state = json.loads(str(state["rng_state"]))
    return sim, rng, next_index, float(state.get("cpu_seconds", 0.0))


# --- the driver ------------------------------------------------------------------------------------------------

class _Progress:
    """Progress lines, at most every LOG_INTERVAL_S seconds: snapshot k of n, step, ρ, Z, E_kin, steps/s and the
    time left until the snapshot in work and for the whole run, with the protocol's remaining work in steps
    (compression to the last grid value; relaxation estimated from the grid points relaxed so far, counting
    those a resumed run wrote before, one window before the first; a relaxation past that estimate at least to
    the end of its window).

    The rate is measured from the end of the first chunk of steps, which pays for loading or compiling the numba
    kernels; no line is logged before it. Nothing here touches the simulation's state."""

    def __init__(self, log: logging.Logger, system: SystemSpec, sim: Simulation, start_index: int):
        self.log, self.system = log, system
        self.last_clock: float | None = None  # set at the end of the first chunk
        self.last_step = sim.step
        self.start_index = start_index
        self.relaxation_steps_done: list[int] = []

    def remaining_steps(self, sim: Simulation, index: int, relaxed: int | None) -> tuple[float, float, float]:
        """(steps to the snapshot at grid point `index`, compression steps left in the run, relaxation steps left in
        the run); `relaxed`: relaxation steps already done at this grid point, None while compressing."""
        grid, step_length = self.system.rho_grid, self.system.wall_speed * sim.time_step
        shifts = [sim.wall_shift] + [wall_shift_for(sim, rho) for rho in grid[index:]]
        compression = [max(0.0, later - earlier) / step_length for earlier, later in zip(shifts, shifts[1:])]
        relax_now = relax_later = 0.0
        if self.system.protocol == "quasistatic":
            rule = self.system.relaxation
            per_point = (float(np.mean(self.relaxation_steps_done)) if self.relaxation_steps_done
                         else float(rule.window_steps))
            relax_now = per_point
            if relaxed is not None:
                # a relaxation ends only where a window ends (or at the cap): one that has run past the mean still
                # has the rest of its window ahead, never "0 s to this snapshot"
                to_window_end = min(rule.window_steps - relaxed % rule.window_steps, rule.max_steps - relaxed)
                relax_now = max(per_point - relaxed, float(to_window_end))
            relax_later = per_point * (len(grid) - index - 1)
        return compression[0] + relax_now, sum(compression), relax_now + relax_later

    def maybe_log(self, sim: Simulation, index: int, kinetic_energy: float, relaxed: int | None = None) -> None:
        """Called after every chunk of steps; `relaxed` as in `remaining_steps`."""
        now = time.monotonic()
        if self.last_clock is None:  # end of the first chunk: start the clock after compilation
            self.last_clock, self.last_step = now, sim.step
            return
        if now - self.last_clock < LOG_INTERVAL_S:
            return
        rate = (sim.step - self.last_step) / max(now - self.last_clock, 1e-9)
        to_snapshot, compression, relaxation = self.remaining_steps(sim, index, relaxed)
        grid = self.system.rho_grid
        self.log.info("%s: snapshot %d of %d (ρ → %.3f), step %d, ρ = %.4f, Z = %.3f, E_kin = %.3e, %.0f steps/s; "
                      "~%s to this snapshot, ~%s left for the run (%.3g compression + %.3g relaxation steps)",
                      self.system.name, index + 1, len(grid), grid[index], sim.step, sim.packing_fraction,
                      2.0 * sim.contact_count() / sim.n_mobile, kinetic_energy, rate, _duration(to_snapshot, rate),
                      _duration(compression + relaxation, rate), compression, relaxation)
        self.last_clock, self.last_step = now, sim.step


def _relaxation_steps_written(paths: Sequence[Path]) -> list[int]:
    """The relaxation steps recorded in snapshots already written (those with a relaxation), so that a resumed
    run estimates its time left from what its relaxations took, not from one window per grid point. A snapshot
    that cannot be read adds nothing: the estimate must never stop a run."""
    steps = []
    for path in paths:
        try:
            with datasets.read_snapshot(path) as snapshot:
                value = int(snapshot["relaxation_steps"])
        except (datasets.DatasetError, OSError, KeyError, ValueError):
            continue
        if value >= 0:
            steps.append(value)
    return steps


def _duration(steps: float, rate: float) -> str:
    """`steps` at `rate` steps/s as h:mm:ss ("?" without a rate)."""
    seconds = steps / rate if rate > 0 else math.inf
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
        progress.maybe_log(sim, index, float(energy[-1]))


def _relax(sim: Simulation, system: SystemSpec, index: int, progress: _Progress, log: logging.Logger) -> int:
    """P1 §3 relaxation with fixed walls until a window meets `system.relaxation.criterion`
    (`forcenet.systems.Relaxation`); returns the number of relaxation steps."""
    rule = system.relaxation
    by_contacts = rule.criterion == CONTACT_NUMBER
    sim.set_walls(0.0, sim.wall_shift)
    window = np.empty(rule.window_steps)
    done = 0
    while True:
        filled = 0
        contacts = set()  # the contact numbers seen at the chunk ends of this window
        while filled < rule.window_steps and done < rule.max_steps:
            steps = min(CHUNK_STEPS, rule.window_steps - filled, rule.max_steps - done)
            sim.advance(steps, window[filled:filled + steps])
            filled += steps
            done += steps
            if by_contacts:
                contacts.add(sim.contact_count())
            progress.maybe_log(sim, index, float(window[filled - 1]), relaxed=done)
        if filled == rule.window_steps:
            if by_contacts:
                if len(contacts) == 1:  # P1 §3: "the contact number does not change over a large number of steps"
                    return done
            else:
                mean = float(np.mean(window))
                fluctuation = float(np.std(window)) / mean if mean > 0 else 0.0
                if fluctuation < rule.tolerance:
                    return done
        if done >= rule.max_steps:
            still = ("the contact number still changing" if by_contacts
                     else f"E_kin fluctuation still ≥ {rule.tolerance:g}")
            log.warning("%s: relaxation at ρ = %.3f hit the cap of %d steps (%s)",
                        system.name, sim.packing_fraction, rule.max_steps, still)
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
            f"(or weaker damping)", step=sim.step, particle=int(sim.particles.particle_id[fastest.particle]),
            rho=sim.packing_fraction, cause="damping")
    return product


#: an overlap blow-up is blamed on the time step when the failing particle, at its speed when it failed, closes a
#: fifth of its diameter (the blow-up limit) within this many steps and moves this many times faster than the walls;
#: otherwise the overlap grew with the compression and the ρ grid is blamed
FEW_STEPS = 100
FAST_SPEED_FACTOR = 10.0


def blow_up_cause(sim: Simulation, system: SystemSpec, error: SimulationBlowUp) -> str:
    """Which setting most likely caused a blow-up of the step loop, as a sentence naming its config key:
    `time_step` for a NaN, an escape, or an overlap that grows within a few steps (FEW_STEPS), the ρ grid for an
    overlap that grows with the compression. Reads the failed state; changes nothing."""
    key = f"systems.{system.name}"
    if error.cause in ("not_finite", "escaped"):
        return (f"most likely {key}.time_step: a particle moved too far in one step of Δt = {system.time_step} τ_c "
                "for the contacts to stop it; lower time_step")
    if error.cause != "overlap" or not 0 <= error.particle < sim.n_mobile:
        return ""
    speed = float(np.linalg.norm(sim.velocities()[error.particle]))
    diameter = 2.0 * float(sim.radii()[error.particle])
    steps = 0.2 * diameter / max(speed * system.time_step, 1e-300)
    if steps <= FEW_STEPS and speed > FAST_SPEED_FACTOR * system.wall_speed:
        return (f"most likely {key}.time_step: at its speed when it failed ({speed:.3g} d_ave/τ_c, "
                f"{speed / system.wall_speed:.0f}× the wall speed) the particle closes a fifth of its diameter in "
                f"~{steps:.0f} steps, a collision that Δt = {system.time_step} τ_c does not resolve; lower time_step")
    return (f"most likely {key}.rho: the overlap grew with the compression (the particle moved at {speed:.3g} "
            f"d_ave/τ_c, ~{steps:.0f} steps per fifth of a diameter, walls at {system.wall_speed:g} d_ave/τ_c): "
            f"ρ = {sim.packing_fraction:.4f} is more than this packing bears; lower the grid's stop "
            f"({system.rho_grid[-1]}) or the wall_speed")


def _advance(sim: Simulation, system: SystemSpec, index: int, target: float, progress: "_Progress",
             log: logging.Logger) -> int:
    """Move the walls to grid value `index` (wall shift `target`), then relax there under the quasistatic protocol
    (P1 §3); the continuous one keeps the walls moving. Returns the relaxation steps (−1 without a relaxation)."""
    quasistatic = system.protocol == "quasistatic"
    _compress_to(sim, target, index, progress, system.wall_speed, stop_walls=quasistatic)
    if not quasistatic:
        return -1
    steps = _relax(sim, system, index, progress, log)
    progress.relaxation_steps_done.append(steps)
    return steps


def continue_with_damping(system: SystemSpec, state: dict, normal_damping: float, grid_steps: int,
                          log: logging.Logger | None = None) -> tuple[Simulation, dict]:
    """Continue a run's checkpoint through the next `grid_steps` values of `system`'s ρ grid under another normal
    damping, writing nothing: what a blow-up depends on (`scripts/probe_checkpoint.py`).

    state: the arrays of a checkpoint.npz (``np.load``); normal_damping: γ_n [d_ave^(−β) τ_c^(−1)], the
    tangential damping scaled with it (the ratio the run had). The protocol is the run's (compression at the wall
    speed, then a relaxation for the quasistatic one). With the run's own γ_n it reproduces the run step for step.
    Returns the simulation where it stopped and {"last_rho": ρ of the last grid value completed, "max_damping_dt":
    the largest λΔt of the stability check at those values, "blow_up": the blow-up's message or ""}."""
    log = log or _LOG
    sim = Simulation.from_state_dict(state)
    law = sim.contact_law
    ratio = law.tangential_damping / law.normal_damping if law.normal_damping else 0.0
    sim.set_law(dataclasses.replace(law, normal_damping=normal_damping, tangential_damping=normal_damping * ratio))
    start = int(state["next_index"])
    progress = _Progress(log, system, sim, start)
    result = {"last_rho": float(sim.packing_fraction), "max_damping_dt": 0.0, "blow_up": ""}
    for index in range(start, min(start + grid_steps, len(system.rho_grid))):
        try:
            _advance(sim, system, index, wall_shift_for(sim, system.rho_grid[index]), progress, log)
            damping_dt = check_damping_is_integrable(sim, system)
        except SimulationBlowUp as error:
            result["blow_up"] = f"{error} (step {error.step}, particle {error.particle}, ρ {error.rho:.4f})"
            break
        result["last_rho"] = float(sim.packing_fraction)
        result["max_damping_dt"] = max(result["max_damping_dt"], damping_dt)
        sim.rebuild()  # as run_compression after each snapshot, so the state matches the run's
    return sim, result


def run_compression(system: SystemSpec, *, seed: int, snapshot_paths: Sequence[str | os.PathLike],
                    checkpoint_path: str | os.PathLike, attrs: dict, log: logging.Logger | None = None) -> float:
    """Compress one realization of `system` through its ρ grid, writing one snapshot per grid value.

    system: a checked system (`forcenet.checks.checked_system`, or `check_system` on a changed copy). snapshot_paths:
    one path per `system.rho_grid` value, same order. checkpoint_path: resumable state (written after each snapshot).
    attrs: provenance stored in every snapshot. Raises SimulationBlowUp when the dynamics become unphysical (no
    snapshot is written for the failed grid value; earlier ones are complete and the checkpoint allows a rerun from
    the last one). Each snapshot records λΔt (`dem_damping_rate_time_step`, the stability check's margin). Returns
    the CPU seconds the whole run took, over every job that resumed it.
    """
    log = log or _LOG
    paths = [Path(p) for p in snapshot_paths]
    if len(paths) != len(system.rho_grid):
        raise ValueError(f"{len(paths)} snapshot paths for {len(system.rho_grid)} ρ values of {system.name}")
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
                 sim.n_mobile, sim.packing_fraction, sim.contact_law.normal_damping, len(paths), system.protocol)
    file_attrs = dict(attrs)
    file_attrs.setdefault("dem_normal_damping", sim.contact_law.normal_damping)
    progress = _Progress(log, system, sim, start)
    progress.relaxation_steps_done += _relaxation_steps_written(paths[:start])
    cpu_start = time.process_time()
    for index in range(start, len(paths)):
        rho = system.rho_grid[index]
        target = wall_shift_for(sim, rho)
        try:
            if index == 0 and resumed is None and system.initial_state is not None \
                    and system.initial_state.relax_first:  # P1 §3: relax from the start (resolves t = 0 overlaps)
                log.info("%s: relaxing the initial state at ρ = %.4f before the first compression", system.name,
                         sim.packing_fraction)
                steps = _relax(sim, system, index, progress, log)
                log.info("%s: initial state relaxed in %d steps (E_kin = %.3e)", system.name, steps,
                         sim.kinetic_energy())
            relaxation_steps = _advance(sim, system, index, target, progress, log)
        except SimulationBlowUp as error:
            cause = blow_up_cause(sim, system, error)
            if not cause:
                raise
            raise SimulationBlowUp(f"{error.reason}; {cause}", step=error.step, particle=error.particle,
                                   rho=error.rho, cause=error.cause) from None
        damping_dt = check_damping_is_integrable(sim, system)
        arrays = snapshot_arrays(sim, relaxation_steps)
        datasets.write_snapshot(paths[index], attrs={**file_attrs, "dem_damping_rate_time_step": damping_dt},
                                **arrays)
        warn_of_overlaps(arrays, system.name, log)
        cpu_seconds = cpu_before + time.process_time() - cpu_start
        save_checkpoint(Path(checkpoint_path), sim, next_index=index + 1, fingerprint=fingerprint, rng=rng,
                        cpu_seconds=cpu_seconds)
        sim.rebuild()  # the resumed run rebuilds here too (Simulation.from_state_dict): identical arrays
        log.info("%s: snapshot %d of %d written, ρ = %.3f (step %d, Z = %.3f, fastest damping rate × Δt = %.2f of "
                 "%.2f)", system.name, index + 1, len(paths), rho, sim.step, 2.0 * sim.contact_count() / sim.n_mobile,
                 damping_dt, stability.GEAR_DAMPING_BOUND)
    return cpu_before + time.process_time() - cpu_start
