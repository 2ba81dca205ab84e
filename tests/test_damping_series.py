"""The damping series' readings (forcenet.damping_series) on hand-made states."""
from __future__ import annotations

import numpy as np
import pytest

from forcenet.damping_series import approach_speeds


def test_approach_speeds_count_only_near_pairs_that_close():
    """Three hand-placed disks of radius 0.5: 0 and 1 are 0.05 apart (gap) and close at 0.3 d_ave/τ_c along the
    line of centres (plus a sliding component that must not count); 1 and 2 are near but separate; 3 is far."""
    position = np.array([[0.0, 0.0], [1.05, 0.0], [1.05, 1.08], [5.0, 5.0]])
    velocity = np.array([[0.1, 0.2], [-0.2, -0.1], [0.0, 0.4], [-1.0, -1.0]])
    radius = np.full(4, 0.5)
    speeds = approach_speeds(position, velocity, radius, gap=0.1)
    np.testing.assert_allclose(speeds, [0.3])
    # a wider gap reaches the far disk's neighbours only if they are near: still one pair
    assert approach_speeds(position, velocity, radius, gap=0.02).size == 0


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

    from forcenet.damping_series import SeriesRun

    assert SeriesRun.parse("results/damping/2d_hertz_g22.1807") == SeriesRun(
        Path("results/damping/2d_hertz_g22.1807"), "2d_hertz", 0)
    assert SeriesRun.parse("results/p1_start:2d_linear") == SeriesRun(Path("results/p1_start"), "2d_linear", 0)
    assert SeriesRun.parse("results/validation:2d_hertz:r03") == SeriesRun(Path("results/validation"), "2d_hertz", 3)
    assert SeriesRun.parse("results/validation:3d_hertz:2").sim == Path("results/validation/sim/3d_hertz/r02")
