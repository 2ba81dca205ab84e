"""What every importer shares: the state it reads (`SourceState`), ρ from the box, the error it raises, file hashes,
and the dispatch from a config's ``source:`` entry to the reader of its format (`source_states`)."""
from __future__ import annotations

import gzip
import hashlib
import math
import zlib
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Iterator, Mapping

import numpy as np

from forcenet.boxes import box_periods, branch_vectors, relative_overlaps
from forcenet.errors import ForcenetError

#: wall ids of the contract (`forcenet.datasets.schema`: wall_contact_wall), by name as a contacts table writes them
WALL_NAMES = ("x_lo", "x_hi", "y_lo", "y_hi", "z_lo", "z_hi")


class SourceError(ForcenetError, ValueError):
    """A source file that cannot be imported; the one-line message names the file and the line or column."""

    def __init__(self, path: str | Path, where: str, problem: str):
        super().__init__(f"{path}{', ' + where if where else ''}: {problem}")
        self.path = str(path)


@dataclass
class SourceState:
    """One state as read from a source, in the source's units (forcenet's analysis normalises every network by its
    own mean force, so only the length unit matters: ρ and the drawings).

    position (N, d), radius (N,); contact_i < contact_j (C,) indices into the particles; force_normal,
    force_tangential (C, d): forces on particle i from j; wall_particle, wall_id (W,), wall_force (W, d); box_lo,
    box_hi (d,); files: the source files this state was read from; timestep: the LAMMPS timestep or the state's
    index in its run's table list; periodic_axes: the letters of the box's periodic axes ("" for a bounded box);
    tilt: a triclinic box's tilt factors (`forcenet.boxes.tilt_labels`), None for an orthogonal box;
    force_disagreement (C,): under ``source.duplicate_contacts`` the difference of a contact's two estimates
    (`merge_two_sided`; NaN for a contact given once), None otherwise."""

    position: np.ndarray
    radius: np.ndarray
    contact_i: np.ndarray
    contact_j: np.ndarray
    force_normal: np.ndarray
    force_tangential: np.ndarray
    box_lo: np.ndarray
    box_hi: np.ndarray
    files: tuple[str, ...]
    timestep: int
    wall_particle: np.ndarray = field(default_factory=lambda: np.zeros(0, dtype=np.int64))
    wall_id: np.ndarray = field(default_factory=lambda: np.zeros(0, dtype=np.int64))
    wall_force: np.ndarray | None = None
    periodic_axes: str = ""
    tilt: np.ndarray | None = None
    force_disagreement: np.ndarray | None = None

    @property
    def dimension(self) -> int:
        return int(self.position.shape[1])

    @property
    def rho(self) -> float:
        """Packing fraction: the particles' area (2D disks) or volume (3D spheres) over the box's (a tilt leaves it
        unchanged: the edge vectors' determinant is the product of hi − lo)."""
        return packing_fraction(self.radius, self.box_lo, self.box_hi)

    def snapshot_arrays(self) -> dict[str, Any]:
        """The keyword arrays of `forcenet.datasets.write_snapshot` (no dynamics: an imported state has none; the
        disagreement of contacts given from each side where ``source.duplicate_contacts`` merged them)."""
        d = self.dimension
        wall_force = np.zeros((0, d)) if self.wall_force is None else self.wall_force
        merged = {} if self.force_disagreement is None else {"contact_force_disagreement": self.force_disagreement}
        return dict(**merged,
                    position=self.position, radius=self.radius, contact_i=self.contact_i, contact_j=self.contact_j,
                    force_normal=self.force_normal, force_tangential=self.force_tangential,
                    wall_contact_particle=self.wall_particle, wall_contact_wall=self.wall_id,
                    wall_contact_force=wall_force, box_lo=self.box_lo, box_hi=self.box_hi, rho=self.rho,
                    Z=2.0 * len(self.contact_i) / len(self.radius))


def packing_fraction(radius: np.ndarray, box_lo: np.ndarray, box_hi: np.ndarray) -> float:
    """Σ π r² / box area (2D) or Σ 4/3 π r³ / box volume (3D)."""
    d = len(box_lo)
    volume = math.pi * np.sum(radius ** 2) if d == 2 else 4.0 / 3.0 * math.pi * np.sum(radius ** 3)
    return float(volume / np.prod(np.asarray(box_hi, float) - np.asarray(box_lo, float)))


def read_source_text(path: str | Path) -> str:
    """A source file's text (UTF-8), gunzipped when its name ends in ``.gz`` (LAMMPS's ``dump custom/gz`` and
    ``local/gz``, a gzipped table); a file that cannot be read raises `SourceError` naming it and why."""
    try:
        if str(path).endswith(".gz"):
            with gzip.open(path, "rt", encoding=ENCODING) as handle:
                return handle.read()
        return Path(path).read_text(encoding=ENCODING)
    except READ_ERRORS as error:
        raise SourceError(path, "", f"cannot be read ({_reason(error, path)})") from None


#: sources are UTF-8; "-sig" drops a leading byte-order mark (Excel's "CSV UTF-8" writes one), which would otherwise
#: become part of the first column's name or of the first ITEM line
ENCODING = "utf-8-sig"
#: what reading a damaged file raises: gzip.BadGzipFile is an OSError, a cut gzip stream an EOFError, corrupt
#: compressed data a zlib.error (not an OSError: issue 57 found it uncaught, naming no file)
READ_ERRORS = (OSError, EOFError, UnicodeDecodeError, zlib.error)


def _reason(error: BaseException, path: str | Path = "") -> str:
    """Why a source file could not be read, in words (a gzip file named without ``.gz`` is said to be one)."""
    text = getattr(error, "strerror", None) or str(error) or type(error).__name__
    if isinstance(error, zlib.error):
        return f"{text}; a corrupt gzip stream"
    if isinstance(error, UnicodeDecodeError) and path and not str(path).endswith(".gz"):
        try:
            with open(path, "rb") as handle:
                if handle.read(2) == b"\x1f\x8b":
                    return f"{text}; the file is gzip-compressed: name it {Path(path).name}.gz"
        except OSError:
            pass
    return text


def source_lines(path: str | Path) -> Iterator[tuple[int, str]]:
    """(line number from 1, text without its line end) of each line of a source file, read one line at a time (the
    memory of a many-timestep dump is one frame's, not the file's), gunzipped like `read_source_text`. A file that
    cannot be read, or whose last line has no final newline (a dump cut while it was being written: LAMMPS ends
    every line), raises `SourceError` naming the file and the line."""
    number = 0
    try:
        handle = (gzip.open(path, "rt", encoding=ENCODING, newline="") if str(path).endswith(".gz")
                  else open(path, encoding=ENCODING, newline=""))
    except READ_ERRORS as error:
        raise SourceError(path, "", f"cannot be read ({_reason(error, path)})") from None
    with handle:
        while True:
            try:
                line = handle.readline()
            except READ_ERRORS as error:
                raise SourceError(path, f"after line {number}" if number else "",
                                  f"cannot be read ({_reason(error, path)})") from None
            if not line:
                return
            number += 1
            if not line.endswith(("\n", "\r")):  # newline="": \r\n and \r end lines too
                raise SourceError(path, f"line {number}", f"the file ends inside this line ({line[-40:]!r}), without "
                                                          "its final newline: cut short while it was being written?")
            yield number, line.rstrip("\r\n")


def coincident_pair(position: np.ndarray) -> tuple[int, int] | None:
    """Indices (a, b) of two particles at exactly the same position (N, d), or None: their contact has no normal
    direction (a NaN force), so an importer names them instead."""
    if len(position) < 2:
        return None
    order = np.lexsort(position.T[::-1])
    same = np.all(position[order[1:]] == position[order[:-1]], axis=1)
    if not same.any():
        return None
    k = int(np.argmax(same))
    a, b = sorted((int(order[k]), int(order[k + 1])))
    return a, b


def negative_magnitude(values: np.ndarray) -> int | None:
    """The first row of force magnitudes (C,) or (C, 1) below zero, or None. Both importers refuse it: a magnitude is
    stored along the repulsive normal (or perpendicular to it), so a negative one would flip the force's direction
    while |F| counted it as repulsive."""
    values = np.asarray(values)
    negative = values.reshape(len(values), -1) < 0 if values.size else np.zeros((0, 1), bool)
    rows = np.flatnonzero(negative.any(axis=1))
    return int(rows[0]) if rows.size else None


def largest_relative_overlap(state: "SourceState") -> tuple[float, int]:
    """(largest overlap relative to the sum of the two radii, its contact index) of a state's particle contacts (as
    `forcenet.report.p1.relative_overlaps` measures a snapshot: P1 §3 states "up to 10 %"); (0, -1) without contacts.
    Periodic images count (`forcenet.boxes`)."""
    if len(state.contact_i) == 0:
        return 0.0, -1
    period = box_periods(state.periodic_axes, state.box_lo, state.box_hi, state.tilt)
    overlap = relative_overlaps(state.position, state.radius, state.contact_i, state.contact_j, period)
    k = int(np.argmax(overlap))
    return float(overlap[k]), k


def file_sha256(path: str | Path) -> str:
    digest = hashlib.sha256()
    with open(path, "rb") as handle:
        for block in iter(lambda: handle.read(1 << 20), b""):
            digest.update(block)
    return digest.hexdigest()


def normal_unit_vectors(position: np.ndarray, i: np.ndarray, j: np.ndarray,
                        period: np.ndarray | None = None) -> np.ndarray:
    """Unit vectors from particle j (its image nearest to i where `period`, `forcenet.boxes.box_periods`, gives
    periodic axes) to particle i: the direction of a repulsive normal force on i."""
    delta = branch_vectors(position, i, j, period)
    return delta / np.linalg.norm(delta, axis=1)[:, None]


def split_total_force(total: np.ndarray, n: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The normal and tangential parts (C, d) of whole contact forces `total` (C, d) on particle i, `n` (C, d) the
    unit vectors from j (its nearest image) to i: F_n = (F · n) n along the line of centres, where a sphere's
    normal force acts, and F_t = F − F_n in the tangent plane. A repulsive normal force has F · n > 0."""
    normal = np.einsum("cd,cd->c", total, n)[:, None] * n
    return normal, total - normal


def perpendicular_unit_vectors(n: np.ndarray) -> np.ndarray:
    """A unit vector perpendicular to each row of `n`: in 2D n rotated by +90°; in 3D n × e, e the axis on which n
    has its smallest component."""
    if n.shape[1] == 2:
        return np.stack([-n[:, 1], n[:, 0]], axis=1)
    axis = np.zeros_like(n)
    axis[np.arange(len(n)), np.argmin(np.abs(n), axis=1)] = 1.0
    t = np.cross(n, axis)
    return t / np.linalg.norm(t, axis=1)[:, None]


def order_pairs(i: np.ndarray, j: np.ndarray, fn: np.ndarray, ft: np.ndarray):
    """Contacts with i < j: a pair given as (j, i) has its forces (on the first particle) reversed."""
    swap = i > j
    i, j = np.where(swap, j, i), np.where(swap, i, j)
    sign = np.where(swap, -1.0, 1.0)[:, None]
    return i, j, fn * sign, ft * sign


# --- the conventions of real inputs (issue 56 item 3): signed tangential components, contacts given from each side,
# several wall sources. The same option of `source:` means the same in both importers (docs/importing.md
# "Conventions of real inputs").

#: ``source.signed_tangential``: how a tangential force given as one signed column (``ft``, or a one-column
#: ``pair_columns.tangential``) is read: ``magnitude`` takes |ft| (stored perpendicular to the normal, as a
#: magnitude), ``vector`` keeps its sign: ft along the normal n (from j to i) turned by +90°, 2D only. Absent: the
#: column is a magnitude and a negative value is refused, naming this option
SIGNED_TANGENTIAL = ("magnitude", "vector")
#: ``source.duplicate_contacts``: how a contact given once from each side (rows i, j and j, i) is merged: ``mean``,
#: the mean of its two estimates of the force on i from j, their disagreement recorded per contact
#: (``contact_force_disagreement``). Absent: a contact given twice is refused, naming this option
DUPLICATE_RULES = ("mean",)
#: ``source.wall_forces``: what the wall forces of several sources on one particle at one wall become: ``separate``
#: (the default), each source's force its own wall contact; ``summed_per_wall``, one contact per particle and wall
#: with the sources' forces summed. Contacts at different walls (a corner particle) stay apart under both
WALL_FORCE_RULES = ("separate", "summed_per_wall")

OPTION_SIGNED = "source.signed_tangential"
OPTION_DUPLICATES = "source.duplicate_contacts"


def signed_tangential_rule(source: Mapping[str, Any], dimension: int, one_column: bool) -> str | None:
    """The `SIGNED_TANGENTIAL` rule `source` states (None: a magnitude, ≥ 0); `SourceError` naming the option when it
    cannot apply: a value not in the list, ``vector`` in 3D (a signed component names a direction only in a plane) or
    a tangential force given as a vector (`one_column` False), whose components are signed already."""
    rule = source.get("signed_tangential")
    if rule is None:
        return None
    if rule not in SIGNED_TANGENTIAL:
        raise SourceError(OPTION_SIGNED, "", f"{rule!r} is not one of {', '.join(SIGNED_TANGENTIAL)}")
    if not one_column:
        raise SourceError(OPTION_SIGNED, "", "applies to a tangential force given as one column (table forces: "
                                             "magnitudes, a one-column pair_columns.tangential); this source gives "
                                             "its components, signed already: leave the option out")
    if rule == "vector" and dimension != 2:
        raise SourceError(OPTION_SIGNED, "", "vector: the sign of one tangential component names a direction only "
                                             "in 2D (along n turned by +90°); a 3D system takes magnitude")
    return rule


def negative_tangential_problem(value: float) -> str:
    """What a refused negative tangential magnitude says: the value and the option that accepts it."""
    return (f"a force magnitude must be ≥ 0, got {value:g}: a signed tangential component is read with "
            f"{OPTION_SIGNED}: magnitude (|ft| taken) or vector (its sign kept, along the normal turned by +90°)")


def tangential_from_column(values: np.ndarray, n: np.ndarray, rule: str | None) -> np.ndarray:
    """Tangential forces (C, d) from one column `values` (C,) or (C, 1), `n` (C, d) the normals from j to i: a
    magnitude (`rule` None or ``magnitude``: |ft|) along `perpendicular_unit_vectors` (n), or with ``vector`` the
    signed component along it (2D: n turned by +90°)."""
    values = np.asarray(values, dtype=float).reshape(len(n), 1)
    return (values if rule == "vector" else np.abs(values)) * perpendicular_unit_vectors(n)


def duplicate_rule(source: Mapping[str, Any]) -> str | None:
    """The `DUPLICATE_RULES` rule `source` states, None if absent; `SourceError` naming the option for another."""
    rule = source.get("duplicate_contacts")
    if rule is not None and rule not in DUPLICATE_RULES:
        raise SourceError(OPTION_DUPLICATES, "", f"{rule!r} is not one of {', '.join(DUPLICATE_RULES)}")
    return rule


@dataclass
class RepeatedContact:
    """A contact whose rows `rule` (`DUPLICATE_RULES`, or None) does not accept: `row` repeats the contact of
    `first` (indices into the rows as given); it appears `how` ("twice, once from each side", …), and `remedy` says
    which option accepts such data, or why none does. An importer's message: "contact a-b appears {how} (first on
    line …): {remedy}"."""

    row: int
    first: int
    how: str
    remedy: str


def repeated_contact(i: np.ndarray, j: np.ndarray, swapped: np.ndarray, rule: str | None) -> RepeatedContact | None:
    """The first row (in the order given) that repeats a contact in a way `rule` refuses, or None. `i` < `j` (C,) are
    the contacts' particles once ordered (`order_pairs`) and `swapped` (C,) bool which rows were given as (j, i).
    Without a rule any repeat is refused, naming `OPTION_DUPLICATES`; with ``mean`` a contact may be given twice,
    once from each side: the same side twice (a repeated row) or a third row is refused."""
    i, j, swapped = (np.asarray(a).reshape(-1) for a in (i, j, swapped))
    if len(i) < 2:
        return None
    keys = i.astype(np.int64) * (int(max(i.max(), j.max())) + 1) + j
    order = np.argsort(keys, kind="stable")  # each contact's rows together, in the order given
    sorted_keys = keys[order]
    starts = np.r_[True, sorted_keys[1:] != sorted_keys[:-1]]
    start = np.maximum.accumulate(np.where(starts, np.arange(len(keys)), 0))
    rank = np.arange(len(keys)) - start  # 0 for a contact's first row, 1 for its second, …
    first = order[start]
    same_side = swapped[order] == swapped[first]
    bad = rank >= 1 if rule is None else (rank >= 2) | ((rank == 1) & same_side)
    if not bad.any():
        return None
    k = int(np.argmin(np.where(bad, order, len(keys))))  # the earliest refused row in the order given
    row, head = int(order[k]), int(first[k])
    if rank[k] >= 2:
        return RepeatedContact(row, head, f"{rank[k] + 1} times", f"{OPTION_DUPLICATES}: mean merges a contact "
                                                                  "given twice, once from each side, no more")
    if same_side[k]:
        return RepeatedContact(row, head, "twice from the same side", f"a repeated row? {OPTION_DUPLICATES}: mean "
                                                                      "merges a contact given once from each side "
                                                                      "(i, j and j, i)")
    return RepeatedContact(row, head, "twice, once from each side", f"{OPTION_DUPLICATES}: mean merges them (the "
                                                                    "mean of the two estimates, their disagreement "
                                                                    "recorded)")


def merge_two_sided(i: np.ndarray, j: np.ndarray, fn: np.ndarray, ft: np.ndarray):
    """Contacts given once from each side merged by the mean of their two estimates (rows already ordered, i < j,
    each a force on i from j, `order_pairs`; `repeated_contact` found none refused): (i, j, F_n, F_t,
    disagreement) with one row per contact in the order of first appearance; disagreement (C,) is |F_a − F_b|, the
    norm of the difference of the two estimates of the whole force F_n + F_t, NaN for a contact given once."""
    keys = np.asarray(i, np.int64) * (int(max(np.max(i, initial=0), np.max(j, initial=0))) + 1) + np.asarray(j)
    unique, first, inverse, counts = np.unique(keys, return_index=True, return_inverse=True, return_counts=True)
    inverse = inverse.reshape(-1)
    d = fn.shape[1]
    fn_sum, ft_sum = np.zeros((len(unique), d)), np.zeros((len(unique), d))
    np.add.at(fn_sum, inverse, fn)
    np.add.at(ft_sum, inverse, ft)
    whole = fn + ft
    signed = np.zeros((len(unique), d))  # estimate a − estimate b: the first row of each contact +, the second −
    np.add.at(signed, inverse, np.where((np.arange(len(keys)) == first[inverse])[:, None], whole, -whole))
    disagreement = np.where(counts == 2, np.linalg.norm(signed, axis=1), np.nan)
    keep = np.argsort(first)  # the order of first appearance
    return (np.asarray(i)[first][keep], np.asarray(j)[first][keep], (fn_sum / counts[:, None])[keep],
            (ft_sum / counts[:, None])[keep], disagreement[keep])


def wall_rule(source: Mapping[str, Any]) -> str:
    """The `WALL_FORCE_RULES` rule `source` states (default ``separate``)."""
    rule = source.get("wall_forces", "separate")
    if rule not in WALL_FORCE_RULES:
        raise SourceError("source.wall_forces", "", f"{rule!r} is not one of {', '.join(WALL_FORCE_RULES)}")
    return rule


def sum_per_wall(particle: np.ndarray, wall: np.ndarray, force: np.ndarray):
    """Wall contacts (W,), (W,), (W, d) with those of one particle at one wall summed into one, in the order of
    their first appearance (`WALL_FORCE_RULES`: summed_per_wall)."""
    if len(particle) == 0:
        return particle, wall, force
    keys = np.asarray(particle, np.int64) * 6 + np.asarray(wall, np.int64)
    unique, first, inverse = np.unique(keys, return_index=True, return_inverse=True)
    summed = np.zeros((len(unique), force.shape[1]))
    np.add.at(summed, inverse.reshape(-1), force)
    keep = np.argsort(first)
    return particle[first][keep], wall[first][keep], summed[keep]
