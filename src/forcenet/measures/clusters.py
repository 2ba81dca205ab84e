"""Force clusters over the threshold grid: number, mean size ⟨S⟩, percolation N_per, shape S_p (P1 §3–5).

At threshold F_th a *cluster* is a connected component of the network restricted to the edges with force
≥ F_th (P2 Eq. 1; the same super-level set as the Betti numbers, so B0(F_th) = number of clusters). A
particle belongs to it through its edges; a network particle without any edge (only when rattlers are
kept) is a one-particle cluster at F_th ≤ 0, as in B0.

- ⟨S⟩ (P1 §4.2): mean number of particles per cluster, the percolating cluster(s) excluded; 0 when there is
  no other cluster (P1 Fig. 4: "⟨S⟩ may vanish in the case no clusters are found").
- Percolating cluster (P1 §4): a cluster containing particles that touch two opposite walls (through the
  network's wall contacts, whatever their force). N_per counts the particles of all percolating clusters
  (normally there is one). Along a periodic axis of an imported box (`ForceNetwork.period`), which has no
  walls, a cluster percolates when it winds around the box: one of its loops, followed from particle to
  nearest image, ends on the particle's own image a whole number of box lengths away (the cluster joins
  itself across the face, as a wall-to-wall cluster joins the two walls). A cluster that only crosses the face does not.
- Shape parameter S̄_p (P1 §5.2): edges / particles, pooled over the clusters of one network ("the number
  of edges in the clusters divided by the number of participating particles"): a path of N_L particles
  gives (N_L − 1)/N_L, a loop 1, denser clusters more; 0 when there are no clusters. The mean of the
  per-cluster ratios is reported too (`shape_parameter_cluster_mean`). `aggregate_shape_parameter` applies
  P1's rule across realizations.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from forcenet.boxes import image_counts
from forcenet.measures import _kernels
from forcenet.network.force_network import ForceNetwork
from forcenet.topology.betti import default_thresholds


@dataclass(frozen=True)
class ClusterCurves:
    """Cluster statistics on a threshold grid; every array has shape (n_thresholds,).

    Attributes
    ----------
    thresholds : F_th [⟨F⟩].
    cluster_count : number of clusters (= B0).
    cluster_particle_count : particles in clusters.
    edge_count : edges in clusters (edges with force ≥ F_th).
    cluster_mean_size : ⟨S⟩ [particles], percolating clusters excluded.
    percolates : bool — some cluster touches two opposite walls (or winds around a periodic axis).
    percolating_count : number of percolating clusters.
    percolating_size : N_per [particles], particles in percolating clusters.
    largest_cluster_size : [particles].
    shape_parameter : S̄_p = edge_count / cluster_particle_count (0 without clusters), P1 §5.2.
    shape_parameter_cluster_mean : mean over clusters of edges/particles (0 without clusters).
    """

    thresholds: np.ndarray
    cluster_count: np.ndarray
    cluster_particle_count: np.ndarray
    edge_count: np.ndarray
    cluster_mean_size: np.ndarray
    percolates: np.ndarray
    percolating_count: np.ndarray
    percolating_size: np.ndarray
    largest_cluster_size: np.ndarray
    shape_parameter: np.ndarray
    shape_parameter_cluster_mean: np.ndarray


@dataclass(frozen=True)
class ClusterSet:
    """The clusters of a network at one threshold.

    Attributes
    ----------
    threshold : F_th [⟨F⟩].
    particle_label : ndarray, shape (N,), int64 — cluster of each particle, −1 when in none.
    size : ndarray, shape (K,), int64 — particles per cluster.
    edge_count : ndarray, shape (K,), int64 — edges per cluster.
    wall_mask : ndarray, shape (K,), int64 — bit w set when the cluster touches wall w.
    percolating : ndarray, shape (K,), bool.
    """

    threshold: float
    particle_label: np.ndarray
    size: np.ndarray
    edge_count: np.ndarray
    wall_mask: np.ndarray
    percolating: np.ndarray


def opposite_wall_masks(dim: int, axes=None) -> np.ndarray:
    """Bit masks of opposite wall pairs, wall ids 2a (low) and 2a + 1 (high) of axis a; shape (n_axes,)."""
    axes = range(dim) if axes is None else axes
    return np.array([(1 << (2 * a)) | (1 << (2 * a + 1)) for a in axes], dtype=np.int64)


def _vertex_walls(network: ForceNetwork) -> np.ndarray:
    """Wall bits of each compact vertex (`ForceNetwork.compact`): bit w set when it touches wall w."""
    graph = network.compact
    walls = np.zeros(graph.n_vertices, dtype=np.int64)
    np.bitwise_or.at(walls, graph.index[network.wall_particle], np.left_shift(1, network.wall_id).astype(np.int64))
    return walls


def _winding_inputs(network: ForceNetwork, edges: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """What the kernels need to follow images: each compact edge's image count (E, d), int64 (the edge vectors
    that take its second particle to the image nearest to its first, `forcenet.boxes.image_counts`), and the
    wall-pair bits of each periodic axis (d,), int64, 0 on the bounded ones. A bounded box gets all-0 bits and
    no image counts (0, d): the kernels then never read them."""
    period = network.period  # edge vectors (d, d): a winding is counted in them, as in a tilted box's lattice
    axis_pairs = np.zeros(network.dim, dtype=np.int64)
    if period is None or not np.any(np.diag(period) > 0):
        return np.zeros((0, network.dim), dtype=np.int64), axis_pairs
    particle = network.compact.particle
    periodic_axes = np.flatnonzero(np.diag(period) > 0)
    axis_pairs[periodic_axes] = opposite_wall_masks(network.dim, periodic_axes)
    return image_counts(network.position, particle[edges[:, 0]], particle[edges[:, 1]], period), axis_pairs


def _percolating(wall_mask: np.ndarray, opposite_pairs: np.ndarray) -> np.ndarray:
    """Whether each wall mask holds both walls of some opposite pair, shape of `wall_mask`, bool."""
    pairs = np.asarray(opposite_pairs, dtype=np.int64)
    return np.any((np.asarray(wall_mask, dtype=np.int64)[..., None] & pairs) == pairs, axis=-1)


def cluster_curves(network: ForceNetwork, thresholds=None, *, percolation_axes=None) -> ClusterCurves:
    """Cluster statistics of a force network at every threshold (module docstring), one union–find sweep.

    Parameters
    ----------
    network : ForceNetwork (forces in ⟨F⟩).
    thresholds : array, shape (T,) [⟨F⟩]; default `default_thresholds()` (0 to 3 by 0.05).
    percolation_axes : axes whose two walls (or, on a periodic axis, winding around it) count for percolation
        (default: all d axes).
    """
    thresholds = default_thresholds() if thresholds is None else np.asarray(thresholds, dtype=np.float64)
    graph = network.compact
    force = graph.force
    by_force = np.argsort(-force, kind="stable")
    by_threshold = np.argsort(-thresholds, kind="stable")
    images, axis_pairs = _winding_inputs(network, graph.edges[by_force])
    counts_sorted, ratio_sorted = _kernels.cluster_sweep(
        graph.vertex_value, graph.edges[by_force, 0], graph.edges[by_force, 1], force[by_force],
        _vertex_walls(network), opposite_wall_masks(network.dim, percolation_axes), thresholds[by_threshold],
        images, axis_pairs)
    counts = np.empty_like(counts_sorted)
    counts[by_threshold] = counts_sorted
    ratio_sum = np.empty_like(ratio_sorted)
    ratio_sum[by_threshold] = ratio_sorted
    k = _kernels
    n_clusters, particles = counts[:, k.N_CLUSTERS], counts[:, k.N_VERTICES]
    other_clusters = n_clusters - counts[:, k.N_PERCOLATING]
    other_particles = particles - counts[:, k.PERCOLATING_SIZE]
    return ClusterCurves(
        thresholds=thresholds, cluster_count=n_clusters, cluster_particle_count=particles,
        edge_count=counts[:, k.N_EDGES],
        cluster_mean_size=_ratio_or_zero(other_particles, other_clusters),
        percolates=counts[:, k.N_PERCOLATING] > 0, percolating_count=counts[:, k.N_PERCOLATING],
        percolating_size=counts[:, k.PERCOLATING_SIZE], largest_cluster_size=counts[:, k.LARGEST_SIZE],
        shape_parameter=_ratio_or_zero(counts[:, k.N_EDGES], particles),
        shape_parameter_cluster_mean=_ratio_or_zero(ratio_sum, n_clusters))


def _ratio_or_zero(numerator, denominator) -> np.ndarray:
    numerator = np.asarray(numerator, dtype=np.float64)
    denominator = np.asarray(denominator, dtype=np.float64)
    return np.divide(numerator, denominator, out=np.zeros_like(numerator), where=denominator > 0)


def clusters_at(network: ForceNetwork, threshold: float, *, percolation_axes=None) -> ClusterSet:
    """The individual clusters at one threshold (sizes, edges, walls, percolation); see module docstring. A
    cluster that winds around a periodic axis has both wall bits of that axis set in its `wall_mask`."""
    graph = network.compact
    particle, walls = graph.particle, _vertex_walls(network)
    edge_a, edge_b = graph.edges[:, 0], graph.edges[:, 1]
    present = graph.vertex_value >= threshold
    strong = graph.force >= threshold
    labels = _kernels.component_labels(particle.size, edge_a[strong], edge_b[strong])
    images, axis_pairs = _winding_inputs(network, graph.edges[strong])
    walls = walls | _kernels.winding_walls(particle.size, edge_a[strong], edge_b[strong], images, axis_pairs)
    # relabel the present vertices' components 0..K−1
    _, labels_present = np.unique(labels[present], return_inverse=True)
    n_clusters = int(labels_present.max(initial=-1)) + 1
    cluster_of_vertex = np.full(particle.size, -1, dtype=np.int64)
    cluster_of_vertex[present] = labels_present
    size = np.bincount(labels_present, minlength=n_clusters)
    edge_count = np.bincount(cluster_of_vertex[edge_a[strong]], minlength=n_clusters)
    wall_mask = np.zeros(n_clusters, dtype=np.int64)
    np.bitwise_or.at(wall_mask, labels_present, walls[present])
    percolating = _percolating(wall_mask, opposite_wall_masks(network.dim, percolation_axes))
    particle_label = np.full(network.n_particles, -1, dtype=np.int64)
    particle_label[particle] = cluster_of_vertex
    return ClusterSet(threshold=float(threshold), particle_label=particle_label, size=size.astype(np.int64),
                      edge_count=edge_count.astype(np.int64), wall_mask=wall_mask, percolating=percolating)


def aggregate_shape_parameter(values, axis: int = 0) -> np.ndarray:
    """S_p across realizations (P1 §5.2).

    "We put S_p = 0 whenever S̄_p = 0 for at least half of the realizations. Otherwise, the values are
    averaged only over the realizations such that S̄_p ≠ 0." NaN entries (missing realizations) are ignored.

    Parameters
    ----------
    values : array — S̄_p per realization along `axis` (any other axes, e.g. ρ × threshold, are kept).
    axis : the realization axis.

    Returns
    -------
    ndarray — `values` reduced along `axis`.
    """
    values = np.asarray(values, dtype=np.float64)
    valid = ~np.isnan(values)
    nonzero = valid & (values != 0)
    n_valid = valid.sum(axis=axis)
    n_nonzero = nonzero.sum(axis=axis)
    total = np.where(nonzero, values, 0.0).sum(axis=axis)
    mean_nonzero = np.divide(total, n_nonzero, out=np.zeros_like(total), where=n_nonzero > 0)
    mostly_zero = (n_valid - n_nonzero) >= 0.5 * n_valid
    return np.where(mostly_zero | (n_valid == 0), 0.0, mean_nonzero)
