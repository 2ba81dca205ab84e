"""Reduced units and contact-law constants (P1 §2, Eq. 1–5; P2 Appendix A).

The DEM engine works in reduced units: length d_ave (mean particle diameter), mass m̄ (mean particle
mass), time τ_c (binary collision time of the paper the system comes from). Forces are then in
m̄ d_ave / τ_c², velocities in d_ave / τ_c.

Physical inputs (P1) are CGS: Young's modulus in Pa is converted to dyn/cm² (1 Pa = 10 dyn/cm²).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

PA_TO_DYN_PER_CM2 = 10.0

#: exponent β of the force law: F_n = k_n x^(1+β) (P1 Eq. 1); linear β = 0, Hertz β = 1/2
FORCE_LAW_BETA = {"linear": 0.0, "hertz": 0.5}


def zeta(beta: float) -> float:
    """Prefactor ζ(β) of the collision time, P1 Eq. 5.

    ζ(β) = √π Γ(1/(2+β)) / ((1 + β/2) Γ((4+β)/(4+2β))); ζ(0) = π, ζ(0.5) = 2.9433.
    """
    return (math.sqrt(math.pi) * math.gamma(1.0 / (2.0 + beta))
            / ((1.0 + beta / 2.0) * math.gamma((4.0 + beta) / (4.0 + 2.0 * beta))))


@dataclass(frozen=True)
class Material:
    """P1 material (§2): hydrogel particles.

    young_modulus [Pa], poisson_ratio [-], mean_diameter d_ave [cm], mean_mass m̄ [g],
    velocity_scale v0 [cm/s] (the compression speed, which sets τ_c for Hertzian contacts).
    """

    young_modulus: float = 23450.0
    poisson_ratio: float = 0.5
    mean_diameter: float = 1.735
    mean_mass: float = 3.0
    velocity_scale: float = 0.01


def normal_stiffness_cgs(material: Material, beta: float) -> float:
    """k_n = 2Y / (3(1 − σ²)) d_ave^(1−β), P1 Eq. 1, in dyn / cm^(1+β)."""
    young = material.young_modulus * PA_TO_DYN_PER_CM2
    return 2.0 * young / (3.0 * (1.0 - material.poisson_ratio ** 2)) * material.mean_diameter ** (1.0 - beta)


def wall_stiffness_factor(material: Material, wall_young_modulus: float, wall_poisson_ratio: float) -> float:
    """k_n(wall) / k_n(pair): P1 Eq. 1's stiffness of a particle–wall contact over that of a particle pair [-].

    P1 Eq. 1's k_n = 2Y/(3(1 − σ²)) d_ave^(1−β) is 4/3 E* d_ave^(1−β) with the Hertz effective modulus of two bodies
    of one material, 1/E* = 2(1 − σ²)/Y. Against a wall of another material (Y_w, σ_w; P1 §2: plexiglass)
    1/E* = (1 − σ²)/Y + (1 − σ_w²)/Y_w, the same expression otherwise (P1 keeps d_ave in k_n for every contact). A
    wall of the particles' material gives 1; a rigid wall 2.
    """
    pair = 2.0 * (1.0 - material.poisson_ratio ** 2) / material.young_modulus  # 1/E* of two particles
    wall = (1.0 - material.poisson_ratio ** 2) / material.young_modulus \
        + (1.0 - wall_poisson_ratio ** 2) / wall_young_modulus
    return pair / wall


def collision_time_seconds(material: Material, beta: float) -> float:
    """τ_c of P1 Eq. 4 in seconds.

    τ_c = ζ(β) (1 + β/2)^(1/(2+β)) (m̄ 3(1−σ²) / (2Y d_ave^(1−β)))^(1/(2+β)) v0^(−β/(2+β)),
    the duration of an undamped collision of effective mass m̄ against a contact of stiffness k_n
    at impact speed v0 (for β = 0 it is π √(m̄/k_n), independent of speed).
    """
    k_n = normal_stiffness_cgs(material, beta)
    exponent = 1.0 / (2.0 + beta)
    return (zeta(beta) * (1.0 + 0.5 * beta) ** exponent * (material.mean_mass / k_n) ** exponent
            * material.velocity_scale ** (-beta * exponent))


def reduced_normal_stiffness(material: Material, beta: float) -> float:
    """k_n in reduced units m̄ d_ave^(−β) τ_c^(−2) for a P1 system.

    F = k_n x^(1+β): k_reduced = k_cgs d_ave^β τ_c² / m̄. For β = 0 this is π² exactly.
    """
    tau_c = collision_time_seconds(material, beta)
    return normal_stiffness_cgs(material, beta) * material.mean_diameter ** beta * tau_c ** 2 / material.mean_mass


def force_unit_dyn(material: Material, beta: float) -> float:
    """One reduced force unit m̄ d_ave / τ_c² in dyn, τ_c of P1 Eq. 4 for the law β.

    τ_c differs between the linear and the Hertz law, so do the reduced force units: ⟨F⟩ of two P1 systems
    compares only after conversion (P1 §3 F_max rule).
    """
    return material.mean_mass * material.mean_diameter / collision_time_seconds(material, beta) ** 2


def stiffness_force_scale_dyn(material: Material, beta: float) -> float:
    """k_n d_ave^(1+β) in dyn: the force P1 Eq. 1 gives for an overlap of one mean diameter.

    With k_n of P1 Eq. 1 it is 2Y d_ave² / (3(1 − σ²)), the same for both laws; in reduced units it is the
    reduced k_n (d_ave = 1): `reduced_normal_stiffness` × `force_unit_dyn`.
    """
    return normal_stiffness_cgs(material, beta) * material.mean_diameter ** (1.0 + beta)


def reduced_velocity_scale(material: Material, beta: float) -> float:
    """v0 in d_ave/τ_c: the P1 compression speed in reduced units."""
    return material.velocity_scale * collision_time_seconds(material, beta) / material.mean_diameter


#: P2 App. A: τ_c = π √(d_ave / (2 g k_n)) is the collision time of two mean particles (reduced mass
#: m̄/2) under a linear spring; in units of that τ_c, k_n = π²/2 whatever its value in m̄ g / d_ave.
P2_REDUCED_NORMAL_STIFFNESS = math.pi ** 2 / 2.0


def undamped_collision_time(k_n: float, beta: float, effective_mass: float, impact_speed: float) -> float:
    """Duration of an undamped head-on collision, F = k_n x^(1+β), reduced mass m_eff, speed v.

    Generalises P1 Eq. 4: t = ζ(β) (1 + β/2)^(1/(2+β)) (m_eff/k_n)^(1/(2+β)) v^(−β/(2+β)).
    """
    exponent = 1.0 / (2.0 + beta)
    return (zeta(beta) * (1.0 + 0.5 * beta) ** exponent * (effective_mass / k_n) ** exponent
            * impact_speed ** (-beta * exponent))


def collision_time_damping(restitution: float, collision_time: float = 1.0) -> float:
    """γ_n = −2 ln(e_n) / τ_c: the linear-law relation of P1's ref. [47], in units of 1/`collision_time`.

    For F = k_n x − γ_n m̄ v_n and an effective mass m̄ the overlap decays as exp(−γ_n t/2), so a collision lasting
    τ_c loses the factor e_n of its speed (weak damping; the exact root is `linear_damping_for_restitution`).
    In reduced units (τ_c = 1) γ_n = −2 ln e_n: 1.386 for e_n = 0.5. Applied to a Hertz law (F_n ∝ x^½ v_n) it
    damps a collision at speed v0 far less: the restitution then depends on the overlap reached
    (`forcenet.dem.calibration.collision_restitution`).
    """
    if not 0.0 < restitution <= 1.0:
        raise ValueError(f"restitution must lie in (0, 1], got {restitution}")
    return -2.0 * math.log(restitution) / collision_time


def linear_damping_for_restitution(k_n: float, restitution: float, effective_mass: float) -> float:
    """γ_n for F = k_n x − γ_n m_eff v_n giving restitution e_n (β = 0).

    The overlap obeys ẍ + γ_n ẋ + (k_n/m_eff) x = 0, so e_n = exp(−γ_n π / (2ω)) with
    ω = √(k_n/m_eff − γ_n²/4), hence γ_n = −2 ln(e_n) √(k_n/m_eff) / √(π² + ln² e_n).
    This ignores the cut of the attractive tail at the end of contact (P1 Eq. 1), which raises e_n
    slightly; the DEM calibration (`forcenet.dem.calibration`) corrects for that numerically and handles
    β = 1/2, where no closed form exists.
    """
    log_e = math.log(restitution)
    return -2.0 * log_e * math.sqrt(k_n / effective_mass) / math.sqrt(math.pi ** 2 + log_e ** 2)
