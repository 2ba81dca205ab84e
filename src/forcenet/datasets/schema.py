"""The netCDF data model: the one place that knows variable names, dimensions, units and long names.

Dimension names are fixed (DESIGN.md): particle, contact, wall_contact, spatial, rho, realization,
threshold, homology_dim, point, force_bin, plus a few for aggregated products. Every variable written by
forcenet has `units` and `long_name`; every file has the global attributes in `REQUIRED_GLOBAL_ATTRS`.

Units are reduced (P1 §2): length d_ave, mass m̄, time τ_c, force m̄ d_ave τ_c⁻². Network forces are in
units of that network's mean force ⟨F⟩ ("<F>").
"""
from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True)
class VariableSpec:
    dims: tuple[str, ...]
    units: str
    long_name: str


FORCE_UNITS = "m_mean d_ave tau_c-2"
NETWORK_FORCE_UNITS = "<F>"  # force divided by the network's mean force
DIMENSIONLESS = "1"

SNAPSHOT_VARIABLES: dict[str, VariableSpec] = {
    "position": VariableSpec(("particle", "spatial"), "d_ave", "particle centre position"),
    "radius": VariableSpec(("particle",), "d_ave", "particle radius"),
    "velocity": VariableSpec(("particle", "spatial"), "d_ave tau_c-1", "particle velocity"),
    "angular_velocity": VariableSpec(("particle", "rotation_axis"), "tau_c-1", "particle angular velocity"),
    "contact_i": VariableSpec(("contact",), DIMENSIONLESS, "index of the first particle of a contact (i < j)"),
    "contact_j": VariableSpec(("contact",), DIMENSIONLESS, "index of the second particle of a contact"),
    "force_normal": VariableSpec(("contact", "spatial"), FORCE_UNITS, "normal contact force on particle i from j"),
    "force_tangential": VariableSpec(("contact", "spatial"), FORCE_UNITS,
                                     "tangential contact force on particle i from j"),
    "wall_contact_particle": VariableSpec(("wall_contact",), DIMENSIONLESS, "particle touching a wall"),
    "wall_contact_wall": VariableSpec(("wall_contact",), DIMENSIONLESS,
                                      "wall id: 0 x_lo, 1 x_hi, 2 y_lo, 3 y_hi, 4 z_lo, 5 z_hi"),
    "wall_contact_force": VariableSpec(("wall_contact", "spatial"), FORCE_UNITS, "force of the wall on the particle"),
    "box_lo": VariableSpec(("spatial",), "d_ave", "lower wall positions"),
    "box_hi": VariableSpec(("spatial",), "d_ave", "upper wall positions"),
    "rho": VariableSpec((), DIMENSIONLESS, "packing fraction"),
    "Z": VariableSpec((), DIMENSIONLESS, "mean number of particle-particle contacts per particle (all particles)"),
    "kinetic_energy": VariableSpec((), "m_mean d_ave2 tau_c-2", "total kinetic energy (translation + rotation)"),
    "pressure": VariableSpec((), "m_mean d_ave-1 tau_c-2 (2D: per unit length)", "mean normal wall stress"),
    "time": VariableSpec((), "tau_c", "simulated time since the start of compression"),
    "step": VariableSpec((), DIMENSIONLESS, "time step index"),
    "relaxation_steps": VariableSpec((), DIMENSIONLESS, "relaxation steps before this snapshot (-1: continuous)"),
}

REQUIRED_GLOBAL_ATTRS = (
    "title", "system", "realization", "seed", "forcenet_version", "git_commit", "config_sha256", "config",
    "Conventions",
)

INDEX_FILL = -1  # fill value for integer index variables (never used for valid data)

# --- analysis of one snapshot: results/analysis/{system}/r{NN}/rho{ρ}.nc -------------------------------------
#
# Dimensions: force_kind ("total" |F_n+F_t| as in P1, "normal", "tangential" as in P2), homology_dim (0, 1[, 2]),
# threshold (F_th grid), force_bin (PDF bins), persistence_bin (rough, weak, medium, strong, essential), point.
#
# Persistence diagrams are ragged; they are stored as one flat `point` dimension (CF "indexed ragged array"
# style): each point carries its force kind and homology dimension, birth ≥ death (super-level filtration,
# in units of ⟨F⟩), and never-dying classes have death = −inf and essential = 1. Select one diagram with
# ds.where((ds.diagram_force_kind == k) & (ds.diagram_homology_dim == h), drop=True) or
# forcenet.datasets.diagram_points(ds, kind, dim).

# the one definition of both: forcenet.network and forcenet.measures import them from here
FORCE_KINDS = ("total", "normal", "tangential")  # P1 uses total; P2 normal and tangential
PERSISTENCE_BINS = ("rough", "weak", "medium", "strong", "essential")  # P1 §5.3, PD0

ANALYSIS_VARIABLES: dict[str, VariableSpec] = {
    "betti": VariableSpec(("force_kind", "homology_dim", "threshold"), DIMENSIONLESS,
                          "Betti number B_k of the super-level network F > F_th"),
    "cluster_count": VariableSpec(("force_kind", "threshold"), DIMENSIONLESS,
                                  "number of clusters (connected components with at least one edge)"),
    "cluster_mean_size": VariableSpec(("force_kind", "threshold"), "particles",
                                      "mean cluster size <S> excluding the percolating cluster"),
    "percolating_size": VariableSpec(("force_kind", "threshold"), "particles",
                                     "size N_per of the percolating cluster (0 if none)"),
    "percolates": VariableSpec(("force_kind", "threshold"), DIMENSIONLESS,
                               "1 if a cluster touches two opposite walls"),
    "percolating_count": VariableSpec(("force_kind", "threshold"), DIMENSIONLESS,
                                      "number of percolating clusters"),
    "largest_cluster_size": VariableSpec(("force_kind", "threshold"), "particles", "size of the largest cluster"),
    "shape_parameter_cluster_mean": VariableSpec(("force_kind", "threshold"), DIMENSIONLESS,
                                                 "shape parameter averaged cluster by cluster"),
    "edge_count": VariableSpec(("force_kind", "threshold"), DIMENSIONLESS, "edges in clusters (for S_p)"),
    "cluster_particle_count": VariableSpec(("force_kind", "threshold"), "particles",
                                           "particles in clusters (for S_p)"),
    "shape_parameter": VariableSpec(("force_kind", "threshold"), DIMENSIONLESS,
                                    "shape parameter S_p: edges / particles in clusters (P1 §5.2)"),
    "force_pdf": VariableSpec(("force_kind", "force_bin"), "<F>-1", "probability density of F/<F>"),
    "mean_force": VariableSpec(("force_kind",), FORCE_UNITS, "mean contact force <F> of the network"),
    "persistence_bin_count": VariableSpec(("force_kind", "persistence_bin"), DIMENSIONLESS,
                                          "PD0 points per persistence bin (P1 §5.3)"),
    "total_persistence": VariableSpec(("force_kind", "homology_dim"), NETWORK_FORCE_UNITS,
                                      "total persistence TP_k: sum of birth - death over finite points"),
    "essential_count": VariableSpec(("force_kind", "homology_dim"), DIMENSIONLESS, "never-dying classes"),
    "Z": VariableSpec((), DIMENSIONLESS, "mean contacts per particle, all particles"),
    "Z_no_rattlers": VariableSpec((), DIMENSIONLESS, "mean contacts per particle, rattlers excluded"),
    "n_particles": VariableSpec((), "particles", "number of particles N"),
    "rho": VariableSpec((), DIMENSIONLESS, "packing fraction"),
    "diagram_force_kind": VariableSpec(("point",), DIMENSIONLESS, "force kind of the point (index into force_kind)"),
    "diagram_homology_dim": VariableSpec(("point",), DIMENSIONLESS, "homology dimension of the point"),
    "birth": VariableSpec(("point",), NETWORK_FORCE_UNITS, "birth of the class (super-level: birth >= death)"),
    "death": VariableSpec(("point",), NETWORK_FORCE_UNITS, "death of the class (-inf: never dies)"),
    "essential": VariableSpec(("point",), DIMENSIONLESS, "1 if the class never dies"),
}
