"""Campaign records: a finished compression run in one compact file (kind "run_record", `schema.RECORD_VARIABLES`).

A paper-size run is hours of DEM; its snapshots are what every analysis, figure and table is computed from. A record
keeps them in the repository (data/validation/, `forcenet.campaign`), so that a run is made once: the build restores
its snapshots from the record (`restore_snapshots`) and analyses them as if it had just simulated them.

What a record keeps of each snapshot: everything the snapshot contract requires (positions, radii, contacts with
their normal and tangential force vectors, wall contacts, box, ρ, Z) and the scalar dynamics (kinetic energy,
pressure, time, step, relaxation steps), in float64 as simulated, so a restored snapshot equals the simulated one in
every value it holds. It drops the per-particle velocities and angular velocities (`DROPPED_VARIABLES`): optional in
the contract, read by no analysis, and a third of a 2D snapshot's bytes. Radii are stored once (a run's radii do not
change; `record_dataset` checks it), contacts as CF contiguous ragged arrays.
"""
from __future__ import annotations

import json
from pathlib import Path
from typing import Any, Mapping, Sequence

import numpy as np
import xarray as xr

from forcenet.datasets.io import DatasetError, dataset_from_specs, read_dataset
from forcenet.datasets.schema import RECORD_VARIABLES, REQUIRED_GLOBAL_ATTRS, SNAPSHOT_DYNAMICS, SNAPSHOT_VARIABLES
from forcenet.datasets.snapshot import write_snapshot

#: the record layout this module writes and reads (global attribute `record_format`)
RECORD_FORMAT = "forcenet-run-record-1"
#: snapshot variables a record does not keep (restored snapshots lack them; the contract makes them optional)
DROPPED_VARIABLES = ("velocity", "angular_velocity")
#: global attributes every snapshot of one run shares; the others may differ from state to state (kept per state in
#: `state_attrs`): λΔt of each state (`dem_damping_rate_time_step`), the commit of a run resumed under a later one
IDENTITY_ATTRS = ("system", "realization", "seed", "dimension", "source_format")
#: the scalar variables of a snapshot (one value per state in a record)
SCALAR_VARIABLES = tuple(name for name, spec in SNAPSHOT_VARIABLES.items() if spec.dims == ())
#: ragged groups: the count variable of each and the per-entry variables it counts
RAGGED = {"contact_count": ("contact_i", "contact_j", "force_normal", "force_tangential"),
          "wall_contact_count": ("wall_contact_particle", "wall_contact_wall", "wall_contact_force")}
#: zlib level and byte shuffle of every array of a record (lossless; measured in data/validation/README.md)
RECORD_ENCODING = {"zlib": True, "complevel": 9, "shuffle": True}


class RecordError(DatasetError):
    """A run's snapshots cannot make a record, or a record does not give back its run's snapshots."""


def record_dataset(snapshots: Sequence[xr.Dataset], labels: Sequence[str], *, simulation_sha256: str,
                   cpu_seconds: float, title: str) -> xr.Dataset:
    """The record of one run from its snapshots, in grid order.

    snapshots : the run's snapshot datasets (`forcenet.datasets.read_snapshot`), one per ρ of its grid
    labels : the grid ρ of each as in its file name ("0.840"), the record's `state` coordinate
    simulation_sha256 : the run's fingerprint (`forcenet.datasets.runs.simulation_sha256`)
    cpu_seconds : CPU time of the run summed over every process that ran or resumed it [s]
    Raises `RecordError` when the snapshots are not one run's (other attributes than the first's where a run's
    snapshots agree, other radii or particle count).
    """
    if len(snapshots) != len(labels) or not snapshots:
        raise RecordError("record", f"{len(snapshots)} snapshots for {len(labels)} grid labels")
    first = snapshots[0]
    shared = {key: value for key, value in first.attrs.items()
              if all(key in s.attrs and _same(s.attrs[key], value) for s in snapshots)}
    differing = sorted({key for s in snapshots for key in s.attrs} - set(shared))
    if set(differing) & set(IDENTITY_ATTRS):
        raise RecordError("record", f"the snapshots disagree in global attributes {differing}: not one run")
    radius = first["radius"].values
    for label, snapshot in zip(labels, snapshots):
        if snapshot.sizes["particle"] != radius.size or not np.array_equal(snapshot["radius"].values, radius):
            raise RecordError("record", f"state {label}: other radii than the run's first state")
    values: dict[str, Any] = {
        "radius": radius,
        "position": np.stack([s["position"].values for s in snapshots]),
        "box_lo": np.stack([s["box_lo"].values for s in snapshots]),
        "box_hi": np.stack([s["box_hi"].values for s in snapshots]),
    }
    for name in SCALAR_VARIABLES:
        values[name] = np.array([s[name].values[()] for s in snapshots])
    for count, members in RAGGED.items():
        values[count] = np.array([s.sizes[SNAPSHOT_VARIABLES[members[0]].dims[0]] for s in snapshots], dtype=np.int64)
        for name in members:
            values[name] = np.concatenate([s[name].values for s in snapshots])
    attrs = {key: first.attrs[key] for key in REQUIRED_GLOBAL_ATTRS}
    attrs.update(title=title, record_format=RECORD_FORMAT, simulation_sha256=simulation_sha256,
                 cpu_seconds=float(cpu_seconds), dimension=int(first.attrs["dimension"]),
                 snapshot_attrs=json.dumps(shared, sort_keys=True, default=_plain),
                 state_attrs=json.dumps([{key: s.attrs[key] for key in differing if key in s.attrs}
                                         for s in snapshots], sort_keys=True, default=_plain),
                 dropped_variables=" ".join(DROPPED_VARIABLES))
    coords = {
        "state": xr.Variable(("state",), [str(label) for label in labels],
                             attrs={"units": "1", "long_name": "grid packing fraction of the state (its file label)"}),
        "spatial": xr.Variable(("spatial",), list(first["spatial"].values), attrs=dict(first["spatial"].attrs)),
    }
    return dataset_from_specs(RECORD_VARIABLES, values, attrs, coords=coords)


def _plain(value: Any) -> Any:
    """A netCDF attribute value as JSON takes it (numpy scalars and arrays)."""
    return value.tolist() if isinstance(value, (np.ndarray, np.generic)) else str(value)


def _same(a: Any, b: Any) -> bool:
    return bool(np.array_equal(np.asarray(a), np.asarray(b)))


def state_snapshot(record: xr.Dataset, index: int) -> tuple[dict[str, Any], dict[str, Any]]:
    """(attrs, arrays) of state `index` of `record`: the keyword arguments of `forcenet.datasets.write_snapshot`
    that give back the run's snapshot at that ρ, every kept variable equal to the simulated one."""
    attrs = {**json.loads(record.attrs["snapshot_attrs"]), **json.loads(record.attrs["state_attrs"])[index]}
    arrays: dict[str, Any] = {"radius": record["radius"].values,
                              "position": record["position"].values[index],
                              "box_lo": record["box_lo"].values[index], "box_hi": record["box_hi"].values[index]}
    for name in SCALAR_VARIABLES:
        arrays[name] = record[name].values[index]
    for count, members in RAGGED.items():
        counts = record[count].values
        start = int(counts[:index].sum())
        for name in members:
            arrays[name] = record[name].values[start:start + int(counts[index])]
    return attrs, arrays


def restore_snapshots(record_path: str | Path, outputs: Sequence[str | Path]) -> list[Path]:
    """Write the snapshot files of a record: `outputs` in the record's state order, each named by its state's label
    (`rho{label}.nc`, checked, so a record never lands on another ρ). Each is written atomically through the
    snapshot contract."""
    record = read_dataset(record_path, "run_record")
    labels = [str(label) for label in record["state"].values]
    if len(outputs) != len(labels):
        raise RecordError(record_path, f"holds {len(labels)} states, but the run has {len(outputs)} snapshots")
    written = []
    for index, (label, output) in enumerate(zip(labels, outputs)):
        if Path(output).name != f"rho{label}.nc":
            raise RecordError(record_path, f"state {index} is ρ = {label}, but its output is {output}")
        attrs, arrays = state_snapshot(record, index)
        written.append(write_snapshot(output, attrs=attrs, **arrays))
    return written


def record_differences(record: xr.Dataset, snapshots: Sequence[xr.Dataset]) -> list[str]:
    """Where the snapshots a record gives back differ from the run's own (empty: the record is faithful): every
    kept variable compared value for value (dtype kind and shape too), and the global attributes."""
    problems = []
    if record.sizes["state"] != len(snapshots):
        return [f"{record.sizes['state']} states recorded, {len(snapshots)} snapshots"]
    kept = [name for name in SNAPSHOT_VARIABLES if name not in DROPPED_VARIABLES]
    for index, original in enumerate(snapshots):
        attrs, arrays = state_snapshot(record, index)
        label = str(record["state"].values[index])
        if attrs != json.loads(json.dumps(dict(original.attrs), sort_keys=True, default=_plain)):
            problems.append(f"state {label}: global attributes differ")
        for name in kept:
            if name not in original.variables:
                if name not in SNAPSHOT_DYNAMICS:
                    problems.append(f"state {label}: '{name}' missing from the snapshot")
                continue
            mine, theirs = np.asarray(arrays[name]), original[name].values
            if mine.shape != theirs.shape or mine.dtype.kind != theirs.dtype.kind or not np.array_equal(mine, theirs):
                problems.append(f"state {label}: '{name}' differs")
    return problems


def record_global_problems(record: xr.Dataset) -> list[str]:
    """A record format this forcenet does not read (its attributes are checked with its kind, `schema.KIND_GLOBAL_ATTRS`,
    when it is read)."""
    if record.attrs["record_format"] != RECORD_FORMAT:
        return [f"record_format is '{record.attrs['record_format']}', this forcenet reads '{RECORD_FORMAT}'"]
    return []


def record_encoding(record: xr.Dataset) -> dict[str, Mapping[str, Any]]:
    """The netCDF encoding of every array of `record` (`RECORD_ENCODING`)."""
    return {name: dict(RECORD_ENCODING) for name, var in record.variables.items()
            if var.dtype.kind in "fiu" and var.ndim > 0}
