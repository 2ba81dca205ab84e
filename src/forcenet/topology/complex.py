"""The flag complex of a force network and its super-level filtration values (P2 §III A).

Vertices are the network particles, edges its contacts; every triangle of edges is filled, so that 3-particle
loops never count as loops (P1 §5.1, P2 §III A: "we refer to a loop involving four or more particles as a
defect"). In 3D every 4-clique (four mutually touching spheres) is by default a filled tetrahedron as well; left
hollow (``fill_tetrahedra=False``, config key ``analysis.fill_tetrahedra``), each such tetrahedral interstice is
an enclosed void of B2 (P1 §5.1 calls B2 "the number of enclosed voids"; docs/decisions.md). Filtration values
(P2 §III A):

    f(edge)    = its force,
    f(vertex)  = max of its incident edges (0 for a vertex without edges: it appears at zero force),
    f(simplex) = min of its edges, for triangles and tetrahedra,

so a simplex is present at threshold θ when f ≥ θ (P2 Eq. 1) and faces always enter no later than cofaces.

Cliques are enumerated with numpy only (no Python loop over simplices): with edges oriented from the lower
to the higher vertex id, every triangle u < v < w is found once as a pair of out-neighbours (v, w) of u that
are themselves joined, and every tetrahedron as a triangle extended by a later out-neighbour x of u joined
to both v and w.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from forcenet.network.force_network import CompactVertices, ForceNetwork, vertex_values  # noqa: F401  (re-exported)


@dataclass(frozen=True)
class FlagComplex(CompactVertices):
    """Simplices of a flag complex with their filtration values on the compact vertex ids of its network
    (`CompactVertices`: ``particle``, ``n_vertices``).

    Attributes (after ``particle``)
    -------------------------------
    vertex_value : ndarray, shape (V,) — f(vertex) [⟨F⟩].
    edges : ndarray, shape (E, 2), int64 — sorted vertex pairs (a < b), lexicographically ordered.
    edge_value : ndarray, shape (E,) [⟨F⟩].
    triangles : ndarray, shape (T, 3), int64 — sorted vertex triples.
    triangle_value : ndarray, shape (T,) [⟨F⟩].
    tetrahedra : ndarray, shape (K, 4), int64 — sorted vertex quadruples (empty unless requested).
    tetrahedron_value : ndarray, shape (K,) [⟨F⟩].
    """

    vertex_value: np.ndarray
    edges: np.ndarray
    edge_value: np.ndarray
    triangles: np.ndarray
    triangle_value: np.ndarray
    tetrahedra: np.ndarray
    tetrahedron_value: np.ndarray

    def simplices(self, dimension: int) -> tuple[np.ndarray, np.ndarray]:
        """(simplices, values) of one dimension: shapes (n, dimension + 1) and (n,)."""
        if dimension == 0:
            return np.arange(self.n_vertices, dtype=np.int64)[:, None], self.vertex_value
        return ((self.edges, self.edge_value), (self.triangles, self.triangle_value),
                (self.tetrahedra, self.tetrahedron_value))[dimension - 1]


def enumerate_cliques(n_vertices: int, edges: np.ndarray, edge_value: np.ndarray, max_size: int = 3):
    """Triangles (and tetrahedra when ``max_size == 4``) of a graph with min-of-edges values.

    Parameters
    ----------
    n_vertices : V.
    edges : ndarray, shape (E, 2), int64 — unique pairs with ``edges[:, 0] < edges[:, 1]``, lexicographically
        sorted.
    edge_value : ndarray, shape (E,).
    max_size : 2 (edges only), 3 (triangles) or 4 (triangles and tetrahedra).

    Returns
    -------
    triangles (T, 3), triangle_value (T,), tetrahedra (K, 4), tetrahedron_value (K,).
    """
    empty_triangles = (np.empty((0, 3), np.int64), np.empty(0))
    empty_tetrahedra = (np.empty((0, 4), np.int64), np.empty(0))
    if max_size < 3 or len(edges) < 3:
        return (*empty_triangles, *empty_tetrahedra)
    low, high = edges[:, 0], edges[:, 1]
    start = np.searchsorted(low, np.arange(n_vertices + 1))  # CSR of out-neighbours (edges sorted by low)
    end_of_row = start[low + 1]  # one past the last out-edge of each edge's lower vertex
    edge_key = low * n_vertices + high  # sorted, since edges are lexicographically sorted

    def edge_index(a: np.ndarray, b: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Index of edge (a, b), a < b, and whether it exists."""
        key = a * n_vertices + b
        index = np.minimum(np.searchsorted(edge_key, key), len(edge_key) - 1)
        return index, edge_key[index] == key

    # wedges: out-edge positions first < second of the same lower vertex u → candidate triangle (u, v, w)
    first, second = _later_positions(np.arange(len(edges)), end_of_row)
    closing, is_triangle = edge_index(high[first], high[second])
    first, second, closing = first[is_triangle], second[is_triangle], closing[is_triangle]
    triangles = np.stack([low[first], high[first], high[second]], axis=1)
    triangle_value = np.minimum(np.minimum(edge_value[first], edge_value[second]), edge_value[closing])
    if max_size < 4 or len(triangles) == 0:
        return triangles, triangle_value, *empty_tetrahedra
    # tetrahedra: a triangle (u, v, w) from positions first < second, extended by a third position of u
    owner, third = _later_positions(second, end_of_row[second])
    to_v, has_v = edge_index(high[first][owner], high[third])
    to_w, has_w = edge_index(high[second][owner], high[third])
    found = has_v & has_w
    owner, third, to_v, to_w = owner[found], third[found], to_v[found], to_w[found]
    tetrahedra = np.concatenate([triangles[owner], high[third][:, None]], axis=1)
    tetrahedron_value = np.minimum(np.minimum(triangle_value[owner], edge_value[third]),
                                   np.minimum(edge_value[to_v], edge_value[to_w]))
    return triangles, triangle_value, tetrahedra, tetrahedron_value


def _later_positions(position: np.ndarray, row_end: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """All pairs (k, q) with q in (position[k], row_end[k]): which item k, and the later position q.

    For edges this pairs an out-edge with every later out-edge of the same vertex. Returns (owner, later)
    where ``owner`` indexes `position`.
    """
    count = row_end - position - 1
    owner = np.repeat(np.arange(len(position)), count)
    offset = np.arange(owner.size) - np.repeat(np.cumsum(count) - count, count)
    return owner, np.repeat(position, count) + 1 + offset


#: the highest filled simplex of a force network's flag complex (global attribute ``flag_complex`` of analysis,
#: stacked and distance files) → what that means
FLAG_COMPLEX_DESCRIPTIONS = {
    "tetrahedra": "flag complex of the contacts, every triangle and every 4-clique (tetrahedron) filled: "
                  "3-particle loops are not loops and 4 mutually touching spheres enclose no void",
    "triangles": "flag complex of the contacts up to triangles: every triangle filled, 4-cliques left hollow "
                 "(in 3D each tetrahedral interstice of 4 mutually touching spheres is an enclosed void of B2; "
                 "a 2D complex needs no tetrahedra)",
}


def flag_complex_name(dim: int, fill_tetrahedra: bool = True) -> str:
    """Key of `FLAG_COMPLEX_DESCRIPTIONS` for the complex whose homology up to dimension d − 1 is computed:
    "tetrahedra" in 3D with `fill_tetrahedra`, else "triangles" (2D needs no simplex above a triangle for
    H0 and H1, so the option does not change a 2D complex)."""
    return "tetrahedra" if dim == 3 and fill_tetrahedra else "triangles"


def flag_complex(network: ForceNetwork, max_simplex_dim: int | None = None) -> FlagComplex:
    """The flag complex of a force network (module docstring).

    Parameters
    ----------
    network : ForceNetwork — forces in ⟨F⟩.
    max_simplex_dim : highest simplex dimension; default ``network.dim`` (triangles in 2D, tetrahedra in
        3D), enough for homology up to dimension d − 1 (PD0, PD1 and, in 3D, PD2).
    """
    max_simplex_dim = network.dim if max_simplex_dim is None else int(max_simplex_dim)
    graph = network.compact  # compact edges already sorted (a < b, lexicographic): the ForceNetwork invariant
    triangles, triangle_value, tetrahedra, tetrahedron_value = enumerate_cliques(
        graph.n_vertices, graph.edges, graph.force, max_size=max_simplex_dim + 1)
    return FlagComplex(particle=graph.particle, vertex_value=graph.vertex_value, edges=graph.edges,
                       edge_value=graph.force, triangles=triangles, triangle_value=triangle_value,
                       tetrahedra=tetrahedra, tetrahedron_value=tetrahedron_value)
