"""Slow, obviously correct references for the DEM kernels: an O(N²) loop over every pair, written with numpy
vectors straight from P1 Eq. 1–3 (no neighbour list, no scalar unrolling, 2D handled as 3D with z = 0)."""
from __future__ import annotations

import numpy as np


def _as3(vector) -> np.ndarray:
    out = np.zeros(3)
    vector = np.atleast_1d(np.asarray(vector, dtype=float))
    out[:len(vector)] = vector
    return out


def _spin3(omega, dim) -> np.ndarray:
    return np.array([0.0, 0.0, float(np.ravel(omega)[0])]) if dim == 2 else np.asarray(omega, dtype=float)


def contact(n, overlap, v_rel, w_sum, m_eff, xi, law, dt, scale=1.0):
    """One contact in 3-vectors: n towards i, v_rel = v_i − v_j, w_sum = a_i ω_i + a_j ω_j, xi the spring.
    Returns (normal force vector, tangential force vector, new spring)."""
    k_n, k_t, g_n, g_t, mu, beta = (law[k] for k in ("k_n", "k_t", "gamma_n", "gamma_t", "mu", "beta"))
    x_beta = overlap ** beta * scale
    v_n = float(np.dot(v_rel, n))
    f_n = max(0.0, k_n * overlap ** (1 + beta) * scale - g_n * x_beta * m_eff * v_n)     # P1 Eq. 1
    slip = v_rel - v_n * n - np.cross(w_sum, n)                                          # contact-point slip
    xi = xi + slip * dt
    xi = xi - n * np.dot(n, xi)                                                          # ξ' = ξ − n(n·ξ)
    f_t = -k_t * x_beta * xi - g_t * x_beta * m_eff * slip                               # P1 Eq. 2
    if np.linalg.norm(f_t) > mu * f_n:                                                   # P1 Eq. 3
        ratio = mu * f_n / np.linalg.norm(f_t)
        f_t, xi = f_t * ratio, xi * ratio
    return f_n * n, f_t, xi


def pair_forces(position, velocity, omega, radius, mass, springs, law, dt, radius_scaled=False):
    """Every pair i < j: forces (N, dim), torques (N, 1|3), new springs {(i, j): xi (dim,)}, contacts
    {(i, j): (normal, tangential)} (force on i from j). radius_scaled: every term × √R_eff (the LAMMPS
    convention), R_eff = r_i r_j / (r_i + r_j)."""
    n_part, dim = position.shape
    force = np.zeros((n_part, 3))
    torque = np.zeros((n_part, 3))
    new_springs, contacts = {}, {}
    for i in range(n_part):
        for j in range(i + 1, n_part):
            r = _as3(position[i]) - _as3(position[j])
            dist = np.linalg.norm(r)
            overlap = radius[i] + radius[j] - dist
            if overlap <= 0:
                continue
            n = r / dist
            a_i, a_j = radius[i] - overlap / 2, radius[j] - overlap / 2
            v_rel = _as3(velocity[i]) - _as3(velocity[j])
            w_sum = a_i * _spin3(omega[i], dim) + a_j * _spin3(omega[j], dim)
            m_eff = mass[i] * mass[j] / (mass[i] + mass[j])
            xi = _as3(springs.get((i, j), np.zeros(dim)))
            scale = np.sqrt(radius[i] * radius[j] / (radius[i] + radius[j])) if radius_scaled else 1.0
            f_n, f_t, xi = contact(n, overlap, v_rel, w_sum, m_eff, xi, law, dt, scale)
            force[i] += f_n + f_t
            force[j] -= f_n + f_t
            torque[i] += np.cross(-a_i * n, f_t)
            torque[j] += np.cross(a_j * n, -f_t)
            new_springs[(i, j)] = xi[:dim]
            contacts[(i, j)] = (f_n[:dim], f_t[:dim])
    return force[:, :dim], (torque[:, 2:] if dim == 2 else torque), new_springs, contacts


def flat_wall_forces(position, velocity, omega, radius, mass, wall_lo, wall_hi, wall_speed, springs, law, dt):
    """Flat walls (wall 2k: at wall_lo[k], 2k+1: at wall_hi[k]) moving inward at wall_speed.
    springs {(i, wall): xi}; returns forces, torques, new springs."""
    n_part, dim = position.shape
    force = np.zeros((n_part, 3))
    torque = np.zeros((n_part, 3))
    new_springs = {}
    for i in range(n_part):
        for k in range(dim):
            for side in (0, 1):
                normal = np.zeros(3)
                normal[k] = 1.0 if side == 0 else -1.0
                distance = position[i, k] - wall_lo[k] if side == 0 else wall_hi[k] - position[i, k]
                overlap = radius[i] - distance                                           # x = d_i/2 − r_i
                if overlap <= 0:
                    continue
                v_rel = _as3(velocity[i]) - normal * wall_speed
                w_sum = distance * _spin3(omega[i], dim)
                xi = _as3(springs.get((i, 2 * k + side), np.zeros(dim)))
                f_n, f_t, xi = contact(normal, overlap, v_rel, w_sum, mass[i], xi, law, dt)
                force[i] += f_n + f_t
                torque[i] += np.cross(-distance * normal, f_t)
                new_springs[(i, 2 * k + side)] = xi[:dim]
    return force[:, :dim], (torque[:, 2:] if dim == 2 else torque), new_springs
