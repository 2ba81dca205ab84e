"""Is the explicit contact damping integrable at the run's time step?

The damping forces (P1 Eq. 1–2: γ_n x^β m̄ v_n and γ_t x^β m̄ v_t) are linear in the velocities, so near a
packing they act as ẍ = −M⁻¹ D ẋ on the generalised velocities (translations and rotations), with

    D = Σ_contacts g (b_n b_nᵀ + B_tᵀ B_t),   g = γ x^β m_eff,

b_n the map to the contact's normal relative velocity and B_t the map to its tangential slip (which includes
the rotations: −(l_i ω_i + l_j ω_j) × n, lever l = r − x/2, or r − x against a flat wall). The Gear corrector
with the engine's velocity estimate is stable on ẍ = −c ẋ only for c Δt below `GEAR_DAMPING_BOUND`
(`tests/test_dem_physics.py` measures the bound on the engine's own kernels). Above it the fastest damped mode
grows each step until the Coulomb cap saturates it: the packing never relaxes, and its rotations carry a
kinetic energy 10⁴–10⁵ times that of a stable run (measured on 2d_hertz, docs/decisions.md).

The fastest rate is the largest eigenvalue of M^(−½) D M^(−½), found here by power iteration on the current
contacts (`fastest_damping_rate`). Rates are in 1/τ_c.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

#: largest c Δt at which the Gear corrector with the engine's velocity estimate (r1 + 2 r2) damps ẍ = −ω² x − c ẋ,
#: for ω Δt ≤ 0.3 (1.5 at ω = 0; `test_gear_corrector_with_strong_damping_is_stable_up_to_its_bound`)
GEAR_DAMPING_BOUND = 1.38
#: at most this many power iterations; the estimate approaches the largest eigenvalue from below and stops
#: once it changes by less than POWER_TOLERANCE (relative)
POWER_ITERATIONS = 200
POWER_TOLERANCE = 1e-6


@dataclass(frozen=True)
class DampingContacts:
    """The damped contacts of a state, each between mobile particle i and j (j = −1: a wall, infinite mass).

    i, j (C,) int; normal (C, d) unit vector from j towards i; normal_coefficient, tangential_coefficient (C,)
    g = γ x^β m_eff with γ_n or γ_t [m̄ τ_c⁻¹]; lever_i, lever_j (C,) [d_ave] from each centre to the contact
    point (lever_j ignored for walls).
    """

    i: np.ndarray
    j: np.ndarray
    normal: np.ndarray
    normal_coefficient: np.ndarray
    tangential_coefficient: np.ndarray
    lever_i: np.ndarray
    lever_j: np.ndarray


@dataclass(frozen=True)
class DampingRate:
    """Fastest damping rate [1/τ_c] and the mobile particle (slot) that dominates its mode."""

    rate: float
    particle: int


def _cross_with_normal(rotation: np.ndarray, normal: np.ndarray) -> np.ndarray:
    """ω × n per contact: (C, 1) rotations about z in 2D give ω (−n_y, n_x); (C, 3) in 3D the cross product."""
    if normal.shape[1] == 2:
        return rotation[:, :1] * np.stack([-normal[:, 1], normal[:, 0]], axis=1)
    return np.cross(rotation, normal)


def _cross_transpose(force: np.ndarray, normal: np.ndarray, n_rot: int) -> np.ndarray:
    """The transpose of ω ↦ ω × n applied to force (C, d): (C, 1) = (−n_y, n_x)·f in 2D, n × f in 3D."""
    if n_rot == 1:
        return (-normal[:, 1] * force[:, 0] + normal[:, 0] * force[:, 1])[:, None]
    return np.cross(normal, force)


def damping_matvec(contacts: DampingContacts, velocity: np.ndarray, rotation: np.ndarray):
    """D q for generalised velocities q = (velocity (N, d), rotation (N, 1|3)): returns (force (N, d), torque
    (N, 1|3)), the damping load with the sign of a dissipation (qᵀ D q ≥ 0)."""
    c = contacts
    wall = c.j < 0
    j = np.where(wall, 0, c.j)
    keep = (~wall)[:, None]
    n_rot = rotation.shape[1]
    relative = velocity[c.i] - np.where(keep, velocity[j], 0.0)
    spin = c.lever_i[:, None] * rotation[c.i] + np.where(keep, c.lever_j[:, None] * rotation[j], 0.0)
    along = np.einsum("ck,ck->c", relative, c.normal)
    slip = relative - along[:, None] * c.normal - _cross_with_normal(spin, c.normal)
    slip_load = c.tangential_coefficient[:, None] * slip
    load = (c.normal_coefficient * along)[:, None] * c.normal + slip_load  # (C, d) on i
    moment = -_cross_transpose(slip_load, c.normal, n_rot)
    force = np.zeros_like(velocity)
    torque = np.zeros_like(rotation)
    for k in range(velocity.shape[1]):
        force[:, k] = (np.bincount(c.i, load[:, k], len(velocity))
                       - np.bincount(j, np.where(wall, 0.0, load[:, k]), len(velocity)))
    for k in range(n_rot):
        torque[:, k] = (np.bincount(c.i, c.lever_i * moment[:, k], len(velocity))
                        + np.bincount(j, np.where(wall, 0.0, c.lever_j * moment[:, k]), len(velocity)))
    return force, torque


def fastest_damping_rate(contacts: DampingContacts, mass: np.ndarray, inertia: np.ndarray,
                         iterations: int = POWER_ITERATIONS) -> DampingRate:
    """Largest eigenvalue of M^(−½) D M^(−½) [1/τ_c] by power iteration (deterministic start).

    mass (N,) [m̄]; inertia (N,) [m̄ d_ave²] (the same about every axis). D is positive semi-definite, so the
    Rayleigh quotient of the iterate rises towards the largest eigenvalue.
    """
    n, dim = len(mass), contacts.normal.shape[1]
    n_rot = 1 if dim == 2 else 3
    if len(contacts.i) == 0:
        return DampingRate(0.0, -1)
    scale_v = 1.0 / np.sqrt(mass)[:, None]
    scale_w = 1.0 / np.sqrt(inertia)[:, None]
    rng = np.random.default_rng(0)
    u = rng.standard_normal((n, dim))
    w = rng.standard_normal((n, n_rot))
    rate = 0.0
    for _ in range(iterations):
        norm = np.sqrt(np.sum(u * u) + np.sum(w * w))
        u, w = u / norm, w / norm
        f, t = damping_matvec(contacts, u * scale_v, w * scale_w)
        f, t = f * scale_v, t * scale_w
        previous, rate = rate, float(np.sum(u * f) + np.sum(w * t))
        u, w = f, t
        if abs(rate - previous) <= POWER_TOLERANCE * rate:
            break
    weight = np.sum(u * u, axis=1) + np.sum(w * w, axis=1)
    return DampingRate(rate, int(np.argmax(weight)))


def damping_contacts(sim) -> DampingContacts:
    """The touching contacts of a `forcenet.dem.engine.Simulation` in its current (corrected) state: pairs of
    the Verlet list (a rough-wall particle is an immobile partner, j = −1) and flat-wall contacts."""
    from forcenet.dem._kernels.contacts import pair_constants

    law = sim.contact_law
    beta, gamma_n, gamma_t = law.beta, law.normal_damping, law.tangential_damping
    n, dim = sim.n_mobile, sim.dimension
    particles, pair_i, pair_j = sim.particles, sim.contacts.pair_i, sim.contacts.pair_j
    position, radius = particles.gear_position[0], particles.radius
    pair_mass, pair_scale = pair_constants(pair_i, pair_j, radius, particles.inv_mass, law.radius_scaled)
    pi, pj = pair_i.astype(np.int64), pair_j.astype(np.int64)
    separation = position[pi] - position[pj]
    distance = np.sqrt(np.einsum("pk,pk->p", separation, separation))
    overlap = radius[pi] + radius[pj] - distance
    touching = overlap > 0.0
    pi, pj, overlap = pi[touching], pj[touching], overlap[touching]
    normal = separation[touching] / distance[touching, None]
    weight = overlap ** beta * pair_mass[touching] * pair_scale[touching]  # P1 Eq. 1–2: x^β m̄
    parts = [(pi, np.where(pj < n, pj, -1), normal, weight, radius[pi] - 0.5 * overlap, radius[pj] - 0.5 * overlap)]
    if sim.walls.flat_walls:
        mobile = np.arange(n)
        for axis in range(dim):
            for plane, sign in ((sim.walls_lo[axis], 1.0), (sim.walls_hi[axis], -1.0)):  # inward normals
                gap = sign * (position[:n, axis] - plane)
                wall_overlap = radius[:n] - gap
                on = wall_overlap > 0.0
                wall_normal = np.zeros((int(on.sum()), dim))
                wall_normal[:, axis] = sign
                parts.append((mobile[on], np.full(int(on.sum()), -1), wall_normal,
                              wall_overlap[on] ** beta * particles.mass[:n][on], gap[on], np.zeros(int(on.sum()))))
    i, j, normals, weights, lever_i, lever_j = (np.concatenate(column) for column in zip(*parts))
    return DampingContacts(i=i, j=j, normal=normals.reshape(-1, dim), normal_coefficient=gamma_n * weights,
                           tangential_coefficient=gamma_t * weights, lever_i=lever_i, lever_j=lever_j)


def fastest_damping_rate_of(sim) -> DampingRate:
    """`fastest_damping_rate` of a Simulation's current contacts (mobile particles only)."""
    n = sim.n_mobile
    mass = sim.particles.mass[:n]
    inertia = 1.0 / sim.particles.inv_inertia[:n]
    return fastest_damping_rate(damping_contacts(sim), mass, inertia)


def stable_time_step(rate: float) -> float:
    """Largest Δt [τ_c] at which a damped mode of this rate [1/τ_c] is integrated stably."""
    return GEAR_DAMPING_BOUND / rate if rate > 0.0 else np.inf


__all__ = ["GEAR_DAMPING_BOUND", "DampingContacts", "DampingRate", "damping_matvec", "fastest_damping_rate",
           "damping_contacts", "fastest_damping_rate_of", "stable_time_step"]
