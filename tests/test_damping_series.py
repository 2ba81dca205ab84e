"""The damping series' readings (forcenet.research.damping_series) on hand-made states."""
from __future__ import annotations

import numpy as np
import pytest

from forcenet.research.damping_series import approach_speeds, median_approach_speed


def test_approach_speeds_count_only_near_pairs_that_close():
    """Three hand-placed disks of radius 0.5: 0 and 1 are 0.05 apart (gap) and close at 0.3 d_ave/τ_c along the
    line of centres (plus a sliding component that must not count); 1 and 2 are near but separate; 3 is far."""
    position = np.array([[0.0, 0.0], [1.05, 0.0], [1.05, 1.08], [5.0, 5.0]])
    velocity = np.array([[0.1, 0.2], [-0.2, -0.1], [0.0, 0.4], [-1.0, -1.0]])
    radius = np.full(4, 0.5)
    speeds = approach_speeds(position, velocity, radius, gap=0.1)
    np.testing.assert_allclose(speeds, [0.3])
    # a gap narrower than the 0.05 between disks 0 and 1 counts no pair at all
    assert approach_speeds(position, velocity, radius, gap=0.02).size == 0


def test_the_median_approach_speed_needs_every_state_s_velocities():
    """Two states of the three disks above (speeds 0.3, and 0.3 and 0.5 with disk 1 closing faster): the median over
    both; a state restored from a campaign record (no velocities) or no state at all gives NaN, not a speed."""
    position = np.array([[0.0, 0.0], [1.05, 0.0], [1.05, 1.08], [5.0, 5.0]])
    radius = np.full(4, 0.5)
    slow = np.array([[0.1, 0.2], [-0.2, -0.1], [0.0, 0.4], [-1.0, -1.0]])
    fast = np.array([[0.1, 0.2], [-0.4, -0.1], [0.0, -0.6], [-1.0, -1.0]])  # 0-1 close at 0.5, 1-2 at 0.5
    assert approach_speeds(position, fast, radius).tolist() == pytest.approx([0.5, 0.5])
    assert median_approach_speed([(position, slow, radius), (position, fast, radius)]) == pytest.approx(0.5)
    assert median_approach_speed([(position, slow, radius)]) == pytest.approx(0.3)
    assert np.isnan(median_approach_speed([(position, slow, radius), (position, None, radius)]))
    assert np.isnan(median_approach_speed([]))


def test_approach_speeds_match_a_slow_reference():
    rng = np.random.default_rng(3)
    position = rng.uniform(0, 8, (300, 2))
    velocity = rng.normal(0, 1, (300, 2))
    radius = rng.uniform(0.3, 0.6, 300)
    reference = []
    for i in range(300):
        for j in range(i + 1, 300):
            offset = position[j] - position[i]
            distance = np.linalg.norm(offset)
            if distance - radius[i] - radius[j] < 0.1:
                closing = -np.dot(velocity[j] - velocity[i], offset / distance)
                if closing > 0:
                    reference.append(closing)
    assert sorted(approach_speeds(position, velocity, radius)) == pytest.approx(sorted(reference))


def test_a_series_run_is_named_by_folder_system_and_realization():
    from pathlib import Path

    from forcenet.research.damping_series import SeriesRun

    assert SeriesRun.parse("results/damping/2d_hertz_g22.1807") == SeriesRun(
        Path("results/damping/2d_hertz_g22.1807"), "2d_hertz", 0)
    assert SeriesRun.parse("results/p1_start:2d_linear") == SeriesRun(Path("results/p1_start"), "2d_linear", 0)
    assert SeriesRun.parse("results/validation:2d_hertz:r03") == SeriesRun(Path("results/validation"), "2d_hertz", 3)
    assert SeriesRun.parse("results/validation:3d_hertz:2").sim == Path("results/validation/sim/3d_hertz/r02")


def test_a_run_without_its_aggregate_is_read_from_its_own_analyses(smoke_run, tmp_path):
    """A campaign run whose other realizations are unfinished has no `network_measures.nc` yet: its readings come
    from its own per-snapshot analyses, equal to the aggregate's; with one analysis missing there are none."""
    import math
    import shutil

    import numpy as np

    from forcenet.research.damping_series import SeriesRun, network_readings, run_network_measures

    results = smoke_run / "results"
    whole = SeriesRun(results, "2d_hertz", 0)
    alone = tmp_path / "results"
    for part in ("sim", "analysis"):
        shutil.copytree(results / part / "2d_hertz" / "r00", alone / part / "2d_hertz" / "r00")
    run = SeriesRun(alone, "2d_hertz", 0)
    assert not (alone / "2d_hertz").exists()  # no aggregate beside the copied run
    from_aggregate, from_analyses = run_network_measures(whole), run_network_measures(run)
    for name in ("betti", "rho_measured", "persistence_bin_count", "cluster_mean_size"):
        np.testing.assert_array_equal(from_analyses[name].values, from_aggregate[name].values)
    # the smoke grid (three states) never jams: read "near jamming" around its middle state
    rho_middle = float(from_aggregate.rho_measured.values[1])
    readings = network_readings(run, rho_middle)
    np.testing.assert_equal(readings, network_readings(whole, rho_middle))
    assert math.isfinite(readings["b0_small_near_jamming"]) and readings["b0_small_near_jamming"] > 0

    first = sorted((alone / "analysis" / "2d_hertz" / "r00").glob("rho*.nc"))[0]
    first.unlink()
    assert run_network_measures(run) is None
    assert all(math.isnan(value) for value in network_readings(run, rho_middle).values())
