"""Box geometry the importers, the snapshot readers and the figures share: which axes of a box are periodic, and the
image of a particle nearest to another (the minimum image convention). numpy only: the importers read their sources
when the workflow is parsed.

Our engine's boxes are bounded by walls on every axis; an imported box may be periodic along some (a LAMMPS dump
whose box bounds are "pp"), which its snapshots record (`forcenet.datasets.schema.PERIODIC_AXES_ATTR`).
"""
from __future__ import annotations

import numpy as np

AXIS_LABELS = ("x", "y", "z")


def box_periods(periodic_axes: str, box_lo, box_hi) -> np.ndarray:
    """The box length on each axis named in `periodic_axes` ("xy" …), 0 on the others, (d,) [length]."""
    lo, hi = np.asarray(box_lo, dtype=float), np.asarray(box_hi, dtype=float)
    return np.where([label in periodic_axes for label in AXIS_LABELS[:lo.size]], hi - lo, 0.0)


def image_counts(position: np.ndarray, i: np.ndarray, j: np.ndarray, period: np.ndarray | None = None) -> np.ndarray:
    """The whole number of box lengths (C, d), int64, that takes particle j of each pair (i, j) to its image
    nearest to particle i, on each axis where `period` (d,) is positive; 0 on the others and everywhere when
    `period` is None (a bounded box)."""
    count = np.zeros((len(i), position.shape[1]), dtype=np.int64)
    period = np.zeros(position.shape[1]) if period is None else np.asarray(period, dtype=float)
    wrap = period > 0
    if wrap.any() and len(i):
        delta = position[i][:, wrap] - position[j][:, wrap]
        count[:, wrap] = np.round(delta / period[wrap])
    return count


def image_shifts(position: np.ndarray, i: np.ndarray, j: np.ndarray, period: np.ndarray | None = None) -> np.ndarray:
    """The shift (C, d) [length] that takes particle j of each pair (i, j) to its image nearest to particle i:
    `image_counts` box lengths on each periodic axis, 0 on the others and everywhere in a bounded box."""
    period = np.zeros(position.shape[1]) if period is None else np.asarray(period, dtype=float)
    return image_counts(position, i, j, period) * period


def branch_vectors(position: np.ndarray, i: np.ndarray, j: np.ndarray, period: np.ndarray | None = None) -> np.ndarray:
    """x_i − x_j of each pair (C, d) [length], to the image of j nearest to i on the periodic axes (`image_shifts`);
    exactly position[i] − position[j] in a bounded box."""
    return position[i] - (position[j] + image_shifts(position, i, j, period))
