"""Writing and reading forcenet netCDF files: provenance, compression, atomic replacement, validation."""
from __future__ import annotations

import json
import os
import secrets
import subprocess
from functools import lru_cache
from pathlib import Path
from typing import Any, Mapping

import numpy as np
import xarray as xr

from forcenet.datasets.schema import DTYPE_KINDS, FILE_KINDS, REQUIRED_GLOBAL_ATTRS, VariableSpec
from forcenet.errors import ForcenetError

CONVENTIONS = "CF-1.10"


class SchemaError(ForcenetError, ValueError):
    """A dataset does not follow the forcenet data model (missing units, long_name or attrs)."""


class DatasetError(SchemaError):
    """A file the pipeline reads is unreadable or not of its kind; the message names the file and what is wrong."""

    def __init__(self, path: str | os.PathLike, problem: str):
        super().__init__(f"{path}: {problem}")
        self.path = str(path)


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
    """Global attributes every forcenet file carries (`schema.REQUIRED_GLOBAL_ATTRS`): its config, seed, version
    and commit."""
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


def schema_problems(ds: xr.Dataset, kind: str | None = None) -> list[str]:
    """What keeps `ds` from being a forcenet file (of `kind`, a key of `schema.FILE_KINDS`, when given): every
    variable needs units and long_name and every file the provenance attributes; a file of a kind needs each of
    its variables with the declared dims and value type, and the coordinates a reader selects on."""
    problems = []
    if kind is not None:
        variables, coordinates = FILE_KINDS[kind]
        for name, spec in variables.items():
            if name not in ds.variables:
                problems.append(f"variable '{name}' missing")
                continue
            var = ds.variables[name]
            if tuple(var.dims) != spec.dims:
                problems.append(f"variable '{name}' has dims {tuple(var.dims)}, expected {spec.dims}")
            if var.dtype.kind not in DTYPE_KINDS[spec.dtype]:
                problems.append(f"variable '{name}' is {var.dtype}, expected {spec.dtype}")
        problems += [f"coordinate '{name}' missing" for name in coordinates if name not in ds.coords]
    problems += [f"variable '{name}' lacks '{key}'" for name, var in ds.variables.items()
                 for key in ("units", "long_name") if key not in var.attrs]
    problems += [f"global attribute '{key}' missing" for key in REQUIRED_GLOBAL_ATTRS if key not in ds.attrs]
    return problems


def validate_dataset(ds: xr.Dataset, kind: str | None = None) -> None:
    """Raise `SchemaError` listing every problem `schema_problems` finds."""
    problems = schema_problems(ds, kind)
    if problems:
        raise SchemaError("; ".join(problems))


def _new_private_name(path: Path) -> Path:
    """A fresh file next to `path`, created with mode 0666 masked by the umask (as open() would), never
    mkstemp's 0600: outputs must be readable by whoever the user's umask lets read them."""
    while True:
        candidate = path.with_name(f".{path.name}.{secrets.token_hex(4)}.tmp")
        try:
            os.close(os.open(candidate, os.O_CREAT | os.O_EXCL | os.O_WRONLY, 0o666))
            return candidate
        except FileExistsError:
            continue


def write_netcdf(ds: xr.Dataset, path: str | os.PathLike, kind: str | None = None) -> Path:
    """Validate (against `kind`'s schema when given) and write `ds` with zlib compression, atomically: a temporary
    file in the same directory is renamed over `path` only once complete, so a killed job never leaves a file that
    looks complete. The file's mode follows the umask like any other output's."""
    validate_dataset(ds, kind)
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    encoding = {name: {"zlib": True, "complevel": 4} for name, var in ds.variables.items()
                if var.dtype.kind in "fiub" and var.ndim > 0}
    tmp_name = _new_private_name(path)
    try:
        ds.to_netcdf(tmp_name, engine="netcdf4", encoding=encoding)
        os.replace(tmp_name, path)
    except BaseException:
        Path(tmp_name).unlink(missing_ok=True)
        raise
    return path


def open_dataset(path: str | os.PathLike) -> xr.Dataset:
    """Open a forcenet file fully into memory (files are small) and close it; no schema check (`read_dataset`)."""
    with xr.open_dataset(path, engine="netcdf4") as ds:
        return ds.load()


def read_dataset(path: str | os.PathLike, kind: str) -> xr.Dataset:
    """Open a file the pipeline reads and check it against the schema of its `kind` (`schema.FILE_KINDS`).

    Raises `DatasetError` with one line naming the file and every problem: unreadable (missing, truncated, not
    netCDF), a missing variable or coordinate, wrong dims or value type, missing units or provenance."""
    try:
        ds = open_dataset(path)
    except Exception as error:  # netCDF4/HDF5 raise OSError, RuntimeError, ValueError or KeyError for bad files
        reason = str(error).strip().splitlines()[0] if str(error).strip() else type(error).__name__
        raise DatasetError(path, f"cannot be read as netCDF ({reason})") from None
    problems = schema_problems(ds, kind)
    if problems:
        raise DatasetError(path, f"not a valid {kind} file: " + "; ".join(problems))
    return ds
