"""forcenet.research.survey.snapshot_row / run_states: the state of a snapshot, on a hand-countable chain of disks."""
from __future__ import annotations

import math

import numpy as np
import pytest

from forcenet.datasets import provenance_attrs, read_snapshot, write_snapshot
from forcenet.datasets.paths import rho_file
from forcenet.research.survey import run_states, snapshot_row


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
    arrays = chain_snapshot_arrays(0.5)
    # make the two overlaps differ: disk 2 shrinks to d = 0.6 and overlaps disk 1 by 0.12, so its contact's
    # fraction is 0.12 / min(1, 0.6) = 0.2 (0.12 if normalised by the larger d); contact (0, 1) stays 0.1 / 1
    arrays["radius"] = np.array([0.5, 0.5, 0.3, 0.5, 0.5])
    arrays["position"][2, 0] = arrays["position"][1, 0] + 0.5 + 0.3 - 0.12  # disk 3 stays 1.62 away: apart
    path = write_snapshot(tmp_path / rho_file("0.500"), attrs=ATTRS, **arrays)
    with read_snapshot(path) as snap:
        row = snapshot_row(snap, force_unit_dyn=10.0)
    assert row["connected"] == 1  # only the middle disk has two contacts
    assert row["overlap_max"] == pytest.approx(0.2) and row["overlap_mean"] == pytest.approx((0.1 + 0.2) / 2)
    assert row["mean_force"] == pytest.approx((3.0 + math.sqrt(32.0)) / 2)
    assert row["mean_force_dyn"] == pytest.approx(10.0 * row["mean_force"])
    assert row["rho_centres"] == pytest.approx(0.5 * (10 / 9) ** 2)


def test_run_states_in_rho_order_and_without_a_force_unit(tmp_path):
    for rho in (0.6, 0.5):
        write_snapshot(tmp_path / rho_file(f"{rho:.3f}"), attrs=ATTRS, **chain_snapshot_arrays(rho))
    rows = run_states(tmp_path)
    assert [row["rho"] for row in rows] == [0.5, 0.6]
    assert math.isnan(rows[0]["mean_force_dyn"])


# --- bulk packing fraction: the inner box away from the walls -------------------------------------------------
def test_bulk_packing_fraction_by_hand():
    from forcenet.dem.packing import bulk_packing_fraction, packing_fraction

    radius = np.array([0.5, 0.5])
    # one disk in the middle, one centred on the inner box's left face (margin 1): 1 + 1/2 disks in 8 x 8
    position = np.array([[5.0, 5.0], [1.0, 5.0]])
    expected = 1.5 * math.pi * 0.25 / 64.0
    assert bulk_packing_fraction(position, radius, [0, 0], [10, 10], 1.0) == pytest.approx(expected)
    # margin 0 is the box average; a margin that leaves no inner box has no bulk
    assert bulk_packing_fraction(position, radius, [0, 0], [10, 10], 0.0) == pytest.approx(
        packing_fraction(radius, np.array([10.0, 10.0])))
    assert math.isnan(bulk_packing_fraction(position, radius, [0, 0], [10, 10], 5.0))
    # a sphere centred on an edge of the inner box (two faces): exactly a quarter of it is inside
    sphere = bulk_packing_fraction(np.array([[1.0, 1.0, 5.0]]), np.array([0.5]), [0, 0, 0], [10, 10, 10], 1.0)
    assert sphere == pytest.approx(0.25 * math.pi / 6.0 / 8.0 ** 3)


def test_bulk_packing_fraction_against_counted_grid_points():
    """A jittered lattice of non-overlapping spheres of two sizes: the analytic shares against the share of a fine
    grid of points of the inner box that lie inside some sphere (the slow obvious reference)."""
    from forcenet.dem.packing import bulk_packing_fraction

    rng = np.random.default_rng(7)
    axis = np.arange(0.75, 6.0, 1.25)
    position = np.stack(np.meshgrid(axis, axis, axis, indexing="ij"), -1).reshape(-1, 3)
    position += rng.uniform(-0.1, 0.1, position.shape)
    radius = rng.choice([0.4, 0.55], len(position))
    margin, lo, hi = 1.3, np.zeros(3), np.full(3, 6.0)
    g = np.linspace(lo[0] + margin, hi[0] - margin, 121)
    g = 0.5 * (g[1:] + g[:-1])  # cell centres
    points = np.stack(np.meshgrid(g, g, g, indexing="ij"), -1).reshape(-1, 3)
    inside = np.zeros(len(points), bool)
    for centre, r in zip(position, radius):
        inside |= ((points - centre) ** 2).sum(axis=1) <= r * r
    assert bulk_packing_fraction(position, radius, lo, hi, margin) == pytest.approx(inside.mean(), abs=0.005)
    # a margin of one sphere radius less is another region, and differs by more than the tolerance above
    assert abs(bulk_packing_fraction(position, radius, lo, hi, 0.9) - inside.mean()) > 0.005


def test_snapshot_row_bulk_packing_fraction(tmp_path):
    path = write_snapshot(tmp_path / rho_file("0.500"), attrs=ATTRS, **chain_snapshot_arrays(0.5))
    with read_snapshot(path) as snap:
        row = snapshot_row(snap, bulk_margin=1.0)
    # all five unit disks lie at least 1 d_ave from the walls of the 10 x 10 box: 5 π/4 in the 8 x 8 inner box
    assert row["rho_bulk"] == pytest.approx(5 * math.pi / 4 / 64)
