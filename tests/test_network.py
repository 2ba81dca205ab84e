"""Contacts → force network: magnitudes, normalisation, rattlers, wall contacts, quadrants, and the one adapter from a
snapshot dataset."""
from dataclasses import replace

import numpy as np
import pytest

from forcenet.measures import coordination_number
from forcenet.network import (
    build_force_network,
    force_magnitude,
    network_from_edge_forces,
    quadrant_mask,
    rattler_free_mask,
    restrict_to_quadrant,
    restrict_to_region,
    snapshot_network,
)


def planar_vectors(magnitude, angle=0.0):
    """(C, 2) vectors of the given magnitudes along one direction."""
    magnitude = np.asarray(magnitude, float)
    return np.stack([magnitude * np.cos(angle), magnitude * np.sin(angle)], axis=1)


def square_with_tail():
    """A 4-cycle 0-1-2-3 with a dangling chain 3-4-5, on a unit grid."""
    position = np.array([[0, 0], [1, 0], [1, 1], [0, 1], [-1, 1], [-2, 1]], float)
    contact_i = np.array([0, 1, 2, 3, 3, 4])
    contact_j = np.array([1, 2, 3, 0, 4, 5])
    return position, contact_i, contact_j


def test_force_kinds_are_the_magnitudes_of_the_vectors():
    normal = np.array([[3.0, 0.0], [0.0, 1.0]])
    tangential = np.array([[0.0, 4.0], [0.0, 1.0]])
    np.testing.assert_allclose(force_magnitude(normal, tangential, "total"), [5.0, 2.0])
    np.testing.assert_allclose(force_magnitude(normal, tangential, "normal"), [3.0, 1.0])
    np.testing.assert_allclose(force_magnitude(normal, tangential, "tangential"), [4.0, 1.0])
    with pytest.raises(ValueError):
        force_magnitude(normal, tangential, "shear")


def test_forces_are_divided_by_the_mean_of_the_positive_ones():
    position, ci, cj = square_with_tail()
    magnitude = np.array([1.0, 2.0, 3.0, 6.0, 0.0, 0.0])  # the tail carries no force: not contacts
    network = build_force_network(position, ci, cj, planar_vectors(magnitude), remove_rattlers=False)
    assert network.mean_force == pytest.approx(3.0)
    np.testing.assert_allclose(np.sort(network.force), [1 / 3, 2 / 3, 1.0, 2.0])
    assert network.n_edges == 4 and network.n_contacts == 4
    assert network.force.mean() == pytest.approx(1.0)
    assert np.all(network.edge_i < network.edge_j)


def test_tangential_network_keeps_only_contacts_with_tangential_force():
    position, ci, cj = square_with_tail()
    normal = planar_vectors([1, 1, 1, 1, 1, 1])
    tangential = planar_vectors([0.5, 0, 0.25, 0, 0, 0], np.pi / 2)
    network = build_force_network(position, ci, cj, normal, tangential, kind="tangential", remove_rattlers=False)
    assert network.n_edges == 2
    np.testing.assert_allclose(np.sort(network.force), [2 / 3, 4 / 3])
    assert network.mean_force == pytest.approx(0.375)


def test_single_pass_removes_only_particles_with_at_most_one_contact():
    position, ci, cj = square_with_tail()
    network = build_force_network(position, ci, cj, planar_vectors(np.ones(6)), remove_rattlers=True)
    # particle 5 has one contact: removed; 4 keeps its two contacts in the single pass (P1 §3)
    np.testing.assert_array_equal(network.particle_mask, [1, 1, 1, 1, 1, 0])
    assert network.n_edges == 5 and network.rattler_rule == "once"


def test_iterative_removal_strips_the_dangling_chain():
    position, ci, cj = square_with_tail()
    network = build_force_network(position, ci, cj, planar_vectors(np.ones(6)), remove_rattlers="iterative")
    np.testing.assert_array_equal(network.particle_mask, [1, 1, 1, 1, 0, 0])
    assert network.n_edges == 4


def test_no_removal_keeps_isolated_particles():
    position = np.zeros((4, 2))
    network = build_force_network(position, [0], [1], planar_vectors([2.0]), remove_rattlers=False)
    assert network.n_kept == 4 and network.n_edges == 1
    removed = build_force_network(position, [0], [1], planar_vectors([2.0]), remove_rattlers=True)
    assert removed.n_kept == 0 and removed.n_edges == 0


def test_rattler_mask_counts_wall_contacts_only_when_asked():
    # 0-1 pair, 1 also touches a wall: with walls counted, 1 has two contacts but 0 still has one
    mask = rattler_free_mask(2, np.array([0]), np.array([1]), "once", np.array([0, 1]))
    np.testing.assert_array_equal(mask, [False, True])
    np.testing.assert_array_equal(rattler_free_mask(2, np.array([0]), np.array([1]), "once"), [False, False])


def test_wall_contacts_follow_the_network_particles():
    position, ci, cj = square_with_tail()
    network = build_force_network(position, ci, cj, planar_vectors(np.ones(6)), wall_particle=[0, 5, 2],
                                  wall_id=[0, 0, 1], wall_force=planar_vectors([1.0, 1.0, 0.0]))
    # 5 is a rattler, 2's wall contact carries no force
    np.testing.assert_array_equal(network.wall_particle, [0])
    np.testing.assert_array_equal(network.wall_id, [0])


def test_invalid_inputs_are_refused():
    position = np.zeros((3, 2))
    with pytest.raises(ValueError, match="more than one contact"):
        build_force_network(position, [0, 1], [1, 0], planar_vectors([1, 1]))
    with pytest.raises(ValueError, match="itself"):
        build_force_network(position, [0], [0], planar_vectors([1]))
    with pytest.raises(ValueError, match="wall ids"):
        build_force_network(position, [0], [1], planar_vectors([1]), wall_particle=[0], wall_id=[4])
    with pytest.raises(ValueError):
        build_force_network(position, [0], [1], planar_vectors([1]), remove_rattlers="sometimes")


def test_coordination_with_and_without_rattlers():
    position, ci, cj = square_with_tail()
    network = build_force_network(position, ci, cj, planar_vectors(np.ones(6)), remove_rattlers=True)
    assert coordination_number(network) == pytest.approx(2 * 6 / 6)
    assert coordination_number(network, include_rattlers=False) == pytest.approx(2 * 5 / 5)


def test_network_from_edge_forces_keeps_forces_as_given():
    network = network_from_edge_forces([2, 0], [1, 1], [0.1, 0.7])
    np.testing.assert_array_equal(network.edge_i, [0, 1])
    np.testing.assert_array_equal(network.force, [0.7, 0.1])  # exact values, sorted by edge
    assert network.mean_force == pytest.approx(0.4)
    normalised = network_from_edge_forces([2, 0], [1, 1], [0.1, 0.7], normalise=True)
    np.testing.assert_allclose(normalised.force, [1.75, 0.25])


def test_quadrants_partition_the_particles_and_drop_crossing_edges():
    # 3×3 grid of particles in the box [0, 3]², nearest-neighbour contacts
    x, y = np.meshgrid(np.arange(3) + 0.5, np.arange(3) + 0.5, indexing="ij")
    position = np.stack([x.ravel(), y.ravel()], axis=1)
    pairs = [(a, b) for a in range(9) for b in range(a + 1, 9)
             if np.isclose(np.linalg.norm(position[a] - position[b]), 1.0)]
    ci, cj = np.array(pairs).T
    network = build_force_network(position, ci, cj, planar_vectors(np.arange(1, 13)), remove_rattlers=False)
    masks = [quadrant_mask(position, [0, 0], [3, 3], name)
             for name in ("bottom left", "bottom right", "top right", "top left")]
    np.testing.assert_array_equal(np.sum(masks, axis=0), np.ones(9))  # every particle in exactly one
    # centre (1.5, 1.5) lies on both dividing lines: it belongs to the top right block
    assert masks[2][4]
    top_right = restrict_to_quadrant(network, [0, 0], [3, 3], "top_right")
    assert top_right.n_kept == 4 and top_right.n_edges == 4  # the 2×2 block (1.5..2.5)² is a 4-cycle
    assert top_right.mean_force == network.mean_force
    bottom_left = restrict_to_quadrant(network, [0, 0], [3, 3], "bottom left")
    assert bottom_left.n_kept == 1 and bottom_left.n_edges == 0
    with pytest.raises(ValueError):
        quadrant_mask(position, [0, 0], [3, 3], "middle")


def test_coordination_without_rattlers_does_not_depend_on_the_force_kind():
    position, ci, cj = square_with_tail()
    normal = planar_vectors(np.ones(6))
    tangential = planar_vectors([1, 0, 0, 0, 0, 0], np.pi / 2)  # only one contact carries friction
    values = [coordination_number(build_force_network(position, ci, cj, normal, tangential, kind=kind),
                                  include_rattlers=False) for kind in ("total", "normal", "tangential")]
    assert values == pytest.approx([2.0, 2.0, 2.0])


def test_compact_graph_renumbers_the_network_particles_in_edge_order():
    network = network_from_edge_forces([5, 0, 3, 1], [1, 5, 0, 3], [1.0, 2.0, 3.0, 4.0], n_particles=6)
    region = restrict_to_region(network, np.array([1, 1, 0, 1, 0, 1], bool))  # particles 0, 1, 3, 5
    graph = region.compact
    assert graph is region.compact  # computed once per network
    np.testing.assert_array_equal(graph.particle, [0, 1, 3, 5])
    np.testing.assert_array_equal(graph.index, [0, 1, -1, 2, -1, 3])
    np.testing.assert_array_equal(graph.edges, [[0, 2], [0, 3], [1, 2], [1, 3]])  # sorted: (0,3) (0,5) (1,3) (1,5)
    np.testing.assert_array_equal(graph.force, [3.0, 2.0, 4.0, 1.0])
    np.testing.assert_array_equal(graph.vertex_value, [3.0, 4.0, 4.0, 2.0])
    unsorted = replace(network, edge_i=network.edge_i[::-1], edge_j=network.edge_j[::-1], force=network.force[::-1])
    with pytest.raises(ValueError, match="sorted"):
        unsorted.compact


def rattler_snapshot():
    """A 2D snapshot: a square of four touching disks 0–3 (a loop, two contacts each) and disk 4 touching only disk 0
    and the left wall (wall 0), so disk 4 is a rattler (P1 §3) unless its wall contact counts. Total (= normal)
    forces 1, 2, 3, 4, 5 on the contacts (0,1), (0,3), (0,4), (1,2), (2,3): ⟨F⟩ = 3; no tangential force."""
    from forcenet.datasets.snapshot import snapshot_dataset

    position = np.array([[1.0, 1.0], [2.0, 1.0], [2.0, 2.0], [1.0, 2.0], [0.0, 0.5]])
    contact_i, contact_j = np.array([0, 0, 0, 1, 2]), np.array([1, 3, 4, 2, 3])
    direction = position[contact_j] - position[contact_i]
    force = np.array([1.0, 2.0, 3.0, 4.0, 5.0])[:, None] * direction / np.linalg.norm(direction, axis=1)[:, None]
    n = len(position)
    return snapshot_dataset(
        attrs={"system": "2d_hertz"}, position=position, radius=np.full(n, 0.5), velocity=np.zeros((n, 2)),
        angular_velocity=np.zeros(n), contact_i=contact_i, contact_j=contact_j, force_normal=force,
        force_tangential=np.zeros_like(force), wall_contact_particle=[4], wall_contact_wall=[0],
        wall_contact_force=[[0.5, 0.0]], box_lo=np.array([-0.5, 0.0]), box_hi=np.array([3.0, 3.0]), rho=0.8, Z=2.0,
        kinetic_energy=0.0, pressure=1.0, time=0.0, step=0, relaxation_steps=-1)


SQUARE = [(0, 1), (0, 3), (1, 2), (2, 3)]


@pytest.mark.parametrize("rule, walls, edges, wall_contacts", [
    ("none", "ignored", SQUARE + [(0, 4)], []),
    ("none", "kept", SQUARE + [(0, 4)], [(4, 0)]),
    ("none", "counted", SQUARE + [(0, 4)], [(4, 0)]),
    ("once", "ignored", SQUARE, []),
    ("once", "kept", SQUARE, []),  # the rattler's wall contact leaves with it
    ("once", "counted", SQUARE + [(0, 4)], [(4, 0)]),  # one particle contact + one wall contact: no rattler
    ("iterative", "kept", SQUARE, []),
])
def test_snapshot_network_has_the_hand_counted_edges(rule, walls, edges, wall_contacts):
    network = snapshot_network(rattler_snapshot(), "total", rattler_rule=rule, wall_contacts=walls)
    assert sorted(zip(network.edge_i.tolist(), network.edge_j.tolist())) == sorted(edges)
    assert list(zip(network.wall_particle.tolist(), network.wall_id.tolist())) == wall_contacts
    assert network.mean_force == pytest.approx(3.0)  # over every particle contact, the rattler's included
    force = dict(zip(zip(network.edge_i.tolist(), network.edge_j.tolist()), network.force))
    assert force[(1, 2)] == pytest.approx(4.0 / 3.0)
    assert network.particle_mask[4] == ((0, 4) in edges)


def test_snapshot_network_weights_the_requested_force_kind():
    snapshot = rattler_snapshot()
    normal = snapshot_network(snapshot, "normal", rattler_rule="none")
    assert normal.n_edges == 5 and normal.kind == "normal"
    assert snapshot_network(snapshot, "tangential", rattler_rule="none").n_edges == 0  # no tangential force
    with pytest.raises(ValueError, match="wall_contacts"):
        snapshot_network(snapshot, "total", rattler_rule="none", wall_contacts="sometimes")

