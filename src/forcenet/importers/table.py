"""The plain table format: one pair of CSV files per state (docs: README "Your own data", docs/tutorial.py).

``particles`` CSV, one row per particle, header ``id,x,y,radius`` (2D) or ``id,x,y,z,radius`` (3D), columns in any
order, extra columns ignored: a unique integer id, the centre and the radius, in any one length unit (ρ and the
drawings use it; forces are analysed in units of each network's mean, so their unit does not matter).

``contacts`` CSV, one row per contact, header ``i,j`` and the forces, with the convention ``source.forces`` states:

- ``magnitudes``: columns ``fn,ft`` — the normal force's magnitude (≥ 0, repulsive) and the tangential force's
  (≥ 0). The normal force on i points from j to i; the tangential one, whose direction a magnitude does not give,
  is stored perpendicular to it (2D: the normal turned by +90°), which keeps |F_n|, |F_t| and |F_n + F_t| — all the
  analysis uses;
- ``vectors``: columns ``fn_x,fn_y[,fn_z],ft_x,ft_y[,ft_z]`` — the normal and tangential force on particle i from
  particle j;
- ``total``: columns ``f_x,f_y[,f_z]`` — the whole contact force on particle i from particle j (as an experiment's
  force inversion or a code that does not split it gives it), split along the line of centres: the normal part
  (F · n) n, n from j (its nearest image) to i, and the tangential rest (`common.split_total_force`).

``i`` and ``j`` are particle ids; ``j`` may instead name a wall (``x_lo``, ``x_hi``, ``y_lo``, ``y_hi``, ``z_lo``,
``z_hi``) for a particle–wall contact (then the forces are the wall's on particle i; a magnitude's normal points
into the box). A pair given as (j, i) is stored as (i, j) with its forces reversed. Rows starting with ``#`` are
comments. A file must end with a newline: one that does not may have been cut inside its last row
(`_complete_last_row`). Box: the state's ``box: {lo: [...], hi: [...]}`` in the config, else ``source.box``, else
the particles' bounding box (min x − r to max x + r on each axis). ``source.periodic`` (e.g. ``[x, y]``) names the axes on which
the box is periodic (it must then be given): a contact across a periodic face joins i to the image of j nearest to
it (`forcenet.boxes`), which directs a magnitude's normal force, and no wall lies on those axes. A given box may be
triclinic, ``box: {lo, hi, tilt: [xy]}`` (3D: ``[xy, xz, yz]``), LAMMPS's tilt factors, tilted only along its
periodic axes; walls then lie on its untilted faces only.

Conventions of real inputs (`forcenet.importers.common`, docs/importing.md): ``source.signed_tangential`` reads a
signed ``ft`` (``magnitude``: |ft|; ``vector``: its sign kept, 2D) where a negative one is otherwise refused;
``source.duplicate_contacts: mean`` merges a contact given once from each side (rows i, j and j, i) into the mean
of its two estimates, recording their disagreement, where a contact given twice is otherwise refused;
``source.wall_forces: summed_per_wall`` sums the rows of one particle at one wall into one wall contact.
"""
from __future__ import annotations

import csv
import math
from pathlib import Path
from typing import Any, Mapping, Sequence

import numpy as np

from forcenet.boxes import AXIS_LABELS, box_periods, tilt_problem, tilted_faces
from forcenet.importers.common import (WALL_NAMES, SourceError, SourceState, coincident_pair, duplicate_rule,
                                       merge_two_sided, negative_magnitude, negative_tangential_problem,
                                       normal_unit_vectors, order_pairs, read_source_text, repeated_contact,
                                       signed_tangential_rule, split_total_force, sum_per_wall,
                                       tangential_from_column, wall_rule)

AXES = AXIS_LABELS
#: the two conventions of the contacts' forces (`source.forces`)
FORCE_CONVENTIONS = ("magnitudes", "vectors", "total")


def read_run(run: Sequence[Mapping[str, Any]], dimension: int, source: Mapping[str, Any]) -> list[SourceState]:
    """The states of one run: a list of {particles, contacts[, box]} (paths relative to where snakemake runs)."""
    return [read_state(state["particles"], state["contacts"], dimension, source.get("forces", "vectors"),
                       box=state.get("box", source.get("box")), index=k, periodic=source.get("periodic", ()),
                       source=source)
            for k, state in enumerate(run)]


def _rows(path: str | Path) -> tuple[list[str], list[tuple[int, list[str]]]]:
    """(header, [(line number, cells)]) of a CSV file, comment and blank lines skipped."""
    text = read_source_text(path)
    rows = [(number, cells) for number, cells in enumerate(csv.reader(text.splitlines()), start=1)
            if cells and any(c.strip() for c in cells) and not cells[0].lstrip().startswith("#")]
    if not rows:
        raise SourceError(path, "", "empty: no header line")
    (_, header), body = rows[0], rows[1:]
    for number, cells in body:  # a cell beyond the header belongs to no column: a shifted or merged row
        if len(cells) > len(header):
            raise SourceError(path, f"line {number}", f"{len(cells)} cells, but the header (line {rows[0][0]}) names "
                                                      f"{len(header)} columns")
    lines = text.splitlines()
    if body and not text.endswith(("\n", "\r")) and body[-1][0] == len(lines):
        _complete_last_row(path, len(header), body, lines[-1])
    return [c.strip() for c in header], body


#: rows above the last whose values in its last column must all have one number of characters after the decimal
#: point (a fixed-format writer such as ``%.6f``) before a last value with fewer is taken for a cut one
FIXED_FORMAT_ROWS = 3


def _complete_last_row(path, columns: int, body: list[tuple[int, list[str]]], line: str) -> None:
    """Refuse a CSV that ends without a final newline: its last row (`line`) may have been cut while the file was
    being written, and a cut inside a value cannot be told from a whole one, so a missing final newline is an error,
    not a guess. The message says what shows the cut where something does — fewer cells than the header's
    `columns`, an empty last cell, a last value with fewer characters after its decimal point than each of the
    ≥ `FIXED_FORMAT_ROWS` rows above it, all alike — and how to read a file whose last line is complete."""
    number, cells = body[-1]
    last = cells[-1].strip()
    k = len(cells) - 1
    above = [row[k].strip() for _, row in body[:-1] if len(row) > k]
    decimals = {len(v.partition(".")[2]) for v in above}
    if len(cells) < columns or not last:
        evidence = f", and {len(cells) - (not last)} of the header's {columns} cells"
    elif (len(above) >= FIXED_FORMAT_ROWS and all("." in v for v in above) and len(decimals) == 1
            and ("." not in last or len(last.partition(".")[2]) < min(decimals))):
        evidence = (f", and its last value {last!r} is shorter than the {len(above)} above it ({min(decimals)} "
                    "characters after the decimal point each)")
    else:
        evidence = ""
    raise SourceError(path, f"line {number}", f"the file ends inside this line ({line[-40:]!r}), without its final "
                                              f"newline{evidence}: cut short while it was being written? If the line "
                                              "is complete, end the file with a newline")


def _columns(path, header: list[str], required: Sequence[str], forbidden: Mapping[str, str] = {}) -> dict[str, int]:
    for name, why in forbidden.items():
        if name in header:
            raise SourceError(path, f"column '{name}'", why)
    missing = [name for name in required if name not in header]
    if missing:
        raise SourceError(path, f"column '{missing[0]}'", f"missing (header: {','.join(header)}; needs "
                                                          f"{','.join(required)})")
    return {name: header.index(name) for name in required}


def _cell(path, number: int, cells: list[str], columns: dict[str, int], name: str) -> str:
    k = columns[name]
    if k >= len(cells) or not cells[k].strip():
        raise SourceError(path, f"line {number}, column '{name}'", "empty")
    return cells[k].strip()


def _number(path, number: int, cells, columns, name: str) -> float:
    text = _cell(path, number, cells, columns, name)
    try:
        value = float(text)
    except ValueError:
        raise SourceError(path, f"line {number}, column '{name}'", f"{text!r} is not a number") from None
    if not math.isfinite(value):
        raise SourceError(path, f"line {number}, column '{name}'", f"{text} is not finite")
    return value


def _integer(path, number: int, cells, columns, name: str) -> int:
    text = _cell(path, number, cells, columns, name)
    try:
        return int(text)
    except ValueError:
        raise SourceError(path, f"line {number}, column '{name}'", f"{text!r} is not an integer id") from None


def read_particles(path: str | Path, dimension: int) -> tuple[dict[int, int], np.ndarray, np.ndarray]:
    """({id: index}, position (N, d), radius (N,)) of a particles CSV."""
    header, body = _rows(path)
    axes = AXES[:dimension]
    forbidden = {"z": "present, but the system is declared 2D (dimension: 2)"} if dimension == 2 else {}
    if dimension == 3 and "z" not in header:
        raise SourceError(path, "column 'z'", "missing: the system is declared 3D (dimension: 3) but the file has "
                                              f"no z (header: {','.join(header)})")
    columns = _columns(path, header, ("id", *axes, "radius"), forbidden)
    if not body:
        raise SourceError(path, "", "no particles")
    index: dict[int, int] = {}
    lines: dict[int, int] = {}
    position = np.empty((len(body), dimension))
    radius = np.empty(len(body))
    for k, (number, cells) in enumerate(body):
        pid = _integer(path, number, cells, columns, "id")
        if pid in index:
            raise SourceError(path, f"line {number}, column 'id'", f"id {pid} appears twice (first on line "
                                                                   f"{lines[pid]})")
        index[pid], lines[pid] = k, number
        position[k] = [_number(path, number, cells, columns, axis) for axis in axes]
        radius[k] = _number(path, number, cells, columns, "radius")
        if radius[k] <= 0:
            raise SourceError(path, f"line {number}, column 'radius'", f"radius {radius[k]:g} is not positive")
    same = coincident_pair(position)
    if same is not None:
        a, b = same
        raise SourceError(path, f"lines {body[a][0]} and {body[b][0]}",
                          f"particles {_cell(path, body[a][0], body[a][1], columns, 'id')} and "
                          f"{_cell(path, body[b][0], body[b][1], columns, 'id')} are at the same position "
                          f"({', '.join(f'{v:g}' for v in position[a])})")
    return index, position, radius


def read_state(particles: str | Path, contacts: str | Path, dimension: int, forces: str = "vectors", *,
               box: Mapping[str, Sequence[float]] | None = None, index: int = 0,
               periodic: Sequence[str] = (), source: Mapping[str, Any] | None = None) -> SourceState:
    """One state from its particles and contacts CSV files (module docstring); `periodic`: the box's periodic axes;
    `source`: the config's ``source:`` entry, for its conventions (``signed_tangential``, ``duplicate_contacts``,
    ``wall_forces``: `forcenet.importers.common`)."""
    if forces not in FORCE_CONVENTIONS:
        raise SourceError(contacts, "", f"unknown force convention {forces!r}: one of {FORCE_CONVENTIONS}")
    source = source or {}
    signed = signed_tangential_rule(source, dimension, one_column=forces == "magnitudes")
    duplicates, walls_rule = duplicate_rule(source), wall_rule(source)
    wrong = [axis for axis in periodic if axis not in AXES[:dimension]]
    if wrong:
        raise SourceError("source.periodic", "", f"axis {wrong[0]!r} is not an axis of a {dimension}D system")
    if periodic and box is None:
        raise SourceError(particles, "box", "a periodic box must be given (the state's box or source.box): the "
                                            "particles' bounding box is not the period")
    periodic_axes = "".join(axis for axis in AXES if axis in periodic)
    tilt = None if box is None or "tilt" not in box else np.asarray(box["tilt"], dtype=float)
    if tilt is not None:
        problem = tilt_problem(periodic_axes, tilt, dimension)
        if problem:
            raise SourceError(particles, "box.tilt", problem)
        tilt = tilt if np.any(tilt) else None
    tilted = np.zeros(dimension, bool) if tilt is None else tilted_faces(tilt, dimension)
    ids, position, radius = read_particles(particles, dimension)
    header, body = _rows(contacts)
    axes = AXES[:dimension]
    force_columns = (("fn", "ft") if forces == "magnitudes" else tuple(f"f_{a}" for a in axes) if forces == "total"
                     else tuple(f"fn_{a}" for a in axes) + tuple(f"ft_{a}" for a in axes))
    z_column = "f_z" if forces == "total" else "fn_z"
    forbidden = {z_column: "present, but the system is declared 2D (dimension: 2)"} if dimension == 2 else {}
    columns = _columns(contacts, header, ("i", "j", *force_columns), forbidden)
    pairs, walls = [], []
    for number, cells in body:
        first = _integer(contacts, number, cells, columns, "i")
        if first not in ids:
            raise SourceError(contacts, f"line {number}, column 'i'", f"no particle with id {first} in {particles}")
        other = _cell(contacts, number, cells, columns, "j")
        values = np.array([_number(contacts, number, cells, columns, name) for name in force_columns])
        # a magnitude is ≥ 0; a signed tangential component is read as source.signed_tangential states
        negative = (negative_magnitude(values[:1 if signed else 2, None]) if forces == "magnitudes" else None)
        if negative is not None:
            raise SourceError(contacts, f"line {number}, column '{force_columns[negative]}'",
                              f"a force magnitude must be ≥ 0, got {values[negative]:g}" if negative == 0 else
                              negative_tangential_problem(values[negative]))
        if other in WALL_NAMES:
            wall = WALL_NAMES.index(other)
            if wall >= 2 * dimension:
                raise SourceError(contacts, f"line {number}, column 'j'", f"wall {other} in a 2D system")
            if AXES[wall // 2] in periodic_axes:
                raise SourceError(contacts, f"line {number}, column 'j'", f"wall {other} on an axis the box is "
                                                                          "periodic on (source.periodic)")
            if tilted[wall // 2]:
                raise SourceError(contacts, f"line {number}, column 'j'", f"wall {other} on a tilted face of the "
                                                                          "triclinic box (box.tilt): walls are "
                                                                          "imported on untilted faces only")
            walls.append((ids[first], wall, values))
            continue
        try:
            second = int(other)
        except ValueError:
            raise SourceError(contacts, f"line {number}, column 'j'", f"{other!r} is neither a particle id nor a wall "
                                                                      f"({', '.join(WALL_NAMES[:2 * dimension])})"
                              ) from None
        if second not in ids:
            raise SourceError(contacts, f"line {number}, column 'j'", f"no particle with id {second} in {particles}")
        if second == first:
            raise SourceError(contacts, f"line {number}, column 'j'", f"particle {first} in contact with itself")
        pairs.append((ids[first], ids[second], values, number, first, second))
    i = np.array([p[0] for p in pairs], dtype=np.int64)
    j = np.array([p[1] for p in pairs], dtype=np.int64)
    values = np.array([p[2] for p in pairs]).reshape(len(pairs), len(force_columns))
    # a contact given twice: refused, or (source.duplicate_contacts) merged once given from each side
    repeat = repeated_contact(np.minimum(i, j), np.maximum(i, j), i > j, duplicates)
    if repeat is not None:
        row, head = pairs[repeat.row], pairs[repeat.first]
        a, b = sorted((row[4], row[5]))
        raise SourceError(contacts, f"line {row[3]}", f"contact {a}-{b} appears {repeat.how} (first on line "
                                                      f"{head[3]}): {repeat.remedy}")
    lo, hi = _box(box, position, radius, particles)
    if forces in ("magnitudes", "total"):
        period = box_periods(periodic_axes, lo, hi, tilt)
        n = normal_unit_vectors(position, i, j, period) if len(pairs) else np.zeros((0, dimension))
        fn, ft = ((values[:, :1] * n, tangential_from_column(values[:, 1], n, signed)) if forces == "magnitudes"
                  else split_total_force(values, n))
    else:
        fn, ft = values[:, :dimension], values[:, dimension:]
    i, j, fn, ft = order_pairs(i, j, fn, ft)
    disagreement = None
    if duplicates is not None:
        i, j, fn, ft, disagreement = merge_two_sided(i, j, fn, ft)
    order = np.lexsort((j, i))
    wall_particle = np.array([w[0] for w in walls], dtype=np.int64)
    wall_id = np.array([w[1] for w in walls], dtype=np.int64)
    wall_values = np.array([w[2] for w in walls]).reshape(len(walls), len(force_columns))
    if forces == "magnitudes":
        n = np.zeros((len(walls), dimension))
        n[np.arange(len(walls)), wall_id // 2] = np.where(wall_id % 2 == 0, 1.0, -1.0)
        wall_force = wall_values[:, :1] * n + tangential_from_column(wall_values[:, 1], n, signed)
    elif forces == "total":
        wall_force = wall_values
    else:
        wall_force = wall_values[:, :dimension] + wall_values[:, dimension:]
    if walls_rule == "summed_per_wall":  # rows of one particle at one wall: one contact, their forces summed
        wall_particle, wall_id, wall_force = sum_per_wall(wall_particle, wall_id, wall_force)
    return SourceState(position=position, radius=radius, contact_i=i[order], contact_j=j[order],
                       force_normal=fn[order], force_tangential=ft[order], box_lo=lo, box_hi=hi,
                       files=(str(particles), str(contacts)), timestep=index, wall_particle=wall_particle,
                       wall_id=wall_id, wall_force=wall_force, periodic_axes=periodic_axes, tilt=tilt,
                       force_disagreement=None if disagreement is None else disagreement[order])


def _box(box, position, radius, where) -> tuple[np.ndarray, np.ndarray]:
    """The state's box: as given, else the particles' bounding box."""
    if box is None:
        return (position - radius[:, None]).min(axis=0), (position + radius[:, None]).max(axis=0)
    return given_box(box, position.shape[1], where)


def given_box(box: Mapping[str, Sequence[float]], dimension: int, where) -> tuple[np.ndarray, np.ndarray]:
    """(lo, hi) of a box the config gives; `SourceError` (naming `where`, the particles file) unless each has
    `dimension` values, hi above lo."""
    lo, hi = np.asarray(box["lo"], dtype=float), np.asarray(box["hi"], dtype=float)
    if lo.shape != (dimension,) or hi.shape != lo.shape or np.any(hi <= lo):
        raise SourceError(where, "box", f"box {{lo: {lo.tolist()}, hi: {hi.tolist()}}} must give {dimension} "
                                        "values each, hi above lo")
    return lo, hi
