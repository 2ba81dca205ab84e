"""Contact force vectors stored along their contact's own axes, losslessly (a campaign record's forces).

A contact's normal force lies along its unit branch vector n̂ = (x_i − x_j)/|x_i − x_j|, and its tangential force in
the plane normal to n̂, so of the d numbers of each vector only one (normal) or d − 1 (tangential) carry information;
the others follow from the positions the record keeps anyway. Stored as raw float64 vectors the forces are most of a
record's bytes (zlib cannot compress the mantissas); stored along the contact's axes they take about 60 %.

Lossless by construction: each vector v (C, d) is kept as its components c (C, k) along k unit axes computed from the
positions, plus the residual r = bits(v) − bits(Σ c_a ê_a), the difference of the IEEE-754 binary64 bit patterns as
int64 (wrapping), so that decoding gives back bits(v) exactly whatever the rounding of the prediction. The residual is
0 where the prediction is exact (the engine computes f_n n̂ as a product, so ≈ 97 % of the normal forces) and a few
units in the last place elsewhere: it costs almost nothing after zlib. Every operation is elementwise IEEE arithmetic
(no reduction whose order could vary), so the prediction is the same on every machine.

Shapes: C contacts, d = 2 or 3 spatial dimensions; positions in d_ave, forces in the snapshot's force units.
"""
from __future__ import annotations

import numpy as np

#: units in the last place searched around the projection for a normal component whose product is exact
_ULP_SEARCH = (0, 1, -1, 2, -2, 3, -3, 4, -4)


def branch_unit_vectors(position: np.ndarray, contact_i: np.ndarray, contact_j: np.ndarray) -> np.ndarray:
    """n̂ (C, d) of each contact: (x_i − x_j)/|x_i − x_j|, the direction of the normal force on i from j; zero where
    the branch vector has no direction (coincident centres, never in a valid state: such a force is kept in its
    residual alone)."""
    return _normalized(position[contact_i] - position[contact_j])


def _normalized(vectors: np.ndarray) -> np.ndarray:
    """vectors (C, d) / their lengths, zero where a vector has none."""
    with np.errstate(divide="ignore", invalid="ignore"):
        unit = vectors * (1.0 / np.sqrt(_dot(vectors, vectors)))[:, None]
    return np.where(np.isfinite(unit), unit, 0.0)


def _cross(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """a × b of (C, 3) vectors, written out (elementwise products and differences in a fixed order, so that every
    machine and numpy version gives the same bits: the residuals depend on them)."""
    return np.stack([a[:, 1] * b[:, 2] - a[:, 2] * b[:, 1], a[:, 2] * b[:, 0] - a[:, 0] * b[:, 2],
                     a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0]], axis=1)


def tangent_axes(normal: np.ndarray) -> list[np.ndarray]:
    """The d − 1 unit axes (each (C, d)) spanning the plane normal to each n̂: in 2D t̂ = (−n̂_y, n̂_x); in 3D
    ê₁ = n̂ × â / |n̂ × â| with â the coordinate axis least aligned with n̂, and ê₂ = n̂ × ê₁."""
    if normal.shape[1] == 2:
        return [np.stack([-normal[:, 1], normal[:, 0]], axis=1)]
    least = np.argmin(np.abs(normal), axis=1)
    axis = np.zeros_like(normal)
    axis[np.arange(len(normal)), least] = 1.0
    first = _normalized(_cross(normal, axis))
    return [first, _cross(normal, first)]


def _prediction(components: np.ndarray, axes: list[np.ndarray]) -> np.ndarray:
    predicted = components[:, 0, None] * axes[0]
    for index in range(1, len(axes)):
        predicted = predicted + components[:, index, None] * axes[index]
    return predicted


def encode_vectors(vectors: np.ndarray, axes: list[np.ndarray]) -> tuple[np.ndarray, np.ndarray]:
    """(components (C, k), residual (C, d) int64) of float64 `vectors` (C, d) along the k unit `axes`: the
    projections (with one axis, the nearest value whose product with the axis is the vector itself, where there is
    one) and the bit-pattern differences that `decode_vectors` adds back."""
    vectors = np.ascontiguousarray(vectors, dtype=np.float64)
    components = np.stack([_dot(vectors, axis) for axis in axes], axis=1)
    if len(axes) == 1 and len(vectors):
        projection = components[:, 0].copy()
        exact = np.zeros(len(vectors), dtype=bool)
        for step in _ULP_SEARCH:
            candidate = (projection.view(np.int64) + step).view(np.float64)
            hit = ~exact & np.all(candidate[:, None] * axes[0] == vectors, axis=1)
            components[hit, 0] = candidate[hit]
            exact |= hit
    residual = vectors.view(np.int64) - np.ascontiguousarray(_prediction(components, axes)).view(np.int64)
    return components, residual


def decode_vectors(components: np.ndarray, residual: np.ndarray, axes: list[np.ndarray]) -> np.ndarray:
    """The float64 vectors (C, d) that `encode_vectors` stored as `components` and `residual`, bit for bit."""
    predicted = np.ascontiguousarray(_prediction(np.asarray(components, dtype=np.float64), axes))
    return (predicted.view(np.int64) + np.asarray(residual, dtype=np.int64)).view(np.float64)


def _dot(vectors: np.ndarray, axis: np.ndarray) -> np.ndarray:
    total = vectors[:, 0] * axis[:, 0] + vectors[:, 1] * axis[:, 1]
    return total + vectors[:, 2] * axis[:, 2] if vectors.shape[1] == 3 else total


def encode_forces(position: np.ndarray, contact_i: np.ndarray, contact_j: np.ndarray, force_normal: np.ndarray,
                  force_tangential: np.ndarray) -> dict[str, np.ndarray]:
    """One state's contact forces as a record stores them: `force_normal_component` (C,) along n̂,
    `force_tangential_component` (C, d − 1) along `tangent_axes`, and their `…_residual` (C, d) int64.
    position (N, d) of the state; contact_i, contact_j (C,); force_normal, force_tangential (C, d)."""
    normal = branch_unit_vectors(position, contact_i, contact_j)
    normal_components, normal_residual = encode_vectors(force_normal, [normal])
    tangential_components, tangential_residual = encode_vectors(force_tangential, tangent_axes(normal))
    return {"force_normal_component": normal_components[:, 0], "force_normal_residual": normal_residual,
            "force_tangential_component": tangential_components, "force_tangential_residual": tangential_residual}


def decode_forces(position: np.ndarray, contact_i: np.ndarray, contact_j: np.ndarray,
                  stored: dict[str, np.ndarray]) -> tuple[np.ndarray, np.ndarray]:
    """(force_normal, force_tangential) (C, d) of one state from what `encode_forces` stored, bit for bit."""
    normal = branch_unit_vectors(position, contact_i, contact_j)
    force_normal = decode_vectors(np.asarray(stored["force_normal_component"])[:, None],
                                  stored["force_normal_residual"], [normal])
    force_tangential = decode_vectors(stored["force_tangential_component"], stored["force_tangential_residual"],
                                      tangent_axes(normal))
    return force_normal, force_tangential
