"""The physical checks that need only the config (`forcenet.checks`): each against a hand computation, with a case
that satisfies it and one that violates it, and the shipped configs (P1's Hertz steps included) passing them."""
from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from conftest import load_config
from forcenet import checks, units
from forcenet.dem import packing
from forcenet.checks import validate_config
from forcenet.systems import ConfigError, system_from_config


def spec(name="2d_linear", **changes):
    return dataclasses.replace(system_from_config(name, load_config()), **changes)


def problem_keys(system):
    return [p.key for p in checks.system_problems(system)]


@pytest.mark.parametrize("config", ["config.yaml", "paper.yaml", "smoke.yaml", "validation.yaml"])
def test_shipped_configs_pass_every_check(config):
    systems = validate_config(load_config(config))
    hertz = {name: s.time_step for name, s in systems.items() if s.force_law == "hertz"}
    assert hertz["2d_hertz"] == 0.02 and hertz["3d_hertz"] == 0.005  # P1's steps are accepted


def test_densest_packing_margin_by_hand():
    assert checks.DENSEST_PACKING[2] == pytest.approx(0.906900, abs=1e-6)
    assert checks.DENSEST_PACKING[3] == pytest.approx(0.740480, abs=1e-6)
    assert checks.max_packing_fraction(2) == pytest.approx(0.9069 / 0.998 ** 2, abs=1e-4)  # 0.9105
    assert checks.max_packing_fraction(3) == 0.739  # below 0.7405 at the grid's three decimals (0.740)


@pytest.mark.parametrize("good, bad", [(0.91, 0.92), (0.91, 0.911)])
def test_a_2d_grid_may_end_at_p1s_091_and_not_past_the_margin(good, bad):
    """Issue 27's grid (ρ 0.92 in 2D: 14 % overlaps), which the earlier 1 % margin admitted, is refused; P1's own
    grid end (0.91, above equal disks' 0.9069 by less than the 0.2 % margin) passes."""
    system = spec("2d_linear")
    assert "rho" not in problem_keys(dataclasses.replace(system, rho_grid=system.rho_grid[:-1] + (good,)))
    problem = checks.system_problems(dataclasses.replace(system, rho_grid=system.rho_grid[:-1] + (bad,)))[0]
    assert problem.key == "rho" and problem.message == (
        f"the last ρ = {bad} is above 0.9105, the densest packing of equal disks (0.9069) compressed to a uniform "
        "overlap of 0.2% of a diameter: lower the grid's stop")


@pytest.mark.parametrize("good, bad", [(0.71, 0.74), (0.739, 0.74), (0.739, 0.76)])
def test_a_3d_grid_stays_below_the_densest_packing_of_spheres(good, bad):
    """Issue 57 W1: a 3D grid to 0.74 (0.7405 at three decimals is 0.740) passed the dry run and blew up at job time;
    now the dry run refuses it, naming the key; P1's 0.71 and 0.739 pass."""
    system = spec("3d_hertz")
    assert "rho" not in problem_keys(dataclasses.replace(system, rho_grid=system.rho_grid[:-1] + (good,)))
    problem = checks.system_problems(dataclasses.replace(system, rho_grid=system.rho_grid[:-1] + (bad,)))[0]
    assert problem.key == "rho" and problem.message == (
        f"the last ρ = {bad} is at or above the densest packing of equal spheres, π/(3√2) = 0.7405 (0.740 at the "
        "grid's 3 decimals), which a disordered packing never reaches (the engine stops at its 20% overlap limit): "
        "end the grid at 0.739 or below")


def test_rho_grid_against_the_initial_lattice_bidisperse_is_exact():
    system = spec("2d_linear")
    rho0 = packing.initial_packing(system, np.random.default_rng(3)).packing_fraction
    assert checks.initial_packing_fraction_bound(system) == pytest.approx(rho0, rel=1e-12)
    assert "rho" in problem_keys(dataclasses.replace(system, rho_grid=(round(rho0, 3) - 0.001, 0.8)))
    assert "rho" not in problem_keys(dataclasses.replace(system, rho_grid=(round(rho0, 3) + 0.002, 0.8)))


def test_polydisperse_lattice_bound_covers_every_seed():
    system = spec("2d_poly_mu05", box_length=8.0)
    bound = checks.initial_packing_fraction_bound(system)
    draws = [packing.initial_packing(system, np.random.default_rng(seed)).packing_fraction for seed in range(200)]
    assert max(draws) < bound
    # expectation: n π/4 E[d²] / L², E[d²] = 1 + r_p²/12 for d uniform in 1 ± r_p/2
    n = packing.sites_per_axis(system) ** 2
    expected = n * math.pi / 4 * (1 + 0.4 ** 2 / 12) / 8.0 ** 2
    assert np.mean(draws) == pytest.approx(expected, rel=0.01)
    fourth = (1.2 ** 5 - 0.8 ** 5) / (5 * 0.4)  # E[d⁴]
    sigma = math.sqrt(n) * math.pi / 4 * math.sqrt(fourth - (1 + 0.4 ** 2 / 12) ** 2) / 8.0 ** 2
    assert bound == pytest.approx(expected + checks.INITIAL_RHO_SIGMAS * sigma)


def test_the_walls_must_reach_the_last_rho():
    system = spec("2d_linear", box_length=3.5, rho_grid=(0.6, 0.9))  # 2 x 2 lattice: the box would shrink to 1.84
    problem = checks.system_problems(system)[0]
    assert problem.key == "rho" and "narrower than" in problem.message
    assert problem_keys(spec("2d_linear", box_length=8.0, rho_grid=(0.6, 0.9))) == []


def test_time_step_against_the_lightest_pair_by_hand():
    """P2 units: k_n = π²/2, so two particles of mass m collide for π √(m/2 / k_n) = √m τ_c (speed-free)."""
    system = spec("2d_poly_mu05")
    d_min = 1 - 0.4 / 2
    mass = d_min ** 2 / (1 + 0.4 ** 2 / 12)  # masses ∝ d², mean 1
    duration, lightest, _ = checks.shortest_collision_time(system)
    assert lightest == pytest.approx(mass) and duration == pytest.approx(math.sqrt(mass))
    limit = math.sqrt(mass) / checks.MIN_STEPS_PER_COLLISION
    assert problem_keys(dataclasses.replace(system, time_step=0.99 * limit)) == []
    assert problem_keys(dataclasses.replace(system, time_step=1.01 * limit)) == ["time_step"]


def test_hertz_collision_time_shortens_with_speed():
    system = spec("2d_hertz")
    slow, _, _ = checks.shortest_collision_time(dataclasses.replace(system, initial_speed=0.01))
    fast, _, _ = checks.shortest_collision_time(dataclasses.replace(system, initial_speed=0.32))
    assert fast / slow == pytest.approx(32 ** -0.2)  # t ∝ v^(−β/(2+β)) = v^(−1/5), P1 Eq. 4
    assert problem_keys(dataclasses.replace(system, initial_speed=0.32)) == ["time_step"]


@pytest.mark.parametrize("name, factor", [("2d_linear", 3.0), ("3d_hertz", 3.5)])
def test_one_contact_damps_its_slip_at_three_or_three_and_a_half_gamma(name, factor):
    """Slip of one contact: γ m_eff (1/m_i + 1/m_j + r²/I_i + r²/I_j) = 3 γ (disks), 3.5 γ (spheres)."""
    assert checks.single_contact_damping_rate(spec(name), 2.0) == pytest.approx(factor * 2.0, rel=1e-5)


def test_damping_against_the_gear_bound_for_the_linear_law():
    system = spec("2d_linear", damping_model="linear_law", time_step=0.06)  # within the collision check (0.0615)
    strong = dataclasses.replace(system, restitution=0.01)  # γ = 2 ln 100 = 9.2: 3 γ Δt = 1.66 > 1.38
    assert checks.normal_damping_estimate(strong) == pytest.approx(-2 * math.log(0.01))
    problem = checks.system_problems(strong)
    assert [p.key for p in problem] == ["time_step"] and "Gear" in problem[0].message
    assert problem_keys(dataclasses.replace(system, restitution=0.1)) == []  # 3 γ Δt = 0.83
    head_on = dataclasses.replace(system, damping_model="head_on", restitution=0.5)
    assert checks.normal_damping_estimate(head_on) == pytest.approx(
        units.linear_damping_for_restitution(system.normal_stiffness, 0.5, 0.5))
    assert checks.normal_damping_estimate(spec("2d_hertz")) is None  # grows with overlap: checked per snapshot


def test_config_validation_names_the_key():
    config = load_config()
    config["systems"]["3d_hertz"]["rho"] = {"start": 0.5, "stop": 0.78, "step": 0.02}
    with pytest.raises(ConfigError, match=r"systems\.3d_hertz\.rho.*densest"):
        validate_config(config)
