"""The contact law of P1 Eq. 1–3, written once per dimension (`contact_2d`, `contact_3d`) and inlined into every
loop that evaluates a contact: particle pairs and flat walls, in the time step and in the recording of a snapshot
alike. Also the head-on collision of two particles under the normal law, which calibrates γ_n.

The law comes as its LAW_* values, in a float64 array (`forcenet.dem.engine.ContactLaw.as_array`) or a tuple
of the same values (see `contacts.py` for which loop takes which).
"""
import math

import numba
import numpy as np

from forcenet._numba import NJIT_DEM, NJIT_DEM_INLINE

# --- the contact law's values, by index -------------------------------------------------------------------------
LAW_K_N = 0        # k_n       [m̄ d_ave^(−β) τ_c^(−2)]
LAW_K_T = 1        # k_t       [same]
LAW_GAMMA_N = 2    # γ_n       [d_ave^(−β) τ_c^(−1)]
LAW_GAMMA_T = 3    # γ_t       [same]
LAW_MU = 4         # Coulomb μ [-]
LAW_BETA = 5       # β: 0 linear, 0.5 Hertz (P1 Eq. 1)
LAW_RADIUS_SCALED = 6  # 1: every term also × √R_eff (LAMMPS gran/hertz convention, benchmark only)
LAW_WALL_STIFFNESS = 7  # k_n, k_t of a flat-wall contact over a pair's: 1, or walls of their own material (P1 §2)
LAW_SIZE = 8

#: how x^β is computed: β = 0 (linear law, x^β = 1), β = ½ (Hertz, √x) or any other β (pow)
MODE_LINEAR = 0
MODE_HERTZ = 1
MODE_POWER = 2


@numba.njit(**NJIT_DEM)
def law_mode(beta):
    """MODE_LINEAR for β = 0, MODE_HERTZ for β = ½, MODE_POWER otherwise."""
    if beta == 0.0:
        return MODE_LINEAR
    if beta == 0.5:
        return MODE_HERTZ
    return MODE_POWER


@numba.njit(**NJIT_DEM)
def scaled_overlap_power(overlap, mode, beta, scale):
    """x^β · scale, with the two force laws of P1 special-cased (exact and fast)."""
    if mode == MODE_LINEAR:
        return scale  # = 1.0 · scale
    if mode == MODE_HERTZ:
        return math.sqrt(overlap) * scale
    return overlap ** beta * scale


@numba.njit(**NJIT_DEM_INLINE)
def contact_2d(law, nx, ny, overlap, v_normal, slip_x, slip_y, m_eff, scale, xi_x, xi_y, spring_dt):
    """Force of one contact in 2D (P1 Eq. 1–3).

    n = (nx, ny): unit normal towards i; overlap x > 0 [d_ave]; v_normal = (v_i − v_j)·n [d_ave/τ_c];
    (slip_x, slip_y): tangential slip velocity of the contact points [d_ave/τ_c]; m_eff: reduced mass [m̄];
    scale: extra factor on every term (1, or √R_eff in the LAMMPS convention); (xi_x, xi_y): the
    Cundall–Strack spring before this step [d_ave]; spring_dt: time over which the slip stretches it [τ_c]
    (0 to evaluate without advancing the spring).
    Returns (F_n ≥ 0 along n, F_t x, F_t y, new spring x, new spring y).

    The spring comes first: the caller loads it before the call, and x^β may call sqrt or pow, around which
    anything still waiting for use is spilled (measured: the spring first is ~1.5 % faster on the 3D step).
    """
    # Cundall–Strack: ξ = ∫ v_t dt, then the projection ξ' = ξ − n(n·ξ) (P1 §2)
    xi_x += slip_x * spring_dt
    xi_y += slip_y * spring_dt
    along = xi_x * nx + xi_y * ny
    xi_x -= along * nx
    xi_y -= along * ny
    x_beta = scaled_overlap_power(overlap, law_mode(law[LAW_BETA]), law[LAW_BETA], scale)
    # P1 Eq. 1: F_n = k_n x^(1+β) − γ_n x^β m̄ v_n, never attractive
    f_n = x_beta * (law[LAW_K_N] * overlap - law[LAW_GAMMA_N] * m_eff * v_normal)
    if f_n < 0.0:
        f_n = 0.0
    # P1 Eq. 2: F_t* = −k_t x^β ξ' − γ_t x^β m̄ v_t
    gamma_t_m = law[LAW_GAMMA_T] * m_eff
    f_tx = -x_beta * (law[LAW_K_T] * xi_x + gamma_t_m * slip_x)
    f_ty = -x_beta * (law[LAW_K_T] * xi_y + gamma_t_m * slip_y)
    # P1 Eq. 3: |F_t| ≤ μ|F_n|; the spring is rescaled by the same factor when the cap applies (P2 Eq. A5)
    f_t_sq = f_tx * f_tx + f_ty * f_ty
    f_t_max = law[LAW_MU] * f_n
    if f_t_sq > f_t_max * f_t_max:
        ratio = f_t_max / math.sqrt(f_t_sq)
        f_tx *= ratio
        f_ty *= ratio
        xi_x *= ratio
        xi_y *= ratio
    return f_n, f_tx, f_ty, xi_x, xi_y


@numba.njit(**NJIT_DEM_INLINE)
def contact_3d(law, nx, ny, nz, overlap, v_normal, slip_x, slip_y, slip_z, m_eff, scale, xi_x, xi_y, xi_z,
               spring_dt):
    """3D version of `contact_2d` (P1 Eq. 1–3); returns (F_n, F_t (3), spring (3)). The uncapped law and the
    Coulomb cap are apart (`contact_3d_uncapped`, `coulomb_cap_3d`) for the 3D pair loop, which applies the cap
    to the few sliding contacts after its vectorised pass."""
    f_n, f_tx, f_ty, f_tz, xi_x, xi_y, xi_z = contact_3d_uncapped(
        law, nx, ny, nz, overlap, v_normal, slip_x, slip_y, slip_z, m_eff, scale, xi_x, xi_y, xi_z, spring_dt)
    f_tx, f_ty, f_tz, xi_x, xi_y, xi_z = coulomb_cap_3d(law[LAW_MU], f_n, f_tx, f_ty, f_tz, xi_x, xi_y, xi_z)
    return f_n, f_tx, f_ty, f_tz, xi_x, xi_y, xi_z


@numba.njit(**NJIT_DEM_INLINE)
def contact_3d_uncapped(law, nx, ny, nz, overlap, v_normal, slip_x, slip_y, slip_z, m_eff, scale, xi_x, xi_y, xi_z,
                        spring_dt):
    """P1 Eq. 1–2 in 3D, before the Coulomb cap: (F_n, F_t (3), spring (3)); arguments as in `contact_2d`."""
    xi_x += slip_x * spring_dt
    xi_y += slip_y * spring_dt
    xi_z += slip_z * spring_dt
    along = xi_x * nx + xi_y * ny + xi_z * nz  # ξ' = ξ − n(n·ξ)
    xi_x -= along * nx
    xi_y -= along * ny
    xi_z -= along * nz
    x_beta = scaled_overlap_power(overlap, law_mode(law[LAW_BETA]), law[LAW_BETA], scale)
    f_n = x_beta * (law[LAW_K_N] * overlap - law[LAW_GAMMA_N] * m_eff * v_normal)  # P1 Eq. 1
    if f_n < 0.0:
        f_n = 0.0
    gamma_t_m = law[LAW_GAMMA_T] * m_eff
    f_tx = -x_beta * (law[LAW_K_T] * xi_x + gamma_t_m * slip_x)  # P1 Eq. 2
    f_ty = -x_beta * (law[LAW_K_T] * xi_y + gamma_t_m * slip_y)
    f_tz = -x_beta * (law[LAW_K_T] * xi_z + gamma_t_m * slip_z)
    return f_n, f_tx, f_ty, f_tz, xi_x, xi_y, xi_z


@numba.njit(**NJIT_DEM_INLINE)
def sliding_3d(mu, f_n, f_tx, f_ty, f_tz):
    """Whether |F_t| > μ F_n, the test of P1 Eq. 3 (without a square root)."""
    f_t_sq = f_tx * f_tx + f_ty * f_ty + f_tz * f_tz
    f_t_max = mu * f_n
    return f_t_sq > f_t_max * f_t_max


@numba.njit(**NJIT_DEM_INLINE)
def coulomb_cap_3d(mu, f_n, f_tx, f_ty, f_tz, xi_x, xi_y, xi_z):
    """P1 Eq. 3: |F_t| ≤ μ F_n; F_t and the spring rescaled by the same factor when the cap applies (P2 Eq. A5).
    Returns (F_t (3), spring (3))."""
    if sliding_3d(mu, f_n, f_tx, f_ty, f_tz):
        ratio = mu * f_n / math.sqrt(f_tx * f_tx + f_ty * f_ty + f_tz * f_tz)
        f_tx *= ratio
        f_ty *= ratio
        f_tz *= ratio
        xi_x *= ratio
        xi_y *= ratio
        xi_z *= ratio
    return f_tx, f_ty, f_tz, xi_x, xi_y, xi_z


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
    mode = law_mode(beta)
    x = 0.0
    v = impact_speed
    t = 0.0
    for _ in range(100 * steps_per_collision):
        k1x, k1v = v, _collision_acceleration(x, v, k_n, mode, beta, gamma_n)
        k2x, k2v = v + 0.5 * h * k1v, _collision_acceleration(x + 0.5 * h * k1x, v + 0.5 * h * k1v, k_n, mode, beta,
                                                               gamma_n)
        k3x, k3v = v + 0.5 * h * k2v, _collision_acceleration(x + 0.5 * h * k2x, v + 0.5 * h * k2v, k_n, mode, beta,
                                                               gamma_n)
        k4x, k4v = v + h * k3v, _collision_acceleration(x + h * k3x, v + h * k3v, k_n, mode, beta, gamma_n)
        x_new = x + h / 6.0 * (k1x + 2.0 * k2x + 2.0 * k3x + k4x)
        v_new = v + h / 6.0 * (k1v + 2.0 * k2v + 2.0 * k3v + k4v)
        if x_new <= 0.0 and t > 0.0:
            fraction = x / (x - x_new)
            v_out = v + fraction * (v_new - v)
            return -v_out / impact_speed, t + fraction * h
        x, v, t = x_new, v_new, t + h
    return np.nan, np.nan


@numba.njit(**NJIT_DEM)
def _collision_acceleration(x, v, k_n_over_m, mode, beta, gamma_n):
    """ẍ of the head-on collision with k_n already divided by m_eff (see `head_on_collision`)."""
    if x <= 0.0:
        return 0.0
    x_beta = scaled_overlap_power(x, mode, beta, 1.0)
    force = x_beta * (k_n_over_m * x + gamma_n * v)
    return -force if force > 0.0 else 0.0
