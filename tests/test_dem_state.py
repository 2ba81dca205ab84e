"""The DEM state as named structures (`forcenet.dem.state`): a checkpoint is every field of them, under the names
checkpoints have always had, and a Simulation read back from one continues bit for bit."""
from __future__ import annotations

import dataclasses
import logging

import numpy as np

from forcenet.dem import protocol
from forcenet.dem._kernels.law import LAW_GAMMA_N, LAW_K_N, LAW_K_T
from forcenet.dem.engine import ContactLaw, Simulation
from forcenet.dem.state import STATE_PARTS

#: the arrays of a checkpoint as every earlier version wrote them: a checkpoint of any of them must keep loading
CHECKPOINT_ARRAYS = {"gear_position", "gear_rotation", "radius", "mass", "inv_mass", "inv_inertia", "particle_id",
                     "box_lo", "box_hi", "wall_state", "wall_anchor", "wall_axis", "wall_sign", "wall_id", "pair_i",
                     "pair_j", "spring", "wall_spring", "law", "n_mobile", "step", "time_step", "skin", "flat_walls",
                     "escape_margin"}


def small_simulation(wall_stiffness_factor: float = 2.0) -> Simulation:
    """16 disks on a jittered lattice between flat walls moving inward, some of them touching."""
    rng = np.random.default_rng(3)
    position = np.stack(np.meshgrid(np.arange(4.0), np.arange(4.0), indexing="ij"), -1).reshape(-1, 2)
    position += rng.uniform(-0.02, 0.02, position.shape)
    radius = rng.uniform(0.48, 0.53, len(position))
    law = ContactLaw(845.0, 724.0, 40.0, 40.0, 0.3, 0.5, wall_stiffness_factor=wall_stiffness_factor)
    sim = Simulation(position=position, radius=radius, mass=(2.0 * radius) ** 2, law=law, time_step=2.0 ** -7,
                     box_lo=np.full(2, -0.45), box_hi=np.full(2, 3.45), velocity=rng.normal(0.0, 0.05, (16, 2)))
    sim.set_walls(2.0 ** -4)
    return sim


def test_the_field_names_are_the_checkpoint_arrays_and_unique():
    names = [field.name for part in STATE_PARTS for field in dataclasses.fields(part)]
    assert len(names) == len(set(names)) and set(names) == CHECKPOINT_ARRAYS
    assert set(small_simulation().state_dict()) == CHECKPOINT_ARRAYS


def test_a_checkpointed_simulation_continues_bit_for_bit(tmp_path):
    sim = small_simulation()
    sim.advance(30)
    path = tmp_path / "checkpoint.npz"
    protocol.save_checkpoint(path, sim, next_index=0, fingerprint="f", rng=np.random.default_rng(1))
    restored, _, _, _ = protocol.load_checkpoint(path, "f", [], logging.getLogger(__name__))
    sim.rebuild()  # as run_compression does after writing a checkpoint
    for simulation in (sim, restored):
        simulation.advance(40)
    assert restored.step == sim.step == 70
    for a, b in ((restored.positions(), sim.positions()), (restored.velocities(), sim.velocities()),
                 (restored.contacts.spring, sim.contacts.spring), (restored.walls.wall_spring, sim.walls.wall_spring)):
        assert a.tobytes() == b.tobytes()


def test_a_checkpoint_without_a_state_array_is_refused_by_name(tmp_path, caplog):
    sim = small_simulation()
    path = tmp_path / "checkpoint.npz"
    state = sim.state_dict()
    del state["wall_spring"]
    np.savez(path, **state, next_index=0, fingerprint="f", rng_state="{}")
    assert protocol.load_checkpoint(path, "f", [], logging.getLogger(__name__)) is None
    assert "'wall_spring'" in caplog.text and str(path) in caplog.text and "starting from scratch" in caplog.text


def test_the_walls_law_follows_the_contact_law():
    """Flat walls of their own material: k_n and k_t × the factor, made once per law (`state.wall_law`)."""
    sim = small_simulation(wall_stiffness_factor=2.0)
    assert sim.kernel_walls().law[LAW_K_N] == 2.0 * 845.0 and sim.kernel_walls().law[LAW_K_T] == 2.0 * 724.0
    sim.set_law(dataclasses.replace(sim.contact_law, wall_stiffness_factor=3.0, normal_damping=1.0))
    walls_law = sim.kernel_walls().law
    assert walls_law[LAW_K_N] == 3.0 * 845.0 and walls_law[LAW_GAMMA_N] == 1.0 and sim.contacts.law[LAW_K_N] == 845.0
