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
