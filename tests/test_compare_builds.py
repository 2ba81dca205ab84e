"""forcenet.datasets.compare: two builds' outputs compared value by value (snapshots bit for bit)."""
import subprocess
import sys
from pathlib import Path

import numpy as np
import xarray as xr

from forcenet.datasets.compare import compare_csv, compare_datasets, compare_trees

ROOT = Path(__file__).resolve().parents[1]


def _dataset(force, attrs=None):
    return xr.Dataset({"force": ("contact", np.asarray(force, dtype=float))},
                      coords={"contact": np.arange(len(force))}, attrs=attrs or {})


def test_identical_datasets_differ_in_nothing_and_attributes_are_ignored():
    assert compare_datasets(_dataset([1.0, np.nan]), _dataset([1.0, np.nan], {"git_commit": "other"}),
                            exact=True) == []


def test_one_changed_value_is_named_with_its_size():
    [line] = compare_datasets(_dataset([1.0, 2.0, 3.0]), _dataset([1.0, 2.5, 3.0]), exact=False)
    assert line.startswith("force: 1 of 3 values differ") and "0.5" in line


def test_exact_comparison_sees_the_last_bit_that_the_tolerant_one_forgives():
    a, b = _dataset([1.0]), _dataset([np.nextafter(1.0, 2.0)])
    assert compare_datasets(a, b, exact=False) == []
    assert compare_datasets(a, b, exact=True) != []
    # bit for bit also tells −0.0 from 0.0, which == does not
    assert compare_datasets(_dataset([0.0]), _dataset([-0.0]), exact=True) != []


def test_missing_variable_dtype_and_dims_are_reported():
    a = _dataset([1.0, 2.0])
    b = a.assign(extra=("contact", [1, 2]))
    assert compare_datasets(a, b, exact=True) == ["extra: only after"]
    c = a.assign(force=a.force.astype("float32"))
    assert "dtype" in compare_datasets(a, c, exact=False)[0]


def test_csv_cells_are_numbers_within_tolerance_and_text_otherwise(tmp_path):
    (tmp_path / "a.csv").write_text("rho,B0/N,system\n0.80,0.1,2d_linear\n0.81,nan,2d_linear\n")
    (tmp_path / "b.csv").write_text("rho,B0/N,system\n0.8,0.1000000000001,2d_linear\n0.81,nan,2d_hertz\n")
    assert compare_csv(tmp_path / "a.csv", tmp_path / "b.csv") == ["row 2, system: '2d_linear' against '2d_hertz'"]


def test_trees_snapshots_bit_for_bit_the_rest_within_tolerance_and_the_script_exit_code(tmp_path):
    for side, last_bit in (("before", 1.0), ("after", np.nextafter(1.0, 2.0))):
        (tmp_path / side / "sim" / "s" / "r00").mkdir(parents=True)
        (tmp_path / side / "s").mkdir()
        _dataset([last_bit]).to_netcdf(tmp_path / side / "sim" / "s" / "r00" / "rho0.800.nc")
        _dataset([last_bit]).to_netcdf(tmp_path / side / "s" / "network_measures.nc")
    (tmp_path / "after" / "s" / "extra.csv").write_text("a\n1\n")
    problems = compare_trees(tmp_path / "before", tmp_path / "after")
    assert len(problems) == 2
    assert any(p.startswith("s/extra.csv: only in") for p in problems)
    assert any(p.startswith("sim/s/r00/rho0.800.nc: force") for p in problems)  # the snapshot, not the aggregate
    script = [sys.executable, str(ROOT / "scripts" / "compare_builds.py")]
    assert subprocess.run(script + [str(tmp_path / "before"), str(tmp_path / "after")],
                          capture_output=True).returncode == 1
    assert subprocess.run(script + [str(tmp_path / "before"), str(tmp_path / "before")],
                          capture_output=True).returncode == 0
