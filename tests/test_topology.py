"""Flag complex, persistence diagrams and Betti curves against hand-countable truth and naive references."""
import itertools

import numpy as np
import pytest

from forcenet.network import network_from_edge_forces
from forcenet.topology import (
    PersistenceDiagrams,
    betti_curves,
    default_thresholds,
    enumerate_cliques,
    filtration_order,
    flag_complex,
    persistence_diagrams,
    quadrant_persistence_diagrams,
)
from naive_topology import betti_numbers, pd0_elder_rule


def diagrams_of(edges, force, dim=2, n=None):
    edges = np.asarray(edges)
    return persistence_diagrams(network_from_edge_forces(edges[:, 0], edges[:, 1], force, dim=dim, n_particles=n))


def points(diagrams, k):
    return sorted(map(tuple, diagrams.points(k).tolist()))


def random_graph(rng, n, p, integer_forces=False):
    edges = np.array([e for e in itertools.combinations(range(n), 2) if rng.random() < p]).reshape(-1, 2)
    force = rng.integers(1, 6, len(edges)).astype(float) if integer_forces else rng.exponential(1.0, len(edges))
    return edges, force


# --- hand-countable complexes --------------------------------------------------------------------------------
def test_a_triangle_adds_no_loop():
    d = diagrams_of([(0, 1), (1, 2), (0, 2)], [1.0, 2.0, 3.0])
    assert points(d, 1) == []
    assert points(d, 0) == [(3.0, -np.inf)]  # one component, born at the strongest contact


def test_a_four_cycle_is_one_loop_that_never_dies():
    d = diagrams_of([(0, 1), (1, 2), (2, 3), (0, 3)], [4.0, 3.0, 2.0, 1.5])
    assert points(d, 1) == [(1.5, -np.inf)]  # born when the weakest edge closes it (P2 §III C)
    assert d.essential[d.homology_dim == 1].all()
    # components: 0-1 born at 4; vertex 3 arrives with its edge 2-3 at 2 and joins at once (zero length)
    assert points(d, 0) == [(4.0, -np.inf)]


def test_two_triangles_sharing_an_edge_have_no_loop():
    d = diagrams_of([(0, 1), (1, 2), (0, 2), (1, 3), (2, 3)], [1.0, 1.0, 1.0, 1.0, 1.0])
    assert points(d, 1) == []


def test_a_square_filled_late_by_its_diagonal_is_a_finite_loop():
    # square edges 3..6 close a loop at 3; the weak diagonal 0-2 (1.0) fills it with two triangles at 1.0
    d = diagrams_of([(0, 1), (1, 2), (2, 3), (0, 3), (0, 2)], [6.0, 5.0, 4.0, 3.0, 1.0])
    assert points(d, 1) == [(3.0, 1.0)]


def test_two_separate_pairs_merge_by_the_elder_rule():
    # components {0,1} born at 5 and {2,3} born at 2 merge through the edge 1-2 at 1: the younger dies
    d = diagrams_of([(0, 1), (2, 3), (1, 2)], [5.0, 2.0, 1.0])
    assert points(d, 0) == [(2.0, 1.0), (5.0, -np.inf)]


def octahedron():
    """K_{2,2,2}: 6 vertices (±x, ±y, ±z), every pair adjacent except opposite ones; no 4-clique."""
    opposite = {(0, 1), (2, 3), (4, 5)}
    return [e for e in itertools.combinations(range(6), 2) if e not in opposite]


@pytest.mark.parametrize("fill_tetrahedra", [True, False])
def test_a_3d_octahedron_shell_encloses_one_void(fill_tetrahedra):
    # no 4-clique: filling tetrahedra or not gives the same complex
    edges = np.asarray(octahedron())
    network = network_from_edge_forces(edges[:, 0], edges[:, 1], np.linspace(1.0, 2.0, len(edges)), dim=3)
    d = persistence_diagrams(network, fill_tetrahedra=fill_tetrahedra)
    assert len(edges) == 12
    assert points(d, 2) == [(1.0, -np.inf)]  # closes with its weakest edge, never filled
    assert not d.essential[d.homology_dim == 1].any()  # loops appear while edges enter, all get filled
    np.testing.assert_array_equal(betti_curves(d, [0.0])[:, 0], [1, 0, 1])
    assert d.max_dim == 2


def tetrahedron_network():
    """Four mutually touching spheres: K4, six edges with distinct forces 1..6 ⟨F⟩."""
    edges = np.array(list(itertools.combinations(range(4), 2)))
    return network_from_edge_forces(edges[:, 0], edges[:, 1], [3.0, 1.0, 6.0, 2.0, 5.0, 4.0], dim=3)


def test_a_tetrahedron_is_filled_in_3d():
    d = persistence_diagrams(tetrahedron_network())
    assert points(d, 2) == [] and points(d, 1) == []
    np.testing.assert_array_equal(betti_curves(d, [0.0])[:, 0], [1, 0, 0])
    assert len(flag_complex(tetrahedron_network()).tetrahedra) == 1


def test_a_hollow_tetrahedron_encloses_one_void_that_never_dies():
    # without the tetrahedron the four triangles are a closed shell: one void, born when the last triangle
    # enters, i.e. at the weakest edge (1.0, shared by the two last triangles), and nothing fills it
    d = persistence_diagrams(tetrahedron_network(), fill_tetrahedra=False)
    assert points(d, 2) == [(1.0, -np.inf)]
    assert d.essential[d.homology_dim == 2].all()
    assert points(d, 1) == [] and points(d, 0) == [(6.0, -np.inf)]
    np.testing.assert_array_equal(betti_curves(d, [0.0, 1.0, 1.5])[2], [1, 1, 0])
    assert d.max_dim == 2


def test_fill_tetrahedra_does_not_change_a_2d_network():
    rng = np.random.default_rng(3)
    for _ in range(5):
        edges, force = random_graph(rng, 9, 0.6)  # dense: many 4-cliques
        network = network_from_edge_forces(edges[:, 0], edges[:, 1], force, dim=2, n_particles=9)
        filled, hollow = (persistence_diagrams(network, fill_tetrahedra=f) for f in (True, False))
        for k in (0, 1):
            assert points(filled, k) == points(hollow, k)
        assert hollow.max_dim == 1


def test_births_and_deaths_are_the_exact_float64_forces():
    # 0.1, 0.2 and 1/3 are not float32 numbers: the rank mapping must bring back the float64 values.
    # Hexagon: {0, 1} born at 0.7 grows through 0-5 and 4-5; {2, 3} born at 1/3 joins it through 3-4 at 0.2
    d = diagrams_of([(0, 1), (2, 3), (1, 2), (3, 4), (4, 5), (0, 5)], [0.7, 1 / 3, 0.1, 0.2, 0.3, 0.4])
    assert points(d, 0) == [(1 / 3, 0.2), (0.7, -np.inf)]
    assert points(d, 1) == [(0.1, -np.inf)]


def test_clique_enumeration_matches_itertools():
    rng = np.random.default_rng(0)
    for _ in range(20):
        edges, force = random_graph(rng, 9, 0.6)
        order = np.lexsort((edges[:, 1], edges[:, 0]))
        edges, force = edges[order], force[order]
        lookup = {tuple(e): f for e, f in zip(edges.tolist(), force)}
        triangles, triangle_value, tetrahedra, tetrahedron_value = enumerate_cliques(9, edges, force, 4)
        expected_triangles = {c: min(lookup[p] for p in itertools.combinations(c, 2))
                              for c in itertools.combinations(range(9), 3)
                              if all(p in lookup for p in itertools.combinations(c, 2))}
        expected_tetrahedra = {c: min(lookup[p] for p in itertools.combinations(c, 2))
                               for c in itertools.combinations(range(9), 4)
                               if all(p in lookup for p in itertools.combinations(c, 2))}
        assert dict(zip(map(tuple, triangles.tolist()), triangle_value)) == expected_triangles
        assert dict(zip(map(tuple, tetrahedra.tolist()), tetrahedron_value)) == expected_tetrahedra


def test_filtration_order_puts_faces_before_cofaces():
    rng = np.random.default_rng(1)
    edges, force = random_graph(rng, 10, 0.5, integer_forces=True)  # many ties
    complex_ = flag_complex(network_from_edge_forces(edges[:, 0], edges[:, 1], force, dim=3), 3)
    simplices, value, dimension = filtration_order(complex_, 3)
    assert np.all(np.diff(value) <= 0)  # super-level: non-increasing values
    position = {tuple(s): k for k, s in enumerate(simplices)}
    for s, k in position.items():
        for face in itertools.combinations(s, len(s) - 1):
            if face:
                assert position[face] < k


# --- against naive references on random graphs ---------------------------------------------------------------
@pytest.mark.parametrize("seed", range(12))
def test_pd0_matches_union_find_elder_rule(seed):
    rng = np.random.default_rng(seed)
    edges, force = random_graph(rng, 14, 0.25, integer_forces=seed % 2 == 0)
    d = diagrams_of(edges, force, n=14)
    finite, essential = pd0_elder_rule(14, [tuple(e) for e in edges.tolist()], list(force))
    zero_dim = d.select(0)
    assert sorted(map(tuple, zero_dim.points(0, include_essential=False).tolist())) == finite
    assert sorted(zero_dim.birth[zero_dim.essential].tolist()) == essential


@pytest.mark.parametrize("dim,n,p", [(2, 9, 0.45), (2, 11, 0.3), (3, 9, 0.6), (3, 8, 0.75)])
def test_betti_curves_match_gf2_homology_at_many_thresholds(dim, n, p):
    rng = np.random.default_rng(100 * dim + n)
    thresholds = np.linspace(0.0, 3.0, 25)
    for _ in range(6):
        edges, force = random_graph(rng, n, p)
        d = diagrams_of(edges, force, dim=dim, n=n)
        curves = betti_curves(d, thresholds)
        edge_list = [tuple(e) for e in edges.tolist()]
        for t, theta in enumerate(thresholds):
            assert curves[:, t].tolist() == betti_numbers(n, edge_list, list(force), theta, dim - 1)


@pytest.mark.parametrize("n,p", [(9, 0.6), (8, 0.75)])
def test_betti_curves_of_hollow_tetrahedra_match_gf2_homology(n, p):
    # complex up to triangles (fill_tetrahedra=False), homology up to B2: every hollow 4-clique is a void
    rng = np.random.default_rng(11 * n)
    thresholds = np.linspace(0.0, 3.0, 25)
    voids = 0
    for _ in range(6):
        edges, force = random_graph(rng, n, p)
        network = network_from_edge_forces(edges[:, 0], edges[:, 1], force, dim=3, n_particles=n)
        curves = betti_curves(persistence_diagrams(network, fill_tetrahedra=False), thresholds)
        edge_list = [tuple(e) for e in edges.tolist()]
        for t, theta in enumerate(thresholds):
            assert curves[:, t].tolist() == betti_numbers(n, edge_list, list(force), theta, 2, max_simplex_dim=2)
        voids += int(curves[2, 0])
    assert voids > 0  # the random graphs do contain hollow 4-cliques


@pytest.mark.parametrize("dim,n,p", [(2, 10, 0.4), (3, 8, 0.7)])
def test_betti_curves_match_gf2_homology_at_thresholds_equal_to_forces(dim, n, p):
    # integer forces 1..5 and integer thresholds: θ equal to a force must count that edge as present (F ≥ θ)
    rng = np.random.default_rng(7 * dim + n)
    thresholds = np.arange(0.0, 7.0)
    for _ in range(6):
        edges, force = random_graph(rng, n, p, integer_forces=True)
        d = diagrams_of(edges, force, dim=dim, n=n)
        curves = betti_curves(d, thresholds)
        edge_list = [tuple(e) for e in edges.tolist()]
        for t, theta in enumerate(thresholds):
            assert curves[:, t].tolist() == betti_numbers(n, edge_list, list(force), theta, dim - 1)


def test_betti_curves_count_points_alive_at_each_threshold():
    d = PersistenceDiagrams(homology_dim=np.array([0, 0, 1, 1]), birth=np.array([2.0, 1.0, 1.5, 0.5]),
                            death=np.array([-np.inf, 0.5, 1.0, -np.inf]))
    curves = betti_curves(d, np.array([0.0, 0.5, 0.75, 1.0, 1.25, 2.0, 2.5]), max_dim=1)
    # alive iff birth ≥ θ > death: (1, 0.5) only for θ in (0.5, 1]; (1.5, 1.0) only for θ in (1, 1.5]
    np.testing.assert_array_equal(curves, [[1, 1, 2, 2, 1, 1, 0],
                                           [1, 1, 0, 0, 1, 0, 0]])


def test_essential_is_read_off_the_deaths():
    d = PersistenceDiagrams(homology_dim=np.array([0, 0, 1]), birth=np.array([2.0, 1.0, 1.5]),
                            death=np.array([-np.inf, 0.5, 1.0]))
    np.testing.assert_array_equal(d.essential, [True, False, False])
    np.testing.assert_array_equal(d.select(0).essential, [True, False])
    assert d.top_dim == 1 and PersistenceDiagrams(d.homology_dim, d.birth, d.death, max_dim=2).top_dim == 2
    np.testing.assert_array_equal(d.lifespan, [np.inf, 0.5, 0.5])
    with pytest.raises(ValueError, match="death"):
        PersistenceDiagrams(d.homology_dim, d.birth, d.death[:2])


def test_default_threshold_grid():
    grid = default_thresholds()
    assert grid.size == 61 and grid[0] == 0.0 and grid[-1] == 3.0
    assert grid[3] == 0.15  # the float nearest 0.15, not 3 × 0.05


def test_empty_network_has_empty_diagrams():
    d = persistence_diagrams(network_from_edge_forces([], [], [], n_particles=0))
    assert d.n_points == 0
    np.testing.assert_array_equal(betti_curves(d, [0.0, 1.0]), np.zeros((2, 2)))


def test_quadrant_diagrams_see_only_their_block():
    x, y = np.meshgrid([0.5, 1.5, 2.5, 3.5], [0.5, 1.5, 2.5, 3.5], indexing="ij")
    position = np.stack([x.ravel(), y.ravel()], axis=1)
    pairs = [(a, b) for a in range(16) for b in range(a + 1, 16)
             if np.isclose(np.linalg.norm(position[a] - position[b]), 1.0)]
    edges = np.array(pairs)
    network = network_from_edge_forces(edges[:, 0], edges[:, 1], np.linspace(1, 2, len(pairs)), position=position)
    blocks = quadrant_persistence_diagrams(network, [0, 0], [4, 4])
    assert list(blocks) == ["bottom left", "bottom right", "top right", "top left"]
    for diagrams in blocks.values():  # each block is one 2×2 square: one component, one loop
        assert np.count_nonzero(diagrams.homology_dim == 0) == 1
        assert np.count_nonzero(diagrams.homology_dim == 1) == 1
    whole = persistence_diagrams(network)
    assert np.count_nonzero(whole.homology_dim == 1) == 9  # the 4×4 grid has 9 unit squares
