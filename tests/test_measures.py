"""Clusters, percolation, shape parameter, force PDF, persistence bins, total persistence, jamming point."""
import itertools

import numpy as np
import pytest

from forcenet.measures import (
    PERSISTENCE_BINS,
    aggregate_shape_parameter,
    cluster_curves,
    clusters_at,
    compute_snapshot_measures,
    fit_logistic,
    force_pdf,
    isostatic_crossing,
    jamming_point,
    persistence_bin_counts,
    total_persistence,
)
from forcenet.network import build_force_network, network_from_edge_forces
from forcenet.topology import PersistenceDiagrams, betti_curves, persistence_diagrams
from naive_topology import components, nearest_image_counts, winding_axes

X_LO, X_HI, Y_LO, Y_HI = range(4)


def chain(n, force, **walls):
    """Particles 0..n−1 in a row along x, consecutive ones in contact."""
    return network_from_edge_forces(np.arange(n - 1), np.arange(1, n), force, n_particles=n,
                                    position=np.stack([np.arange(n), np.zeros(n)], axis=1), **walls)


# --- percolation and cluster sizes ---------------------------------------------------------------------------
def test_a_chain_spanning_two_opposite_walls_percolates():
    force = [2.0, 1.0, 3.0, 2.0]  # 5 particles; the weakest link (1.0) is between particles 1 and 2
    network = chain(5, force, wall_particle=[0, 4], wall_id=[X_LO, X_HI])
    curves = cluster_curves(network, np.array([0.0, 1.0, 1.5, 2.5, 3.5]))
    np.testing.assert_array_equal(curves.percolates, [True, True, False, False, False])
    np.testing.assert_array_equal(curves.percolating_size, [5, 5, 0, 0, 0])
    np.testing.assert_array_equal(curves.cluster_count, [1, 1, 2, 1, 0])
    # ⟨S⟩ leaves the percolating cluster out; at 1.5 the chain splits into {0,1} and {2,3,4}
    np.testing.assert_allclose(curves.cluster_mean_size, [0.0, 0.0, 2.5, 2.0, 0.0])
    np.testing.assert_array_equal(curves.largest_cluster_size, [5, 5, 3, 2, 0])


def test_touching_one_wall_or_two_adjacent_walls_is_not_percolation():
    network = chain(4, [1.0, 1.0, 1.0], wall_particle=[0, 3, 3], wall_id=[X_LO, X_LO, Y_HI])
    assert not cluster_curves(network, np.array([0.0])).percolates[0]


def test_percolation_axes_can_be_restricted():
    network = chain(3, [1.0, 1.0], wall_particle=[0, 2], wall_id=[Y_LO, Y_HI])
    assert cluster_curves(network, np.array([0.5])).percolates[0]
    assert not cluster_curves(network, np.array([0.5]), percolation_axes=[0]).percolates[0]


def test_clusters_at_one_threshold():
    network = chain(6, [3.0, 3.0, 0.5, 3.0, 3.0], wall_particle=[0, 5], wall_id=[X_LO, X_HI])
    clusters = clusters_at(network, 1.0)
    np.testing.assert_array_equal(np.sort(clusters.size), [3, 3])
    np.testing.assert_array_equal(clusters.edge_count, [2, 2])
    assert not clusters.percolating.any()
    np.testing.assert_array_equal(clusters.particle_label, [0, 0, 0, 1, 1, 1])
    assert clusters_at(network, 0.5).percolating.tolist() == [True]
    assert (clusters_at(network, 5.0).particle_label == -1).all()


def ring_across_x(force, period):
    """Four particles in a row at x = 0.5 … 3.5, y = 1, each touching the next, the last touching the first
    through the x face of a box 4 wide when that axis is periodic (`period`)."""
    return network_from_edge_forces([0, 1, 2, 0], [1, 2, 3, 3], force, position=[[0.5, 1], [1.5, 1], [2.5, 1],
                                                                               [3.5, 1]], period=period)


def test_a_ring_around_a_periodic_axis_percolates_and_the_same_ring_in_a_bounded_box_does_not():
    force = [2.0, 2.0, 2.0, 1.0]  # the face-crossing contact 0–3 is the weakest: the ring closes at F_th ≤ 1
    thresholds = np.array([0.0, 1.0, 1.5, 3.0])
    periodic = cluster_curves(ring_across_x(force, [4.0, 0.0]), thresholds)
    np.testing.assert_array_equal(periodic.percolates, [True, True, False, False])
    np.testing.assert_array_equal(periodic.percolating_size, [4, 4, 0, 0])
    np.testing.assert_allclose(periodic.cluster_mean_size, [0.0, 0.0, 4.0, 0.0])  # the ring is left out of ⟨S⟩
    bounded = cluster_curves(ring_across_x(force, None), thresholds)
    assert not bounded.percolates.any()
    np.testing.assert_array_equal(bounded.cluster_count, periodic.cluster_count)
    assert clusters_at(ring_across_x(force, [4.0, 0.0]), 1.0).percolating.tolist() == [True]
    assert clusters_at(ring_across_x(force, [4.0, 0.0]), 1.0).wall_mask.tolist() == [(1 << X_LO) | (1 << X_HI)]
    assert clusters_at(ring_across_x(force, None), 1.0).percolating.tolist() == [False]
    with pytest.raises(ValueError, match="period must hold 2 box lengths"):
        ring_across_x(force, [4.0])
    # only the axes asked for count: winding around x is x's percolation
    assert not cluster_curves(ring_across_x(force, [4.0, 0.0]), thresholds, percolation_axes=[1]).percolates.any()


def test_crossing_a_periodic_face_without_winding_around_it_is_not_percolation():
    # a triangle that straddles the x face (x = 0.3, 3.7, 3.7 in a box 4 wide): its loop is contractible
    position = [[0.3, 1.0], [3.7, 0.6], [3.7, 1.4]]
    triangle = network_from_edge_forces([0, 0, 1], [1, 2, 2], [1.0, 1.0, 1.0], position=position, period=[4.0, 0.0])
    assert not cluster_curves(triangle, np.array([0.0])).percolates[0]
    assert not clusters_at(triangle, 0.0).percolating[0]
    # an open chain through the face
    chain_through = network_from_edge_forces([0, 1], [1, 2], [1.0, 1.0], position=[[3.2, 1], [0.1, 1], [1.0, 1]],
                                             period=[4.0, 0.0])
    assert not cluster_curves(chain_through, np.array([0.0])).percolates[0]


def test_a_box_periodic_in_x_with_walls_in_y_percolates_either_way():
    # the ring of `ring_across_x` winds around x; a separate chain 4–5–6 touches both y walls
    position = [[0.5, 1], [1.5, 1], [2.5, 1], [3.5, 1], [1.0, 3.0], [1.0, 4.0], [1.0, 5.0]]
    network = network_from_edge_forces([0, 1, 2, 0, 4, 5], [1, 2, 3, 3, 5, 6], [1.0, 1.0, 1.0, 0.5, 2.0, 2.0],
                                       position=position, period=[4.0, 0.0], wall_particle=[4, 6],
                                       wall_id=[Y_LO, Y_HI])
    curves = cluster_curves(network, np.array([0.0, 0.75]))
    np.testing.assert_array_equal(curves.percolating_count, [2, 1])
    np.testing.assert_array_equal(curves.percolating_size, [7, 3])
    np.testing.assert_array_equal(cluster_curves(network, np.array([0.0]), percolation_axes=[0]).percolating_size,
                                  [4])


@pytest.mark.parametrize("seed", range(6))
@pytest.mark.parametrize("period", [[6.0, 6.0], [6.0, 0.0], [4.0, 4.0, 4.0]])
def test_winding_percolation_matches_breadth_first_search(seed, period):
    rng = np.random.default_rng(seed)
    dim, n = len(period), 40 if len(period) == 2 else 45
    extent = np.where(np.array(period) > 0, period, 6.0)
    position = rng.random((n, dim)) * extent
    pairs = np.array(list(itertools.combinations(range(n), 2)))
    images = nearest_image_counts(position, pairs[:, 0], pairs[:, 1], period)
    gap = np.linalg.norm(position[pairs[:, 0]] - position[pairs[:, 1]] - images * np.array(period), axis=1)
    near = gap < (1.4 if dim == 2 else 1.35)
    edges, images = pairs[near], images[near]
    force = rng.exponential(1.0, len(edges))
    network = network_from_edge_forces(edges[:, 0], edges[:, 1], force, n_particles=n, position=position,
                                       dim=dim, period=period)
    thresholds = np.linspace(0.0, 2.5, 26)
    curves = cluster_curves(network, thresholds)
    edge_list = [tuple(e) for e in edges.tolist()]
    periodic_axes = set(np.flatnonzero(np.array(period) > 0).tolist())
    wound = []
    for t, theta in enumerate(thresholds):
        groups = components(n, edge_list, list(force), theta)
        winds = [bool(axes & periodic_axes) for axes in winding_axes(n, edge_list, images, list(force), theta)]
        wound.append(any(winds))
        assert curves.percolating_count[t] == sum(winds)
        assert curves.percolating_size[t] == sum(len(g) for g, w in zip(groups, winds) if w)
        at = clusters_at(network, theta)
        assert at.percolating.sum() == sum(winds)
        assert at.size[at.percolating].sum() == curves.percolating_size[t]
    assert wound[0] and not wound[-1]  # the case holds both: a network that winds at small F_th, not at large


@pytest.mark.parametrize("seed", range(8))
def test_cluster_sweep_matches_breadth_first_search_and_b0(seed):
    rng = np.random.default_rng(seed)
    n = 30
    edges = np.array([e for e in itertools.combinations(range(n), 2) if rng.random() < 0.08]).reshape(-1, 2)
    force = rng.exponential(1.0, len(edges))
    walls = rng.choice(n, 8, replace=False)
    network = network_from_edge_forces(edges[:, 0], edges[:, 1], force, n_particles=n, wall_particle=walls,
                                       wall_id=np.arange(8) % 4)
    wall_of = {}
    for p, w in zip(walls.tolist(), (np.arange(8) % 4).tolist()):
        wall_of.setdefault(p, set()).add(w)
    thresholds = np.linspace(0.0, 3.0, 31)
    curves = cluster_curves(network, thresholds)
    betti = betti_curves(persistence_diagrams(network), thresholds)
    edge_list = [tuple(e) for e in edges.tolist()]
    for t, theta in enumerate(thresholds):
        groups = components(n, edge_list, list(force), theta)
        if theta <= 0:  # network particles without any contact are one-particle clusters at F_th ≤ 0 (= B0)
            isolated = set(range(n)) - {v for e in edge_list for v in e}
            groups += [{v} for v in isolated]
        touching = [set().union(*(wall_of.get(v, set()) for v in g)) for g in groups]
        percolating = [({0, 1} <= w) or ({2, 3} <= w) for w in touching]
        others = [len(g) for g, p in zip(groups, percolating) if not p]
        edges_in = [sum(1 for (a, _), f in zip(edge_list, force) if f >= theta and a in g) for g in groups]
        assert curves.cluster_count[t] == len(groups) == betti[0, t]
        assert curves.percolating_count[t] == sum(percolating)
        assert curves.percolates[t] == any(percolating)
        assert curves.percolating_size[t] == sum(len(g) for g, p in zip(groups, percolating) if p)
        assert curves.cluster_mean_size[t] == pytest.approx(np.mean(others) if others else 0.0)
        assert curves.largest_cluster_size[t] == max((len(g) for g in groups), default=0)
        strong = int(np.count_nonzero(force >= theta))
        assert curves.edge_count[t] == strong
        assert curves.shape_parameter[t] == pytest.approx(strong / sum(map(len, groups)) if groups else 0.0)
        assert sum(edges_in) == strong
        assert curves.shape_parameter_cluster_mean[t] == pytest.approx(
            np.mean([e / len(g) for e, g in zip(edges_in, groups)]) if groups else 0.0)


# --- shape parameter (P1 §5.2) --------------------------------------------------------------------------------
@pytest.mark.parametrize("n", [2, 5, 12])
def test_shape_parameter_of_an_open_path(n):
    curves = cluster_curves(chain(n, np.ones(n - 1)), np.array([0.5]))
    assert curves.shape_parameter[0] == pytest.approx((n - 1) / n)


def test_shape_parameter_of_a_loop_is_one():
    n = 7
    network = network_from_edge_forces(np.arange(n), (np.arange(n) + 1) % n, np.ones(n))
    assert cluster_curves(network, np.array([0.5])).shape_parameter[0] == pytest.approx(1.0)


def test_shape_parameter_of_a_square_lattice_patch():
    side = 4  # 16 particles, 2 × 4 × 3 = 24 edges
    index = np.arange(side * side).reshape(side, side)
    pairs = np.concatenate([np.stack([index[:, :-1].ravel(), index[:, 1:].ravel()], axis=1),
                            np.stack([index[:-1, :].ravel(), index[1:, :].ravel()], axis=1)])
    network = network_from_edge_forces(pairs[:, 0], pairs[:, 1], np.ones(len(pairs)))
    curves = cluster_curves(network, np.array([0.5, 2.0]))
    np.testing.assert_allclose(curves.shape_parameter, [24 / 16, 0.0])
    np.testing.assert_allclose(curves.shape_parameter_cluster_mean, [24 / 16, 0.0])


def test_shape_parameter_pools_clusters_and_the_cluster_mean_does_not():
    # a 3-path (2 edges / 3 particles) and a 4-loop (4 / 4)
    network = network_from_edge_forces([0, 1, 3, 4, 5, 6], [1, 2, 4, 5, 6, 3], np.ones(6))
    curves = cluster_curves(network, np.array([0.5]))
    assert curves.shape_parameter[0] == pytest.approx(6 / 7)
    assert curves.shape_parameter_cluster_mean[0] == pytest.approx((2 / 3 + 1) / 2)


def test_shape_parameter_across_realizations_follows_p1():
    # P1 §5.2: 0 if S̄_p = 0 in at least half of the realizations, else the mean over the non-zero ones
    values = np.array([[0.0, 0.0, 1.0, 1.2],
                       [0.0, 1.5, 1.0, np.nan],
                       [0.9, 1.5, 0.0, 1.4]])
    np.testing.assert_allclose(aggregate_shape_parameter(values, axis=0), [0.0, 1.5, 1.0, 1.3])


def test_shape_parameter_across_realizations_at_exactly_half_zero():
    # 4 realizations: exactly half zero (2 of 4) is "at least half" -> 0; one zero in 4 -> mean of the other 3
    values = np.array([[0.0, 0.0, 1.0, 0.0],
                       [0.0, 1.2, 1.2, 0.8],
                       [1.4, 1.4, 1.4, np.nan],
                       [1.6, 1.6, 1.6, np.nan]])
    # column 3: two NaN realizations are ignored, so 1 zero of 2 valid is again exactly half -> 0
    np.testing.assert_allclose(aggregate_shape_parameter(values, axis=0), [0.0, (1.2 + 1.4 + 1.6) / 3,
                                                                           (1.0 + 1.2 + 1.4 + 1.6) / 4, 0.0])
    # same columns along axis 1 give the same answer
    np.testing.assert_allclose(aggregate_shape_parameter(values.T, axis=1),
                               aggregate_shape_parameter(values, axis=0))
    # just under half: 1 zero of 3 valid -> mean of the non-zero two
    assert aggregate_shape_parameter(np.array([0.0, 0.9, 1.1, np.nan]))[()] == pytest.approx(1.0)


# --- forces, persistence summaries ---------------------------------------------------------------------------
def test_force_pdf_on_fixed_bins():
    network = network_from_edge_forces(np.arange(4), np.arange(1, 5), [0.25, 0.75, 0.75, 7.0])
    pdf, edges = force_pdf(network, np.array([0.0, 0.5, 1.0, 2.0]))
    np.testing.assert_allclose(pdf, [0.25 / 0.5, 0.5 / 0.5, 0.0])
    assert np.sum(pdf * np.diff(edges)) == pytest.approx(0.75)  # one force in four lies beyond the bins
    default_pdf, default_edges = force_pdf(network)
    assert default_edges[0] == 0.0 and default_edges[-1] == 6.0 and default_pdf.size == 60


def constructed_diagrams():
    # PD0: rough (lifespan ≤ 0.1), weak, medium, strong points and one essential; PD1: two finite points
    return PersistenceDiagrams(
        homology_dim=np.array([0, 0, 0, 0, 0, 0, 1, 1, 1]),
        birth=np.array([3.0, 2.55, 1.2, 0.5, 0.45, 4.0, 1.0, 0.8, 2.0]),
        death=np.array([2.95, 0.5, 0.2, 0.3, 0.2, -np.inf, 0.5, 0.6, -np.inf]),
        max_dim=1)


def test_persistence_bins_of_a_constructed_diagram():
    counts = persistence_bin_counts(constructed_diagrams(), 0)
    assert dict(zip(PERSISTENCE_BINS, counts.tolist())) == {"rough": 1, "weak": 2, "medium": 1, "strong": 1,
                                                            "essential": 1}


def test_persistence_bins_on_the_bin_edges():
    # P1 §5.3 edges: rough iff lifespan <= 0.1; weak [0.1, 1), medium [1, 2.5), strong >= 2.5.
    # Deaths of 0 keep lifespan == birth exactly in floating point, so the 0.1 edge is hit exactly.
    below = lambda edge: np.nextafter(edge, 0.0)  # noqa: E731  (the float just under an edge)
    birth = np.array([0.1, np.nextafter(0.1, 1.0), below(1.0), 1.0, below(2.5), 2.5, 0.05])
    death = np.array([0.0, 0.0, 0.0, 0.5, 1.0, 1.0, -np.inf])
    expected = [{"rough": 1}, {"weak": 1}, {"weak": 1}, {"medium": 1}, {"medium": 1}, {"strong": 1},
                {"essential": 1}]  # the last: essential whatever its (tiny) birth
    for b, d, want in zip(birth, death, expected):
        one = PersistenceDiagrams(homology_dim=np.array([0]), birth=np.array([b]), death=np.array([d]), max_dim=1)
        got = dict(zip(PERSISTENCE_BINS, persistence_bin_counts(one, 0).tolist()))
        assert got == {name: want.get(name, 0) for name in PERSISTENCE_BINS}, (b, d)
    # rough wins over birth: at a strong-range birth, lifespan 1/16 is rough and 1/8 is strong (exact dyadics)
    high = PersistenceDiagrams(homology_dim=np.array([0, 0]), birth=np.array([3.0, 3.0]),
                               death=np.array([3.0 - 0.0625, 3.0 - 0.125]), max_dim=1)
    assert persistence_bin_counts(high, 0).tolist() == [1, 0, 0, 1, 0]


def test_total_persistence_of_a_constructed_diagram():
    tp = total_persistence(constructed_diagrams())
    np.testing.assert_allclose(tp, [0.05 + 2.05 + 1.0 + 0.2 + 0.25, 0.5 + 0.2])


# --- jamming point -------------------------------------------------------------------------------------------
def synthetic_compression(rng, rho_j=0.842, width=0.008, noise=0.15, realizations=1):
    rho = np.round(np.arange(0.80, 0.90, 0.004), 6)
    z = 0.4 + (4.2 - 0.4) / (1 + np.exp(-(rho - rho_j) / width))
    return rho, z + rng.normal(0.0, noise, (realizations, rho.size)).squeeze()


@pytest.mark.parametrize("seed", range(5))
def test_jamming_point_of_a_noisy_sigmoid(seed):
    rng = np.random.default_rng(seed)
    rho, z = synthetic_compression(rng)
    assert jamming_point(rho, z) == pytest.approx(0.842, abs=0.003)
    assert jamming_point(rho, z, method="smoothed_derivative") == pytest.approx(0.842, abs=0.006)


def test_jamming_point_pools_realizations():
    rng = np.random.default_rng(42)
    rho, z = synthetic_compression(rng, noise=0.4, realizations=20)  # ρ_J = 0.842, shifted to 3D's 0.57
    rho = rho - 0.842 + 0.57
    fit = fit_logistic(rho, z)
    assert fit.rho_j == pytest.approx(0.57, abs=0.002)
    assert fit.z_high - fit.z_low == pytest.approx(3.8, rel=0.1)


def test_jamming_point_needs_a_rise_inside_the_range():
    rho = np.linspace(0.8, 0.9, 20)
    assert np.isnan(jamming_point(rho, np.full(20, 4.0) + 0.01 * np.sin(rho * 100)))
    assert np.isnan(jamming_point(rho, 4.0 - 30 * (rho - 0.8)))  # Z falling: no jamming


def test_isostatic_crossing_interpolates_linearly():
    rho = np.array([0.80, 0.82, 0.84, 0.86])
    z = np.array([1.0, 2.0, 4.0, 4.5])
    assert isostatic_crossing(rho, z, dimension=2) == pytest.approx(0.83)  # Z = 3 halfway from 2 to 4
    assert isostatic_crossing(rho, z, dimension=3) == pytest.approx(0.84)
    assert np.isnan(isostatic_crossing(rho, z, dimension=4))
    assert np.isnan(isostatic_crossing(rho, z + 3, dimension=2))  # already above d + 1 at the start


# --- all measures in one call --------------------------------------------------------------------------------
def test_snapshot_measures_are_consistent():
    rng = np.random.default_rng(3)
    position = rng.uniform(0, 10, (120, 2))
    pairs = np.array([(a, b) for a, b in itertools.combinations(range(120), 2)
                      if np.linalg.norm(position[a] - position[b]) < 1.4])
    angle = rng.uniform(0, 2 * np.pi, len(pairs))
    normal = rng.lognormal(0, 0.5, len(pairs))[:, None] * np.stack([np.cos(angle), np.sin(angle)], axis=1)
    network = build_force_network(position, pairs[:, 0], pairs[:, 1], normal, 0.2 * normal[:, ::-1],
                                  wall_particle=np.flatnonzero(position[:, 0] < 1),
                                  wall_id=np.zeros(np.count_nonzero(position[:, 0] < 1), int))
    measures = compute_snapshot_measures(network)
    assert measures.betti.shape == (2, 61) and measures.thresholds[0] == 0.0
    np.testing.assert_array_equal(measures.betti[0], measures.cluster_count)
    # ⟨F⟩: the mean total force |F_n + F_t| over all contacts, straight from the input vectors
    assert measures.mean_force == pytest.approx(np.linalg.norm(normal + 0.2 * normal[:, ::-1], axis=1).mean())
    # Z without rattlers by direct count: rattlers have ≤ 1 contact (one pass), walls not counted
    degree = np.bincount(pairs.ravel(), minlength=120)
    non_rattler = degree >= 2
    assert 0 < np.count_nonzero(~non_rattler) < 120  # the case is not trivial
    kept_contacts = np.count_nonzero(non_rattler[pairs[:, 0]] & non_rattler[pairs[:, 1]])
    assert measures.Z_no_rattlers == pytest.approx(2 * kept_contacts / np.count_nonzero(non_rattler))
    assert measures.Z == pytest.approx(degree.mean())
    # the P1 bins cover every PD0 point once (deaths ≥ 0, so a non-rough finite point has birth > 0.1)
    assert measures.total_persistence.shape == (2,) and measures.persistence_bin_count.shape == (5,)
    assert measures.persistence_bin_count.sum() == np.count_nonzero(measures.diagrams.homology_dim == 0)
    # at F_th = 0 the whole complex is present: only never-dying classes are alive (finite deaths are > 0)
    np.testing.assert_array_equal(measures.essential_count, measures.betti[:, 0])
    assert measures.persistence_bin_count[-1] == measures.essential_count[0]
    stored = measures.as_dict()
    assert {"betti", "cluster_mean_size", "percolating_size", "percolates", "shape_parameter", "force_pdf", "Z",
            "Z_no_rattlers", "birth", "death", "essential", "diagram_homology_dim"} <= set(stored)
    assert all(isinstance(value, np.ndarray) for value in stored.values())
