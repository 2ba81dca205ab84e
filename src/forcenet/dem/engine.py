"""The DEM engine: state arrays, neighbour list and time stepping around the numba kernels (`_kernels/`).

`Simulation` holds one system (mobile particles, flat or rough walls, Verlet list with tangential history)
and advances it; `protocol.py` drives it through a compression. Everything is in reduced units (length
d_ave, mass m̄, time τ_c) unless a caller passes other numbers (the LAMMPS benchmark does).

The kernels take their arguments grouped in the named tuples of `kernel_arguments.py` (`Motion`, `Bodies`,
`Pairs`, …), views of the Simulation's arrays made afresh for every kernel call, so a rebuild that replaces an
array needs no bookkeeping.

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
from forcenet.dem._kernels.law import (LAW_BETA, LAW_GAMMA_N, LAW_GAMMA_T, LAW_K_N, LAW_K_T, LAW_MU,
                                       LAW_RADIUS_SCALED, LAW_SIZE, LAW_WALL_STIFFNESS)
from forcenet.dem.kernel_arguments import (Bodies, Integrator, Loads, Motion, PairRecord, Pairs, RebuildWatch,
                                           WallRecord, Walls)
from forcenet.dem.packing import WallParticles, packing_fraction
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
class ContactLaw:
    """Contact law (P1 Eq. 1–3): F_n = k_n x^(1+β) − γ_n x^β m_eff v_n ≥ 0,
    F_t = −k_t x^β ξ' − γ_t x^β m_eff v_t capped at μ F_n.

    normal_stiffness k_n [m̄ d_ave^(−β) τ_c^(−2)], tangential_stiffness k_t [same], normal_damping γ_n and
    tangential_damping γ_t [d_ave^(−β) τ_c^(−1)], friction μ, beta β. radius_scaled: multiply every term by
    √R_eff (R_eff = r_i r_j/(r_i + r_j), r_i at a wall) as LAMMPS gran/hertz does — benchmark only.
    wall_stiffness_factor: k_n and k_t of a flat-wall contact over the pair's (1: walls of the particles' material).
    """

    normal_stiffness: float
    tangential_stiffness: float
    normal_damping: float
    tangential_damping: float
    friction: float
    beta: float
    radius_scaled: bool = False
    wall_stiffness_factor: float = 1.0

    def as_array(self) -> np.ndarray:
        """The LAW_* layout (checkpoints)."""
        law = np.zeros(LAW_SIZE)
        law[LAW_K_N] = self.normal_stiffness
        law[LAW_K_T] = self.tangential_stiffness
        law[LAW_GAMMA_N] = self.normal_damping
        law[LAW_GAMMA_T] = self.tangential_damping
        law[LAW_MU] = self.friction
        law[LAW_BETA] = self.beta
        law[LAW_RADIUS_SCALED] = 1.0 if self.radius_scaled else 0.0
        law[LAW_WALL_STIFFNESS] = self.wall_stiffness_factor
        return law

    @classmethod
    def from_array(cls, law: np.ndarray) -> "ContactLaw":
        return cls(normal_stiffness=float(law[LAW_K_N]), tangential_stiffness=float(law[LAW_K_T]),
                   normal_damping=float(law[LAW_GAMMA_N]), tangential_damping=float(law[LAW_GAMMA_T]),
                   friction=float(law[LAW_MU]), beta=float(law[LAW_BETA]),
                   radius_scaled=bool(law[LAW_RADIUS_SCALED]),
                   # a law array of checkpoints older than the wall factor has 7 values: walls of the particles'
                   wall_stiffness_factor=float(law[LAW_WALL_STIFFNESS]) if law.size > LAW_WALL_STIFFNESS else 1.0)


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


_STATE_ARRAYS = ("gear_position", "gear_rotation", "radius", "mass", "inv_mass", "inv_inertia", "particle_id",
                 "box_lo", "box_hi", "wall_state", "wall_anchor", "wall_axis", "wall_sign", "wall_id",
                 "pair_i", "pair_j", "spring", "wall_spring", "law")
_STATE_SCALARS = ("n_mobile", "step", "time_step", "skin", "flat_walls", "escape_margin")


class Simulation:
    """A DEM system: mobile particles (slots 0..n_mobile−1, re-ordered by cell at each rebuild; `particle_id`
    maps slots back to input order) and rough-wall particles (slots n_mobile.., fixed order).

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
        self.n_mobile = n_mobile
        self.time_step = float(time_step)
        self.skin = float(skin)
        self.step = 0
        self.flat_walls = walls == "flat"
        self.gear_position = np.zeros((5, n_total, dim))
        self.gear_rotation = np.zeros((5, n_total, rot))
        self.gear_position[0, :n_mobile] = position
        if velocity is not None:
            self.gear_position[1, :n_mobile] = np.asarray(velocity, dtype=float) * self.time_step
        if angular_velocity is not None:
            self.gear_rotation[1, :n_mobile] = np.asarray(angular_velocity, dtype=float).reshape(n_mobile, rot) * self.time_step
        self.radius = np.zeros(n_total)
        self.radius[:n_mobile] = radius
        self.mass = np.asarray(mass, dtype=float).copy()
        inertia = (0.5 if dim == 2 else 0.4) * self.mass * self.radius[:n_mobile] ** 2  # disk m r²/2, sphere 2 m r²/5
        self.inv_mass = np.zeros(n_total)
        self.inv_mass[:n_mobile] = 1.0 / self.mass
        self.inv_inertia = np.zeros(n_total)
        self.inv_inertia[:n_mobile] = 1.0 / inertia
        self.particle_id = np.arange(n_mobile, dtype=np.int64)
        if walls == "none":
            box_lo, box_hi = np.full(dim, -np.inf), np.full(dim, np.inf)
        self.box_lo = np.asarray(box_lo, dtype=float).copy()
        self.box_hi = np.asarray(box_hi, dtype=float).copy()
        self.wall_state = np.array([0.0, 0.0, np.inf, 0.0])  # shift, speed, shift_max, speed in the last step
        if n_wall:
            self.wall_anchor = np.ascontiguousarray(wall_particles.anchor, dtype=float)
            self.wall_axis = np.asarray(wall_particles.axis, dtype=np.int64)
            self.wall_sign = np.asarray(wall_particles.sign, dtype=float)
            self.wall_id = np.asarray(wall_particles.wall_id, dtype=np.int64)
            self.radius[n_mobile:] = wall_particles.radius
            self.escape_margin = float(wall_particles.radius)
        else:
            self.wall_anchor = np.zeros((0, dim))
            self.wall_axis = np.zeros(0, dtype=np.int64)
            self.wall_sign = np.zeros(0)
            self.wall_id = np.zeros(0, dtype=np.int64)
            self.escape_margin = 0.0
        self.law = law.as_array()
        self.wall_spring = np.zeros((n_mobile, 2 * dim, dim))
        self.pair_i = np.zeros(0, dtype=np.int32)
        self.pair_j = np.zeros(0, dtype=np.int32)
        self.spring = np.zeros((0, dim))
        self._allocate_work()
        self._place_walls()
        self.rebuild()
        self._start_gear_accelerations()

    # --- construction helpers --------------------------------------------------------------------------
    def _allocate_work(self):
        n_total, dim = self.gear_position.shape[1:]
        self.force = np.zeros((n_total, dim))
        self.torque = np.zeros((n_total, self.gear_rotation.shape[2]))
        self.status = np.zeros(2, dtype=np.int64)
        self.force_velocity = np.zeros((n_total, dim))
        self.force_spin = np.zeros((n_total, self.gear_rotation.shape[2]))
        self.reference_position = np.zeros((n_total, dim))
        self.reference_shift = 0.0

    def _place_walls(self):
        if len(self.wall_anchor):
            stepping.place_wall_particles(self.gear_position, self.force_velocity, self.n_mobile,
                                          self._walls(every_entry=True), self.wall_state[0], 0.0)

    def _start_gear_accelerations(self):
        """Gear's second scaled derivative from the forces at t = 0 (springs all zero, velocities as given)."""
        forces = self.evaluate_forces()
        half_dt_sq = 0.5 * self.time_step ** 2
        self.gear_position[2, :self.n_mobile] = half_dt_sq * forces[0][:self.n_mobile] * self.inv_mass[:self.n_mobile, None]
        self.gear_rotation[2, :self.n_mobile] = half_dt_sq * forces[1][:self.n_mobile] * self.inv_inertia[:self.n_mobile, None]

    # --- properties ----------------------------------------------------------------------------------------
    @property
    def dimension(self) -> int:
        return self.gear_position.shape[2]

    @property
    def n_pairs(self) -> int:
        return len(self.pair_i)

    @property
    def wall_shift(self) -> float:
        return float(self.wall_state[0])

    @property
    def time(self) -> float:
        return self.step * self.time_step

    @property
    def walls_lo(self) -> np.ndarray:
        """Current lower wall planes (d,) [d_ave]."""
        return self.box_lo + self.wall_state[0]

    @property
    def walls_hi(self) -> np.ndarray:
        return self.box_hi - self.wall_state[0]

    @property
    def packing_fraction(self) -> float:
        span = self.walls_hi - self.walls_lo
        if not np.all(np.isfinite(span)):
            return 0.0
        return packing_fraction(self.radius[:self.n_mobile], span)

    def set_walls(self, speed: float, shift_max: float = np.inf) -> None:
        """Walls move inward at `speed` [d_ave/τ_c] until their shift reaches shift_max [d_ave]."""
        self.wall_state[1] = speed
        self.wall_state[2] = shift_max

    def _ordered(self, values: np.ndarray) -> np.ndarray:
        """Per-slot values (n_mobile, …) → input particle order."""
        out = np.empty_like(values)
        out[self.particle_id] = values
        return out

    def positions(self) -> np.ndarray:
        """(N, d) [d_ave], input order."""
        return self._ordered(self.gear_position[0, :self.n_mobile])

    def velocities(self) -> np.ndarray:
        return self._ordered(self.gear_position[1, :self.n_mobile] / self.time_step)

    def angular_velocities(self) -> np.ndarray:
        """(N,) in 2D, (N, 3) in 3D [1/τ_c], input order."""
        omega = self._ordered(self.gear_rotation[1, :self.n_mobile] / self.time_step)
        return omega[:, 0] if self.dimension == 2 else omega

    def radii(self) -> np.ndarray:
        return self._ordered(self.radius[:self.n_mobile])

    def kinetic_energy(self) -> float:
        """Σ ½ m v² + ½ I ω² [m̄ d_ave² τ_c⁻²]."""
        n = self.n_mobile
        v = self.gear_position[1, :n] / self.time_step
        w = self.gear_rotation[1, :n] / self.time_step
        return float(0.5 * np.sum(self.mass * np.sum(v * v, axis=1))
                     + 0.5 * np.sum(np.sum(w * w, axis=1) / self.inv_inertia[:n]))

    # --- neighbour list ------------------------------------------------------------------------------------
    def rebuild(self) -> None:
        """Sort the mobile particles by cell, rebuild the Verlet list, carry the springs over."""
        n, n_total = self.n_mobile, self.gear_position.shape[1]
        dim = self.dimension
        position = self.gear_position[0]
        if not np.all(np.isfinite(position)):
            raise FloatingPointError("non-finite position at a neighbour-list rebuild")
        cutoff = 2.0 * float(self.radius.max()) + self.skin
        origin = position.min(axis=0) - 1e-9
        extent = position.max(axis=0) - origin
        cell_size = max(cutoff, float(extent.max()) / MAX_CELLS_PER_AXIS[dim])
        n_cells = np.ones(3, dtype=np.int64)
        n_cells[:dim] = np.maximum(1, np.floor(extent / cell_size).astype(np.int64) + 1)
        cells = neighbours.cell_index(position, n, origin, cell_size, n_cells)
        order = np.argsort(cells, kind="stable")
        new_slot = np.arange(n_total, dtype=np.int64)
        new_slot[order] = np.arange(n, dtype=np.int64)
        for name in ("gear_position", "gear_rotation"):
            array = getattr(self, name)
            array[:, :n] = array[:, order]
        for name in ("radius", "inv_mass", "inv_inertia"):
            array = getattr(self, name)
            array[:n] = array[order]
        self.mass = self.mass[order]
        self.particle_id = self.particle_id[order]
        self.wall_spring = np.ascontiguousarray(self.wall_spring[order])
        pair_i, pair_j = neighbours.build_pair_list(self.gear_position[0], self.radius, n, n_total, self.skin,
                                                    origin, cell_size, n_cells)
        spring = np.zeros((len(pair_i), dim))
        neighbours.transfer_springs(self.pair_i, self.pair_j, self.spring, len(self.pair_i), new_slot,
                                    pair_i, pair_j, spring, n_total)
        # touching pairs first, each group still sorted by i then j: the pair loop's contact test then mispredicts
        # only where a contact opened or closed since the rebuild, not at every pair that is merely near
        # (measured: −12 to −17 % on the 3D pair loop)
        order = np.argsort(~self._touching(pair_i, pair_j), kind="stable")
        self.pair_i, self.pair_j = pair_i[order], pair_j[order]
        self.spring = np.ascontiguousarray(spring[order])
        # the (particle, wall) entries that can touch before the next rebuild: within the spring-release band (the
        # skin) of that wall now, plus the skin (both they and the walls move less than half a skin until then),
        # plus a margin for the step that crosses the rebuild threshold
        self.wall_entry_particle, self.wall_entry_wall = contacts.wall_candidates(
            position, self.radius, n, self.walls_lo, self.walls_hi, WALL_REACH_IN_SKINS * self.skin)
        half_dt_sq = 0.5 * self.time_step ** 2
        self.accel_position = np.repeat(half_dt_sq * self.inv_mass[:, None], dim, axis=1)
        self.accel_rotation = np.repeat(half_dt_sq * self.inv_inertia[:, None], self.gear_rotation.shape[2], axis=1)
        # ½ m and ½ I per component, for the kinetic energy summed in the fused Gear pass (0 for wall particles)
        self.half_mass = np.zeros_like(self.accel_position)
        self.half_mass[:n] = 0.5 * self.mass[:, None]
        self.half_inertia = np.zeros_like(self.accel_rotation)
        self.half_inertia[:n] = 0.5 / self.inv_inertia[:n, None]
        self.reference_position = self.gear_position[0].copy()
        self.reference_shift = float(self.wall_state[0])

    # --- time stepping -------------------------------------------------------------------------------------
    def advance(self, n_steps: int, kinetic_energy: np.ndarray | None = None) -> np.ndarray:
        """Advance n_steps time steps; returns the kinetic energy after each step (n_steps,).

        Raises SimulationBlowUp (step, particle in input order, ρ) on a NaN, an overlap above 20 % of a
        diameter or a particle centre outside the walls.
        """
        if kinetic_energy is None:
            kinetic_energy = np.empty(n_steps)
        done = 0
        while done < n_steps:
            dt = self.time_step
            gear = Integrator(self.gear_position, self.gear_rotation, self.accel_position, self.accel_rotation,
                              self.half_mass, self.half_inertia, dt)
            motion = Motion(self.gear_position[0], self.force_velocity, self.force_spin, 1.0 / dt)
            watch = RebuildWatch(self.reference_position, self.reference_shift, 0.5 * self.skin)
            steps = stepping.advance(gear, motion, Loads(self.force, self.torque), self._bodies(), self._pairs(),
                                     self._walls(), self.law, watch, n_steps - done, kinetic_energy[done:],
                                     self.status)
            done += steps
            self.step += steps
            code = int(self.status[0])
            if code == stepping.STATUS_REBUILD:
                self.rebuild()
            elif code != stepping.STATUS_DONE:
                self._raise_blow_up(code, int(self.status[1]))
        return kinetic_energy[:n_steps]

    def _raise_blow_up(self, code: int, slot: int) -> None:
        particle = int(self.particle_id[slot]) if 0 <= slot < self.n_mobile else -1
        reason = {stepping.STATUS_NOT_FINITE: "non-finite position or velocity",
                  stepping.STATUS_OVERLAP: f"overlap above {contacts.MAX_OVERLAP_FRACTION:.0%} of a diameter",
                  stepping.STATUS_ESCAPED: "particle centre outside the walls"}.get(code, f"status {code}")
        cause = {stepping.STATUS_NOT_FINITE: "not_finite", stepping.STATUS_OVERLAP: "overlap",
                 stepping.STATUS_ESCAPED: "escaped"}.get(code, "")
        if 0 <= slot < self.n_mobile:
            reason += f" (position {self.gear_position[0, slot].tolist()})"
        raise SimulationBlowUp(reason, step=self.step, particle=particle, rho=self.packing_fraction, cause=cause)

    # --- the kernels' arguments ---------------------------------------------------------------------------
    @property
    def contact_law(self) -> ContactLaw:
        return ContactLaw.from_array(self.law)

    def law_values(self) -> tuple[float, ...]:
        """The law as the pair kernels take it: a tuple of the LAW_* values (as `advance` makes it)."""
        return tuple(float(value) for value in self.law)

    def _bodies(self) -> Bodies:
        return Bodies(self.radius, self.inv_mass, self.n_mobile)

    def _pairs(self, spring: np.ndarray | None = None) -> Pairs:
        return Pairs(self.pair_i, self.pair_j, len(self.pair_i), self.spring if spring is None else spring)

    def _walls(self, spring: np.ndarray | None = None, every_entry: bool = False) -> Walls:
        """The walls as the time step sees them: the flat-wall entries that can touch before the next rebuild,
        springs released within one skin; or, with every_entry, every (particle, wall) entry and every spring
        of a wall that does not touch released (for recording)."""
        if every_entry:
            n_walls = 2 * self.dimension
            entry_particle = np.repeat(np.arange(self.n_mobile, dtype=np.int64), n_walls)
            entry_wall = np.tile(np.arange(n_walls, dtype=np.int64), self.n_mobile)
        else:
            entry_particle, entry_wall = self.wall_entry_particle, self.wall_entry_wall
        return Walls(flat=self.flat_walls, box_lo=self.box_lo, box_hi=self.box_hi, state=self.wall_state,
                     spring=self.wall_spring if spring is None else spring, entry_particle=entry_particle,
                     entry_wall=entry_wall, release_band=np.inf if every_entry else self.skin,
                     escape_margin=self.escape_margin, anchor=self.wall_anchor, axis=self.wall_axis,
                     sign=self.wall_sign)

    # --- forces at one instant -----------------------------------------------------------------------------
    def record(self, spring_dt: float = 0.0, spring: np.ndarray | None = None,
               wall_spring: np.ndarray | None = None) -> RecordedForces:
        """Evaluate every contact at the current (corrected) state with the kernels of the time step.

        The springs advance by spring_dt [τ_c] (0: evaluated as they are) in the given arrays spring
        (n_pairs, d) and wall_spring (N, 2d, d), updated in place; by default in copies of the Simulation's,
        which stay unchanged."""
        n, dim = self.n_mobile, self.dimension
        n_pairs = len(self.pair_i)
        loads = Loads(np.zeros_like(self.force), np.zeros_like(self.torque))
        motion = Motion(self.gear_position[0], self.gear_position[1], self.gear_rotation[1], 1.0 / self.time_step)
        wall_record = WallRecord(np.zeros((n, 2 * dim)), np.zeros((n, 2 * dim, dim)))
        if self.flat_walls:
            walls = self._walls(self.wall_spring.copy() if wall_spring is None else wall_spring, every_entry=True)
            contacts.flat_wall_forces(motion, self._bodies(), walls, self.walls_lo, self.walls_hi, self.law,
                                      spring_dt, loads, wall_record)
        pair_record = PairRecord(np.zeros(n_pairs), np.zeros(n_pairs), np.zeros((n_pairs, dim)),
                                 np.zeros((n_pairs, dim)))
        pair_kernel = contacts.pair_forces_2d if dim == 2 else contacts.pair_forces_3d
        pair_kernel(motion, self._bodies(), self._pairs(self.spring.copy() if spring is None else spring),
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
        _, _, overlap, normal, tangential, wall_overlap, wall_force = self.record()
        touching = overlap > 0.0
        slot_i, slot_j = self.pair_i[touching].astype(np.int64), self.pair_j[touching].astype(np.int64)
        f_n, f_t = normal[touching], tangential[touching]
        between = slot_j < n
        # particle–particle contacts, relabelled to input order with i < j (force on i from j)
        ci, cj = self.particle_id[slot_i[between]], self.particle_id[slot_j[between]]
        fn, ft = f_n[between].copy(), f_t[between].copy()
        swap = ci > cj
        ci, cj = np.where(swap, cj, ci), np.where(swap, ci, cj)
        fn[swap] *= -1.0
        ft[swap] *= -1.0
        order = np.lexsort((cj, ci))
        # wall contacts: rough-wall particles (pairs with j ≥ n) and flat walls
        wall_particle = [self.particle_id[slot_i[~between]]]
        wall_which = [self.wall_id[slot_j[~between] - n]]
        wall_f = [f_n[~between] + f_t[~between]]
        if self.flat_walls:
            slot, wall = np.nonzero(wall_overlap > 0.0)
            wall_particle.append(self.particle_id[slot])
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
        mobile = self.pair_j < self.n_mobile
        return int(np.count_nonzero(self._touching(self.pair_i[mobile], self.pair_j[mobile])))

    def _touching(self, pair_i: np.ndarray, pair_j: np.ndarray) -> np.ndarray:
        """Whether each listed pair overlaps now (bool, len(pair_i))."""
        position = self.gear_position[0]
        d = position[pair_i] - position[pair_j]
        reach = self.radius[pair_i] + self.radius[pair_j]
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
        """Every array and scalar that determines the future of the run (for np.savez)."""
        state = {name: getattr(self, name) for name in _STATE_ARRAYS}
        state.update({name: getattr(self, name) for name in _STATE_SCALARS})
        return state

    @classmethod
    def from_state_dict(cls, state) -> "Simulation":
        """Rebuild a Simulation from `state_dict()` output (e.g. an np.load of a checkpoint). The Verlet list is
        rebuilt (carrying the springs), exactly as `rebuild()` does in the uninterrupted run."""
        sim = cls.__new__(cls)
        for name in _STATE_ARRAYS:
            setattr(sim, name, np.array(state[name]))
        if sim.law.size < LAW_SIZE:  # a checkpoint from before the wall factor: walls of the particles' material
            sim.law = ContactLaw.from_array(sim.law).as_array()
        sim.n_mobile = int(state["n_mobile"])
        sim.step = int(state["step"])
        sim.time_step = float(state["time_step"])
        sim.skin = float(state["skin"])
        sim.flat_walls = bool(state["flat_walls"])
        sim.escape_margin = float(state["escape_margin"])
        sim._allocate_work()
        sim.rebuild()
        return sim
