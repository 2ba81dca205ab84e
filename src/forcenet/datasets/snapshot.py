"""Snapshot files: one per (system, realization, ρ), written by the DEM driver (variables in `schema.SNAPSHOT_VARIABLES`)."""
from __future__ import annotations

import os
from pathlib import Path
from typing import Any, Mapping

import numpy as np
import xarray as xr

from forcenet.datasets.io import dataset_from_specs, read_dataset, write_netcdf
from forcenet.datasets.schema import SNAPSHOT_VARIABLES

SPATIAL_LABELS = ("x", "y", "z")
ROTATION_LABELS_2D = ("z",)


def snapshot_dataset(*, attrs: Mapping[str, Any], **arrays: Any) -> xr.Dataset:
    """Build a snapshot dataset from the DEM arrays (keyword names = `SNAPSHOT_VARIABLES`).

    Shapes: position, velocity (N, d) [d_ave, d_ave/τ_c]; radius (N,); angular_velocity (N,) in 2D or
    (N, 3) in 3D [1/τ_c]; contact_i, contact_j (C,); force_normal, force_tangential (C, d) [m̄ d_ave/τ_c²];
    wall_contact_particle, wall_contact_wall (W,); wall_contact_force (W, d); box_lo, box_hi (d,);
    scalars rho, Z, kinetic_energy, pressure, time, step, relaxation_steps.
    """
    position = np.asarray(arrays["position"], dtype=float)
    dim = position.shape[1]
    values = dict(arrays)
    angular = np.asarray(values["angular_velocity"], dtype=float)
    values["angular_velocity"] = angular.reshape(len(position), -1)
    for name in ("contact_i", "contact_j", "wall_contact_particle", "wall_contact_wall"):
        values[name] = np.asarray(values[name], dtype=np.int32).reshape(-1)
    for name in ("force_normal", "force_tangential", "wall_contact_force"):
        values[name] = np.asarray(values[name], dtype=float).reshape(-1, dim)
    for name in ("step", "relaxation_steps"):
        values[name] = np.int64(values[name])
    coords = {
        "spatial": xr.Variable(("spatial",), list(SPATIAL_LABELS[:dim]),
                               attrs={"units": "1", "long_name": "Cartesian axis"}),
        "rotation_axis": xr.Variable(("rotation_axis",), list(ROTATION_LABELS_2D if dim == 2 else SPATIAL_LABELS),
                                     attrs={"units": "1", "long_name": "axis of rotation"}),
    }
    ds = dataset_from_specs(SNAPSHOT_VARIABLES, values, {**attrs, "dimension": dim}, coords=coords)
    return ds


def write_snapshot(path: str | os.PathLike, *, attrs: Mapping[str, Any], **arrays: Any) -> Path:
    """Write one snapshot atomically (see `snapshot_dataset` for the arrays)."""
    return write_netcdf(snapshot_dataset(attrs=attrs, **arrays), path, kind="snapshot")


def read_snapshot(path: str | os.PathLike) -> xr.Dataset:
    """A snapshot file, checked against `SNAPSHOT_VARIABLES` (`DatasetError` naming the file otherwise)."""
    return read_dataset(path, "snapshot")
