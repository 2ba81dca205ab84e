"""scripts/p2_finite_loops.py: the share of β1 distances before ρ_J above zero under each never-dying convention."""
from __future__ import annotations

import sys

import pytest

from conftest import REPO
from test_report_p2 import p2_shaped

sys.path.insert(0, str(REPO / "scripts"))
import p2_finite_loops  # noqa: E402

from forcenet.report import p2  # noqa: E402


def test_the_loops_before_jamming_are_counted_under_each_convention(tmp_path):
    shipped = p2_shaped()  # rho_J = 0.78; every beta1 distance > 0
    rho_j = p2.jamming_density(shipped, 2)
    dropped = shipped.copy(deep=True)
    loops = dict(force_kind="normal", homology_dim=1, metric="bottleneck")
    before = shipped["rho"].values[shipped["rho"].values < rho_j]
    dropped["distance"].loc[{**loops, "rho": before}] = 0.0  # no finite loop before jamming
    dropped["distance"].loc[{**loops, "rho": before[-1:], "realization": 0}] = 0.3  # one pair of one realization
    for folder, ds in ((tmp_path, shipped), (tmp_path / p2_finite_loops.DROP_FOLDER, dropped)):
        (folder / "2d_poly_mu05").mkdir(parents=True)
        ds.to_netcdf(folder / "2d_poly_mu05" / "distances.nc")
    row = p2_finite_loops.loop_row(tmp_path, "2d_poly_mu05").strip("| ").split(" | ")
    share = 100 / (before.size * shipped.sizes["realization"])
    assert row == ["2d_poly_mu05", f"{rho_j:.4f}", "100.0 %", f"{shipped['rho'].values[0]:.3f}", f"{share:.1f} %",
                   f"{before[-1]:.3f}"]


def test_a_missing_distances_file_is_named_in_one_line(tmp_path):
    with pytest.raises(SystemExit, match=r"2d_poly_mu05/distances.nc is missing: make it with"):
        p2_finite_loops.loop_row(tmp_path, "2d_poly_mu05")
