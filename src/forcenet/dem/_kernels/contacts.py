"""Contact forces: the particle pairs of the Verlet list (`pair_forces_2d`, `pair_forces_3d`) and the flat walls
(`flat_wall_forces`), each written once and used both by the time step (`stepping.advance`, record = None) and to
record the forces of a snapshot (record = a `PairRecord` / `WallRecord`), with the contact law of `law.py`
inlined. The 3D pair loop runs in blocks of touching pairs, with the law vectorised over a block (see the
comment above `PAIR_BLOCK`). numba compiles one specialization per kind of record; the time step's has no
recording code at all, so both compute the same forces to the last bit (`tests/test_dem_stepping.py`). For that,
the recording stores only values the step computes anyway (F_n and n, not the product F_n n: a second use of that
multiplication would keep LLVM from fusing it into F_n n + F_t, and the two specializations would round
differently).

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
  are then arguments, held in registers across the loop; the 3D loop passes β and the LAMMPS convention of the
  Hertz law to its law pass as constants); the flat walls read theirs per contact from the float64
  array walls.law. Each loop takes the law as it always has: under NJIT_DEM's contraction LLVM's choice of which
  multiply-adds to fuse depends on it, and so the trajectories stay bit-identical to those of earlier versions.

A pair (i, j) has i < j; n = (r_i − r_j)/|r_i − r_j| points from j to i; forces are "on i from j". Particles
with index ≥ n_mobile are rough-wall particles (infinite mass: m_eff = m_i).
"""
import math

import numba
import numpy as np

from forcenet._numba import NJIT_DEM, NJIT_DEM_INLINE
from forcenet.dem._kernels.law import (LAW_BETA, LAW_GAMMA_N, LAW_GAMMA_T, LAW_K_N, LAW_K_T, LAW_MU, LAW_RADIUS_SCALED,
                                      contact_2d, contact_3d, contact_3d_uncapped, coulomb_cap_3d, sliding_3d)

#: blow-up threshold: overlap / diameter (smaller diameter of the pair)
MAX_OVERLAP_FRACTION = 0.2

#: unsigned offsets of the flat pair loops
U1 = np.uint64(1)
U2 = np.uint64(2)
U3 = np.uint64(3)

# Both pair loops read flat views of the per-particle arrays at unsigned offsets, which drops the stride and
# negative-index arithmetic from every access (−5 to −9 % on the pair loop). The engine lists the pairs touching at
# a rebuild first, so the distance test mispredicts only where a contact opened or closed since.
#
# The 3D loop runs in blocks of up to PAIR_BLOCK touching pairs, in three passes over each block:
#   1. gather (scalar): each listed pair's distance test; an open pair's spring is zeroed there, a touching pair's
#      values (separation, radii, relative velocity, spins, 1/m_i + 1/m_j, spring) go to the block buffer, one
#      contiguous row per value;
#   2. law (vectorised, `_block_law_3d`): the contact law of every pair of the block without the Coulomb cap,
#      from and to the buffer only;
#   3. scatter (scalar): the cap on the few sliding contacts (P1 Eq. 3), springs back, force and torque sums, the
#      worst overlap, the record.
# Pass 2 touches nothing but the buffer, at constant row offsets, so LLVM can prove it free of aliasing and
# vectorises it (with the particle arrays in the same loop it cannot: a gathered load may alias any store); its
# square roots and divisions then run four pairs to an instruction, and the cap's are paid by the sliding
# contacts only. Every pair meets the same operations in the same order as in a one-pass loop, so forces,
# springs and trajectories are the same to the last bit. β and the LAMMPS convention are constants of pass 2 for
# the Hertz law (x^β as a square root, no √R_eff when off): a pow call would keep it scalar, and a per-pair choice
# would do work it discards. The 2D law is short: there the buffer's stores and loads cost what vectorising
# saves (docs/performance.md), and the 2D loop stays one pass.
#
# Measured and dropped (docs/performance.md): in the blocks, every listed pair through pass 2, blocks of 64 or
# 128, a per-pair table of m_eff, particle i's sums kept in registers over its row; in a one-pass loop, a per-pair
# table of m_eff (more memory traffic than the division it saves), a row-wise loop, branch-free and
# two-at-a-time loops, an interleaved per-particle layout; particles re-ordered along a space-filling curve.

#: touching pairs per block of the 3D loop (32 beat 64 and 128 on its pair loop; the buffer stays in L1)
PAIR_BLOCK = 32


# the block buffer's rows, PAIR_BLOCK values each: gathered (pass 1), computed (pass 2), computed for a record only
_ROW_NAMES = ("x y z sq ri rj vx vy vz wix wiy wiz wjx wjy wjz im sx sy sz "
              "fx fy fz cx cy cz li lj excess xix xiy xiz fn nx ny nz ftx fty ftz sliding "
              "overlap").split()
(ROW_X, ROW_Y, ROW_Z, ROW_SQ, ROW_RI, ROW_RJ, ROW_VX, ROW_VY, ROW_VZ, ROW_WIX, ROW_WIY, ROW_WIZ, ROW_WJX, ROW_WJY,
 ROW_WJZ, ROW_IM, ROW_SX, ROW_SY, ROW_SZ,
 ROW_FX, ROW_FY, ROW_FZ, ROW_CX, ROW_CY, ROW_CZ, ROW_LI, ROW_LJ, ROW_EXCESS, ROW_XI_X, ROW_XI_Y, ROW_XI_Z,
 ROW_FN, ROW_NX, ROW_NY, ROW_NZ, ROW_FTX, ROW_FTY, ROW_FTZ, ROW_SLIDING,
 ROW_OVERLAP) = (
    np.uint64(k * PAIR_BLOCK) for k in range(len(_ROW_NAMES)))  # uint64 offsets: no negative-index arithmetic
#: length of the block buffer
BLOCK_BUFFER = len(_ROW_NAMES) * PAIR_BLOCK


@numba.njit(**NJIT_DEM)
def new_pair_block():
    """Scratch of `pair_forces_3d`: the block buffer (BLOCK_BUFFER,) and the block's pair indices (PAIR_BLOCK,)."""
    return np.empty(BLOCK_BUFFER), np.empty(PAIR_BLOCK, dtype=np.int64)


@numba.njit(**NJIT_DEM_INLINE)
def _block_law_3d(n, buf, law, velocity_scale, spring_dt, record):
    """Pass 2 of `pair_forces_3d` on the first n pairs of the block buffer buf (rows ROW_*)."""
    for k in range(n):
        b = np.uint64(k)
        dx = buf[ROW_X + b]
        dy = buf[ROW_Y + b]
        dz = buf[ROW_Z + b]
        r_i = buf[ROW_RI + b]
        r_j = buf[ROW_RJ + b]
        distance = math.sqrt(buf[ROW_SQ + b])
        overlap = (r_i + r_j) - distance
        inv_distance = 1.0 / distance
        nx = dx * inv_distance
        ny = dy * inv_distance
        nz = dz * inv_distance
        lever_i = r_i - 0.5 * overlap
        lever_j = r_j - 0.5 * overlap
        vx = buf[ROW_VX + b] * velocity_scale
        vy = buf[ROW_VY + b] * velocity_scale
        vz = buf[ROW_VZ + b] * velocity_scale
        v_normal = vx * nx + vy * ny + vz * nz
        wx = (lever_i * buf[ROW_WIX + b] + lever_j * buf[ROW_WJX + b]) * velocity_scale
        wy = (lever_i * buf[ROW_WIY + b] + lever_j * buf[ROW_WJY + b]) * velocity_scale
        wz = (lever_i * buf[ROW_WIZ + b] + lever_j * buf[ROW_WJZ + b]) * velocity_scale
        # slip: v_ij − v_n n − (a_i ω_i + a_j ω_j) × n
        slip_x = vx - v_normal * nx - (wy * nz - wz * ny)
        slip_y = vy - v_normal * ny - (wz * nx - wx * nz)
        slip_z = vz - v_normal * nz - (wx * ny - wy * nx)
        m_eff = 1.0 / buf[ROW_IM + b]
        scale = math.sqrt(r_i * r_j / (r_i + r_j)) if law[LAW_RADIUS_SCALED] != 0.0 else 1.0
        # the law without the Coulomb cap: a sliding contact (1–2 % of them on the benchmark states) is capped in
        # the scatter, so that the cap's square root and division are not paid for every pair of the block
        f_n, f_tx, f_ty, f_tz, xi_x, xi_y, xi_z = contact_3d_uncapped(
            law, nx, ny, nz, overlap, v_normal, slip_x, slip_y, slip_z, m_eff, scale,
            buf[ROW_SX + b], buf[ROW_SY + b], buf[ROW_SZ + b], spring_dt)
        fx, fy, fz, cx, cy, cz = _force_and_moment_3d(f_n, nx, ny, nz, f_tx, f_ty, f_tz)
        buf[ROW_XI_X + b] = xi_x
        buf[ROW_XI_Y + b] = xi_y
        buf[ROW_XI_Z + b] = xi_z
        buf[ROW_FX + b] = fx
        buf[ROW_FY + b] = fy
        buf[ROW_FZ + b] = fz
        buf[ROW_CX + b] = cx
        buf[ROW_CY + b] = cy
        buf[ROW_CZ + b] = cz
        buf[ROW_LI + b] = lever_i
        buf[ROW_LJ + b] = lever_j
        buf[ROW_EXCESS + b] = overlap - MAX_OVERLAP_FRACTION * 2.0 * min(r_i, r_j)
        buf[ROW_FN + b] = f_n  # what the cap needs, and the record
        buf[ROW_NX + b] = nx
        buf[ROW_NY + b] = ny
        buf[ROW_NZ + b] = nz
        buf[ROW_FTX + b] = f_tx
        buf[ROW_FTY + b] = f_ty
        buf[ROW_FTZ + b] = f_tz
        buf[ROW_SLIDING + b] = 1.0 if sliding_3d(law[LAW_MU], f_n, f_tx, f_ty, f_tz) else 0.0
        if record is not None:
            buf[ROW_OVERLAP + b] = overlap


@numba.njit(**NJIT_DEM_INLINE)
def _force_and_moment_3d(f_n, nx, ny, nz, f_tx, f_ty, f_tz):
    """The force on i, F_n n + F_t, and n × F_t (τ_i = −a_i n × F_t, τ_j = −a_j n × F_t)."""
    return (f_n * nx + f_tx, f_n * ny + f_ty, f_n * nz + f_tz,
            ny * f_tz - nz * f_ty, nz * f_tx - nx * f_tz, nx * f_ty - ny * f_tx)


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
def pair_forces_3d(motion, bodies, pairs, law, spring_dt, loads, record, block=None):
    """3D version of `pair_forces_2d`: position, velocity, spin, force, torque, spring and the recorded normal
    and tangential (·, 3). Runs in blocks of PAIR_BLOCK touching pairs, the law vectorised over each block (see
    the comment above PAIR_BLOCK); the same forces and springs, to the last bit, as a one-pass loop. block: the
    scratch of a block, `new_pair_block()` (the time step makes it once per call of `advance`), or None to make
    it here."""
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
    count = pairs.count
    if block is None:
        buf, block_pair = new_pair_block()
    else:
        buf, block_pair = block
    k_n = law[LAW_K_N]  # the law's values; β and the LAMMPS convention pick the version of pass 2
    k_t = law[LAW_K_T]
    gamma_n = law[LAW_GAMMA_N]
    gamma_t = law[LAW_GAMMA_T]
    mu = law[LAW_MU]
    beta = law[LAW_BETA]
    radius_scaled = law[LAW_RADIUS_SCALED]
    p = 0
    while p < count:
        n = 0  # 1. gather
        while p < count and n < PAIR_BLOCK:
            i = np.uint32(pair_i[p])
            j = np.uint32(pair_j[p])
            i0 = U3 * i
            j0 = U3 * j
            s = U3 * np.uint64(p)
            dx = x[i0] - x[j0]
            dy = x[i0 + U1] - x[j0 + U1]
            dz = x[i0 + U2] - x[j0 + U2]
            r_i = radius[i]
            r_j = radius[j]
            contact_distance = r_i + r_j
            distance_sq = dx * dx + dy * dy + dz * dz
            if not distance_sq < contact_distance * contact_distance:
                spring[s] = 0.0
                spring[s + U1] = 0.0
                spring[s + U2] = 0.0
                if record is not None:
                    record.overlap[p] = 0.0
                p += 1
                continue
            b = np.uint64(n)
            block_pair[n] = p
            buf[ROW_X + b] = dx
            buf[ROW_Y + b] = dy
            buf[ROW_Z + b] = dz
            buf[ROW_SQ + b] = distance_sq
            buf[ROW_RI + b] = r_i
            buf[ROW_RJ + b] = r_j
            buf[ROW_VX + b] = v[i0] - v[j0]
            buf[ROW_VY + b] = v[i0 + U1] - v[j0 + U1]
            buf[ROW_VZ + b] = v[i0 + U2] - v[j0 + U2]
            buf[ROW_WIX + b] = w[i0]
            buf[ROW_WIY + b] = w[i0 + U1]
            buf[ROW_WIZ + b] = w[i0 + U2]
            buf[ROW_WJX + b] = w[j0]
            buf[ROW_WJY + b] = w[j0 + U1]
            buf[ROW_WJZ + b] = w[j0 + U2]
            buf[ROW_IM + b] = inv_mass[i] + inv_mass[j]
            buf[ROW_SX + b] = spring[s]
            buf[ROW_SY + b] = spring[s + U1]
            buf[ROW_SZ + b] = spring[s + U2]
            n += 1
            p += 1
        # 2. the law, vectorised: Hertz (the 3D law of P1) with β and the LAMMPS convention as constants; any
        # other law as it comes. Not the linear law with constants: x^β = 1 would let LLVM fold the sign of
        # F_t = −x^β(…) into n × F_t and round it differently from the one-pass loop (the linear 3D law is used by
        # the benchmarks and tests only).
        if beta == 0.5 and radius_scaled == 0.0:
            _block_law_3d(n, buf, (k_n, k_t, gamma_n, gamma_t, mu, 0.5, 0.0), velocity_scale, spring_dt, record)
        elif beta == 0.5:
            _block_law_3d(n, buf, (k_n, k_t, gamma_n, gamma_t, mu, 0.5, 1.0), velocity_scale, spring_dt, record)
        else:
            _block_law_3d(n, buf, law, velocity_scale, spring_dt, record)
        for k in range(n):  # 3. scatter
            b = np.uint64(k)
            q = block_pair[k]
            s = U3 * np.uint64(q)
            xi_x = buf[ROW_XI_X + b]
            xi_y = buf[ROW_XI_Y + b]
            xi_z = buf[ROW_XI_Z + b]
            f_tx = buf[ROW_FTX + b]
            f_ty = buf[ROW_FTY + b]
            f_tz = buf[ROW_FTZ + b]
            fx = buf[ROW_FX + b]
            fy = buf[ROW_FY + b]
            fz = buf[ROW_FZ + b]
            cx = buf[ROW_CX + b]
            cy = buf[ROW_CY + b]
            cz = buf[ROW_CZ + b]
            if buf[ROW_SLIDING + b] != 0.0:  # P1 Eq. 3, then the force and moment again
                f_n = buf[ROW_FN + b]
                nx = buf[ROW_NX + b]
                ny = buf[ROW_NY + b]
                nz = buf[ROW_NZ + b]
                f_tx, f_ty, f_tz, xi_x, xi_y, xi_z = coulomb_cap_3d(mu, f_n, f_tx, f_ty, f_tz, xi_x, xi_y, xi_z)
                fx, fy, fz, cx, cy, cz = _force_and_moment_3d(f_n, nx, ny, nz, f_tx, f_ty, f_tz)
            spring[s] = xi_x
            spring[s + U1] = xi_y
            spring[s + U2] = xi_z
            i0 = U3 * np.uint32(pair_i[q])
            j0 = U3 * np.uint32(pair_j[q])
            excess = buf[ROW_EXCESS + b]
            if excess > worst_excess:
                worst_excess = excess
                worst_pair = q
            f[i0] += fx
            f[i0 + U1] += fy
            f[i0 + U2] += fz
            f[j0] -= fx
            f[j0 + U1] -= fy
            f[j0 + U2] -= fz
            lever_i = buf[ROW_LI + b]
            lever_j = buf[ROW_LJ + b]
            t[i0] -= lever_i * cx
            t[i0 + U1] -= lever_i * cy
            t[i0 + U2] -= lever_i * cz
            t[j0] -= lever_j * cx
            t[j0 + U1] -= lever_j * cy
            t[j0 + U2] -= lever_j * cz
            if record is not None:
                record.overlap[q] = buf[ROW_OVERLAP + b]
                record.normal_force[q] = buf[ROW_FN + b]
                record.normal[q, 0] = buf[ROW_NX + b]
                record.normal[q, 1] = buf[ROW_NY + b]
                record.normal[q, 2] = buf[ROW_NZ + b]
                record.tangential[q, 0] = f_tx
                record.tangential[q, 1] = f_ty
                record.tangential[q, 2] = f_tz
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
        # side 0 or 1 by arithmetic, not a branch: the entries' walls follow each other in no pattern, and a branch
        # on the side mispredicted (measured 0.5–4 % on the 3D step). −(x − hi) is hi − x to the last bit.
        axis = wall >> 1
        side = wall & 1
        sign = 1.0 - 2.0 * side
        plane = hi[axis] if side else lo[axis]
        distance = (position[i, axis] - plane) * sign
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
