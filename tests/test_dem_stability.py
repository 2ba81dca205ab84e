"""The damping-stability check (`forcenet.dem.stability`): the damping operator against a dense construction,
its fastest rate against hand-countable contacts and a dense eigen-solve, and the protocol refusing to write a
snapshot whose contact damping is too fast for Δt."""
from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest
import xarray as xr

from forcenet.dem import stability
from forcenet.dem.protocol import SimulationBlowUp
from conftest import load_config
from forcenet.systems import Relaxation, system_from_config
from test_dem_protocol import run, tiny


def contacts(i, j, normal, g_n, g_t, lever_i, lever_j):
    return stability.DampingContacts(i=np.asarray(i), j=np.asarray(j), normal=np.asarray(normal, dtype=float),
                                     normal_coefficient=np.asarray(g_n, dtype=float),
                                     tangential_coefficient=np.asarray(g_t, dtype=float),
                                     lever_i=np.asarray(lever_i, dtype=float), lever_j=np.asarray(lever_j, dtype=float))


def test_one_disk_on_a_wall_has_the_rates_of_its_two_modes():
    """Normal: g_n / m. Tangential slip u_t − l ω: g_t (1/m + l²/I)."""
    mass, inertia, lever = np.array([2.0]), np.array([0.3]), 0.45
    normal_only = contacts([0], [-1], [[0.0, 1.0]], [10.0], [0.0], [lever], [0.0])
    assert stability.fastest_damping_rate(normal_only, mass, inertia).rate == pytest.approx(10.0 / 2.0)
    tangential_only = contacts([0], [-1], [[0.0, 1.0]], [0.0], [10.0], [lever], [0.0])
    expected = 10.0 * (1 / 2.0 + lever ** 2 / 0.3)
    assert stability.fastest_damping_rate(tangential_only, mass, inertia).rate == pytest.approx(expected)


@pytest.mark.parametrize("dim", [2, 3])
def test_a_pair_has_the_rates_of_its_relative_modes(dim):
    """Two particles, one contact: normal g_n (1/m_i + 1/m_j), slip g_t (1/m_i + 1/m_j + l_i²/I_i + l_j²/I_j)."""
    mass, inertia = np.array([1.0, 3.0]), np.array([0.1, 0.4])
    normal = np.eye(dim)[0]
    g_n, g_t, li, lj = 4.0, 2.0, 0.4, 0.6
    pair = contacts([0], [1], [normal], [g_n], [g_t], [li], [lj])
    both = g_n * (1 + 1 / 3), g_t * (1 + 1 / 3 + li ** 2 / 0.1 + lj ** 2 / 0.4)
    assert stability.fastest_damping_rate(pair, mass, inertia).rate == pytest.approx(max(both))
    assert stability.fastest_damping_rate(pair, mass, inertia).particle == 0  # the light one moves most


def dense_damping(c: stability.DampingContacts, n: int, dim: int) -> np.ndarray:
    """D by the slow obvious construction: Σ g_n b bᵀ + g_t B_tᵀ B_t over contacts, per particle (u, ω)."""
    n_rot = 1 if dim == 2 else 3
    width = dim + n_rot
    damping = np.zeros((n * width, n * width))
    for q in range(len(c.i)):
        n_q = c.normal[q]
        if dim == 2:
            spin = np.array([[-n_q[1]], [n_q[0]]])                                     # ω ↦ ω ẑ × n
        else:
            spin = np.array([[0, n_q[2], -n_q[1]], [-n_q[2], 0, n_q[0]], [n_q[1], -n_q[0], 0]])  # ω ↦ ω × n
        b_n = np.zeros((1, n * width))
        b_t = np.zeros((dim, n * width))
        for particle, sign, lever in ((c.i[q], 1.0, c.lever_i[q]), (c.j[q], -1.0, c.lever_j[q])):
            if particle < 0:
                continue
            start = particle * width
            b_n[0, start:start + dim] = sign * n_q
            b_t[:, start:start + dim] = sign * (np.eye(dim) - np.outer(n_q, n_q))
            b_t[:, start + dim:start + width] = -lever * spin
        damping += c.normal_coefficient[q] * b_n.T @ b_n + c.tangential_coefficient[q] * b_t.T @ b_t
    return damping


@pytest.mark.parametrize("dim", [2, 3])
def test_operator_and_fastest_rate_match_a_dense_reference(dim):
    rng = np.random.default_rng(dim)
    n, count = 10, 25
    n_rot = 1 if dim == 2 else 3
    i = rng.integers(0, n, count)
    j = rng.integers(-1, n, count)
    j = np.where(j == i, -1, j)  # some wall contacts
    normal = rng.standard_normal((count, dim))
    normal /= np.linalg.norm(normal, axis=1)[:, None]
    c = contacts(i, j, normal, rng.uniform(1, 5, count), rng.uniform(1, 5, count), rng.uniform(0.3, 0.6, count),
                 rng.uniform(0.3, 0.6, count))
    mass, inertia = rng.uniform(0.5, 2.0, n), rng.uniform(0.05, 0.3, n)
    damping = dense_damping(c, n, dim)
    q = rng.standard_normal(n * (dim + n_rot)).reshape(n, dim + n_rot)
    force, torque = stability.damping_matvec(c, q[:, :dim], q[:, dim:])
    np.testing.assert_allclose(np.hstack([force, torque]).reshape(-1), damping @ q.reshape(-1), atol=1e-12)
    weights = np.hstack([np.repeat(mass[:, None], dim, 1), np.repeat(inertia[:, None], n_rot, 1)]).reshape(-1)
    largest = np.linalg.eigvalsh(damping / np.sqrt(np.outer(weights, weights)))[-1]
    assert stability.fastest_damping_rate(c, mass, inertia).rate == pytest.approx(largest, rel=1e-4)


def hertz_packing(time_step: float):
    """36 Hertzian disks with the head-on damping (e_n = 0.5 at v0, γ_n = 209) compressed to ρ = 0.84 and 0.88."""
    return tiny("2d_hertz", box_length=8.0, rho_grid=(0.84, 0.88), time_step=time_step, damping_model="head_on",
                relaxation=Relaxation(window_steps=2000, tolerance=0.1, max_steps=20000))


def test_a_packing_at_a_stable_time_step_relaxes(tmp_path):
    """At Δt = 0.0025 τ_c the damped modes are integrable (rate · Δt ≈ 1): above jamming the packing comes to
    rest, its particles far slower than the walls were (kinetic energy < 1 % of N · ½ m̄ v0²). At 0.005 τ_c the
    chatter made rms speeds exceed v0 (docs/decisions.md)."""
    system = hertz_packing(0.0025)
    paths = run(system, tmp_path)
    with xr.open_dataset(paths[-1]) as ds:
        assert float(ds.Z) > 3.0
        wall_speed_energy = ds.sizes["particle"] * 0.5 * system.wall_speed ** 2
        assert float(ds.kinetic_energy) < 0.01 * wall_speed_energy


def test_a_time_step_too_long_for_the_damping_stops_before_the_snapshot(tmp_path):
    """At P1's 3D step 0.005 τ_c the rotational damping of these contacts is past the Gear bound: the run stops
    with the step, particle, ρ and the config key, and writes no snapshot for that ρ."""
    paths = [tmp_path / "rho0.840.nc", tmp_path / "rho0.880.nc"]
    with pytest.raises(SimulationBlowUp, match=r"systems\.2d_hertz\.time_step ≤") as failure:
        run(hertz_packing(0.005), tmp_path)
    assert failure.value.rho == pytest.approx(0.84)
    assert 0 <= failure.value.particle < 36
    assert "rate · Δt" in str(failure.value) and "particle" in str(failure.value)
    assert not any(path.exists() for path in paths)


@pytest.mark.parametrize("config_name", ["config.yaml", "smoke.yaml", "paper.yaml"])
@pytest.mark.parametrize("name, box_length", [("2d_hertz", 9.0), ("3d_hertz", 7.0)])
def test_each_hertz_system_passes_the_top_of_its_grid_with_its_config_settings(config_name, name, box_length,
                                                                               tmp_path):
    """The Hertz systems as configured (the damping rule's γ_n on the √2 grid, P1's Δt: 0.02 τ_c in 2D, 0.005 τ_c
    in 3D) in a small box, compressed to the last two ρ of their grid: the damping check passes (the run would stop
    otherwise) within the rule's margin (λΔt ≤ 0.8 × the Gear bound, docs/decisions.md), and the packing comes to
    rest relative to the compression (rms speed < 0.3 v0, i.e. kinetic energy < 10 % of N · ½ m̄ v0²; the rotational
    chatter of an unstable step had rms speeds above v0). Only the box (with the default lattice) and, for
    paper.yaml, the relaxation window (1.5·10⁵ steps) are reduced. The same contacts with the head-on damping
    (γ_n ≈ 200–280) stop at these steps: `test_a_time_step_too_long_for_the_damping_stops_before_the_snapshot`."""
    system = system_from_config(name, load_config(config_name))
    assert system.damping_model == "explicit"
    grid_index = 2.0 * math.log2(system.normal_damping / (2.0 * math.log(2.0)))  # γ_n = 1.3863 · 2^(k/2)
    assert grid_index == pytest.approx(round(grid_index), abs=1e-4)
    assert system.time_step == {2: 0.02, 3: 0.005}[system.dimension]  # P1 §2
    relaxation = dataclasses.replace(system.relaxation, window_steps=min(system.relaxation.window_steps, 2000),
                                     max_steps=min(system.relaxation.max_steps, 40000))
    system = dataclasses.replace(system, box_length=box_length, rho_grid=system.rho_grid[-2:], relaxation=relaxation,
                                 initial_state=None)
    paths = run(system, tmp_path)
    with xr.open_dataset(paths[-1]) as ds:
        assert float(ds.attrs["dem_damping_rate_time_step"]) <= 0.8 * stability.GEAR_DAMPING_BOUND
        assert float(ds.rho) == pytest.approx(system.rho_grid[-1])
        assert float(ds.Z) > system.dimension + 1  # jammed: above isostatic
        # the packing's own energy: a rattler (< 2 contacts) keeps whatever spin or flight it has (its constant
        # E_kin would stop P1's fluctuation test at once), so only the particles in the network count
        assert packing_kinetic_energy(ds) < 0.1 * ds.sizes["particle"] * 0.5 * system.wall_speed ** 2


def packing_kinetic_energy(ds: xr.Dataset) -> float:
    """Kinetic energy (translation + rotation) [m̄ d_ave² τ_c⁻²] of the particles with ≥ 2 particle contacts of a
    snapshot; masses ∝ d^dim with mean 1, inertia m r²/2 (disk) or 2 m r²/5 (sphere), as the engine's."""
    from forcenet.dem.packing import particle_masses
    from forcenet.network.force_network import rattler_free_mask

    dim = ds.sizes["spatial"]
    radius = ds.radius.values
    mass = particle_masses(2.0 * radius, dim)
    inertia = mass * radius ** 2 * (0.5 if dim == 2 else 0.4)
    in_network = rattler_free_mask(ds.sizes["particle"], ds.contact_i.values, ds.contact_j.values, "once")
    energy = 0.5 * mass * (ds.velocity.values ** 2).sum(axis=1) + \
        0.5 * inertia * (ds.angular_velocity.values ** 2).sum(axis=1)
    return float(energy[in_network].sum())
