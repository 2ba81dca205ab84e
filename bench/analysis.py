"""Benchmark (not a test): analysis cost of one snapshot and of one consecutive-pair distance.

Synthetic but realistic networks: particle centres on a jittered triangular (2D, N ≈ 2000) or FCC (3D,
N ≈ 4000) lattice, the contact network = near neighbours thinned at random to a mean degree ≈ 4 (2D) or ≈ 6
(3D), contact forces with lognormal magnitudes and random directions, wall contacts for particles next to the
box faces. Timed:

- snapshot_ms_{2d,3d}: `build_force_network` (from contact force vectors) + `persistence_diagrams` +
  `compute_snapshot_measures` (Betti curves, clusters/percolation/shape on 61 thresholds, PDF, Z, bins, TP);
- distances_ms_2d: `diagram_distances` for PD0 and PD1 (d_B, d_W1, d_W2 each) between the diagrams of the
  2D network and of a "next snapshot" (forces perturbed by 5 %, 2 % of contacts opened);
  distances_ms_2d_small_change: the same for a gentler step (1 %, 0.5 %), for context.

Medians over several runs after one warm-up run (numba compilation excluded). The last line printed is one
JSON object; the run's record goes to bench/results/analysis.json (bench/records.py; not with ``--no-record``).
Run: ``.venv/bin/python bench/analysis.py``.
"""
from __future__ import annotations

import argparse
import json
import time

import numpy as np

from forcenet.measures import compute_snapshot_measures
from forcenet.network import build_force_network
from forcenet.topology import diagram_distances, persistence_diagrams

import records  # bench/records.py

TARGETS_MS = {"snapshot_ms_2d": 60.0, "snapshot_ms_3d": 300.0, "distances_ms_2d": 200.0}


def lattice_positions(dim: int, n_target: int, rng: np.random.Generator) -> tuple[np.ndarray, float]:
    """Jittered triangular (2D) or FCC (3D) lattice with unit nearest-neighbour distance; (positions, box side)."""
    if dim == 2:
        side = int(round(np.sqrt(n_target)))
        i, j = np.meshgrid(np.arange(side), np.arange(side), indexing="ij")
        points = np.stack([i + 0.5 * (j % 2), j * np.sqrt(3) / 2], axis=-1).reshape(-1, 2).astype(float)
    else:
        cells = int(round((n_target / 4) ** (1 / 3)))
        base = np.array([[0, 0, 0], [0.5, 0.5, 0], [0.5, 0, 0.5], [0, 0.5, 0.5]])
        grid = np.stack(np.meshgrid(*[np.arange(cells)] * 3, indexing="ij"), axis=-1).reshape(-1, 1, 3)
        points = ((grid + base) * np.sqrt(2)).reshape(-1, 3)
    points += rng.normal(0.0, 0.08, points.shape)
    return points - points.min(axis=0) + 0.5, float(points.max() + 1.0)


def neighbour_pairs(position: np.ndarray, cutoff: float) -> tuple[np.ndarray, np.ndarray]:
    """All pairs closer than `cutoff` (cell list on a grid of cutoff-sized cells)."""
    cell = np.floor(position / cutoff).astype(np.int64)
    shape = cell.max(axis=0) + 1
    key = np.ravel_multi_index(cell.T, shape)
    order = np.argsort(key)
    pairs = []
    dim = position.shape[1]
    offsets = np.stack(np.meshgrid(*[[-1, 0, 1]] * dim, indexing="ij"), axis=-1).reshape(-1, dim)
    sorted_key = key[order]
    for offset in offsets:
        neighbour_cell = cell + offset
        valid = np.all((neighbour_cell >= 0) & (neighbour_cell < shape), axis=1)
        target = np.ravel_multi_index(neighbour_cell[valid].T, shape)
        start = np.searchsorted(sorted_key, target, side="left")
        stop = np.searchsorted(sorted_key, target, side="right")
        source = np.flatnonzero(valid)
        count = stop - start
        i = np.repeat(source, count)
        j = order[np.concatenate([np.arange(a, b) for a, b in zip(start, stop)]) if count.sum() else []]
        pairs.append((i, np.asarray(j, dtype=np.int64)))
    i = np.concatenate([p[0] for p in pairs])
    j = np.concatenate([p[1] for p in pairs])
    keep = (i < j) & (np.linalg.norm(position[i] - position[j], axis=1) < cutoff)
    return i[keep], j[keep]


def synthetic_snapshot(dim: int, n_target: int, mean_degree: float, seed: int) -> dict:
    """Snapshot arrays (position, contacts, force vectors, wall contacts) of a synthetic packing."""
    rng = np.random.default_rng(seed)
    position, box = lattice_positions(dim, n_target, rng)
    i, j = neighbour_pairs(position, 1.2)
    keep = rng.random(i.size) < mean_degree * len(position) / (2 * i.size)
    i, j = i[keep], j[keep]
    magnitude = rng.lognormal(0.0, 0.6, i.size)
    normal = position[j] - position[i]
    normal /= np.linalg.norm(normal, axis=1, keepdims=True)
    tangent = rng.normal(size=normal.shape)
    tangent -= normal * np.sum(tangent * normal, axis=1, keepdims=True)
    tangent /= np.linalg.norm(tangent, axis=1, keepdims=True)
    friction = 0.3 * rng.random(i.size)
    force_normal = -normal * magnitude[:, None]
    force_tangential = tangent * (friction * magnitude)[:, None]
    wall_particle, wall_id = [], []
    low, high = position.min(axis=0), position.max(axis=0)
    for axis in range(dim):
        for side, touches in enumerate((position[:, axis] < low[axis] + 0.3, position[:, axis] > high[axis] - 0.3)):
            wall_particle.append(np.flatnonzero(touches))
            wall_id.append(np.full(np.count_nonzero(touches), 2 * axis + side))
    return dict(position=position, contact_i=i, contact_j=j, force_normal=force_normal,
                force_tangential=force_tangential, wall_particle=np.concatenate(wall_particle),
                wall_id=np.concatenate(wall_id))


def next_snapshot(snapshot: dict, seed: int, force_change: float = 0.05, opened: float = 0.02) -> dict:
    """The 'next' state of a compression: forces perturbed by `force_change`, a fraction `opened` of the
    contacts opened."""
    rng = np.random.default_rng(seed)
    keep = rng.random(snapshot["contact_i"].size) > opened
    scale = np.exp(rng.normal(0.0, force_change, keep.sum()))[:, None]
    return {**snapshot, "contact_i": snapshot["contact_i"][keep], "contact_j": snapshot["contact_j"][keep],
            "force_normal": snapshot["force_normal"][keep] * scale,
            "force_tangential": snapshot["force_tangential"][keep] * scale}


def analyse(snapshot: dict):
    network = build_force_network(**snapshot, kind="total")
    return network, compute_snapshot_measures(network)


def median_ms(function, repeats: int) -> float:
    function()  # warm-up: numba compilation / caches
    times = []
    for _ in range(repeats):
        start = time.perf_counter()
        function()
        times.append(time.perf_counter() - start)
    return 1e3 * float(np.median(times))


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    records.add_no_record(parser)
    args = parser.parse_args(argv)
    run = records.Run("analysis", enabled=records.wanted(args, argv),
                      settings=dict(targets_ms=TARGETS_MS, repeats=dict(snapshot_2d=15, snapshot_3d=7, distances=5)))
    snapshot_2d = synthetic_snapshot(2, 2000, 4.0, seed=1)
    snapshot_3d = synthetic_snapshot(3, 4000, 6.0, seed=2)
    rows = []
    results = {}
    networks = {}
    for label, snapshot, repeats in (("2d", snapshot_2d, 15), ("3d", snapshot_3d, 7)):
        network, measures = analyse(snapshot)
        results[f"snapshot_ms_{label}"] = median_ms(lambda: analyse(snapshot), repeats)
        counts = np.bincount(measures.diagrams.homology_dim, minlength=network.dim)
        networks[label] = dict(N=int(network.n_particles), contacts=int(network.n_edges), Z=float(measures.Z),
                               diagram_points=counts.tolist())
        rows.append((f"snapshot {label}", results[f"snapshot_ms_{label}"],
                     f"N={network.n_particles} kept={network.n_kept} E={network.n_edges} "
                     f"Z={measures.Z:.2f} PD points per k={counts.tolist()}"))
    diagrams_a = persistence_diagrams(build_force_network(**snapshot_2d))
    for key, label, change in (("distances_ms_2d", "distances 2d", (0.05, 0.02)),
                               ("distances_ms_2d_small_change", "  small step", (0.01, 0.005))):
        diagrams_b = persistence_diagrams(build_force_network(**next_snapshot(snapshot_2d, 3, *change)))

        def distances():
            return [diagram_distances(diagrams_a, diagrams_b, k) for k in (0, 1)]

        results[key] = median_ms(distances, 5)
        rows.append((label, results[key], "; ".join(
            f"PD{k}: d_B={v['bottleneck']:.3g} d_W1={v['wasserstein_1']:.3g} d_W2={v['wasserstein_2']:.3g}"
            for k, v in enumerate(distances()))))
    print(f"{'measure':<14} {'median ms':>10} {'target':>8}  details")
    for (name, ms, details), key in zip(rows, results):
        target = f"{TARGETS_MS[key]:.0f}" if key in TARGETS_MS else "–"
        print(f"{name:<14} {ms:>10.1f} {target:>8}  {details}")
    summary = {key: round(value, 2) for key, value in results.items()}
    run.write(measured={**summary, "networks": networks}, peer=None)
    print(json.dumps(summary))


if __name__ == "__main__":
    main()
