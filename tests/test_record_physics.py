"""The committed campaign records obey mechanics: a state relaxed to rest by P1's protocol is in equilibrium, so the
recorded contact and wall forces on each particle sum to ~0 (`forcenet.measures.forces.force_imbalance`). A record
whose forces are not those that moved its particles (a kernel that recorded other forces than it stepped with)
fails here."""
from __future__ import annotations

import numpy as np
import pytest

from conftest import REPO, load_config
from forcenet import campaign
from forcenet.datasets.records import read_dataset, state_snapshot
from forcenet.measures.forces import FORCE_BALANCE_TOLERANCE, force_imbalance, net_contact_forces

CONFIG = load_config("validation.yaml")
RECORDS = REPO / CONFIG["records_dir"]


def chain(wall_force: float) -> dict:
    """Three disks in a row pressed between two walls: each pair pushes with 1 along x, the walls with `wall_force`."""
    return {"radius": np.ones(3), "contact_i": np.array([1, 2]), "contact_j": np.array([0, 1]),
            "force_normal": np.array([[1.0, 0.0], [1.0, 0.0]]), "force_tangential": np.zeros((2, 2)),
            "wall_contact_particle": np.array([0, 2]),
            "wall_contact_force": np.array([[wall_force, 0.0], [-wall_force, 0.0]])}


def test_net_forces_follow_newtons_third_law_by_hand():
    net = net_contact_forces(3, [1], [0], [[2.0, -1.0]], [0], [[0.5, 0.0]])
    np.testing.assert_array_equal(net, [[-1.5, 1.0], [2.0, -1.0], [0.0, 0.0]])


def test_a_chain_pressed_by_its_walls_balances_and_a_doubled_wall_force_does_not():
    # particle 0: -1 from particle 1, +1 from the lower wall; particle 2: +1 from 1, -1 from the upper wall
    assert force_imbalance(chain(1.0)) == (0.0, 0)
    # walls twice as strong as the chain transmits: particles 0 and 2 feel 1 too much (mean normal force 1)
    imbalance, particle = force_imbalance(chain(2.0))
    assert imbalance == pytest.approx(1.0) and particle in (0, 2)


def quasistatic_records() -> list[dict]:
    return [row for row in campaign.read_manifest(RECORDS) if row["file"].endswith("states.nc")
            and CONFIG["systems"][row["system"]]["protocol"] == "quasistatic"]


@pytest.mark.parametrize("row", quasistatic_records(), ids=lambda row: f"{row['system']}-{row['realization']}")
def test_every_jammed_state_of_a_record_is_in_equilibrium(row):
    record = read_dataset(RECORDS / row["file"], "run_record")
    dimension = record.sizes["spatial"]
    jammed = [index for index in range(record.sizes["state"]) if float(record["Z"].values[index]) >= dimension + 1]
    assert jammed, "a paper-size run ends jammed"
    for index in jammed:
        _, arrays = state_snapshot(record, index)
        imbalance, particle = force_imbalance(arrays)
        assert imbalance <= FORCE_BALANCE_TOLERANCE, (
            f"{row['file']} state {record['state'].values[index]}: particle {particle} feels a net contact force "
            f"{imbalance:.3g} x the mean normal force")
