"""The stepping loop (`advance`) and the recording of a snapshot (`Simulation.record`) compute the same forces,
torques and springs, bit for bit, on random 2D and 3D states with flat or rough walls, for every branch of the
contact law (linear, Hertz, Hertz × √R_eff, another β) and with sticking and Coulomb-capped (sliding) contacts
alike: both run the same kernels (`pair_forces_2d/3d`, `flat_wall_forces`), the step with record = None.

Two checks: (1) the forces of one step as `advance` computes them against the recording kernels on the same input;
(2) `Simulation.advance` over a few steps against the same steps written out with the recording kernels (Gear
prediction, wall motion, forces, Gear correction): the whole state, the rough-wall particles' force rows and the
kinetic energies must be identical, so `advance` really computes its forces as (1) checks.
"""
from __future__ import annotations

import numpy as np
import pytest

from forcenet.dem._kernels import contacts, stepping
from forcenet.dem._kernels import gear as gear_kernels
from forcenet.dem.engine import ContactLaw, Simulation
from forcenet.dem.kernel_arguments import Loads, Motion, PairRecord, WallRecord
from forcenet.dem.packing import rough_walls

LAWS = {
    "linear": ContactLaw(9.87, 8.46, 2.3, 2.3, 0.5, 0.0),
    "hertz": ContactLaw(845.0, 724.0, 40.0, 40.0, 0.3, 0.5),
    "hertz_scaled": ContactLaw(845.0, 724.0, 40.0, 40.0, 0.3, 0.5, radius_scaled=True),  # LAMMPS convention
    "beta_quarter": ContactLaw(200.0, 170.0, 10.0, 10.0, 0.4, 0.25),  # x^β by pow
}
#: a dyadic time step and wall speed: the wall shift after k steps is exact, so writing the steps out in numpy
#: (`steps_with_recording_kernels`) reproduces the wall motion of `advance` to the bit on any CPU
TIME_STEP = 2.0 ** -7
WALL_SPEED = 2.0 ** -4
N_STEPS = 6


def bits(array) -> np.ndarray:
    """The bit patterns of a float64 array (equal bits, not merely equal values: −0.0 ≠ 0.0)."""
    return np.ascontiguousarray(array, dtype=np.float64).view(np.uint64)


def random_state(dim: int, law: ContactLaw, walls: str, seed: int) -> Simulation:
    """A jittered square/cubic lattice of spacing 1 with radii 0.47–0.54 (pair overlaps up to 12 % of a
    diameter, some neighbours apart), walls 0.45 from the outer centres (so the outer particles press on them),
    random velocities, spins, springs (pairs and flat walls) and higher Gear derivatives, walls moving inward."""
    rng = np.random.default_rng(seed)
    n_side = 6 if dim == 2 else 4
    sites = np.arange(n_side, dtype=float)
    position = np.stack(np.meshgrid(*[sites] * dim, indexing="ij"), -1).reshape(-1, dim)
    n = len(position)
    position += rng.uniform(-0.02, 0.02, position.shape)
    radius = rng.uniform(0.47, 0.54, n)
    box_lo, box_hi = np.full(dim, -0.45), np.full(dim, n_side - 1 + 0.45)
    sim = Simulation(position=position, radius=radius, mass=(2.0 * radius) ** dim, law=law, time_step=TIME_STEP,
                     box_lo=box_lo, box_hi=box_hi, velocity=rng.normal(0.0, 0.05, (n, dim)),
                     angular_velocity=rng.normal(0.0, 0.1, n if dim == 2 else (n, 3)), walls=walls,
                     wall_particles=rough_walls(box_lo, box_hi) if walls == "rough" else None)
    # open pairs too: their springs must be dropped
    sim.contacts.spring[:] = rng.normal(0.0, 0.03, sim.contacts.spring.shape)
    sim.walls.wall_spring[:] = rng.normal(0.0, 0.03, sim.walls.wall_spring.shape)
    for derivatives in (sim.particles.gear_position, sim.particles.gear_rotation):
        derivatives[3:, :n] = rng.normal(0.0, 1e-6, derivatives[3:, :n].shape)
    sim.set_walls(WALL_SPEED)
    return sim


def with_wall_speed(walls, wall_speed: float):
    """The walls with the speed of the last step set to wall_speed (the kernels read it from state[3])."""
    state = walls.state.copy()
    state[3] = wall_speed
    return walls._replace(state=state)


def stepping_forces(sim: Simulation, velocity, spin, wall_speed: float):
    """Force, torque and the updated springs of one step as `advance` computes them (velocities: the scaled
    derivatives the step's forces see), on copies of the springs."""
    spring, wall_spring = sim.contacts.spring.copy(), sim.walls.wall_spring.copy()
    loads = Loads(np.zeros_like(sim.work.loads.force), np.zeros_like(sim.work.loads.torque))
    motion = Motion(sim.particles.gear_position[0], velocity, spin, 1.0 / sim.time_step)
    if sim.walls.flat_walls:
        walls = with_wall_speed(sim.kernel_walls(wall_spring), wall_speed)
        contacts.flat_wall_forces(motion, sim.kernel_bodies(), walls, sim.walls_lo, sim.walls_hi, sim.time_step, loads,
                                  None)
    pair_kernel = contacts.pair_forces_2d if sim.dimension == 2 else contacts.pair_forces_3d
    pair_kernel(motion, sim.kernel_bodies(), sim.kernel_pairs(spring), sim.law_values(), sim.time_step, loads, None)
    return loads.force, loads.torque, spring, wall_spring


def recording_forces(sim: Simulation, position, velocity, spin, lo, hi, wall_speed: float, spring, wall_spring,
                     force, torque):
    """The recording kernels on the given positions, velocities and walls (planes lo, hi moving at wall_speed),
    accumulating into force, torque and updating the springs in place (spring_dt = Δt and a release band of one
    skin, as in a step). Returns (pair overlaps, normal and tangential pair forces, wall overlaps, wall forces)."""
    dim, dt, n = sim.dimension, sim.time_step, sim.n_mobile
    loads = Loads(force, torque)
    motion = Motion(position, velocity, spin, 1.0 / dt)
    wall_record = WallRecord(np.zeros((n, 2 * dim)), np.zeros((n, 2 * dim, dim)))
    if sim.walls.flat_walls:
        walls = with_wall_speed(sim.kernel_walls(wall_spring, every_entry=True), wall_speed)
        walls = walls._replace(release_band=sim.contacts.skin)
        contacts.flat_wall_forces(motion, sim.kernel_bodies(), walls, lo, hi, dt, loads, wall_record)
    record = PairRecord(np.zeros(sim.n_pairs), np.zeros(sim.n_pairs), np.zeros((sim.n_pairs, dim)),
                        np.zeros((sim.n_pairs, dim)))
    pair_kernel = contacts.pair_forces_2d if dim == 2 else contacts.pair_forces_3d
    pair_kernel(motion, sim.kernel_bodies(), sim.kernel_pairs(spring), sim.law_values(), dt, loads, record)
    return (record.overlap, record.normal_force[:, None] * record.normal, record.tangential, wall_record.overlap,
            wall_record.force)


CASES = [(dim, walls, law) for dim in (2, 3) for walls in ("flat", "rough") for law in LAWS]


def one_step_of_both(dim: int, walls: str, law_name: str):
    """A random state, and the forces of one step on it by `stepping_forces` and by `recording_forces`."""
    sim = random_state(dim, LAWS[law_name], walls, seed=dim * 10 + len(law_name))
    rng = np.random.default_rng(1)
    velocity = sim.particles.gear_position[1] + rng.normal(0.0, 1e-4, sim.particles.gear_position[1].shape)
    spin = sim.particles.gear_rotation[1].copy()
    stepped = stepping_forces(sim, velocity, spin, WALL_SPEED)
    spring, wall_spring = sim.contacts.spring.copy(), sim.walls.wall_spring.copy()
    force, torque = np.zeros_like(sim.work.loads.force), np.zeros_like(sim.work.loads.torque)
    recorded = recording_forces(sim, sim.particles.gear_position[0], velocity, spin, sim.walls_lo, sim.walls_hi,
                                WALL_SPEED, spring, wall_spring, force, torque)
    return sim, stepped, (force, torque, spring, wall_spring), recorded


@pytest.mark.parametrize("dim, walls, law_name", CASES)
def test_random_states_exercise_every_branch(dim, walls, law_name):
    """Contacts between particles and with the walls, open pairs (their springs dropped), and both sides of the
    Coulomb cap (P1 Eq. 3: |F_t| = μ F_n when sliding, below when sticking)."""
    sim, _, (_, _, spring, _), (overlap, normal, tangential, wall_overlap, _) = one_step_of_both(dim, walls, law_name)
    touching = overlap > 0.0
    f_n, f_t = np.linalg.norm(normal[touching], axis=1), np.linalg.norm(tangential[touching], axis=1)
    sliding = np.isclose(f_t, LAWS[law_name].friction * f_n, rtol=1e-12)
    assert 0 < np.count_nonzero(sliding) < np.count_nonzero(touching) < sim.n_pairs
    assert np.all(f_t <= LAWS[law_name].friction * f_n * (1 + 1e-12))
    on_walls = np.count_nonzero(wall_overlap) if walls == "flat" else np.count_nonzero(sim.contacts.pair_j[touching]
                                                                                      >= sim.n_mobile)
    assert on_walls >= (4 if dim == 2 else 8)
    assert np.all(spring[~touching] == 0.0) and np.all(sim.contacts.spring[~touching] != 0.0)


@pytest.mark.parametrize("dim, walls, law_name", CASES)
def test_step_forces_equal_the_recording_kernels_bit_for_bit(dim, walls, law_name):
    _, stepped, recorded, _ = one_step_of_both(dim, walls, law_name)
    for name, value, reference in zip(("force", "torque", "spring", "wall spring"), stepped, recorded):
        np.testing.assert_array_equal(bits(value), bits(reference), err_msg=name)


def steps_with_recording_kernels(sim: Simulation, n_steps: int):
    """`advance` written out step by step with the recording kernels: predict, move the walls, forces, correct
    (on copies). Returns (gear_position, gear_rotation, spring, wall_spring, force, torque, kinetic energies)."""
    gear_position, gear_rotation = sim.particles.gear_position.copy(), sim.particles.gear_rotation.copy()
    spring, wall_spring = sim.contacts.spring.copy(), sim.walls.wall_spring.copy()
    force, torque = np.zeros_like(sim.work.loads.force), np.zeros_like(sim.work.loads.torque)
    velocity, spin = np.zeros_like(sim.work.force_velocity), np.zeros_like(sim.work.force_spin)
    n, dt, work = sim.n_mobile, sim.time_step, sim.work
    shift = float(sim.walls.wall_state[0])
    energies = []
    gear_kernels.gear_predict(gear_position, n, velocity, force)
    gear_kernels.gear_predict(gear_rotation, n, spin, torque, False)  # no angle, as `advance`
    for _ in range(n_steps):
        new_shift = shift + WALL_SPEED * dt  # exact (dyadic)
        wall_speed = (new_shift - shift) * (1.0 / dt)
        shift = new_shift
        if len(sim.walls.wall_anchor):
            stepping.place_wall_particles(gear_position, velocity, n, sim.kernel_walls(), shift, wall_speed * dt)
        force[n:], torque[n:] = 0.0, 0.0
        recording_forces(sim, gear_position[0], velocity, spin, sim.walls.box_lo + shift, sim.walls.box_hi - shift,
                         wall_speed, spring, wall_spring, force, torque)
        energy = (gear_kernels.gear_correct_predict(gear_position, force, work.accel_position, work.half_mass, n,
                                                    velocity)
                  + gear_kernels.gear_correct_predict(gear_rotation, torque, work.accel_rotation, work.half_inertia, n,
                                                      spin, None, False))
        energies.append(energy * (1.0 / dt) * (1.0 / dt))
    gear_kernels.gear_unpredict(gear_position, n)
    gear_kernels.gear_unpredict(gear_rotation, n, False)
    return gear_position, gear_rotation, spring, wall_spring, force, torque, np.array(energies)


@pytest.mark.parametrize("dim, walls, law_name", CASES)
def test_advance_is_the_recording_kernels_step_by_step(dim, walls, law_name):
    sim = random_state(dim, LAWS[law_name], walls, seed=dim * 10 + len(law_name))
    expected = steps_with_recording_kernels(sim, N_STEPS)
    energy = sim.advance(N_STEPS)
    assert sim.step == N_STEPS and sim.work.status[0] == stepping.STATUS_DONE  # no rebuild in between
    n = sim.n_mobile
    loads = sim.work.loads
    got = (sim.particles.gear_position, sim.particles.gear_rotation, sim.contacts.spring, sim.walls.wall_spring,
           loads.force[n:], loads.torque[n:], energy)
    names = ("gear_position", "gear_rotation", "spring", "wall_spring", "force on wall particles",
             "torque on wall particles", "kinetic energy")
    for name, value, reference in zip(names, got, expected[:4] + (expected[4][n:], expected[5][n:], expected[6])):
        np.testing.assert_array_equal(bits(value), bits(reference), err_msg=name)
    if walls == "rough":
        assert np.any(sim.work.loads.force[n:] != 0.0), "the wall particles should carry forces"


def slow_check_positions(position, reference, n_mobile, lo, hi, margin, limit_sq):
    """`stepping.check_positions` written the obvious way: (how many finite |r − r_ref|² exceed limit_sq, first
    particle outside [lo − margin, hi + margin] or not finite, else −1)."""
    displacement_sq = [float(np.sum((position[i] - reference[i]) ** 2)) for i in range(n_mobile)]
    outside = [i for i in range(n_mobile)
               if not (np.all(position[i] >= lo - margin) and np.all(position[i] <= hi + margin))]
    return sum(d > limit_sq for d in displacement_sq), (outside[0] if outside else -1)


@pytest.mark.parametrize("dim", [2, 3])
def test_check_positions_counts_the_far_moved_and_finds_the_first_escape(dim):
    rng = np.random.default_rng(dim)
    n = 50
    lo, hi, margin = np.zeros(dim), np.full(dim, 10.0), 0.25
    position = rng.uniform(0.0, 10.0, (n, dim))
    reference = position + rng.normal(0.0, 0.01, position.shape)
    reference[17] = position[17] + 0.3  # the largest displacements: 0.09 per axis, then 0.04 per axis
    reference[23] = position[23] - 0.2
    for limit_sq, moved in [(0.09 * dim * 1.001, 0), (0.09 * dim * 0.999, 1), (0.04 * dim * 0.999, 2), (0.0, n)]:
        result = stepping.check_positions(position, reference, n, lo, hi, margin, limit_sq)
        assert result == (moved, -1)
        assert result == slow_check_positions(position, reference, n, lo, hi, margin, limit_sq)
    for axis in range(dim):  # each bound alone, a particle in the margin before it: the escape is the later one
        for side, (in_margin, beyond) in enumerate([(-0.2, -0.3), (10.2, 10.3)]):
            moved = position.copy()
            moved[5, axis] = in_margin
            assert stepping.check_positions(moved, reference, n, lo, hi, margin, 1.0)[1] == -1, (axis, side)
            moved[9, axis] = beyond
            assert stepping.check_positions(moved, reference, n, lo, hi, margin, 1.0)[1] == 9, (axis, side)
    position[40, dim - 1] = 10.0 + margin  # on the margin: still inside
    assert stepping.check_positions(position, reference, n, lo, hi, margin, 1.0)[1] == -1
    position[40, dim - 1] = 10.3  # beyond it
    position[45, 0] = -0.3
    assert stepping.check_positions(position, reference, n, lo, hi, margin, 1.0)[1] == 40
    position[30, 1] = np.nan  # not finite: fails every bound, and does not count as moved
    position[35, 0] = np.inf
    position[36, 0] = -np.inf
    moved_far = [i for i in (35, 36, 40, 45) if np.sum((position[i] - reference[i]) ** 2) > 1.0]  # 35, 36: by inf
    assert stepping.check_positions(position, reference, n, lo, hi, margin, 1.0) == (len(moved_far), 30)
    for n_mobile in (30, 36, 37):  # only the first n_mobile particles count
        assert stepping.check_positions(position, reference, n_mobile, lo, hi, margin, 1.0) == slow_check_positions(
            position, reference, n_mobile, lo, hi, margin, 1.0)
