"""Measures of force networks: clusters ⟨S⟩, percolation N_per, shape S_p, force PDF, Z, jamming point,
persistence bins and total persistence, and all single-snapshot measures in one call."""
from forcenet.measures.clusters import (
    ClusterCurves,
    ClusterSet,
    aggregate_shape_parameter,
    cluster_curves,
    clusters_at,
    opposite_wall_masks,
)
from forcenet.measures.forces import (
    FORCE_PDF_BINS,
    FORCE_PDF_MAX,
    coordination_number,
    default_force_bin_edges,
    force_pdf,
)
from forcenet.measures.jamming import (
    JAMMING_METHODS,
    LogisticFit,
    fit_logistic,
    isostatic_crossing,
    jamming_point,
    smoothed_slope,
)
from forcenet.measures.persistence_stats import (
    PERSISTENCE_BINS,
    essential_counts,
    persistence_bin_counts,
    total_persistence,
)
from forcenet.measures.snapshot import SnapshotMeasures, compute_snapshot_measures

__all__ = [
    "ClusterCurves", "ClusterSet", "aggregate_shape_parameter", "cluster_curves", "clusters_at",
    "opposite_wall_masks", "FORCE_PDF_BINS", "FORCE_PDF_MAX", "coordination_number", "default_force_bin_edges",
    "force_pdf", "JAMMING_METHODS", "LogisticFit", "fit_logistic", "isostatic_crossing", "jamming_point",
    "smoothed_slope", "PERSISTENCE_BINS", "essential_counts", "persistence_bin_counts", "total_persistence",
    "SnapshotMeasures", "compute_snapshot_measures",
]
