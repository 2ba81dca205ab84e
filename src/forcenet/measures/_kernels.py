"""numba kernels for cluster statistics over a threshold sweep (driven by `measures.clusters`).

Only numpy, numba and math are imported here (kernels live apart from their drivers). Vertices are compact ids 0..V−1.
"""
from __future__ import annotations

import numba
import numpy as np

from forcenet._numba import NJIT

# columns of the sweep's per-threshold output table
N_VERTICES, N_CLUSTERS, N_EDGES, N_PERCOLATING, PERCOLATING_SIZE, LARGEST_SIZE = range(6)
N_COUNTS = 6


@numba.njit(**NJIT)
def _find(parent, vertex):
    root = vertex
    while parent[root] != root:
        root = parent[root]
    while parent[vertex] != root:  # path compression
        parent[vertex], vertex = root, parent[vertex]
    return root


@numba.njit(**NJIT)
def _percolates(wall_mask, opposite_pairs):
    for pair in opposite_pairs:
        if wall_mask & pair == pair:
            return True
    return False


@numba.njit(**NJIT)
def cluster_sweep(vertex_value, edge_a, edge_b, edge_value, vertex_walls, opposite_pairs, thresholds):
    """Union–find over a super-level sweep: cluster statistics at every threshold in one pass.

    Vertices enter at their value, edges at theirs (both ≥ θ present, P2 Eq. 1); statistics are updated
    at each merge, so the cost is O((V + E) α + T) instead of one labelling per threshold.

    Parameters
    ----------
    vertex_value : float64 (V,) — a vertex is present when value ≥ θ (≥ each of its edges' values).
    edge_a, edge_b : int64 (E,) — edges, sorted by decreasing `edge_value`.
    edge_value : float64 (E,), non-increasing.
    vertex_walls : int64 (V,) — bit w set when the vertex touches wall w.
    opposite_pairs : int64 (P,) — bit masks of opposite wall pairs (percolation: both bits in one cluster).
    thresholds : float64 (T,), non-increasing.

    Returns
    -------
    counts : int64 (T, N_COUNTS) — per threshold: vertices present, clusters, edges present, percolating
        clusters, particles in percolating clusters, largest cluster size.
    ratio_sum : float64 (T,) — Σ over clusters of edges/particles (for a per-cluster mean shape parameter).
    """
    n_vertices = vertex_value.size
    parent = np.arange(n_vertices)
    size = np.ones(n_vertices, np.int64)
    edges_in = np.zeros(n_vertices, np.int64)
    walls = vertex_walls.copy()
    vertex_order = np.argsort(-vertex_value, kind="mergesort")
    counts = np.zeros((thresholds.size, N_COUNTS), np.int64)
    ratio_sum_out = np.zeros(thresholds.size)
    present = clusters = edges = n_perc = perc_size = largest = 0
    ratio_sum = 0.0
    next_vertex = next_edge = 0
    for t in range(thresholds.size):
        threshold = thresholds[t]
        while next_vertex < n_vertices and vertex_value[vertex_order[next_vertex]] >= threshold:
            v = vertex_order[next_vertex]
            next_vertex += 1
            present += 1
            clusters += 1
            largest = max(largest, 1)
            if _percolates(walls[v], opposite_pairs):
                n_perc += 1
                perc_size += 1
        while next_edge < edge_value.size and edge_value[next_edge] >= threshold:
            root_a = _find(parent, edge_a[next_edge])
            root_b = _find(parent, edge_b[next_edge])
            next_edge += 1
            edges += 1
            if root_a == root_b:  # closes a loop inside one cluster
                ratio_sum += 1.0 / size[root_a]
                edges_in[root_a] += 1
                continue
            # remove both clusters' contributions, merge (union by size), add the merged one's
            for root in (root_a, root_b):
                ratio_sum -= edges_in[root] / size[root]
                if _percolates(walls[root], opposite_pairs):
                    n_perc -= 1
                    perc_size -= size[root]
            if size[root_a] < size[root_b]:
                root_a, root_b = root_b, root_a
            parent[root_b] = root_a
            size[root_a] += size[root_b]
            edges_in[root_a] += edges_in[root_b] + 1
            walls[root_a] |= walls[root_b]
            clusters -= 1
            largest = max(largest, size[root_a])
            ratio_sum += edges_in[root_a] / size[root_a]
            if _percolates(walls[root_a], opposite_pairs):
                n_perc += 1
                perc_size += size[root_a]
        counts[t, N_VERTICES] = present
        counts[t, N_CLUSTERS] = clusters
        counts[t, N_EDGES] = edges
        counts[t, N_PERCOLATING] = n_perc
        counts[t, PERCOLATING_SIZE] = perc_size
        counts[t, LARGEST_SIZE] = largest
        ratio_sum_out[t] = ratio_sum
    return counts, ratio_sum_out


@numba.njit(**NJIT)
def component_labels(n_vertices, edge_a, edge_b):
    """Connected-component label of each vertex, labels 0..K−1 in order of first appearance by vertex id."""
    parent = np.arange(n_vertices)
    for k in range(edge_a.size):
        root_a = _find(parent, edge_a[k])
        root_b = _find(parent, edge_b[k])
        if root_a != root_b:
            parent[max(root_a, root_b)] = min(root_a, root_b)
    labels = np.full(n_vertices, -1, np.int64)
    next_label = 0
    for v in range(n_vertices):
        root = _find(parent, v)
        if labels[root] == -1:
            labels[root] = next_label
            next_label += 1
        labels[v] = labels[root]
    return labels
