"""The netCDF data model: the one place that knows variable names, dimensions, units and long names.

Dimension names are fixed: particle, contact, wall_contact, spatial, rho, realization,
threshold, homology_dim, point, force_bin, plus a few for aggregated products. Every variable written by
forcenet has `units` and `long_name`; every file has the global attributes in `REQUIRED_GLOBAL_ATTRS`.

Units are reduced (P1 §2): length d_ave, mass m̄, time τ_c, force m̄ d_ave τ_c⁻². Network forces are in
units of that network's mean force ⟨F⟩ ("<F>"). An imported snapshot's lengths and forces, and its analyses'
``mean_force``, carry its source's units instead (``systems.<name>.units``, `forcenet.importers.sequence.unit`).
"""
from __future__ import annotations

from dataclasses import dataclass


#: the numpy dtype kinds a reader accepts for a variable declared "int" or "float" (width is free: int8 … int64)
DTYPE_KINDS = {"int": "iu", "float": "f"}


@dataclass(frozen=True)
class VariableSpec:
    """One variable on disk: its dimensions, `units`, `long_name` and value type ("int" or "float")."""

    dims: tuple[str, ...]
    units: str
    long_name: str
    dtype: str = "float"


FORCE_UNITS = "m_mean d_ave tau_c-2"
NETWORK_FORCE_UNITS = "<F>"  # force divided by the network's mean force
DIMENSIONLESS = "1"

SNAPSHOT_VARIABLES: dict[str, VariableSpec] = {
    "position": VariableSpec(("particle", "spatial"), "d_ave", "particle centre position"),
    "radius": VariableSpec(("particle",), "d_ave", "particle radius"),
    "velocity": VariableSpec(("particle", "spatial"), "d_ave tau_c-1", "particle velocity"),
    "angular_velocity": VariableSpec(("particle", "rotation_axis"), "tau_c-1", "particle angular velocity"),
    "contact_i": VariableSpec(("contact",), DIMENSIONLESS, "index of the first particle of a contact (i < j)",
                              dtype="int"),
    "contact_j": VariableSpec(("contact",), DIMENSIONLESS, "index of the second particle of a contact", dtype="int"),
    "force_normal": VariableSpec(("contact", "spatial"), FORCE_UNITS, "normal contact force on particle i from j"),
    "force_tangential": VariableSpec(("contact", "spatial"), FORCE_UNITS,
                                     "tangential contact force on particle i from j"),
    "wall_contact_particle": VariableSpec(("wall_contact",), DIMENSIONLESS, "particle touching a wall", dtype="int"),
    "wall_contact_wall": VariableSpec(("wall_contact",), DIMENSIONLESS,
                                      "wall id: 0 x_lo, 1 x_hi, 2 y_lo, 3 y_hi, 4 z_lo, 5 z_hi", dtype="int"),
    "wall_contact_force": VariableSpec(("wall_contact", "spatial"), FORCE_UNITS, "force of the wall on the particle"),
    "box_lo": VariableSpec(("spatial",), "d_ave", "lower wall positions"),
    "box_hi": VariableSpec(("spatial",), "d_ave", "upper wall positions"),
    "rho": VariableSpec((), DIMENSIONLESS, "packing fraction"),
    "Z": VariableSpec((), DIMENSIONLESS, "mean number of particle-particle contacts per particle (all particles)"),
    "kinetic_energy": VariableSpec((), "m_mean d_ave2 tau_c-2", "total kinetic energy (translation + rotation)"),
    "pressure": VariableSpec((), "m_mean d_ave-1 tau_c-2 (2D: per unit length)", "mean normal wall stress"),
    "time": VariableSpec((), "tau_c", "simulated time since the start of compression"),
    "step": VariableSpec((), DIMENSIONLESS, "time step index", dtype="int"),
    "relaxation_steps": VariableSpec((), DIMENSIONLESS, "relaxation steps before this snapshot (-1: continuous)",
                                     dtype="int"),
}

REQUIRED_GLOBAL_ATTRS = (
    "title", "system", "realization", "seed", "forcenet_version", "git_commit", "config_sha256", "config",
    "Conventions",
)

# --- the snapshot contract: what every snapshot has, whoever wrote it (our engine or an importer) ------------------
#
# Every snapshot has the variables of SNAPSHOT_VARIABLES except the dynamics of a DEM run (SNAPSHOT_DYNAMICS: our
# engine writes them, an imported state need not have them), the global attributes REQUIRED_GLOBAL_ATTRS and
# SNAPSHOT_GLOBAL_ATTRS, and an imported one also SNAPSHOT_SOURCE_ATTRS (its source files and their sha256).
# `forcenet.datasets.io.read_dataset` / `write_netcdf` check the values as well (SNAPSHOT_FINITE_VARIABLES finite,
# radii > 0, contact indices naming particles, `dimension` equal to the size of `spatial`, box_hi > box_lo).
# Wall contacts may be empty (a state without walls: percolation is then never decided).

#: the variables of a DEM run's dynamics: written by our engine, optional in the contract (an import has none)
SNAPSHOT_DYNAMICS = ("velocity", "angular_velocity", "kinetic_energy", "pressure", "time", "step",
                     "relaxation_steps")
#: variables an import writes only under the option that makes them, optional in the contract (absent from our
#: engine's snapshots and from campaign records): the disagreement of a contact given once from each side, whose two
#: estimates ``source.duplicate_contacts: mean`` merged into their mean (`forcenet.importers.common.merge_two_sided`),
#: in the source's force unit like the forces
SNAPSHOT_IMPORT_VARIABLES: dict[str, VariableSpec] = {
    "contact_force_disagreement": VariableSpec(
        ("contact",), FORCE_UNITS,
        "disagreement |F_a - F_b| of the two estimates of the force on i from j of a contact given once from each "
        "side, merged into their mean (source.duplicate_contacts); NaN where the contact is given once"),
}
#: global attributes of every snapshot beyond REQUIRED_GLOBAL_ATTRS: the spatial dimension (2 or 3)
SNAPSHOT_GLOBAL_ATTRS = ("dimension",)
#: global attribute saying where a snapshot came from (absent in snapshots written before it existed: our engine)
SOURCE_FORMAT_ATTR = "source_format"
#: `source_format` of our engine's snapshots
ENGINE_SOURCE_FORMAT = "forcenet-dem"
#: provenance of an imported snapshot (source_format other than ENGINE_SOURCE_FORMAT): the source files (JSON list),
#: their sha256 (JSON list, same order) and the timestep (LAMMPS) or state index (tables) the snapshot holds
SNAPSHOT_SOURCE_ATTRS = ("source_files", "source_sha256", "source_timestep")
#: global attribute of a snapshot whose box is periodic along some axes (an import of a LAMMPS dump whose box bounds
#: are "pp"): their letters, e.g. "xy"; absent where every axis is bounded (our engine: walls). A contact across a
#: periodic face joins particle i to the image of j nearest to it (`forcenet.boxes.image_shifts`), and a cluster
#: percolates along a periodic axis by winding around it (`forcenet.measures.clusters`); the snapshot's analysis
#: files carry the attribute too
PERIODIC_AXES_ATTR = "periodic_axes"
#: global attribute of a snapshot whose box is triclinic (an import of a LAMMPS dump with tilt factors, e.g. a sheared
#: packing): its tilt factors [d_ave] in LAMMPS's order, xy in 2D and xy, xz, yz in 3D (`forcenet.boxes`); absent
#: for an orthogonal box. A box is tilted only along its periodic axes; the snapshot's analysis files carry it too
BOX_TILT_ATTR = "box_tilt"
#: global attributes of a sequence (an imported run ordered by a coordinate other than ρ, `forcenet.importers.sequence`):
#: the coordinate's name (strain, time, frame, timestep) and unit on its snapshots, analyses' stacked files and
#: distances, and on each snapshot the state's value of it. A stacked file (network_measures, diagrams, distances)
#: of a sequence names its state axis after the coordinate on disk (dimension `strain`, `point_strain` …) where a
#: compression's is `rho`; `forcenet.datasets.io` writes and reads it so (`sequence_on_disk`), and ρ is then the
#: measured variable `rho_measured` of each state. Absent: a compression (every DEM file)
STATE_COORDINATE_ATTR = "state_coordinate"
STATE_UNITS_ATTR = "state_coordinate_units"
STATE_VALUE_ATTR = "state_coordinate_value"
#: the long name of each sequence coordinate (the stacked files' state axis of that name)
STATE_COORDINATE_LONG_NAMES = {
    "strain": "strain of the state (source.sequence)",
    "time": "time of the state (source.sequence)",
    "frame": "position of the state in its run (source.sequence: 0, 1, 2, ...)",
    "timestep": "timestep of the state in its source (source.sequence)",
}

#: the global attributes a file of any kind may lack, each with what a file without it is: the value its readers take
#: (`forcenet.datasets.optional_attr`, the one reader of them; every other global attribute of a kind is required,
#: `KIND_GLOBAL_ATTRS`, and read as ``ds.attrs[name]``)
OPTIONAL_GLOBAL_ATTRS: dict[str, object] = {
    SOURCE_FORMAT_ATTR: ENGINE_SOURCE_FORMAT,  # our engine (its snapshots written before the attribute existed)
    PERIODIC_AXES_ATTR: "",  # every axis bounded (walls)
    BOX_TILT_ATTR: None,  # an orthogonal box
    STATE_COORDINATE_ATTR: "rho",  # a compression: its states ordered by ρ
    STATE_UNITS_ATTR: DIMENSIONLESS,  # ρ's unit
    STATE_VALUE_ATTR: None,  # a compression's state: its coordinate is its ρ
}

#: variables that must hold finite values (issue 27: a NaN position or force is refused, never analysed)
SNAPSHOT_FINITE_VARIABLES = ("position", "radius", "force_normal", "force_tangential", "wall_contact_force",
                             "box_lo", "box_hi", "rho", "Z")

INDEX_FILL = -1  # fill value for integer index variables (never used for valid data)

# --- analysis of one snapshot: results/analysis/{system}/r{NN}/rho{ρ}.nc -------------------------------------
#
# Dimensions: force_kind ("total" |F_n+F_t| as in P1, "normal", "tangential" as in P2), homology_dim (0, 1[, 2]),
# threshold (F_th grid), force_bin (PDF bins), persistence_bin (rough, weak, medium, strong, essential), point.
#
# Persistence diagrams are ragged; they are stored as one flat `point` dimension (CF "indexed ragged array"
# style): each point carries its force kind and homology dimension, birth ≥ death (super-level filtration,
# in units of ⟨F⟩), and never-dying classes have death = −inf and essential = 1. Read one diagram with
# forcenet.datasets.diagram_points(ds, kind, homology_dim) (stacked diagrams.nc: also realization=, rho=).

# the one definition of both: forcenet.network and forcenet.measures import them from here
FORCE_KINDS = ("total", "normal", "tangential")  # P1 uses total; P2 normal and tangential
PERSISTENCE_BINS = ("rough", "weak", "medium", "strong", "essential")  # P1 §5.3, PD0

ANALYSIS_VARIABLES: dict[str, VariableSpec] = {
    "betti": VariableSpec(("force_kind", "homology_dim", "threshold"), DIMENSIONLESS,
                          "Betti number B_k of the super-level network F >= F_th", dtype="int"),
    "cluster_count": VariableSpec(("force_kind", "threshold"), DIMENSIONLESS,
                                  "number of clusters (connected components with at least one edge)", dtype="int"),
    "cluster_mean_size": VariableSpec(("force_kind", "threshold"), "particles",
                                      "mean cluster size <S> excluding the percolating cluster"),
    "percolating_size": VariableSpec(("force_kind", "threshold"), "particles",
                                     "size N_per of the percolating cluster (0 if none)", dtype="int"),
    "percolates": VariableSpec(("force_kind", "threshold"), DIMENSIONLESS,
                               "1 if a cluster touches two opposite walls (or winds around a periodic axis)",
                               dtype="int"),
    "percolating_count": VariableSpec(("force_kind", "threshold"), DIMENSIONLESS,
                                      "number of percolating clusters", dtype="int"),
    "largest_cluster_size": VariableSpec(("force_kind", "threshold"), "particles", "size of the largest cluster",
                                         dtype="int"),
    "shape_parameter_cluster_mean": VariableSpec(("force_kind", "threshold"), DIMENSIONLESS,
                                                 "shape parameter averaged cluster by cluster"),
    "edge_count": VariableSpec(("force_kind", "threshold"), DIMENSIONLESS, "edges in clusters (for S_p)", dtype="int"),
    "cluster_particle_count": VariableSpec(("force_kind", "threshold"), "particles",
                                           "particles in clusters (for S_p)", dtype="int"),
    "shape_parameter": VariableSpec(("force_kind", "threshold"), DIMENSIONLESS,
                                    "shape parameter S_p: edges / particles in clusters (P1 §5.2)"),
    "force_pdf": VariableSpec(("force_kind", "force_bin"), "<F>-1", "probability density of F/<F>"),
    "mean_force": VariableSpec(("force_kind",), FORCE_UNITS, "mean contact force <F> of the network"),
    "persistence_bin_count": VariableSpec(("force_kind", "persistence_bin"), DIMENSIONLESS,
                                          "PD0 points per persistence bin (P1 §5.3)", dtype="int"),
    "total_persistence": VariableSpec(("force_kind", "homology_dim"), NETWORK_FORCE_UNITS,
                                      "total persistence TP_k: sum of birth - death over finite points"),
    "essential_count": VariableSpec(("force_kind", "homology_dim"), DIMENSIONLESS, "never-dying classes",
                                    dtype="int"),
    "Z": VariableSpec((), DIMENSIONLESS, "mean contacts per particle, all particles"),
    "Z_no_rattlers": VariableSpec((), DIMENSIONLESS, "mean contacts per particle, rattlers excluded"),
    "n_particles": VariableSpec((), "particles", "number of particles N", dtype="int"),
    "rho": VariableSpec((), DIMENSIONLESS, "packing fraction"),
    "diagram_force_kind": VariableSpec(("point",), DIMENSIONLESS, "force kind of the point (index into force_kind)",
                                       dtype="int"),
    "diagram_homology_dim": VariableSpec(("point",), DIMENSIONLESS, "homology dimension of the point", dtype="int"),
    "birth": VariableSpec(("point",), NETWORK_FORCE_UNITS, "birth of the class (super-level: birth >= death)"),
    "death": VariableSpec(("point",), NETWORK_FORCE_UNITS, "death of the class (-inf: never dies)"),
    "essential": VariableSpec(("point",), DIMENSIONLESS, "1 if the class never dies", dtype="int"),
}

#: per-point variables of the persistence diagrams (analysis files and diagrams.nc)
DIAGRAM_VARIABLES = ("diagram_force_kind", "diagram_homology_dim", "birth", "death", "essential")

# --- one system stacked over (realization, ρ): results/{system}/network_measures.nc and diagrams.nc -----------
#
# `rho` is the grid packing fraction of the config (systems.<name>.rho), the coordinate to select on; the
# measured packing fraction of each snapshot is the variable `rho_measured` (quasi-static runs stop the walls on
# the grid, continuous runs take the first step past it).
RHO_MEASURED = VariableSpec(("realization", "rho"), DIMENSIONLESS, "measured packing fraction of the snapshot")

NETWORK_MEASURES_VARIABLES: dict[str, VariableSpec] = {
    **{name: VariableSpec(("realization", "rho", *spec.dims), spec.units, spec.long_name, spec.dtype)
       for name, spec in ANALYSIS_VARIABLES.items() if name not in DIAGRAM_VARIABLES and name != "rho"},
    "rho_measured": RHO_MEASURED,
}

DIAGRAMS_VARIABLES: dict[str, VariableSpec] = {
    **{name: ANALYSIS_VARIABLES[name] for name in DIAGRAM_VARIABLES},
    "point_realization": VariableSpec(("point",), DIMENSIONLESS, "realization of the point", dtype="int"),
    "point_rho": VariableSpec(("point",), DIMENSIONLESS, "grid packing fraction of the point's snapshot"),
    "point_rho_measured": VariableSpec(("point",), DIMENSIONLESS, "measured packing fraction of the point's snapshot"),
}

# --- P2 distances between consecutive snapshots: results/{system}/distances.nc ----------------------------------
#
# `rho` is the grid packing fraction of the later snapshot of each pair; `rho_measured` its measured value and
# `rho_previous` the measured value of the earlier snapshot, per realization (forcenet.report.p2_distances computes them).
DISTANCES_VARIABLES: dict[str, VariableSpec] = {
    "distance": VariableSpec(("realization", "rho", "force_kind", "homology_dim", "metric"), NETWORK_FORCE_UNITS,
                             "distance between the persistence diagrams of consecutive snapshots"),
    "Z": VariableSpec(("realization", "rho"), DIMENSIONLESS, "mean contacts per particle Z of the later snapshot"),
    "rho_previous": VariableSpec(("realization", "rho"), DIMENSIONLESS, "packing fraction of the earlier snapshot"),
    "rho_measured": VariableSpec(("realization", "rho"), DIMENSIONLESS, "packing fraction of the later snapshot"),
}

#: variables of an analysis file that must be finite (forces in <F>, ρ, Z); `death` is finite or -inf where
#: `essential` is 1 (a class that never dies)
ANALYSIS_FINITE_VARIABLES = ("mean_force", "total_persistence", "rho", "Z", "birth")

# --- one P2 run in brief: what P2's products read from it, its diagrams apart --------------------------------------
#
# results/{system}/p2_runs/{realization}.nc (kind "p2_run", `forcenet.report.p2_distances.run_summary`): per state of
# the run's grid (`grid_state`, the grid ρ) its measured ρ, Z, never-dying class counts and diagram point counts, and
# the distances between consecutive states (`pair`: the later state of each) under each convention for never-dying
# classes the build reads (`essential_convention`). P2's distances, validation table and never-dying class counts are
# made from these files; a campaign record of a P2 run (kind "p2_run_record") holds the same and the states a, b, c
# of Tables I-III can be taken from (`forcenet.datasets.records`).
P2_RUN_VARIABLES: dict[str, VariableSpec] = {
    "state_rho": VariableSpec(("grid_state",), DIMENSIONLESS, "measured packing fraction of the state"),
    "state_Z": VariableSpec(("grid_state",), DIMENSIONLESS,
                            "mean number of particle-particle contacts per particle of the state (all particles)"),
    "essential_count": VariableSpec(("grid_state", "force_kind", "homology_dim"), DIMENSIONLESS,
                                    "never-dying classes of the state's diagram PD_k", dtype="int"),
    "point_count": VariableSpec(("grid_state", "force_kind", "homology_dim"), DIMENSIONLESS,
                                "points of the state's persistence diagram PD_k", dtype="int"),
    "point_total": VariableSpec(("grid_state",), DIMENSIONLESS,
                                "points of every persistence diagram of the state (all force kinds and k)",
                                dtype="int"),
    "distance": VariableSpec(("essential_convention", "pair", "force_kind", "homology_dim", "metric"),
                             NETWORK_FORCE_UNITS,
                             "distance between the persistence diagrams of consecutive states (the pair's later "
                             "state and the one before it)"),
}
#: global attributes of a P2 run summary beyond REQUIRED_GLOBAL_ATTRS: those of an analysis (the networks its
#: diagrams were made of) and the run's simulation fingerprint
P2_RUN_GLOBAL_ATTRS = ("dimension", "rattler_rule", "flag_complex", "simulation_sha256")

# --- a campaign record: one finished compression run in one file, data/validation/{system}/{realization}/states.nc ---
#
# The snapshots of a run stacked over `state` (one per ρ of the grid, labelled by the grid ρ as in the file names),
# its contacts and wall contacts as CF contiguous ragged arrays (the state's `contact_count` consecutive entries of
# `contact`, in state order). Radii are the run's (constant over its states); the dynamics arrays (velocity,
# angular velocity) are not kept: no analysis reads them (`forcenet.datasets.records`).
RECORD_VARIABLES: dict[str, VariableSpec] = {
    "radius": SNAPSHOT_VARIABLES["radius"],
    "position": VariableSpec(("state", "particle", "spatial"), "d_ave", "particle centre position"),
    "box_lo": VariableSpec(("state", "spatial"), "d_ave", "lower wall positions"),
    "box_hi": VariableSpec(("state", "spatial"), "d_ave", "upper wall positions"),
    **{name: VariableSpec(("state",), spec.units, spec.long_name, spec.dtype)
       for name, spec in SNAPSHOT_VARIABLES.items() if spec.dims == ()},
    "contact_count": VariableSpec(("state",), DIMENSIONLESS, "contacts of the state (consecutive in `contact`)",
                                  dtype="int"),
    "contact_i": SNAPSHOT_VARIABLES["contact_i"],
    "contact_j": SNAPSHOT_VARIABLES["contact_j"],
    "force_normal_component": VariableSpec(
        ("contact",), FORCE_UNITS, "normal contact force on particle i from j along the unit branch vector "
        "n = (x_i - x_j)/|x_i - x_j| (force_normal = force_normal_component n + force_normal_residual)"),
    "force_normal_residual": VariableSpec(
        ("contact", "spatial"), DIMENSIONLESS, "force_normal minus force_normal_component n, as the difference of "
        "their IEEE-754 binary64 bit patterns (0 where the product is exact)", dtype="int"),
    "force_tangential_component": VariableSpec(
        ("contact", "tangent_axis"), FORCE_UNITS, "tangential contact force on particle i from j along the unit axes "
        "normal to n: 2D (-n_y, n_x); 3D e1 = n x a/|n x a| (a: the coordinate axis least aligned with n), e2 = n x e1"),
    "force_tangential_residual": VariableSpec(
        ("contact", "spatial"), DIMENSIONLESS, "force_tangential minus its components along the tangent axes, as the "
        "difference of their IEEE-754 binary64 bit patterns", dtype="int"),
    "wall_contact_count": VariableSpec(("state",), DIMENSIONLESS,
                                      "wall contacts of the state (consecutive in `wall_contact`)", dtype="int"),
    "wall_contact_particle": SNAPSHOT_VARIABLES["wall_contact_particle"],
    "wall_contact_wall": SNAPSHOT_VARIABLES["wall_contact_wall"],
    "wall_contact_force": SNAPSHOT_VARIABLES["wall_contact_force"],
}
#: how a record stores each contact's force vectors (`forcenet.datasets.force_codec`), losslessly
FORCE_STORAGE = ("force_normal_component", "force_normal_residual", "force_tangential_component",
                 "force_tangential_residual")
#: global attributes of a record beyond REQUIRED_GLOBAL_ATTRS: the record format, the run's simulation fingerprint
#: (`forcenet.datasets.runs.simulation_sha256`), its CPU seconds summed over every process that ran it, the
#: dimension, the global attributes its snapshots share (JSON), those of each state that differ (JSON list: the commit
#: of a run resumed under a later one) and the snapshot variables it does not keep
RECORD_GLOBAL_ATTRS = ("record_format", "simulation_sha256", "cpu_seconds", "dimension", "snapshot_attrs",
                       "state_attrs", "dropped_variables")

# --- a campaign record of a P2 run: data/validation/{system}/{realization}/p2_run.nc ---------------------------------
#
# A P2 run's 100 states do not fit the records' budget (data/validation/README.md, "Size"): its record holds the run's
# summary (P2_RUN_VARIABLES: every distance, count and Z that P2's products read) and, of the frictional system, the
# states among which Tables I-III and Figs 1, 3 take a, b, c (`forcenet.pipeline_p2.p2_read_state_indices`), stored as a
# run record stores them (RECORD_VARIABLES over `state`, labelled by the grid ρ); the frictionless system's record
# keeps no state (none of the RECORD_VARIABLES).
P2_RUN_RECORD_VARIABLES: dict[str, VariableSpec] = {**P2_RUN_VARIABLES, **RECORD_VARIABLES}
#: global attributes of a P2 run record: a run record's, the analysis attributes of the summary and the grid labels
P2_RUN_RECORD_GLOBAL_ATTRS = (*RECORD_GLOBAL_ATTRS, "rattler_rule", "flag_complex", "grid_labels")

#: global attributes of each file kind beyond REQUIRED_GLOBAL_ATTRS (its provenance), checked on writing and reading,
#: so that a reader indexes them and never falls back to a default: the spatial dimension; the rattler rule and flag
#: complex that made an analysis's networks (`forcenet.pipeline.rattler_attrs`, `flag_complex_attrs`); a stacked
#: file's force law and, for P1's F_max rule, the system's force constants (`forcenet.pipeline.force_constants`); a
#: distances file's convention for never-dying classes
ANALYSIS_GLOBAL_ATTRS = ("dimension", "rattler_rule", "flag_complex")
STACKED_GLOBAL_ATTRS = (*ANALYSIS_GLOBAL_ATTRS, "force_law")
FORCE_CONSTANT_ATTRS = ("force_unit_dyn", "stiffness_scale_reduced", "normal_stiffness_cgs")
KIND_GLOBAL_ATTRS: dict[str, tuple[str, ...]] = {
    "snapshot": SNAPSHOT_GLOBAL_ATTRS,
    "analysis": ANALYSIS_GLOBAL_ATTRS,
    "network_measures": (*STACKED_GLOBAL_ATTRS, *FORCE_CONSTANT_ATTRS),
    "diagrams": STACKED_GLOBAL_ATTRS,
    "distances": (*STACKED_GLOBAL_ATTRS, "essential_convention"),
    "run_record": RECORD_GLOBAL_ATTRS,
    "p2_run": P2_RUN_GLOBAL_ATTRS,
    "p2_run_record": P2_RUN_RECORD_GLOBAL_ATTRS,
}

#: every file kind the pipeline reads: its variables and the coordinates a reader selects on
FILE_KINDS: dict[str, tuple[dict[str, VariableSpec], tuple[str, ...]]] = {
    "snapshot": ({**SNAPSHOT_VARIABLES, **SNAPSHOT_IMPORT_VARIABLES}, ("spatial",)),
    "analysis": (ANALYSIS_VARIABLES, ("force_kind", "homology_dim", "threshold", "force_bin", "persistence_bin")),
    "network_measures": (NETWORK_MEASURES_VARIABLES, ("realization", "rho", "force_kind", "homology_dim",
                                                      "threshold", "force_bin", "persistence_bin")),
    "diagrams": (DIAGRAMS_VARIABLES, ("force_kind",)),
    "distances": (DISTANCES_VARIABLES, ("realization", "rho", "force_kind", "homology_dim", "metric")),
    "run_record": (RECORD_VARIABLES, ("state", "spatial")),
    "p2_run": (P2_RUN_VARIABLES, ("grid_state", "essential_convention", "force_kind", "homology_dim", "metric")),
    "p2_run_record": (P2_RUN_RECORD_VARIABLES, ("grid_state", "essential_convention", "force_kind", "homology_dim",
                                                "metric")),
}

#: variables of a file kind that may be absent (when present they must match their spec)
OPTIONAL_VARIABLES: dict[str, tuple[str, ...]] = {"snapshot": (*SNAPSHOT_DYNAMICS, *SNAPSHOT_IMPORT_VARIABLES),
                                                  "p2_run_record": tuple(RECORD_VARIABLES)}  # no state kept
