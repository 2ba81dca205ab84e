"""Physics invariants of the DEM engine: binary collisions (P1 Eq. 4, restitution), Coulomb cap and spring
projection, momentum and energy balance, the wall contact law."""
from __future__ import annotations

import math

import numpy as np
import pytest

from forcenet import units
from forcenet.dem import calibration, protocol, stability
from forcenet.dem._kernels import gear as gear_kernels
from forcenet.dem._kernels.law import contact_2d, contact_3d
from forcenet.dem.engine import ContactLaw, Simulation

P1_HERTZ_K = units.reduced_normal_stiffness(units.Material(), 0.5)


def two_particle_simulation(law: ContactLaw, speed: float, time_step: float, dim: int = 2) -> Simulation:
    """Factory: two mean particles (mass 1, diameter 1) approaching head-on along x at relative speed `speed`,
    just apart, no walls."""
    position = np.zeros((2, dim))
    position[1, 0] = 1.0 + 0.5 * speed * time_step
    velocity = np.zeros((2, dim))
    velocity[0, 0], velocity[1, 0] = 0.5 * speed, -0.5 * speed
    return Simulation(position=position, radius=[0.5, 0.5], mass=[1.0, 1.0], law=law, time_step=time_step,
                      box_lo=np.zeros(dim), box_hi=np.ones(dim), velocity=velocity, walls="none")


def collide(sim: Simulation, max_steps: int = 100000) -> tuple[float, float]:
    """Run until the pair separates; returns (contact duration, outgoing relative speed)."""
    steps_in_contact = 0
    for _ in range(max_steps):
        sim.advance(1)
        if sim.contact_count():
            steps_in_contact += 1
        elif steps_in_contact:
            break
    v = sim.velocities()
    return steps_in_contact * sim.time_step, float(v[1, 0] - v[0, 0])


@pytest.mark.parametrize("beta, k_n, speed", [(0.0, math.pi ** 2, 0.1), (0.5, P1_HERTZ_K, 2e-3),
                                              (0.5, P1_HERTZ_K, 0.05)])
def test_undamped_collision_lasts_p1_eq4(beta, k_n, speed):
    expected = units.undamped_collision_time(k_n, beta, 0.5, speed)
    law = ContactLaw(k_n, 0.8 * k_n, 0.0, 0.0, 0.5, beta)
    duration, v_out = collide(two_particle_simulation(law, speed, expected / 400))
    assert duration == pytest.approx(expected, rel=5e-3)
    assert v_out == pytest.approx(speed, rel=1e-3)  # elastic
    assert calibration.collision_duration(k_n, beta, 0.0, 0.5, speed) == pytest.approx(expected, rel=1e-6)


@pytest.mark.parametrize("beta, k_n, speed, time_step", [(0.0, math.pi ** 2, 0.1, 0.02),
                                                         (0.5, P1_HERTZ_K, 2e-3, 0.02),
                                                         (0.0, units.P2_REDUCED_NORMAL_STIFFNESS, 0.01, 0.02)])
def test_calibrated_damping_gives_the_restitution(beta, k_n, speed, time_step):
    """γ_n from calibration.py gives e_n = 0.5 for two mean particles, in the engine at the papers' Δt."""
    gamma = calibration.normal_damping_for_restitution(k_n, beta, 0.5, 0.5, speed)
    assert calibration.collision_restitution(k_n, beta, gamma, 0.5, speed) == pytest.approx(0.5, abs=1e-8)
    law = ContactLaw(k_n, 0.8 * k_n, gamma, gamma, 0.5, beta)
    _, v_out = collide(two_particle_simulation(law, speed, time_step))
    assert v_out / speed == pytest.approx(0.5, abs=0.02)
    # and the closed form alone (no tail cut) would be wrong by more than that for the linear law
    if beta == 0.0:
        closed = units.linear_damping_for_restitution(k_n, 0.5, 0.5)
        assert calibration.collision_restitution(k_n, 0.0, closed, 0.5, speed) > 0.53


def linear_restitution(k_n: float, gamma: float, m_eff: float, cut: bool = True) -> float:
    """Exact restitution of the linear law (P1 Eq. 1, β = 0), m ẍ = −max(0, k_n x + γ m ẋ), x(0) = 0: the damped
    oscillator x = (v0/ω) e^(−γt/2) sin ωt, ω = √(k_n/m − γ²/4). With the cut the force never turns attractive: it
    reaches 0 where ẍ = 0, tan ωt* = γω/(γ²/4 − ω²), and the pair leaves freely at ẋ(t*); without it the overlap
    returns to 0 at ωt = π, e = exp(−γπ/2ω)."""
    omega = math.sqrt(k_n / m_eff - gamma ** 2 / 4)
    if not cut:
        return math.exp(-gamma * math.pi / (2 * omega))
    t = (math.pi - math.atan2(gamma * omega, omega ** 2 - gamma ** 2 / 4)) / omega
    return -math.exp(-gamma * t / 2) * (math.cos(omega * t) - gamma / (2 * omega) * math.sin(omega * t))


def test_linear_law_damping_is_minus_two_ln_e_per_collision_time():
    """P1 ref. [47]: γ_n = −2 ln(e_n)/τ_c. In τ_c units 1.386 for e_n = 0.5; a linear collision of effective mass
    m̄ (it lasts τ_c, P1 Eq. 4) then has restitution e_n up to the weak-damping approximation (and the cut of the
    attractive tail, which raises it), while two mean particles (m_eff = m̄/2, shorter contact) keep more. Both the
    calibration's collision and the engine's give the exact damped-oscillator value with the cut."""
    assert units.collision_time_damping(0.5) == pytest.approx(2.0 * math.log(2.0))
    assert units.collision_time_damping(0.5, collision_time=2.0) == pytest.approx(math.log(2.0))
    assert units.collision_time_damping(1.0) == 0.0
    with pytest.raises(ValueError):
        units.collision_time_damping(0.0)
    k_n, speed = math.pi ** 2, 0.1  # τ_c = π √(m̄/k_n) = 1
    for e_n in (0.9, 0.95, 0.5):
        gamma = units.collision_time_damping(e_n)
        for m_eff in (1.0, 0.5):
            exact = linear_restitution(k_n, gamma, m_eff)
            # RK4 step h of `head_on_collision`; its first stage sees no force at x = 0, where the linear law has
            # γ m v0: the collision runs as from v0 (1 + hγ/6), an O(h) error on e (its O(h²) rest: the 1 %)
            h = 3.0 * math.sqrt(m_eff / k_n) / calibration.STEPS_PER_COLLISION
            e = calibration.collision_restitution(k_n, 0.0, gamma, m_eff, speed)
            assert abs(e / exact - 1) <= 1.01 * h * gamma / 6 + 1e-9, (e_n, m_eff, e, exact)
        if e_n > 0.8:  # weak damping: e ≈ e_n (0.902 for e_n = 0.9: ω < ω0 and the cut raise it)
            assert linear_restitution(k_n, gamma, 1.0) == pytest.approx(e_n, abs=0.005)
    gamma = units.collision_time_damping(0.5)
    # strong damping: the cut raises e by 0.05 (0.543 against 0.491), 500× the tolerances here
    assert linear_restitution(k_n, gamma, 1.0) - linear_restitution(k_n, gamma, 1.0, cut=False) > 0.04
    assert linear_restitution(k_n, gamma, 0.5) > 0.6
    # the engine (Gear, contact from overlap > 0 to overlap ≤ 0, force capped at 0): two mean particles; its
    # error on e is second order in Δt, so it shrinks 4× from τ/100 to τ/200 (τ = π/ω) towards the exact value
    law = ContactLaw(k_n, 0.8 * k_n, gamma, gamma, 0.5, 0.0)
    exact = linear_restitution(k_n, gamma, 0.5)
    duration = math.pi / math.sqrt(k_n / 0.5 - gamma ** 2 / 4)
    errors = [collide(two_particle_simulation(law, speed, duration / n))[1] / speed - exact for n in (100, 200)]
    assert abs(errors[1]) < 1e-4 and 3.0 < errors[0] / errors[1] < 5.0, errors


@pytest.mark.parametrize("model", ["linear_law", "head_on"])
def test_damping_model_of_a_system(model):
    """Each `damping_model` gives its γ_n: linear_law the closed form whatever β, head_on e_n = 0.5 in a v0
    collision of two mean particles; for the Hertz law the linear-law γ_n leaves that collision nearly elastic."""
    import dataclasses

    from conftest import load_config
    from forcenet.systems import system_from_config

    for name in ("2d_linear", "2d_hertz", "3d_hertz"):
        system = dataclasses.replace(system_from_config(name, load_config()), damping_model=model)
        gamma = calibration.normal_damping_for_system(system)
        speed = system.wall_speed if system.beta else 1.0
        e_n = calibration.collision_restitution(system.normal_stiffness, system.beta, gamma, 0.5, speed)
        if model == "linear_law":
            assert gamma == pytest.approx(2.0 * math.log(2.0))
            assert e_n > (0.99 if system.beta else 0.6)
        else:
            assert e_n == pytest.approx(0.5, abs=1e-8)
    with pytest.raises(ValueError, match="damping model"):
        calibration.normal_damping_for_system(dataclasses.replace(system, damping_model="implicit"))


def test_explicit_damping_is_the_stated_value_and_sets_the_restitution():
    """``damping_model: explicit`` integrates exactly `normal_damping`: the head-on γ_n stated explicitly gives
    the same e_n = 0.5 at v0, and a stronger γ_n a smaller restitution (the series of docs/validation/damping.md)."""
    import dataclasses

    from conftest import load_config
    from forcenet.systems import system_from_config

    system = system_from_config("2d_hertz", load_config())
    head_on = calibration.normal_damping_for_system(dataclasses.replace(system, damping_model="head_on"))
    explicit = dataclasses.replace(system, damping_model="explicit", normal_damping=head_on)
    assert calibration.normal_damping_for_system(explicit) == head_on
    restitution = [calibration.collision_restitution(system.normal_stiffness, system.beta, gamma, 0.5,
                                                     system.wall_speed) for gamma in (head_on, 0.5 * head_on)]
    assert restitution[0] == pytest.approx(0.5, abs=1e-8)
    assert 0.5 < restitution[1] < 1.0
    # the engine: the law the protocol builds for the explicit system, in a head-on collision of two mean particles
    # at v0. Gear's error on e is second order in Δt (x^β = √x: no force jump at contact), so it shrinks 4× from
    # t_c/100 to t_c/200, where it is < 2e-4, a thousandth of the 0.19 between the two γ_n
    v0 = system.wall_speed
    for gamma, expected in zip((head_on, 0.5 * head_on), restitution):
        law = protocol.contact_law_for_system(dataclasses.replace(explicit, normal_damping=gamma))
        assert law.normal_damping == gamma
        duration = calibration.collision_duration(system.normal_stiffness, system.beta, gamma, 0.5, v0)
        errors = [collide(two_particle_simulation(law, v0, duration / n))[1] / v0 - expected for n in (100, 200)]
        assert abs(errors[1]) < 2e-4 and 3.0 < errors[0] / errors[1] < 5.0, (gamma, errors)


def damped_oscillator_amplitude(omega_dt: float, damping_dt: float, steps: int = 3000) -> float:
    """Run ẍ = −ω² x − c ẋ (unit mass, Δt = 1; omega_dt = ω Δt, damping_dt = c Δt) through the engine's own
    Gear kernels, the damping seeing the velocity that `gear_predict` hands to the forces; returns the final
    |Δt ẋ| + |Δt² ẍ/2| from x = v = 1 (x itself settles at a constant when ω = 0)."""
    gear = np.zeros((5, 1, 1))
    gear[0, 0, 0] = 1.0
    gear[1, 0, 0] = 1.0
    load = np.zeros((1, 1))
    force_velocity = np.zeros((1, 1))
    accel_scale = np.full((1, 1), 0.5)  # Δt²/2 · 1/m
    half_mass = np.full((1, 1), 0.5)
    gear_kernels.gear_predict(gear, 1, force_velocity, load)  # as `advance` does
    for _ in range(steps):
        load[0, 0] = -omega_dt ** 2 * gear[0, 0, 0] - damping_dt * force_velocity[0, 0]
        gear_kernels.gear_correct_predict(gear, load, accel_scale, half_mass, 1, force_velocity)
        if not abs(gear[1, 0, 0]) < 1e6:  # grown: stop before it overflows
            break
    gear_kernels.gear_unpredict(gear, 1)
    return abs(gear[1, 0, 0]) + abs(gear[2, 0, 0])


@pytest.mark.parametrize("omega_dt, damping_bound", [(0.0, 1.5), (0.3, stability.GEAR_DAMPING_BOUND), (0.6, 1.05)])
def test_gear_corrector_with_strong_damping_is_stable_up_to_its_bound(omega_dt, damping_bound):
    """The damping sees r1 + 2 r2 (`gear_predict`): the step map's spectral radius stays ≤ 1 up to c Δt ≈ 1.5 at
    ω = 0, 1.38 at ω Δt = 0.3 and 1.05 at ω Δt = 0.6 (`forcenet.dem.stability` checks every snapshot against
    the 0.3 value, docs/decisions.md); beyond it the run must grow."""
    assert damped_oscillator_amplitude(omega_dt, 0.95 * damping_bound) < 1e-2
    assert damped_oscillator_amplitude(omega_dt, 1.1 * damping_bound) > 1e2


def test_spring_is_projected_onto_the_tangent_plane():
    law = ContactLaw(100.0, 80.0, 0.0, 0.0, 10.0, 0.0).as_array()
    n = np.array([0.6, 0.8, 0.0])
    xi = np.array([0.01, 0.02, 0.005])  # has a normal part n·ξ = 0.022
    f_n, fx, fy, fz, sx, sy, sz = contact_3d(law, *n, 0.01, 0.0, 0.0, 0.0, 0.0, 0.5, 1.0, *xi, 0.0)
    projected = xi - n * np.dot(n, xi)
    np.testing.assert_allclose([sx, sy, sz], projected, atol=1e-15)
    np.testing.assert_allclose([fx, fy, fz], -80.0 * projected, atol=1e-13)
    assert f_n == pytest.approx(1.0)
    assert abs(np.dot([fx, fy, fz], n)) < 1e-15


@pytest.mark.parametrize("beta", [0.0, 0.5])
def test_coulomb_cap_limits_the_force_and_rescales_the_spring(beta):
    mu, overlap = 0.3, 0.02
    law = ContactLaw(100.0, 80.0, 0.0, 0.0, mu, beta).as_array()
    f_n, fx, fy, sx, sy = contact_2d(law, 1.0, 0.0, overlap, 0.0, 0.0, 0.0, 0.5, 1.0, 0.0, 0.05, 0.0)
    assert f_n == pytest.approx(100.0 * overlap ** (1 + beta))
    assert math.hypot(fx, fy) == pytest.approx(mu * f_n)           # P1 Eq. 3
    assert fy < 0 and fx == 0.0                                     # opposes the spring
    trial = 80.0 * overlap ** beta * 0.05
    assert sy == pytest.approx(0.05 * mu * f_n / trial)              # ξ rescaled by the same factor
    # a small spring sticks: the force is the spring force itself
    f_n, fx, fy, sx, sy = contact_2d(law, 1.0, 0.0, overlap, 0.0, 0.0, 0.0, 0.5, 1.0, 0.0, 1e-5, 0.0)
    assert fy == pytest.approx(-80.0 * overlap ** beta * 1e-5) and sy == 1e-5


def test_normal_force_is_never_attractive():
    law = ContactLaw(100.0, 80.0, 50.0, 0.0, 0.5, 0.0).as_array()
    f_n, *_ = contact_2d(law, 1.0, 0.0, 0.001, 1.0, 0.0, 0.0, 1.0, 1.0, 0.0, 0.0, 0.0)
    assert f_n == 0.0  # separating fast: damping exceeds the spring


def dense_cloud(dim: int, seed: int = 0, n_side: int = 6):
    """A compressed perturbed lattice (overlaps ≈ 3 %) with random velocities and spins, in the middle of space."""
    rng = np.random.default_rng(seed)
    grid = np.stack(np.meshgrid(*[np.arange(n_side)] * dim, indexing="ij"), -1).reshape(-1, dim) * 0.97
    position = grid + rng.uniform(-0.02, 0.02, grid.shape)
    n = len(position)
    radius = rng.uniform(0.49, 0.51, n)
    mass = (2 * radius) ** dim
    velocity = rng.normal(0.0, 0.05, (n, dim))
    omega = rng.normal(0.0, 0.2, (n,) if dim == 2 else (n, 3))
    return position, radius, mass, velocity, omega


def total_momentum(sim: Simulation):
    v = sim.velocities()
    x = sim.positions()
    m = sim.masses()
    inertia = 1.0 / sim._ordered(sim.particles.inv_inertia[:sim.n_mobile])
    p = (m[:, None] * v).sum(axis=0)
    omega = sim.angular_velocities().reshape(sim.n_mobile, -1)
    if sim.dimension == 2:
        angular = np.sum(m * (x[:, 0] * v[:, 1] - x[:, 1] * v[:, 0]) + inertia * omega[:, 0])
    else:
        angular = (m[:, None] * np.cross(x, v)).sum(axis=0) + (inertia[:, None] * omega).sum(axis=0)
    return p, np.atleast_1d(angular)


@pytest.mark.parametrize("dim", [2, 3])
def test_momentum_is_conserved_without_walls(dim):
    position, radius, mass, velocity, omega = dense_cloud(dim)
    law = ContactLaw(math.pi ** 2, 8.0, 2.0, 2.0, 0.5, 0.5 if dim == 3 else 0.0)
    sim = Simulation(position=position, radius=radius, mass=mass, law=law, time_step=0.01, box_lo=np.zeros(dim),
                     box_hi=np.ones(dim), velocity=velocity, angular_velocity=omega, walls="none")
    p0, l0 = total_momentum(sim)
    assert sim.contact_count() > 10
    sim.advance(100)
    assert sim.contact_count() > 10
    sim.advance(400)
    p1, l1 = total_momentum(sim)
    np.testing.assert_allclose(p1, p0, atol=1e-12)  # pairwise forces cancel exactly
    # torques act at one contact point for both particles, so L is conserved up to the integration error
    np.testing.assert_allclose(l1, l0, rtol=1e-5)


def elastic_energy(sim: Simulation, law: ContactLaw) -> float:
    x = sim.particles.gear_position[0]
    energy = 0.0
    for i, j in zip(sim.contacts.pair_i, sim.contacts.pair_j):
        overlap = sim.particles.radius[i] + sim.particles.radius[j] - np.linalg.norm(x[i] - x[j])
        if overlap > 0:
            energy += law.normal_stiffness / (2 + law.beta) * overlap ** (2 + law.beta)
    if sim.walls.flat_walls:
        for k in range(sim.dimension):
            for overlap in (sim.particles.radius[:sim.n_mobile] - (x[:sim.n_mobile, k] - sim.walls_lo[k]),
                            sim.particles.radius[:sim.n_mobile] - (sim.walls_hi[k] - x[:sim.n_mobile, k])):
                energy += np.sum(law.normal_stiffness / (2 + law.beta) * np.clip(overlap, 0, None) ** (2 + law.beta))
    return float(energy)


@pytest.mark.parametrize("dim, beta", [(2, 0.0), (2, 0.5), (3, 0.5)])
def test_energy_is_conserved_without_damping_and_friction(dim, beta):
    position, radius, mass, velocity, omega = dense_cloud(dim, seed=3, n_side=5)
    law = ContactLaw(math.pi ** 2 if beta == 0 else 200.0, 0.0, 0.0, 0.0, 0.0, beta)
    box_lo, box_hi = np.full(dim, -0.48), np.full(dim, 4 * 0.97 + 0.48)  # flat walls touching the cloud
    sim = Simulation(position=position, radius=radius, mass=mass, law=law, time_step=0.005, box_lo=box_lo,
                     box_hi=box_hi, velocity=velocity, angular_velocity=omega, walls="flat")
    e0 = sim.kinetic_energy() + elastic_energy(sim, law)
    sim.advance(4000)
    e1 = sim.kinetic_energy() + elastic_energy(sim, law)
    assert elastic_energy(sim, law) > 0.01 * e0, "contacts should store energy"
    assert e1 == pytest.approx(e0, rel=2e-3)


def wall_contact_reference(law: ContactLaw, normal, overlap, radius, mass, velocity, spin, spring):
    """P1 Eq. 1–3 for a particle against a flat wall at rest, written out with 3-vectors (2D in the z = 0 plane):
    the wall is the partner of infinite mass (m_eff = m), the contact point lies on the wall plane, r − x from the
    centre; returns (force, torque about the centre)."""
    n = np.asarray(normal, dtype=float)
    x_beta = overlap ** law.beta
    r_contact = -(radius - overlap) * n
    v_contact = np.asarray(velocity, dtype=float) + np.cross(spin, r_contact)
    v_normal = v_contact @ n
    f_n = max(0.0, law.normal_stiffness * overlap ** (1 + law.beta) - law.normal_damping * x_beta * mass * v_normal)
    xi = np.asarray(spring, dtype=float) - (np.asarray(spring) @ n) * n  # the spring's tangential part (P1 §2)
    f_t = -x_beta * (law.tangential_stiffness * xi + law.tangential_damping * mass * (v_contact - v_normal * n))
    if np.linalg.norm(f_t) > law.friction * f_n:  # P1 Eq. 3
        f_t *= law.friction * f_n / np.linalg.norm(f_t)
    return f_n * n + f_t, np.cross(r_contact, f_t)


@pytest.mark.parametrize("dim, beta", [(2, 0.0), (3, 0.5)])
def test_wall_contact_law(dim, beta):
    """A particle at rest overlapping the x_lo wall by x feels k_n x^(1+β) along +x and no torque; a wall moving in
    at v adds the damping γ_n x^β m v (m_eff = particle mass). A particle that slides and spins against the wall
    feels P1 Eq. 2–3 at the contact point (the slip of that point, the tangential spring) and their torque
    r_c × F_t about its centre, r_c = −(r − x) n; a spin about the normal gives none."""
    k_n, gamma, mass, overlap, speed = 50.0, 3.0, 1.7, 0.01, 0.02
    law = ContactLaw(k_n, 40.0, gamma, gamma, 0.5, beta)
    position = np.full((1, dim), 2.0)
    position[0, 0] = 0.5 - overlap
    sim = Simulation(position=position, radius=[0.5], mass=[mass], law=law, time_step=0.01, box_lo=np.zeros(dim),
                     box_hi=np.full(dim, 4.0), walls="flat")
    force, torque = sim.evaluate_forces()
    expected = np.zeros(dim)
    expected[0] = k_n * overlap ** (1 + beta)
    np.testing.assert_allclose(force[0], expected, rtol=1e-12)
    np.testing.assert_allclose(torque[0], 0.0, atol=1e-15)
    sim.walls.wall_state[3] = speed  # the walls are moving inward at `speed`
    force, _ = sim.evaluate_forces()
    assert force[0, 0] == pytest.approx(k_n * overlap ** (1 + beta) + gamma * overlap ** beta * mass * speed)
    contacts = sim.contact_forces()
    assert contacts.wall_contact_wall.tolist() == [0] and contacts.wall_contact_particle.tolist() == [0]
    # sliding and spinning, walls at rest: under the Coulomb cap (small slip) and at it (fast spin)
    spring = np.array([0.002, 0.001, -0.0005])  # the normal part (along x) must be projected away
    for spin_scale, capped in ((0.05, False), (5.0, True)):
        velocity = np.array([-0.01, 0.004, -0.003])  # into the wall (v_n < 0: the damping adds to F_n) and along it
        spin = spin_scale * np.array([0.3, 0.1, -0.2]) if dim == 3 else np.array([0.0, 0.0, -0.2 * spin_scale])
        sim = Simulation(position=position, radius=[0.5], mass=[mass], law=law, time_step=0.01,
                         box_lo=np.zeros(dim), box_hi=np.full(dim, 4.0), walls="flat", velocity=[velocity[:dim]],
                         angular_velocity=[spin if dim == 3 else spin[2]])
        sim.walls.wall_spring[0, 0] = spring[:dim]  # particle 0, wall 0 (x_lo)
        reference_force, reference_torque = wall_contact_reference(law, [1.0, 0.0, 0.0], overlap, 0.5, mass,
                                                                   np.append(velocity[:dim], [0.0] * (3 - dim)),
                                                                   spin, np.append(spring[:dim], [0.0] * (3 - dim)))
        f_t = np.linalg.norm(reference_force[1:])
        if dim == 2 and not capped:  # by hand: slip v_y − (r − x) ω = 0.004 + 0.49 · 0.01, ξ' = (0, 0.001)
            assert reference_force[1] == pytest.approx(-(40.0 * 0.001 + gamma * mass * (0.004 + 0.49 * 0.01)))
        assert (f_t == pytest.approx(0.5 * reference_force[0])) if capped else f_t < 0.9 * 0.5 * reference_force[0]
        assert np.linalg.norm(reference_torque) == pytest.approx((0.5 - overlap) * f_t)  # r_c ⊥ F_t, |r_c| = r − x
        force, torque = sim.evaluate_forces()
        np.testing.assert_allclose(force[0], reference_force[:dim], rtol=1e-12, atol=1e-15)
        np.testing.assert_allclose(torque[0], reference_torque if dim == 3 else reference_torque[2:], rtol=1e-12,
                                   atol=1e-15)
        if dim == 3:
            assert torque[0, 0] == 0.0  # spin about the normal: no rolling or torsion resistance in P1's law
