"""The diagram-matching solver: numba kernels for the optimal matchings behind the exact bottleneck and
Wasserstein distances between persistence diagrams (driven by `topology.distances`). One algorithm, kept in one
module although over 600 lines: the bottleneck distance (is there a perfect matching within a threshold:
`threshold_graph` + Hopcroft–Karp, `has_perfect_matching`) and the W_q distance (a min-cost transport between the
points and the diagonal: `diagram_transport`, augmenting row reduction then shortest augmenting paths) work on the
same point pairs, candidate graphs and dual checks.

Kernels live apart from their drivers and import only numpy, numba and math (and the numba options of
`forcenet._numba`). Bipartite graphs are in CSR form: row r has columns ``column[row_start[r]:row_start[r + 1]]``
with weights ``weight[...]``.
"""
from __future__ import annotations

import math

import numba
import numpy as np

from forcenet._numba import NJIT


@numba.njit(**NJIT)
def _power(x, q):
    """x ** q with the common degrees as products (a float power is ~10× slower in the dense loops)."""
    if q == 1.0:
        return x
    if q == 2.0:
        return x * x
    return x ** q


@numba.njit(**NJIT)
def _useful(c, delta_a, delta_b, q, for_bottleneck):
    """Can matching two points at L∞ distance c beat sending both to the diagonal?

    With the L∞ ground metric a point's distance to the diagonal is δ = (birth − death) / 2. Matching a to
    b beats the diagonal only if ``c^q < δ_a^q + δ_b^q`` (Wasserstein) or ``c < max(δ_a, δ_b)``
    (bottleneck); every other pair can be left out without changing the optimum.
    """
    if for_bottleneck:
        return c < max(delta_a, delta_b)
    return _power(c, q) < _power(delta_a, q) + _power(delta_b, q)


@numba.njit(**NJIT)
def threshold_graph(birth_a, death_a, birth_b, death_b, max_weight):
    """Bipartite graph (CSR) of the bottleneck matching of diagram A to diagram B, edges weighted by L∞ distance.

    Rows: the n points of A, then the m diagonal copies of B's points. Columns: the m points of B, then the
    n diagonal copies of A's points. Edges: every useful pair (i, j) (`_useful`, bottleneck) at its
    distance; each point with its own diagonal copy at its distance to the diagonal; and, for each useful
    pair, B's copy j with A's copy i at the pair's distance — enough, since a_i ↔ b_j leaves exactly those
    two copies to pair, and weighting it like the pair makes it appear with the pair in every threshold
    graph. Edges heavier than `max_weight` are left out.

    Returns row_start (n + m + 1,), column (E,), weight (E,), and a lower bound on the bottleneck distance:
    the largest over rows and columns of their lightest edge (inf if one has none).
    """
    n, m = birth_a.size, birth_b.size
    delta_a = 0.5 * (birth_a - death_a)
    delta_b = 0.5 * (birth_b - death_b)
    degree = np.zeros(n + m + 1, np.int64)
    for i in range(n):
        degree[i + 1] += delta_a[i] <= max_weight
        for j in range(m):
            c = max(abs(birth_a[i] - birth_b[j]), abs(death_a[i] - death_b[j]))
            if c <= max_weight and _useful(c, delta_a[i], delta_b[j], 1.0, True):
                degree[i + 1] += 1
                degree[n + j + 1] += 1
    for j in range(m):
        degree[n + j + 1] += delta_b[j] <= max_weight
    row_start = np.cumsum(degree)
    fill = row_start[:-1].copy()
    column = np.empty(row_start[-1], np.int64)
    weight = np.empty(row_start[-1])
    for i in range(n):
        if delta_a[i] <= max_weight:
            column[fill[i]], weight[fill[i]] = m + i, delta_a[i]
            fill[i] += 1
        for j in range(m):
            c = max(abs(birth_a[i] - birth_b[j]), abs(death_a[i] - death_b[j]))
            if c <= max_weight and _useful(c, delta_a[i], delta_b[j], 1.0, True):
                column[fill[i]], weight[fill[i]] = j, c
                fill[i] += 1
                column[fill[n + j]], weight[fill[n + j]] = m + i, c
                fill[n + j] += 1
    for j in range(m):
        if delta_b[j] <= max_weight:
            column[fill[n + j]], weight[fill[n + j]] = j, delta_b[j]
            fill[n + j] += 1
    lightest_row = np.full(n + m, np.inf)
    lightest_column = np.full(n + m, np.inf)
    for r in range(n + m):
        for k in range(row_start[r], row_start[r + 1]):
            lightest_row[r] = min(lightest_row[r], weight[k])
            lightest_column[column[k]] = min(lightest_column[column[k]], weight[k])
    lower = 0.0
    for r in range(n + m):
        lower = max(lower, lightest_row[r], lightest_column[r])
    return row_start, column, weight, lower


@numba.njit(**NJIT)
def line_matching(birth_a, birth_b, death, q):
    """Optimal degree-q matching of two sets of points on one death line, among themselves and the diagonal.

    Points (birth, `death`) with `birth_a`, `birth_b` sorted ascending: their L∞ distance is the birth
    difference, a point's distance to the diagonal (birth − death)/2. |x − y|^q is convex, so some optimal
    matching never crosses (a₁ < a₂ matched to b₂ < b₁ can be swapped at no extra cost): edit-distance
    dynamic programming over the two sorted lists, O(n m) time, n m bytes. Returns the partner (index into
    `birth_b`) of each A point, −1 for the diagonal.
    """
    n, m = birth_a.size, birth_b.size
    choice = np.zeros((n + 1, m + 1), np.int8)  # 1: A point to the diagonal, 2: B point to it, 3: pair
    previous = np.empty(m + 1)
    current = np.empty(m + 1)
    previous[0] = 0.0
    for j in range(1, m + 1):
        previous[j] = previous[j - 1] + _power(0.5 * (birth_b[j - 1] - death), q)
        choice[0, j] = 2
    for i in range(1, n + 1):
        to_diagonal = _power(0.5 * (birth_a[i - 1] - death), q)
        current[0] = previous[0] + to_diagonal
        choice[i, 0] = 1
        for j in range(1, m + 1):
            best, taken = previous[j] + to_diagonal, 1
            value = current[j - 1] + _power(0.5 * (birth_b[j - 1] - death), q)
            if value < best:
                best, taken = value, 2
            value = previous[j - 1] + _power(abs(birth_a[i - 1] - birth_b[j - 1]), q)
            if value < best:
                best, taken = value, 3
            current[j] = best
            choice[i, j] = taken
        previous, current = current, previous
    partner = np.full(n, -1, np.int64)
    i, j = n, m
    while i > 0 or j > 0:
        if choice[i, j] == 1:
            i -= 1
        elif choice[i, j] == 2:
            j -= 1
        else:
            partner[i - 1] = j - 1
            i -= 1
            j -= 1
    return partner


@numba.njit(**NJIT)
def new_pairs(birth_a, death_a, birth_b, death_b, index_a, index_b, present):
    """The pairs (index_a, index_b) not yet `present` (bool, shape (n, m)), each once, in order of first
    appearance, with their L∞ distance; marks them present. Returns (index_a, index_b, distance).
    """
    keep = np.zeros(index_a.size, np.bool_)
    count = 0
    for k in range(index_a.size):
        if not present[index_a[k], index_b[k]]:
            present[index_a[k], index_b[k]] = True
            keep[k] = True
            count += 1
    new_a = np.empty(count, np.int64)
    new_b = np.empty(count, np.int64)
    distance = np.empty(count)
    count = 0
    for k in range(index_a.size):
        if keep[k]:
            i, j = index_a[k], index_b[k]
            new_a[count], new_b[count] = i, j
            distance[count] = max(abs(birth_a[i] - birth_b[j]), abs(death_a[i] - death_b[j]))
            count += 1
    return new_a, new_b, distance


@numba.njit(**NJIT)
def nearest_useful_pairs(birth_a, death_a, birth_b, death_b, q, n_nearest):
    """For every point of A its `n_nearest` closest useful partners in B, and vice versa (L∞).

    The sparse start of the Wasserstein solve; pairs missing from it are added back if the optimality
    check (`dual_violations`) finds they matter. Returns (index_a, index_b), possibly with repeats.
    """
    partners_of_a = _nearest_useful(birth_a, death_a, birth_b, death_b, q, n_nearest)
    partners_of_b = _nearest_useful(birth_b, death_b, birth_a, death_a, q, n_nearest)
    return _flatten_pairs(partners_of_a, partners_of_b)


@numba.njit(**NJIT)
def _nearest_useful(birth_from, death_from, birth_to, death_to, q, n_nearest):
    """(len(from), n_nearest) table of the closest useful partners in `to` (−1 where fewer exist).

    The L∞ distance is at least the birth difference, so with `to` sorted by birth the search walks
    outwards from each point's birth and stops once the birth gap exceeds the current k-th distance.
    """
    order = np.argsort(birth_to)
    sorted_birth = birth_to[order]
    delta_to = 0.5 * (birth_to - death_to)
    best = np.full((birth_from.size, n_nearest), -1, np.int64)
    cost = np.full((birth_from.size, n_nearest), np.inf)
    for i in range(birth_from.size):
        delta_i = 0.5 * (birth_from[i] - death_from[i])
        middle = np.searchsorted(sorted_birth, birth_from[i])
        low, high = middle - 1, middle
        while low >= 0 or high < sorted_birth.size:
            gap_low = birth_from[i] - sorted_birth[low] if low >= 0 else np.inf
            gap_high = sorted_birth[high] - birth_from[i] if high < sorted_birth.size else np.inf
            if min(gap_low, gap_high) >= cost[i, n_nearest - 1]:
                break
            if gap_low <= gap_high:
                k = order[low]
                low -= 1
            else:
                k = order[high]
                high += 1
            c = max(abs(birth_from[i] - birth_to[k]), abs(death_from[i] - death_to[k]))
            if c < cost[i, n_nearest - 1] and _useful(c, delta_i, delta_to[k], q, False):
                _keep_smallest(cost[i], best[i], c, k)
    return best


@numba.njit(**NJIT)
def _keep_smallest(costs, items, cost, item):
    """Insert (cost, item) into the ascending buffer `costs`/`items` if it is among the smallest."""
    last = costs.size - 1
    if cost >= costs[last]:
        return
    position = last
    while position > 0 and costs[position - 1] > cost:
        costs[position] = costs[position - 1]
        items[position] = items[position - 1]
        position -= 1
    costs[position] = cost
    items[position] = item


@numba.njit(**NJIT)
def dual_violations(birth_a, death_a, birth_b, death_b, q, potential, tolerance, n_worst):
    """Useful pairs whose arcs, absent from the sparse transport graph, would lower its cost.

    The flow of `diagram_transport` is optimal for the complete problem iff every possible arc has reduced
    cost c^q + π(a_i) − π(b_j) ≥ 0 (π from `diagram_transport`; B point j is node n + 1 + j). Only useful
    pairs (`_useful`) need checking: the others are never part of an optimal matching. For every point of
    A and of B, its `n_worst` most violating pairs (by more than `tolerance`) are returned as
    (index_a, index_b), possibly with repeats; empty when the flow is optimal.
    """
    n, m = birth_a.size, birth_b.size
    worst_b = np.full((n, n_worst), -1, np.int64)
    slack_b = np.full((n, n_worst), -tolerance)
    worst_a = np.full((m, n_worst), -1, np.int64)
    slack_a = np.full((m, n_worst), -tolerance)
    for i in range(n):
        delta_a = 0.5 * (birth_a[i] - death_a[i])
        for j in range(m):
            distance = max(abs(birth_a[i] - birth_b[j]), abs(death_a[i] - death_b[j]))
            slack = _power(distance, q) + potential[i] - potential[n + 1 + j]
            if slack < slack_b[i, n_worst - 1] or slack < slack_a[j, n_worst - 1]:
                if _useful(distance, delta_a, 0.5 * (birth_b[j] - death_b[j]), q, False):
                    _keep_smallest(slack_b[i], worst_b[i], slack, j)
                    _keep_smallest(slack_a[j], worst_a[j], slack, i)
    return _flatten_pairs(worst_b, worst_a)


@numba.njit(**NJIT)
def _flatten_pairs(partners_of_a, partners_of_b):
    """(index_a, index_b) of the filled entries (≥ 0) of per-point partner tables (n, k) and (m, k)."""
    count = 0
    for i in range(partners_of_a.shape[0]):
        for t in range(partners_of_a.shape[1]):
            count += partners_of_a[i, t] >= 0
    for j in range(partners_of_b.shape[0]):
        for t in range(partners_of_b.shape[1]):
            count += partners_of_b[j, t] >= 0
    index_a = np.empty(count, np.int64)
    index_b = np.empty(count, np.int64)
    count = 0
    for i in range(partners_of_a.shape[0]):
        for t in range(partners_of_a.shape[1]):
            if partners_of_a[i, t] >= 0:
                index_a[count] = i
                index_b[count] = partners_of_a[i, t]
                count += 1
    for j in range(partners_of_b.shape[0]):
        for t in range(partners_of_b.shape[1]):
            if partners_of_b[j, t] >= 0:
                index_a[count] = partners_of_b[j, t]
                index_b[count] = j
                count += 1
    return index_a, index_b


@numba.njit(**NJIT)
def _heap_push(keys, values, size, key, value):
    position = size
    keys[position] = key
    values[position] = value
    while position > 0:
        parent = (position - 1) // 2
        if keys[parent] <= keys[position]:
            break
        keys[parent], keys[position] = keys[position], keys[parent]
        values[parent], values[position] = values[position], values[parent]
        position = parent
    return size + 1


@numba.njit(**NJIT)
def _heap_pop(keys, values, size):
    """Remove the smallest item; returns (key, value, new size)."""
    key, value = keys[0], values[0]
    size -= 1
    keys[0], values[0] = keys[size], values[size]
    position = 0
    while True:
        left = 2 * position + 1
        if left >= size:
            break
        child = left
        if left + 1 < size and keys[left + 1] < keys[left]:
            child = left + 1
        if keys[position] <= keys[child]:
            break
        keys[child], keys[position] = keys[position], keys[child]
        values[child], values[position] = values[position], values[child]
        position = child
    return key, value, size


@numba.njit(**NJIT)
def _transport_graph(n, m, pair_a, pair_b, pair_cost, diagonal_cost_a, diagonal_cost_b):
    """Residual graph of the diagram transport problem (see `diagram_transport`), zero flow.

    Returns start (n_nodes + 1,) CSR offsets; arc_to, arc_room (int64), arc_cost, arc_twin (paired reverse
    arc) of shape (2 F,); forward_arc (F,) — residual index of each forward arc, in the order pairs,
    A → diagonal sink, diagonal source → B, diagonal source → sink; balance (n_nodes,) — supply (+) or
    demand (−) of each node.
    """
    source, sink = n, n + m + 1
    n_nodes = n + m + 2
    n_pairs = pair_a.size
    n_forward = n_pairs + n + m + 1
    tail = np.empty(n_forward, np.int64)
    head = np.empty(n_forward, np.int64)
    capacity = np.ones(n_forward, np.int64)
    cost = np.empty(n_forward)
    for k in range(n_pairs):
        tail[k], head[k], cost[k] = pair_a[k], n + 1 + pair_b[k], pair_cost[k]
    for i in range(n):
        tail[n_pairs + i], head[n_pairs + i], cost[n_pairs + i] = i, sink, diagonal_cost_a[i]
    for j in range(m):
        k = n_pairs + n + j
        tail[k], head[k], cost[k] = source, n + 1 + j, diagonal_cost_b[j]
    last = n_forward - 1
    tail[last], head[last], cost[last], capacity[last] = source, sink, 0.0, m
    degree = np.zeros(n_nodes + 1, np.int64)
    for k in range(n_forward):
        degree[tail[k] + 1] += 1
        degree[head[k] + 1] += 1
    start = np.cumsum(degree)
    fill = start[:-1].copy()
    arc_to = np.empty(2 * n_forward, np.int64)
    arc_room = np.empty(2 * n_forward, np.int64)
    arc_cost = np.empty(2 * n_forward)
    arc_twin = np.empty(2 * n_forward, np.int64)
    forward_arc = np.empty(n_forward, np.int64)
    for k in range(n_forward):
        a, b = fill[tail[k]], fill[head[k]]
        fill[tail[k]] += 1
        fill[head[k]] += 1
        arc_to[a], arc_room[a], arc_cost[a], arc_twin[a] = head[k], capacity[k], cost[k], b
        arc_to[b], arc_room[b], arc_cost[b], arc_twin[b] = tail[k], 0, -cost[k], a
        forward_arc[k] = a
    balance = np.zeros(n_nodes, np.int64)
    balance[:n] = 1
    balance[source] = m
    balance[n + 1:n + 1 + m] = -1
    balance[sink] = -n
    return start, arc_to, arc_room, arc_cost, arc_twin, forward_arc, balance


@numba.njit(**NJIT)
def _send(a, amount, arc_to, arc_room, arc_twin, excess):
    """Move `amount` units along residual arc a (negative: back along it), keeping excesses balanced."""
    arc_room[a] -= amount
    arc_room[arc_twin[a]] += amount
    excess[arc_to[arc_twin[a]]] -= amount
    excess[arc_to[a]] += amount


@numba.njit(**NJIT)
def _shortest_path_finish(start, arc_to, arc_room, arc_cost, arc_twin, excess, price):
    """Route all excess to the deficits by shortest paths, many per Dijkstra run, starting from any prices.

    First the arcs with negative reduced cost c + p(u) − p(v) are saturated (afterwards every arc with room
    has reduced cost ≥ 0). Then phases until no excess is left: one Dijkstra on reduced costs from all
    nodes with excess at once, stopped when the deficits reached could absorb all the excess (or nothing is
    left to reach); with D the last distance taken, prices += min(distance, D) − D, which keeps every
    reduced cost ≥ 0 and makes each arc of the shortest-path forest tight; then augmentation along the
    forest path of every reached deficit, nearest first, while its arcs still have room and its root excess
    (a tight path stays tight after other augmentations: their reverse arcs are tight too). Each phase
    augments at least once. Returns False if some excess cannot be routed.
    """
    inf = math.inf
    n_nodes = price.size
    for v in range(n_nodes):
        for a in range(start[v], start[v + 1]):
            if arc_room[a] > 0 and arc_cost[a] + price[v] - price[arc_to[a]] < 0:
                _send(a, arc_room[a], arc_to, arc_room, arc_twin, excess)
    distance = np.full(n_nodes, inf)
    done = np.zeros(n_nodes, np.bool_)
    parent = np.full(n_nodes, -1, np.int64)
    touched = np.empty(n_nodes, np.int64)  # nodes with a finite distance, in the order first reached
    taken = np.empty(n_nodes, np.int64)  # nodes taken from the heap (final distance), in increasing distance
    heap_keys = np.empty(arc_to.size + n_nodes + 1)
    heap_values = np.empty(arc_to.size + n_nodes + 1, np.int64)
    while True:
        heap_size, n_touched, supply = 0, 0, 0
        for v in range(n_nodes):
            if excess[v] > 0:
                distance[v] = 0.0
                touched[n_touched] = v
                n_touched += 1
                heap_size = _heap_push(heap_keys, heap_values, heap_size, 0.0, v)
                supply += excess[v]
        if supply == 0:
            return True
        n_taken, demand, reach = 0, 0, 0.0
        while heap_size > 0 and demand < supply:
            key, v, heap_size = _heap_pop(heap_keys, heap_values, heap_size)
            if done[v] or key > distance[v]:
                continue
            done[v] = True
            taken[n_taken] = v
            n_taken += 1
            reach = key
            if excess[v] < 0:
                demand -= excess[v]
            for a in range(start[v], start[v + 1]):
                w = arc_to[a]
                if arc_room[a] == 0 or done[w]:  # done: final; rounding must not rewire it into a cycle
                    continue
                candidate = key + arc_cost[a] + price[v] - price[w]
                if candidate < distance[w]:
                    if distance[w] == inf:
                        touched[n_touched] = w
                        n_touched += 1
                    distance[w] = candidate
                    parent[w] = a
                    heap_size = _heap_push(heap_keys, heap_values, heap_size, candidate, w)
        if demand == 0:
            return False
        for t in range(n_touched):  # untouched nodes would all get + reach − reach: skip them
            v = touched[t]
            price[v] += min(distance[v], reach) - reach
        for t in range(n_taken):
            target = taken[t]
            if excess[target] >= 0:
                continue
            amount = -excess[target]
            v = target
            while parent[v] != -1:
                amount = min(amount, arc_room[parent[v]])
                v = arc_to[arc_twin[parent[v]]]
            amount = min(amount, excess[v])  # v: the root, a node that had excess
            if amount <= 0:
                continue
            v = target
            while parent[v] != -1:  # intermediate nodes gain and lose the same amount
                a = parent[v]
                _send(a, amount, arc_to, arc_room, arc_twin, excess)
                v = arc_to[arc_twin[a]]
        for t in range(n_touched):
            v = touched[t]
            distance[v] = inf
            done[v] = False
            parent[v] = -1


@numba.njit(**NJIT)
def _augmenting_row_reduction(n, start, arc_to, arc_room, arc_cost, arc_twin, excess, price, max_steps):
    """Jonker–Volgenant augmenting row reduction for the A points (nodes 0..n−1), an auction with zero bid
    increment: a free point takes its cheapest arc (reduced by the target's price) and lowers that target's
    price until it is indifferent to its second choice; the point that held the target becomes free. The
    diagonal sink is a target with room for every point and a fixed price. Prices of B points only drop,
    so every reduced cost stays ≥ 0 and every used arc tight; the points still free after `max_steps`
    are left to the shortest-path finish.
    """
    sink = price.size - 1
    owner = np.full(price.size, -1, np.int64)  # A point holding a B point
    used_arc = np.full(n, -1, np.int64)
    queue = np.empty(max_steps + n + 1, np.int64)
    head, tail = 0, 0
    for i in range(n):
        if excess[i] > 0:
            queue[tail] = i
            tail += 1
    steps = 0
    while head < tail and steps < max_steps:
        i = queue[head]
        head += 1
        steps += 1
        best, second = math.inf, math.inf
        best_arc, second_arc = -1, -1
        for a in range(start[i], start[i + 1]):
            if arc_room[a] == 0:  # only arcs out of a free point exist here, all with room; be safe
                continue
            value = arc_cost[a] - price[arc_to[a]]
            if value < best or (value == best and owner[arc_to[a]] == -1 and owner[arc_to[best_arc]] != -1):
                second, second_arc = best, best_arc
                best, best_arc = value, a
            elif value < second:
                second, second_arc = value, a
        target = arc_to[best_arc]
        if target != sink and owner[target] != -1 and best == second and second_arc != -1 \
                and (arc_to[second_arc] == sink or owner[arc_to[second_arc]] == -1):
            best_arc, target = second_arc, arc_to[second_arc]  # a tie with a free target: no eviction
        elif target != sink and second > best:
            price[target] -= second - best  # now indifferent between the two: reduced cost 0 on both
        # row dual u_i = −price: its reduced costs are value − u_i ≥ 0, and 0 on the arc it takes
        price[i] = -second if target != sink else -best
        if target != sink and owner[target] != -1:  # evict the holder: it is free again
            holder = owner[target]
            _send(used_arc[holder], -1, arc_to, arc_room, arc_twin, excess)
            used_arc[holder] = -1
            queue[tail] = holder
            tail += 1
        _send(best_arc, 1, arc_to, arc_room, arc_twin, excess)
        used_arc[i] = best_arc
        if target != sink:
            owner[target] = i


@numba.njit(**NJIT)
def diagram_transport(n, m, pair_a, pair_b, pair_cost, diagonal_cost_a, diagonal_cost_b, initial_flow,
                      initial_price):
    """Exact minimum-cost matching of two diagrams as a transportation problem (successive shortest paths).

    Nodes: the n points of A (supply 1 each) and a diagonal source (supply m: the diagonal copies of B's
    points); the m points of B (demand 1 each) and a diagonal sink (demand n). Arcs: A point → B point for
    the given pairs (cost `pair_cost`), A point → diagonal sink (its diagonal cost), diagonal source → B
    point (its diagonal cost), diagonal source → diagonal sink (cost 0). Collapsing all diagonal copies into
    two nodes is exact — they are interchangeable — and keeps the graph sparse.

    Cold start (empty `initial_flow`), as Jonker–Volgenant do: column reduction (p(b) = cheapest arc into
    b), augmenting row reduction (`_augmenting_row_reduction`) that places most A points cheaply, the
    diagonal source → sink arc filled. Warm start: `initial_flow` and `initial_price` are the optimum of
    the same problem with only the first P₀ pairs (flow in the order below, length P₀ + n + m + 1); pairs
    added since may have negative reduced cost and are repaired — worth it when few were added. Either way
    `_shortest_path_finish` then routes what is left exactly. Costs must be ≥ 0.

    Returns
    -------
    flow : int64, shape (P + n + m + 1,) — flow on the arcs in the order: pairs, A → sink, source → B,
        source → sink; all −1 if the problem were infeasible (it never is).
    potential : float64, shape (n + m + 2,) — node prices: A points (0..n−1), diagonal source (n), B points
        (n+1..n+m), diagonal sink (n+m+1); every arc with room has c + π(u) − π(v) ≥ 0 (optimality).
    """
    start, arc_to, arc_room, arc_cost, arc_twin, forward_arc, excess = _transport_graph(
        n, m, pair_a, pair_b, pair_cost, diagonal_cost_a, diagonal_cost_b)
    n_forward = forward_arc.size
    source, sink = n, n + m + 1
    if initial_flow.size > 0:
        price = initial_price.copy()
        old_pairs = initial_flow.size - (n + m + 1)
        added = pair_a.size - old_pairs
        for k in range(initial_flow.size):
            if initial_flow[k] != 0:
                _send(forward_arc[k if k < old_pairs else k + added], initial_flow[k], arc_to, arc_room,
                      arc_twin, excess)
    else:
        price = np.zeros(n + m + 2)
        # column reduction: p(b) = cheapest arc into b (every reduced cost ≥ 0 with p = 0 elsewhere)
        for j in range(m):
            price[n + 1 + j] = diagonal_cost_b[j]
        for k in range(pair_a.size):
            price[n + 1 + pair_b[k]] = min(price[n + 1 + pair_b[k]], pair_cost[k])
        _augmenting_row_reduction(n, start, arc_to, arc_room, arc_cost, arc_twin, excess, price, 4 * (n + m))
        bulk = min(excess[source], -excess[sink])  # diagonal ↔ diagonal, tight (cost 0, both prices 0)
        _send(forward_arc[n_forward - 1], bulk, arc_to, arc_room, arc_twin, excess)
    if not _shortest_path_finish(start, arc_to, arc_room, arc_cost, arc_twin, excess, price):
        return np.full(n_forward, -1, np.int64), price
    flow = np.empty(n_forward, np.int64)
    for k in range(n_forward):
        flow[k] = arc_room[arc_twin[forward_arc[k]]]
    return flow, price


@numba.njit(**NJIT)
def has_perfect_matching(row_start, column, weight, n, threshold, edge_of_row, row_of_col):
    """Whether the bipartite graph restricted to edges with weight ≤ threshold has a perfect matching.

    Hopcroft–Karp: breadth-first layers from the free rows, then vertex-disjoint shortest augmenting paths
    by an explicit-stack depth-first search; O(E √V). Warm start: `edge_of_row` (edge index of each row's
    match, −1 if free) and `row_of_col` hold a matching from an earlier call; edges heavier than
    `threshold` are dropped from it, and the arrays return a maximum matching of this threshold graph.
    """
    unmatched = -1
    far = n + 1
    matched = 0
    for row in range(n):
        k = edge_of_row[row]
        if k == unmatched:
            continue
        if weight[k] > threshold:
            row_of_col[column[k]] = unmatched
            edge_of_row[row] = unmatched
        else:
            matched += 1
    for row in range(n):  # greedy completion
        if edge_of_row[row] != unmatched:
            continue
        for k in range(row_start[row], row_start[row + 1]):
            if weight[k] <= threshold and row_of_col[column[k]] == unmatched:
                edge_of_row[row] = k
                row_of_col[column[k]] = row
                matched += 1
                break
    layer = np.empty(n, np.int64)
    queue = np.empty(n, np.int64)
    next_edge = np.empty(n, np.int64)
    stack = np.empty(n + 1, np.int64)
    via = np.empty(n + 1, np.int64)  # edge taken from stack[level] towards stack[level + 1]
    while matched < n:
        head, tail = 0, 0
        for row in range(n):
            if edge_of_row[row] == unmatched:
                layer[row] = 0
                queue[tail] = row
                tail += 1
            else:
                layer[row] = far
        found = False
        while head < tail:
            row = queue[head]
            head += 1
            for k in range(row_start[row], row_start[row + 1]):
                if weight[k] > threshold:
                    continue
                partner = row_of_col[column[k]]
                if partner == unmatched:
                    found = True
                elif layer[partner] == far:
                    layer[partner] = layer[row] + 1
                    queue[tail] = partner
                    tail += 1
        if not found:
            return False
        for row in range(n):
            next_edge[row] = row_start[row]
        for root in range(n):
            if edge_of_row[root] != unmatched:
                continue
            depth = 0
            stack[0] = root
            while depth >= 0:
                row = stack[depth]
                advanced = False
                while next_edge[row] < row_start[row + 1]:
                    k = next_edge[row]
                    next_edge[row] += 1
                    if weight[k] > threshold:
                        continue
                    partner = row_of_col[column[k]]
                    if partner == unmatched:
                        # augment: stack[depth] takes k, each earlier row takes the edge it went through
                        edge_of_row[row] = k
                        row_of_col[column[k]] = row
                        for level in range(depth - 1, -1, -1):
                            edge_of_row[stack[level]] = via[level]
                            row_of_col[column[via[level]]] = stack[level]
                        matched += 1
                        depth = -1
                        advanced = True
                        break
                    if layer[partner] == layer[row] + 1:
                        via[depth] = k
                        depth += 1
                        stack[depth] = partner
                        advanced = True
                        break
                if not advanced:
                    layer[row] = far  # dead end for this phase
                    depth -= 1
    return True
