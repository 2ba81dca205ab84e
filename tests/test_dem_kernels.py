"""DEM kernels against the slow O(N²) reference (`naive_dem.py`), and the neighbour-list machinery."""
from __future__ import annotations

import numpy as np
import pytest

import naive_dem
from forcenet.dem._kernels import contacts, neighbours
from forcenet.dem._kernels import gear as gear_kernels
from forcenet.dem.engine import ContactLaw, Simulation
from forcenet.dem.kernel_arguments import Bodies, Loads, Motion, PairRecord, Pairs, Walls
from forcenet.dem.state import wall_law as wall_law_array

LAWS = {
    "linear": dict(k_n=9.87, k_t=8.46, gamma_n=2.3, gamma_t=2.3, mu=0.5, beta=0.0),
    "hertz": dict(k_n=845.0, k_t=724.0, gamma_n=40.0, gamma_t=40.0, mu=0.3, beta=0.5),
}
#: β of neither paper: the pair loops' law at run time instead of as constants
POWER_LAW = dict(k_n=300.0, k_t=250.0, gamma_n=10.0, gamma_t=10.0, mu=0.4, beta=0.3)


def law_array(law: dict, wall_stiffness_factor: float = 1.0, radius_scaled: bool = False) -> np.ndarray:
    return ContactLaw(law["k_n"], law["k_t"], law["gamma_n"], law["gamma_t"], law["mu"], law["beta"],
                      radius_scaled=radius_scaled, wall_stiffness_factor=wall_stiffness_factor).as_array()


def random_configuration(dim: int, n: int, seed: int):
    """Random dense configuration with overlaps of a few per cent, random velocities, spins and springs."""
    rng = np.random.default_rng(seed)
    side = (n * 0.9 ** dim) ** (1 / dim) * (0.95 if dim == 2 else 0.9)
    position = rng.uniform(0.0, side, (n, dim))
    radius = rng.uniform(0.4, 0.6, n)
    mass = (2 * radius) ** dim
    velocity = rng.normal(0.0, 0.05, (n, dim))
    omega = rng.normal(0.0, 0.1, (n,) if dim == 2 else (n, 3))
    pairs = [(i, j) for i in range(n) for j in range(i + 1, n)
             if np.linalg.norm(position[i] - position[j]) < radius[i] + radius[j] + 0.3]
    springs = {pair: rng.normal(0.0, 0.02, dim) for pair in pairs}
    return position, radius, mass, velocity, omega, pairs, springs, side


@pytest.mark.parametrize("dim", [2, 3])
@pytest.mark.parametrize("law_name, radius_scaled", [("linear", False), ("hertz", False), ("hertz", True),
                                                     ("linear", True), ("power", False)])
def test_pair_forces_match_naive_reference(dim, law_name, radius_scaled):
    """Every version of the pair loops' law (Hertz and linear, with and without the LAMMPS convention's √R_eff,
    and any other β), over more touching pairs than one block, open pairs among them."""
    law = POWER_LAW if law_name == "power" else LAWS[law_name]
    position, radius, mass, velocity, omega, pairs, springs, _ = random_configuration(dim, 60, seed=dim)
    dt = 0.01
    pair_i = np.array([p[0] for p in pairs], dtype=np.int32)
    pair_j = np.array([p[1] for p in pairs], dtype=np.int32)
    spring = np.array([springs[p] for p in pairs])
    force = np.zeros((60, dim))
    torque = np.zeros((60, 1 if dim == 2 else 3))
    kernel = contacts.pair_forces_2d if dim == 2 else contacts.pair_forces_3d
    record = PairRecord(np.zeros(len(pairs)), np.zeros(len(pairs)), np.zeros((len(pairs), dim)),
                        np.zeros((len(pairs), dim)))
    kernel(Motion(position, velocity, omega.reshape(60, -1), 1.0), Bodies(radius, 1.0 / mass, 60),
           Pairs(pair_i, pair_j, len(pairs), spring), tuple(law_array(law, radius_scaled=radius_scaled)), dt,
           Loads(force, torque), record)
    overlap = record.overlap
    ref_force, ref_torque, ref_springs, ref_contacts = naive_dem.pair_forces(
        position, velocity, omega, radius, mass, springs, law, dt, radius_scaled)
    assert len(ref_contacts) > max(40, contacts.PAIR_BLOCK), "the configuration should have many contacts"
    assert len(ref_contacts) < len(pairs), "and listed pairs that do not touch"
    assert np.count_nonzero(overlap > 0) == len(ref_contacts)
    np.testing.assert_allclose(force, ref_force, rtol=1e-10, atol=1e-12)
    np.testing.assert_allclose(torque, ref_torque, rtol=1e-10, atol=1e-12)
    for p, pair in enumerate(pairs):
        expected = ref_springs.get(pair, np.zeros(dim))  # springs of open pairs are removed
        np.testing.assert_allclose(spring[p], expected, rtol=1e-10, atol=1e-14)
    capped = sum(np.linalg.norm(ft) >= law["mu"] * np.linalg.norm(fn) * (1 - 1e-12)
                 for fn, ft in ref_contacts.values())
    assert 0 < capped < len(ref_contacts), "both sliding and sticking contacts should be exercised"


@pytest.mark.parametrize("dim", [2, 3])
@pytest.mark.parametrize("law_name", ["linear", "hertz"])
@pytest.mark.parametrize("wall_factor", [1.0, 1.9999817])  # the particles' material; plexiglass (P1 §2)
def test_flat_walls_match_naive_reference(dim, law_name, wall_factor):
    """Walls of their own material: the reference law with k_n and k_t times the wall factor, the pair's damping."""
    law = LAWS[law_name]
    wall_law = dict(law, k_n=law["k_n"] * wall_factor, k_t=law["k_t"] * wall_factor)
    rng = np.random.default_rng(10 + dim)
    n = 80
    position = rng.uniform(0.3, 3.7, (n, dim))
    radius = rng.uniform(0.4, 0.6, n)
    mass = (2 * radius) ** dim
    velocity = rng.normal(0.0, 0.05, (n, dim))
    omega = rng.normal(0.0, 0.1, (n,) if dim == 2 else (n, 3))
    lo, hi, speed, dt = np.zeros(dim), np.full(dim, 4.0), 0.01, 0.01
    wall_spring = rng.normal(0.0, 0.02, (n, 2 * dim, dim))
    springs = {(i, w): wall_spring[i, w].copy() for i in range(n) for w in range(2 * dim)}
    force = np.zeros((n, dim))
    torque = np.zeros((n, 1 if dim == 2 else 3))
    walls = Walls(flat=True, box_lo=lo, box_hi=hi, state=np.array([0.0, speed, np.inf, speed]),
                  law=wall_law_array(law_array(law, wall_factor)), spring=wall_spring,
                  entry_particle=np.repeat(np.arange(n), 2 * dim), entry_wall=np.tile(np.arange(2 * dim), n),
                  release_band=np.inf, escape_margin=0.0, anchor=np.zeros((0, dim)), axis=np.zeros(0, dtype=np.int64),
                  sign=np.zeros(0))
    contacts.flat_wall_forces(Motion(position, velocity, omega.reshape(n, -1), 1.0), Bodies(radius, 1.0 / mass, n),
                              walls, lo, hi, dt, Loads(force, torque), None)
    ref_force, ref_torque, ref_springs = naive_dem.flat_wall_forces(position, velocity, omega, radius, mass, lo, hi,
                                                                    speed, springs, wall_law, dt)
    assert len(ref_springs) > 10
    np.testing.assert_allclose(force, ref_force, rtol=1e-10, atol=1e-12)
    np.testing.assert_allclose(torque, ref_torque, rtol=1e-10, atol=1e-12)
    for i in range(n):
        for w in range(2 * dim):
            np.testing.assert_allclose(wall_spring[i, w], ref_springs.get((i, w), np.zeros(dim)), atol=1e-14)


@pytest.mark.parametrize("dim", [2, 3])
def test_verlet_list_finds_every_pair_within_reach(dim):
    position, radius, *_ = random_configuration(dim, 200, seed=5)
    skin = 0.15
    origin = position.min(axis=0) - 1e-9
    cell = 2 * radius.max() + skin
    n_cells = np.ones(3, dtype=np.int64)
    n_cells[:dim] = np.floor((position.max(axis=0) - origin) / cell).astype(np.int64) + 1
    pair_i, pair_j = neighbours.build_pair_list(position, radius, 200, 200, skin, origin, cell, n_cells)
    found = set(zip(pair_i.tolist(), pair_j.tolist()))
    expected = {(i, j) for i in range(200) for j in range(i + 1, 200)
                if np.linalg.norm(position[i] - position[j]) < radius[i] + radius[j] + skin}
    assert found == expected
    keys = pair_i.astype(np.int64) * 200 + pair_j
    assert np.all(np.diff(keys) > 0), "the list is sorted by i, then j"


def particle_id_of_pair(sim: Simulation, p: int) -> tuple[int, int]:
    """The input indices of listed pair p's particles."""
    particle_id = sim.particles.particle_id
    return particle_id[sim.contacts.pair_i[p]], particle_id[sim.contacts.pair_j[p]]


def test_rebuild_carries_tangential_history_across_reordering():
    """Springs survive a rebuild that re-orders the particles (and flips i, j of some pairs)."""
    rng = np.random.default_rng(7)
    position = np.stack(np.meshgrid(np.arange(9), np.arange(9), indexing="ij"), -1).reshape(-1, 2) * 0.97
    position = position + rng.uniform(-0.01, 0.01, position.shape)
    radius = np.full(81, 0.5)
    mass = np.ones(81)
    velocity = rng.normal(0.0, 0.05, (81, 2))
    omega = rng.normal(0.0, 0.1, 81)
    law = ContactLaw(9.87, 8.46, 0.0, 0.0, 0.5, 0.0)
    sim = Simulation(position=position, radius=radius, mass=mass, law=law, time_step=0.01, box_lo=[-5, -5],
                     box_hi=[50, 50], velocity=velocity, angular_velocity=omega, walls="none")
    sim.advance(5)
    before = {}
    for p in range(sim.n_pairs):
        if np.any(sim.contacts.spring[p] != 0):
            a, b = particle_id_of_pair(sim, p)
            before[(a, b)] = sim.contacts.spring[p].copy()
    assert len(before) > 20
    rng = np.random.default_rng(0)
    perm = rng.permutation(sim.n_mobile)  # scramble the slots to force a different order and flipped pairs
    for name in ("gear_position", "gear_rotation"):
        getattr(sim.particles, name)[:, :sim.n_mobile] = getattr(sim.particles, name)[:, perm]
    for name in ("radius", "inv_mass", "inv_inertia"):
        getattr(sim.particles, name)[:sim.n_mobile] = getattr(sim.particles, name)[perm]
    sim.particles.mass, sim.particles.particle_id = sim.particles.mass[perm], sim.particles.particle_id[perm]
    inverse = np.empty_like(perm)
    inverse[perm] = np.arange(len(perm))
    old_i, old_j = inverse[sim.contacts.pair_i], inverse[sim.contacts.pair_j]
    swap = old_i > old_j
    sim.contacts.pair_i = np.where(swap, old_j, old_i).astype(np.int32)
    sim.contacts.pair_j = np.where(swap, old_i, old_j).astype(np.int32)
    sim.contacts.spring = np.where(swap[:, None], -sim.contacts.spring, sim.contacts.spring)
    sim.rebuild()
    after = {}
    for p in range(sim.n_pairs):
        if np.any(sim.contacts.spring[p] != 0):
            a, b = particle_id_of_pair(sim, p)
            after[(a, b) if a < b else (b, a)] = sim.contacts.spring[p] if a < b else -sim.contacts.spring[p]
    before = {(a, b) if a < b else (b, a): (v if a < b else -v) for (a, b), v in before.items()}
    assert after.keys() == before.keys()
    for key in before:
        np.testing.assert_array_equal(after[key], before[key])


GEAR_CORRECTOR = np.array([19 / 120, 3 / 4, 1.0, 1 / 2, 1 / 12])  # 5-value Gear, second-order ODE
PASCAL = np.array([[1, 1, 1, 1, 1], [0, 1, 2, 3, 4], [0, 0, 1, 3, 6], [0, 0, 0, 1, 4], [0, 0, 0, 0, 1]], float)


@pytest.mark.parametrize("integrate_row0", [True, False])
@pytest.mark.parametrize("components, n_total, n_mobile, scratch", [
    (1, 23, 19, False), (2, 23, 19, False), (3, 23, 19, True),  # within one block; the four lanes have a tail
    (3, 150, 131, True), (2, 150, 131, False), (1, 140, 129, False), (1, 257, 256, True)])  # several blocks: a short
    # last one, one of a single component, none short
def test_fused_gear_pass_matches_corrector_then_predictor(components, n_total, n_mobile, scratch, integrate_row0):
    """`gear_correct_predict` = the textbook corrector r_k += C_k (Δt²/2 · F/m − r2), then the Taylor (Pascal)
    step, for the first n_mobile particles; kinetic energy of the corrected state; loads cleared; the other
    particles' rows untouched; the same with the scratch made by the caller (as the step does) or by the kernel.
    Without integrate_row0 (the rotation's angle) row 0 is left exactly as it was and the other rows are the same;
    so with `gear_predict` and `gear_unpredict`."""
    rng = np.random.default_rng(components + n_total)
    gear = rng.normal(0.0, 1e-3, (5, n_total, components))
    load = rng.normal(0.0, 1.0, (n_total, components))
    accel_scale = rng.uniform(1e-6, 1e-5, (n_total, components))
    half_weight = rng.uniform(0.1, 1.0, (n_total, components))
    expected = gear.copy()
    flat = expected[:, :n_mobile].reshape(5, -1)
    delta = accel_scale[:n_mobile].ravel() * load[:n_mobile].ravel() - flat[2]
    corrected = flat + GEAR_CORRECTOR[:, None] * delta
    energy = np.sum(half_weight[:n_mobile].ravel() * corrected[1] ** 2)
    velocity = corrected[1] + 2.0 * corrected[2]
    flat[:] = PASCAL @ corrected
    row0 = gear[0].copy()
    if not integrate_row0:
        expected[0] = row0
        corrected[0] = row0[:n_mobile].ravel()
    force_velocity = np.zeros((n_total, components))
    block = gear_kernels.new_gear_block() if scratch else None
    result = gear_kernels.gear_correct_predict(gear, load, accel_scale, half_weight, n_mobile, force_velocity,
                                               block, integrate_row0)
    np.testing.assert_allclose(gear, expected, rtol=1e-13, atol=1e-18)
    np.testing.assert_allclose(force_velocity[:n_mobile].ravel(), velocity, rtol=1e-13, atol=1e-18)
    assert not force_velocity[n_mobile:].any()
    assert result == pytest.approx(energy, rel=1e-13)
    assert not load[:n_mobile].any() and load[n_mobile:].all()
    gear_kernels.gear_unpredict(gear, n_mobile, integrate_row0)  # and back to the corrected state
    np.testing.assert_allclose(gear[:, :n_mobile].reshape(5, -1), corrected, rtol=1e-9, atol=1e-15)
    assert integrate_row0 or np.array_equal(gear[0], row0)
    gear_kernels.gear_predict(gear, n_mobile, force_velocity, load, integrate_row0)  # the Taylor step alone
    predicted = PASCAL @ corrected
    if not integrate_row0:
        predicted[0] = row0[:n_mobile].ravel()
    np.testing.assert_allclose(gear[:, :n_mobile].reshape(5, -1), predicted, rtol=1e-9, atol=1e-15)
    assert integrate_row0 or np.array_equal(gear[0], row0)
