"""LAMMPS text dumps: a ``dump custom`` of the atoms with a ``dump local`` of the pair forces, 2D or 3D, one or
many timesteps (README "Your own data"; the shipped example and how it was made: data/examples/lammps_2d/).

Atoms dump (``dump custom``): columns ``id``, ``x``, ``y``, ``z`` (a 2D dump may leave z out or hold it constant),
``radius`` (or ``diameter``; ``type`` and any others are ignored). Positions may also be LAMMPS's scaled ``xs ys
zs`` (fractions of the dump's box), unwrapped ``xu yu zu`` (folded back into the box on its periodic axes) or scaled
unwrapped ``xsu ysu zsu``; per axis the first present of x, xs, xu, xsu is read. The box of each timestep is the
dump's BOX BOUNDS unless the config gives ``source.box``; ρ is the particles' area (2D) or volume (3D) over the box's.
A triclinic box (BOX BOUNDS ``xy xz yz …``: LAMMPS's bounding box and tilt factors, e.g. a run sheared by
``fix deform``) is read as lo, hi and the tilt (`forcenet.boxes`), tilted only along periodic axes as LAMMPS allows.
An axis of the system whose boundary flags are ``pp`` is periodic (a 2D run's z does not count): a pair touching
through that face joins i to the image of j nearest to it (`forcenet.boxes`), and no wall lies on it.
Optional wall forces: ``source.wall_columns`` names the atom columns holding the force of the walls on each atom
(e.g. ``[f_walls[2], f_walls[3], f_walls[4]]`` of ``fix wall/gran/region … contacts``); an atom with a non-zero wall
force gets one wall contact, at the box face nearest to it (fix wall/gran/region's per-atom output holds one contact
per atom). Several wall fixes (one ``fix wall/gran`` per axis, as LAMMPS's granular examples) are a list of sources
``{columns, walls}`` (`wall_sources`): each source's force is its own contact at the nearest of its walls, so a
particle in a corner touching two walls gets two; ``source.wall_forces: summed_per_wall`` sums those of one atom at
one wall. A one-column tangential force may be signed (``source.signed_tangential``) and a pair may be listed from
each side (``source.duplicate_contacts: mean``, as ``newton off`` lists a pair across processors), as in a table
(`forcenet.importers.common`).

Pairs dump (``dump local``): one row per pair (``compute property/local patom1 patom2`` and ``compute pair/local
force p1 p2 p3`` of a ``gran/*`` pair style); ``source.pair_columns`` names the columns: ``i``, ``j`` (atom ids),
``normal`` (one column: the normal force's magnitude, repulsive > 0, directed from j to i, as ``compute pair/local
force``; or 2–3 columns: the vector on i) and ``tangential`` (2–3 columns: the vector on i, as pair gran's
p1 p2 p3; or one column: the magnitude, stored perpendicular to the normal), or instead of both ``total`` (2–3
columns: the whole contact force on i, as codes that do not split it write it; split along the line of centres,
`forcenet.importers.common.split_total_force`). Rows whose forces are all zero are
neighbours not in contact and are left out. The atoms and pairs dumps must hold the same timesteps in the same
order; ``source.timesteps`` picks some of them (default: all).
"""
from __future__ import annotations

from dataclasses import dataclass, field
from itertools import zip_longest
from pathlib import Path
from typing import Any, Iterator, Mapping, Sequence

import numpy as np

from forcenet.boxes import (AXIS_LABELS, TILT_LABELS, box_periods, box_vectors, fold_into_box, tilt_labels,
                            tilt_problem, tilted_faces)
from forcenet.importers.common import (WALL_NAMES, SourceError, SourceState, coincident_pair, duplicate_rule,
                                       merge_two_sided, negative_magnitude, negative_tangential_problem,
                                       normal_unit_vectors, order_pairs, repeated_contact,
                                       signed_tangential_rule, source_lines, split_total_force, sum_per_wall,
                                       tangential_from_column, wall_rule)

#: the pair columns of the shipped example (bench/lammps/make_import_example.py), used where the config names none
DEFAULT_PAIR_COLUMNS = {"i": "c_pid[1]", "j": "c_pid[2]", "normal": ["c_pf[1]"],
                        "tangential": ["c_pf[2]", "c_pf[3]", "c_pf[4]"]}


@dataclass
class Frame:
    """One timestep of a dump: its timestep, box bounds (3, 2) (a triclinic box's lo and hi, not the bounding box
    the dump writes), column names, rows (n, columns), the line number of its first row, which of x, y, z are
    periodic (boundary flags "pp" on the BOX BOUNDS line) and the tilt factors xy, xz, yz (zero: orthogonal)."""

    timestep: int
    line: int
    box: np.ndarray
    columns: list[str]
    rows: np.ndarray
    first_row_line: int
    periodic: tuple[bool, ...] = (False, False, False)
    tilt: np.ndarray = field(default_factory=lambda: np.zeros(3))


def read_frames(path: str | Path, kind: str) -> Iterator[Frame]:
    """The frames of a LAMMPS text dump, one at a time as the file is read (memory: one frame); `kind` "ATOMS" (dump
    custom) or "ENTRIES" (dump local). The structure is checked as it is read: a file cut anywhere (inside a header,
    before its announced rows, inside the last value: no final newline), a row of the wrong width, a value that is no
    number and a corrupt gzip stream each raise `SourceError` naming the file and the line."""
    count_item = "NUMBER OF ATOMS" if kind == "ATOMS" else "NUMBER OF ENTRIES"
    dump = "dump custom" if kind == "ATOMS" else "dump local"
    lines = source_lines(path)
    last = 0  # the number of the last line read

    def take(what: str) -> str:
        nonlocal last
        item = next(lines, None)
        if item is None:
            raise SourceError(path, f"line {last + 1}", f"the file ends where {what} should be: cut short?")
        last = item[0]
        return item[1]

    def expect(item: str, text: str | None = None) -> str:
        text = take(f"'ITEM: {item}'") if text is None else text
        if not text.startswith(f"ITEM: {item}"):
            raise SourceError(path, f"line {last}", f"expected 'ITEM: {item}', found {text!r} (a LAMMPS {dump} file?)")
        return text[len(f"ITEM: {item}"):].strip()

    def integer(after: str) -> int:
        text = take(f"the integer after 'ITEM: {after}' (line {last})")
        words = text.split()
        if len(words) != 1 or not words[0].lstrip("+-").isdigit():
            raise SourceError(path, f"line {last}", f"expected one integer after 'ITEM: {after}', found {text!r}")
        return int(words[0])

    frames = 0
    while True:
        item = next(lines, None)
        while item is not None and not item[1].strip():  # blank lines between frames
            item = next(lines, None)
        if item is None:
            break
        last, start = item[0], item[0]
        expect("TIMESTEP", item[1])
        timestep = integer("TIMESTEP")
        expect(count_item)
        count = integer(count_item)
        if count < 0:
            raise SourceError(path, f"line {last}", f"a negative number of rows ({count})")
        bounds = expect("BOX BOUNDS")
        triclinic = all(word in bounds.split() for word in TILT_LABELS)  # "xy xz yz pp pp pp"
        box = np.empty((3, 3 if triclinic else 2))
        for a in range(3):
            text = take(f"line {a + 1} of the 3 lines of box bounds (line {start})")
            words = text.split()
            try:
                if len(words) != box.shape[1]:
                    raise ValueError
                box[a] = [float(v) for v in words]
            except ValueError:
                raise SourceError(path, f"line {last}", "expected three lines of box bounds 'lo hi'"
                                  + (" and a tilt factor (the header says xy xz yz)" if triclinic else "")
                                  + f", found {text!r}") from None
        if not np.all(np.isfinite(box)):
            raise SourceError(path, f"line {last - 2}", "box bounds that are NaN or infinite")
        if np.any(box[:, 1] <= box[:, 0]):
            a = int(np.argmax(box[:, 1] <= box[:, 0]))
            raise SourceError(path, f"line {last - 2 + a}", f"box bounds {box[a, 0]:g} {box[a, 1]:g}: hi must exceed lo")
        tilt = box[:, 2] if triclinic else np.zeros(3)
        box = _triclinic_box(box[:, :2], tilt) if triclinic else box
        # "pp ff pp": per axis, LAMMPS's boundary style at its lo and hi faces
        flags = [word for word in bounds.split() if word not in TILT_LABELS]
        periodic = tuple(a < len(flags) and flags[a] == "pp" for a in range(3))
        columns = expect(kind).split()
        if not columns or len(set(columns)) != len(columns):
            raise SourceError(path, f"line {last}", f"the column names {' '.join(columns)!r} must be given, each once")
        first = last + 1
        block = [take(f"row {r + 1} of the {count} that timestep {timestep} (line {start}) announces")
                 for r in range(count)]
        yield Frame(timestep, start, box, columns, _rows(path, block, first, columns), first, periodic, tilt)
        frames += 1
    if not frames:
        raise SourceError(path, "", "empty")


def _rows(path, block: list[str], first: int, columns: list[str]) -> np.ndarray:
    """The values (rows, columns) of a frame's rows `block` (`first`: the line number of its first); a row of another
    width or a cell that is not a number raises `SourceError` naming its line."""
    if not block:
        return np.empty((0, len(columns)))
    try:  # numpy's C reader: a 2-million-line dump in about a second, not a Python loop per cell
        rows = np.loadtxt(block, dtype=float, comments=None, ndmin=2)
    except ValueError:
        rows = None
    if rows is not None and rows.shape == (len(block), len(columns)):
        return rows
    for r, line in enumerate(block):  # what numpy refused (or a blank line, which it skips): the first bad row
        cells = line.split()
        if len(cells) != len(columns):
            raise SourceError(path, f"line {first + r}", f"{len(cells)} values for the {len(columns)} columns "
                                                         f"{' '.join(columns)}")
        try:
            [float(c) for c in cells]
        except ValueError:
            raise SourceError(path, f"line {first + r}", f"not a number in {line!r}") from None
    raise SourceError(path, f"line {first}", "rows numpy cannot read as numbers")  # not reached: a row is named


def _triclinic_box(bounding: np.ndarray, tilt: np.ndarray) -> np.ndarray:
    """A triclinic box's lo and hi (3, 2) from the bounding box a dump writes with its tilt factors xy, xz, yz
    (LAMMPS's Howto triclinic: xlo_bound = xlo + min(0, xy, xz, xy + xz), …)."""
    xy, xz, yz = tilt
    box = bounding.copy()
    box[0] -= (min(0.0, xy, xz, xy + xz), max(0.0, xy, xz, xy + xz))
    box[1] -= (min(0.0, yz), max(0.0, yz))
    return box


def frame_tilt(path, frame: Frame, dimension: int) -> np.ndarray | None:
    """The tilt factors of a frame's box as the system has them (`forcenet.boxes.tilt_labels`: xy in 2D), None for
    an orthogonal box; a 2D system's box may be tilted only in its plane."""
    if not np.any(frame.tilt):
        return None
    if dimension == 2 and np.any(frame.tilt[1:]):
        raise SourceError(path, f"timestep {frame.timestep} (line {frame.line})",
                          f"tilt factors xz = {frame.tilt[1]:g}, yz = {frame.tilt[2]:g} out of the plane of a 2D system")
    return frame.tilt[:len(tilt_labels(dimension))].copy()


def _column(path, frame: Frame, name: str, what: str) -> np.ndarray:
    if name not in frame.columns:
        raise SourceError(path, f"column '{name}'", f"missing ({what}; the columns at line {frame.first_row_line - 1} "
                                                    f"are {' '.join(frame.columns)})")
    return frame.rows[:, frame.columns.index(name)]


def _ids(path, frame: Frame, name: str, what: str) -> np.ndarray:
    """A column of atom ids (n,) as integers; a NaN, infinite or fractional id raises `SourceError` naming its line
    (a cast would make ids 1 and 1.5 one atom, and put contacts on the wrong particle)."""
    values = _column(path, frame, name, what)
    bad = ~np.isfinite(values) | (values != np.round(values))
    if bad.any():
        r = int(np.argmax(bad))
        raise SourceError(path, f"line {frame.first_row_line + r}, column '{name}'",
                          f"atom id {values[r]:g} is not an integer")
    return values.astype(np.int64)


def _finite(path, frame: Frame, values: np.ndarray, name: str) -> None:
    bad = ~np.isfinite(values)
    if bad.any():
        raise SourceError(path, f"line {frame.first_row_line + int(np.argmax(bad))}, column '{name}'",
                          "NaN or infinite value")


#: LAMMPS's position columns of one axis, in the order they are looked for: unscaled, scaled (fractions of the box),
#: unwrapped (image flags applied: outside the box on a periodic axis), scaled unwrapped
POSITION_COLUMNS = ("{}", "{}s", "{}u", "{}su")


def _position_column(frame: Frame, axis: str) -> str | None:
    """The column an axis's positions are read from: the first of `POSITION_COLUMNS` the dump has, or None."""
    return next((form.format(axis) for form in POSITION_COLUMNS if form.format(axis) in frame.columns), None)


def _positions(path, frame: Frame, axes: Sequence[str]) -> np.ndarray:
    """Position (N, len(axes)) in the dump's length unit, inside the box on its periodic axes when the dump gave
    them unwrapped. Scaled positions are fractions of the box's edges: in a triclinic box of all of them together,
    so an axis scaled and another not are refused there."""
    columns, values = [], np.empty((len(frame.rows), len(axes)))
    for a, axis in enumerate(axes):
        name = _position_column(frame, axis)
        if name is None:
            names = [form.format(axis) for form in POSITION_COLUMNS]
            raise SourceError(path, f"column '{axis}'", f"missing (the positions: one of {', '.join(names)}; the "
                                                        f"columns at line {frame.first_row_line - 1} are "
                                                        f"{' '.join(frame.columns)})")
        values[:, a] = _column(path, frame, name, "")
        _finite(path, frame, values[:, a], name)
        columns.append(name)
    lo, hi = frame.box[:len(axes), 0], frame.box[:len(axes), 1]
    tilt = frame.tilt[:len(tilt_labels(len(axes)))] if np.any(frame.tilt) else None
    scaled = np.array(["s" in name[1:] for name in columns])  # xs, xsu: fractions of the dump's box
    if tilt is not None and scaled.any() and not scaled.all():
        raise SourceError(path, f"column '{columns[int(np.argmin(scaled))]}'",
                          f"scaled and unscaled positions ({' '.join(columns)}) in a triclinic box: give all scaled "
                          "or none")
    if tilt is not None and scaled.all():
        position = lo + values @ box_vectors(lo, hi, tilt)
    else:
        position = np.where(scaled, lo + values * (hi - lo), values)
    unwrapped = np.array([name.endswith("u") for name in columns])  # back into the box, as LAMMPS's x
    periodic = np.asarray(frame.periodic[:len(axes)], dtype=bool)
    if np.any(unwrapped & periodic):
        position = fold_into_box(position, lo, hi, unwrapped & periodic, tilt)
    return position


@dataclass
class WallSource:
    """One source of wall forces in the atoms dump (``source.wall_columns``: one wall fix's per-atom force columns):
    its columns, the wall ids it may touch (`WALL_NAMES` indices; None: every face of a bounded axis, the nearest
    taken) and the config key that names it, for messages."""

    columns: list[str]
    walls: tuple[int, ...] | None
    key: str


def wall_sources(given: Any, dimension: int) -> list[WallSource]:
    """The wall sources of ``source.wall_columns``: one list of column names (one source, e.g. ``fix
    wall/gran/region … contacts``: its contact at the box face nearest the atom), or a list of sources ``{columns,
    walls}`` (several wall fixes, e.g. ``fix wall/gran … xplane`` and ``… yplane``: each source's contact at the
    nearest of its own walls, so a corner atom touching both gets two). `SourceError` naming the key for a wall
    that is not one of the system's."""
    if not given:
        return []
    if all(isinstance(item, str) for item in given):
        return [WallSource(list(given), None, "source.wall_columns")]
    sources = []
    for k, item in enumerate(given):
        key = f"source.wall_columns[{k}]"
        names = list(item["walls"])
        wrong = [name for name in names if name not in WALL_NAMES[:2 * dimension]]
        if wrong:
            raise SourceError(key, "walls", f"{wrong[0]!r} is not a wall of a {dimension}D system (one of "
                                            f"{', '.join(WALL_NAMES[:2 * dimension])})")
        sources.append(WallSource(list(item["columns"]), tuple(WALL_NAMES.index(name) for name in names), key))
    return sources


def atom_state(path, frame: Frame, dimension: int, wall_columns: Any = None):
    """(ids, position (N, d), radius, box_lo, box_hi, wall forces) of one atoms frame; the wall forces are a list
    of (N, d) arrays, one per source of ``wall_columns`` (`wall_sources`), or None without any."""
    if len(frame.rows) == 0:
        raise SourceError(path, f"timestep {frame.timestep} (line {frame.line})", "no atoms")
    ids = _ids(path, frame, "id", "the atom ids")
    name = _position_column(frame, "z")
    if dimension == 3 and name is None:
        raise SourceError(path, "column 'z'", "missing: the system is declared 3D (dimension: 3) but the dump has no z")
    position = _positions(path, frame, AXIS_LABELS[:dimension])
    if name is not None and len(frame.rows) > 1:
        z = position[:, 2] if dimension == 3 else _column(path, frame, name, "")
        if dimension == 3 and np.ptp(z) == 0:
            raise SourceError(path, f"column '{name}' (timestep {frame.timestep}, line {frame.line})",
                              f"every atom at {name} = {z[0]:g}: a 2D state, but the system is declared 3D "
                              "(dimension: 3)")
        if dimension == 2 and np.ptp(z) > 0:
            raise SourceError(path, f"column '{name}' (timestep {frame.timestep}, line {frame.line})",
                              "the atoms are spread in z: a 3D state, but the system is declared 2D (dimension: 2)")
    size_column = "radius" if "radius" in frame.columns or "diameter" not in frame.columns else "diameter"
    radius = _column(path, frame, size_column, "the atom radii, or their diameters")
    _finite(path, frame, radius, size_column)
    if np.any(radius <= 0):
        raise SourceError(path, f"line {frame.first_row_line + int(np.argmax(radius <= 0))}, column '{size_column}'",
                          f"{size_column} {radius[np.argmax(radius <= 0)]:g} is not positive")
    if size_column == "diameter":
        radius = 0.5 * radius
    unique, first = np.unique(ids, return_index=True)
    if len(unique) != len(ids):
        again = int(np.setdiff1d(np.arange(len(ids)), first)[0])
        r = int(np.flatnonzero(ids == ids[again])[0])
        raise SourceError(path, f"line {frame.first_row_line + again}, column 'id'",
                          f"atom id {ids[again]} repeats (first on line {frame.first_row_line + r})")
    same = coincident_pair(position)
    if same is not None:
        a, b = same
        raise SourceError(path, f"lines {frame.first_row_line + a} and {frame.first_row_line + b}",
                          f"atoms {ids[a]} and {ids[b]} are at the same position "
                          f"({', '.join(f'{v:g}' for v in position[a])}) at timestep {frame.timestep}")
    order = np.argsort(ids)  # particles in id order, as LAMMPS numbers them
    wall_forces = None
    if wall_columns:
        wall_forces = []
        for wall in wall_sources(wall_columns, dimension):
            force = np.stack([_column(path, frame, c, wall.key) for c in wall.columns], axis=1)
            for c, name in enumerate(wall.columns):
                _finite(path, frame, force[:, c], name)
            wall_forces.append(force[:, :dimension][order])
    return (ids[order], position[order], radius[order], frame.box[:dimension, 0],
            frame.box[:dimension, 1], wall_forces)


def pair_forces(path, frame: Frame, ids: np.ndarray, position: np.ndarray, columns: Mapping[str, Any],
                atoms_path, period: np.ndarray | None = None, *, signed: str | None = None,
                duplicates: str | None = None) -> tuple[np.ndarray, ...]:
    """(i, j, F_n (C, d), F_t (C, d), disagreement (C,) or None) of one pairs frame, i < j indices into the atoms of
    the same timestep; a force given as a magnitude points along the line from j's image nearest to i (`period`:
    the box's periodic edge vectors, `forcenet.boxes.box_periods`) to i, and a total force (`columns["total"]`, in
    place of normal and tangential) is split along that line (`split_total_force`). `signed`: how a one-column
    tangential force is read (``source.signed_tangential``, `common.SIGNED_TANGENTIAL`; None: a magnitude ≥ 0);
    `duplicates`: ``source.duplicate_contacts`` (a pair listed from each side, as ``newton off`` lists a pair
    across processors, merged by the mean; None: refused), whose disagreement is returned."""
    dimension = position.shape[1]
    force_keys = ("total",) if "total" in columns else ("normal", "tangential")
    names = {key: ([columns[key]] if isinstance(columns[key], str) else list(columns[key]))
             for key in ("i", "j", *force_keys)}
    values = {key: np.stack([_column(path, frame, c, f"source.pair_columns.{key}") for c in cols], axis=1)
              for key, cols in names.items()}
    for key in ("i", "j"):
        values[key] = _ids(path, frame, names[key][0], f"source.pair_columns.{key}")[:, None]
    for key in force_keys:
        for c, name in enumerate(names[key]):
            _finite(path, frame, values[key][:, c], name)
        allowed = (2, 3) if key == "total" else (1, 2, 3)
        if values[key].shape[1] not in allowed or (values[key].shape[1] == 2 and dimension == 3):
            raise SourceError(path, f"source.pair_columns.{key}",
                              ("needs the vector's " if key == "total" else "needs 1 column (magnitude) or the vector's ")
                              + f"{dimension} or 3 components")
    touching = np.any(np.concatenate([values[key] for key in force_keys], axis=1) != 0, axis=1)
    index = {}
    for key in ("i", "j"):  # ids are sorted (`atom_state`): each pair's atoms found by bisection, not a Python loop
        atoms = values[key][:, 0]
        slot = np.minimum(np.searchsorted(ids, atoms), len(ids) - 1)
        found = ids[slot] == atoms
        missing = np.flatnonzero(touching & ~found)
        if missing.size:
            r = int(missing[0])
            raise SourceError(path, f"line {frame.first_row_line + r}, column '{names[key][0]}'",
                              f"atom id {atoms[r]} is not in {atoms_path} at timestep {frame.timestep}")
        index[key] = np.where(found, slot, -1)
    rows = np.flatnonzero(touching)
    for key in force_keys:  # a magnitude (one column) is signed the same way as in the table importer: ≥ 0
        if key != "total" and values[key].shape[1] == 1 and not (key == "tangential" and signed):
            r = negative_magnitude(values[key][rows])
            if r is not None:
                raise SourceError(path, f"line {frame.first_row_line + rows[r]}, column '{names[key][0]}'",
                                  f"a force magnitude must be ≥ 0, got {values[key][rows[r], 0]:g} "
                                  f"(source.pair_columns.{key} names a magnitude, repulsive > 0)" if key == "normal" else
                                  negative_tangential_problem(values[key][rows[r], 0]))
    i, j = index["i"][rows], index["j"][rows]
    same = i == j
    if same.any():
        raise SourceError(path, f"line {frame.first_row_line + rows[np.argmax(same)]}", "an atom paired with itself")
    n = normal_unit_vectors(position, i, j, period)
    if "total" in columns:
        fn, ft = split_total_force(values["total"][rows][:, :dimension], n)
    else:
        fn = values["normal"][rows]
        fn = fn[:, :1] * n if fn.shape[1] == 1 else fn[:, :dimension]
        ft = values["tangential"][rows]
        ft = tangential_from_column(ft[:, 0], n, signed) if ft.shape[1] == 1 else ft[:, :dimension]
    swapped = i > j
    i, j, fn, ft = order_pairs(i, j, fn, ft)
    repeat = repeated_contact(i, j, swapped, duplicates)
    if repeat is not None:
        r = repeat.row
        raise SourceError(path, f"line {frame.first_row_line + rows[r]}",
                          f"the pair of atoms {ids[i[r]]}, {ids[j[r]]} appears {repeat.how} at timestep "
                          f"{frame.timestep} (first on line {frame.first_row_line + rows[repeat.first]}): "
                          f"{repeat.remedy}")
    disagreement = None
    if duplicates is not None:
        i, j, fn, ft, disagreement = merge_two_sided(i, j, fn, ft)
    order = np.lexsort((j, i))
    return i[order], j[order], fn[order], ft[order], None if disagreement is None else disagreement[order]


def wall_contacts(position, radius, box_lo, box_hi, wall_force, bounded=None, walls=None):
    """One wall contact per atom with a non-zero wall force (N, d), at the box face nearest to it among those of the
    `bounded` axes ((d,) bool; default all: a periodic axis has no walls) and, where `walls` (wall ids) is given,
    among those walls."""
    if wall_force is None:
        return np.zeros(0, np.int64), np.zeros(0, np.int64), None
    atoms = np.flatnonzero(np.any(wall_force != 0, axis=1))
    d = position.shape[1]
    bounded = np.ones(d, bool) if bounded is None else np.asarray(bounded, bool)
    allowed = np.concatenate([bounded, bounded])  # faces in the order lo x, y, z then hi x, y, z
    if walls is not None:
        allowed &= np.isin(np.r_[2 * np.arange(d), 2 * np.arange(d) + 1], list(walls))
    gaps = np.concatenate([position[atoms] - box_lo, box_hi - position[atoms]], axis=1)  # (W, 2d): lo faces, hi faces
    gaps[:, ~allowed] = np.inf
    face = np.argmin(gaps, axis=1)
    wall = np.where(face < d, 2 * face, 2 * (face - d) + 1)
    return atoms, wall.astype(np.int64), wall_force[atoms]


def source_wall_contacts(path, frame: Frame, position, radius, box_lo, box_hi, wall_forces, bounded, sources,
                         rule: str):
    """The wall contacts of every source (`wall_sources`; `wall_forces` one (N, d) array each), in atom order and,
    for one atom, source order; `rule` (``source.wall_forces``) ``summed_per_wall`` sums the contacts of one atom at
    one wall. A source whose walls all lie on periodic axes, and carries a force, is refused naming its key."""
    if wall_forces is None:
        return np.zeros(0, np.int64), np.zeros(0, np.int64), None
    d = position.shape[1]
    parts = []
    for k, (source, force) in enumerate(zip(sources, wall_forces)):
        if source.walls is not None and np.any(force != 0):
            usable = [w for w in source.walls if bounded[w // 2]]
            if not usable:
                names = ", ".join(WALL_NAMES[w] for w in source.walls)
                raise SourceError(path, f"timestep {frame.timestep} (line {frame.line})",
                                  f"wall forces in {source.key}, whose walls ({names}) lie on periodic axes of the "
                                  "box: no walls there")
        atoms, wall, f = wall_contacts(position, radius, box_lo, box_hi, force, bounded, source.walls)
        parts.append((atoms, wall, f, np.full(len(atoms), k)))
    atoms, wall, force, which = (np.concatenate([part[c] for part in parts]) for c in range(4))
    order = np.lexsort((which, atoms))
    atoms, wall, force = atoms[order], wall[order], force[order].reshape(-1, d)
    if rule == "summed_per_wall":
        atoms, wall, force = sum_per_wall(atoms, wall, force)
    return atoms.astype(np.int64), wall.astype(np.int64), force


def read_run(run: Mapping[str, Any], dimension: int, source: Mapping[str, Any]) -> list[SourceState]:
    """The states of one run: ``{atoms: dump custom, pairs: dump local}`` (module docstring)."""
    atoms_path, pairs_path = run["atoms"], run["pairs"]
    given = source.get("pair_columns", {})
    # a total force replaces the default normal and tangential columns (the schema refuses both given)
    columns = {**{key: value for key, value in DEFAULT_PAIR_COLUMNS.items()
                  if "total" not in given or key not in ("normal", "tangential")}, **given}
    wanted = source.get("timesteps")
    # the conventions of the source (forcenet.importers.common): checked once, before any frame is read
    one_column = "total" not in columns and (isinstance(columns["tangential"], str) or len(columns["tangential"]) == 1)
    signed = signed_tangential_rule(source, dimension, one_column)
    duplicates, walls_rule = duplicate_rule(source), wall_rule(source)
    sources = wall_sources(source.get("wall_columns"), dimension)
    states, have = [], []
    # frame by frame, the two dumps side by side: the memory of the raw rows is one frame's
    for a, p in zip_longest(read_frames(atoms_path, "ATOMS"), read_frames(pairs_path, "ENTRIES")):
        if a is None or p is None:
            longer, shorter, extra = (atoms_path, pairs_path, a) if p is None else (pairs_path, atoms_path, p)
            raise SourceError(longer, f"line {extra.line}", f"timestep {extra.timestep} has no match in {shorter}")
        if a.timestep != p.timestep:
            raise SourceError(pairs_path, f"line {p.line}", f"timestep {p.timestep} where {atoms_path} has timestep "
                                                            f"{a.timestep} (line {a.line}): the dumps do not match")
        have.append(a.timestep)
        if wanted is not None and a.timestep not in wanted:
            continue
        ids, position, radius, lo, hi, wall_force = atom_state(atoms_path, a, dimension, source.get("wall_columns"))
        tilt = frame_tilt(atoms_path, a, dimension)
        if "box" in source:
            lo, hi = np.asarray(source["box"]["lo"], float), np.asarray(source["box"]["hi"], float)
            tilt = np.asarray(source["box"]["tilt"], float) if "tilt" in source["box"] else None
        # a 2D LAMMPS run is periodic in z by rule: only the system's own axes count
        periodic = np.asarray(a.periodic[:dimension], bool)
        axes = "".join(label for label, wrap in zip(AXIS_LABELS, periodic) if wrap)
        if tilt is not None:
            problem = tilt_problem(axes, tilt, dimension)
            if problem:
                raise (SourceError("source.box", "tilt", problem) if "box" in source else
                       SourceError(atoms_path, f"timestep {a.timestep} (line {a.line})", problem))
            if not np.any(tilt):
                tilt = None
        if wall_force is not None and any(np.any(force != 0) for force in wall_force):
            if periodic.all():
                raise SourceError(atoms_path, f"timestep {a.timestep} (line {a.line})",
                                  "wall forces in source.wall_columns, but every axis of the box is periodic: no walls")
            if tilt is not None and np.any(tilted_faces(tilt, dimension) & ~periodic):
                raise SourceError(atoms_path, f"timestep {a.timestep} (line {a.line})",
                                  "wall forces in source.wall_columns on a tilted face of a triclinic box: walls are "
                                  "imported on untilted faces only")
        i, j, fn, ft, disagreement = pair_forces(pairs_path, p, ids, position, columns, atoms_path,
                                                 box_periods(axes, lo, hi, tilt), signed=signed, duplicates=duplicates)
        wall_atoms, wall_id, wall_f = source_wall_contacts(atoms_path, a, position, radius, lo, hi, wall_force,
                                                           ~periodic, sources, walls_rule)
        states.append(SourceState(position=position, radius=radius, contact_i=i, contact_j=j, force_normal=fn,
                                  force_tangential=ft, box_lo=lo, box_hi=hi, files=(str(atoms_path), str(pairs_path)),
                                  timestep=a.timestep, wall_particle=wall_atoms, wall_id=wall_id, wall_force=wall_f,
                                  periodic_axes=axes, tilt=tilt, force_disagreement=disagreement))
    missing = [step for step in wanted or () if step not in have]
    if missing:
        raise SourceError(atoms_path, "source.timesteps", f"timestep {missing[0]} is not in the dump ({have})")
    return states
