"""Numba kernels of the DEM engine: contact forces, flat walls, Gear predictor–corrector, neighbour lists.

Only numpy, numba and math (plus the DEM numba options, `forcenet._numba.NJIT_DEM`). Drivers live in `engine.py` and `protocol.py`.

Conventions (all in reduced units: length d_ave, mass m̄, time τ_c):

* positions and their time derivatives are held as Gear "scaled derivatives" (Allen & Tildesley §3.2):
  ``gear[k] = Δt^k / k! · d^k r / dt^k`` for k = 0..4, shape (5, N, C) with C = d for translation and
  C = 1 (2D, rotation about z) or 3 (3D) for rotation. The rotation "position" is the integrated angle
  (meaningless in 3D, never reported); only its derivatives (ω, torque / I) matter.
* a pair (i, j) always has i < j; n = (r_i − r_j)/|r_i − r_j| points from j to i; forces are "on i from j".
* the contact law is a float64 array `law` indexed by the LAW_* constants below.
* particles with index ≥ n_mobile are wall particles (rough walls, P2): inverse mass and inertia 0,
  positions prescribed by the wall motion, never integrated.
"""
import math

import numba
import numpy as np

from forcenet._numba import NJIT_DEM

# --- the contact law -------------------------------------------------------------------------------------------
LAW_K_N = 0        # k_n       [m̄ d_ave^(−β) τ_c^(−2)]
LAW_K_T = 1        # k_t       [same]
LAW_GAMMA_N = 2    # γ_n       [d_ave^(−β) τ_c^(−1)]
LAW_GAMMA_T = 3    # γ_t       [same]
LAW_MU = 4         # Coulomb μ [-]
LAW_BETA = 5       # β: 0 linear, 0.5 Hertz (P1 Eq. 1)
LAW_RADIUS_SCALED = 6  # 1: every term also × √R_eff (LAMMPS gran/hertz convention, benchmark only)
LAW_SIZE = 7

# --- status codes returned by `advance` ------------------------------------------------------------------------
STATUS_DONE = 0          # all requested steps done
STATUS_REBUILD = 1       # a particle moved more than half the skin: rebuild the neighbour list
STATUS_NOT_FINITE = 2    # NaN or inf in a position or velocity
STATUS_OVERLAP = 3       # an overlap above MAX_OVERLAP_FRACTION of a diameter
STATUS_ESCAPED = 4       # a particle centre left the box

#: blow-up threshold: overlap / diameter (smaller diameter of the pair)
MAX_OVERLAP_FRACTION = 0.2

#: Gear corrector coefficients for a second-order equation with 5 values (Allen & Tildesley Table E.2)
GEAR_C0 = 19.0 / 120.0
GEAR_C1 = 3.0 / 4.0
GEAR_C3 = 1.0 / 2.0
GEAR_C4 = 1.0 / 12.0


@numba.njit(**NJIT_DEM)
def _overlap_power(overlap, beta):
    """x^β, with the two force laws of P1 special-cased (exact and fast)."""
    if beta == 0.0:
        return 1.0
    if beta == 0.5:
        return math.sqrt(overlap)
    return overlap ** beta


@numba.njit(**NJIT_DEM)
def contact_force_2d(nx, ny, overlap, v_normal, slip_x, slip_y, m_eff, scale, xi_x, xi_y, law, spring_dt):
    """Force of one contact in 2D (P1 Eq. 1–3).

    n = (nx, ny): unit normal towards i; overlap x > 0 [d_ave]; v_normal = (v_i − v_j)·n [d_ave/τ_c];
    (slip_x, slip_y): tangential slip velocity of the contact points [d_ave/τ_c]; m_eff: reduced mass [m̄];
    scale: extra factor on every term (1, or √R_eff in the LAMMPS convention); (xi_x, xi_y): the
    Cundall–Strack spring before this step [d_ave]; spring_dt: time over which the slip stretches it [τ_c]
    (0 to evaluate without advancing the spring).
    Returns (F_n ≥ 0 along n, F_t x, F_t y, new spring x, new spring y).
    """
    x_beta = _overlap_power(overlap, law[LAW_BETA]) * scale
    # P1 Eq. 1: F_n = k_n x^(1+β) − γ_n x^β m̄ v_n, never attractive
    f_n = x_beta * (law[LAW_K_N] * overlap - law[LAW_GAMMA_N] * m_eff * v_normal)
    if f_n < 0.0:
        f_n = 0.0
    # Cundall–Strack: ξ = ∫ v_t dt, then the projection ξ' = ξ − n(n·ξ) (P1 §2)
    xi_x += slip_x * spring_dt
    xi_y += slip_y * spring_dt
    along = xi_x * nx + xi_y * ny
    xi_x -= along * nx
    xi_y -= along * ny
    # P1 Eq. 2: F_t* = −k_t x^β ξ' − γ_t x^β m̄ v_t
    f_tx = -x_beta * (law[LAW_K_T] * xi_x + law[LAW_GAMMA_T] * m_eff * slip_x)
    f_ty = -x_beta * (law[LAW_K_T] * xi_y + law[LAW_GAMMA_T] * m_eff * slip_y)
    # P1 Eq. 3: |F_t| ≤ μ|F_n|; the spring is rescaled by the same factor when the cap applies
    f_t_sq = f_tx * f_tx + f_ty * f_ty
    f_t_max = law[LAW_MU] * f_n
    if f_t_sq > f_t_max * f_t_max:
        ratio = f_t_max / math.sqrt(f_t_sq)
        f_tx *= ratio
        f_ty *= ratio
        xi_x *= ratio
        xi_y *= ratio
    return f_n, f_tx, f_ty, xi_x, xi_y


@numba.njit(**NJIT_DEM)
def contact_force_3d(nx, ny, nz, overlap, v_normal, slip_x, slip_y, slip_z, m_eff, scale,
                     xi_x, xi_y, xi_z, law, spring_dt):
    """3D version of `contact_force_2d` (P1 Eq. 1–3); returns (F_n, F_t (3), spring (3))."""
    x_beta = _overlap_power(overlap, law[LAW_BETA]) * scale
    f_n = x_beta * (law[LAW_K_N] * overlap - law[LAW_GAMMA_N] * m_eff * v_normal)  # P1 Eq. 1
    if f_n < 0.0:
        f_n = 0.0
    xi_x += slip_x * spring_dt
    xi_y += slip_y * spring_dt
    xi_z += slip_z * spring_dt
    along = xi_x * nx + xi_y * ny + xi_z * nz  # ξ' = ξ − n(n·ξ)
    xi_x -= along * nx
    xi_y -= along * ny
    xi_z -= along * nz
    f_tx = -x_beta * (law[LAW_K_T] * xi_x + law[LAW_GAMMA_T] * m_eff * slip_x)  # P1 Eq. 2
    f_ty = -x_beta * (law[LAW_K_T] * xi_y + law[LAW_GAMMA_T] * m_eff * slip_y)
    f_tz = -x_beta * (law[LAW_K_T] * xi_z + law[LAW_GAMMA_T] * m_eff * slip_z)
    f_t_sq = f_tx * f_tx + f_ty * f_ty + f_tz * f_tz
    f_t_max = law[LAW_MU] * f_n
    if f_t_sq > f_t_max * f_t_max:  # P1 Eq. 3
        ratio = f_t_max / math.sqrt(f_t_sq)
        f_tx *= ratio
        f_ty *= ratio
        f_tz *= ratio
        xi_x *= ratio
        xi_y *= ratio
        xi_z *= ratio
    return f_n, f_tx, f_ty, f_tz, xi_x, xi_y, xi_z


@numba.njit(**NJIT_DEM)
def pair_forces_2d(position, velocity, angular_velocity, velocity_scale, radius, pair_mass, pair_scale,
                   pair_i, pair_j, n_pairs, spring, law, spring_dt, force, torque,
                   record, record_overlap, record_normal, record_tangential):
    """Add the particle–particle contact forces of the Verlet list to `force` and `torque` (2D).

    position (N, 2) [d_ave]; velocity (N, 2) and angular_velocity (N, 1) are multiplied by velocity_scale
    (1/Δt when they are Gear scaled derivatives); radius (N,); pair_mass (≥ n_pairs,) the reduced mass m_eff of
    each pair and pair_scale its extra factor (1, or √R_eff in the LAMMPS convention), see `pair_constants`;
    pair_i, pair_j (≥ n_pairs,) int;
    spring (≥ n_pairs, 2) Cundall–Strack springs, updated in place (zeroed when a contact opens);
    force (N, 2), torque (N, 1) accumulated. When `record`, the overlap (0 if apart), normal and
    tangential force on i of every pair are written to record_* (n_pairs,), (n_pairs, 2).
    Returns (overlap / smaller diameter of the pair that exceeds the blow-up threshold most — the largest
    fraction whenever one is above it —, index of that pair or −1).
    """
    worst_excess = -np.inf
    worst_pair = -1
    for p in range(n_pairs):
        i = pair_i[p]
        j = pair_j[p]
        dx = position[i, 0] - position[j, 0]
        dy = position[i, 1] - position[j, 1]
        contact_distance = radius[i] + radius[j]
        distance_sq = dx * dx + dy * dy
        if not distance_sq < contact_distance * contact_distance:
            spring[p, 0] = 0.0  # the contact opened (or never formed): the spring is removed
            spring[p, 1] = 0.0
            if record:
                record_overlap[p] = 0.0
            continue
        distance = math.sqrt(distance_sq)
        overlap = contact_distance - distance  # P1: x = d_ij − r_ij
        inv_distance = 1.0 / distance
        nx = dx * inv_distance
        ny = dy * inv_distance
        excess = overlap - MAX_OVERLAP_FRACTION * 2.0 * min(radius[i], radius[j])  # blow-up check, no division
        if excess > worst_excess:
            worst_excess = excess
            worst_pair = p
        lever_i = radius[i] - 0.5 * overlap  # centre to contact point
        lever_j = radius[j] - 0.5 * overlap
        vx = (velocity[i, 0] - velocity[j, 0]) * velocity_scale
        vy = (velocity[i, 1] - velocity[j, 1]) * velocity_scale
        v_normal = vx * nx + vy * ny
        spin = (lever_i * angular_velocity[i, 0] + lever_j * angular_velocity[j, 0]) * velocity_scale
        # slip of the contact points: v_ij − v_n n − (a_i ω_i + a_j ω_j) ẑ × n
        slip_x = vx - v_normal * nx + spin * ny
        slip_y = vy - v_normal * ny - spin * nx
        m_eff = pair_mass[p]
        scale = pair_scale[p]
        f_n, f_tx, f_ty, xi_x, xi_y = contact_force_2d(nx, ny, overlap, v_normal, slip_x, slip_y, m_eff, scale,
                                                       spring[p, 0], spring[p, 1], law, spring_dt)
        spring[p, 0] = xi_x
        spring[p, 1] = xi_y
        fx = f_n * nx + f_tx
        fy = f_n * ny + f_ty
        force[i, 0] += fx
        force[i, 1] += fy
        force[j, 0] -= fx
        force[j, 1] -= fy
        n_cross_ft = nx * f_ty - ny * f_tx  # torques: τ_i = −a_i n × F_t, τ_j = −a_j n × F_t
        torque[i, 0] -= lever_i * n_cross_ft
        torque[j, 0] -= lever_j * n_cross_ft
        if record:
            record_overlap[p] = overlap
            record_normal[p, 0] = f_n * nx
            record_normal[p, 1] = f_n * ny
            record_tangential[p, 0] = f_tx
            record_tangential[p, 1] = f_ty
    return _worst_fraction(worst_pair, worst_excess, pair_i, pair_j, radius), worst_pair


@numba.njit(**NJIT_DEM)
def pair_constants(pair_i, pair_j, radius, inv_mass, law):
    """Per-pair constants of the Verlet list: reduced mass 1/(1/m_i + 1/m_j) (m_i against a wall particle) and
    the LAMMPS-convention factor √(r_i r_j/(r_i + r_j)) (1 unless law[LAW_RADIUS_SCALED])."""
    n = pair_i.shape[0]
    pair_mass = np.empty(n)
    pair_scale = np.ones(n)
    for p in range(n):
        i = pair_i[p]
        j = pair_j[p]
        pair_mass[p] = 1.0 / (inv_mass[i] + inv_mass[j])
        if law[LAW_RADIUS_SCALED] != 0.0:
            pair_scale[p] = math.sqrt(radius[i] * radius[j] / (radius[i] + radius[j]))
    return pair_mass, pair_scale


@numba.njit(**NJIT_DEM)
def _worst_fraction(worst_pair, worst_excess, pair_i, pair_j, radius):
    """Overlap / smaller diameter of the pair with the largest excess over the blow-up threshold."""
    if worst_pair < 0:
        return 0.0
    diameter = 2.0 * min(radius[pair_i[worst_pair]], radius[pair_j[worst_pair]])
    return MAX_OVERLAP_FRACTION + worst_excess / diameter


@numba.njit(**NJIT_DEM)
def pair_forces_3d(position, velocity, angular_velocity, velocity_scale, radius, pair_mass, pair_scale,
                   pair_i, pair_j, n_pairs, spring, law, spring_dt, force, torque,
                   record, record_overlap, record_normal, record_tangential):
    """3D version of `pair_forces_2d`: position, velocity, angular_velocity, force, torque, spring (·, 3)."""
    worst_excess = -np.inf
    worst_pair = -1
    for p in range(n_pairs):
        i = pair_i[p]
        j = pair_j[p]
        dx = position[i, 0] - position[j, 0]
        dy = position[i, 1] - position[j, 1]
        dz = position[i, 2] - position[j, 2]
        contact_distance = radius[i] + radius[j]
        distance_sq = dx * dx + dy * dy + dz * dz
        if not distance_sq < contact_distance * contact_distance:
            spring[p, 0] = 0.0
            spring[p, 1] = 0.0
            spring[p, 2] = 0.0
            if record:
                record_overlap[p] = 0.0
            continue
        distance = math.sqrt(distance_sq)
        overlap = contact_distance - distance
        inv_distance = 1.0 / distance
        nx = dx * inv_distance
        ny = dy * inv_distance
        nz = dz * inv_distance
        excess = overlap - MAX_OVERLAP_FRACTION * 2.0 * min(radius[i], radius[j])  # blow-up check, no division
        if excess > worst_excess:
            worst_excess = excess
            worst_pair = p
        lever_i = radius[i] - 0.5 * overlap
        lever_j = radius[j] - 0.5 * overlap
        vx = (velocity[i, 0] - velocity[j, 0]) * velocity_scale
        vy = (velocity[i, 1] - velocity[j, 1]) * velocity_scale
        vz = (velocity[i, 2] - velocity[j, 2]) * velocity_scale
        v_normal = vx * nx + vy * ny + vz * nz
        wx = (lever_i * angular_velocity[i, 0] + lever_j * angular_velocity[j, 0]) * velocity_scale
        wy = (lever_i * angular_velocity[i, 1] + lever_j * angular_velocity[j, 1]) * velocity_scale
        wz = (lever_i * angular_velocity[i, 2] + lever_j * angular_velocity[j, 2]) * velocity_scale
        # slip: v_ij − v_n n − (a_i ω_i + a_j ω_j) × n
        slip_x = vx - v_normal * nx - (wy * nz - wz * ny)
        slip_y = vy - v_normal * ny - (wz * nx - wx * nz)
        slip_z = vz - v_normal * nz - (wx * ny - wy * nx)
        m_eff = pair_mass[p]
        scale = pair_scale[p]
        f_n, f_tx, f_ty, f_tz, xi_x, xi_y, xi_z = contact_force_3d(
            nx, ny, nz, overlap, v_normal, slip_x, slip_y, slip_z, m_eff, scale,
            spring[p, 0], spring[p, 1], spring[p, 2], law, spring_dt)
        spring[p, 0] = xi_x
        spring[p, 1] = xi_y
        spring[p, 2] = xi_z
        fx = f_n * nx + f_tx
        fy = f_n * ny + f_ty
        fz = f_n * nz + f_tz
        force[i, 0] += fx
        force[i, 1] += fy
        force[i, 2] += fz
        force[j, 0] -= fx
        force[j, 1] -= fy
        force[j, 2] -= fz
        cx = ny * f_tz - nz * f_ty  # n × F_t
        cy = nz * f_tx - nx * f_tz
        cz = nx * f_ty - ny * f_tx
        torque[i, 0] -= lever_i * cx
        torque[i, 1] -= lever_i * cy
        torque[i, 2] -= lever_i * cz
        torque[j, 0] -= lever_j * cx
        torque[j, 1] -= lever_j * cy
        torque[j, 2] -= lever_j * cz
        if record:
            record_overlap[p] = overlap
            record_normal[p, 0] = f_n * nx
            record_normal[p, 1] = f_n * ny
            record_normal[p, 2] = f_n * nz
            record_tangential[p, 0] = f_tx
            record_tangential[p, 1] = f_ty
            record_tangential[p, 2] = f_tz
    return _worst_fraction(worst_pair, worst_excess, pair_i, pair_j, radius), worst_pair


@numba.njit(**NJIT_DEM)
def flat_wall_forces(position, velocity, angular_velocity, velocity_scale, radius, inv_mass, n_mobile,
                     wall_lo, wall_hi, wall_speed, wall_spring, law, spring_dt, force, torque,
                     record, record_overlap, record_force, release_band):
    """Add the forces of the 2d flat walls (P1 §2: same law, overlap x = d_i/2 − distance to the wall).

    Wall w = 2·axis + side (side 0: at wall_lo[axis], normal +e_axis; side 1: at wall_hi[axis], normal
    −e_axis), moving inward at wall_speed [d_ave/τ_c] (its velocity enters the damping and the slip).
    The wall is the partner j with infinite mass and radius: m_eff = m_i, R_eff = r_i.
    wall_spring (N, 2d, d) holds one Cundall–Strack spring per particle and wall; a spring is reset to zero
    when its particle is apart from the wall by less than release_band [d_ave] (a contact that opens in a step
    is within the band; the Verlet skin is a safe value; inf resets every spring). When `record`, the
    overlap (N, 2d) and the total force of each wall on each particle (N, 2d, d) are written.
    Returns (largest overlap / diameter, particle index or −1).
    """
    n_walls = 2 * position.shape[1]
    every_particle = np.repeat(np.arange(n_mobile), n_walls)
    every_wall = np.empty(n_mobile * n_walls, dtype=np.int64)
    for q in range(every_wall.shape[0]):
        every_wall[q] = q % n_walls
    return flat_wall_forces_of(every_particle, every_wall, position, velocity, angular_velocity, velocity_scale,
                               radius, inv_mass, wall_lo, wall_hi, wall_speed, wall_spring, law, spring_dt, force,
                               torque, record, record_overlap, record_force, release_band)


@numba.njit(**NJIT_DEM)
def flat_wall_forces_of(entry_particle, entry_wall, position, velocity, angular_velocity, velocity_scale, radius,
                        inv_mass, wall_lo, wall_hi, wall_speed, wall_spring, law, spring_dt, force, torque, record,
                        record_overlap, record_force, release_band):
    """`flat_wall_forces` for the listed (particle, wall) entries only, particle-major (`wall_candidates`):
    the other particles and walls are left alone."""
    dim = position.shape[1]
    radius_scaled = law[LAW_RADIUS_SCALED] != 0.0
    worst_fraction = 0.0
    worst_particle = -1
    for q in range(entry_particle.shape[0]):
        i = entry_particle[q]
        wall = entry_wall[q]
        axis = wall // 2
        if wall % 2 == 0:
            distance = position[i, axis] - wall_lo[axis]
            sign = 1.0
        else:
            distance = wall_hi[axis] - position[i, axis]
            sign = -1.0
        overlap = radius[i] - distance  # P1: x = 0.5 d_i − r_i
        if not overlap > 0.0:
            if record:
                record_overlap[i, wall] = 0.0
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
            f_n, f_tx, f_ty, xi_x, xi_y = contact_force_2d(
                nx, ny, overlap, v_normal, slip_x, slip_y, m_eff, scale,
                wall_spring[i, wall, 0], wall_spring[i, wall, 1], law, spring_dt)
            wall_spring[i, wall, 0] = xi_x
            wall_spring[i, wall, 1] = xi_y
            fx = f_n * nx + f_tx
            fy = f_n * ny + f_ty
            force[i, 0] += fx
            force[i, 1] += fy
            torque[i, 0] -= lever * (nx * f_ty - ny * f_tx)
            if record:
                record_force[i, wall, 0] = fx
                record_force[i, wall, 1] = fy
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
            f_n, f_tx, f_ty, f_tz, xi_x, xi_y, xi_z = contact_force_3d(
                nx, ny, nz, overlap, v_normal, slip_x, slip_y, slip_z, m_eff, scale,
                wall_spring[i, wall, 0], wall_spring[i, wall, 1], wall_spring[i, wall, 2], law, spring_dt)
            wall_spring[i, wall, 0] = xi_x
            wall_spring[i, wall, 1] = xi_y
            wall_spring[i, wall, 2] = xi_z
            force[i, 0] += f_n * nx + f_tx
            force[i, 1] += f_n * ny + f_ty
            force[i, 2] += f_n * nz + f_tz
            torque[i, 0] -= lever * (ny * f_tz - nz * f_ty)
            torque[i, 1] -= lever * (nz * f_tx - nx * f_tz)
            torque[i, 2] -= lever * (nx * f_ty - ny * f_tx)
            if record:
                record_force[i, wall, 0] = f_n * nx + f_tx
                record_force[i, wall, 1] = f_n * ny + f_ty
                record_force[i, wall, 2] = f_n * nz + f_tz
        if record:
            record_overlap[i, wall] = overlap
    return worst_fraction, worst_particle


# --- Gear predictor–corrector (4th order: 5 values) -----------------------------------------------------------

@numba.njit(**NJIT_DEM)
def gear_predict(gear, n_mobile, force_velocity, load):
    """Taylor (Pascal-triangle) prediction of the scaled derivatives gear (5, N, C), particles < n_mobile; their
    rows of load (N, C) (the force or torque about to be summed) are cleared in the same pass.

    force_velocity (N, C) receives the second-order prediction r1 + 2 r2 (= Δt (v + a Δt)) that the
    velocity-dependent forces (damping, spring increments) use instead of the full fourth-order r1. Stability of
    the corrector on ẍ = −ω² x − c ẋ (spectral radius of the step map; `tests/test_dem_physics.py` checks it on
    these kernels): with the full prediction it fails at c Δt ≈ 0.25; with r1 + 2 r2 at c Δt ≈ 1.5 (ω = 0), 1.4
    (ω Δt = 0.3), 1.05 (0.6), 0.7 (0.8). The midpoint r1 + r2 would stand c Δt ≈ 1.9 at every ω Δt ≤ 0.8, but a
    spring integrated with it (ξ += v_t Δt, F = −k ξ) grows without damping at any ω Δt, and the 3D smoke run blew
    up, so it was not adopted.
    """
    r0 = gear[0].reshape(-1)  # flat views: one vectorisable loop over every component
    r1 = gear[1].reshape(-1)
    r2 = gear[2].reshape(-1)
    r3 = gear[3].reshape(-1)
    r4 = gear[4].reshape(-1)
    v = force_velocity.reshape(-1)
    f = load.reshape(-1)
    for j in range(n_mobile * gear.shape[2]):
        a1 = r1[j]
        a2 = r2[j]
        a3 = r3[j]
        a4 = r4[j]
        v[j] = a1 + 2.0 * a2
        r0[j] += a1 + a2 + a3 + a4
        r1[j] = a1 + 2.0 * a2 + 3.0 * a3 + 4.0 * a4
        r2[j] = a2 + 3.0 * a3 + 6.0 * a4
        r3[j] = a3 + 4.0 * a4
        f[j] = 0.0


@numba.njit(**NJIT_DEM)
def _correct_predict_one(j, r0, r1, r2, r3, r4, f, v, scale, weight):
    """One component of `gear_correct_predict`; returns its weight · r1² after the correction."""
    delta = scale[j] * f[j] - r2[j]
    a1 = r1[j] + GEAR_C1 * delta
    a2 = r2[j] + delta
    a3 = r3[j] + GEAR_C3 * delta
    a4 = r4[j] + GEAR_C4 * delta
    v[j] = a1 + 2.0 * a2
    r0[j] = (r0[j] + GEAR_C0 * delta) + (a1 + a2 + a3 + a4)  # corrected r0, then the Taylor step
    r1[j] = a1 + 2.0 * a2 + 3.0 * a3 + 4.0 * a4
    r2[j] = a2 + 3.0 * a3 + 6.0 * a4
    r3[j] = a3 + 4.0 * a4
    r4[j] = a4
    f[j] = 0.0
    return weight[j] * a1 * a1


@numba.njit(**NJIT_DEM)
def gear_correct_predict(gear, load, accel_scale, half_weight, n_mobile, force_velocity):
    """Gear 5-value corrector of this step followed by `gear_predict` of the next, in one pass over gear
    (5, N, C), particles < n_mobile: the new acceleration term is accel_scale · load, with accel_scale (N, C) =
    Δt²/2 · (1/m or 1/I) of each component, and the corrected values are the old ones + (C0, C1, 1, C3, C4) ·
    (accel_scale · load − r2). One pass has half the memory traffic of two (measured +6 to +13 % on the 3D
    step). Returns the kinetic energy × Δt² of the corrected state,
    Σ half_weight · r1², with half_weight (N, C) = ½ m or ½ I per component, summed in four interleaved partial
    sums (a fixed order: deterministic). On return gear holds the prediction for the next step, force_velocity
    its r1 + 2 r2 and load is cleared, as after `gear_predict`; `gear_unpredict` recovers the corrected state."""
    r0 = gear[0].reshape(-1)
    r1 = gear[1].reshape(-1)
    r2 = gear[2].reshape(-1)
    r3 = gear[3].reshape(-1)
    r4 = gear[4].reshape(-1)
    f = load.reshape(-1)
    v = force_velocity.reshape(-1)
    scale = accel_scale.reshape(-1)
    weight = half_weight.reshape(-1)
    n = n_mobile * gear.shape[2]
    e0 = 0.0
    e1 = 0.0
    e2 = 0.0
    e3 = 0.0
    n_blocks = n // 4
    for block in range(n_blocks):  # four independent lanes: the sums need no reassociation to vectorise
        j = 4 * block
        e0 += _correct_predict_one(j, r0, r1, r2, r3, r4, f, v, scale, weight)
        e1 += _correct_predict_one(j + 1, r0, r1, r2, r3, r4, f, v, scale, weight)
        e2 += _correct_predict_one(j + 2, r0, r1, r2, r3, r4, f, v, scale, weight)
        e3 += _correct_predict_one(j + 3, r0, r1, r2, r3, r4, f, v, scale, weight)
    for j in range(4 * n_blocks, n):
        e0 += _correct_predict_one(j, r0, r1, r2, r3, r4, f, v, scale, weight)
    return (e0 + e1) + (e2 + e3)


@numba.njit(**NJIT_DEM)
def gear_unpredict(gear, n_mobile):
    """Undo `gear_predict`'s Taylor step on gear (5, N, C), particles < n_mobile (the inverse Pascal matrix;
    exact up to rounding): back to the corrected state after `gear_correct_predict`."""
    r0 = gear[0].reshape(-1)
    r1 = gear[1].reshape(-1)
    r2 = gear[2].reshape(-1)
    r3 = gear[3].reshape(-1)
    r4 = gear[4].reshape(-1)
    for j in range(n_mobile * gear.shape[2]):
        a4 = r4[j]
        a3 = r3[j] - 4.0 * a4
        a2 = r2[j] - 3.0 * a3 - 6.0 * a4
        a1 = r1[j] - 2.0 * a2 - 3.0 * a3 - 4.0 * a4
        r0[j] -= a1 + a2 + a3 + a4
        r1[j] = a1
        r2[j] = a2
        r3[j] = a3


@numba.njit(**NJIT_DEM)
def check_positions(position, reference, n_mobile, lo, hi, escape_margin):
    """Largest squared displacement since the last rebuild, and the first particle whose centre is not
    finite or lies outside [lo − margin, hi + margin] (−1 if none)."""
    dim = position.shape[1]
    max_sq = 0.0
    bad = -1
    for i in range(n_mobile):
        d_sq = 0.0
        inside = True
        for k in range(dim):
            x = position[i, k]
            inside = inside and x >= lo[k] - escape_margin and x <= hi[k] + escape_margin
            d = x - reference[i, k]
            d_sq += d * d
        if not inside and bad < 0:
            bad = i
        max_sq = max(max_sq, d_sq)
    return max_sq, bad


@numba.njit(**NJIT_DEM)
def place_wall_particles(gear_position, force_velocity, n_mobile, wall_anchor, wall_axis, wall_sign,
                         box_lo, box_hi, shift, velocity_dt):
    """Rough walls at wall shift `shift` [d_ave], walls moving inward by velocity_dt (= v_wall Δt) per step.

    Wall particle w moves with its wall along the wall's axis (anchor + sign·shift) and, along the other axes,
    contracts affinely with the box about its centre (factor L(t)/L0, L = box_hi − box_lo − 2 shift), so the
    rough boundary shrinks uniformly and the corners never form a closing wedge. Positions go to
    gear_position[0], scaled velocities to gear_position[1] and force_velocity.
    """
    dim = wall_anchor.shape[1]
    for w in range(wall_anchor.shape[0]):
        idx = n_mobile + w
        axis = wall_axis[w]
        for k in range(dim):
            if k == axis:
                gear_position[0, idx, k] = wall_anchor[w, k] + wall_sign[w] * shift
                gear_position[1, idx, k] = wall_sign[w] * velocity_dt
            else:
                length0 = box_hi[k] - box_lo[k]
                centre = 0.5 * (box_hi[k] + box_lo[k])
                offset = wall_anchor[w, k] - centre
                gear_position[0, idx, k] = centre + offset * (length0 - 2.0 * shift) / length0
                gear_position[1, idx, k] = -offset * 2.0 * velocity_dt / length0
            force_velocity[idx, k] = gear_position[1, idx, k]


# --- the time-step loop ----------------------------------------------------------------------------------------
#
# `advance` runs many steps per call (one numba call per chunk, no allocation per step). The pair loop is
# `_pair_loop_2d` / `_pair_loop_3d`: the operations of `pair_forces_2d` / `pair_forces_3d` in the same order (the
# same results to the last bit under the same compiler options), with the law's constants hoisted out of the loop
# and the per-pair constants of `pair_constants` formed in the loop from per-particle values (a per-pair table
# costs more memory traffic than the division and square root: measured 4 % of the whole 3D step). The loops read
# flat views of the per-particle arrays at unsigned offsets, which drops the stride and negative-index arithmetic
# from every access (−5 to −9 % on the pair loop). A touching pair costs ~100 cycles, most of it the latency of
# one chain (position → √, 1/d → n → slip → spring → Coulomb test); the engine lists the pairs that touch at a
# rebuild first, so the contact test mispredicts only where a contact opened or closed since then. Measured and
# dropped: accumulating particle i's force over its row in registers (−10 % in 3D), computing every listed pair
# without the contact branch, compacting the touching pairs and computing them two at a time, and a blocked
# pair loop (gather the touching pairs, vectorised forces, scatter): all were slower inside the step, as was
# an interleaved per-particle layout (no change). Outside the pair loop the step streams the Gear values: the
# corrector of one step and the predictor of the next are one pass that also clears the force sums
# (`gear_correct_predict`), and the flat walls visit only the (particle, wall) entries that can touch before the
# next rebuild (`wall_candidates`).

#: unsigned offsets of the flat pair loops
U1 = np.uint64(1)
U2 = np.uint64(2)
U3 = np.uint64(3)

#: force-law selector of the pair loops
MODE_LINEAR = 0
MODE_HERTZ = 1
MODE_POWER = 2


@numba.njit(**NJIT_DEM)
def law_mode(beta):
    """MODE_LINEAR for β = 0, MODE_HERTZ for β = ½, MODE_POWER otherwise (x^β by pow)."""
    if beta == 0.0:
        return MODE_LINEAR
    if beta == 0.5:
        return MODE_HERTZ
    return MODE_POWER


@numba.njit(**NJIT_DEM)
def _x_beta(overlap, mode, beta, scale):
    if mode == MODE_LINEAR:
        return scale  # = 1.0 · scale
    if mode == MODE_HERTZ:
        return math.sqrt(overlap) * scale
    return overlap ** beta * scale


@numba.njit(**NJIT_DEM)
def _pair_loop_2d(position, velocity, angular_velocity, velocity_scale, radius, inv_mass, pair_i, n_pairs, pair_j,
                  spring, k_n, k_t, gamma_n, gamma_t, mu, mode, beta, radius_scaled, spring_dt, force, torque):
    """The stepping version of `pair_forces_2d` (same operations in the same order): the law comes as scalars
    (k_n, k_t, γ_n, γ_t, μ, `law_mode`, β, whether × √R_eff) hoisted out of the loop; inv_mass (N,) [1/m̄] gives
    m_eff; spring is the flat (n_pairs·2,) view; nothing is recorded. Returns (largest excess of an overlap
    over the blow-up threshold, its pair; −1 when no pair touches)."""
    worst_excess = -np.inf
    worst_pair = -1
    x = position.reshape(-1)  # flat views indexed by unsigned offsets: no stride or negative-index arithmetic
    v = velocity.reshape(-1)
    w = angular_velocity.reshape(-1)
    f = force.reshape(-1)
    t = torque.reshape(-1)
    for p in range(n_pairs):
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
            continue
        distance = math.sqrt(distance_sq)
        overlap = contact_distance - distance
        inv_distance = 1.0 / distance
        nx = dx * inv_distance
        ny = dy * inv_distance
        excess = overlap - MAX_OVERLAP_FRACTION * 2.0 * min(r_i, r_j)
        if excess > worst_excess:
            worst_excess = excess
            worst_pair = p
        lever_i = r_i - 0.5 * overlap
        lever_j = r_j - 0.5 * overlap
        vx = (v[i0] - v[j0]) * velocity_scale
        vy = (v[i1] - v[j1]) * velocity_scale
        v_normal = vx * nx + vy * ny
        spin = (lever_i * w[i] + lever_j * w[j]) * velocity_scale
        slip_x = vx - v_normal * nx + spin * ny
        slip_y = vy - v_normal * ny - spin * nx
        m_eff = 1.0 / (inv_mass[i] + inv_mass[j])  # `pair_constants`, formed here: cheaper than a per-pair table
        scale = math.sqrt(r_i * r_j / (r_i + r_j)) if radius_scaled else 1.0
        x_beta = _x_beta(overlap, mode, beta, scale)
        f_n = x_beta * (k_n * overlap - gamma_n * m_eff * v_normal)  # P1 Eq. 1
        if f_n < 0.0:
            f_n = 0.0
        xi_x = spring[2 * p] + slip_x * spring_dt
        xi_y = spring[2 * p + 1] + slip_y * spring_dt
        along = xi_x * nx + xi_y * ny
        xi_x -= along * nx
        xi_y -= along * ny
        gamma_t_m = gamma_t * m_eff
        f_tx = -x_beta * (k_t * xi_x + gamma_t_m * slip_x)  # P1 Eq. 2
        f_ty = -x_beta * (k_t * xi_y + gamma_t_m * slip_y)
        f_t_sq = f_tx * f_tx + f_ty * f_ty
        f_t_max = mu * f_n
        if f_t_sq > f_t_max * f_t_max:  # P1 Eq. 3
            ratio = f_t_max / math.sqrt(f_t_sq)
            f_tx *= ratio
            f_ty *= ratio
            xi_x *= ratio
            xi_y *= ratio
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
    return worst_excess, worst_pair


@numba.njit(**NJIT_DEM)
def _pair_loop_3d(position, velocity, angular_velocity, velocity_scale, radius, inv_mass, pair_i, n_pairs, pair_j,
                  spring, k_n, k_t, gamma_n, gamma_t, mu, mode, beta, radius_scaled, spring_dt, force, torque):
    """3D version of `_pair_loop_2d` (the arithmetic of `pair_forces_3d`)."""
    worst_excess = -np.inf
    worst_pair = -1
    x = position.reshape(-1)  # flat views indexed by unsigned offsets, as in the 2D loop
    v = velocity.reshape(-1)
    w = angular_velocity.reshape(-1)
    f = force.reshape(-1)
    t = torque.reshape(-1)
    for p in range(n_pairs):
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
        slip_x = vx - v_normal * nx - (wy * nz - wz * ny)
        slip_y = vy - v_normal * ny - (wz * nx - wx * nz)
        slip_z = vz - v_normal * nz - (wx * ny - wy * nx)
        m_eff = 1.0 / (inv_mass[i] + inv_mass[j])
        scale = math.sqrt(r_i * r_j / (r_i + r_j)) if radius_scaled else 1.0
        x_beta = _x_beta(overlap, mode, beta, scale)
        f_n = x_beta * (k_n * overlap - gamma_n * m_eff * v_normal)
        if f_n < 0.0:
            f_n = 0.0
        s = 3 * p
        xi_x = spring[s] + slip_x * spring_dt
        xi_y = spring[s + 1] + slip_y * spring_dt
        xi_z = spring[s + 2] + slip_z * spring_dt
        along = xi_x * nx + xi_y * ny + xi_z * nz
        xi_x -= along * nx
        xi_y -= along * ny
        xi_z -= along * nz
        gamma_t_m = gamma_t * m_eff
        f_tx = -x_beta * (k_t * xi_x + gamma_t_m * slip_x)
        f_ty = -x_beta * (k_t * xi_y + gamma_t_m * slip_y)
        f_tz = -x_beta * (k_t * xi_z + gamma_t_m * slip_z)
        f_t_sq = f_tx * f_tx + f_ty * f_ty + f_tz * f_tz
        f_t_max = mu * f_n
        if f_t_sq > f_t_max * f_t_max:
            ratio = f_t_max / math.sqrt(f_t_sq)
            f_tx *= ratio
            f_ty *= ratio
            f_tz *= ratio
            xi_x *= ratio
            xi_y *= ratio
            xi_z *= ratio
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
        cx = ny * f_tz - nz * f_ty
        cy = nz * f_tx - nx * f_tz
        cz = nx * f_ty - ny * f_tx
        t[i0] -= lever_i * cx
        t[i1] -= lever_i * cy
        t[i2] -= lever_i * cz
        t[j0] -= lever_j * cx
        t[j1] -= lever_j * cy
        t[j2] -= lever_j * cz
    return worst_excess, worst_pair


@numba.njit(**NJIT_DEM)
def wall_candidates(position, radius, n_mobile, wall_lo, wall_hi, reach):
    """The (particle, wall) entries, particle-major, of the mobile particles whose centre is closer than
    radius + reach to that flat wall (see `advance`): two arrays (particle, wall id 2·axis + side)."""
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


@numba.njit(**NJIT_DEM)
def _step_status(gear_position, bad, energy, worst_pair, worst_excess, pair_i, pair_j, radius, worst_wall,
                 wall_particle, max_sq, wall_travel, half_skin):
    """Whether `advance` must stop after a step, and why: (status code, particle slot or −1). A particle outside
    the walls or not finite (`check_positions`), a non-finite energy, an overlap above MAX_OVERLAP_FRACTION of a
    diameter (pair or wall), or a displacement / wall travel beyond half the skin (rebuild)."""
    if bad >= 0:
        for k in range(gear_position.shape[2]):
            if not (math.isfinite(gear_position[0, bad, k]) and math.isfinite(gear_position[1, bad, k])):
                return STATUS_NOT_FINITE, bad
        return STATUS_ESCAPED, bad
    if not math.isfinite(energy):
        return STATUS_NOT_FINITE, -1
    worst_pair_fraction = _worst_fraction(worst_pair, worst_excess, pair_i, pair_j, radius)
    if worst_pair_fraction > MAX_OVERLAP_FRACTION or worst_wall > MAX_OVERLAP_FRACTION:
        return STATUS_OVERLAP, (pair_i[worst_pair] if worst_pair_fraction >= worst_wall else wall_particle)
    if max_sq > half_skin * half_skin or wall_travel > half_skin:
        return STATUS_REBUILD, -1
    return STATUS_DONE, -1


@numba.njit(**NJIT_DEM)
def advance(gear_position, gear_rotation, n_mobile, radius, inv_mass, half_mass, half_inertia, accel_position,
            accel_rotation, pair_i, pair_j, n_pairs, spring, wall_spring, wall_entry_particle,
            wall_entry_wall, law, dt,
            flat_walls, box_lo, box_hi, wall_state, wall_anchor, wall_axis, wall_sign, escape_margin,
            reference_position, reference_shift, half_skin,
            n_steps, kinetic_energy, force, torque, force_velocity, force_spin, status):
    """Advance the system by up to n_steps Gear steps (predict, walls, forces, correct). The correction of one
    step and the prediction of the next are one pass (`gear_correct_predict`); the last prediction is undone
    (`gear_unpredict`) before returning, so between calls gear holds the corrected state.

    Per particle: inv_mass (N,) (0 for wall particles); per component, half_mass (N, d) and half_inertia
    (N, 1|3) = ½ m, ½ I for the kinetic energy and accel_position (N, d), accel_rotation (N, 1|3) = Δt²/2 · 1/m,
    1/I. Pairs: the half Verlet
    list pair_i, pair_j (i < j, in any fixed order: the engine lists the pairs touching at the rebuild first),
    n_pairs of them, and the springs (n_pairs, d). wall_entry_particle, wall_entry_wall: the (particle, wall)
    entries that can come into contact before the next rebuild (`wall_candidates` at the last rebuild with reach
    release band + skin + margin: until then nobody moves by more than half the skin, nor do the walls); the
    others are exactly those that `flat_wall_forces` would skip.

    wall_state = [shift, speed, shift_max, last speed]: every wall sits `shift` inward of box_lo / box_hi [d_ave]
    and moves inward at `speed` [d_ave/τ_c] until shift reaches shift_max; shift and the speed of the last step
    are updated in place. kinetic_energy (≥ n_steps,) receives the total kinetic energy after each step
    [m̄ d_ave² τ_c⁻²]. Stops early after a step whose largest displacement since the last rebuild exceeds half
    the skin (STATUS_REBUILD) or that blew up. force_velocity (N, d), force_spin (N, 1|3) are work arrays (the
    velocities the forces see, see `gear_predict`). status (2,) int receives [code, particle index]. Returns the
    number of steps done. The forces are those of the reference kernels (`pair_forces_2d` …) to the last bit;
    the rebuild and escape checks look at the predicted positions, the ones the next forces will see.
    """
    dim = gear_position.shape[2]
    inv_dt = 1.0 / dt
    lo = np.empty(dim)
    hi = np.empty(dim)
    no_overlap = np.empty((0, 2 * dim))
    no_force = np.empty((0, 2 * dim, dim))
    k_n = law[LAW_K_N]
    k_t = law[LAW_K_T]
    mu = law[LAW_MU]
    beta = law[LAW_BETA]
    mode = law_mode(beta)
    gamma_n = law[LAW_GAMMA_N]
    gamma_t = law[LAW_GAMMA_T]
    radius_scaled = law[LAW_RADIUS_SCALED] != 0.0
    spring_flat = spring.reshape(-1)
    status[0] = STATUS_DONE
    status[1] = -1
    gear_predict(gear_position, n_mobile, force_velocity, force)
    gear_predict(gear_rotation, n_mobile, force_spin, torque)
    for step in range(n_steps):
        # the walls at t + Δt
        old_shift = wall_state[0]
        shift = old_shift + wall_state[1] * dt
        if shift > wall_state[2]:
            shift = wall_state[2]
        if shift < old_shift:
            shift = old_shift
        wall_state[0] = shift
        wall_speed = (shift - old_shift) * inv_dt
        wall_state[3] = wall_speed
        for k in range(dim):
            lo[k] = box_lo[k] + shift
            hi[k] = box_hi[k] - shift
        if wall_anchor.shape[0] > 0:
            place_wall_particles(gear_position, force_velocity, n_mobile, wall_anchor, wall_axis, wall_sign,
                                 box_lo, box_hi, shift, wall_speed * dt)
        force[n_mobile:, :] = 0.0  # the wall particles' rows (the Gear pass cleared the mobile ones)
        torque[n_mobile:, :] = 0.0
        worst_wall = 0.0
        wall_particle = -1
        if flat_walls:
            worst_wall, wall_particle = flat_wall_forces_of(
                wall_entry_particle, wall_entry_wall, gear_position[0], force_velocity, force_spin, inv_dt, radius,
                inv_mass, lo, hi, wall_speed, wall_spring, law, dt, force, torque, False, no_overlap, no_force, 2.0 * half_skin)
        if dim == 2:
            worst_excess, worst_pair = _pair_loop_2d(
                gear_position[0], force_velocity, force_spin, inv_dt, radius, inv_mass, pair_i, n_pairs, pair_j,
                spring_flat, k_n, k_t, gamma_n, gamma_t, mu, mode, beta, radius_scaled, dt, force, torque)
        else:
            worst_excess, worst_pair = _pair_loop_3d(
                gear_position[0], force_velocity, force_spin, inv_dt, radius, inv_mass, pair_i, n_pairs, pair_j,
                spring_flat, k_n, k_t, gamma_n, gamma_t, mu, mode, beta, radius_scaled, dt, force, torque)
        energy = (gear_correct_predict(gear_position, force, accel_position, half_mass, n_mobile, force_velocity)
                  + gear_correct_predict(gear_rotation, torque, accel_rotation, half_inertia, n_mobile,
                                         force_spin))
        kinetic_energy[step] = energy * inv_dt * inv_dt
        max_sq, bad = check_positions(gear_position[0], reference_position, n_mobile, lo, hi, escape_margin)
        code, particle = _step_status(gear_position, bad, energy, worst_pair, worst_excess, pair_i, pair_j, radius,
                                      worst_wall, wall_particle, max_sq, shift - reference_shift, half_skin)
        if code != STATUS_DONE:
            gear_unpredict(gear_position, n_mobile)  # back to the corrected state of this step
            gear_unpredict(gear_rotation, n_mobile)
            status[0] = code
            status[1] = particle
            return step + 1
    gear_unpredict(gear_position, n_mobile)
    gear_unpredict(gear_rotation, n_mobile)
    return n_steps


# --- neighbour lists ----------------------------------------------------------------------------------------

@numba.njit(**NJIT_DEM)
def cell_index(position, n, origin, cell_size, n_cells):
    """Linear cell index (n,) of the first n particles on a grid of n_cells (3,) cubes of side cell_size
    starting at origin (d,); coordinates outside the grid are clamped to its border cells."""
    dim = position.shape[1]
    cells = np.empty(n, dtype=np.int64)
    for i in range(n):
        linear = 0
        for k in range(3):
            c = 0
            if k < dim:
                c = int(math.floor((position[i, k] - origin[k]) / cell_size))
                if c < 0:
                    c = 0
                elif c >= n_cells[k]:
                    c = n_cells[k] - 1
            linear = linear * n_cells[k] + c
        cells[i] = linear
    return cells


@numba.njit(**NJIT_DEM)
def build_pair_list(position, radius, n_mobile, n_total, skin, origin, cell_size, n_cells):
    """Verlet list: every pair i < j with |r_i − r_j| < r_i + r_j + skin, i mobile (wall–wall pairs excluded),
    found through a cell list; sorted by i then j. Returns (pair_i, pair_j) int32 arrays."""
    dim = position.shape[1]
    cells = cell_index(position, n_total, origin, cell_size, n_cells)
    total_cells = n_cells[0] * n_cells[1] * n_cells[2]
    cell_start = np.zeros(total_cells + 1, dtype=np.int64)
    for i in range(n_total):
        cell_start[cells[i] + 1] += 1
    for c in range(total_cells):
        cell_start[c + 1] += cell_start[c]
    fill = cell_start[:-1].copy()
    members = np.empty(n_total, dtype=np.int64)
    for i in range(n_total):
        members[fill[cells[i]]] = i
        fill[cells[i]] += 1
    span_z = 1 if dim == 3 else 0
    row_count = np.zeros(n_mobile + 1, dtype=np.int64)
    for sweep in range(2):  # 0: count each row, 1: fill
        if sweep == 1:
            for i in range(n_mobile):
                row_count[i + 1] += row_count[i]
            n_pairs = row_count[n_mobile]
            pair_i = np.empty(n_pairs, dtype=np.int32)
            pair_j = np.empty(n_pairs, dtype=np.int32)
        for i in range(n_mobile):
            c = cells[i]
            cz = c % n_cells[2]
            cy = (c // n_cells[2]) % n_cells[1]
            cx = c // (n_cells[2] * n_cells[1])
            written = 0
            for ox in range(max(cx - 1, 0), min(cx + 2, n_cells[0])):
                for oy in range(max(cy - 1, 0), min(cy + 2, n_cells[1])):
                    for oz in range(max(cz - span_z, 0), min(cz + span_z + 1, n_cells[2])):
                        neighbour_cell = (ox * n_cells[1] + oy) * n_cells[2] + oz
                        for m in range(cell_start[neighbour_cell], cell_start[neighbour_cell + 1]):
                            j = members[m]
                            if j <= i:
                                continue
                            d_sq = 0.0
                            for k in range(dim):
                                d = position[i, k] - position[j, k]
                                d_sq += d * d
                            reach = radius[i] + radius[j] + skin
                            if d_sq < reach * reach:
                                if sweep == 0:
                                    row_count[i + 1] += 1
                                else:
                                    pair_i[row_count[i] + written] = i
                                    pair_j[row_count[i] + written] = j
                                written += 1
            if sweep == 1:  # insertion sort of the row by j (rows are short)
                start = row_count[i]
                for a in range(start + 1, start + written):
                    value = pair_j[a]
                    b = a - 1
                    while b >= start and pair_j[b] > value:
                        pair_j[b + 1] = pair_j[b]
                        b -= 1
                    pair_j[b + 1] = value
    return pair_i, pair_j


@numba.njit(**NJIT_DEM)
def transfer_springs(old_i, old_j, old_spring, n_old, new_slot, new_i, new_j, new_spring, n_total):
    """Carry the tangential history across a rebuild (and a reordering of particles).

    Every old pair with a non-zero spring is mapped through new_slot (old slot → new slot), oriented i < j
    (the spring changes sign when i and j swap: ξ integrates the slip of i relative to j) and looked up in
    the new list (sorted by i, then j). new_spring must be zero on entry. Returns how many non-zero springs
    found no pair in the new list (0 unless the skin was exceeded).
    """
    dim = old_spring.shape[1]
    n_active = 0
    for p in range(n_old):
        for k in range(dim):
            if old_spring[p, k] != 0.0:
                n_active += 1
                break
    keys = np.empty(n_active, dtype=np.int64)
    source = np.empty(n_active, dtype=np.int64)
    signs = np.empty(n_active)
    q = 0
    for p in range(n_old):
        active = False
        for k in range(dim):
            if old_spring[p, k] != 0.0:
                active = True
        if not active:
            continue
        a = new_slot[old_i[p]]
        b = new_slot[old_j[p]]
        sign = 1.0
        if a > b:
            a, b = b, a
            sign = -1.0
        keys[q] = a * n_total + b
        source[q] = p
        signs[q] = sign
        q += 1
    order = np.argsort(keys)
    lost = 0
    cursor = 0
    n_new = new_i.shape[0]
    for t in range(n_active):
        key = keys[order[t]]
        while cursor < n_new and new_i[cursor] * np.int64(n_total) + new_j[cursor] < key:
            cursor += 1
        if cursor < n_new and new_i[cursor] * np.int64(n_total) + new_j[cursor] == key:
            for k in range(dim):
                new_spring[cursor, k] = signs[order[t]] * old_spring[source[order[t]], k]
        else:
            lost += 1
    return lost


# --- two-particle collision (calibration of γ_n) ------------------------------------------------------------

@numba.njit(**NJIT_DEM)
def head_on_collision(k_n, beta, gamma_n, effective_mass, impact_speed, steps_per_collision):
    """Integrate a head-on collision, m_eff ẍ = −max(0, k_n x^(1+β) + γ_n x^β m_eff ẋ), x(0) = 0,
    ẋ(0) = impact_speed (RK4, fixed step), until the overlap x returns to 0.

    Returns (restitution |ẋ_out| / ẋ_in, contact duration). The step is the undamped duration estimate
    divided by steps_per_collision; the exit is located by linear interpolation.
    """
    exponent = 1.0 / (2.0 + beta)
    duration_guess = (3.0 * (effective_mass / k_n) ** exponent * impact_speed ** (-beta * exponent))
    h = duration_guess / steps_per_collision
    k_n = k_n / effective_mass  # the reduced mass divides out of m_eff ẍ = −F
    x = 0.0
    v = impact_speed
    t = 0.0
    for _ in range(100 * steps_per_collision):
        k1x, k1v = v, _collision_acceleration(x, v, k_n, beta, gamma_n)
        k2x, k2v = v + 0.5 * h * k1v, _collision_acceleration(x + 0.5 * h * k1x, v + 0.5 * h * k1v, k_n, beta, gamma_n)
        k3x, k3v = v + 0.5 * h * k2v, _collision_acceleration(x + 0.5 * h * k2x, v + 0.5 * h * k2v, k_n, beta, gamma_n)
        k4x, k4v = v + h * k3v, _collision_acceleration(x + h * k3x, v + h * k3v, k_n, beta, gamma_n)
        x_new = x + h / 6.0 * (k1x + 2.0 * k2x + 2.0 * k3x + k4x)
        v_new = v + h / 6.0 * (k1v + 2.0 * k2v + 2.0 * k3v + k4v)
        if x_new <= 0.0 and t > 0.0:
            fraction = x / (x - x_new)
            v_out = v + fraction * (v_new - v)
            return -v_out / impact_speed, t + fraction * h
        x, v, t = x_new, v_new, t + h
    return np.nan, np.nan


@numba.njit(**NJIT_DEM)
def _collision_acceleration(x, v, k_n_over_m, beta, gamma_n):
    """ẍ of the head-on collision with k_n already divided by m_eff (see `head_on_collision`)."""
    if x <= 0.0:
        return 0.0
    x_beta = _overlap_power(x, beta)
    force = x_beta * (k_n_over_m * x + gamma_n * v)
    return -force if force > 0.0 else 0.0
