"""Flag-complex super-level filtration, persistence via dionysus, Betti curves, diagram distances."""
from forcenet.topology.betti import betti_curves, default_thresholds
from forcenet.topology.complex import (
    FLAG_COMPLEX_DESCRIPTIONS,
    FlagComplex,
    enumerate_cliques,
    flag_complex,
    flag_complex_name,
    vertex_values,
)
from forcenet.topology.distances import (
    ESSENTIAL_CONVENTIONS,
    METRICS,
    bottleneck_distance,
    consecutive_diagram_distances,
    diagram_distances,
    dionysus_distances,
    matchable_points,
    wasserstein_distance,
)
from forcenet.topology.persistence import (
    PersistenceDiagrams,
    filtration_order,
    persistence_diagrams,
    persistence_of_complex,
    quadrant_persistence_diagrams,
)

__all__ = [
    "betti_curves", "default_thresholds", "FLAG_COMPLEX_DESCRIPTIONS", "FlagComplex", "enumerate_cliques",
    "flag_complex", "flag_complex_name", "vertex_values",
    "ESSENTIAL_CONVENTIONS", "METRICS", "bottleneck_distance", "consecutive_diagram_distances",
    "diagram_distances", "dionysus_distances", "matchable_points", "wasserstein_distance", "PersistenceDiagrams",
    "filtration_order", "persistence_diagrams", "persistence_of_complex", "quadrant_persistence_diagrams",
]
