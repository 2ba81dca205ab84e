"""The arguments of the DEM kernels (`forcenet.dem._kernels`), grouped in numba-compatible named tuples.

numba passes a named tuple's fields as separate arguments, so grouping costs nothing inside a kernel; the driver
(`forcenet.dem.engine.Simulation`) makes them afresh for every kernel call, from views of its own arrays.
Everything is in reduced units: length d_ave, mass m̄, time τ_c. N counts every slot (mobile particles first,
then rough-wall particles), d is the dimension, P the number of listed pairs.

numba's on-disk cache refers to these classes by module and name; this file is one of the kernel sources that name
the cache's folder (`forcenet._numba.KERNEL_SOURCES`), so renaming or moving one compiles the kernels afresh.
"""
from __future__ import annotations

from typing import NamedTuple

import numpy as np


class Motion(NamedTuple):
    """What the contact forces see: position (N, d) [d_ave]; velocity (N, d) and spin (N, 1|3), in units of
    1/velocity_scale (Gear scaled derivatives: velocity_scale = 1/Δt)."""
    position: np.ndarray
    velocity: np.ndarray
    spin: np.ndarray
    velocity_scale: float


class Loads(NamedTuple):
    """Force (N, d) and torque (N, 1|3) sums [m̄ d_ave τ_c⁻², m̄ d_ave² τ_c⁻²]."""
    force: np.ndarray
    torque: np.ndarray


class Bodies(NamedTuple):
    """Per slot: radius (N,) [d_ave], inv_mass (N,) [1/m̄] (0 for rough-wall particles); the first n_mobile
    slots are the mobile particles."""
    radius: np.ndarray
    inv_mass: np.ndarray
    n_mobile: int


class Pairs(NamedTuple):
    """The half Verlet list: i, j (int32, i < j) of its first `count` pairs, and their Cundall–Strack springs
    spring (count, d) [d_ave]."""
    i: np.ndarray
    j: np.ndarray
    count: int
    spring: np.ndarray


class Walls(NamedTuple):
    """The walls: flat (bool; else rough-wall particles or none), box_lo, box_hi (d,) the planes at shift 0
    [d_ave], state = [shift, speed, shift_max, speed of the last step]; flat walls: law (LAW_SIZE,) the contact law
    of a wall contact (the pair's, k_n and k_t × its LAW_WALL_STIFFNESS: `engine.wall_law`), spring (N, 2d, d), the
    (particle, wall) entries to visit entry_particle, entry_wall (int64), release_band [d_ave]; escape_margin
    [d_ave]; rough-wall particles: anchor (W, d), axis (W,) int64, sign (W,)."""
    flat: bool
    box_lo: np.ndarray
    box_hi: np.ndarray
    state: np.ndarray
    law: np.ndarray
    spring: np.ndarray
    entry_particle: np.ndarray
    entry_wall: np.ndarray
    release_band: float
    escape_margin: float
    anchor: np.ndarray
    axis: np.ndarray
    sign: np.ndarray


class Integrator(NamedTuple):
    """The Gear state: position (5, N, d), rotation (5, N, 1|3) scaled derivatives; accel_position (N, d),
    accel_rotation (N, 1|3) = Δt²/2 · 1/m, 1/I; half_mass, half_inertia = ½ m, ½ I per component; dt [τ_c]."""
    position: np.ndarray
    rotation: np.ndarray
    accel_position: np.ndarray
    accel_rotation: np.ndarray
    half_mass: np.ndarray
    half_inertia: np.ndarray
    dt: float


class RebuildWatch(NamedTuple):
    """Positions (N, d) and wall shift at the last rebuild [d_ave]; a step that moves anything further than
    half_skin since then stops `advance` for a rebuild."""
    reference_position: np.ndarray
    reference_shift: float
    half_skin: float


class PairRecord(NamedTuple):
    """Filled by the pair kernels when recording: overlap (P,) [d_ave] (0 if apart); for the touching pairs
    normal_force (P,) F_n ≥ 0, normal (P, d) the unit normal n (towards i), tangential (P, d) F_t on i."""
    overlap: np.ndarray
    normal_force: np.ndarray
    normal: np.ndarray
    tangential: np.ndarray


class WallRecord(NamedTuple):
    """Filled by the flat-wall kernel when recording: overlap (N, 2d) [d_ave], force (N, 2d, d) of each wall on
    each particle."""
    overlap: np.ndarray
    force: np.ndarray
