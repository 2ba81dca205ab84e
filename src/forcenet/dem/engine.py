"""The DEM engine: state arrays, neighbour list and time stepping around the numba kernels (`_kernels/`).

`Simulation` holds one system (mobile particles, flat or rough walls, Verlet list with tangential history)
and advances it; `protocol.py` drives it through a compression. Everything is in reduced units (length
d_ave, mass m̄, time τ_c) unless a caller passes other numbers (the LAMMPS benchmark does).

The state is four named structures (`state.py`): `particles`, `contacts`, `walls` and `clock`; checkpoints are
written from them field by field (`state_dict`). What the step derives from them (the flat walls' contact law,
the entries and references of the last rebuild, the force sums) is `StepWork`, never checkpointed. The kernels
take their arguments grouped in the named tuples of `kernel_arguments.py` (`Motion`, `Bodies`, `Pairs`, …),
views of these arrays made afresh for every kernel call, so a rebuild that replaces an array needs no
bookkeeping.

Neighbour list: Verlet list of all pairs closer than r_i + r_j + skin, built through a cell list; it is
rebuilt when a particle (or a wall) has moved more than skin/2 since the last build. At each rebuild the
mobile particles are re-ordered by cell (memory locality) and the tangential springs are carried over to
the new list (`_kernels.neighbours.transfer_springs`), so contacts never lose their history; the pairs touching at
the rebuild are listed first (see `rebuild`).
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import NamedTuple

import numpy as np

from forcenet.dem._kernels import contacts, neighbours, stepping
from forcenet.dem._kernels.law import LAW_SIZE
from forcenet.dem.kernel_arguments import (Bodies, Integrator, Loads, Motion, PairRecord, Pairs, RebuildWatch,
                                           WallRecord, Walls)
from forcenet.dem.packing import WallParticles, packing_fraction
from forcenet.dem.state import (Clock, ContactLaw, ContactState, ParticleState, WallState, checkpoint_arrays,
                                from_checkpoint, wall_law)
from forcenet.errors import ForcenetError

#: default Verlet skin [d_ave]
DEFAULT_SKIN = 0.1
#: most cells along one axis of the cell list (the cells grow when particles spread further)
MAX_CELLS_PER_AXIS = {2: 2048, 3: 160}
#: flat walls: particles within (radius + this × skin) of a wall at a rebuild are checked for wall contacts until
#: the next one (1 skin of spring-release band + 1 skin of relative motion + margin)
WALL_REACH_IN_SKINS = 2.5


class SimulationBlowUp(ForcenetError, RuntimeError):
    """The simulation became unphysical: a NaN, an overlap above 20 % of a diameter, or an escaped particle."""

    def __init__(self, message: str, *, step: int, particle: int, rho: float, cause: str = ""):
        super().__init__(f"DEM blow-up at step {step}, particle {particle}, ρ = {rho:.5f}: {message}")
        self.reason = message
        self.step = step
        self.particle = particle
        self.rho = rho
        self.cause = cause  # "overlap", "not_finite", "escaped" (the step loop's checks), "damping" (the driver's)


@dataclass(frozen=True)
class ContactForces:
    """Forces at one instant, in original particle order.

    contact_i, contact_j (C,) particle–particle contacts with i < j; force_normal, force_tangential (C, d) on
    i from j; wall_contact_particle, wall_contact_wall (W,) (wall id 2·axis + side); wall_contact_force (W, d)
    on the particle; wall_normal_load (2d,) Σ over each wall's contacts of the force component along that wall's
    inward normal [m̄ d_ave τ_c⁻²].
    """

    contact_i: np.ndarray
    contact_j: np.ndarray
    force_normal: np.ndarray
    force_tangential: np.ndarray
    wall_contact_particle: np.ndarray
    wall_contact_wall: np.ndarray
    wall_contact_force: np.ndarray
    wall_normal_load: np.ndarray


class RecordedForces(NamedTuple):
    """`Simulation.record`, in slot order: force (N_slots, d) and torque (N_slots, 1|3) sums; per listed pair
    overlap (P,) [d_ave] (0 if apart), normal and tangential force on i (P, d) (0 if apart); per mobile particle
    and flat wall overlap (N, 2d) and force on the particle (N, 2d, d)."""
    force: np.ndarray
    torque: np.ndarray
    overlap: np.ndarray
    normal: np.ndarray
    tangential: np.ndarray
    wall_overlap: np.ndarray
    wall_force: np.ndarray


@dataclass(eq=False)
class StepWork:
    """What the time step derives from the state and works in; never checkpointed (made from the state at
    construction, refreshed by `Simulation.rebuild` and `Simulation.set_law`).

    wall_law (LAW_SIZE,): the flat walls' contact law (`wall_law`); loads: the force (N, d) and torque (N, 1|3)
    sums; force_velocity (N, d), force_spin (N, 1|3): the velocities the forces see (Gear predicted); status (2,)
    int64: [code, slot] of the last `stepping.advance`. Set at each rebuild: reference_position (N, d) and
    reference_shift, positions and wall shift then [d_ave]; wall_entry_particle, wall_entry_wall (E,) int64, the
    flat-wall entries that can touch before the next rebuild; accel_position (N, d), accel_rotation (N, 1|3) =
    Δt²/2 · 1/m, 1/I per component; half_mass, half_inertia = ½ m, ½ I per component (0 for wall particles)."""
    wall_law: np.ndarray
    loads: Loads
    force_velocity: np.ndarray
    force_spin: np.ndarray
    status: np.ndarray
    reference_position: np.ndarray
    reference_shift: float
    wall_entry_particle: np.ndarray
    wall_entry_wall: np.ndarray
    accel_position: np.ndarray
    accel_rotation: np.ndarray
    half_mass: np.ndarray
    half_inertia: np.ndarray


class Simulation:
    """A DEM system: mobile particles (slots 0..n_mobile−1, re-ordered by cell at each rebuild; `particle_id`
    maps slots back to input order) and rough-wall particles (slots n_mobile.., fixed order).

    The state is `particles`, `contacts`, `walls` and `clock` (`forcenet.dem.state`); `work` is derived from it.

    Parameters
    ----------
    position, velocity : (N, d) [d_ave], [d_ave/τ_c]
    radius, mass : (N,) [d_ave], [m̄]
    law : ContactLaw
    time_step : Δt [τ_c]
    box_lo, box_hi : (d,) wall planes at shift 0 [d_ave]
    walls : "flat" (P1), "rough" (P2, needs wall_particles) or "none" (no confinement)
    angular_velocity : (N,) in 2D or (N, 3) in 3D [1/τ_c], default 0
    skin : Verlet skin [d_ave]
    """

    particles: ParticleState
    contacts: ContactState
    walls: WallState
    clock: Clock
    work: StepWork

    def __init__(self, *, position, radius, mass, law: ContactLaw, time_step: float, box_lo, box_hi,
                 velocity=None, angular_velocity=None, walls: str = "flat",
                 wall_particles: WallParticles | None = None, skin: float = DEFAULT_SKIN):
        position = np.asarray(position, dtype=float)
        n_mobile, dim = position.shape
        if walls not in ("flat", "rough", "none"):
            raise ValueError(f"walls must be 'flat', 'rough' or 'none', got {walls!r}")
        if walls == "rough" and wall_particles is None:
            raise ValueError("rough walls need wall_particles")
        n_wall = len(wall_particles.anchor) if walls == "rough" else 0
        n_total = n_mobile + n_wall
        rot = 1 if dim == 2 else 3
        self.clock = Clock(step=0, time_step=float(time_step))
        gear_position = np.zeros((5, n_total, dim))
        gear_rotation = np.zeros((5, n_total, rot))
        gear_position[0, :n_mobile] = position
        if velocity is not None:
            gear_position[1, :n_mobile] = np.asarray(velocity, dtype=float) * self.clock.time_step
        if angular_velocity is not None:
            gear_rotation[1, :n_mobile] = (np.asarray(angular_velocity, dtype=float).reshape(n_mobile, rot)
                                           * self.clock.time_step)
        all_radius = np.zeros(n_total)
        all_radius[:n_mobile] = radius
        mass = np.asarray(mass, dtype=float).copy()
        inertia = (0.5 if dim == 2 else 0.4) * mass * all_radius[:n_mobile] ** 2  # disk m r²/2, sphere 2 m r²/5
        inv_mass = np.zeros(n_total)
        inv_mass[:n_mobile] = 1.0 / mass
        inv_inertia = np.zeros(n_total)
        inv_inertia[:n_mobile] = 1.0 / inertia
        if walls == "none":
            box_lo, box_hi = np.full(dim, -np.inf), np.full(dim, np.inf)
        if n_wall:
            all_radius[n_mobile:] = wall_particles.radius
            rough = dict(wall_anchor=np.ascontiguousarray(wall_particles.anchor, dtype=float),
                         wall_axis=np.asarray(wall_particles.axis, dtype=np.int64),
                         wall_sign=np.asarray(wall_particles.sign, dtype=float),
                         wall_id=np.asarray(wall_particles.wall_id, dtype=np.int64),
                         escape_margin=float(wall_particles.radius))
        else:
            rough = dict(wall_anchor=np.zeros((0, dim)), wall_axis=np.zeros(0, dtype=np.int64),
                         wall_sign=np.zeros(0), wall_id=np.zeros(0, dtype=np.int64), escape_margin=0.0)
        self.particles = ParticleState(gear_position=gear_position, gear_rotation=gear_rotation, radius=all_radius,
                                       mass=mass, inv_mass=inv_mass, inv_inertia=inv_inertia,
                                       particle_id=np.arange(n_mobile, dtype=np.int64), n_mobile=n_mobile)
        # shift, speed, shift_max, speed in the last step
        self.walls = WallState(box_lo=np.asarray(box_lo, dtype=float).copy(),
                               box_hi=np.asarray(box_hi, dtype=float).copy(),
                               wall_state=np.array([0.0, 0.0, np.inf, 0.0]), flat_walls=walls == "flat",
                               wall_spring=np.zeros((n_mobile, 2 * dim, dim)), **rough)
        self.contacts = ContactState(law=law.as_array(), skin=float(skin), pair_i=np.zeros(0, dtype=np.int32),
                                     pair_j=np.zeros(0, dtype=np.int32), spring=np.zeros((0, dim)))
        self._allocate_work()
        self._place_walls()
        self.rebuild()
        self._start_gear_accelerations()

    # --- construction helpers --------------------------------------------------------------------------
    def _allocate_work(self):
        """`work` for the current state; the fields that `rebuild` sets are left empty."""
        n_total, dim = self.particles.gear_position.shape[1:]
        rot = self.particles.gear_rotation.shape[2]
        empty = np.zeros(0, dtype=np.int64)
        self.work = StepWork(wall_law=wall_law(self.contacts.law),
                             loads=Loads(np.zeros((n_total, dim)), np.zeros((n_total, rot))),
                             force_velocity=np.zeros((n_total, dim)), force_spin=np.zeros((n_total, rot)),
                             status=np.zeros(2, dtype=np.int64), reference_position=np.zeros((n_total, dim)),
                             reference_shift=0.0, wall_entry_particle=empty, wall_entry_wall=empty,
                             accel_position=np.zeros((n_total, dim)), accel_rotation=np.zeros((n_total, rot)),
                             half_mass=np.zeros((n_total, dim)), half_inertia=np.zeros((n_total, rot)))

    def _place_walls(self):
        if len(self.walls.wall_anchor):
            stepping.place_wall_particles(self.particles.gear_position, self.work.force_velocity, self.n_mobile,
                                          self.kernel_walls(every_entry=True), self.walls.wall_state[0], 0.0)

    def _start_gear_accelerations(self):
        """Gear's second scaled derivative from the forces at t = 0 (springs all zero, velocities as given)."""
        forces = self.evaluate_forces()
        half_dt_sq = 0.5 * self.time_step ** 2
        n, particles = self.n_mobile, self.particles
        particles.gear_position[2, :n] = half_dt_sq * forces[0][:n] * particles.inv_mass[:n, None]
        particles.gear_rotation[2, :n] = half_dt_sq * forces[1][:n] * particles.inv_inertia[:n, None]

    # --- properties ----------------------------------------------------------------------------------------
    @property
    def n_mobile(self) -> int:
        return self.particles.n_mobile

    @property
    def step(self) -> int:
        return self.clock.step

    @property
    def time_step(self) -> float:
        """Δt [τ_c]."""
        return self.clock.time_step

    @property
    def dimension(self) -> int:
        return self.particles.gear_position.shape[2]

    @property
    def n_pairs(self) -> int:
        return len(self.contacts.pair_i)

    @property
    def wall_shift(self) -> float:
        return float(self.walls.wall_state[0])

    @property
    def time(self) -> float:
        return self.step * self.time_step

    @property
    def walls_lo(self) -> np.ndarray:
        """Current lower wall planes (d,) [d_ave]."""
        return self.walls.box_lo + self.walls.wall_state[0]

    @property
    def walls_hi(self) -> np.ndarray:
        return self.walls.box_hi - self.walls.wall_state[0]

    @property
    def packing_fraction(self) -> float:
        span = self.walls_hi - self.walls_lo
        if not np.all(np.isfinite(span)):
            return 0.0
        return packing_fraction(self.particles.radius[:self.n_mobile], span)

    def set_walls(self, speed: float, shift_max: float = np.inf) -> None:
        """Walls move inward at `speed` [d_ave/τ_c] until their shift reaches shift_max [d_ave]."""
        self.walls.wall_state[1] = speed
        self.walls.wall_state[2] = shift_max

    def _ordered(self, values: np.ndarray) -> np.ndarray:
        """Per-slot values (n_mobile, …) → input particle order."""
        out = np.empty_like(values)
        out[self.particles.particle_id] = values
        return out

    def positions(self) -> np.ndarray:
        """(N, d) [d_ave], input order."""
        return self._ordered(self.particles.gear_position[0, :self.n_mobile])

    def velocities(self) -> np.ndarray:
        return self._ordered(self.particles.gear_position[1, :self.n_mobile] / self.time_step)

    def angular_velocities(self) -> np.ndarray:
        """(N,) in 2D, (N, 3) in 3D [1/τ_c], input order."""
        omega = self._ordered(self.particles.gear_rotation[1, :self.n_mobile] / self.time_step)
        return omega[:, 0] if self.dimension == 2 else omega

    def radii(self) -> np.ndarray:
        return self._ordered(self.particles.radius[:self.n_mobile])

    def masses(self) -> np.ndarray:
        """(N,) [m̄], input order."""
        return self._ordered(self.particles.mass)

    def kinetic_energy(self) -> float:
        """Σ ½ m v² + ½ I ω² [m̄ d_ave² τ_c⁻²]."""
        n, particles = self.n_mobile, self.particles
        v = particles.gear_position[1, :n] / self.time_step
        w = particles.gear_rotation[1, :n] / self.time_step
        return float(0.5 * np.sum(particles.mass * np.sum(v * v, axis=1))
                     + 0.5 * np.sum(np.sum(w * w, axis=1) / particles.inv_inertia[:n]))

    # --- neighbour list ------------------------------------------------------------------------------------
    def rebuild(self) -> None:
        """Sort the mobile particles by cell, rebuild the Verlet list, carry the springs over."""
        particles, contact_state, walls, work = self.particles, self.contacts, self.walls, self.work
        n, n_total = self.n_mobile, particles.gear_position.shape[1]
        dim = self.dimension
        position = particles.gear_position[0]
        if not np.all(np.isfinite(position)):
            raise FloatingPointError("non-finite position at a neighbour-list rebuild")
        skin = contact_state.skin
        cutoff = 2.0 * float(particles.radius.max()) + skin
        origin = position.min(axis=0) - 1e-9
        extent = position.max(axis=0) - origin
        cell_size = max(cutoff, float(extent.max()) / MAX_CELLS_PER_AXIS[dim])
        n_cells = np.ones(3, dtype=np.int64)
        n_cells[:dim] = np.maximum(1, np.floor(extent / cell_size).astype(np.int64) + 1)
        cells = neighbours.cell_index(position, n, origin, cell_size, n_cells)
        order = np.argsort(cells, kind="stable")
        new_slot = np.arange(n_total, dtype=np.int64)
        new_slot[order] = np.arange(n, dtype=np.int64)
        for array in (particles.gear_position, particles.gear_rotation):
            array[:, :n] = array[:, order]
        for array in (particles.radius, particles.inv_mass, particles.inv_inertia):
            array[:n] = array[order]
        particles.mass = particles.mass[order]
        particles.particle_id = particles.particle_id[order]
        walls.wall_spring = np.ascontiguousarray(walls.wall_spring[order])
        pair_i, pair_j = neighbours.build_pair_list(particles.gear_position[0], particles.radius, n, n_total, skin,
                                                    origin, cell_size, n_cells)
        spring = np.zeros((len(pair_i), dim))
        neighbours.transfer_springs(contact_state.pair_i, contact_state.pair_j, contact_state.spring,
                                    len(contact_state.pair_i), new_slot, pair_i, pair_j, spring, n_total)
        # touching pairs first, each group still sorted by i then j: the pair loop's contact test then mispredicts
        # only where a contact opened or closed since the rebuild, not at every pair that is merely near
        # (measured: −12 to −17 % on the 3D pair loop)
        order = np.argsort(~self._touching(pair_i, pair_j), kind="stable")
        contact_state.pair_i, contact_state.pair_j = pair_i[order], pair_j[order]
        contact_state.spring = np.ascontiguousarray(spring[order])
        # the (particle, wall) entries that can touch before the next rebuild: within the spring-release band (the
        # skin) of that wall now, plus the skin (both they and the walls move less than half a skin until then),
        # plus a margin for the step that crosses the rebuild threshold
        work.wall_entry_particle, work.wall_entry_wall = contacts.wall_candidates(
            position, particles.radius, n, self.walls_lo, self.walls_hi, WALL_REACH_IN_SKINS * skin)
        half_dt_sq = 0.5 * self.time_step ** 2
        work.accel_position = np.repeat(half_dt_sq * particles.inv_mass[:, None], dim, axis=1)
        work.accel_rotation = np.repeat(half_dt_sq * particles.inv_inertia[:, None], particles.gear_rotation.shape[2],
                                        axis=1)
        # ½ m and ½ I per component, for the kinetic energy summed in the fused Gear pass (0 for wall particles)
        work.half_mass = np.zeros_like(work.accel_position)
        work.half_mass[:n] = 0.5 * particles.mass[:, None]
        work.half_inertia = np.zeros_like(work.accel_rotation)
        work.half_inertia[:n] = 0.5 / particles.inv_inertia[:n, None]
        work.reference_position = particles.gear_position[0].copy()
        work.reference_shift = float(walls.wall_state[0])

    # --- time stepping -------------------------------------------------------------------------------------
    def advance(self, n_steps: int, kinetic_energy: np.ndarray | None = None) -> np.ndarray:
        """Advance n_steps time steps; returns the kinetic energy after each step (n_steps,).

        Raises SimulationBlowUp (step, particle in input order, ρ) on a NaN, an overlap above 20 % of a
        diameter or a particle centre outside the walls.
        """
        if kinetic_energy is None:
            kinetic_energy = np.empty(n_steps)
        particles, work = self.particles, self.work
        done = 0
        while done < n_steps:
            dt = self.clock.time_step
            gear = Integrator(particles.gear_position, particles.gear_rotation, work.accel_position,
                              work.accel_rotation, work.half_mass, work.half_inertia, dt)
            motion = Motion(particles.gear_position[0], work.force_velocity, work.force_spin, 1.0 / dt)
            watch = RebuildWatch(work.reference_position, work.reference_shift, 0.5 * self.contacts.skin)
            steps = stepping.advance(gear, motion, work.loads, self.kernel_bodies(), self.kernel_pairs(),
                                     self.kernel_walls(), self.contacts.law, watch, n_steps - done,
                                     kinetic_energy[done:], work.status)
            done += steps
            self.clock.step += steps
            code = int(work.status[0])
            if code == stepping.STATUS_REBUILD:
                self.rebuild()
            elif code != stepping.STATUS_DONE:
                self._raise_blow_up(code, int(work.status[1]))
        return kinetic_energy[:n_steps]

    def _raise_blow_up(self, code: int, slot: int) -> None:
        particle = int(self.particles.particle_id[slot]) if 0 <= slot < self.n_mobile else -1
        reason = {stepping.STATUS_NOT_FINITE: "non-finite position or velocity",
                  stepping.STATUS_OVERLAP: f"overlap above {contacts.MAX_OVERLAP_FRACTION:.0%} of a diameter",
                  stepping.STATUS_ESCAPED: "particle centre outside the walls"}.get(code, f"status {code}")
        cause = {stepping.STATUS_NOT_FINITE: "not_finite", stepping.STATUS_OVERLAP: "overlap",
                 stepping.STATUS_ESCAPED: "escaped"}.get(code, "")
        if 0 <= slot < self.n_mobile:
            reason += f" (position {self.particles.gear_position[0, slot].tolist()})"
        raise SimulationBlowUp(reason, step=self.step, particle=particle, rho=self.packing_fraction, cause=cause)

    # --- the contact law and the kernels' arguments ----------------------------------------------------------
    @property
    def contact_law(self) -> ContactLaw:
        return ContactLaw.from_array(self.contacts.law)

    def set_law(self, law: ContactLaw) -> None:
        """Continue under another contact law (the flat walls' law follows)."""
        self.contacts.law = law.as_array()
        self.work.wall_law = wall_law(self.contacts.law)

    def law_values(self) -> tuple[float, ...]:
        """The law as the pair kernels take it: a tuple of the LAW_* values (as `advance` makes it)."""
        return tuple(float(value) for value in self.contacts.law)

    def kernel_bodies(self) -> Bodies:
        return Bodies(self.particles.radius, self.particles.inv_mass, self.n_mobile)

    def kernel_pairs(self, spring: np.ndarray | None = None) -> Pairs:
        """The Verlet list with its springs, or with the given spring array (P, d) in their place."""
        contact_state = self.contacts
        return Pairs(contact_state.pair_i, contact_state.pair_j, len(contact_state.pair_i),
                     contact_state.spring if spring is None else spring)

    def kernel_walls(self, spring: np.ndarray | None = None, every_entry: bool = False) -> Walls:
        """The walls as the time step sees them: the flat-wall entries that can touch before the next rebuild,
        springs released within one skin; or, with every_entry, every (particle, wall) entry and every spring
        of a wall that does not touch released (for recording). spring (N, 2d, d): in place of the walls'."""
        walls = self.walls
        if every_entry:
            n_walls = 2 * self.dimension
            entry_particle = np.repeat(np.arange(self.n_mobile, dtype=np.int64), n_walls)
            entry_wall = np.tile(np.arange(n_walls, dtype=np.int64), self.n_mobile)
        else:
            entry_particle, entry_wall = self.work.wall_entry_particle, self.work.wall_entry_wall
        return Walls(flat=walls.flat_walls, box_lo=walls.box_lo, box_hi=walls.box_hi, state=walls.wall_state,
                     law=self.work.wall_law, spring=walls.wall_spring if spring is None else spring,
                     entry_particle=entry_particle, entry_wall=entry_wall,
                     release_band=np.inf if every_entry else self.contacts.skin, escape_margin=walls.escape_margin,
                     anchor=walls.wall_anchor, axis=walls.wall_axis, sign=walls.wall_sign)

    # --- forces at one instant -----------------------------------------------------------------------------
    def record(self, spring_dt: float = 0.0, spring: np.ndarray | None = None,
               wall_spring: np.ndarray | None = None) -> RecordedForces:
        """Evaluate every contact at the current (corrected) state with the kernels of the time step.

        The springs advance by spring_dt [τ_c] (0: evaluated as they are) in the given arrays spring
        (n_pairs, d) and wall_spring (N, 2d, d), updated in place; by default in copies of the Simulation's,
        which stay unchanged."""
        n, dim = self.n_mobile, self.dimension
        n_pairs = self.n_pairs
        gear_position, gear_rotation = self.particles.gear_position, self.particles.gear_rotation
        loads = Loads(np.zeros_like(self.work.loads.force), np.zeros_like(self.work.loads.torque))
        motion = Motion(gear_position[0], gear_position[1], gear_rotation[1], 1.0 / self.time_step)
        wall_record = WallRecord(np.zeros((n, 2 * dim)), np.zeros((n, 2 * dim, dim)))
        if self.walls.flat_walls:
            walls = self.kernel_walls(self.walls.wall_spring.copy() if wall_spring is None else wall_spring,
                                      every_entry=True)
            contacts.flat_wall_forces(motion, self.kernel_bodies(), walls, self.walls_lo, self.walls_hi,
                                      spring_dt, loads, wall_record)
        pair_record = PairRecord(np.zeros(n_pairs), np.zeros(n_pairs), np.zeros((n_pairs, dim)),
                                 np.zeros((n_pairs, dim)))
        pair_kernel = contacts.pair_forces_2d if dim == 2 else contacts.pair_forces_3d
        pair_kernel(motion, self.kernel_bodies(), self.kernel_pairs(self.contacts.spring.copy() if spring is None
                                                                   else spring),
                    self.law_values(), spring_dt, loads, pair_record)
        return RecordedForces(force=loads.force, torque=loads.torque, overlap=pair_record.overlap,
                              normal=pair_record.normal_force[:, None] * pair_record.normal,
                              tangential=pair_record.tangential, wall_overlap=wall_record.overlap,
                              wall_force=wall_record.force)

    def evaluate_forces(self):
        """Total force (N_slots, d) and torque (N_slots, 1|3) at the current state, springs unchanged."""
        recorded = self.record()
        return recorded.force, recorded.torque

    def contact_forces(self) -> ContactForces:
        """Every contact (overlap > 0) and its force, in input particle order (see `ContactForces`)."""
        n, dim = self.n_mobile, self.dimension
        particle_id, wall_id = self.particles.particle_id, self.walls.wall_id
        _, _, overlap, normal, tangential, wall_overlap, wall_force = self.record()
        touching = overlap > 0.0
        slot_i = self.contacts.pair_i[touching].astype(np.int64)
        slot_j = self.contacts.pair_j[touching].astype(np.int64)
        f_n, f_t = normal[touching], tangential[touching]
        between = slot_j < n
        # particle–particle contacts, relabelled to input order with i < j (force on i from j)
        ci, cj = particle_id[slot_i[between]], particle_id[slot_j[between]]
        fn, ft = f_n[between].copy(), f_t[between].copy()
        swap = ci > cj
        ci, cj = np.where(swap, cj, ci), np.where(swap, ci, cj)
        fn[swap] *= -1.0
        ft[swap] *= -1.0
        order = np.lexsort((cj, ci))
        # wall contacts: rough-wall particles (pairs with j ≥ n) and flat walls
        wall_particle = [particle_id[slot_i[~between]]]
        wall_which = [wall_id[slot_j[~between] - n]]
        wall_f = [f_n[~between] + f_t[~between]]
        if self.walls.flat_walls:
            slot, wall = np.nonzero(wall_overlap > 0.0)
            wall_particle.append(particle_id[slot])
            wall_which.append(wall)
            wall_f.append(wall_force[slot, wall])
        wp = np.concatenate(wall_particle).astype(np.int64)
        ww = np.concatenate(wall_which).astype(np.int64)
        wf = np.concatenate(wall_f).reshape(-1, dim)
        wall_order = np.lexsort((ww, wp))
        wp, ww, wf = wp[wall_order], ww[wall_order], wf[wall_order]
        load = np.zeros(2 * dim)
        inward = np.where(ww % 2 == 0, 1.0, -1.0)
        np.add.at(load, ww, wf[np.arange(len(ww)), ww // 2] * inward)
        return ContactForces(contact_i=ci[order], contact_j=cj[order], force_normal=fn[order],
                             force_tangential=ft[order], wall_contact_particle=wp, wall_contact_wall=ww,
                             wall_contact_force=wf, wall_normal_load=load)

    def contact_count(self) -> int:
        """Number of touching particle–particle pairs (cheap; for progress logs)."""
        mobile = self.contacts.pair_j < self.n_mobile
        return int(np.count_nonzero(self._touching(self.contacts.pair_i[mobile], self.contacts.pair_j[mobile])))

    def _touching(self, pair_i: np.ndarray, pair_j: np.ndarray) -> np.ndarray:
        """Whether each listed pair overlaps now (bool, len(pair_i))."""
        position, radius = self.particles.gear_position[0], self.particles.radius
        d = position[pair_i] - position[pair_j]
        reach = radius[pair_i] + radius[pair_j]
        return np.einsum("pk,pk->p", d, d) < reach * reach

    def wall_pressure(self, load: np.ndarray) -> float:
        """Mean normal stress on the walls: mean over the 2d walls of (normal load / wall length or area)
        [m̄ d_ave^(1−d) τ_c⁻² … i.e. per unit length in 2D, per unit area in 3D]."""
        span = self.walls_hi - self.walls_lo
        dim = self.dimension
        face = np.array([np.prod(np.delete(span, k)) for k in range(dim) for _ in range(2)])
        return float(np.mean(load / face))

    # --- checkpoints -------------------------------------------------------------------------------------
    def state_dict(self) -> dict:
        """Every field of the state structures, by name (for np.savez): what determines the future of the run."""
        return checkpoint_arrays(self.particles, self.contacts, self.walls, self.clock)

    @classmethod
    def from_state_dict(cls, state) -> "Simulation":
        """Rebuild a Simulation from `state_dict()` output (e.g. an np.load of a checkpoint). The Verlet list is
        rebuilt (carrying the springs), exactly as `rebuild()` does in the uninterrupted run."""
        sim = cls.__new__(cls)
        sim.particles = from_checkpoint(ParticleState, state)
        sim.contacts = from_checkpoint(ContactState, state)
        sim.walls = from_checkpoint(WallState, state)
        sim.clock = from_checkpoint(Clock, state)
        if sim.contacts.law.size < LAW_SIZE:  # from before the wall factor: walls of the particles' material
            sim.contacts.law = ContactLaw.from_array(sim.contacts.law).as_array()
        sim._allocate_work()
        sim.rebuild()
        return sim
