"""Golden files (tests/data/golden/, tests/data/README.md): real smoke-build snapshots and their analyses, read by
the unit tier without building anything. Each snapshot, analysed again with the analysis settings of the config it
records, gives its committed analysis value for value: a change to the network, topology or measures that moves any
number of a P1 2D (rattlers removed), a 3D (hollow tetrahedra) or a P2 (rattlers kept) analysis shows here first."""
from __future__ import annotations

import json
import logging
from pathlib import Path

import numpy as np
import pytest

from forcenet import pipeline
from forcenet.datasets import read_dataset, read_snapshot

GOLDEN = Path(__file__).resolve().parent / "data" / "golden"
CASES = [("2d_linear", "0.880"), ("3d_hertz", "0.680"), ("2d_poly_mu05", "0.860")]


@pytest.mark.parametrize("system, rho", CASES)
def test_a_golden_snapshot_analyses_to_its_golden_analysis(system, rho, tmp_path):
    snapshot_path = GOLDEN / f"snapshot_{system}_rho{rho}.nc"
    snapshot = read_snapshot(snapshot_path)
    assert snapshot.attrs["system"] == system and abs(float(snapshot.rho) - float(rho)) < 5e-3  # the state it names
    params = pipeline.snapshot_analysis_params(json.loads(snapshot.attrs["config"]), system)
    pipeline.analyze_snapshot(str(snapshot_path), str(tmp_path / "analysis.nc"), params,
                              logging.getLogger("forcenet.tests.golden"), snap=snapshot)
    again = read_dataset(tmp_path / "analysis.nc", "analysis")
    golden = read_dataset(GOLDEN / f"analysis_{system}_rho{rho}.nc", "analysis")
    assert set(again.variables) == set(golden.variables)
    for name, variable in golden.variables.items():
        assert variable.dims == again[name].dims, name
        assert np.array_equal(variable.values, again[name].values), name
    for key in ("rattler_rule", "flag_complex", "system", "config_sha256"):
        assert again.attrs[key] == golden.attrs[key], key


def test_the_golden_analyses_differ_from_one_another():
    """The comparison above would pass vacuously if the files were copies: three systems, three sets of numbers."""
    betti = [read_dataset(GOLDEN / f"analysis_{system}_rho{rho}.nc", "analysis")["betti"].values for system, rho in CASES]
    assert betti[0].shape != betti[1].shape  # 3D has B2
    assert not np.array_equal(betti[0], betti[2])


def test_a_file_without_its_kinds_global_attribute_is_refused_naming_it(tmp_path):
    """The contract of each kind names its own global attributes (`schema.KIND_GLOBAL_ATTRS`): an analysis without
    the flag complex that made its diagrams is refused on reading, the golden one as it is is read."""
    from forcenet.datasets import DatasetError, open_dataset

    golden = GOLDEN / "analysis_3d_hertz_rho0.680.nc"
    read_dataset(golden, "analysis")
    ds = open_dataset(golden)
    del ds.attrs["flag_complex"]
    ds.to_netcdf(tmp_path / "analysis.nc")
    with pytest.raises(DatasetError, match="not a valid analysis file: global attribute 'flag_complex' missing$"):
        read_dataset(tmp_path / "analysis.nc", "analysis")
