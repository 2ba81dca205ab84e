"""A record's contact forces stored along each contact's axes (`forcenet.datasets.force_codec`): lossless, and compact
only where the physics says (a normal force along its branch vector, a tangential one normal to it)."""
import numpy as np
import pytest

from forcenet.datasets.force_codec import (branch_unit_vectors, decode_forces, decode_vectors, encode_forces,
                                           encode_vectors, tangent_axes)


def test_branch_unit_vector_points_from_j_to_i():
    position = np.array([[3.0, 4.0], [0.0, 0.0]])
    normal = branch_unit_vectors(position, np.array([0]), np.array([1]))
    np.testing.assert_allclose(normal, [[0.6, 0.8]], rtol=1e-15)


def test_a_normal_force_along_its_branch_is_one_number_and_no_residual():
    position = np.array([[1.0, 0.0], [0.0, 0.0]])  # n = (1, 0): the force (2.5, 0) is 2.5 n exactly
    stored = encode_forces(position, np.array([0]), np.array([1]), np.array([[2.5, 0.0]]), np.array([[0.0, -0.75]]))
    assert stored["force_normal_component"].tolist() == [2.5]
    assert stored["force_normal_residual"].tolist() == [[0, 0]]
    assert stored["force_tangential_component"].tolist() == [[-0.75]]  # t = (-n_y, n_x) = (0, 1)
    assert stored["force_tangential_residual"].tolist() == [[0, 0]]


def test_a_force_off_its_axis_is_carried_by_the_residual():
    """A 'normal' force that is not along the branch (never in a valid state) is still given back exactly."""
    position = np.array([[1.0, 0.0], [0.0, 0.0]])
    force = np.array([[2.5, 1.0]])
    stored = encode_forces(position, np.array([0]), np.array([1]), force, np.zeros((1, 2)))
    assert np.any(stored["force_normal_residual"] != 0)
    normal, _ = decode_forces(position, np.array([0]), np.array([1]), stored)
    np.testing.assert_array_equal(normal, force)


def test_coincident_centres_keep_the_force_in_the_residual():
    position = np.zeros((2, 3))
    force = np.array([[0.1, -0.2, 0.3]])
    stored = encode_forces(position, np.array([0]), np.array([1]), force, -force)
    normal, tangential = decode_forces(position, np.array([0]), np.array([1]), stored)
    assert normal.view(np.int64).tolist() == force.view(np.int64).tolist()
    assert tangential.view(np.int64).tolist() == (-force).view(np.int64).tolist()


def test_tangent_axes_are_orthonormal_and_normal_to_n():
    rng = np.random.default_rng(3)
    for dim in (2, 3):
        normal = branch_unit_vectors(rng.normal(size=(50, dim)), np.arange(0, 50, 2), np.arange(1, 50, 2))
        axes = tangent_axes(normal)
        assert len(axes) == dim - 1
        for a, axis in enumerate(axes):
            np.testing.assert_allclose(np.sum(axis * normal, axis=1), 0.0, atol=1e-15)
            np.testing.assert_allclose(np.sum(axis * axis, axis=1), 1.0, rtol=1e-15)
            for other in axes[a + 1:]:
                np.testing.assert_allclose(np.sum(axis * other, axis=1), 0.0, atol=1e-15)


@pytest.mark.parametrize("dim", [2, 3])
def test_contact_forces_come_back_bit_for_bit(dim):
    """Forces as the engine makes them (f_n n̂ plus a tangential force rounded off the tangent plane), and
    arbitrary vectors, all decode to the same bits."""
    rng = np.random.default_rng(dim)
    position = rng.uniform(0, 20, size=(400, dim))
    i, j = np.arange(0, 400, 2), np.arange(1, 400, 2)
    normal = branch_unit_vectors(position, i, j)
    magnitude = rng.lognormal(size=len(i))
    force_normal = magnitude[:, None] * normal
    random = rng.normal(size=(len(i), dim))
    force_tangential = random - np.sum(random * normal, axis=1)[:, None] * normal
    stored = encode_forces(position, i, j, force_normal, force_tangential)
    back_normal, back_tangential = decode_forces(position, i, j, stored)
    assert np.array_equal(back_normal.view(np.int64), force_normal.view(np.int64))
    assert np.array_equal(back_tangential.view(np.int64), force_tangential.view(np.int64))
    assert np.count_nonzero(np.any(stored["force_normal_residual"] != 0, axis=1)) == 0  # f_n n̂ is a product
    components, residual = encode_vectors(random, [normal])  # arbitrary vectors: exact, through the residual
    assert np.array_equal(decode_vectors(components, residual, [normal]).view(np.int64), random.view(np.int64))


def test_a_changed_residual_changes_the_force():
    """The residual is read: decoding is not the prediction alone."""
    position = np.array([[1.0, 0.0], [0.0, 0.0]])
    stored = encode_forces(position, np.array([0]), np.array([1]), np.array([[2.5, 0.0]]), np.zeros((1, 2)))
    stored["force_normal_residual"] = stored["force_normal_residual"] + 1
    normal, _ = decode_forces(position, np.array([0]), np.array([1]), stored)
    assert normal[0, 0] == np.nextafter(2.5, 3.0)
