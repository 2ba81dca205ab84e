"""forcenet.report.p1_diagnostics on hand-countable networks: contact shares, percolation and ⟨S⟩/N-peak
thresholds, the two readings of P1 §5.2's shape parameter."""
from __future__ import annotations

import numpy as np
import pytest
import xarray as xr

from forcenet.report import p1_diagnostics as diag
from forcenet.report.p1_judging import SystemData

THRESHOLDS = np.array([0.0, 0.5, 1.0, 1.5])
RHO = np.array([0.80, 0.82, 0.84])


def measures(**variables) -> xr.Dataset:
    """A (realization 2, rho 3, threshold 4) measures dataset: every variable given as a nested list or array;
    the others zero."""
    dims = ("realization", "rho", "threshold")
    shape = (2, RHO.size, THRESHOLDS.size)
    names = ("edge_count", "percolates", "cluster_mean_size", "shape_parameter", "shape_parameter_cluster_mean")
    data = {name: (dims, np.asarray(variables.get(name, np.zeros(shape)), dtype=float)) for name in names}
    data["n_particles"] = (("realization", "rho"), np.full((2, RHO.size), 100.0))
    data["Z_no_rattlers"] = (("realization", "rho"), np.array([[0.1, 3.0, 4.0], [0.3, 3.2, 4.2]]))
    data["total_persistence"] = (("realization", "rho", "homology_dim"), np.zeros((2, RHO.size, 2)))
    return xr.Dataset(data, coords={"realization": [0, 1], "rho": RHO, "threshold": THRESHOLDS,
                                    "homology_dim": [0, 1]})


def system(ds: xr.Dataset, rho_j: float = 0.80, name: str = "2d_hertz") -> SystemData:
    return SystemData(name=name, dimension=2, force_law="hertz", data=ds, full=ds, rho_j=rho_j, rho_max=np.nan,
                      tolerance=0.01, window=0.02)


def test_contact_share_counts_the_edges_above_each_threshold():
    edges = np.zeros((2, 3, 4))
    edges[0, 1] = [10, 6, 3, 0]  # realization 0 at rho 0.82: 6 of 10 contacts carry F >= 0.5 <F>, ...
    edges[1, 1] = [20, 10, 2, 2]
    share = diag.contact_share_above(system(measures(edge_count=edges))).sel(rho=0.82)
    np.testing.assert_allclose(share.values, [1.0, (0.6 + 0.5) / 2, (0.3 + 0.1) / 2, (0.0 + 0.1) / 2])
    # a network without contacts has no share (not 0 %)
    assert np.isnan(diag.contact_share_above(system(measures(edge_count=edges))).sel(rho=0.80)).all()


def test_percolation_threshold_is_the_last_threshold_where_most_realizations_span():
    spans = np.zeros((2, 3, 4))
    spans[0, 2] = [1, 1, 0, 0]
    spans[1, 2] = [1, 1, 1, 0]  # at F_th = 1.0 one of two realizations spans: half, P1's majority rule holds
    ds = measures(percolates=spans)
    values = diag.percolation_threshold_per_rho(system(ds))
    assert values.sel(rho=0.84) == 1.0
    assert np.isnan(values.sel(rho=0.80))  # no realization spans at any threshold
    assert diag.percolation_threshold_per_rho(system(ds), majority=0.75).sel(rho=0.84) == 0.5


def test_cluster_size_peak_threshold_is_the_argmax_of_the_mean_size():
    size = np.zeros((2, 3, 4))
    size[:, 1] = [[1, 2, 8, 3], [1, 6, 2, 3]]  # means 1, 4, 5, 3: largest at F_th = 1.0, not 0.5 (one run's max)
    peaks = diag.size_peak_threshold_per_rho(system(measures(cluster_mean_size=size)))
    assert peaks.sel(rho=0.82) == 1.0
    assert np.isnan(peaks.sel(rho=0.80))  # no finite cluster: no peak


def test_the_shape_readings_and_their_swap():
    pooled = np.full((2, 3, 4), 0.75)  # one path of four particles: 3 edges / 4 particles
    per_cluster = np.full((2, 3, 4), 0.625)  # a path of four and a pair: mean of 0.75 and 0.5
    ds = measures(shape_parameter=pooled, shape_parameter_cluster_mean=per_cluster)
    readings = diag.shape_readings(system(ds))
    assert float(readings["pooled"][0].max()) == pytest.approx(0.75)
    assert float(readings["cluster_mean"][0].max()) == pytest.approx(0.625)
    swapped = diag.with_shape_reading(ds, "cluster_mean")
    np.testing.assert_array_equal(swapped["shape_parameter"].values, per_cluster)
    np.testing.assert_array_equal(ds["shape_parameter"].values, pooled)  # the input is left alone
    with pytest.raises(ValueError, match="unknown shape-parameter reading 'degree'"):
        diag.with_shape_reading(ds, "degree")


def test_network_rows_and_common_rho():
    edges = np.tile([10.0, 5.0, 2.0, 1.0], (2, 3, 1))
    rows = diag.network_rows(system(measures(edge_count=edges)), thresholds=(0.5, 1.0))
    assert list(rows["rho"]) == pytest.approx(list(RHO))
    assert list(rows["share_F>=0.5"]) == pytest.approx([0.5] * 3)
    assert list(rows["Z_no_rattlers"]) == pytest.approx([0.2, 3.1, 4.1])
    assert "strong N0/N" not in rows  # no persistence bins in these results
    # with P1's bins: the strong-bin N0/N beside the share of contacts at F >= 2.5 <F> that its points are born at
    bins = measures(edge_count=edges).assign_coords(threshold=[0.0, 1.0, 2.5, 3.0])
    counts = np.zeros((2, RHO.size, 5))
    counts[:, :, 3] = [[2.0, 4.0, 6.0], [4.0, 6.0, 8.0]]  # strong points of 100 particles
    bins["persistence_bin_count"] = (("realization", "rho", "persistence_bin"), counts)
    bins = bins.assign_coords(persistence_bin=["rough", "weak", "medium", "strong", "essential"])
    binned = diag.network_rows(system(bins), thresholds=(1.0,))
    assert list(binned["strong N0/N"]) == pytest.approx([0.03, 0.05, 0.07])
    assert list(binned["rough N0/N"]) == pytest.approx([0.0] * 3)
    assert list(binned["share_F>=2.5"]) == pytest.approx([0.2] * 3)  # 2 of 10 edges at F_th = 2.5
    first = system(measures(), rho_j=0.80)
    second = system(measures().sel(rho=[0.82, 0.84]), rho_j=0.815)
    # beyond rho_J + 0.01: 0.82 and 0.84 for the first, only 0.84 for the second (0.82 < 0.825)
    np.testing.assert_allclose(diag.common_rho(first, second), [0.84])
