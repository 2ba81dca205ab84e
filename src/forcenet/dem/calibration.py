"""The normal damping γ_n from the restitution coefficient e_n (P1 gives no e_n; we use 0.5).

Two damping models, chosen per system by `systems.<name>.damping_model` (docs/decisions.md, "Damping"):

``linear_law`` (the Hertz systems' default)
    γ_n = −2 ln(e_n)/τ_c (`forcenet.units.collision_time_damping`), the linear-law relation of P1's ref. [47],
    applied in the system's own τ_c units whatever β. It is the damping that lets P1's own time steps (0.02 τ_c
    in 2D, 0.005 τ_c in 3D) integrate compressed Hertz packings; a Hertz collision at v0 is then nearly
    elastic (e ≈ 0.996 in P1 units).
``head_on`` (the linear systems' default)
    γ_n is chosen so that a binary head-on collision of two *mean* particles (mass m̄ each, reduced mass m̄/2)
    has restitution e_n under the engine's own normal law, F_n = max(0, k_n x^(1+β) − γ_n x^β m_eff v_n)
    (P1 Eq. 1, never attractive):

* linear (β = 0): the closed form `forcenet.units.linear_damping_for_restitution` ignores the cut of the
  attractive tail, which raises e_n; the value used here is the root of the numerically integrated
  collision (speed independent), started from the closed form.
* Hertz (β = 1/2): no closed form, and e_n depends weakly on the impact speed (1 − e_n grows ∝ v^(1/5)).
  The collision is integrated at the system's compression speed (`SystemSpec.wall_speed`: P1's v0, the
  "characteristic velocity" at which P1 Eq. 4 defines τ_c).

The collision is integrated with RK4 at 4000 steps per collision (`_kernels.law.head_on_collision`); the
bisection stops at a relative tolerance of 1e-10 on γ_n.
"""
from __future__ import annotations

import functools

from forcenet import units
from forcenet.dem._kernels.law import head_on_collision

#: reduced mass of two mean particles [m̄]: the calibration collision
MEAN_PAIR_EFFECTIVE_MASS = 0.5
STEPS_PER_COLLISION = 4000


def collision_restitution(normal_stiffness: float, beta: float, normal_damping: float, effective_mass: float,
                          impact_speed: float) -> float:
    """Restitution e_n of a head-on collision (exact law, RK4) [-]."""
    e, _ = head_on_collision(normal_stiffness, beta, normal_damping, effective_mass, impact_speed,
                             STEPS_PER_COLLISION)
    return float(e)


def collision_duration(normal_stiffness: float, beta: float, normal_damping: float, effective_mass: float,
                       impact_speed: float) -> float:
    """Contact duration of a head-on collision [τ_c]; undamped it is P1 Eq. 4 (`units.undamped_collision_time`)."""
    _, duration = head_on_collision(normal_stiffness, beta, normal_damping, effective_mass, impact_speed,
                                    STEPS_PER_COLLISION)
    return float(duration)


@functools.lru_cache(maxsize=64)
def normal_damping_for_restitution(normal_stiffness: float, beta: float, restitution: float,
                                   effective_mass: float = MEAN_PAIR_EFFECTIVE_MASS,
                                   impact_speed: float = 1.0) -> float:
    """γ_n [d_ave^(−β) τ_c^(−1)] such that a head-on collision (reduced mass effective_mass [m̄], relative
    speed impact_speed [d_ave/τ_c]) has restitution `restitution`. e_n = 1 gives 0."""
    if not 0.0 < restitution <= 1.0:
        raise ValueError(f"restitution must lie in (0, 1], got {restitution}")
    if restitution == 1.0:
        return 0.0

    def excess(gamma: float) -> float:
        return collision_restitution(normal_stiffness, beta, gamma, effective_mass, impact_speed) - restitution

    # exact for β = 0 up to the tail cut; for β = 1/2 only a starting bracket
    guess = units.linear_damping_for_restitution(normal_stiffness, restitution, effective_mass)
    low, high = 0.0, max(guess, 1e-12)
    while excess(high) > 0.0:  # e_n falls as γ_n grows
        low, high = high, 2.0 * high
        if high > 1e12:
            raise RuntimeError("no damping reaches the requested restitution")
    for _ in range(200):
        middle = 0.5 * (low + high)
        if excess(middle) > 0.0:
            low = middle
        else:
            high = middle
        if high - low <= 1e-10 * high:
            break
    return 0.5 * (low + high)


#: values of `systems.<name>.damping_model`
DAMPING_MODELS = ("linear_law", "head_on", "explicit")


def normal_damping_for_system(system) -> float:
    """γ_n [d_ave^(−β) τ_c^(−1)] of a `forcenet.systems.SystemSpec` under its `damping_model`: the linear-law
    relation −2 ln(e_n)/τ_c, or the head-on calibration (two mean particles, impact speed = the wall speed for
    Hertz; the linear law's restitution does not depend on speed)."""
    if system.damping_model == "linear_law":
        return units.collision_time_damping(system.restitution)
    if system.damping_model == "explicit":
        return float(system.normal_damping)
    if system.damping_model != "head_on":
        raise ValueError(f"unknown damping model {system.damping_model!r} (known: {DAMPING_MODELS})")
    speed = 1.0 if system.beta == 0.0 else system.wall_speed
    return normal_damping_for_restitution(system.normal_stiffness, system.beta, system.restitution,
                                          MEAN_PAIR_EFFECTIVE_MASS, speed)


__all__ = ["collision_restitution", "collision_duration", "normal_damping_for_restitution",
           "normal_damping_for_system", "MEAN_PAIR_EFFECTIVE_MASS", "DAMPING_MODELS"]
