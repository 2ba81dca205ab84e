"""The netCDF data model: round trips, units and long names everywhere, provenance, atomic writes."""
from __future__ import annotations

import numpy as np
import pytest
import xarray as xr

from forcenet.datasets import (SchemaError, open_dataset, provenance_attrs, read_snapshot, validate_dataset,
                               write_netcdf, write_snapshot)
from forcenet.datasets.aggregate import stack_diagrams, stack_network_measures
from forcenet.datasets.analysis import analysis_dataset
from forcenet.measures.snapshot import compute_snapshot_measures
from forcenet.network import build_force_network


def attrs():
    return provenance_attrs(system="2d_test", realization=3, seed=42, config={"seed": 1}, title="test")


def two_triangles_snapshot(rho=0.8):
    """Four disks: two triangles sharing the edge 1-2, particle 0 touching the x_lo wall."""
    position = np.array([[0.5, 0.5], [1.5, 0.5], [1.0, 1.366], [2.0, 1.366]])
    contact_i = np.array([0, 0, 1, 1, 2])
    contact_j = np.array([1, 2, 2, 3, 3])
    force_normal = np.array([[1.0, 0], [0.5, 0.8], [-0.5, 0.8], [0.5, 0.8], [1.0, 0]]) * 0.1
    force_tangential = np.array([[0, 0.01], [0.01, 0], [0, 0.02], [0.0, 0], [0, 0.03]])
    return dict(position=position, radius=np.full(4, 0.5), velocity=np.zeros((4, 2)), angular_velocity=np.zeros(4),
                contact_i=contact_i, contact_j=contact_j, force_normal=force_normal,
                force_tangential=force_tangential, wall_contact_particle=[0], wall_contact_wall=[0],
                wall_contact_force=[[0.1, 0.0]], box_lo=[0.0, 0.0], box_hi=[3.0, 3.0], rho=rho, Z=2.5,
                kinetic_energy=1e-9, pressure=0.01, time=12.5, step=625, relaxation_steps=100)


def test_snapshot_round_trip_keeps_values_units_and_provenance(tmp_path):
    arrays = two_triangles_snapshot()
    path = write_snapshot(tmp_path / "rho0.800.nc", attrs=attrs(), **arrays)
    ds = read_snapshot(path)
    validate_dataset(ds)
    np.testing.assert_array_equal(ds.position.values, arrays["position"])
    np.testing.assert_array_equal(ds.contact_j.values, arrays["contact_j"])
    np.testing.assert_array_equal(ds.force_tangential.values, arrays["force_tangential"])
    assert float(ds.rho) == 0.8 and int(ds.step) == 625
    assert ds.position.attrs["units"] == "d_ave" and ds.force_normal.attrs["long_name"]
    for key in ("system", "realization", "seed", "forcenet_version", "git_commit", "config_sha256", "config"):
        assert key in ds.attrs
    assert ds.attrs["seed"] == 42 and ds.attrs["realization"] == 3
    assert ds.encoding.get("source") and ds.position.encoding["zlib"]


def test_analysis_round_trip_and_stacking(tmp_path):
    snapshots = [two_triangles_snapshot(rho) for rho in (0.80, 0.82)]
    analyses = []
    for k, snap in enumerate(snapshots):
        measures = {kind: compute_snapshot_measures(build_force_network(
            snap["position"], snap["contact_i"], snap["contact_j"], snap["force_normal"], snap["force_tangential"],
            kind=kind, remove_rattlers=False, wall_particle=[0], wall_id=[0]), thresholds=np.linspace(0, 3, 61),
            force_bin_edges=np.linspace(0, 6, 61)) for kind in ("total", "normal", "tangential")}
        ds = analysis_dataset(measures, rho=snap["rho"], attrs=attrs())
        path = write_netcdf(ds, tmp_path / f"a{k}.nc")
        back = open_dataset(path)
        xr.testing.assert_identical(back, ds)
        analyses.append(back)
    first = analyses[0]
    # two triangles sharing an edge: one component at F_th = 0, no loop (3-particle loops never count)
    assert int(first.betti.sel(force_kind="total", homology_dim=0, threshold=0.0)) == 1
    assert int(first.betti.sel(force_kind="total", homology_dim=1).max()) == 0
    total = first.where(first.diagram_force_kind == 0, drop=True)
    assert int(total.essential.sum()) == 1 and np.isneginf(total.death.values[total.essential.values == 1]).all()
    stacked = stack_network_measures(analyses, [0, 0], [0.80, 0.82], attrs())
    assert stacked.betti.dims == ("realization", "rho", "force_kind", "homology_dim", "threshold")
    validate_dataset(stacked)
    points = stack_diagrams(analyses, [0, 0], [0.80, 0.82], attrs())
    assert points.sizes["point"] == sum(a.sizes["point"] for a in analyses)
    validate_dataset(points)


def test_validation_names_what_is_missing(tmp_path):
    ds = xr.Dataset({"x": ("particle", np.zeros(3), {"units": "d_ave"})}, attrs=attrs())
    with pytest.raises(SchemaError, match="'x' lacks 'long_name'"):
        write_netcdf(ds, tmp_path / "bad.nc")
    assert not list(tmp_path.iterdir()), "a failed write must leave nothing behind"
    ds = xr.Dataset({"x": ("particle", np.zeros(3), {"units": "d_ave", "long_name": "x"})})
    with pytest.raises(SchemaError, match="global attribute 'seed' missing"):
        validate_dataset(ds)
