"""Campaign records: a finished compression run in one compact file (kind "run_record", `schema.RECORD_VARIABLES`).

A paper-size run is hours of DEM; its snapshots are what every analysis, figure and table is computed from. A record
keeps them in the repository (data/validation/, `forcenet.campaign`), so that a run is made once: the build restores
its snapshots from the record (`restore_snapshots`) and analyses them as if it had just simulated them.

What a record keeps of each snapshot: everything the snapshot contract requires (positions, radii, contacts with
their normal and tangential force vectors, wall contacts, box, ρ, Z) and the scalar dynamics (kinetic energy,
pressure, time, step, relaxation steps), so a restored snapshot equals the simulated one in every value it holds, bit
for bit. The contact force vectors are stored along each contact's own axes (`forcenet.datasets.force_codec`: a
normal component, d − 1 tangential ones and exact bit-pattern residuals), about 60 % of their bytes as raw vectors.
It drops the per-particle velocities and angular velocities (`DROPPED_VARIABLES`): optional in the contract, read by
no analysis, and a third of a 2D snapshot's bytes. Radii are stored once (a run's radii do not change;
`record_dataset` checks it), contacts as CF contiguous ragged arrays.

A P2 run (kind "p2_run_record", `p2_record_dataset`) does not fit as states: its record holds the run's summary
(`forcenet.report.p2_distances.run_summary`: distances under each never-dying convention, Z, never-dying class and
diagram point counts of every state) and only the states Tables I-III can read, stored as above; `restore_p2_run`
writes the summary and those snapshots back.
"""
from __future__ import annotations

import json
from pathlib import Path
from typing import Any, Mapping, Sequence

import numpy as np
import xarray as xr

from forcenet.datasets.force_codec import decode_forces, encode_forces
from forcenet.datasets.io import DatasetError, dataset_from_specs, read_dataset
from forcenet.datasets.schema import (FORCE_STORAGE, P2_RUN_VARIABLES, RECORD_VARIABLES, REQUIRED_GLOBAL_ATTRS,
                                      SNAPSHOT_DYNAMICS, SNAPSHOT_VARIABLES)
from forcenet.datasets.snapshot import write_snapshot

#: the record layout this module writes and reads (global attribute `record_format`)
RECORD_FORMAT = "forcenet-run-record-2"
#: the layout of a P2 run's record (kind "p2_run_record")
P2_RECORD_FORMAT = "forcenet-p2-run-record-2"
#: global attributes of a P2 run summary that its record keeps (the networks its diagrams were made of)
P2_SUMMARY_ATTRS = ("rattler_rule", "rattler_rule_description", "flag_complex", "flag_complex_description")
#: snapshot variables a record does not keep (restored snapshots lack them; the contract makes them optional)
DROPPED_VARIABLES = ("velocity", "angular_velocity")
#: global attributes every snapshot of one run shares; the others may differ from state to state (kept per state in
#: `state_attrs`): λΔt of each state (`dem_damping_rate_time_step`), the commit of a run resumed under a later one
IDENTITY_ATTRS = ("system", "realization", "seed", "dimension", "source_format")
#: the scalar variables of a snapshot (one value per state in a record)
SCALAR_VARIABLES = tuple(name for name, spec in SNAPSHOT_VARIABLES.items() if spec.dims == ())
#: ragged groups: the count variable of each and the per-entry variables it counts
RAGGED = {"contact_count": ("contact_i", "contact_j", *FORCE_STORAGE),
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
    stored = [encode_forces(s["position"].values, s["contact_i"].values, s["contact_j"].values,
                            s["force_normal"].values, s["force_tangential"].values) for s in snapshots]
    for count, members in RAGGED.items():
        values[count] = np.array([s.sizes[SNAPSHOT_VARIABLES[members[0]].dims[0]] for s in snapshots], dtype=np.int64)
        for name in members:
            values[name] = np.concatenate([forces[name] if name in FORCE_STORAGE else s[name].values
                                           for s, forces in zip(snapshots, stored)])
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
    stored = {name: arrays.pop(name) for name in FORCE_STORAGE}
    arrays["force_normal"], arrays["force_tangential"] = decode_forces(arrays["position"], arrays["contact_i"],
                                                                       arrays["contact_j"], stored)
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


def record_global_problems(record: xr.Dataset, expected: str = RECORD_FORMAT) -> list[str]:
    """A record format this forcenet does not read (its attributes are checked with its kind, `schema.KIND_GLOBAL_ATTRS`,
    when it is read); `expected` is `P2_RECORD_FORMAT` for a P2 run's record."""
    if record.attrs["record_format"] != expected:
        return [f"record_format is '{record.attrs['record_format']}', this forcenet reads '{expected}'"]
    return []


def p2_record_dataset(summary: xr.Dataset, snapshots: Sequence[xr.Dataset], labels: Sequence[str],
                      kept: Sequence[int], *, simulation_sha256: str, cpu_seconds: float, title: str) -> xr.Dataset:
    """The record of one P2 run: its `summary` (kind "p2_run") and the states `kept` (indices into the run's
    `snapshots`, labelled by `labels`, in grid order) as `record_dataset` stores them; none kept leaves out every
    state variable. Raises `RecordError` when the summary is of another run or another grid."""
    if len(snapshots) != len(labels) or summary.sizes["grid_state"] != len(labels):
        raise RecordError("record", f"{len(snapshots)} snapshots, {len(labels)} labels and a summary of "
                                    f"{summary.sizes['grid_state']} states: not one run")
    if summary.attrs["simulation_sha256"] != simulation_sha256 or any(
            str(summary.attrs[key]) != str(snapshots[0].attrs[key]) for key in ("system", "realization")):
        raise RecordError("record", "the summary is of another run than the snapshots")
    if kept:
        base = record_dataset([snapshots[i] for i in kept], [labels[i] for i in kept],
                              simulation_sha256=simulation_sha256, cpu_seconds=cpu_seconds, title=title)
    else:
        first = snapshots[0]
        base = xr.Dataset(attrs={**{key: first.attrs[key] for key in REQUIRED_GLOBAL_ATTRS}, "title": title,
                                 "simulation_sha256": simulation_sha256, "cpu_seconds": float(cpu_seconds),
                                 "dimension": int(first.attrs["dimension"]), "snapshot_attrs": "{}",
                                 "state_attrs": "[]", "dropped_variables": " ".join(DROPPED_VARIABLES)})
    record = xr.merge([summary[list(P2_RUN_VARIABLES)], base], combine_attrs="override")
    record.attrs = {**base.attrs, "record_format": P2_RECORD_FORMAT, "grid_labels": " ".join(labels),
                    **{key: summary.attrs[key] for key in P2_SUMMARY_ATTRS}}
    return record


def p2_record_summary(record: xr.Dataset) -> xr.Dataset:
    """The run summary (kind "p2_run") a P2 run record holds, as the run's analyses gave it."""
    summary = record[list(P2_RUN_VARIABLES)].drop_dims(["state", "particle", "contact", "wall_contact", "spatial"],
                                                       errors="ignore")
    summary.attrs = {**{key: record.attrs[key] for key in REQUIRED_GLOBAL_ATTRS},
                     "dimension": int(record.attrs["dimension"]),
                     "simulation_sha256": record.attrs["simulation_sha256"],
                     **{key: record.attrs[key] for key in P2_SUMMARY_ATTRS}}
    return summary


def p2_record_labels(record: xr.Dataset) -> list[str]:
    """The grid labels of the states a P2 run record keeps (none for the frictionless system's)."""
    return [str(label) for label in record["state"].values] if "state" in record.coords else []


def restore_p2_run(record_path: str | Path, summary_output: str | Path, outputs: Sequence[str | Path],
                   conventions: Sequence[str]) -> list[Path]:
    """Write a P2 run's summary (`summary_output`, kind "p2_run") and the snapshots `outputs` from its record: each
    output named by a state the record keeps (`rho{label}.nc`). Raises `RecordError` naming the record when it
    lacks a never-dying convention of `conventions` or a state of `outputs`."""
    from forcenet.datasets.io import write_netcdf

    record = read_dataset(record_path, "p2_run_record")
    held = [str(c) for c in record["essential_convention"].values]
    missing = [c for c in conventions if c not in held]
    if missing:
        raise RecordError(record_path, f"holds distances under the never-dying conventions {held}, not under "
                                       f"{missing}: the run must be made again, its states not being kept (forcenet-campaign drop, then "
                                       "run)")
    labels = p2_record_labels(record)
    written = []
    for output in outputs:
        label = Path(output).name.removeprefix("rho").removesuffix(".nc")
        if label not in labels:
            raise RecordError(record_path, f"keeps the states {labels}, not {Path(output).name}")
        attrs, arrays = state_snapshot(record, labels.index(label))
        written.append(write_snapshot(output, attrs=attrs, **arrays))
    summary = p2_record_summary(record)
    write_netcdf(summary, summary_output, kind="p2_run")
    return [*written, Path(summary_output)]


def record_encoding(record: xr.Dataset) -> dict[str, Mapping[str, Any]]:
    """The netCDF encoding of every array of `record` (`RECORD_ENCODING`)."""
    return {name: dict(RECORD_ENCODING) for name, var in record.variables.items()
            if var.dtype.kind in "fiu" and var.ndim > 0}


#: the earlier record layouts `recoded_record` converts: the contact forces as raw float64 vectors
EARLIER_FORMATS = {"forcenet-run-record-1": RECORD_FORMAT, "forcenet-p2-run-record-1": P2_RECORD_FORMAT}


def recoded_record(record: xr.Dataset) -> xr.Dataset:
    """A record of an earlier layout (`EARLIER_FORMATS`) in this one, every state giving back the same values bit
    for bit (checked: raises `RecordError` otherwise); a record of this layout is returned as it is."""
    layout = str(record.attrs["record_format"])
    if layout not in EARLIER_FORMATS:
        return record
    recoded = record.drop_vars(["force_normal", "force_tangential"], errors="ignore")
    recoded.attrs = {**record.attrs, "record_format": EARLIER_FORMATS[layout]}
    if "force_normal" not in record:  # a P2 record that keeps no state
        return recoded
    starts = np.concatenate([[0], np.cumsum(record["contact_count"].values)])
    stored = [encode_forces(record["position"].values[index], *(record[name].values[start:stop] for name in
                                                                 ("contact_i", "contact_j", "force_normal",
                                                                  "force_tangential")))
              for index, (start, stop) in enumerate(zip(starts[:-1], starts[1:]))]
    for name in FORCE_STORAGE:
        spec = RECORD_VARIABLES[name]
        recoded[name] = xr.Variable(spec.dims, np.concatenate([forces[name] for forces in stored]),
                                    attrs={"units": spec.units, "long_name": spec.long_name})
    for index, (start, stop) in enumerate(zip(starts[:-1], starts[1:])):
        _, arrays = state_snapshot(recoded, index)
        for name in ("force_normal", "force_tangential"):
            if not np.array_equal(arrays[name].view(np.int64), record[name].values[start:stop].view(np.int64)):
                raise RecordError("record", f"state {index}: '{name}' would not be given back bit for bit")
    return recoded
