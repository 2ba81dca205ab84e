"""Bottleneck and Wasserstein distances (L∞ ground metric) against P2's worked example and brute force."""
import math

import numpy as np
import pytest

from forcenet.topology import (
    PersistenceDiagrams,
    bottleneck_distance,
    consecutive_diagram_distances,
    diagram_distances,
    matchable_points,
    wasserstein_distance,
)
from forcenet.topology import _kernels, distances
from naive_topology import optimal_matching_costs


def random_diagram(rng, n, essential=0):
    """n finite super-level points (birth > death ≥ 0) and `essential` never-dying ones."""
    birth = rng.uniform(0.2, 3.0, n)
    death = birth - rng.exponential(0.4, n)
    points = np.stack([birth, np.maximum(death, 0.0)], axis=1)
    points = points[points[:, 0] > points[:, 1]]
    never = np.stack([rng.uniform(0.5, 3.0, essential), np.full(essential, -np.inf)], axis=1)
    return np.concatenate([points, never])


def test_p2_worked_example():
    # P2 §III D, Fig. 5: PD0(f) = {(5, −1)}, PD0(g) = {(3, −1)} + 7 × (1, 0); never-dying classes at −1
    f = np.array([[5.0, -np.inf]])
    g = np.array([[3.0, -np.inf]] + [[1.0, 0.0]] * 7)
    result = diagram_distances(f, g, 0, essential="minus_one")
    assert result["bottleneck"] == 2.0
    assert result["wasserstein_1"] == pytest.approx(5.5, abs=1e-12)  # 2 + 7 × 0.5
    # the paper prints ≈ 2.6; under L∞ it is √(2² + 7 × 0.5²) = √5.75 = 2.398 (DESIGN.md)
    assert result["wasserstein_2"] == pytest.approx(math.sqrt(5.75), abs=1e-12)
    assert result["wasserstein_2"] == pytest.approx(2.398, abs=5e-4)


def test_p2_worked_example_from_persistence_diagrams():
    f = PersistenceDiagrams(np.array([0]), np.array([5.0]), np.array([-np.inf]), np.array([True]))
    g = PersistenceDiagrams(np.zeros(8, int), np.array([3.0] + [1.0] * 7), np.array([-np.inf] + [0.0] * 7),
                            np.array([True] + [False] * 7))
    assert diagram_distances(f, g, 0)["wasserstein_1"] == pytest.approx(5.5)
    assert diagram_distances(f, g, 1) == {"bottleneck": 0.0, "wasserstein_1": 0.0, "wasserstein_2": 0.0}


def test_essential_conventions():
    f = np.array([[5.0, -np.inf]])
    g = np.array([[3.0, -np.inf], [1.0, 0.0]])
    assert diagram_distances(f, g, 0, "minus_one")["wasserstein_1"] == pytest.approx(2.5)
    assert diagram_distances(f, g, 0, "zero")["wasserstein_1"] == pytest.approx(2.5)
    assert diagram_distances(f, g, 0, "drop")["wasserstein_1"] == pytest.approx(0.5)
    # an essential class born at 0 has zero length under "zero": it disappears
    np.testing.assert_array_equal(matchable_points(np.array([[0.0, -np.inf]]), essential="zero"), np.empty((0, 2)))
    with pytest.raises(ValueError):
        matchable_points(f, essential="infinity")


def test_distance_to_itself_is_zero_and_symmetric():
    rng = np.random.default_rng(5)
    a, b = random_diagram(rng, 30, 3), random_diagram(rng, 25, 2)
    for metric, value in diagram_distances(a, a, 0).items():
        assert value == 0.0, metric
    forward, backward = diagram_distances(a, b, 0), diagram_distances(b, a, 0)
    for metric in forward:
        assert forward[metric] == pytest.approx(backward[metric], rel=1e-12)


@pytest.mark.parametrize("seed", range(25))
def test_exact_solver_matches_enumeration_of_all_matchings(seed):
    rng = np.random.default_rng(seed)
    a = random_diagram(rng, int(rng.integers(0, 4)), int(rng.integers(0, 2)))
    b = random_diagram(rng, int(rng.integers(0, 4)), int(rng.integers(0, 2)))
    a, b = matchable_points(a), matchable_points(b)
    if len(a) + len(b) > 7:
        a, b = a[:3], b[:3]
    for q in (1.0, 2.0):
        expected_bottleneck, expected = optimal_matching_costs(a, b, q)
        assert wasserstein_distance(a, b, q) == pytest.approx(expected, rel=1e-12, abs=1e-12)
    assert bottleneck_distance(a, b) == pytest.approx(expected_bottleneck, rel=1e-12, abs=1e-12)


@pytest.mark.parametrize("seed", range(10))
def test_bottleneck_le_w2_le_w1(seed):
    rng = np.random.default_rng(1000 + seed)
    a, b = random_diagram(rng, 60, 4), random_diagram(rng, 50, 5)
    d = diagram_distances(a, b, 0)
    assert 0 < d["bottleneck"] <= d["wasserstein_2"] * (1 + 1e-12)
    assert d["wasserstein_2"] <= d["wasserstein_1"] * (1 + 1e-12)


def full_graph_cost(a, b, q):
    """Σ cost^q of the optimal matching solved on ALL pairs at once (no sparsify-and-verify)."""
    index_a, index_b = np.divmod(np.arange(len(a) * len(b)), len(b))
    distance = np.max(np.abs(a[index_a] - b[index_b]), axis=1)
    delta_a, delta_b = 0.5 * (a[:, 0] - a[:, 1]), 0.5 * (b[:, 0] - b[:, 1])
    flow, _ = _kernels.diagram_transport(len(a), len(b), index_a, index_b, distance ** q, delta_a ** q,
                                         delta_b ** q, np.empty(0, np.int64), np.empty(0))
    cost = np.concatenate([distance ** q, delta_a ** q, delta_b ** q, [0.0]])
    return float(np.sum(flow * cost))


@pytest.mark.parametrize("q", [1.0, 2.0])
@pytest.mark.parametrize("warm_start_fraction", [0.0, 1e9])  # every round cold / every round repaired
def test_sparsify_and_verify_reaches_the_full_optimum(monkeypatch, q, warm_start_fraction):
    # few initial partners force several verification rounds; the essential classes on the line death = −1
    # make the instance degenerate, as in 2D PD1
    monkeypatch.setattr(distances, "N_NEAREST", 1)
    monkeypatch.setattr(distances, "N_WORST", 1)
    monkeypatch.setattr(distances, "WARM_START_FRACTION", warm_start_fraction)
    rng = np.random.default_rng(7)
    finite_a = random_diagram(rng, 80)
    finite_b = finite_a[10:] + rng.normal(0, 0.05, finite_a[10:].shape)
    never_a = rng.uniform(0.5, 3.0, 60)
    never_b = np.concatenate([never_a[5:] + rng.normal(0, 0.05, 55), rng.uniform(0.5, 3.0, 3)])
    a = matchable_points(np.concatenate([finite_a, np.stack([never_a, np.full(60, -np.inf)], axis=1)]))
    b = matchable_points(np.concatenate([finite_b, np.stack([never_b, np.full(58, -np.inf)], axis=1)]))
    total, _ = distances._optimal_matching(a, b, q)
    assert total == pytest.approx(full_graph_cost(a, b, q), rel=1e-12)


def test_agrees_with_dionysus_and_hera():
    rng = np.random.default_rng(11)
    a, b = random_diagram(rng, 40, 3), random_diagram(rng, 35, 2)
    exact = diagram_distances(a, b, 0)
    library = diagram_distances(a, b, 0, backend="dionysus", hera_delta=1e-4)
    assert library["bottleneck"] == pytest.approx(exact["bottleneck"], rel=1e-5)  # float32 inside dionysus
    for metric in ("wasserstein_1", "wasserstein_2"):
        assert library[metric] == pytest.approx(exact[metric], rel=2e-4)


def test_dionysus_timeout_falls_back_to_the_exact_solver():
    f = np.array([[5.0, -np.inf]])
    g = np.array([[3.0, -np.inf]] + [[1.0, 0.0]] * 7)
    with pytest.warns(RuntimeWarning, match="exact backend"):
        result = diagram_distances(f, g, 0, backend="dionysus", timeout_s=1e-3)
    assert result["wasserstein_1"] == pytest.approx(5.5)


def test_consecutive_distances_and_ratios():
    def one_dim(points):
        points = np.asarray(points, float).reshape(-1, 2)
        return PersistenceDiagrams(np.zeros(len(points), int), points[:, 0], points[:, 1],
                                   ~np.isfinite(points[:, 1]))

    sequence = [one_dim([[5.0, -np.inf]]), one_dim([[3.0, -np.inf]] + [[1.0, 0.0]] * 7),
                one_dim([[3.0, -np.inf]] + [[1.0, 0.0]] * 7)]
    result = consecutive_diagram_distances(sequence, homology_dims=(0, 1))
    assert result["bottleneck"].shape == (2, 2)
    np.testing.assert_allclose(result["bottleneck"][:, 0], [2.0, 0.0])
    np.testing.assert_allclose(result["ratio_bottleneck_wasserstein_1"][0, 0], 2.0 / 5.5)
    assert np.isnan(result["ratio_bottleneck_wasserstein_2"][1, 0])  # 0 / 0
