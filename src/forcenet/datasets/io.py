"""Writing and reading forcenet netCDF files: provenance, compression, atomic replacement, validation."""
from __future__ import annotations

import json
import os
import subprocess
import tempfile
from functools import lru_cache
from pathlib import Path
from typing import Any, Mapping

import numpy as np
import xarray as xr

from forcenet.datasets.schema import REQUIRED_GLOBAL_ATTRS, VariableSpec

CONVENTIONS = "CF-1.10"


class SchemaError(ValueError):
    """A dataset does not follow the forcenet data model (missing units, long_name or attrs)."""


@lru_cache(maxsize=1)
def git_commit() -> str:
    """Commit of the forcenet source tree ('unknown' outside a git checkout; '+dirty' if modified)."""
    root = Path(__file__).resolve().parents[3]
    try:
        commit = subprocess.run(["git", "-C", str(root), "rev-parse", "HEAD"], capture_output=True,
                                text=True, timeout=10, check=True).stdout.strip()
        dirty = subprocess.run(["git", "-C", str(root), "status", "--porcelain", "--untracked-files=no",
                                "--", "src", "workflow"], capture_output=True, text=True, timeout=10).stdout.strip()
        return commit + ("+dirty" if dirty else "")
    except (OSError, subprocess.SubprocessError):
        return "unknown"


def provenance_attrs(*, system: str, realization: int, seed: int, config: Mapping[str, Any] | None,
                     title: str) -> dict[str, Any]:
    """Global attributes every forcenet file carries (DESIGN.md, data model)."""
    from forcenet import __version__
    from forcenet.systems import config_sha256

    config = dict(config or {})
    return {
        "title": title,
        "system": system,
        "realization": int(realization),
        "seed": int(seed),
        "forcenet_version": __version__,
        "git_commit": git_commit(),
        "config_sha256": config_sha256(config),
        "config": json.dumps(config, sort_keys=True, default=str),
        "Conventions": CONVENTIONS,
    }


def make_variable(spec: VariableSpec, values: Any, **extra_attrs: Any) -> xr.Variable:
    values = np.asarray(values)
    if values.ndim != len(spec.dims):
        raise SchemaError(f"expected {len(spec.dims)} dims {spec.dims}, got shape {values.shape}")
    return xr.Variable(spec.dims, values, attrs={"units": spec.units, "long_name": spec.long_name, **extra_attrs})


def dataset_from_specs(specs: Mapping[str, VariableSpec], values: Mapping[str, Any],
                       attrs: Mapping[str, Any], coords: Mapping[str, xr.Variable] | None = None) -> xr.Dataset:
    """Build a dataset from named values, attaching units and long_name from `specs`."""
    unknown = set(values) - set(specs)
    if unknown:
        raise SchemaError(f"variables without a schema entry: {sorted(unknown)}")
    missing = set(specs) - set(values)
    if missing:
        raise SchemaError(f"missing variables: {sorted(missing)}")
    data_vars = {name: make_variable(specs[name], values[name]) for name in specs}
    return xr.Dataset(data_vars, coords=coords, attrs=dict(attrs))


def validate_dataset(ds: xr.Dataset) -> None:
    """Raise `SchemaError` unless every variable has units and long_name and the global attrs are present."""
    problems = [f"variable '{name}' lacks '{key}'" for name, var in ds.variables.items()
                for key in ("units", "long_name") if key not in var.attrs]
    problems += [f"global attribute '{key}' missing" for key in REQUIRED_GLOBAL_ATTRS if key not in ds.attrs]
    if problems:
        raise SchemaError("; ".join(problems))


def write_netcdf(ds: xr.Dataset, path: str | os.PathLike) -> Path:
    """Validate and write `ds` with zlib compression, atomically: a temporary file in the same directory
    is renamed over `path` only once complete, so a killed job never leaves a file that looks complete."""
    validate_dataset(ds)
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    encoding = {name: {"zlib": True, "complevel": 4} for name, var in ds.variables.items()
                if var.dtype.kind in "fiub" and var.ndim > 0}
    fd, tmp_name = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".tmp", dir=path.parent)
    os.close(fd)
    try:
        ds.to_netcdf(tmp_name, engine="netcdf4", encoding=encoding)
        os.replace(tmp_name, path)
    except BaseException:
        Path(tmp_name).unlink(missing_ok=True)
        raise
    return path


def open_dataset(path: str | os.PathLike) -> xr.Dataset:
    """Open a forcenet file fully into memory (files are small) and close it."""
    with xr.open_dataset(path, engine="netcdf4") as ds:
        return ds.load()
