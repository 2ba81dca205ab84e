"""Betti curves B_k(θ) read off persistence diagrams.

In the super-level filtration a class with (birth, death) is alive in the force network FN(θ) = {f ≥ θ}
(P2 Eq. 1) exactly when birth ≥ θ > death, so B_k(θ) = #{points of PD_k with birth ≥ θ > death}; never-dying
classes (death = −inf) are alive for every θ ≤ birth. P1 §5.1 counts B0 (clusters), B1 (loops of ≥ 4
particles) and B2 (voids, 3D) over F_th ∈ [0, 3].
"""
from __future__ import annotations

import numpy as np

from forcenet.topology.persistence import PersistenceDiagrams

THRESHOLD_STOP = 3.0  # P1 §3: F_th ∈ [0.0, 3.0]
THRESHOLD_STEP = 0.05


def default_thresholds(start: float = 0.0, stop: float = THRESHOLD_STOP, step: float = THRESHOLD_STEP) -> np.ndarray:
    """Threshold grid F_th from `start` to `stop` inclusive by `step` [⟨F⟩]; default 0, 0.05, …, 3 (61 values).

    Values are rounded to 12 decimals so that 0.15 is the float nearest 0.15, not 3 × 0.05.
    """
    count = int(round((stop - start) / step)) + 1
    return np.round(start + step * np.arange(count), 12)


def betti_curves(diagrams: PersistenceDiagrams, thresholds: np.ndarray | None = None,
                 max_dim: int | None = None) -> np.ndarray:
    """B_k(θ) for k = 0..max_dim.

    Parameters
    ----------
    diagrams : PersistenceDiagrams.
    thresholds : array, shape (n_thresholds,) [⟨F⟩]; default `default_thresholds()`.
    max_dim : highest k; default ``diagrams.top_dim`` (``max_dim``, or the highest dimension present).

    Returns
    -------
    ndarray, shape (max_dim + 1, n_thresholds), int64.
    """
    thresholds = default_thresholds() if thresholds is None else np.asarray(thresholds, dtype=np.float64)
    homology_dim = np.asarray(diagrams.homology_dim)
    max_dim = diagrams.top_dim if max_dim is None else int(max_dim)
    birth, death = np.asarray(diagrams.birth), np.asarray(diagrams.death)
    curves = np.zeros((max_dim + 1, thresholds.size), dtype=np.int64)
    for k in range(max_dim + 1):
        mask = homology_dim == k
        born = np.sort(birth[mask])
        died = np.sort(death[mask])
        # #{birth ≥ θ} − #{death ≥ θ}: every point with death ≥ θ also has birth ≥ θ
        curves[k] = ((born.size - np.searchsorted(born, thresholds, side="left"))
                     - (died.size - np.searchsorted(died, thresholds, side="left")))
    return curves
