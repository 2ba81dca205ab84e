"""Contact forces: the particle pairs of the Verlet list (`pair_forces_2d`, `pair_forces_3d`) and the flat walls
(`flat_wall_forces`), each written once and used both by the time step (`stepping.advance`, record = None) and to
record the forces of a snapshot (record = a `PairRecord` / `WallRecord`), with the contact law of `law.py`
inlined. numba compiles one specialization per kind of record; the time step's has no recording code at all, so
both compute the same forces to the last bit (`tests/test_dem_stepping.py`). For that, the recording stores only
values the step computes anyway (F_n and n, not the product F_n n: a second use of that multiplication would keep
LLVM from fusing it into F_n n + F_t, and the two specializations would round differently).

Arguments are named tuples of `forcenet.dem.kernel_arguments` (fields in reduced units: d_ave, m̄, τ_c):

* motion (`Motion`): position (N, d), velocity (N, d) and spin (N, 1|3), the latter two multiplied by
  velocity_scale (1/Δt for Gear scaled derivatives);
* bodies (`Bodies`): radius (N,), inv_mass (N,) (0 for rough-wall particles), n_mobile;
* pairs (`Pairs`): the half Verlet list i, j (int32, i < j, i mobile), count, and spring (≥ count, d), the
  Cundall–Strack springs, updated in place (zeroed when a contact opens);
* walls (`Walls`): flat walls' contact law law (the LAW_* array, k_n and k_t already scaled for walls of their
  own material), springs spring (N, 2d, d), the (particle, wall) entries entry_particle, entry_wall to visit,
  release_band, and state (shift, speed, shift_max, speed of the last step);
* loads (`Loads`): force (N, d) and torque (N, 1|3), accumulated;
* law: the LAW_* values of `law.py`, as a tuple for the pair loops (`advance` makes it once per call; its values
  are then arguments, held in registers across the loop); the flat walls read theirs per contact from the float64
  array walls.law. Each loop takes the law as it always has: under NJIT_DEM's contraction LLVM's choice of which
  multiply-adds to fuse depends on it, and so the trajectories stay bit-identical to those of earlier versions.

A pair (i, j) has i < j; n = (r_i − r_j)/|r_i − r_j| points from j to i; forces are "on i from j". Particles
with index ≥ n_mobile are rough-wall particles (infinite mass: m_eff = m_i).
"""
import math

import numba
import numpy as np

from forcenet._numba import NJIT_DEM
from forcenet.dem._kernels.law import LAW_RADIUS_SCALED, contact_2d, contact_3d

#: blow-up threshold: overlap / diameter (smaller diameter of the pair)
MAX_OVERLAP_FRACTION = 0.2

#: unsigned offsets of the flat pair loops
U1 = np.uint64(1)
U2 = np.uint64(2)
U3 = np.uint64(3)

# The pair loops read flat views of the per-particle arrays at unsigned offsets, which drops the stride and
# negative-index arithmetic from every access (−5 to −9 % on the pair loop), and form the per-pair constants of
# `pair_constants` from per-particle values (a per-pair table costs more memory traffic than the division and
# square root: measured 4 % of the whole 3D step). A touching pair costs ~100 cycles, most of it the latency of
# one chain (position → √, 1/d → n → slip → spring → Coulomb test); the engine lists the pairs that touch at a
# rebuild first, so the contact test mispredicts only where a contact opened or closed since then. Measured and
# dropped: accumulating particle i's force over its row in registers (−10 % in 3D), computing every listed pair
# without the contact branch, compacting the touching pairs and computing them two at a time, and a blocked
# pair loop (gather the touching pairs, vectorised forces, scatter): all were slower inside the step, as was
# an interleaved per-particle layout (no change).


@numba.njit(**NJIT_DEM)
def pair_forces_2d(motion, bodies, pairs, law, spring_dt, loads, record):
    """Add the particle–particle contact forces of the Verlet list to loads.force and loads.torque (2D).

    record: None, or a `PairRecord` whose overlap (≥ count,) receives every pair's overlap (0 if apart) and, for
    the touching pairs, normal_force (≥ count,) F_n ≥ 0, normal (≥ count, 2) the unit normal n and tangential
    (≥ count, 2) F_t on i. Returns (largest excess of an overlap over the blow-up threshold, its pair; −inf and
    −1 when no pair touches): see `worst_pair_fraction`.
    """
    worst_excess = -np.inf
    worst_pair = -1
    x = motion.position.reshape(-1)  # flat views indexed by unsigned offsets: no stride or negative-index arithmetic
    v = motion.velocity.reshape(-1)
    w = motion.spin.reshape(-1)
    f = loads.force.reshape(-1)
    t = loads.torque.reshape(-1)
    spring = pairs.spring.reshape(-1)
    pair_i = pairs.i  # every field read once, outside the loop
    pair_j = pairs.j
    radius = bodies.radius
    inv_mass = bodies.inv_mass
    velocity_scale = motion.velocity_scale
    radius_scaled = law[LAW_RADIUS_SCALED] != 0.0
    for p in range(pairs.count):
        i = np.uint32(pair_i[p])
        j = np.uint32(pair_j[p])
        i0 = U2 * i
        i1 = i0 + U1
        j0 = U2 * j
        j1 = j0 + U1
        dx = x[i0] - x[j0]
        dy = x[i1] - x[j1]
        r_i = radius[i]
        r_j = radius[j]
        contact_distance = r_i + r_j
        distance_sq = dx * dx + dy * dy
        if not distance_sq < contact_distance * contact_distance:
            spring[2 * p] = 0.0  # the contact opened (or never formed): the spring is removed
            spring[2 * p + 1] = 0.0
            if record is not None:
                record.overlap[p] = 0.0
            continue
        distance = math.sqrt(distance_sq)
        overlap = contact_distance - distance  # P1: x = d_ij − r_ij
        inv_distance = 1.0 / distance
        nx = dx * inv_distance
        ny = dy * inv_distance
        excess = overlap - MAX_OVERLAP_FRACTION * 2.0 * min(r_i, r_j)  # blow-up check, no division
        if excess > worst_excess:
            worst_excess = excess
            worst_pair = p
        lever_i = r_i - 0.5 * overlap  # centre to contact point
        lever_j = r_j - 0.5 * overlap
        vx = (v[i0] - v[j0]) * velocity_scale
        vy = (v[i1] - v[j1]) * velocity_scale
        v_normal = vx * nx + vy * ny
        spin = (lever_i * w[i] + lever_j * w[j]) * velocity_scale
        # slip of the contact points: v_ij − v_n n − (a_i ω_i + a_j ω_j) ẑ × n
        slip_x = vx - v_normal * nx + spin * ny
        slip_y = vy - v_normal * ny - spin * nx
        m_eff = 1.0 / (inv_mass[i] + inv_mass[j])  # `pair_constants`, formed here: cheaper than a per-pair table
        scale = math.sqrt(r_i * r_j / (r_i + r_j)) if radius_scaled else 1.0
        f_n, f_tx, f_ty, xi_x, xi_y = contact_2d(law, nx, ny, overlap, v_normal, slip_x, slip_y, m_eff, scale,
                                                 spring[2 * p], spring[2 * p + 1], spring_dt)
        spring[2 * p] = xi_x
        spring[2 * p + 1] = xi_y
        fx = f_n * nx + f_tx
        fy = f_n * ny + f_ty
        f[i0] += fx
        f[i1] += fy
        f[j0] -= fx
        f[j1] -= fy
        n_cross_ft = nx * f_ty - ny * f_tx  # torques: τ_i = −a_i n × F_t, τ_j = −a_j n × F_t
        t[i] -= lever_i * n_cross_ft
        t[j] -= lever_j * n_cross_ft
        if record is not None:  # only values the step computes anyway: the recorded forces are the step's
            record.overlap[p] = overlap
            record.normal_force[p] = f_n
            record.normal[p, 0] = nx
            record.normal[p, 1] = ny
            record.tangential[p, 0] = f_tx
            record.tangential[p, 1] = f_ty
    return worst_excess, worst_pair


@numba.njit(**NJIT_DEM)
def pair_forces_3d(motion, bodies, pairs, law, spring_dt, loads, record):
    """3D version of `pair_forces_2d`: position, velocity, spin, force, torque, spring and the recorded normal
    and tangential (·, 3)."""
    worst_excess = -np.inf
    worst_pair = -1
    x = motion.position.reshape(-1)  # flat views indexed by unsigned offsets, as in the 2D loop
    v = motion.velocity.reshape(-1)
    w = motion.spin.reshape(-1)
    f = loads.force.reshape(-1)
    t = loads.torque.reshape(-1)
    spring = pairs.spring.reshape(-1)
    pair_i = pairs.i  # every field read once, outside the loop
    pair_j = pairs.j
    radius = bodies.radius
    inv_mass = bodies.inv_mass
    velocity_scale = motion.velocity_scale
    radius_scaled = law[LAW_RADIUS_SCALED] != 0.0
    for p in range(pairs.count):
        i = np.uint32(pair_i[p])
        j = np.uint32(pair_j[p])
        i0 = U3 * i
        i1 = i0 + U1
        i2 = i0 + U2
        j0 = U3 * j
        j1 = j0 + U1
        j2 = j0 + U2
        dx = x[i0] - x[j0]
        dy = x[i1] - x[j1]
        dz = x[i2] - x[j2]
        r_i = radius[i]
        r_j = radius[j]
        contact_distance = r_i + r_j
        distance_sq = dx * dx + dy * dy + dz * dz
        if not distance_sq < contact_distance * contact_distance:
            spring[3 * p] = 0.0
            spring[3 * p + 1] = 0.0
            spring[3 * p + 2] = 0.0
            if record is not None:
                record.overlap[p] = 0.0
            continue
        distance = math.sqrt(distance_sq)
        overlap = contact_distance - distance
        inv_distance = 1.0 / distance
        nx = dx * inv_distance
        ny = dy * inv_distance
        nz = dz * inv_distance
        excess = overlap - MAX_OVERLAP_FRACTION * 2.0 * min(r_i, r_j)
        if excess > worst_excess:
            worst_excess = excess
            worst_pair = p
        lever_i = r_i - 0.5 * overlap
        lever_j = r_j - 0.5 * overlap
        vx = (v[i0] - v[j0]) * velocity_scale
        vy = (v[i1] - v[j1]) * velocity_scale
        vz = (v[i2] - v[j2]) * velocity_scale
        v_normal = vx * nx + vy * ny + vz * nz
        wx = (lever_i * w[i0] + lever_j * w[j0]) * velocity_scale
        wy = (lever_i * w[i1] + lever_j * w[j1]) * velocity_scale
        wz = (lever_i * w[i2] + lever_j * w[j2]) * velocity_scale
        # slip: v_ij − v_n n − (a_i ω_i + a_j ω_j) × n
        slip_x = vx - v_normal * nx - (wy * nz - wz * ny)
        slip_y = vy - v_normal * ny - (wz * nx - wx * nz)
        slip_z = vz - v_normal * nz - (wx * ny - wy * nx)
        m_eff = 1.0 / (inv_mass[i] + inv_mass[j])
        scale = math.sqrt(r_i * r_j / (r_i + r_j)) if radius_scaled else 1.0
        s = 3 * p
        f_n, f_tx, f_ty, f_tz, xi_x, xi_y, xi_z = contact_3d(
            law, nx, ny, nz, overlap, v_normal, slip_x, slip_y, slip_z, m_eff, scale,
            spring[s], spring[s + 1], spring[s + 2], spring_dt)
        spring[s] = xi_x
        spring[s + 1] = xi_y
        spring[s + 2] = xi_z
        fx = f_n * nx + f_tx
        fy = f_n * ny + f_ty
        fz = f_n * nz + f_tz
        f[i0] += fx
        f[i1] += fy
        f[i2] += fz
        f[j0] -= fx
        f[j1] -= fy
        f[j2] -= fz
        cx = ny * f_tz - nz * f_ty  # n × F_t
        cy = nz * f_tx - nx * f_tz
        cz = nx * f_ty - ny * f_tx
        t[i0] -= lever_i * cx
        t[i1] -= lever_i * cy
        t[i2] -= lever_i * cz
        t[j0] -= lever_j * cx
        t[j1] -= lever_j * cy
        t[j2] -= lever_j * cz
        if record is not None:
            record.overlap[p] = overlap
            record.normal_force[p] = f_n
            record.normal[p, 0] = nx
            record.normal[p, 1] = ny
            record.normal[p, 2] = nz
            record.tangential[p, 0] = f_tx
            record.tangential[p, 1] = f_ty
            record.tangential[p, 2] = f_tz
    return worst_excess, worst_pair


@numba.njit(**NJIT_DEM)
def worst_pair_fraction(worst_excess, worst_pair, pairs, radius):
    """Overlap / smaller diameter of the pair with the largest excess over the blow-up threshold (0 if none)."""
    if worst_pair < 0:
        return 0.0
    diameter = 2.0 * min(radius[pairs.i[worst_pair]], radius[pairs.j[worst_pair]])
    return MAX_OVERLAP_FRACTION + worst_excess / diameter


@numba.njit(**NJIT_DEM)
def pair_constants(pair_i, pair_j, radius, inv_mass, radius_scaled):
    """Per-pair constants, as the pair loops form them: reduced mass 1/(1/m_i + 1/m_j) (m_i against a wall
    particle) and the LAMMPS-convention factor √(r_i r_j/(r_i + r_j)) (1 unless radius_scaled). (n_pairs,) each."""
    n = pair_i.shape[0]
    pair_mass = np.empty(n)
    pair_scale = np.ones(n)
    for p in range(n):
        i = pair_i[p]
        j = pair_j[p]
        pair_mass[p] = 1.0 / (inv_mass[i] + inv_mass[j])
        if radius_scaled:
            pair_scale[p] = math.sqrt(radius[i] * radius[j] / (radius[i] + radius[j]))
    return pair_mass, pair_scale


# --- flat walls ------------------------------------------------------------------------------------------------

@numba.njit(**NJIT_DEM)
def flat_wall_forces(motion, bodies, walls, lo, hi, spring_dt, loads, record):
    """Add the forces of the 2d flat walls (P1 §2: the law walls.law, the pair's with k_n and k_t scaled for walls
    of their own material; overlap x = d_i/2 − distance to the wall) for the
    (particle, wall) entries walls.entry_particle, walls.entry_wall (particle-major); the others are left alone.

    Wall w = 2·axis + side (side 0: at lo[axis], normal +e_axis; side 1: at hi[axis], normal −e_axis), moving
    inward at walls.state[3] [d_ave/τ_c] (its velocity enters the damping and the slip). The wall is the partner
    j with infinite mass and radius: m_eff = m_i, R_eff = r_i. walls.spring (N, 2d, d) holds one Cundall–Strack
    spring per particle and wall; a spring is reset to zero when its particle is apart from the wall by less than
    walls.release_band [d_ave] (a contact that opens in a step is within the band; the Verlet skin is a safe
    value; inf resets every spring). record: None, or a `WallRecord` whose overlap (N, 2d) and force (N, 2d, d)
    (the total force of each wall on each particle) receive the visited entries.
    Returns (largest overlap / diameter, particle index or −1).
    """
    position = motion.position
    velocity = motion.velocity
    angular_velocity = motion.spin
    velocity_scale = motion.velocity_scale
    radius = bodies.radius
    inv_mass = bodies.inv_mass
    wall_spring = walls.spring
    entry_particle = walls.entry_particle
    entry_wall = walls.entry_wall
    wall_speed = walls.state[3]
    release_band = walls.release_band
    force = loads.force
    torque = loads.torque
    dim = position.shape[1]
    wall_law = walls.law
    radius_scaled = wall_law[LAW_RADIUS_SCALED] != 0.0
    worst_fraction = 0.0
    worst_particle = -1
    for q in range(entry_particle.shape[0]):
        i = entry_particle[q]
        wall = entry_wall[q]
        axis = wall // 2
        if wall % 2 == 0:
            distance = position[i, axis] - lo[axis]
            sign = 1.0
        else:
            distance = hi[axis] - position[i, axis]
            sign = -1.0
        overlap = radius[i] - distance  # P1: x = 0.5 d_i − r_i
        if not overlap > 0.0:
            if record is not None:
                record.overlap[i, wall] = 0.0
            if overlap > -release_band:  # a contact can only have opened within the band
                for k in range(dim):
                    wall_spring[i, wall, k] = 0.0
            continue
        fraction = overlap / (2.0 * radius[i])
        if fraction > worst_fraction:
            worst_fraction = fraction
            worst_particle = i
        m_eff = 1.0 / inv_mass[i]
        scale = math.sqrt(radius[i]) if radius_scaled else 1.0
        lever = distance
        # the wall moves along its normal n = sign e_axis at wall_speed
        if dim == 2:
            nx = sign if axis == 0 else 0.0
            ny = sign if axis == 1 else 0.0
            vx = velocity[i, 0] * velocity_scale - nx * wall_speed
            vy = velocity[i, 1] * velocity_scale - ny * wall_speed
            v_normal = vx * nx + vy * ny
            spin = lever * angular_velocity[i, 0] * velocity_scale
            slip_x = vx - v_normal * nx + spin * ny
            slip_y = vy - v_normal * ny - spin * nx
            f_n, f_tx, f_ty, xi_x, xi_y = contact_2d(
                wall_law, nx, ny, overlap, v_normal, slip_x, slip_y, m_eff, scale,
                wall_spring[i, wall, 0], wall_spring[i, wall, 1], spring_dt)
            wall_spring[i, wall, 0] = xi_x
            wall_spring[i, wall, 1] = xi_y
            fx = f_n * nx + f_tx
            fy = f_n * ny + f_ty
            force[i, 0] += fx
            force[i, 1] += fy
            torque[i, 0] -= lever * (nx * f_ty - ny * f_tx)
            if record is not None:
                record.force[i, wall, 0] = fx
                record.force[i, wall, 1] = fy
        else:
            nx = sign if axis == 0 else 0.0
            ny = sign if axis == 1 else 0.0
            nz = sign if axis == 2 else 0.0
            vx = velocity[i, 0] * velocity_scale - nx * wall_speed
            vy = velocity[i, 1] * velocity_scale - ny * wall_speed
            vz = velocity[i, 2] * velocity_scale - nz * wall_speed
            v_normal = vx * nx + vy * ny + vz * nz
            wx = lever * angular_velocity[i, 0] * velocity_scale
            wy = lever * angular_velocity[i, 1] * velocity_scale
            wz = lever * angular_velocity[i, 2] * velocity_scale
            slip_x = vx - v_normal * nx - (wy * nz - wz * ny)
            slip_y = vy - v_normal * ny - (wz * nx - wx * nz)
            slip_z = vz - v_normal * nz - (wx * ny - wy * nx)
            f_n, f_tx, f_ty, f_tz, xi_x, xi_y, xi_z = contact_3d(
                wall_law, nx, ny, nz, overlap, v_normal, slip_x, slip_y, slip_z, m_eff, scale,
                wall_spring[i, wall, 0], wall_spring[i, wall, 1], wall_spring[i, wall, 2], spring_dt)
            wall_spring[i, wall, 0] = xi_x
            wall_spring[i, wall, 1] = xi_y
            wall_spring[i, wall, 2] = xi_z
            force[i, 0] += f_n * nx + f_tx
            force[i, 1] += f_n * ny + f_ty
            force[i, 2] += f_n * nz + f_tz
            torque[i, 0] -= lever * (ny * f_tz - nz * f_ty)
            torque[i, 1] -= lever * (nz * f_tx - nx * f_tz)
            torque[i, 2] -= lever * (nx * f_ty - ny * f_tx)
            if record is not None:
                record.force[i, wall, 0] = f_n * nx + f_tx
                record.force[i, wall, 1] = f_n * ny + f_ty
                record.force[i, wall, 2] = f_n * nz + f_tz
        if record is not None:
            record.overlap[i, wall] = overlap
    return worst_fraction, worst_particle


@numba.njit(**NJIT_DEM)
def wall_candidates(position, radius, n_mobile, wall_lo, wall_hi, reach):
    """The (particle, wall) entries, particle-major, of the mobile particles whose centre is closer than
    radius + reach to that flat wall (the ones the time step visits, see `stepping.advance`): two int64 arrays
    (particle, wall id 2·axis + side)."""
    dim = position.shape[1]
    entry_particle = np.empty(2 * dim * n_mobile, dtype=np.int64)
    entry_wall = np.empty(2 * dim * n_mobile, dtype=np.int64)
    n = 0
    for i in range(n_mobile):
        limit = radius[i] + reach
        for wall in range(2 * dim):
            axis = wall // 2
            gap = position[i, axis] - wall_lo[axis] if wall % 2 == 0 else wall_hi[axis] - position[i, axis]
            if not gap >= limit:
                entry_particle[n] = i
                entry_wall[n] = wall
                n += 1
    return entry_particle[:n].copy(), entry_wall[:n].copy()
