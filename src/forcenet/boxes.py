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


def image_shifts(position: np.ndarray, i: np.ndarray, j: np.ndarray, period: np.ndarray | None = None) -> np.ndarray:
    """The shift (C, d) [length] that takes particle j of each pair (i, j) to its image nearest to particle i: a
    whole number of box lengths on each axis where `period` (d,) is positive, 0 on the others and everywhere when
    `period` is None (a bounded box)."""
    shift = np.zeros((len(i), position.shape[1]))
    period = np.zeros(position.shape[1]) if period is None else np.asarray(period, dtype=float)
    wrap = period > 0
    if wrap.any() and len(i):
        delta = position[i][:, wrap] - position[j][:, wrap]
        shift[:, wrap] = period[wrap] * np.round(delta / period[wrap])
    return shift


def branch_vectors(position: np.ndarray, i: np.ndarray, j: np.ndarray, period: np.ndarray | None = None) -> np.ndarray:
    """x_i − x_j of each pair (C, d) [length], to the image of j nearest to i on the periodic axes (`image_shifts`);
    exactly position[i] − position[j] in a bounded box."""
    return position[i] - (position[j] + image_shifts(position, i, j, period))
