"""Slow, obviously correct references for the topology and cluster code (tested against in tests/).

Everything here works on small graphs given as an edge list with forces, with plain Python: cliques by
itertools, homology ranks over GF(2) by Gaussian elimination on Python-int bit rows, components by
breadth-first search (with the loops that wind around a periodic box), nearest images by trying every
neighbouring image, optimal matchings by enumerating permutations.
"""
from __future__ import annotations

import itertools
import math
from collections import deque

import numpy as np


def thresholded_complex(n_vertices, edges, force, threshold, max_simplex_dim):
    """Simplices of the flag complex present at θ (all edges ≥ θ), by brute-force clique search.

    A vertex is present when some incident edge is ≥ θ, or (isolated vertex, value 0) when θ ≤ 0.
    Returns a list over dimensions of sets of sorted vertex tuples.
    """
    strong = {tuple(sorted(e)) for e, f in zip(edges, force) if f >= threshold}
    touched = {v for e in strong for v in e}
    degree = {v: 0 for v in range(n_vertices)}
    for e in edges:
        degree[e[0]] += 1
        degree[e[1]] += 1
    vertices = {v for v in range(n_vertices) if v in touched or (degree[v] == 0 and threshold <= 0)}
    simplices = [{(v,) for v in vertices}, set(strong)]
    for size in range(3, max_simplex_dim + 2):
        simplices.append({c for c in itertools.combinations(sorted(vertices), size)
                          if all(pair in strong for pair in itertools.combinations(c, 2))})
    return simplices[:max_simplex_dim + 1]


def gf2_rank(rows):
    """Rank over GF(2) of a list of Python ints (bit rows)."""
    pivots = {}
    rank = 0
    for row in rows:
        while row:
            top = row.bit_length() - 1
            if top not in pivots:
                pivots[top] = row
                rank += 1
                break
            row ^= pivots[top]
    return rank


def boundary_rank(higher, lower):
    """Rank of the boundary map from `higher`-dimensional simplices to `lower`-dimensional ones over GF(2)."""
    index = {s: i for i, s in enumerate(sorted(lower))}
    rows = []
    for s in higher:
        row = 0
        for face in itertools.combinations(s, len(s) - 1):
            row |= 1 << index[face]
        rows.append(row)
    return gf2_rank(rows)


def betti_numbers(n_vertices, edges, force, threshold, max_homology_dim, max_simplex_dim=None):
    """B_0..B_max_homology_dim of the flag complex at θ, with simplices up to dimension `max_simplex_dim`
    (default max_homology_dim + 1; a lower one leaves the top cliques hollow)."""
    top = max_homology_dim + 1 if max_simplex_dim is None else max_simplex_dim
    simplices = thresholded_complex(n_vertices, edges, force, threshold, top)
    simplices += [set()] * (max_homology_dim + 1 - top)  # no simplices above `top`
    ranks = [0] + [boundary_rank(simplices[k], simplices[k - 1]) for k in range(1, len(simplices))] + [0]
    return [len(simplices[k]) - ranks[k] - ranks[k + 1] for k in range(max_homology_dim + 1)]


def pd0_elder_rule(n_vertices, edges, force):
    """PD0 of the super-level filtration by union–find with the elder rule.

    Vertices enter at the largest incident force (0 if none), edges at their force, in decreasing order
    (vertices first on ties). When an edge joins two components the younger one (lower birth) dies.
    Returns (finite points as a sorted list of (birth, death) with birth > death, sorted essential births).
    """
    value = [0.0] * n_vertices
    for (a, b), f in zip(edges, force):
        value[a] = max(value[a], f)
        value[b] = max(value[b], f)
    parent = list(range(n_vertices))
    birth = list(value)

    def find(v):
        while parent[v] != v:
            v = parent[v]
        return v

    finite = []
    for (a, b), f in sorted(zip(edges, force), key=lambda item: -item[1]):
        ra, rb = find(a), find(b)
        if ra == rb:
            continue
        young, old = (ra, rb) if birth[ra] < birth[rb] else (rb, ra)
        if birth[young] > f:
            finite.append((birth[young], f))
        parent[young] = old
    essential = sorted(birth[v] for v in range(n_vertices) if find(v) == v)
    return sorted(finite), essential


def components(n_vertices, edges, force, threshold):
    """Connected components (sets of vertices) of the graph of edges with force ≥ θ; vertices without such
    an edge are left out."""
    adjacency = {v: [] for v in range(n_vertices)}
    for (a, b), f in zip(edges, force):
        if f >= threshold:
            adjacency[a].append(b)
            adjacency[b].append(a)
    seen, result = set(), []
    for start in range(n_vertices):
        if start in seen or not adjacency[start]:
            continue
        queue, group = deque([start]), {start}
        seen.add(start)
        while queue:
            v = queue.popleft()
            for w in adjacency[v]:
                if w not in seen:
                    seen.add(w)
                    group.add(w)
                    queue.append(w)
        result.append(group)
    return result


def nearest_image_counts(position, i, j, period):
    """For each pair, the whole box lengths (one of −1, 0, +1 per periodic axis) that take particle j to its image
    nearest to particle i, found by trying all 3^d neighbouring images (ties go to the first tried)."""
    dim = len(period)
    trials = [np.array(t) * np.array([1 if p > 0 else 0 for p in period])
              for t in itertools.product((-1, 0, 1), repeat=dim)]
    counts = []
    for a, b in zip(i, j):
        distance = [np.linalg.norm(position[a] - (position[b] + t * np.asarray(period))) for t in trials]
        counts.append(trials[int(np.argmin(distance))])
    return np.array(counts, dtype=np.int64).reshape(len(i), dim)


def winding_axes(n_vertices, edges, images, force, threshold):
    """For each component of `components` (same order), the set of axes some loop of it winds around: a breadth-first
    search places every particle at an image (whole box lengths per axis) that its tree edges agree with; an edge
    (a, b) with image count s that then disagrees, U(a) + s ≠ U(b), closes a loop winding by that difference."""
    adjacency = {v: [] for v in range(n_vertices)}
    for (a, b), s, f in zip(edges, images, force):
        if f >= threshold:
            adjacency[a].append((b, np.asarray(s)))
            adjacency[b].append((a, -np.asarray(s)))
    result = []
    for group in components(n_vertices, edges, force, threshold):
        start = min(group)
        place, queue = {start: np.zeros(len(images[0]), dtype=np.int64)}, deque([start])
        while queue:
            v = queue.popleft()
            for w, s in adjacency[v]:
                if w not in place:
                    place[w] = place[v] + s
                    queue.append(w)
        axes = set()
        for (a, b), s, f in zip(edges, images, force):
            if f >= threshold and a in group:
                axes |= set(np.flatnonzero(place[a] + np.asarray(s) != place[b]).tolist())
        result.append(axes)
    return result


def optimal_matching_costs(points_a, points_b, q):
    """(d_B, W_q) by enumerating every matching of two tiny diagrams with the diagonal (L∞ ground metric).

    Each point of A is matched to a point of B or to the diagonal, each point of B likewise: the classical
    (n + m) × (n + m) assignment with diagonal copies, solved by trying every permutation.
    """
    a, b = np.asarray(points_a, float).reshape(-1, 2), np.asarray(points_b, float).reshape(-1, 2)
    n, m = len(a), len(b)
    size = n + m
    cost = np.full((size, size), math.inf)
    for i in range(n):
        for j in range(m):
            cost[i, j] = np.max(np.abs(a[i] - b[j]))
        cost[i, m + i] = 0.5 * (a[i, 0] - a[i, 1])
    for j in range(m):
        cost[n + j, j] = 0.5 * (b[j, 0] - b[j, 1])
        cost[n + j, m:] = 0.0
    best_total, best_max = math.inf, math.inf
    for permutation in itertools.permutations(range(size)):
        chosen = cost[np.arange(size), permutation]
        if not np.all(np.isfinite(chosen)):
            continue
        best_total = min(best_total, float(np.sum(chosen ** q)))
        best_max = min(best_max, float(np.max(chosen, initial=0.0)))
    return best_max, best_total ** (1.0 / q)
