"""Contacts → force network: edges, force magnitudes in units of ⟨F⟩, rattlers, wall contacts, regions; one
snapshot dataset → its network (`snapshot_network`, the one adapter every reader of snapshots uses)."""
from forcenet.network.force_network import (
    FORCE_KINDS,
    RATTLER_RULE_DESCRIPTIONS,
    RATTLER_RULES,
    CompactGraph,
    ForceNetwork,
    build_force_network,
    force_magnitude,
    network_from_edge_forces,
    rattler_free_mask,
    resolve_rattler_rule,
)
from forcenet.network.snapshot import WALL_CONTACTS, snapshot_network
from forcenet.network.regions import (
    QUADRANTS,
    quadrant_mask,
    restrict_to_quadrant,
    restrict_to_region,
)

__all__ = [
    "FORCE_KINDS", "RATTLER_RULES", "RATTLER_RULE_DESCRIPTIONS", "CompactGraph", "ForceNetwork",
    "build_force_network", "force_magnitude",
    "network_from_edge_forces", "rattler_free_mask", "resolve_rattler_rule", "QUADRANTS", "quadrant_mask",
    "restrict_to_quadrant", "restrict_to_region", "WALL_CONTACTS", "snapshot_network",
]
