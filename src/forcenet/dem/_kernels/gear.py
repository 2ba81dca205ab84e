"""The Gear predictor–corrector (4th order: 5 values) of the DEM time step (Allen & Tildesley §3.2, Table E.2).

Positions and their time derivatives are held as Gear "scaled derivatives" ``gear[k] = Δt^k / k! · d^k r / dt^k``
for k = 0..4, shape (5, N, C) with C = d for translation and C = 1 (2D, rotation about z) or 3 (3D) for rotation.
The rotation's row 0 would be the integrated angle: meaningless in 3D (the components of ω do not integrate to an
orientation), and in 2D a disk's angle enters no force. Nothing reads it, so the time step does not integrate it
(`integrate_row0=False`; it stays as the state holds it, 0): the rotation's Gear pass then streams four rows
instead of five (a faster 3D step below jamming, where the Gear pass is half of it: docs/performance.md). Only the
first n_mobile particles are integrated (the others are rough-wall particles, moved by
`stepping.place_wall_particles`).
"""
import numba
import numpy as np

from forcenet._numba import NJIT_DEM

#: Gear corrector coefficients for a second-order equation with 5 values (Allen & Tildesley Table E.2)
GEAR_C0 = 19.0 / 120.0
GEAR_C1 = 3.0 / 4.0
GEAR_C3 = 1.0 / 2.0
GEAR_C4 = 1.0 / 12.0


@numba.njit(**NJIT_DEM)
def gear_predict(gear, n_mobile, force_velocity, load, integrate_row0=True):
    """Taylor (Pascal-triangle) prediction of the scaled derivatives gear (5, N, C), particles < n_mobile, row 0
    only if integrate_row0 (see the module docstring); their rows of load (N, C) (the force or torque about to be
    summed) are cleared in the same pass.

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
        if integrate_row0:
            r0[j] += a1 + a2 + a3 + a4
        r1[j] = a1 + 2.0 * a2 + 3.0 * a3 + 4.0 * a4
        r2[j] = a2 + 3.0 * a3 + 6.0 * a4
        r3[j] = a3 + 4.0 * a4
        f[j] = 0.0


# `gear_correct_predict` runs in blocks of GEAR_BLOCK components, in three passes over each block:
#   1. the corrector and the next prediction (`_block_correct_predict`): it reads the Gear values, the load and the
#      per-component scales from their arrays and writes the new values only into the block buffer, one row each;
#   2. the buffer's rows copied back (one loop per destination array), the load rows cleared;
#   3. the kinetic energy summed from the buffer in four interleaved partial sums.
# Pass 1 writes one array only, so LLVM needs a few run-time overlap tests to vectorise it (four components to an
# instruction); a one-pass loop writes eight arrays, every store may alias every load, and it stays scalar. The
# passes are functions of their own, not inlined in numba's IR: inlined, the views they take are reference-counted
# in every block, and the pass was slower than the one-pass loop. Every component meets the same operations in the
# same order as in a one-pass loop, and the partial sums take the same components in the same order: the values and
# the energy are the same to the last bit.

#: components per block of `gear_correct_predict`: a multiple of 4 (the energy's partial sums); the buffer (14 kB)
#: stays in L1. On a loose 4096-sphere state (ρ = 0.53) the 3D step was 3 % faster with 256 than with 128, which
#: was 6 % faster than with 64; 512 was no faster than 256.
GEAR_BLOCK = 256
_GEAR_ROW_NAMES = ("r0", "r1", "r2", "r3", "r4", "velocity", "energy")
GEAR_ROW_R0, GEAR_ROW_R1, GEAR_ROW_R2, GEAR_ROW_R3, GEAR_ROW_R4, GEAR_ROW_VELOCITY, GEAR_ROW_ENERGY = (
    np.uint64(k * GEAR_BLOCK) for k in range(len(_GEAR_ROW_NAMES)))  # uint64 offsets: no negative-index arithmetic


@numba.njit(**NJIT_DEM)
def new_gear_block():
    """Scratch of `gear_correct_predict`: the block buffer (7 · GEAR_BLOCK,)."""
    return np.empty(len(_GEAR_ROW_NAMES) * GEAR_BLOCK)


@numba.njit(**NJIT_DEM)
def _block_correct_predict(buf, start, count, r0, r1, r2, r3, r4, f, scale, weight):
    """Pass 1 of `gear_correct_predict` on components start … start + count − 1: the corrected-and-predicted
    values and weight · r1² (after the correction) into the rows of buf; the arrays are only read. r0 None: row 0
    is not integrated (numba compiles that case apart, without it)."""
    for k in range(count):
        j = np.uint64(start + k)
        b = np.uint64(k)
        delta = scale[j] * f[j] - r2[j]
        a1 = r1[j] + GEAR_C1 * delta
        a2 = r2[j] + delta
        a3 = r3[j] + GEAR_C3 * delta
        a4 = r4[j] + GEAR_C4 * delta
        buf[GEAR_ROW_VELOCITY + b] = a1 + 2.0 * a2
        if r0 is not None:
            buf[GEAR_ROW_R0 + b] = (r0[j] + GEAR_C0 * delta) + (a1 + a2 + a3 + a4)  # corrected, then the Taylor step
        buf[GEAR_ROW_R1 + b] = a1 + 2.0 * a2 + 3.0 * a3 + 4.0 * a4
        buf[GEAR_ROW_R2 + b] = a2 + 3.0 * a3 + 6.0 * a4
        buf[GEAR_ROW_R3 + b] = a3 + 4.0 * a4
        buf[GEAR_ROW_R4 + b] = a4
        buf[GEAR_ROW_ENERGY + b] = weight[j] * a1 * a1


@numba.njit(**NJIT_DEM)
def _copy_row(target, start, buf, row, count):
    """target[start + k] = buf[row + k], k < count (pass 2 of `gear_correct_predict`)."""
    for k in range(count):
        target[np.uint64(start + k)] = buf[row + np.uint64(k)]


@numba.njit(**NJIT_DEM)
def gear_correct_predict(gear, load, accel_scale, half_weight, n_mobile, force_velocity, block=None,
                         integrate_row0=True):
    """Gear 5-value corrector of this step followed by `gear_predict` of the next, in one pass over gear
    (5, N, C), particles < n_mobile: the new acceleration term is accel_scale · load, with accel_scale (N, C) =
    Δt²/2 · (1/m or 1/I) of each component, and the corrected values are the old ones + (C0, C1, 1, C3, C4) ·
    (accel_scale · load − r2). One pass has half the memory traffic of two (measured +6 to +13 % on the 3D
    step). Returns the kinetic energy × Δt² of the corrected state,
    Σ half_weight · r1², with half_weight (N, C) = ½ m or ½ I per component, summed in four interleaved partial
    sums (component j in sum j mod 4, the tail past the last multiple of 4 in the first; a fixed order:
    deterministic). On return gear holds the prediction for the next step, force_velocity its r1 + 2 r2 and load
    is cleared, as after `gear_predict`; `gear_unpredict` recovers the corrected state. Runs in blocks of
    GEAR_BLOCK components (see the comment above GEAR_BLOCK); block: the scratch, `new_gear_block()` (the time
    step makes it once per call of `advance`), or None to make it here. integrate_row0: False leaves row 0 as it is
    (the rotation's, see the module docstring)."""
    r0 = gear[0].reshape(-1)
    r1 = gear[1].reshape(-1)
    r2 = gear[2].reshape(-1)
    r3 = gear[3].reshape(-1)
    r4 = gear[4].reshape(-1)
    f = load.reshape(-1)
    v = force_velocity.reshape(-1)
    scale = accel_scale.reshape(-1)
    weight = half_weight.reshape(-1)
    buf = new_gear_block() if block is None else block
    n = n_mobile * gear.shape[2]
    e0 = 0.0
    e1 = 0.0
    e2 = 0.0
    e3 = 0.0
    for start in range(0, n, GEAR_BLOCK):
        count = min(GEAR_BLOCK, n - start)
        if integrate_row0:
            _block_correct_predict(buf, start, count, r0, r1, r2, r3, r4, f, scale, weight)
            _copy_row(r0, start, buf, GEAR_ROW_R0, count)
        else:
            _block_correct_predict(buf, start, count, None, r1, r2, r3, r4, f, scale, weight)
        _copy_row(r1, start, buf, GEAR_ROW_R1, count)
        _copy_row(r2, start, buf, GEAR_ROW_R2, count)
        _copy_row(r3, start, buf, GEAR_ROW_R3, count)
        _copy_row(r4, start, buf, GEAR_ROW_R4, count)
        _copy_row(v, start, buf, GEAR_ROW_VELOCITY, count)
        for k in range(count):
            f[np.uint64(start + k)] = 0.0
        whole = count - count % 4  # start is a multiple of 4: lane k % 4 is lane j % 4
        for k in range(0, whole, 4):
            b = GEAR_ROW_ENERGY + np.uint64(k)
            e0 += buf[b]
            e1 += buf[b + np.uint64(1)]
            e2 += buf[b + np.uint64(2)]
            e3 += buf[b + np.uint64(3)]
        for k in range(whole, count):  # the tail (last block only)
            e0 += buf[GEAR_ROW_ENERGY + np.uint64(k)]
    return (e0 + e1) + (e2 + e3)


@numba.njit(**NJIT_DEM)
def gear_unpredict(gear, n_mobile, integrate_row0=True):
    """Undo `gear_predict`'s Taylor step on gear (5, N, C), particles < n_mobile (the inverse Pascal matrix;
    exact up to rounding): back to the corrected state after `gear_correct_predict`. Row 0 only if
    integrate_row0."""
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
        if integrate_row0:
            r0[j] -= a1 + a2 + a3 + a4
        r1[j] = a1
        r2[j] = a2
        r3[j] = a3
