"""Which reader reads a config system's ``source:`` entry: the states of one run (`source_states`, the import job
and `forcenet-check-config`) and the files its import job takes as inputs (`run_files`). Above the readers
(`lammps`, `table`) and `scan`, which share the primitives of `common`."""
from __future__ import annotations

from typing import Any, Mapping

from forcenet.importers import lammps, table
from forcenet.importers.common import SourceError, SourceState
from forcenet.importers.scan import record_path, run_paths


def source_states(entry: Mapping[str, Any], realization: int, *, where: str = "source") -> list[SourceState]:
    """Every state of one run (`realization`) of a config system's ``source:`` entry, read by its format's reader,
    in the order the source gives them."""
    source, dimension = entry["source"], int(entry["dimension"])
    run = source["runs"][realization]
    if source["format"] == "table":
        return table.read_run(run, dimension, source)
    if source["format"] == "lammps":
        return lammps.read_run(run, dimension, source)
    raise SourceError(where, "", f"unknown format {source['format']!r}")


def run_files(entry: Mapping[str, Any], realization: int) -> list[str]:
    """The inputs of the import job of one run of a ``source:`` entry: its source files and the record of each
    (`forcenet.importers.scan`, written when the workflow parsed the config; listed where it exists), whose
    modification time moves when the file's size or modification time changes, so that a file replaced under an
    older modification time is imported again."""
    files = run_paths(entry, realization)
    return files + [str(record) for record in map(record_path, files) if record.exists()]
