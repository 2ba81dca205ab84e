"""What the workflow learns of an imported system's source files when it parses its config (every ``snakemake``
call, a dry run included): their paths and sizes, and the number of atoms in a LAMMPS dump's first header, never
their contents.

The states an imported run has (their ρ, or a sequence's coordinate: the names of its snapshots) come from the
config (`forcenet.importers.system.imported_system`); the import job reads every file in full and checks it against
them (`forcenet.importers.system.checked_run`). Here each source file is checked to exist, to be a file and not to be
empty (`checked_size`), and a small record of its status is kept (`record_path`, in `record_dir`): its path, size
and modification time. The record is an input of the import job (`forcenet.importers.run_files`), and its own
modification time moves when the file's size or modification time changes: a source replaced by other content with
an older modification time (copied with ``cp -p``, unpacked from an archive) is imported again, which Snakemake's
comparison of times alone missed. A record first written for a file gets the file's own modification time, so
outputs made before records existed stay up to date. `first_state_particles` reads the first lines of run 0's
particles file (the cost model's job size): a bounded read, whatever the file's length.
"""
from __future__ import annotations

import hashlib
import itertools
import json
import os
import stat
import time
from pathlib import Path
from typing import Any, Mapping

from forcenet.importers.common import SourceError, source_lines

#: the environment variable naming the folder of the records (default `DEFAULT_RECORD_DIR`, below the working
#: directory: Snakemake's own folder, which ``--directory`` moves with the run)
RECORD_DIR_ENV = "FORCENET_SOURCE_RECORDS"
DEFAULT_RECORD_DIR = ".snakemake/forcenet-sources"
#: bumped when what a record holds changes
RECORD_VERSION = 2


def record_dir() -> Path:
    return Path(os.environ.get(RECORD_DIR_ENV, DEFAULT_RECORD_DIR))


def record_path(path: str | Path) -> Path:
    """The record of source file `path`: its name and a hash of the path as the config gives it (two files of one
    name differ; a relative path keeps its record when the working directory is copied or moved, as the records'
    folder is relative to it too)."""
    given = os.path.normpath(path)
    return record_dir() / f"{Path(path).name}.{hashlib.sha256(given.encode()).hexdigest()[:16]}.json"


def checked_size(path: str | Path) -> os.stat_result:
    """The file's status; a missing or empty file, or a folder, raises `SourceError` naming it."""
    try:
        status = os.stat(path)
    except OSError as error:
        raise SourceError(path, "", f"cannot be read ({error.strerror or error})") from None
    if not stat.S_ISREG(status.st_mode):
        raise SourceError(path, "", "not a file (a folder?)")
    if status.st_size == 0:
        raise SourceError(path, "", "empty (0 bytes)")
    return status


def file_record(path: str | Path) -> dict[str, Any]:
    """The record of one source file, {path, size, mtime_ns, version}, from its status alone (`checked_size`: the
    file is not read). Stored when it differs from the stored one; the stored record's modification time is the
    file's own the first time, and now when the file's size or modification time changed (its import job reruns)."""
    status = checked_size(path)
    record = {"path": os.path.normpath(path), "size": status.st_size, "mtime_ns": status.st_mtime_ns,
              "version": RECORD_VERSION}
    stored = record_path(path)
    old = _load(stored)
    if old == record:
        return record
    same_file = old is not None and all(old.get(key) == record[key] for key in ("path", "size", "mtime_ns"))
    # first record: the source's own time (outputs already built stay current); a changed file: now (reimport)
    stamp = (status.st_mtime_ns if old is None else os.stat(stored).st_mtime_ns if same_file else time.time_ns())
    _store(stored, record, stamp)
    return record


def run_paths(entry: Mapping[str, Any], realization: int) -> list[str]:
    """The source files of one run of a ``source:`` entry: a LAMMPS run's atoms and pairs dumps, a table run's
    particles and contacts files of each state, in order."""
    run = entry["source"]["runs"][realization]
    if entry["source"]["format"] == "lammps":
        return [run["atoms"], run["pairs"]]
    return [path for state in run for path in (state["particles"], state["contacts"])]


#: the most a table's particles count is estimated from (bytes of its first lines)
ESTIMATE_BYTES = 1 << 16


def first_state_particles(entry: Mapping[str, Any]) -> int:
    """The particles of run 0's first state, for the cost model, from a bounded read of its particles file: a LAMMPS
    atoms dump's first header (``ITEM: NUMBER OF ATOMS``, exact), a table's rows counted in its first
    `ESTIMATE_BYTES` (exact for a smaller file, else scaled to the file's size). 0 where that read finds no count (a
    header that is not one, a file cut short): the import job reads the file in full and names the problem."""
    run = entry["source"]["runs"][0]
    path = run["atoms"] if entry["source"]["format"] == "lammps" else run[0]["particles"]
    try:
        if entry["source"]["format"] == "lammps":
            head = [text.strip() for _, text in itertools.islice(source_lines(path), 4)]
            known = (len(head) == 4 and head[0] == "ITEM: TIMESTEP" and head[2] == "ITEM: NUMBER OF ATOMS"
                     and head[3].isdigit())
            return int(head[3]) if known else 0
        rows, read = 0, 0
        for _, text in source_lines(path):
            read += len(text) + 1
            rows += bool(text.strip()) and not text.lstrip().startswith("#")
            if read >= ESTIMATE_BYTES:
                return max(1, round((rows - 1) * os.stat(path).st_size / read))
        return max(rows - 1, 0)  # the header is no particle
    except SourceError:
        return 0


def _load(path: Path) -> dict[str, Any] | None:
    try:
        record = json.loads(path.read_text(encoding="utf-8"))
    except (OSError, ValueError):
        return None
    return record if isinstance(record, dict) else None


def _store(path: Path, record: Mapping[str, Any], mtime_ns: int) -> None:
    """Write the record under a temporary name and rename it (a reader never sees half a record), with `mtime_ns`.
    A folder that cannot be written leaves the record unstored: the next call scans again."""
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        temporary = path.with_name(f".{path.name}.{os.getpid()}.tmp")
        temporary.write_text(json.dumps(record, sort_keys=True), encoding="utf-8")
        os.utime(temporary, ns=(mtime_ns, mtime_ns))
        os.replace(temporary, path)
    except OSError:
        pass


