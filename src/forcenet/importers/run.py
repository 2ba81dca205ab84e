"""One imported run → its contract snapshots (rule ``import_{system}``, `forcenet.pipeline.import_states`)."""
from __future__ import annotations

import json
from typing import Any, Mapping, Sequence

import numpy as np

from forcenet.boxes import P1_OVERLAP_BOUND
from forcenet.importers.common import SourceError, file_sha256, largest_relative_overlap

#: the snapshot variables in the source's length and force units (`forcenet.importers.sequence.unit`)
LENGTH_VARIABLES = ("position", "radius", "box_lo", "box_hi")
FORCE_VARIABLES = ("force_normal", "force_tangential", "wall_contact_force", "contact_force_disagreement")


def import_run(*, config: Mapping[str, Any], system: str, realization: int, outputs: Sequence[str],
               log=None) -> list[str]:
    """Read every state of run `realization` of `system`'s ``source:`` and write one snapshot per state to
    `outputs` (in the source's order: increasing ρ, or a sequence's coordinate, which each snapshot then records). Every state is read and checked against the snapshot
    contract before the first file is written: a malformed source writes nothing."""
    from forcenet.datasets import provenance_attrs
    from forcenet.datasets.io import DatasetError, schema_problems, write_netcdf
    from forcenet.datasets.schema import (BOX_TILT_ATTR, PERIODIC_AXES_ATTR, SOURCE_FORMAT_ATTR, STATE_COORDINATE_ATTR,
                                          STATE_UNITS_ATTR, STATE_VALUE_ATTR)
    from forcenet.datasets.snapshot import snapshot_dataset

    from forcenet.importers.sequence import coordinate, coordinate_units, unit
    from forcenet.importers.system import UndeclaredStates, checked_run, imported_system, measured_labels

    entry = config["systems"][system]
    try:
        spec = imported_system(system, entry)
    except UndeclaredStates:  # a direct call (the workflow refuses such a config before any job): the files' own ρ
        spec = imported_system(system, {**entry, "rho": measured_labels(system, entry)})
    # every state read and checked against the states the config declares (their number, ρ or coordinate)
    states, values = checked_run(system, entry, spec, realization)
    if len(outputs) != len(states):
        raise SourceError(f"systems.{system}.source.runs[{realization}]", "",
                          f"{len(states)} states for {len(outputs)} outputs: the rule's outputs are the declared states")

    hashes: dict[str, str] = {}
    datasets = []
    for k, (state, output) in enumerate(zip(states, outputs)):
        overlap, contact = largest_relative_overlap(state)
        if overlap > P1_OVERLAP_BOUND and log is not None:
            log.warning("%s: timestep %s has overlaps up to %.1f %% of the sum of the radii (particles %d and %d), "
                        "past the %.0f %% P1 states: check the source's units and radii", state.files[0],
                        state.timestep, 100 * overlap, state.contact_i[contact], state.contact_j[contact],
                        100 * P1_OVERLAP_BOUND)
        if state.force_disagreement is not None and log is not None:
            merged = np.isfinite(state.force_disagreement)
            log.info("%s: timestep %s: %d of %d contacts given once from each side, merged into the mean of their two "
                     "estimates (source.duplicate_contacts: mean); their disagreement |F_a - F_b| at most %.4g, "
                     "recorded as contact_force_disagreement", state.files[-1], state.timestep, int(merged.sum()),
                     len(merged), float(np.max(state.force_disagreement[merged], initial=0.0)))
        attrs = provenance_attrs(system=system, realization=realization, seed=-1, config=config,
                                 title=f"forcenet snapshot imported from {entry['source']['format']}, {system}")
        attrs.update({SOURCE_FORMAT_ATTR: entry["source"]["format"],
                      "source_files": json.dumps(list(state.files)),
                      "source_sha256": json.dumps([hashes.setdefault(f, file_sha256(f)) for f in state.files]),
                      "source_timestep": int(state.timestep)})
        if values is not None:  # absent for a compression, as in our engine's snapshots
            attrs.update({STATE_COORDINATE_ATTR: coordinate(entry), STATE_VALUE_ATTR: values[k],
                          STATE_UNITS_ATTR: coordinate_units(entry)})
        if state.periodic_axes:  # absent for a bounded box, as in our engine's snapshots
            attrs[PERIODIC_AXES_ATTR] = state.periodic_axes
        if state.tilt is not None:  # absent for an orthogonal box
            attrs[BOX_TILT_ATTR] = np.asarray(state.tilt, dtype=float)
        ds = snapshot_dataset(attrs=attrs, **state.snapshot_arrays())
        for names, quantity in ((LENGTH_VARIABLES, "length"), (FORCE_VARIABLES, "force")):
            for name in names:  # the source's units (systems.<name>.units), never the engine's reduced ones
                if name in ds.variables:  # contact_force_disagreement: only under source.duplicate_contacts
                    ds[name].attrs["units"] = unit(entry, quantity)
        problems = schema_problems(ds, "snapshot")
        if problems:
            raise DatasetError(state.files[0], f"timestep {state.timestep} breaks the snapshot contract: "
                                               + "; ".join(problems))
        datasets.append(ds)
    for ds, output in zip(datasets, outputs):
        write_netcdf(ds, output, kind="snapshot")
        if log is not None:
            log.info("%s: imported timestep %s of %s, rho %.4f, %d particles, %d contacts", output,
                     ds.attrs["source_timestep"], ", ".join(json.loads(ds.attrs["source_files"])), float(ds.rho),
                     ds.sizes["particle"], ds.sizes["contact"])
    return list(outputs)
