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
from forcenet.topology import _matching, distances
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
    # the paper prints ≈ 2.6; under L∞ it is √(2² + 7 × 0.5²) = √5.75 = 2.398 (docs/decisions.md)
    assert result["wasserstein_2"] == pytest.approx(math.sqrt(5.75), abs=1e-12)
    assert result["wasserstein_2"] == pytest.approx(2.398, abs=5e-4)


def test_p2_worked_example_from_persistence_diagrams():
    f = PersistenceDiagrams(np.array([0]), np.array([5.0]), np.array([-np.inf]))
    g = PersistenceDiagrams(np.zeros(8, int), np.array([3.0] + [1.0] * 7), np.array([-np.inf] + [0.0] * 7))
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
    flow, _ = _matching.diagram_transport(len(a), len(b), index_a, index_b, distance ** q, delta_a ** q,
                                         delta_b ** q, np.empty(0, np.int64), np.empty(0))
    cost = np.concatenate([distance ** q, delta_a ** q, delta_b ** q, [0.0]])
    return float(np.sum(flow * cost))


@pytest.mark.parametrize("q", [1.0, 2.0])
@pytest.mark.parametrize("warm_start_fraction", [0.0, 1e9])  # every round cold / every round repaired
@pytest.mark.parametrize("line_band", [0, 3])
def test_sparsify_and_verify_reaches_the_full_optimum(monkeypatch, q, warm_start_fraction, line_band):
    # few initial partners force several verification rounds; the essential classes on the line death = −1
    # make the instance degenerate, as in 2D PD1
    monkeypatch.setattr(distances, "N_NEAREST", 1)
    monkeypatch.setattr(distances, "N_WORST", 1)
    monkeypatch.setattr(distances, "WARM_START_FRACTION", warm_start_fraction)
    monkeypatch.setattr(distances, "LINE_BAND", line_band)
    rng = np.random.default_rng(7)
    finite_a = random_diagram(rng, 80)
    finite_b = finite_a[10:] + rng.normal(0, 0.05, finite_a[10:].shape)
    never_a = rng.uniform(0.5, 3.0, 60)
    never_b = np.concatenate([never_a[5:] + rng.normal(0, 0.05, 55), rng.uniform(0.5, 3.0, 3)])
    a = matchable_points(np.concatenate([finite_a, np.stack([never_a, np.full(60, -np.inf)], axis=1)]))
    b = matchable_points(np.concatenate([finite_b, np.stack([never_b, np.full(58, -np.inf)], axis=1)]))
    total, _ = distances._optimal_matching(a, b, q)
    assert total == pytest.approx(full_graph_cost(a, b, q), rel=1e-12)


@pytest.mark.filterwarnings("error::RuntimeWarning")  # a fallback to the exact solver would compare it with itself
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


def test_consecutive_diagram_distances():
    # (ratios d_B/d_Wq: forcenet.report.p2.distance_ratio, tested in test_report_p2.py)
    def one_dim(points):
        points = np.asarray(points, float).reshape(-1, 2)
        return PersistenceDiagrams(np.zeros(len(points), int), points[:, 0], points[:, 1],
                                   ~np.isfinite(points[:, 1]))

    sequence = [one_dim([[5.0, -np.inf]]), one_dim([[3.0, -np.inf]] + [[1.0, 0.0]] * 7),
                one_dim([[3.0, -np.inf]] + [[1.0, 0.0]] * 7)]
    result = consecutive_diagram_distances(sequence, homology_dims=(0, 1))
    assert sorted(result) == sorted(distances.METRICS)
    assert result["bottleneck"].shape == (2, 2)
    np.testing.assert_allclose(result["bottleneck"][:, 0], [2.0, 0.0])
    np.testing.assert_allclose(result["wasserstein_1"][:, 0], [5.5, 0.0])
    np.testing.assert_allclose(result["wasserstein_2"][:, 1], [0.0, 0.0])  # no PD1 points anywhere


@pytest.mark.parametrize("q", [1.0, 2.0])
def test_line_matching_is_optimal_for_points_on_one_death_line(q):
    # points sharing death −1 with tied births: the dynamic programme equals enumeration of all matchings
    rng = np.random.default_rng(int(q))
    for _ in range(30):
        birth_a = np.sort(rng.choice([0.2, 0.5, 0.6, 1.1, 1.4], int(rng.integers(1, 4))))
        birth_b = np.sort(rng.choice([0.2, 0.5, 0.7, 1.1, 1.5], int(rng.integers(1, 4))))
        partner = _matching.line_matching(birth_a, birth_b, -1.0, q)
        matched = partner[partner >= 0]
        assert np.unique(matched).size == matched.size  # a matching
        total = np.sum(np.abs(birth_a[partner >= 0] - birth_b[matched]) ** q)
        total += np.sum((0.5 * (birth_a[partner < 0] + 1)) ** q)
        total += np.sum((0.5 * (np.delete(birth_b, matched) + 1)) ** q)
        a = np.stack([birth_a, np.full(len(birth_a), -1.0)], axis=1)
        b = np.stack([birth_b, np.full(len(birth_b), -1.0)], axis=1)
        assert total ** (1 / q) == pytest.approx(optimal_matching_costs(a, b, q)[1], rel=1e-12, abs=1e-12)


def brute_force_bottleneck(a, b):
    """Smallest L∞ threshold with a perfect matching of the full (n + m) × (n + m) graph with diagonal copies
    (every pair, diagonal copies all joined at 0), by Kuhn's augmenting paths over every candidate value."""
    n, m = len(a), len(b)
    weight = np.full((n + m, n + m), np.inf)
    weight[:n, :m] = np.max(np.abs(a[:, None, :] - b[None, :, :]), axis=2)
    weight[np.arange(n), m + np.arange(n)] = 0.5 * (a[:, 0] - a[:, 1])
    weight[n + np.arange(m), np.arange(m)] = 0.5 * (b[:, 0] - b[:, 1])
    weight[n:, m:] = 0.0

    def perfect(threshold):
        allowed = weight <= threshold
        row_of_col = [-1] * (n + m)

        def augment(row, seen):
            for col in np.flatnonzero(allowed[row]):
                if not seen[col]:
                    seen[col] = True
                    if row_of_col[col] < 0 or augment(row_of_col[col], seen):
                        row_of_col[col] = row
                        return True
            return False
        return all(augment(row, [False] * (n + m)) for row in range(n + m))

    values = np.unique(weight[np.isfinite(weight)])
    low, high = 0, values.size - 1
    while low < high:
        middle = (low + high) // 2
        low, high = (low, middle) if perfect(values[middle]) else (middle + 1, high)
    return float(values[low])


@pytest.mark.parametrize("seed", range(6))
def test_many_points_on_the_line_death_minus_one_match_the_full_solve(seed):
    # 2D-PD1-like diagrams: most points never die (death −1 under "minus_one"), births with ties, B's line
    # shifted a few places against A's (long chains in the optimal matching), finite points that may be
    # matched across to the line; compared with one solve on ALL pairs and a brute-force bottleneck
    rng = np.random.default_rng(300 + seed)
    never_a = np.round(rng.uniform(0.1, 1.5, 40), 2)  # rounding makes ties
    never_b = np.concatenate([np.round(never_a[3:] + rng.normal(0, 0.02, 37), 2), np.round(rng.uniform(0.1, 1.5, 4), 2)])
    finite_a, finite_b = random_diagram(rng, 8), random_diagram(rng, 6)
    a = matchable_points(np.concatenate([finite_a, np.stack([never_a, np.full(40, -np.inf)], axis=1)]))
    b = matchable_points(np.concatenate([finite_b, np.stack([never_b, np.full(41, -np.inf)], axis=1)]))
    d = diagram_distances(a, b, 0)
    for q in (1, 2):
        assert d[f"wasserstein_{q}"] == pytest.approx(full_graph_cost(a, b, q) ** (1 / q), rel=1e-12)
    assert d["bottleneck"] == brute_force_bottleneck(a, b)
    assert d["bottleneck"] == bottleneck_distance(a, b, upper_bound=np.inf)  # the binary search alone


def test_never_dying_classes_matched_only_with_each_other():
    # convention "apart" (issue 25): P2's worked example with the two never-dying classes paired by birth (5 vs 3:
    # 2 in L-infinity) and the seven finite points of g going to the diagonal (0.5 each)
    f = np.array([[5.0, -np.inf]])
    g = np.array([[3.0, -np.inf]] + [[1.0, 0.0]] * 7)
    d = diagram_distances(f, g, 0, "apart")
    assert d["bottleneck"] == pytest.approx(2.0) and d["wasserstein_1"] == pytest.approx(3.5 + 2.0)
    assert d["wasserstein_2"] == pytest.approx(math.sqrt(7 * 0.25 + 4.0))
    # births pair off in order (the optimal matching on a line), whatever the order given
    two = diagram_distances(np.array([[5.0, -np.inf], [1.0, -np.inf]]), np.array([[1.5, -np.inf], [4.0, -np.inf]]),
                            0, "apart")
    assert two["bottleneck"] == pytest.approx(1.0) and two["wasserstein_1"] == pytest.approx(1.5)
    # different numbers of never-dying classes: no matching exists
    assert math.isinf(diagram_distances(f, np.array([[5.0, -np.inf], [3.0, -np.inf]]), 0, "apart")["bottleneck"])
    # under P2's -1 the same pair is finite: the floor the never-dying classes put under d_B
    assert diagram_distances(f, np.array([[5.0, -np.inf], [3.0, -np.inf]]), 0, "minus_one")["bottleneck"] == 2.0
