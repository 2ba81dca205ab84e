"""Bottleneck and Wasserstein distances between persistence diagrams, L∞ ground metric (P2 §III D).

A matching γ pairs each point of one diagram with a point of the other or with the diagonal;
d_B = min_γ max ‖p − γ(p)‖_∞ and d_Wq = min_γ (Σ ‖p − γ(p)‖_∞^q)^(1/q). A point's L∞ distance to the
diagonal is (birth − death)/2. Always d_B ≤ d_W2 ≤ d_W1.

Never-dying classes (death −inf) cannot be matched as they are; the ``essential`` convention decides:
``"minus_one"`` (default) gives them death −1 as P2 §III B does (Fig. 5: PD0(f) = {(5, −1)}), ``"zero"``
gives death 0, ``"drop"`` leaves them out, ``"apart"`` matches them only with each other (the usual treatment of
essential classes: the finite points are matched as with ``"drop"``, the never-dying ones of the two diagrams pair
off by birth, in order, each pair costing |b − b'|; diagrams with different numbers of never-dying classes are an
infinite distance apart). Zero-length points (birth == death) are removed: they lie on the diagonal and cost
nothing.

Backends
--------
``"exact"`` (default): float64, exact optimum, always terminates (no iteration count depends on
tolerances). Only pairs that can beat the diagonal are ever matched (`_matching._useful`).
Wasserstein: a transportation problem with the diagonal collapsed into one source and one sink node
(`_matching.diagram_transport`: Jonker–Volgenant start, then shortest augmenting paths, many per Dijkstra
run), solved on a sparse graph — each point's `N_NEAREST` nearest useful partners, plus, where many points
share one death line (2D PD1: the never-dying loops at −1), a band around the optimal matching of that
line alone (`_matching.line_matching`, exact by dynamic programming: it never crosses) — and re-solved with
the pairs its optimal prices say are missing until they certify optimality on every useful pair.
Bottleneck: one perfect-matching test just below the largest distance of the W1/W2 matchings (often the
answer), else binary search over the candidate distances below it, each step a warm-started Hopcroft–Karp
test on the threshold graph (`_matching.threshold_graph`; diagonal copies kept on transposed pairs:
a_i ↔ b_j leaves exactly their two copies to pair). On the 2D benchmark (`bench/analysis.py`, PD0 and PD1,
all three distances) it takes ~140 ms (median; the version before the line band and multi-path phases took
~600 ms on the same machine); PD1's W2 solve (~50 ms) and bottleneck graph (~40 ms) are the largest parts.

``"dionysus"``: dionysus' `bottleneck_distance(delta=0)` and hera's `wasserstein_distance(internal_p=-1)`
(L∞) on NEGATED diagrams (libraries expect birth < death). hera can hang on some inputs, so it runs in a
child process killed after ``timeout_s``; on timeout or failure the exact backend answers (with a warning).
"""
from __future__ import annotations

import io
import json
import subprocess
import sys
import warnings
from typing import Sequence

import numpy as np

from forcenet.topology import _matching
from forcenet.topology.persistence import PersistenceDiagrams

ESSENTIAL_CONVENTIONS = ("minus_one", "zero", "drop", "apart")
METRICS = ("bottleneck", "wasserstein_1", "wasserstein_2")
BACKENDS = ("exact", "dionysus")


def matchable_points(diagram, homology_dim: int | None = None, essential: str = "minus_one") -> np.ndarray:
    """Finite, non-degenerate (birth, death) points ready for matching.

    Parameters
    ----------
    diagram : PersistenceDiagrams, or array-like of shape (n, 2) with death −inf for never-dying classes.
    homology_dim : which diagram, when `diagram` is a PersistenceDiagrams.
    essential : "minus_one", "zero", "drop" or "apart" (module docstring; "apart" leaves the never-dying classes
        out here, as "drop": `essential_births` gives them).

    Returns
    -------
    ndarray, shape (k, 2), float64, birth > death.
    """
    if essential not in ESSENTIAL_CONVENTIONS:
        raise ValueError(f"essential must be one of {ESSENTIAL_CONVENTIONS}, got {essential!r}")
    if isinstance(diagram, PersistenceDiagrams):
        if homology_dim is None:
            raise ValueError("homology_dim is required for a PersistenceDiagrams")
        one = diagram.select(homology_dim)
        points = np.stack([np.asarray(one.birth, np.float64), np.asarray(one.death, np.float64)], axis=1)
        never_dies = one.essential
    else:
        points = np.asarray(diagram, dtype=np.float64).reshape(-1, 2).copy()
        never_dies = ~np.isfinite(points[:, 1])
    if essential in ("drop", "apart"):
        points = points[~never_dies]
    else:
        points[never_dies, 1] = -1.0 if essential == "minus_one" else 0.0
    if not np.all(np.isfinite(points)):
        raise ValueError("births must be finite")
    return points[points[:, 0] > points[:, 1]].reshape(-1, 2)


def essential_births(diagram, homology_dim: int | None = None) -> np.ndarray:
    """The births of the never-dying classes of a diagram (PersistenceDiagrams or (n, 2) array with death −inf),
    sorted."""
    if isinstance(diagram, PersistenceDiagrams):
        if homology_dim is None:
            raise ValueError("homology_dim is required for a PersistenceDiagrams")
        one = diagram.select(homology_dim)
        return np.sort(np.asarray(one.birth, np.float64)[np.asarray(one.essential, bool)])
    points = np.asarray(diagram, dtype=np.float64).reshape(-1, 2)
    return np.sort(points[~np.isfinite(points[:, 1]), 0])


def _with_essential_matched(distances: dict[str, float], births_a: np.ndarray, births_b: np.ndarray
                            ) -> dict[str, float]:
    """The distances of the finite points combined with the never-dying classes matched only with each other
    (convention "apart"): births paired in sorted order (optimal for points on one line), each pair costing
    |b − b'| in L∞; infinite when the diagrams hold different numbers of never-dying classes."""
    if births_a.size != births_b.size:
        return {metric: float("inf") for metric in METRICS}
    gaps = np.abs(births_a - births_b)
    largest = float(gaps.max()) if gaps.size else 0.0
    return {"bottleneck": max(distances["bottleneck"], largest),
            "wasserstein_1": distances["wasserstein_1"] + float(gaps.sum()),
            "wasserstein_2": float(np.sqrt(distances["wasserstein_2"] ** 2 + float(np.sum(gaps ** 2))))}


N_NEAREST = 16  # partners per point in the first sparse Wasserstein graph (with the line band: one solve)
N_WORST = 32  # most violating pairs per point added after each optimality check
WARM_START_FRACTION = 0.05  # re-solve from the last optimum when fewer pairs than this fraction are added
LINE_BAND = 3  # B partners on each side of an A point's place in the optimal matching along a shared line
MAX_LINE_CELLS = 16_000_000  # largest line for `_matching.line_matching` (its n m bytes)


def _line_pairs(points_a: np.ndarray, points_b: np.ndarray, q: float) -> tuple[np.ndarray, np.ndarray]:
    """Pairs near the optimal matching of the points on the death line both diagrams share most.

    Many points on one death line (2D PD1: hundreds of never-dying loops at death −1) make a degenerate,
    one-dimensional block that nearest-partner lists cover badly: its optimal matching shifts long chains
    of points by a few places. `_matching.line_matching` solves the block alone; its matching, widened by
    `LINE_BAND` places on each side, joins the first sparse graph. Only a hint: optimality is still
    certified on every pair (`_optimal_matching`). Returns (index_a, index_b), possibly empty.
    """
    none = np.empty(0, np.int64), np.empty(0, np.int64)
    deaths, counts = np.unique(points_a[:, 1], return_counts=True)
    shared = np.isin(deaths, points_b[:, 1])
    if not shared.any():
        return none
    death = deaths[shared][np.argmax(counts[shared])]
    on_a, on_b = np.flatnonzero(points_a[:, 1] == death), np.flatnonzero(points_b[:, 1] == death)
    if min(on_a.size, on_b.size) < 2 or on_a.size * on_b.size > MAX_LINE_CELLS:
        return none
    on_a = on_a[np.argsort(points_a[on_a, 0], kind="stable")]
    on_b = on_b[np.argsort(points_b[on_b, 0], kind="stable")]
    birth_a, birth_b = np.ascontiguousarray(points_a[on_a, 0]), np.ascontiguousarray(points_b[on_b, 0])
    partner = _matching.line_matching(birth_a, birth_b, float(death), float(q))
    place = np.where(partner >= 0, partner, np.searchsorted(birth_b, birth_a))
    band = np.clip(place[:, None] + np.arange(-LINE_BAND, LINE_BAND + 1), 0, on_b.size - 1)
    return np.repeat(on_a, band.shape[1]), on_b[band.ravel()]


def _optimal_matching(points_a: np.ndarray, points_b: np.ndarray, q: float) -> tuple[float, float]:
    """Exact degree-q Wasserstein matching: (Σ cost^q, largest L∞ distance in the matching).

    Sparsify and verify: solve the transport problem (`_matching.diagram_transport`) on each point's
    `N_NEAREST` closest useful partners and the shared death line's band (`_line_pairs`), then check its
    optimal potentials against every useful pair
    (`_matching.dual_violations`); add the most violating pairs and solve again until none is left. The flow
    is then optimal for the complete problem (LP duality: a feasible flow and potentials with all reduced
    costs ≥ 0 that are tight on the flow).
    """
    n, m = len(points_a), len(points_b)
    birth_a, death_a = np.ascontiguousarray(points_a[:, 0]), np.ascontiguousarray(points_a[:, 1])
    birth_b, death_b = np.ascontiguousarray(points_b[:, 0]), np.ascontiguousarray(points_b[:, 1])
    delta_a, delta_b = 0.5 * (birth_a - death_a), 0.5 * (birth_b - death_b)
    present = np.zeros((n, m), bool)  # pairs in the sparse graph
    first_a, first_b = _matching.nearest_useful_pairs(birth_a, death_a, birth_b, death_b, float(q), N_NEAREST)
    line_a, line_b = _line_pairs(points_a, points_b, q)
    index_a, index_b, distance = _matching.new_pairs(birth_a, death_a, birth_b, death_b,
                                                    np.concatenate([line_a, first_a]),
                                                    np.concatenate([line_b, first_b]), present)
    scale = max(float(np.abs(points_a).max(initial=0.0)), float(np.abs(points_b).max(initial=0.0)), 1.0) ** q
    flow, potential = np.empty(0, np.int64), np.empty(0)
    while True:
        flow, potential = _matching.diagram_transport(n, m, index_a, index_b, distance ** q, delta_a ** q,
                                                     delta_b ** q, flow, potential)
        if flow.size and flow[0] < 0:  # cannot happen: everything can go to the diagonal
            raise RuntimeError("the diagram transport problem has no feasible flow")
        # pairs already in the graph are settled (a used arc may have negative reduced cost: it is full)
        missing_a, missing_b, missing_distance = _matching.new_pairs(
            birth_a, death_a, birth_b, death_b,
            *_matching.dual_violations(birth_a, death_a, birth_b, death_b, float(q), potential, 1e-12 * scale,
                                      N_WORST), present)
        if missing_a.size == 0:
            break
        # few new pairs: repair the last optimum (pairs keep their order, new ones appended); many: restart
        # cold, which measured faster than repairing thousands of arcs
        if missing_a.size > WARM_START_FRACTION * index_a.size:
            flow, potential = np.empty(0, np.int64), np.empty(0)
        index_a, index_b = np.concatenate([index_a, missing_a]), np.concatenate([index_b, missing_b])
        distance = np.concatenate([distance, missing_distance])
    # arcs in `diagram_transport` order: pairs, A → diagonal, diagonal → B, diagonal → diagonal (cost 0)
    arc_distance = np.concatenate([distance, delta_a, delta_b, [0.0]])
    used = flow > 0
    return (float(np.sum(flow[used] * arc_distance[used] ** q)),
            float(np.max(arc_distance[used], initial=0.0)))


def wasserstein_distance(points_a, points_b, q: float = 1.0) -> float:
    """Exact degree-q Wasserstein distance, L∞ ground metric, between finite super-level diagrams.

    Parameters
    ----------
    points_a, points_b : arrays, shape (n, 2), (m, 2) — (birth, death), birth ≥ death, finite [⟨F⟩].
    q : degree ≥ 1.
    """
    points_a, points_b = _finite(points_a), _finite(points_b)
    if q < 1:
        raise ValueError("q must be ≥ 1")
    if len(points_a) + len(points_b) == 0:
        return 0.0
    total, _ = _optimal_matching(points_a, points_b, q)
    return float(total ** (1.0 / q))


def bottleneck_distance(points_a, points_b, *, upper_bound: float | None = None) -> float:
    """Exact bottleneck distance, L∞ ground metric, between finite super-level diagrams.

    The answer is one of the edge weights of `_matching.threshold_graph`: first a test just below an upper
    bound (the largest distance of any perfect matching — by default the degree-2 Wasserstein one; often
    the answer), then binary search over the weights between a lower bound (every row and column needs an
    edge) and it, each step a warm-started Hopcroft–Karp perfect-matching test.
    Only pairs closer than the farther of their two diagonal distances can matter (`_matching._useful`).

    Parameters
    ----------
    points_a, points_b : arrays, shape (n, 2), (m, 2) — finite (birth, death), birth ≥ death [⟨F⟩].
    upper_bound : the largest L∞ distance of some perfect matching, if already known.
    """
    points_a, points_b = _finite(points_a), _finite(points_b)
    size = len(points_a) + len(points_b)
    if size == 0:
        return 0.0
    if upper_bound is None:
        _, upper_bound = _optimal_matching(points_a, points_b, 2.0)
    upper_bound = float(upper_bound)
    row_start, column, weight, lower = _matching.threshold_graph(
        points_a[:, 0].copy(), points_a[:, 1].copy(), points_b[:, 0].copy(), points_b[:, 1].copy(), upper_bound)
    edge_of_row = np.full(size, -1, dtype=np.int64)  # matching carried between the steps (warm start)
    row_of_col = np.full(size, -1, dtype=np.int64)
    # the bound itself is often the answer: try the next lighter weight first
    below = weight[weight < upper_bound]
    if below.size == 0 or below.max() < lower or not _matching.has_perfect_matching(
            row_start, column, weight, size, below.max(), edge_of_row, row_of_col):
        return upper_bound
    values = np.unique(below[below >= lower])  # values[-1] is feasible
    low, high = 0, values.size - 1
    while low < high:
        middle = (low + high) // 2
        if _matching.has_perfect_matching(row_start, column, weight, size, values[middle], edge_of_row, row_of_col):
            high = middle
        else:
            low = middle + 1
    return float(values[low])


def _finite(points) -> np.ndarray:
    points = np.asarray(points, dtype=np.float64).reshape(-1, 2)
    if not np.all(np.isfinite(points)):
        raise ValueError("points must be finite; apply an essential convention first (matchable_points)")
    return points[points[:, 0] > points[:, 1]]


def diagram_distances(pd_a, pd_b, homology_dim: int = 0, essential: str = "minus_one", *,
                      backend: str = "exact", timeout_s: float = 60.0, hera_delta: float = 1e-3
                      ) -> dict[str, float]:
    """d_B, d_W1, d_W2 between the PD_k of two networks (P2 §III D).

    Parameters
    ----------
    pd_a, pd_b : PersistenceDiagrams, or (n, 2) arrays of (birth, death) with death −inf for never-dying.
    homology_dim : k.
    essential : never-dying convention, "minus_one" (P2, default), "zero", "drop" or "apart" (module docstring).
    backend : "exact" (default) or "dionysus" (module docstring).
    timeout_s : wall-clock limit for the dionysus child process [s].
    hera_delta : relative error allowed to hera's Wasserstein (dionysus backend only).

    Returns
    -------
    dict {"bottleneck", "wasserstein_1", "wasserstein_2"} → float [⟨F⟩].
    """
    if backend not in BACKENDS:
        raise ValueError(f"backend must be one of {BACKENDS}, got {backend!r}")
    if essential == "apart":
        finite = diagram_distances(pd_a, pd_b, homology_dim, "drop", backend=backend, timeout_s=timeout_s,
                                   hera_delta=hera_delta)
        return _with_essential_matched(finite, essential_births(pd_a, homology_dim),
                                       essential_births(pd_b, homology_dim))
    points_a = matchable_points(pd_a, homology_dim, essential)
    points_b = matchable_points(pd_b, homology_dim, essential)
    if backend == "dionysus":
        result = dionysus_distances(points_a, points_b, timeout_s=timeout_s, hera_delta=hera_delta)
        if result is not None:
            return result
    if len(points_a) + len(points_b) == 0:
        return {metric: 0.0 for metric in METRICS}
    total_1, largest_1 = _optimal_matching(points_a, points_b, 1.0)
    total_2, largest_2 = _optimal_matching(points_a, points_b, 2.0)
    return {"bottleneck": bottleneck_distance(points_a, points_b, upper_bound=min(largest_1, largest_2)),
            "wasserstein_1": total_1, "wasserstein_2": float(np.sqrt(total_2))}


def dionysus_distances(points_a: np.ndarray, points_b: np.ndarray, *, timeout_s: float = 60.0,
                       hera_delta: float = 1e-3) -> dict[str, float] | None:
    """d_B (dionysus, delta=0) and d_W1, d_W2 (hera, L∞) in a child process; None on timeout or failure.

    Inputs are finite super-level points (birth > death); they are negated before dionysus sees them.
    """
    buffer = io.BytesIO()
    np.savez(buffer, a=-np.asarray(points_a, np.float64), b=-np.asarray(points_b, np.float64),
             hera_delta=np.float64(hera_delta))
    try:
        done = subprocess.run([sys.executable, "-m", "forcenet.topology._dionysus_worker"], input=buffer.getvalue(),
                              capture_output=True, timeout=timeout_s, check=True)
        return {name: float(value) for name, value in json.loads(done.stdout).items()}
    except subprocess.TimeoutExpired:
        warnings.warn(f"dionysus/hera distance exceeded {timeout_s} s; using the exact backend", RuntimeWarning,
                      stacklevel=3)
    except (subprocess.CalledProcessError, ValueError) as error:
        warnings.warn(f"dionysus distance failed ({error}); using the exact backend", RuntimeWarning, stacklevel=3)
    return None


def consecutive_diagram_distances(diagrams: Sequence, homology_dims: Sequence[int] = (0, 1),
                                  essential: str = "minus_one", **options) -> dict[str, np.ndarray]:
    """Distances between consecutive diagrams of a sequence (P2 §IV, Figs 6–10).

    `forcenet.report.p2_distances.consecutive_distances` labels these per force kind; the ratios d_B/d_Wq of P2
    Figs 7, 10 are `forcenet.report.p2.distance_ratio`.

    Parameters
    ----------
    diagrams : sequence of PersistenceDiagrams, length S (e.g. increasing ρ).
    homology_dims : k values.
    essential, options : passed to `diagram_distances`.

    Returns
    -------
    dict {"bottleneck", "wasserstein_1", "wasserstein_2"} of ndarrays, shape (S − 1, len(homology_dims)) [⟨F⟩].
    Row s compares diagrams s and s + 1.
    """
    n_pairs = max(len(diagrams) - 1, 0)
    result = {metric: np.zeros((n_pairs, len(homology_dims))) for metric in METRICS}
    for s in range(n_pairs):
        for column, k in enumerate(homology_dims):
            for metric, value in diagram_distances(diagrams[s], diagrams[s + 1], k, essential, **options).items():
                result[metric][s, column] = value
    return result
