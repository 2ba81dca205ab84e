"""Summaries of persistence diagrams: P1 §5.3 persistence bins of PD0 and total persistence TP_k."""
from __future__ import annotations

import numpy as np

from forcenet.datasets.schema import PERSISTENCE_BINS  # noqa: F401  (re-exported: the bin order)
from forcenet.topology.persistence import PersistenceDiagrams

ROUGH_LIFESPAN = 0.1  # P1 §5.3: rough if θ_b − θ_d ≤ 0.1
WEAK_BIRTH, MEDIUM_BIRTH, STRONG_BIRTH = 0.1, 1.0, 2.5  # P1 §5.3: weak [0.1, 1), medium [1, 2.5), strong ≥ 2.5


def persistence_bin_counts(diagrams: PersistenceDiagrams, homology_dim: int = 0) -> np.ndarray:
    """Points of PD_k per P1 §5.3 bin, in the order of `PERSISTENCE_BINS`.

    rough: finite points with lifespan ≤ 0.1; the other finite points by birth: weak 0.1 ≤ θ_b < 1,
    medium 1 ≤ θ_b < 2.5, strong θ_b ≥ 2.5; essential: never-dying classes, counted apart whatever their
    birth. (A finite non-rough point has θ_b > 0.1, since deaths are ≥ 0, so the bins cover every point.)

    Returns
    -------
    ndarray, shape (5,), int64.
    """
    one = diagrams.select(homology_dim)
    essential = one.essential
    rough = one.lifespan[~essential] <= ROUGH_LIFESPAN
    birth = np.asarray(one.birth)[~essential][~rough]
    return np.array([np.count_nonzero(rough),
                     np.count_nonzero((birth >= WEAK_BIRTH) & (birth < MEDIUM_BIRTH)),
                     np.count_nonzero((birth >= MEDIUM_BIRTH) & (birth < STRONG_BIRTH)),
                     np.count_nonzero(birth >= STRONG_BIRTH),
                     np.count_nonzero(essential)], dtype=np.int64)


def total_persistence(diagrams: PersistenceDiagrams, max_dim: int | None = None) -> np.ndarray:
    """TP_k = Σ (θ_b − θ_d) over the finite points of PD_k (P1 §5.3), k = 0..max_dim; shape (max_dim + 1,).

    `max_dim` defaults to `PersistenceDiagrams.top_dim`. Never-dying classes are left out (their lifespan is
    infinite); count them with `essential_counts`.
    """
    max_dim = diagrams.top_dim if max_dim is None else int(max_dim)
    finite = ~diagrams.essential
    return np.bincount(np.asarray(diagrams.homology_dim)[finite], weights=diagrams.lifespan[finite],
                       minlength=max_dim + 1)[:max_dim + 1].astype(np.float64)


def essential_counts(diagrams: PersistenceDiagrams, max_dim: int | None = None) -> np.ndarray:
    """Never-dying classes per homology dimension, shape (max_dim + 1,), int64; `max_dim` defaults to
    `PersistenceDiagrams.top_dim`."""
    max_dim = diagrams.top_dim if max_dim is None else int(max_dim)
    return np.bincount(np.asarray(diagrams.homology_dim)[diagrams.essential], minlength=max_dim + 1)[:max_dim + 1]
