"""Neighbour lists of the DEM engine: a cell list (`cell_index`) gives the Verlet list of every pair closer than
r_i + r_j + skin (`build_pair_list`), and the tangential springs are carried from the old list to the new one
across a rebuild and a re-ordering of the particles (`transfer_springs`).
"""
import math

import numba
import numpy as np

from forcenet._numba import NJIT_DEM


@numba.njit(**NJIT_DEM)
def cell_index(position, n, origin, cell_size, n_cells):
    """Linear cell index (n,) of the first n particles on a grid of n_cells (3,) cubes of side cell_size
    starting at origin (d,); coordinates outside the grid are clamped to its border cells."""
    dim = position.shape[1]
    cells = np.empty(n, dtype=np.int64)
    for i in range(n):
        linear = 0
        for k in range(3):
            c = 0
            if k < dim:
                c = int(math.floor((position[i, k] - origin[k]) / cell_size))
                if c < 0:
                    c = 0
                elif c >= n_cells[k]:
                    c = n_cells[k] - 1
            linear = linear * n_cells[k] + c
        cells[i] = linear
    return cells


@numba.njit(**NJIT_DEM)
def build_pair_list(position, radius, n_mobile, n_total, skin, origin, cell_size, n_cells):
    """Verlet list: every pair i < j with |r_i − r_j| < r_i + r_j + skin, i mobile (wall–wall pairs excluded),
    found through a cell list; sorted by i then j. Returns (pair_i, pair_j) int32 arrays."""
    dim = position.shape[1]
    cells = cell_index(position, n_total, origin, cell_size, n_cells)
    total_cells = n_cells[0] * n_cells[1] * n_cells[2]
    cell_start = np.zeros(total_cells + 1, dtype=np.int64)
    for i in range(n_total):
        cell_start[cells[i] + 1] += 1
    for c in range(total_cells):
        cell_start[c + 1] += cell_start[c]
    fill = cell_start[:-1].copy()
    members = np.empty(n_total, dtype=np.int64)
    for i in range(n_total):
        members[fill[cells[i]]] = i
        fill[cells[i]] += 1
    span_z = 1 if dim == 3 else 0
    row_count = np.zeros(n_mobile + 1, dtype=np.int64)
    for sweep in range(2):  # 0: count each row, 1: fill
        if sweep == 1:
            for i in range(n_mobile):
                row_count[i + 1] += row_count[i]
            n_pairs = row_count[n_mobile]
            pair_i = np.empty(n_pairs, dtype=np.int32)
            pair_j = np.empty(n_pairs, dtype=np.int32)
        for i in range(n_mobile):
            c = cells[i]
            cz = c % n_cells[2]
            cy = (c // n_cells[2]) % n_cells[1]
            cx = c // (n_cells[2] * n_cells[1])
            written = 0
            for ox in range(max(cx - 1, 0), min(cx + 2, n_cells[0])):
                for oy in range(max(cy - 1, 0), min(cy + 2, n_cells[1])):
                    for oz in range(max(cz - span_z, 0), min(cz + span_z + 1, n_cells[2])):
                        neighbour_cell = (ox * n_cells[1] + oy) * n_cells[2] + oz
                        for m in range(cell_start[neighbour_cell], cell_start[neighbour_cell + 1]):
                            j = members[m]
                            if j <= i:
                                continue
                            d_sq = 0.0
                            for k in range(dim):
                                d = position[i, k] - position[j, k]
                                d_sq += d * d
                            reach = radius[i] + radius[j] + skin
                            if d_sq < reach * reach:
                                if sweep == 0:
                                    row_count[i + 1] += 1
                                else:
                                    pair_i[row_count[i] + written] = i
                                    pair_j[row_count[i] + written] = j
                                written += 1
            if sweep == 1:  # insertion sort of the row by j (rows are short)
                start = row_count[i]
                for a in range(start + 1, start + written):
                    value = pair_j[a]
                    b = a - 1
                    while b >= start and pair_j[b] > value:
                        pair_j[b + 1] = pair_j[b]
                        b -= 1
                    pair_j[b + 1] = value
    return pair_i, pair_j


@numba.njit(**NJIT_DEM)
def transfer_springs(old_i, old_j, old_spring, n_old, new_slot, new_i, new_j, new_spring, n_total):
    """Carry the tangential history across a rebuild (and a reordering of particles).

    Every old pair with a non-zero spring is mapped through new_slot (old slot → new slot), oriented i < j
    (the spring changes sign when i and j swap: ξ integrates the slip of i relative to j) and looked up in
    the new list (sorted by i, then j). new_spring must be zero on entry. Returns how many non-zero springs
    found no pair in the new list (0 unless the skin was exceeded).
    """
    dim = old_spring.shape[1]
    n_active = 0
    for p in range(n_old):
        for k in range(dim):
            if old_spring[p, k] != 0.0:
                n_active += 1
                break
    keys = np.empty(n_active, dtype=np.int64)
    source = np.empty(n_active, dtype=np.int64)
    signs = np.empty(n_active)
    q = 0
    for p in range(n_old):
        active = False
        for k in range(dim):
            if old_spring[p, k] != 0.0:
                active = True
        if not active:
            continue
        a = new_slot[old_i[p]]
        b = new_slot[old_j[p]]
        sign = 1.0
        if a > b:
            a, b = b, a
            sign = -1.0
        keys[q] = a * n_total + b
        source[q] = p
        signs[q] = sign
        q += 1
    order = np.argsort(keys)
    lost = 0
    cursor = 0
    n_new = new_i.shape[0]
    for t in range(n_active):
        key = keys[order[t]]
        while cursor < n_new and new_i[cursor] * np.int64(n_total) + new_j[cursor] < key:
            cursor += 1
        if cursor < n_new and new_i[cursor] * np.int64(n_total) + new_j[cursor] == key:
            for k in range(dim):
                new_spring[cursor, k] = signs[order[t]] * old_spring[source[order[t]], k]
        else:
            lost += 1
    return lost
