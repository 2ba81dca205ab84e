"""What the workflow needs of an imported system when it parses its config (every ``snakemake`` call, a dry run
included), read once per source content and then only looked up.

Parsing needs each state's ρ (the label in its snapshot's file name) and the particles of run 0's first state (the
cost model). Those come from the particles alone: a LAMMPS atoms dump (its box bounds and radii, `scan_atoms`) or a
table's particles CSV (`scan_particles`); the pairs and contacts files are only checked to exist and be non-empty.
What a scan finds is kept in a small record per source file (`record_path`, in `record_dir`), with the file's size,
modification time and sha256: a later call whose file has the same size and modification time reads the record, not
the file (issue 57: a 2-million-line dump cost 24.5 s and 492 MB on every call, ``-n`` included). Every file is read
in full and checked (pairs, contacts, forces) by the import job (`forcenet.importers.import_run`).

The record is also an input of the import job (`forcenet.importers.run_files`), and its modification time moves
only when the file's content changes: a source replaced by other content with an older modification time (copied
with ``cp -p``, unpacked from an archive) is imported again, which Snakemake's comparison of times alone missed. A
record first written for a file gets the file's own modification time, so outputs made before records existed stay
up to date.
"""
from __future__ import annotations

import hashlib
import json
import math
import os
import stat
import time
from pathlib import Path
from typing import Any, Callable, Mapping

import numpy as np

from forcenet.importers.common import SourceError, file_sha256
from forcenet.importers.table import given_box, read_particles

#: the environment variable naming the folder of the records (default `DEFAULT_RECORD_DIR`, below the working
#: directory: Snakemake's own folder, which ``--directory`` moves with the run)
RECORD_DIR_ENV = "FORCENET_SOURCE_RECORDS"
DEFAULT_RECORD_DIR = ".snakemake/forcenet-sources"
#: bumped when what a scan stores changes: older records are scanned again
RECORD_VERSION = 1


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


def file_record(path: str | Path, how: str | None = None, scan: Callable[[], Any] | None = None) -> dict[str, Any]:
    """The record of one source file: {path, size, mtime_ns, sha256, scans: {how: what `scan` returned}}. Read from
    its file when the source's size and modification time are those recorded (and it holds scan `how`), else made
    now (the file hashed, `scan` run) and stored; its modification time then changes only if the sha256 did."""
    status = checked_size(path)
    key = {"path": os.path.normpath(path), "size": status.st_size, "mtime_ns": status.st_mtime_ns,
           "version": RECORD_VERSION}
    stored = record_path(path)
    old = _load(stored)
    if old is not None and all(old.get(name) == value for name, value in key.items()) and (
            how is None or how in old.get("scans", {})):
        return old
    sha256 = file_sha256(path)
    same_content = old is not None and old.get("sha256") == sha256
    scans = dict(old.get("scans", {})) if same_content and old.get("version") == RECORD_VERSION else {}
    if how is not None:
        scans[how] = scan()
    record = {**key, "sha256": sha256, "scans": scans}
    # first record: the source's own time (outputs already built stay current); new content: now (reimport)
    stamp = (status.st_mtime_ns if old is None else os.stat(stored).st_mtime_ns if same_content else time.time_ns())
    _store(stored, record, stamp)
    return record


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


def _volume(radius: np.ndarray, dimension: int) -> float:
    """Σ π r² (2D) or Σ 4/3 π r³ (3D), as `forcenet.importers.common.packing_fraction` sums it."""
    return float(math.pi * np.sum(radius ** 2) if dimension == 2 else 4.0 / 3.0 * math.pi * np.sum(radius ** 3))


def scan_atoms(path: str | Path, dimension: int) -> list[dict[str, Any]]:
    """Per timestep of a LAMMPS atoms dump: {timestep, particles, volume (the particles'), lo, hi (the box on the
    system's axes)}, each frame's atoms checked as the import job checks them (`lammps.atom_state`)."""
    from forcenet.importers import lammps

    frames = []
    for frame in lammps.read_frames(path, "ATOMS"):
        _, _, radius, lo, hi, _ = lammps.atom_state(path, frame, dimension)
        frames.append({"timestep": frame.timestep, "particles": len(radius), "volume": _volume(radius, dimension),
                       "lo": lo.tolist(), "hi": hi.tolist()})
    return frames


def scan_particles(path: str | Path, dimension: int) -> dict[str, Any]:
    """A table's particles CSV: {particles, volume, lo, hi (the particles' bounding box)} (`table.read_particles`)."""
    _, position, radius = read_particles(path, dimension)
    return {"particles": len(radius), "volume": _volume(radius, dimension),
            "lo": (position - radius[:, None]).min(axis=0).tolist(),
            "hi": (position + radius[:, None]).max(axis=0).tolist()}


def _rho(volume: float, lo, hi, path, where: str) -> float:
    """ρ of a state; one at or above 1 raises `SourceError` naming the file and the state: its particles do not fit
    their box (radii and box in different length units, or diameters given as radii)."""
    rho = float(volume / np.prod(np.asarray(hi, float) - np.asarray(lo, float)))
    if not 0.0 < rho < 1.0:
        raise SourceError(path, where, f"ρ = {rho:.4g}: the particles' {'area' if len(lo) == 2 else 'volume'} is not "
                                       "below the box's (radii and box in different units? diameters given as radii?)")
    return rho


def run_outline(entry: Mapping[str, Any], realization: int) -> list[tuple[float, int]]:
    """(ρ, particles) of each state of one run of a ``source:`` entry, in the source's order, from the records
    (`file_record`): the particles files scanned once per content, the others checked to exist and be non-empty."""
    return [(rho, particles) for rho, particles, _ in run_scan(entry, realization)]


def run_scan(entry: Mapping[str, Any], realization: int) -> list[tuple[float, int, int]]:
    """(ρ, particles, timestep) of each state of one run, as `run_outline`; the timestep is a LAMMPS state's and a
    table state's index in its run."""
    source, dimension = entry["source"], int(entry["dimension"])
    run = source["runs"][realization]
    if source["format"] not in ("lammps", "table"):
        raise SourceError("source.format", "", f"unknown format {source['format']!r}")
    if source["format"] == "lammps":
        file_record(run["pairs"])
        frames = file_record(run["atoms"], f"lammps:{dimension}",
                             lambda: scan_atoms(run["atoms"], dimension))["scans"][f"lammps:{dimension}"]
        wanted = source.get("timesteps")
        if wanted is not None:
            have = [frame["timestep"] for frame in frames]
            missing = [step for step in wanted if step not in have]
            if missing:
                raise SourceError(run["atoms"], "source.timesteps", f"timestep {missing[0]} is not in the dump ({have})")
            frames = [frame for frame in frames if frame["timestep"] in wanted]
        box = source.get("box")
        return [(_rho(f["volume"], box["lo"] if box else f["lo"], box["hi"] if box else f["hi"], run["atoms"],
                      f"timestep {f['timestep']}"), f["particles"], int(f["timestep"])) for f in frames]
    states = []
    for state in run:
        file_record(state["contacts"])
        scan = file_record(state["particles"], f"table:{dimension}",
                           lambda: scan_particles(state["particles"], dimension))["scans"][f"table:{dimension}"]
        box = state.get("box", source.get("box"))
        lo, hi = (scan["lo"], scan["hi"]) if box is None else given_box(box, dimension, state["particles"])
        states.append((_rho(scan["volume"], lo, hi, state["particles"], "box" if box else ""), scan["particles"],
                       len(states)))
    return states
