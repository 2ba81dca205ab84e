"""P1 Eq. 4–5: collision-time prefactor, k_n and τ_c, damping for a target restitution."""
import math

import numpy as np
import pytest

from forcenet import units


def test_zeta_values_from_p1():
    assert units.zeta(0.0) == pytest.approx(math.pi, rel=1e-12)
    assert units.zeta(0.5) == pytest.approx(2.9433, abs=5e-5)


def test_linear_collision_time_is_pi_sqrt_m_over_k():
    material = units.Material()
    k_n = units.normal_stiffness_cgs(material, 0.0)
    # P1 Eq. 1 with β = 0: k_n = 2Y d / (3(1 − σ²)), Y in dyn/cm²
    assert k_n == pytest.approx(2 * 234500.0 * 1.735 / (3 * 0.75))
    assert units.collision_time_seconds(material, 0.0) == pytest.approx(math.pi * math.sqrt(3.0 / k_n))
    # reduced units: τ_c = 1 and m̄ = 1 ⇒ k_n = π²
    assert units.reduced_normal_stiffness(material, 0.0) == pytest.approx(math.pi ** 2)


def test_hertz_collision_time_matches_eq4_and_reduced_units_are_consistent():
    material = units.Material()
    beta = 0.5
    k_n = units.normal_stiffness_cgs(material, beta)
    tau = units.collision_time_seconds(material, beta)
    expected = (2.9432 * 1.25 ** 0.4 * (3.0 / k_n) ** 0.4 * 0.01 ** -0.2)
    assert tau == pytest.approx(expected, rel=1e-4)
    # In reduced units the same formula must give exactly 1 τ_c at the reduced v0.
    k_red = units.reduced_normal_stiffness(material, beta)
    v_red = units.reduced_velocity_scale(material, beta)
    assert units.undamped_collision_time(k_red, beta, 1.0, v_red) == pytest.approx(1.0, rel=1e-12)


@pytest.mark.parametrize("beta", [0.0, 0.5])
def test_force_scales_in_dyn(beta):
    material = units.Material()
    tau = units.collision_time_seconds(material, beta)
    assert units.force_unit_dyn(material, beta) == pytest.approx(3.0 * 1.735 / tau ** 2, rel=1e-12)
    # k_n d_ave^(1+β) = 2Y d_ave²/(3(1 − σ²)) for both laws (Y = 234500 dyn/cm²) ...
    assert units.stiffness_force_scale_dyn(material, beta) == pytest.approx(2 * 234500.0 * 1.735 ** 2 / 2.25)
    # ... and the reduced k_n (d_ave = 1) converted to dyn
    assert units.stiffness_force_scale_dyn(material, beta) == pytest.approx(
        units.reduced_normal_stiffness(material, beta) * units.force_unit_dyn(material, beta), rel=1e-12)


def test_collision_time_by_direct_integration_of_undamped_hertz():
    # Integrate m ẍ = −k x^1.5 with a fine leapfrog: the contact lasts P1 Eq. 4.
    k, m, v = 3.0, 0.7, 0.2
    dt = 1e-5
    x, vel, t = 0.0, v, 0.0
    while True:
        vel -= k * max(x, 0.0) ** 1.5 / m * dt
        x += vel * dt
        t += dt
        if x < 0:
            break
    assert t == pytest.approx(units.undamped_collision_time(k, 0.5, m, v), rel=1e-3)


@pytest.mark.parametrize("restitution", [0.3, 0.5, 0.9])
def test_linear_damping_gives_restitution_of_damped_oscillator(restitution):
    k, m = 10.0, 0.5
    gamma = units.linear_damping_for_restitution(k, restitution, m)
    omega = math.sqrt(k / m - gamma ** 2 / 4)
    assert math.exp(-gamma * math.pi / (2 * omega)) == pytest.approx(restitution)
    assert np.isfinite(gamma) and gamma > 0


def test_wall_stiffness_factor_is_the_ratio_of_effective_moduli():
    """P1 Eq. 1's k_n ∝ Y/(1 − σ²) = 2 E* for two bodies of one material; against a wall, 1/E* = (1 − σ²)/Y +
    (1 − σ_w²)/Y_w: a wall of the particles' material gives 1, a rigid one 2, plexiglass (3 GPa, 0.35) 2/(1 + ε)."""
    material = units.Material()
    assert units.wall_stiffness_factor(material, material.young_modulus, material.poisson_ratio) == pytest.approx(1.0)
    assert units.wall_stiffness_factor(material, 1e30, 0.3) == pytest.approx(2.0, rel=1e-12)
    epsilon = (1 - 0.35 ** 2) / 3.0e9 / ((1 - 0.5 ** 2) / 23450.0)  # by hand: 9.146e-6
    assert units.wall_stiffness_factor(material, 3.0e9, 0.35) == pytest.approx(2.0 / (1.0 + epsilon), rel=1e-12)
    assert 1.99998 < units.wall_stiffness_factor(material, 3.0e9, 0.35) < 1.99999
    # a wall softer than the particles makes the contact softer than a pair's
    assert units.wall_stiffness_factor(material, 0.5 * material.young_modulus, material.poisson_ratio) < 1.0
