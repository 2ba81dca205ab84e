"""Persistence diagrams of the super-level filtration of a force network's flag complex (P2 §III A–C).

dionysus computes persistence of a *sub*-level (increasing) filtration and stores filtration values as
float32. Both pitfalls are handled here:

- the complex is ordered by NEGATED value, ties broken faces-first by dimension (a vertex's value is ≥ its
  edges', a triangle's ≤ its edges', so this order is a filtration), and handed to dionysus with each
  simplex's *rank* in that order as its value — integers below 2²⁴ are exact in float32;
- birth and death ranks are then mapped back to the original float64 values, so every birth and death is
  exactly a force of the network (no float32 rounding).

Conventions of the stored diagrams (`datasets/schema.py`): super-level, birth ≥ death, in units of ⟨F⟩;
never-dying classes have death = −inf and ``essential = True``; zero-length points (birth == death: a
feature born and killed at the same force) are not stored — they depend on how ties are broken, and P1/P2's
bins and counts ignore them.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from forcenet.network.force_network import ForceNetwork
from forcenet.network.regions import QUADRANTS, restrict_to_quadrant
from forcenet.topology.complex import FlagComplex, flag_complex

_FLOAT32_EXACT_INTEGERS = 2 ** 24


@dataclass(frozen=True)
class PersistenceDiagrams:
    """Persistence diagrams of all homology dimensions of one network, as flat arrays of points.

    Attributes
    ----------
    homology_dim : ndarray, shape (P,), int64 — k of each point (0 components, 1 loops, 2 voids).
    birth : ndarray, shape (P,) — threshold at which the class appears [⟨F⟩].
    death : ndarray, shape (P,) — threshold at which it dies [⟨F⟩]; −inf when it never dies.
    max_dim : highest homology dimension computed (d − 1); −1 when unknown (diagrams built by hand).
    essential (property) : ndarray, shape (P,), bool — the class never dies, i.e. ``~isfinite(death)``.
    """

    homology_dim: np.ndarray
    birth: np.ndarray
    death: np.ndarray
    max_dim: int = -1

    def __post_init__(self):
        n = np.asarray(self.birth).shape
        for name in ("homology_dim", "death"):
            if np.asarray(getattr(self, name)).shape != n:
                raise ValueError(f"{name} must have the shape of birth {n}")

    @property
    def essential(self) -> np.ndarray:
        """The class never dies (death −inf), shape (P,), bool."""
        return ~np.isfinite(np.asarray(self.death))

    @property
    def n_points(self) -> int:
        return int(np.asarray(self.birth).size)

    @property
    def top_dim(self) -> int:
        """Highest homology dimension: `max_dim`, or when unknown (−1) the highest one present (0 if none)."""
        return self.max_dim if self.max_dim >= 0 else int(np.max(np.asarray(self.homology_dim), initial=0))

    @property
    def lifespan(self) -> np.ndarray:
        """birth − death, shape (P,) [⟨F⟩]; +inf for never-dying classes."""
        return np.asarray(self.birth) - np.asarray(self.death)

    def select(self, homology_dim: int) -> "PersistenceDiagrams":
        """The points of one homology dimension."""
        mask = np.asarray(self.homology_dim) == homology_dim
        return PersistenceDiagrams(np.asarray(self.homology_dim)[mask], np.asarray(self.birth)[mask],
                                   np.asarray(self.death)[mask], max_dim=self.max_dim)

    def points(self, homology_dim: int, *, include_essential: bool = True) -> np.ndarray:
        """(birth, death) pairs of one homology dimension, shape (n, 2); essential ones have death −inf."""
        one = self.select(homology_dim)
        keep = np.ones(one.n_points, dtype=bool) if include_essential else ~one.essential
        return np.stack([one.birth[keep], one.death[keep]], axis=1).astype(np.float64).reshape(-1, 2)


def filtration_order(complex_: FlagComplex, max_simplex_dim: int) -> tuple[list, np.ndarray, np.ndarray]:
    """All simplices in super-level filtration order.

    Returns
    -------
    simplices : list of vertex lists, in filtration order.
    value : ndarray, shape (S,) — f of each simplex in that order [⟨F⟩], non-increasing.
    dimension : ndarray, shape (S,), int64.
    """
    blocks = [complex_.simplices(k) for k in range(max_simplex_dim + 1)]
    value = np.concatenate([v for _, v in blocks])
    dimension = np.concatenate([np.full(len(v), k, dtype=np.int64) for k, (_, v) in enumerate(blocks)])
    # negated value ascending, faces first on ties: dionysus accepts a coface before its face silently and
    # then computes wrong diagrams
    order = np.lexsort((dimension, -value))
    as_lists = [item for s, _ in blocks for item in s.tolist()]
    return [as_lists[k] for k in order.tolist()], value[order], dimension[order]


def persistence_of_complex(complex_: FlagComplex, max_homology_dim: int) -> PersistenceDiagrams:
    """Persistence diagrams of a flag complex with dionysus (module docstring).

    Parameters
    ----------
    complex_ : FlagComplex — its simplices up to dimension ``max_homology_dim + 1`` are used; a complex without
        simplices of that dimension (tetrahedra left hollow) leaves the top-dimensional classes essential.
    max_homology_dim : highest homology dimension reported.
    """
    import dionysus  # imported lazily: heavy, and only this function needs it

    simplices, value, dimension = filtration_order(complex_, max_homology_dim + 1)
    if len(simplices) >= _FLOAT32_EXACT_INTEGERS:
        raise ValueError("too many simplices for exact rank values in dionysus' float32 storage")
    filtration = dionysus.Filtration(list(zip(simplices, range(len(simplices)))))
    reduced = dionysus.homology_persistence(filtration)
    homology_dim, birth_rank, death_rank = [], [], []
    for k, diagram in enumerate(dionysus.init_diagrams(reduced, filtration)):
        if k > max_homology_dim:
            break
        for point in diagram:
            homology_dim.append(k)
            birth_rank.append(point.birth)
            death_rank.append(point.death)
    birth_rank = np.asarray(birth_rank, dtype=np.float64)
    death_rank = np.asarray(death_rank, dtype=np.float64)
    essential = ~np.isfinite(death_rank)
    birth = value[birth_rank.astype(np.int64)]
    death = np.full(birth.size, -np.inf)
    death[~essential] = value[death_rank[~essential].astype(np.int64)]
    homology_dim = np.asarray(homology_dim, dtype=np.int64)
    keep = essential | (birth > death)  # zero-length points are not stored (module docstring)
    # order: by dimension, then birth descending, then death descending (stable, readable storage)
    order = np.lexsort((-death[keep], -birth[keep], homology_dim[keep]))
    return PersistenceDiagrams(homology_dim=homology_dim[keep][order], birth=birth[keep][order],
                               death=death[keep][order], max_dim=max_homology_dim)


def persistence_diagrams(network: ForceNetwork, *, max_homology_dim: int | None = None,
                         fill_tetrahedra: bool = True) -> PersistenceDiagrams:
    """PD0, PD1 (and PD2 in 3D) of a force network's super-level flag filtration (P1 §5.3, P2 §III C).

    Parameters
    ----------
    network : ForceNetwork (forces in ⟨F⟩).
    max_homology_dim : default d − 1 (1 in 2D, 2 in 3D).
    fill_tetrahedra : fill every 4-clique with a tetrahedron (default; config key ``analysis.fill_tetrahedra``).
        False stops the complex at triangles while homology is still computed up to `max_homology_dim`: in 3D
        the four triangles of each hollow 4-clique then enclose a void, a PD2 class that never dies (essential),
        born when the last of them enters (at the 4-clique's weakest contact). A 2D network is unaffected either
        way (PD0 and PD1 need no simplex above a triangle).

    Returns
    -------
    PersistenceDiagrams, births and deaths exactly equal to network forces (float64), birth ≥ death.
    """
    max_homology_dim = network.dim - 1 if max_homology_dim is None else int(max_homology_dim)
    max_simplex_dim = max_homology_dim + 1 if fill_tetrahedra else min(max_homology_dim + 1, 2)
    complex_ = flag_complex(network, max_simplex_dim=max_simplex_dim)
    return persistence_of_complex(complex_, max_homology_dim)


def quadrant_persistence_diagrams(network: ForceNetwork, box_lo, box_hi, tilt=None) -> dict[str, PersistenceDiagrams]:
    """Diagrams of the four quarters of the box (`tilt`: a triclinic box's tilt factors), keyed by P2's block names
    (P2 Tables II–III)."""
    return {name: persistence_diagrams(restrict_to_quadrant(network, box_lo, box_hi, name, tilt))
            for name in QUADRANTS}
