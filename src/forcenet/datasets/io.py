"""Writing and reading forcenet netCDF files: provenance, compression, atomic replacement, validation."""
from __future__ import annotations

import contextlib
import json
import os
import secrets
import signal
import subprocess
import threading
from functools import lru_cache
from pathlib import Path
from typing import Any, Mapping

import numpy as np
import xarray as xr

from forcenet.boxes import tilt_problem
from forcenet.datasets.runs import config_sha256, run_mismatch
from forcenet.datasets.schema import (ANALYSIS_FINITE_VARIABLES, BOX_TILT_ATTR, DTYPE_KINDS, ENGINE_SOURCE_FORMAT,
                                      FILE_KINDS, KIND_GLOBAL_ATTRS, OPTIONAL_GLOBAL_ATTRS, OPTIONAL_VARIABLES,
                                      PERIODIC_AXES_ATTR, REQUIRED_GLOBAL_ATTRS, SNAPSHOT_FINITE_VARIABLES,
                                      SNAPSHOT_GLOBAL_ATTRS, SNAPSHOT_SOURCE_ATTRS, SOURCE_FORMAT_ATTR,
                                      STATE_COORDINATE_ATTR, STATE_COORDINATE_LONG_NAMES, STATE_UNITS_ATTR,
                                      VariableSpec)
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


def optional_attr(ds: xr.Dataset, name: str) -> Any:
    """The global attribute `name` of `ds`, or, where the file lacks it, what that means (`schema.
    OPTIONAL_GLOBAL_ATTRS`: a compression's state axis ρ, an engine's snapshot, a bounded orthogonal box). The one
    reader of an attribute a file may lack; KeyError for any other: a kind's required attribute is read as
    ``ds.attrs[name]``, the validated read (`read_dataset`) having refused a file without it."""
    if name not in OPTIONAL_GLOBAL_ATTRS:
        raise KeyError(f"global attribute '{name}' is not optional (schema.OPTIONAL_GLOBAL_ATTRS): a reader indexes it")
    return ds.attrs.get(name, OPTIONAL_GLOBAL_ATTRS[name])


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
        optional = OPTIONAL_VARIABLES.get(kind, ())
        for name, spec in variables.items():
            if name not in ds.variables:
                if name not in optional:
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
    if kind is not None:  # the kind's own (the snapshot's dimension is checked with its values)
        problems += [f"global attribute '{key}' missing" for key in KIND_GLOBAL_ATTRS.get(kind, ())
                     if key not in ds.attrs and not (kind == "snapshot" and key in SNAPSHOT_GLOBAL_ATTRS)]
    if not problems and kind in VALUE_CHECKS:  # values only once the structure is right
        problems += VALUE_CHECKS[kind](ds)
    return problems


def _nonfinite(ds: xr.Dataset, name: str, allowed: np.ndarray | None = None) -> list[str]:
    """"variable 'name' has a NaN or infinite value at <dim> <index>" for the first such value (none: [])."""
    values = np.asarray(ds[name].values, dtype=float)
    bad = ~np.isfinite(values)
    if allowed is not None:
        bad &= ~allowed
    if not bad.any():
        return []
    where = np.unravel_index(int(np.argmax(bad)), values.shape) if values.ndim else ()
    at = ", ".join(f"{dim} {index}" for dim, index in zip(ds[name].dims, where))
    return [f"variable '{name}' has a NaN or infinite value{' at ' + at if at else ''}"]


def snapshot_value_problems(ds: xr.Dataset) -> list[str]:
    """What breaks the snapshot contract in the values (`schema`: the snapshot contract): the `dimension` attribute
    (2 or 3, the size of `spatial`), an imported snapshot's source provenance, non-finite positions, radii, forces,
    box or ρ, a radius ≤ 0, contact or wall indices naming no particle or wall, a box with box_hi ≤ box_lo, tilt
    factors (`schema.BOX_TILT_ATTR`) of the wrong number, non-finite or along a bounded axis."""
    problems = [f"global attribute '{key}' missing" for key in SNAPSHOT_GLOBAL_ATTRS if key not in ds.attrs]
    source = optional_attr(ds, SOURCE_FORMAT_ATTR)
    if source != ENGINE_SOURCE_FORMAT:
        problems += [f"global attribute '{key}' missing (imported snapshot, {SOURCE_FORMAT_ATTR} '{source}')"
                     for key in SNAPSHOT_SOURCE_ATTRS if key not in ds.attrs]
    if problems:
        return problems
    spatial = ds.sizes["spatial"]
    try:
        dimension = int(ds.attrs["dimension"])
    except (TypeError, ValueError):
        dimension = -1
    if dimension not in (2, 3) or dimension != spatial:
        return [f"global attribute 'dimension' is {ds.attrs['dimension']}, but the positions have {spatial} "
                "components"]
    for name in SNAPSHOT_FINITE_VARIABLES:
        problems += _nonfinite(ds, name)
    if problems:
        return problems
    radius = ds["radius"].values
    if np.any(radius <= 0):
        problems.append(f"variable 'radius' is not positive at particle {int(np.argmax(radius <= 0))} "
                        f"({float(radius[np.argmax(radius <= 0)])!r})")
    n = ds.sizes["particle"]
    for name in ("contact_i", "contact_j", "wall_contact_particle"):
        values = ds[name].values
        outside = (values < 0) | (values >= n)
        if outside.any():
            k = int(np.argmax(outside))
            problems.append(f"variable '{name}' names particle {int(values[k])} at {ds[name].dims[0]} {k}, but there "
                            f"are {n} particles")
    same = ds["contact_i"].values == ds["contact_j"].values
    if same.any():
        problems.append(f"variables 'contact_i', 'contact_j': particle {int(ds['contact_i'].values[np.argmax(same)])} "
                        f"in contact with itself at contact {int(np.argmax(same))}")
    walls = ds["wall_contact_wall"].values
    if np.any((walls < 0) | (walls >= 2 * dimension)):
        problems.append(f"variable 'wall_contact_wall' has a wall id outside 0 … {2 * dimension - 1}")
    if np.any(ds["box_hi"].values <= ds["box_lo"].values):
        problems.append("variables 'box_lo', 'box_hi': box_hi must exceed box_lo on every axis")
    if BOX_TILT_ATTR in ds.attrs:
        tilt = tilt_problem(str(optional_attr(ds, PERIODIC_AXES_ATTR)), ds.attrs[BOX_TILT_ATTR], dimension)
        if tilt:
            problems.append(f"global attribute '{BOX_TILT_ATTR}': {tilt}")
    return problems


def analysis_value_problems(ds: xr.Dataset) -> list[str]:
    """Non-finite values where an analysis file must have finite ones (`schema.ANALYSIS_FINITE_VARIABLES`; `death`
    is −inf exactly where `essential` is 1)."""
    problems = []
    for name in ANALYSIS_FINITE_VARIABLES:
        problems += _nonfinite(ds, name)
    death = np.asarray(ds["death"].values, dtype=float)
    problems += _nonfinite(ds, "death", allowed=(death == -np.inf) & (ds["essential"].values == 1))
    return problems


#: file kind → the checks of its values (run by `schema_problems` once the variables are there)
VALUE_CHECKS = {"snapshot": snapshot_value_problems, "analysis": analysis_value_problems}


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


def sequence_on_disk(ds: xr.Dataset) -> xr.Dataset:
    """`ds` as a file of a sequence (`schema.STATE_COORDINATE_ATTR`: an imported run ordered by strain, time, frame or
    timestep) stores it: its state axis `rho` (in memory, where every reader selects on it) named after the
    coordinate, with the coordinate's unit and long name, and `point_rho` likewise; ρ stays `rho_measured`. Any
    other dataset is returned as it is."""
    name = optional_attr(ds, STATE_COORDINATE_ATTR)
    if name == "rho" or "rho" not in ds.dims:
        return ds
    out = ds.rename({"rho": name, **({"point_rho": f"point_{name}"} if "point_rho" in ds.variables else {})})
    units = str(optional_attr(ds, STATE_UNITS_ATTR))
    out[name].attrs = {"units": units, "long_name": STATE_COORDINATE_LONG_NAMES.get(name, name)}
    if f"point_{name}" in out.variables:
        out[f"point_{name}"].attrs = {"units": units,
                                      "long_name": f"{STATE_COORDINATE_LONG_NAMES.get(name, name)} of the point"}
    return out


def sequence_in_memory(ds: xr.Dataset) -> xr.Dataset:
    """A file of a sequence as the readers take it (`sequence_on_disk` undone): its state axis renamed `rho`."""
    name = optional_attr(ds, STATE_COORDINATE_ATTR)
    if name == "rho" or name not in ds.dims:
        return ds
    point = f"point_{name}"
    return ds.rename({name: "rho", **({point: "point_rho"} if point in ds.variables else {})})


def write_netcdf(ds: xr.Dataset, path: str | os.PathLike, kind: str | None = None,
                 encoding: Mapping[str, Mapping[str, Any]] | None = None) -> Path:
    """Validate (against `kind`'s schema when given) and write `ds` with zlib compression, atomically: a temporary
    file in the same directory is renamed over `path` only once complete, so a killed job never leaves a file that
    looks complete. `encoding` replaces the default (zlib level 4) of the variables it names (a campaign record's
    level 9 with byte shuffle). The file's mode follows the umask like any other output's. A dataset that breaks the schema
    (values included: a NaN force in a snapshot) raises `DatasetError` naming `path`, and nothing is written. A
    Ctrl-C during the write takes effect once it is over (`interrupts_deferred`): no lock held, no partial file."""
    problems = schema_problems(ds, kind)
    if problems:
        raise DatasetError(path, f"not written, not a valid {kind or 'forcenet'} file: " + "; ".join(problems))
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    ds = sequence_on_disk(ds)
    encoding = {**{name: {"zlib": True, "complevel": 4} for name, var in ds.variables.items()
                   if var.dtype.kind in "fiub" and var.ndim > 0}, **(encoding or {})}
    with interrupts_deferred():
        tmp_name = _new_private_name(path)
        try:
            ds.to_netcdf(tmp_name, engine="netcdf4", encoding=encoding)
            os.replace(tmp_name, path)
        except BaseException:
            Path(tmp_name).unlink(missing_ok=True)
            raise
    return path


@contextlib.contextmanager
def interrupts_deferred():
    """Hold back SIGINT (Ctrl-C, and what Snakemake sends its local jobs) while xarray holds its netCDF/HDF5 lock,
    and deliver it once the block is done (a write: renamed into place or its temporary file removed).

    Why: xarray takes two locks in turn (netCDF4_.NETCDF4_PYTHON_LOCK, a CombinedLock). A KeyboardInterrupt raised
    between the two acquisitions leaves the first held, and the close that follows in xarray's cleanup waits on it
    for ever: 5 of 20 Ctrl-Cs in issue 57's loop hung a job until a second Ctrl-C. A file is written or read in well
    under a second, so the first Ctrl-C still ends the run within seconds. Outside the main thread (where Python
    runs signal handlers) the block runs as it is."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    received: list[tuple[int, Any]] = []
    previous = signal.signal(signal.SIGINT, lambda signum, frame: received.append((signum, frame)))
    try:
        yield
    finally:
        signal.signal(signal.SIGINT, signal.SIG_DFL if previous is None else previous)  # None: set outside Python
        if received:
            if callable(previous):  # Python's default_int_handler raises KeyboardInterrupt here
                previous(*received[0])
            elif previous == signal.SIG_DFL:
                os.kill(os.getpid(), signal.SIGINT)


def open_dataset(path: str | os.PathLike) -> xr.Dataset:
    """Open a forcenet file fully into memory (files are small) and close it; no schema check (`read_dataset`).
    A Ctrl-C arriving meanwhile is delivered once the file is closed (`interrupts_deferred`)."""
    with interrupts_deferred(), xr.open_dataset(path, engine="netcdf4") as ds:
        return ds.load()


def read_dataset(path: str | os.PathLike, kind: str, expect: Mapping[str, Any] | None = None) -> xr.Dataset:
    """Open a file the pipeline reads and check it against the schema of its `kind` (`schema.FILE_KINDS`).

    Raises `DatasetError` with one line naming the file and every problem: unreadable (missing, truncated, not
    netCDF), a missing variable or coordinate, wrong dims or value type, missing units or provenance, values the
    kind forbids (`VALUE_CHECKS`: NaN or infinite positions, radii or forces …). With `expect`
    (`forcenet.datasets.runs.run_expectation`), a file recorded for another run is refused as well."""
    try:
        ds = open_dataset(path)
    except Exception as error:  # netCDF4/HDF5 raise OSError, RuntimeError, ValueError or KeyError for bad files
        reason = str(error).strip().splitlines()[0] if str(error).strip() else type(error).__name__
        raise DatasetError(path, f"cannot be read as netCDF ({reason})") from None
    ds = sequence_in_memory(ds)
    problems = schema_problems(ds, kind)
    if problems:
        raise DatasetError(path, f"not a valid {kind} file: " + "; ".join(problems))
    if expect is not None:
        problem = run_mismatch(ds, expect)
        if problem:
            raise DatasetError(path, f"not of this run: {problem}")
    return ds
