"""Snapshot files: one per (system, realization, ρ) — the snapshot contract every writer and reader goes through.

Our DEM engine (`forcenet.dem.protocol`) and every importer (`forcenet.importers`: LAMMPS dumps, contact tables)
write snapshots with `write_snapshot`; the analysis, figures and tables read them with `read_snapshot`. What a
snapshot holds is declared in `forcenet.datasets.schema` (SNAPSHOT_VARIABLES, of which SNAPSHOT_DYNAMICS are
optional; REQUIRED_GLOBAL_ATTRS and SNAPSHOT_GLOBAL_ATTRS; SNAPSHOT_SOURCE_ATTRS for an imported one) and checked,
values included, on writing and on reading (`forcenet.datasets.io.snapshot_value_problems`). A reader that knows the
run a snapshot belongs to passes `expect=` (`forcenet.datasets.runs.run_expectation`): a snapshot recorded for
another system, dimension or simulation settings is refused, naming the file and the attribute.
"""
from __future__ import annotations

import os
from pathlib import Path
from typing import Any, Mapping

import numpy as np
import xarray as xr

from forcenet.boxes import AXIS_LABELS, box_periods
from forcenet.datasets.io import dataset_from_specs, optional_attr, read_dataset, write_netcdf
from forcenet.datasets.schema import (BOX_TILT_ATTR, PERIODIC_AXES_ATTR, SNAPSHOT_DYNAMICS,
                                      SNAPSHOT_IMPORT_VARIABLES, SNAPSHOT_VARIABLES)

SPATIAL_LABELS = AXIS_LABELS  # the `spatial` coordinate
ROTATION_LABELS_2D = ("z",)


def box_tilt(snapshot: xr.Dataset) -> np.ndarray | None:
    """The tilt factors of a snapshot's triclinic box (`BOX_TILT_ATTR`: xy in 2D, xy, xz, yz in 3D) [d_ave]; None for
    an orthogonal box (our engine's, and most imports)."""
    tilt = optional_attr(snapshot, BOX_TILT_ATTR)
    return None if tilt is None else np.asarray(tilt, dtype=float).reshape(-1)


def periodic_vectors(snapshot: xr.Dataset) -> np.ndarray | None:
    """The edge vector of each periodic axis of a snapshot's box (`PERIODIC_AXES_ATTR`, tilted by `box_tilt`) as rows,
    zero rows on the bounded axes, (d, d) [d_ave]; None for a bounded box (our engine's snapshots, whose boxes have
    walls), as `forcenet.boxes` takes it."""
    axes = str(optional_attr(snapshot, PERIODIC_AXES_ATTR))
    return (box_periods(axes, snapshot["box_lo"].values, snapshot["box_hi"].values, box_tilt(snapshot)) if axes
            else None)


def snapshot_dataset(*, attrs: Mapping[str, Any], **arrays: Any) -> xr.Dataset:
    """Build a snapshot dataset from its arrays (keyword names = `SNAPSHOT_VARIABLES`; the dynamics
    `SNAPSHOT_DYNAMICS` may be left out, as an importer does; an importer's optional `SNAPSHOT_IMPORT_VARIABLES`,
    contact_force_disagreement (C,), are written where given).

    Shapes: position, velocity (N, d) [d_ave, d_ave/τ_c]; radius (N,); angular_velocity (N,) in 2D or
    (N, 3) in 3D [1/τ_c]; contact_i, contact_j (C,); force_normal, force_tangential (C, d) [m̄ d_ave/τ_c²];
    wall_contact_particle, wall_contact_wall (W,); wall_contact_force (W, d); box_lo, box_hi (d,);
    scalars rho, Z, kinetic_energy, pressure, time, step, relaxation_steps.
    """
    position = np.asarray(arrays["position"], dtype=float)
    dim = position.shape[1]
    values = dict(arrays)
    if "angular_velocity" in values:
        angular = np.asarray(values["angular_velocity"], dtype=float)
        values["angular_velocity"] = angular.reshape(len(position), -1)
    for name in ("contact_i", "contact_j", "wall_contact_particle", "wall_contact_wall"):
        values[name] = np.asarray(values[name], dtype=np.int32).reshape(-1)
    for name in ("force_normal", "force_tangential", "wall_contact_force"):
        values[name] = np.asarray(values[name], dtype=float).reshape(-1, dim)
    for name in ("step", "relaxation_steps"):
        if name in values:
            values[name] = np.int64(values[name])
    specs = {**{name: spec for name, spec in SNAPSHOT_VARIABLES.items()
                if name in values or name not in SNAPSHOT_DYNAMICS},
             **{name: spec for name, spec in SNAPSHOT_IMPORT_VARIABLES.items() if name in values}}
    coords = {
        "spatial": xr.Variable(("spatial",), list(SPATIAL_LABELS[:dim]),
                               attrs={"units": "1", "long_name": "Cartesian axis"}),
    }
    if "angular_velocity" in values:
        coords["rotation_axis"] = xr.Variable(("rotation_axis",),
                                              list(ROTATION_LABELS_2D if dim == 2 else SPATIAL_LABELS),
                                              attrs={"units": "1", "long_name": "axis of rotation"})
    return dataset_from_specs(specs, values, {**attrs, "dimension": dim}, coords=coords)


def write_snapshot(path: str | os.PathLike, *, attrs: Mapping[str, Any], **arrays: Any) -> Path:
    """Write one snapshot atomically, checked against the contract (see `snapshot_dataset` for the arrays)."""
    return write_netcdf(snapshot_dataset(attrs=attrs, **arrays), path, kind="snapshot")


def read_snapshot(path: str | os.PathLike, expect: Mapping[str, Any] | None = None) -> xr.Dataset:
    """A snapshot file, checked against the contract (`DatasetError` naming the file otherwise); with `expect`
    (`forcenet.datasets.runs.run_expectation` of the run it is read for) also that it was written for that
    run (`forcenet.datasets.runs.run_mismatch`)."""
    return read_dataset(path, "snapshot", expect=expect)
