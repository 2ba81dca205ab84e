"""Compare two builds' outputs value by value (a restructuring must not change what the pipeline computes).

`compare_trees(before, after)` walks two results folders and compares every netCDF file and every table (CSV)
they share:

* netCDF: the same variables and coordinates, each with the same dims, dtype and values. Snapshots (files under
  a ``sim/`` folder: the DEM's output) must agree bit for bit; every other file (analysis, aggregates,
  distances) within `rtol`/`atol`, NaN equal to NaN. Attributes are not compared: they carry the commit, the
  date and the config, which differ between builds by design.
* CSV: the same header and rows; numeric cells within the same tolerance, the rest equal as text.

Files found in only one of the trees are reported too. Each difference is one line naming the file and the
variable (or row and column) and the largest difference.
"""
from __future__ import annotations

import csv
import math
from pathlib import Path

import numpy as np
import xarray as xr

from forcenet.datasets.paths import SIM_DIR

#: relative and absolute tolerance outside the DEM's own output
DEFAULT_RTOL = 1e-9
DEFAULT_ATOL = 1e-12


def _is_snapshot(relative: Path) -> bool:
    """Whether a results-relative path is a DEM snapshot (compared bit for bit): a file of the runs' folder."""
    return bool(relative.parts) and relative.parts[0] == SIM_DIR


def _array_difference(name: str, a: np.ndarray, b: np.ndarray, exact: bool, rtol: float, atol: float) -> str | None:
    """One line describing how two arrays differ, or None if they agree (NaN == NaN)."""
    if a.shape != b.shape:
        return f"{name}: shape {a.shape} against {b.shape}"
    if a.dtype != b.dtype:
        return f"{name}: dtype {a.dtype} against {b.dtype}"
    if a.dtype.kind not in "fc":
        if not np.array_equal(a, b):
            return f"{name}: {int(np.sum(a != b))} of {a.size} values differ"
        return None
    if exact:
        same = (a == b) | (np.isnan(a) & np.isnan(b))
        # bit for bit: −0.0 against 0.0 or two NaN payloads are not told apart by ==; compare the bytes too
        if same.all() and a.tobytes() == b.tobytes():
            return None
        if same.all():
            return f"{name}: equal values with different bit patterns (signed zeros or NaN payloads)"
    else:
        same = np.isclose(a, b, rtol=rtol, atol=atol, equal_nan=True)
        if same.all():
            return None
    finite = np.isfinite(a) & np.isfinite(b)
    largest = float(np.max(np.abs(a - b)[finite])) if (finite & ~same).any() else math.nan
    return (f"{name}: {int(np.sum(~same))} of {a.size} values differ "
            f"({'bit for bit' if exact else f'rtol {rtol:g}, atol {atol:g}'}; largest |Δ| {largest:.3g})")


def compare_datasets(before: xr.Dataset, after: xr.Dataset, exact: bool,
                     rtol: float = DEFAULT_RTOL, atol: float = DEFAULT_ATOL) -> list[str]:
    """Differences between two datasets' variables and coordinates (attributes ignored); [] if none."""
    problems = []
    names_before = set(before.variables)
    names_after = set(after.variables)
    for name in sorted(names_before - names_after):
        problems.append(f"{name}: only before")
    for name in sorted(names_after - names_before):
        problems.append(f"{name}: only after")
    for name in sorted(names_before & names_after):
        a, b = before[name], after[name]
        if a.dims != b.dims:
            problems.append(f"{name}: dims {a.dims} against {b.dims}")
            continue
        line = _array_difference(name, np.asarray(a.values), np.asarray(b.values), exact, rtol, atol)
        if line:
            problems.append(line)
    return problems


def _csv_cell_differs(a: str, b: str, rtol: float, atol: float) -> bool:
    """Whether two CSV cells differ: as numbers within tolerance when both parse, else as text."""
    if a == b:
        return False
    try:
        x, y = float(a), float(b)
    except ValueError:
        return True
    if math.isnan(x) and math.isnan(y):
        return False
    return not math.isclose(x, y, rel_tol=rtol, abs_tol=atol)


def compare_csv(before: Path, after: Path, rtol: float = DEFAULT_RTOL, atol: float = DEFAULT_ATOL) -> list[str]:
    """Differences between two CSV tables: header, row count, and each differing cell (row, column)."""
    with open(before, newline="") as handle:
        rows_before = list(csv.reader(handle))
    with open(after, newline="") as handle:
        rows_after = list(csv.reader(handle))
    if not rows_before or not rows_after:
        return [] if rows_before == rows_after else ["one table is empty"]
    if rows_before[0] != rows_after[0]:
        return [f"header {rows_before[0]} against {rows_after[0]}"]
    if len(rows_before) != len(rows_after):
        return [f"{len(rows_before) - 1} rows against {len(rows_after) - 1}"]
    header = rows_before[0]
    problems = []
    for number, (row_a, row_b) in enumerate(zip(rows_before[1:], rows_after[1:]), start=1):
        for column, a, b in zip(header, row_a, row_b):
            if _csv_cell_differs(a, b, rtol, atol):
                problems.append(f"row {number}, {column}: {a!r} against {b!r}")
    return problems


def compare_trees(before: str | Path, after: str | Path, rtol: float = DEFAULT_RTOL,
                  atol: float = DEFAULT_ATOL) -> list[str]:
    """Every difference between two results folders' netCDF files and CSV tables, one line each ([] if none).

    Paths are matched relative to each folder; hidden folders (a run's ``.partial`` staging) are skipped."""
    before, after = Path(before), Path(after)

    def files(root: Path) -> set[Path]:
        return {path.relative_to(root) for path in root.rglob("*")
                if path.is_file() and path.suffix in (".nc", ".csv")
                and not any(part.startswith(".") for part in path.relative_to(root).parts)}

    found_before, found_after = files(before), files(after)
    problems = [f"{path}: only in {before}" for path in sorted(found_before - found_after)]
    problems += [f"{path}: only in {after}" for path in sorted(found_after - found_before)]
    for relative in sorted(found_before & found_after):
        if relative.suffix == ".csv":
            lines = compare_csv(before / relative, after / relative, rtol, atol)
        else:
            with xr.open_dataset(before / relative) as a, xr.open_dataset(after / relative) as b:
                lines = compare_datasets(a.load(), b.load(), _is_snapshot(relative), rtol, atol)
        problems += [f"{relative}: {line}" for line in lines]
    return problems
