"""forcenet.survey.snapshot_row / run_states: the state of a snapshot, on a hand-countable chain of disks."""
from __future__ import annotations

import math

import numpy as np
import pytest

from forcenet.datasets import provenance_attrs, read_snapshot, write_snapshot
from forcenet.datasets.paths import rho_file
from forcenet.survey import run_states, snapshot_row


def chain_snapshot_arrays(rho: float, overlap: float = 0.1) -> dict:
    """Four unit disks (d = 1) in a row along x, each pair of neighbours overlapping by `overlap` except the last
    pair, which is apart; a fifth disk far away. Contacts (0,1) and (1,2) with |F_n| 3 and 4, F_t (0, 4) on
    the second: |F| = 3 and sqrt(32)."""
    step = 1.0 - overlap
    position = np.array([[2.0, 5.0], [2.0 + step, 5.0], [2.0 + 2 * step, 5.0], [2.0 + 3 * step + 0.5, 5.0],
                         [8.0, 8.0]])
    return dict(position=position, radius=np.full(5, 0.5), velocity=np.zeros((5, 2)), angular_velocity=np.zeros(5),
                contact_i=[0, 1], contact_j=[1, 2], force_normal=[[-3.0, 0.0], [-4.0, 0.0]],
                force_tangential=[[0.0, 0.0], [0.0, 4.0]], wall_contact_particle=[], wall_contact_wall=[],
                wall_contact_force=np.zeros((0, 2)), box_lo=[0.0, 0.0], box_hi=[10.0, 10.0], rho=rho, Z=0.8,
                kinetic_energy=1e-9, pressure=0.0, time=1.0, step=10, relaxation_steps=1000)


ATTRS = {**provenance_attrs(system="2d_linear", realization=0, seed=1, config=None, title="a chain"),
         "dem_damping_rate_time_step": 0.4}


def test_snapshot_row_counts_the_chain(tmp_path):
    path = write_snapshot(tmp_path / rho_file("0.500"), attrs=ATTRS, **chain_snapshot_arrays(0.5))
    with read_snapshot(path) as snap:
        row = snapshot_row(snap, force_unit_dyn=10.0)
    assert row["connected"] == 1  # only the middle disk has two contacts
    assert row["overlap_max"] == pytest.approx(0.1) and row["overlap_mean"] == pytest.approx(0.1)
    assert row["mean_force"] == pytest.approx((3.0 + math.sqrt(32.0)) / 2)
    assert row["mean_force_dyn"] == pytest.approx(10.0 * row["mean_force"])
    assert row["rho_centres"] == pytest.approx(0.5 * (10 / 9) ** 2)


def test_run_states_in_rho_order_and_without_a_force_unit(tmp_path):
    for rho in (0.6, 0.5):
        write_snapshot(tmp_path / rho_file(f"{rho:.3f}"), attrs=ATTRS, **chain_snapshot_arrays(rho))
    rows = run_states(tmp_path)
    assert [row["rho"] for row in rows] == [0.5, 0.6]
    assert math.isnan(rows[0]["mean_force_dyn"])
