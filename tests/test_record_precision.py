"""scripts/record_precision.py (forcenet.research.record_precision), whose table data/validation/README.md quotes:
on a record of the golden P1 snapshot, rounding nothing moves no measure, rounding to float16 moves the forces'
measures, and the cluster curves and diagrams are compared too."""
from __future__ import annotations

import numpy as np

from forcenet.datasets import read_snapshot, write_netcdf
from forcenet.datasets.records import record_dataset, record_encoding
from forcenet.research.record_precision import float32_differences
from test_golden import GOLDEN


def golden_record(tmp_path):
    snapshot = read_snapshot(GOLDEN / "snapshot_2d_linear_rho0.880.nc")
    record = record_dataset([snapshot], ["0.880"], simulation_sha256="x", cpu_seconds=1.0, title="golden")
    return write_netcdf(record, tmp_path / "states.nc", kind="run_record", encoding=record_encoding(record))


def test_rounding_nothing_moves_no_measure_and_float16_moves_the_forces(tmp_path):
    path = golden_record(tmp_path)
    same = float32_differences(path, "2d_linear", dtype=np.float64)
    assert same and all(value == 0.0 for value in same.values())
    assert {("total", "betti"), ("total", "clusters.cluster_count"), ("normal", "diagrams.birth")} <= set(same)
    coarse = float32_differences(path, "2d_linear", dtype=np.float16)
    assert coarse[("total", "mean_force")] > 1e-5 and coarse[("total", "thresholds")] == 0.0
