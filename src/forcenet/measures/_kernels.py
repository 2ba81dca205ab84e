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
def _root_and_image(parent, image, vertex, total):
    """Root of `vertex` without path compression (which would lose the images), and in `total` (d,) the image
    of `vertex` in its root's frame: the box lengths per axis by which its position must be shifted so that
    every edge of its cluster joins nearest images. `image[v]` is v's image relative to `parent[v]`."""
    total[:] = 0
    while parent[vertex] != vertex:
        total += image[vertex]
        vertex = parent[vertex]
    return vertex


@numba.njit(**NJIT)
def _link(image_a, edge_image, image_b, link):
    """Into `link` (d,): where the edge places b, image_a + edge_image, relative to where b's cluster places it,
    image_b; for b's root relative to a's root when they differ, the winding of the loop closed when they agree."""
    for axis in range(link.size):
        link[axis] = image_a[axis] + edge_image[axis] - image_b[axis]


@numba.njit(**NJIT)
def _attach(parent, size, image, root_a, root_b, link, follow_images):
    """Union by size of two clusters' roots; with `follow_images`, `link` (d,) is root_b's image relative to
    root_a. Returns (kept root, absorbed root)."""
    sign = 1
    if size[root_a] < size[root_b]:
        root_a, root_b = root_b, root_a
        sign = -1
    parent[root_b] = root_a
    if follow_images:
        for axis in range(link.size):
            image[root_b, axis] = sign * link[axis]
    size[root_a] += size[root_b]
    return root_a, root_b


@numba.njit(**NJIT)
def _winding_walls(winding, axis_pairs):
    """The opposite-wall bits of every axis on which `winding` (d,) is not 0: a cycle that winds around a
    periodic axis joins a cluster to its own image, as two opposite walls would (P1 §4's percolation)."""
    mask = 0
    for axis in range(winding.size):
        if winding[axis] != 0:
            mask |= axis_pairs[axis]
    return mask


@numba.njit(**NJIT)
def _percolates(wall_mask, opposite_pairs):
    for pair in opposite_pairs:
        if wall_mask & pair == pair:
            return True
    return False


@numba.njit(**NJIT)
def cluster_sweep(vertex_value, edge_a, edge_b, edge_value, vertex_walls, opposite_pairs, thresholds, edge_image,
                  axis_pairs):
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
    edge_image : int64 (E, d) — box lengths that take b to its image nearest to a, per edge (0 when bounded).
    axis_pairs : int64 (d,) — wall-pair bits set on a cluster that winds around axis k (periodic axes), 0 on the
        bounded axes; all 0 for a bounded box, which then never follows images.

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
    periodic = np.any(axis_pairs != 0)
    image = np.zeros((n_vertices if periodic else 0, edge_image.shape[1]), np.int64)
    image_a = np.zeros(edge_image.shape[1], np.int64)
    image_b = np.zeros(edge_image.shape[1], np.int64)
    link = np.zeros(edge_image.shape[1], np.int64)
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
            edge = next_edge
            next_edge += 1
            edges += 1
            if periodic:
                root_a = _root_and_image(parent, image, edge_a[edge], image_a)
                root_b = _root_and_image(parent, image, edge_b[edge], image_b)
                _link(image_a, edge_image[edge], image_b, link)
            else:
                root_a = _find(parent, edge_a[edge])
                root_b = _find(parent, edge_b[edge])
            if root_a == root_b:  # closes a loop inside one cluster
                ratio_sum += 1.0 / size[root_a]
                edges_in[root_a] += 1
                if periodic:  # a loop that winds around a periodic axis joins the cluster to its own image
                    was_percolating = _percolates(walls[root_a], opposite_pairs)
                    walls[root_a] |= _winding_walls(link, axis_pairs)
                    if not was_percolating and _percolates(walls[root_a], opposite_pairs):
                        n_perc += 1
                        perc_size += size[root_a]
                continue
            # remove both clusters' contributions, merge (union by size), add the merged one's
            for root in (root_a, root_b):
                ratio_sum -= edges_in[root] / size[root]
                if _percolates(walls[root], opposite_pairs):
                    n_perc -= 1
                    perc_size -= size[root]
            root_a, root_b = _attach(parent, size, image, root_a, root_b, link, periodic)
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


@numba.njit(**NJIT)
def winding_walls(n_vertices, edge_a, edge_b, edge_image, axis_pairs):
    """The wall-pair bits of every periodic axis around which each vertex's component winds (`cluster_sweep`'s
    images), shape (n_vertices,), int64; 0 for every vertex when `axis_pairs` is all 0 (a bounded box)."""
    walls = np.zeros(n_vertices, np.int64)
    if not np.any(axis_pairs != 0):
        return walls
    parent = np.arange(n_vertices)
    size = np.ones(n_vertices, np.int64)
    image = np.zeros((n_vertices, edge_image.shape[1]), np.int64)
    image_a = np.zeros(edge_image.shape[1], np.int64)
    image_b = np.zeros(edge_image.shape[1], np.int64)
    link = np.zeros(edge_image.shape[1], np.int64)
    for edge in range(edge_a.size):
        root_a = _root_and_image(parent, image, edge_a[edge], image_a)
        root_b = _root_and_image(parent, image, edge_b[edge], image_b)
        _link(image_a, edge_image[edge], image_b, link)
        if root_a == root_b:
            walls[root_a] |= _winding_walls(link, axis_pairs)
            continue
        root_a, root_b = _attach(parent, size, image, root_a, root_b, link, True)
        walls[root_a] |= walls[root_b]
    for v in range(n_vertices):
        walls[v] = walls[_root_and_image(parent, image, v, image_a)]
    return walls
