"""The netCDF data model: round trips, units and long names everywhere, provenance, atomic writes."""
from __future__ import annotations

import numpy as np
import pytest
import xarray as xr

from forcenet import pipeline
from forcenet.datasets import (SchemaError, diagram_points, open_dataset, provenance_attrs, read_dataset,
                               read_snapshot, validate_dataset, write_netcdf, write_snapshot)
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
    analyses, written = [], []
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
        written.append(measures)
    first = analyses[0]
    # two triangles sharing an edge: one component at F_th = 0, no loop (3-particle loops never count)
    assert int(first.betti.sel(force_kind="total", homology_dim=0, threshold=0.0)) == 1
    assert int(first.betti.sel(force_kind="total", homology_dim=1).max()) == 0
    total = diagram_points(first, "total")
    assert int(total.essential.sum()) == 1 and np.isneginf(total.death[total.essential]).all()
    for kind, measures in written[0].items():  # the reader gives back what the analysis wrote, point for point
        stored, computed = diagram_points(first, kind), measures.diagrams
        np.testing.assert_array_equal(stored.homology_dim, computed.homology_dim)
        np.testing.assert_array_equal(stored.birth, computed.birth)
        np.testing.assert_array_equal(stored.death, computed.death)
        np.testing.assert_array_equal(stored.essential, computed.essential)
    stacked = stack_network_measures(analyses, [0, 0], [0.80, 0.82], attrs())
    assert stacked.betti.dims == ("realization", "rho", "force_kind", "homology_dim", "threshold")
    validate_dataset(stacked)
    points = stack_diagrams(analyses, [0, 0], [0.80, 0.82], attrs())
    assert points.sizes["point"] == sum(a.sizes["point"] for a in analyses)
    validate_dataset(points)
    for analysis, rho in zip(analyses, (0.80, 0.82)):  # each snapshot's points, selected from the stacked file
        for kind in ("total", "normal", "tangential"):
            selected = diagram_points(points, kind, realization=0, rho=rho)
            for stored, alone in zip(selected, diagram_points(analysis, kind)):
                np.testing.assert_array_equal(stored, alone)


def tetrahedron_snapshot(rho=0.6):
    """Four unit spheres at the corners of a regular tetrahedron of edge 1: all six pairs touch, normal forces
    1..6 (distinct) along the centre line, small tangential forces; sphere 0 touches the x_lo wall."""
    position = np.array([[1.0, 1.0, 1.0], [2.0, 1.0, 1.0], [1.5, 1.0 + np.sqrt(3) / 2, 1.0],
                         [1.5, 1.0 + np.sqrt(3) / 6, 1.0 + np.sqrt(2 / 3)]])
    contact_i, contact_j = np.array([0, 0, 0, 1, 1, 2]), np.array([1, 2, 3, 2, 3, 3])
    direction = position[contact_j] - position[contact_i]
    force_normal = np.array([3.0, 1.0, 6.0, 2.0, 5.0, 4.0])[:, None] * direction
    force_tangential = np.cross(direction, [0.0, 0.0, 1.0]) * 0.01 + [0.0, 0.0, 0.005]
    return dict(position=position, radius=np.full(4, 0.5), velocity=np.zeros((4, 3)),
                angular_velocity=np.zeros((4, 3)), contact_i=contact_i, contact_j=contact_j,
                force_normal=force_normal, force_tangential=force_tangential, wall_contact_particle=[0],
                wall_contact_wall=[0], wall_contact_force=[[0.1, 0.0, 0.0]], box_lo=[0.0, 0.0, 0.0],
                box_hi=[3.0, 3.0, 3.0], rho=rho, Z=3.0, kinetic_energy=1e-9, pressure=0.01, time=12.5, step=625,
                relaxation_steps=100)


def test_analysis_config_fill_tetrahedra_reaches_the_3d_diagrams_and_is_recorded(tmp_path, default_config):
    """analysis.fill_tetrahedra through the pipeline: four mutually touching spheres enclose no void when the
    tetrahedron is filled, one never-dying void born at the weakest contact when it is not; each analysis file
    names its complex, and stacking refuses to mix the two."""
    snapshot = write_snapshot(tmp_path / "sim.nc", attrs=pipeline.run_attrs(default_config, "3d_hertz", 0, "test"),
                              **tetrahedron_snapshot())
    analyses = {}
    for fill in (True, False):
        analysis = {**default_config["analysis"], "fill_tetrahedra": fill}
        analyses[fill] = tmp_path / f"analysis_{fill}.nc"
        pipeline.analyze_run(snapshots=[str(snapshot)], outputs=[str(analyses[fill])], analysis=analysis)
    filled, hollow = (read_dataset(analyses[fill], "analysis") for fill in (True, False))
    assert filled.attrs["flag_complex"] == "tetrahedra" and hollow.attrs["flag_complex"] == "triangles"
    assert "4-clique" in hollow.attrs["flag_complex_description"]
    arrays = tetrahedron_snapshot()
    magnitudes = {"normal": np.linalg.norm(arrays["force_normal"], axis=1),
                  "total": np.linalg.norm(arrays["force_normal"] + arrays["force_tangential"], axis=1)}
    for kind, magnitude in magnitudes.items():
        betti = {fill: ds.betti.sel(force_kind=kind) for fill, ds in ((True, filled), (False, hollow))}
        assert int(betti[True].sel(homology_dim=2).max()) == 0 and int(betti[False].sel(homology_dim=2)[0]) == 1
        assert int(betti[True].sel(homology_dim=1).max()) == 0 == int(betti[False].sel(homology_dim=1).max())
        assert int(filled.essential_count.sel(force_kind=kind, homology_dim=2)) == 0
        assert int(hollow.essential_count.sel(force_kind=kind, homology_dim=2)) == 1
        assert diagram_points(filled, kind, 2).birth.size == 0
        void = diagram_points(hollow, kind, 2)
        # born when the last triangle enters, at the weakest contact (in units of the network's mean force)
        assert void.birth.size == 1 and bool(void.essential[0])
        assert float(void.birth[0]) == pytest.approx(magnitude.min() / magnitude.mean(), rel=1e-12)
    xr.testing.assert_equal(filled.betti.sel(homology_dim=[0, 1]), hollow.betti.sel(homology_dim=[0, 1]))
    with pytest.raises(ValueError, match="flag complexes"):
        pipeline.aggregate(analyses=[str(analyses[True]), str(analyses[False])], realizations=[0, 0],
                           rhos=[0.6, 0.6], measures_path=str(tmp_path / "m.nc"), diagrams_path=str(tmp_path / "d.nc"),
                           config=default_config, system="3d_hertz")
    assert not (tmp_path / "m.nc").exists() and not (tmp_path / "d.nc").exists()
    pipeline.aggregate(analyses=[str(analyses[False])], realizations=[0], rhos=[0.6],
                       measures_path=str(tmp_path / "m.nc"), diagrams_path=str(tmp_path / "d.nc"),
                       config=default_config, system="3d_hertz")
    for name in ("m.nc", "d.nc"):
        assert open_dataset(tmp_path / name).attrs["flag_complex"] == "triangles"


def test_validation_names_what_is_missing(tmp_path):
    ds = xr.Dataset({"x": ("particle", np.zeros(3), {"units": "d_ave"})}, attrs=attrs())
    with pytest.raises(SchemaError, match="'x' lacks 'long_name'"):
        write_netcdf(ds, tmp_path / "bad.nc")
    assert not list(tmp_path.iterdir()), "a failed write must leave nothing behind"
    ds = xr.Dataset({"x": ("particle", np.zeros(3), {"units": "d_ave", "long_name": "x"})})
    with pytest.raises(SchemaError, match="global attribute 'seed' missing"):
        validate_dataset(ds)


def points_analysis(rho: float, points: list[tuple[str, int, float, float]]) -> xr.Dataset:
    """An analysis-like dataset holding only diagram points: (force kind, k, birth, death) each, death −inf for a
    never-dying class (its `essential` flag follows)."""
    kinds = ["total", "normal", "tangential"]
    kind, dim, birth, death = (list(column) for column in zip(*points)) if points else ([], [], [], [])
    spec = {"units": "1", "long_name": "test"}
    return xr.Dataset({
        "diagram_force_kind": ("point", np.array([kinds.index(k) for k in kind], dtype=np.int8), spec),
        "diagram_homology_dim": ("point", np.array(dim, dtype=np.int8), spec),
        "birth": ("point", np.array(birth, dtype=float), spec),
        "death": ("point", np.array(death, dtype=float), spec),
        "essential": ("point", np.isneginf(np.array(death, dtype=float)).astype(np.int8), spec),
        "rho": ((), rho, spec),
    }, coords={"force_kind": ("force_kind", kinds, spec), "homology_dim": ("homology_dim", [0, 1], spec)},
        attrs=attrs())


def test_diagram_points_selects_one_kind_dimension_and_snapshot(tmp_path):
    a = points_analysis(0.80, [("total", 0, 2.0, -np.inf), ("normal", 0, 3.0, -np.inf), ("normal", 0, 1.5, 0.5),
                               ("normal", 1, 1.2, 0.9), ("tangential", 0, 0.7, 0.1)])
    b = points_analysis(0.82, [("normal", 0, 2.5, -np.inf), ("normal", 1, 1.1, 0.4)])
    c = points_analysis(0.80, [("normal", 1, 4.0, 3.0)])
    normal = diagram_points(a, "normal")
    np.testing.assert_array_equal(normal.homology_dim, [0, 0, 1])
    np.testing.assert_array_equal(normal.birth, [3.0, 1.5, 1.2])
    np.testing.assert_array_equal(normal.death, [-np.inf, 0.5, 0.9])
    np.testing.assert_array_equal(normal.essential, [True, False, False])
    assert normal.birth.dtype == np.float64 and normal.homology_dim.dtype == np.int64
    np.testing.assert_array_equal(diagram_points(a, "normal", 1).birth, [1.2])
    assert diagram_points(a, "total", 1).birth.size == 0 and diagram_points(a, "tangential", 0).death.tolist() == [0.1]
    # a stacked file: realization 0 at ρ 0.80 (a) and 0.82 (b), realization 1 at 0.80 (c); read back validated
    stacked_attrs = {**attrs(), "dimension": 2, "force_law": "linear", "rattler_rule": "once", "flag_complex": "triangles"}
    path = write_netcdf(stack_diagrams([a, b, c], [0, 0, 1], [0.80, 0.82, 0.80], stacked_attrs),
                        tmp_path / "diagrams.nc", kind="diagrams")
    stacked = read_dataset(path, "diagrams")
    np.testing.assert_array_equal(diagram_points(stacked, "normal", realization=0, rho=0.82).birth, [2.5, 1.1])
    np.testing.assert_array_equal(diagram_points(stacked, "normal", 1, realization=0, rho=0.80).birth, [1.2])
    np.testing.assert_array_equal(diagram_points(stacked, "normal", 1, realization=1, rho=0.80).birth, [4.0])
    assert diagram_points(stacked, "normal", realization=1, rho=0.82).birth.size == 0  # no such snapshot point
    assert diagram_points(stacked, "total", realization=0, rho=0.80).essential.tolist() == [True]


def test_diagram_points_treats_a_flagged_or_infinite_death_as_never_dying():
    ds = points_analysis(0.80, [("total", 0, 2.0, -1.0), ("total", 0, 1.0, 0.5), ("total", 0, 3.0, -np.inf)])
    ds["essential"].values[:] = [1, 0, 0]  # a file giving a never-dying class P2's death −1, flagged essential
    points = diagram_points(ds, "total")
    np.testing.assert_array_equal(points.essential, [True, False, True])
    np.testing.assert_array_equal(points.death, [-np.inf, 0.5, -np.inf])


@pytest.mark.parametrize("call, message", [
    (lambda a, s: diagram_points(a, "shear"), "force kind 'shear' not in this file"),
    (lambda a, s: diagram_points(a, "total", 2), "homology dimension 2 not in this file"),
    (lambda a, s: diagram_points(a, "total", realization=0, rho=0.8), "an analysis file holds one snapshot"),
    (lambda a, s: diagram_points(s, "total", rho=0.8), "give both realization and rho"),
    (lambda a, s: diagram_points(s, "total", realization=0), "give both realization and rho"),
    (lambda a, s: diagram_points(s, "total", realization=5, rho=0.8),
     r"realization 5 not in this file; it holds \[0\]"),
])
def test_diagram_points_names_a_selection_the_file_cannot_answer(call, message):
    analysis = points_analysis(0.80, [("total", 0, 2.0, -np.inf), ("total", 1, 1.2, 0.9)])
    stacked = stack_diagrams([analysis], [0], [0.80], attrs())
    with pytest.raises(ValueError, match=message):
        call(analysis, stacked)


def test_an_optional_global_attribute_reads_as_its_declared_meaning_and_no_other_has_a_default():
    """Issue 55: the attributes a file may lack are declared with what their absence means
    (`schema.OPTIONAL_GLOBAL_ATTRS`) and read by `optional_attr`; a kind's required attribute has no default there."""
    from forcenet.datasets import optional_attr
    from forcenet.datasets.schema import KIND_GLOBAL_ATTRS, OPTIONAL_GLOBAL_ATTRS, REQUIRED_GLOBAL_ATTRS

    required = {*REQUIRED_GLOBAL_ATTRS, *(name for names in KIND_GLOBAL_ATTRS.values() for name in names)}
    assert not required & set(OPTIONAL_GLOBAL_ATTRS)
    compression = xr.Dataset()
    assert optional_attr(compression, "state_coordinate") == "rho"
    assert optional_attr(compression, "periodic_axes") == "" and optional_attr(compression, "box_tilt") is None
    assert optional_attr(xr.Dataset(attrs={"state_coordinate": "strain"}), "state_coordinate") == "strain"
    for name in required:
        with pytest.raises(KeyError, match=f"'{name}' is not optional"):
            optional_attr(compression, name)
