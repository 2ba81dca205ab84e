"""The snapshot contract (`forcenet.datasets.schema`, checked by `forcenet.datasets.io` on writing and reading):
engine snapshots, imported snapshots and snapshots written before the contract pass the same check; NaN or
infinite positions, radii or forces, impossible indices and a snapshot of another run are refused with one line
naming the file and the variable or attribute (issue 26 item 1, issue 27's snapshot items)."""
from __future__ import annotations

import json

import numpy as np
import pytest

from conftest import load_config
from forcenet import pipeline
from forcenet.datasets import DatasetError, open_dataset, read_dataset, read_snapshot, write_snapshot
from forcenet.datasets.runs import run_expectation
from forcenet.datasets.schema import SNAPSHOT_DYNAMICS
from forcenet.datasets.snapshot import snapshot_dataset
from forcenet.systems import system_from_config
from test_datasets import attrs, two_triangles_snapshot

CONFIG = load_config("smoke.yaml")


def run_attrs(system="2d_hertz", config=CONFIG):
    return {**pipeline.run_attrs(config, system, 0, title=f"test snapshot {system}")}


def write(path, system="2d_hertz", config=CONFIG, **changes):
    arrays = {**two_triangles_snapshot(), **changes}
    return write_snapshot(path, attrs=run_attrs(system, config), **arrays)


def test_an_engine_snapshot_without_the_new_attributes_still_reads(tmp_path):
    """A snapshot as the engine wrote it before the contract (no source_format) passes unchanged; the engine now
    records source_format forcenet-dem."""
    assert run_attrs()["source_format"] == "forcenet-dem"
    old = {key: value for key, value in run_attrs().items() if key != "source_format"}
    path = write_snapshot(tmp_path / "rho0.800.nc", attrs=old, **two_triangles_snapshot())
    ds = read_snapshot(path, expect=run_expectation(system_from_config("2d_hertz", CONFIG), CONFIG))
    assert "source_format" not in ds.attrs and int(ds.attrs["dimension"]) == 2


def test_the_dynamics_are_optional_the_contract_variables_are_not(tmp_path):
    arrays = {k: v for k, v in two_triangles_snapshot().items() if k not in SNAPSHOT_DYNAMICS}
    imported = {**attrs(), "source_format": "contact-table", "source_files": json.dumps(["p.csv", "c.csv"]),
                "source_sha256": json.dumps(["0" * 64, "1" * 64]), "source_timestep": 0}
    path = write_snapshot(tmp_path / "imported.nc", attrs=imported, **arrays)
    ds = read_snapshot(path)
    assert "velocity" not in ds and ds.attrs["source_format"] == "contact-table"
    del arrays["radius"]
    with pytest.raises(Exception, match="missing variables: \\['radius'\\]"):
        snapshot_dataset(attrs=imported, **arrays)


def test_an_imported_snapshot_must_record_its_source(tmp_path):
    arrays = {k: v for k, v in two_triangles_snapshot().items() if k not in SNAPSHOT_DYNAMICS}
    with pytest.raises(DatasetError, match="global attribute 'source_sha256' missing \\(imported snapshot"):
        write_snapshot(tmp_path / "x.nc", attrs={**attrs(), "source_format": "lammps-dump", "source_files": "[]",
                                                  "source_timestep": 3}, **arrays)
    assert not (tmp_path / "x.nc").exists()


def nan_at(name, index):
    values = np.array(two_triangles_snapshot()[name], dtype=float)
    values[index] = np.nan if name != "radius" else np.inf
    return values


@pytest.mark.parametrize("name, index, where", [
    ("position", (2, 1), "particle 2, spatial 1"),
    ("radius", 3, "particle 3"),
    ("force_normal", (4, 0), "contact 4, spatial 0"),
    ("force_tangential", (1, 1), "contact 1, spatial 1"),
    ("wall_contact_force", (0, 0), "wall_contact 0, spatial 0"),
])
def test_nan_or_infinite_values_are_refused_on_writing_and_on_reading(tmp_path, name, index, where):
    expected = f"variable '{name}' has a NaN or infinite value at {where}"
    with pytest.raises(DatasetError, match=expected) as caught:
        write(tmp_path / "w.nc", **{name: nan_at(name, index)})
    assert str(caught.value).startswith(f"{tmp_path / 'w.nc'}: ") and "\n" not in str(caught.value)
    assert not (tmp_path / "w.nc").exists()
    # a file with the NaN written by another tool: refused on reading, naming the file and the variable
    good = write(tmp_path / "good.nc")
    ds = open_dataset(good)
    ds[name].values[index] = np.nan
    ds.to_netcdf(tmp_path / "bad.nc")
    with pytest.raises(DatasetError, match=f"^{tmp_path / 'bad.nc'}: not a valid snapshot file: {expected}$"):
        read_snapshot(tmp_path / "bad.nc")
    read_snapshot(good)  # the good one passes


@pytest.mark.parametrize("changes, expected", [
    ({"radius": [0.5, 0.5, -0.5, 0.5]}, "variable 'radius' is not positive at particle 2"),
    ({"contact_j": [1, 2, 2, 3, 4]}, "variable 'contact_j' names particle 4 at contact 4, but there are 4 particles"),
    ({"contact_i": [0, 0, 1, 3, 2]}, "particle 3 in contact with itself at contact 3"),
    ({"wall_contact_wall": [4]}, "variable 'wall_contact_wall' has a wall id outside 0 … 3"),
    ({"box_hi": [3.0, 0.0]}, "box_hi must exceed box_lo"),
])
def test_impossible_values_are_refused(tmp_path, changes, expected):
    with pytest.raises(DatasetError, match=expected):
        write(tmp_path / "w.nc", **changes)


def test_an_analysis_file_with_a_nan_force_is_refused(tmp_path):
    snap = write(tmp_path / "rho0.800.nc")
    analysis = tmp_path / "a.nc"
    pipeline.analyze_run(snapshots=[str(snap)], outputs=[str(analysis)],
                         analysis=pipeline.snapshot_analysis_params(CONFIG, "2d_hertz"))
    read_dataset(analysis, "analysis")  # essential classes at death −inf pass
    for name in ("mean_force", "birth", "death"):
        ds = open_dataset(analysis)
        ds[name].values[0] = np.nan
        bad = tmp_path / f"bad_{name}.nc"
        ds.to_netcdf(bad)
        with pytest.raises(DatasetError, match=f"^{bad}: .*variable '{name}' has a NaN or infinite value"):
            read_dataset(bad, "analysis")


def test_a_snapshot_of_another_run_is_refused_naming_the_attribute(tmp_path):
    """A 2d_linear snapshot copied over a 2d_hertz one, a 3D one under a 2D system, one made under other settings."""
    expect = run_expectation(system_from_config("2d_hertz", CONFIG), CONFIG)
    linear = write(tmp_path / "linear.nc", system="2d_linear")
    with pytest.raises(DatasetError, match=f"^{linear}: not of this run: global attribute 'system' is '2d_linear', "
                                           "but this run is '2d_hertz'$"):
        read_snapshot(linear, expect=expect)
    other = {**CONFIG, "systems": {**CONFIG["systems"],
                                   "2d_hertz": {**CONFIG["systems"]["2d_hertz"], "friction": 0.3}}}
    changed = write(tmp_path / "changed.nc", config=other)
    with pytest.raises(DatasetError, match="global attribute 'config' records other settings for system '2d_hertz'"):
        read_snapshot(changed, expect=expect)
    # an analysis key or another system changed: the snapshot still belongs to the run
    edited = {**CONFIG, "analysis": {**CONFIG["analysis"], "essential_convention": "zero"},
              "systems": {**CONFIG["systems"], "2d_linear": {**CONFIG["systems"]["2d_linear"], "friction": 0.1}}}
    read_snapshot(write(tmp_path / "same.nc", config=edited), expect=expect)
    ds = open_dataset(write(tmp_path / "ok.nc"))
    ds.attrs["dimension"] = 3
    ds.to_netcdf(tmp_path / "dim.nc")
    with pytest.raises(DatasetError, match="global attribute 'dimension' is 3, but the positions have 2 components"):
        read_snapshot(tmp_path / "dim.nc", expect=expect)
    with pytest.raises(DatasetError, match="global attribute 'dimension' is 2, but system '2d_hertz' has dimension 3"):
        read_snapshot(tmp_path / "ok.nc", expect={**expect, "dimension": 3})


def test_a_snapshot_of_another_realization_or_state_copied_in_place_is_refused(tmp_path):
    """The file's folder names its realization and its name the grid ρ (`state_expectation`): realization 0's
    state at ρ = 0.80 copied to r01/rho0.800.nc or to r00/rho0.840.nc is refused, in its own place it is read."""
    from forcenet.datasets.runs import state_expectation

    expect = run_expectation(system_from_config("2d_hertz", CONFIG), CONFIG)
    grid = system_from_config("2d_hertz", CONFIG).rho_grid
    assert expect["rho_tolerance"] == pytest.approx(0.5 * min(b - a for a, b in zip(grid, grid[1:])))
    (tmp_path / "r00").mkdir()
    (tmp_path / "r01").mkdir()
    own = write(tmp_path / "r00" / "rho0.800.nc")
    read_snapshot(own, expect=state_expectation(expect, own))
    other_run = write(tmp_path / "r01" / "rho0.800.nc")
    with pytest.raises(DatasetError, match=f"^{other_run}: not of this run: global attribute 'realization' is 0, but "
                                           "this file is of realization 1: the snapshot belongs to another run$"):
        read_snapshot(other_run, expect=state_expectation(expect, other_run))
    other_state = write(tmp_path / "r00" / "rho0.840.nc")
    with pytest.raises(DatasetError, match=f"^{other_state}: not of this run: its packing fraction is 0.8000, but "
                                           "this file is the state at rho = 0.840: the snapshot is another state"):
        read_snapshot(other_state, expect=state_expectation(expect, other_state))
    assert state_expectation(expect, tmp_path / "elsewhere.nc") == expect  # a path named otherwise: the run only


def test_the_analysis_job_refuses_a_snapshot_of_another_run_and_writes_nothing(tmp_path):
    hertz, linear = write(tmp_path / "rho0.800.nc"), write(tmp_path / "rho0.840.nc", system="2d_linear")
    out = tmp_path / "out"
    with pytest.raises(SystemExit):
        pipeline.analyze_run(snapshots=[str(hertz), str(linear)], outputs=[str(out / "a.nc"), str(out / "b.nc")],
                             analysis=pipeline.snapshot_analysis_params(CONFIG, "2d_hertz"),
                             log_path=str(tmp_path / "log"), expect=run_expectation(system_from_config("2d_hertz", CONFIG), CONFIG))
    errors = [line for line in (tmp_path / "log").read_text().splitlines() if " ERROR " in line]
    assert len(errors) == 1 and f"{linear}: not of this run: global attribute 'system'" in errors[0]
    assert not out.exists()


def test_stacking_refuses_an_analysis_of_another_run(tmp_path):
    """An analysis file copied from 2d_linear into 2d_hertz's set is refused by the aggregation, naming it."""
    analyses = []
    for system in ("2d_hertz", "2d_linear"):
        snap = write(tmp_path / f"{system}.nc", system=system)
        analyses.append(str(tmp_path / f"a_{system}.nc"))
        pipeline.analyze_run(snapshots=[str(snap)], outputs=[analyses[-1]],
                             analysis=pipeline.snapshot_analysis_params(CONFIG, "2d_hertz"))
    out = tmp_path / "out"
    job = dict(realizations=[0, 0], rhos=[0.80, 0.84], measures_path=str(out / "m.nc"), diagrams_path=str(out / "d.nc"),
               config=CONFIG, system="2d_hertz", log_path=str(tmp_path / "log"))
    with pytest.raises(SystemExit):
        pipeline.aggregate(analyses=analyses, **job)
    errors = [line for line in (tmp_path / "log").read_text().splitlines() if " ERROR " in line]
    assert len(errors) == 1 and f"{analyses[1]}: not of this run: global attribute 'system' is '2d_linear'" in errors[0]
    assert not out.exists()
    pipeline.aggregate(analyses=[analyses[0]], **{**job, "realizations": [0], "rhos": [0.80]})  # its own: stacked
    assert (out / "m.nc").exists()


def test_branch_vectors_take_the_nearest_image_on_periodic_axes_only():
    from forcenet.boxes import box_periods, branch_vectors, image_shifts

    position = np.array([[0.2, 0.5], [9.4, 3.5], [5.0, 2.0]])
    i, j = np.array([0, 0, 2]), np.array([1, 2, 1])
    bounded = branch_vectors(position, i, j)
    np.testing.assert_array_equal(bounded, position[i] - position[j])  # bit for bit: our engine's snapshots
    period = box_periods("x", [0, 0], [10, 4])
    np.testing.assert_array_equal(period, [[10.0, 0.0], [0.0, 0.0]])  # edge vectors: a's along x, none along y
    # 0 → 1: x through the face (0.2 − (9.4 − 10) = 0.8), y not periodic (0.5 − 3.5 = −3); 0 → 2 and 2 → 1 inside
    np.testing.assert_allclose(branch_vectors(position, i, j, period), [[0.8, -3.0], [-4.8, -1.5], [-4.4, -1.5]])
    np.testing.assert_allclose(image_shifts(position, i, j, period), [[-10.0, 0.0], [0.0, 0.0], [0.0, 0.0]])
    both = box_periods("xy", [0, 0], [10, 4])
    np.testing.assert_allclose(branch_vectors(position, i, j, both)[0], [0.8, 1.0])  # 0.5 − (3.5 − 4)
    assert image_shifts(position, i[:0], j[:0], both).shape == (0, 2)
