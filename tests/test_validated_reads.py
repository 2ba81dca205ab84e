"""Every file the pipeline reads is checked against the schema of its kind when it is read (snapshot, analysis,
network_measures, diagrams, distances): a broken file stops the job with one line naming the file and what is
wrong, and the job writes nothing. Also: outputs honour the umask; distances.nc and diagrams.nc select on the grid ρ.
"""
from __future__ import annotations

import os
import stat
from pathlib import Path

import numpy as np
import pytest
import xarray as xr

from conftest import load_config
from forcenet import pipeline, pipeline_figures, pipeline_p2
from forcenet.datasets import (DatasetError, open_dataset, provenance_attrs, read_dataset, write_netcdf,
                               write_snapshot)
from forcenet.datasets.aggregate import distances_on_grid
from forcenet.datasets.runs import simulation_sha256
from forcenet.report import p2_distances
from test_datasets import attrs, two_triangles_snapshot
from test_report_p2 import worked_example_analyses

CONFIG = load_config()


def snapshots(directory: Path, rhos=(0.80, 0.84, 0.88)) -> list[Path]:
    """Snapshots of realization 0 of CONFIG's 2d_linear (the run they are aggregated for)."""
    run = pipeline.run_attrs(CONFIG, "2d_linear", 0, title="test snapshot")
    return [write_snapshot(directory / f"rho{rho:.3f}.nc", attrs=run, **two_triangles_snapshot(rho)) for rho in rhos]


@pytest.fixture(scope="module")
def good(tmp_path_factory) -> dict[str, list[Path]]:
    """Valid files of every kind, made by the pipeline's own functions from a hand-made snapshot."""
    root = tmp_path_factory.mktemp("good")
    snaps = snapshots(root / "sim")
    analyses = [root / "analysis" / path.name for path in snaps]
    pipeline.analyze_run(snapshots=[str(p) for p in snaps], outputs=[str(p) for p in analyses],
                         analysis=CONFIG["analysis"], log_path=str(root / "analyze.log"))
    measures, diagrams = root / "network_measures.nc", root / "diagrams.nc"
    pipeline.aggregate(analyses=[str(p) for p in analyses], realizations=[0, 0, 0], rhos=[0.80, 0.84, 0.88],
                       measures_path=str(measures), diagrams_path=str(diagrams), config=CONFIG, system="2d_linear",
                       log_path=str(root / "aggregate.log"))
    per_realization = [p2_distances.consecutive_distances(worked_example_analyses(rhos=(0.70, 0.71 + 1e-4 * r, 0.72)))
                       for r in range(2)]
    stacked = p2_distances.stack_distances(per_realization, [0, 1], {**provenance_attrs(
        system="2d_poly_mu05", realization=-1, seed=1, config={}, title="P2 distances"),
        "dimension": 2, "force_law": "linear", "rattler_rule": "none", "flag_complex": "triangles"})
    distances = write_netcdf(distances_on_grid(stacked, [0.71, 0.72]), root / "distances.nc", kind="distances")
    opened = [read_dataset(path, "analysis") for path in analyses]
    summary_attrs = {**pipeline.run_attrs(CONFIG, "2d_linear", 0, title="P2 run summary"), "dimension": 2,
                     "simulation_sha256": simulation_sha256(CONFIG, "2d_linear"),
                     **pipeline.common_analysis_attrs(opened)}
    run = write_netcdf(p2_distances.run_summary(opened, ["minus_one"], [0.80, 0.84, 0.88], summary_attrs),
                       root / "p2_runs" / "r00.nc", kind="p2_run")
    return {"snapshot": snaps, "analysis": analyses, "network_measures": [measures], "diagrams": [diagrams],
            "distances": [distances], "p2_run": [run]}


def broken_copy(source: Path, target: Path, how: str, name: str | None = None) -> Path:
    """A copy of `source` with one thing wrong: a variable dropped, turned into float, given other dims, a global
    attribute dropped ("attr"), or the file truncated to half its bytes. Written with xarray directly (the pipeline's
    writer would refuse it)."""
    target.parent.mkdir(parents=True, exist_ok=True)
    if how == "truncated":
        data = source.read_bytes()
        target.write_bytes(data[:len(data) // 2])
        return target
    ds = open_dataset(source)
    if how == "missing":
        ds = ds.drop_vars(name)
    elif how == "float":
        ds[name] = ds[name].astype(float)
    elif how == "dims":
        ds[name] = ds[name].rename({ds[name].dims[0]: "elsewhere"})
    elif how == "attr":
        del ds.attrs[name]
    ds.to_netcdf(target)
    return target


def run_job(job, log: Path) -> str:
    """Run a pipeline job that must fail on its input: exit status 1 and the log's one ERROR line (no traceback)."""
    with pytest.raises(SystemExit) as stop:
        job()
    assert stop.value.code == 1
    text = log.read_text()
    assert "Traceback" not in text
    errors = [line for line in text.splitlines() if " ERROR " in line]
    assert len(errors) == 1, text
    return errors[0]


CASES = {
    # kind: (how it is broken, variable, what the message must say)
    "snapshot-missing": ("snapshot", "missing", "force_tangential", "variable 'force_tangential' missing"),
    "snapshot-radius": ("snapshot", "missing", "radius", "variable 'radius' missing"),
    "snapshot-truncated": ("snapshot", "truncated", None, "cannot be read as netCDF"),
    "analysis-missing": ("analysis", "missing", "betti", "variable 'betti' missing"),
    "analysis-float": ("analysis", "float", "betti", "variable 'betti' is float64, expected int"),
    "network_measures-dims": ("network_measures", "dims", "Z", "variable 'Z' has dims ('elsewhere', 'rho')"),
    "diagrams-missing": ("diagrams", "missing", "death", "variable 'death' missing"),
    "distances-missing": ("distances", "missing", "distance", "variable 'distance' missing"),
    "distances-truncated": ("distances", "truncated", None, "cannot be read as netCDF"),
}


def reading_job(kind: str, inputs: list[str], good, out: Path, log: Path, tmp_path: Path):
    """The pipeline job that reads `inputs`, files of `kind` (writing under `out`, logging to `log`)."""
    if kind == "snapshot":  # the good first snapshot must not be analysed either
        outputs = [str(out / Path(p).name) for p in inputs]
        return lambda: pipeline.analyze_run(snapshots=inputs, outputs=outputs, analysis=CONFIG["analysis"],
                                            log_path=str(log))
    if kind == "analysis":
        return lambda: pipeline.aggregate(analyses=inputs, realizations=[0, 0, 0], rhos=[0.80, 0.84, 0.88],
                                          measures_path=str(out / "m.nc"), diagrams_path=str(out / "d.nc"),
                                          config=CONFIG, system="2d_linear", log_path=str(log))
    if kind == "network_measures":
        return lambda: pipeline.p1_validation_table(measures=inputs, systems=["2d_linear"], force_unit="dyn",
                                                    csv=str(out / "t.csv"), md=str(out / "t.md"), log_path=str(log))
    if kind == "diagrams":
        return lambda: pipeline_figures.figure(name="p1_fig10_persistence_diagram", systems=["2d_linear"],
                                       inputs={"measures": [str(p) for p in good["network_measures"]],
                                               "diagrams": inputs},
                                       pdf=str(out / "f.pdf"), png=str(out / "f.png"), csv=str(out / "f.csv"),
                                       log_path=str(log))
    if kind == "distances":
        return lambda: pipeline_p2.p2_validation_table(distances=inputs, tables=[], frictional="2d_poly_mu05",
                                                    frictionless=None, md=str(out / "v.md"), csv=str(out / "v.csv"),
                                                    states=str(tmp_path / "states.csv"), log_path=str(log))
    return lambda: pipeline_p2.p2_distances(runs=inputs, realizations=[0], output=str(out / "d.nc"),  # p2_run
                                            essential_convention="minus_one", config=CONFIG, system="2d_linear",
                                            log_path=str(log))


@pytest.mark.parametrize("case", sorted(CASES))
def test_a_broken_input_stops_the_job_with_one_line_and_writes_nothing(good, tmp_path, case):
    kind, how, name, expected = CASES[case]
    out, log = tmp_path / "out", tmp_path / "job.log"
    files = [Path(p) for p in good[kind]]
    broken = broken_copy(files[1 if len(files) > 1 else 0], tmp_path / "in" / files[-1].name, how, name)
    inputs = [str(broken if i == (1 if len(files) > 1 else 0) else p) for i, p in enumerate(files)]
    line = run_job(reading_job(kind, inputs, good, out, log, tmp_path), log)
    assert f"{broken}: " in line and expected in line, line
    assert not out.exists() or not any(out.iterdir()), "a failed job must write nothing"


#: kind: a global attribute of its contract (`forcenet.datasets.schema.KIND_GLOBAL_ATTRS`) that its readers index
#: (the analysis, the network movie and P2 Tables I-III a snapshot's realization; aggregate and P2 distances the
#: rattler rule and flag complex every analysis or run summary shares; P1's F_max rule the force constants; P2's
#: validation table the never-dying convention)
INDEXED_ATTRIBUTES = {"snapshot": "realization", "analysis": "rattler_rule", "network_measures": "force_unit_dyn",
                      "distances": "essential_convention", "p2_run": "flag_complex"}


@pytest.mark.parametrize("kind", sorted(INDEXED_ATTRIBUTES))
def test_a_file_without_a_global_attribute_its_reader_indexes_is_refused_naming_it(good, tmp_path, kind):
    """The readers index their kind's global attributes (issue 55: no `.attrs.get` with a default): a file without
    one stops the job that reads it at its validated read, with one line naming the file and the attribute."""
    name = INDEXED_ATTRIBUTES[kind]
    out, log = tmp_path / "out", tmp_path / "job.log"
    files = [Path(p) for p in good[kind]]
    broken = broken_copy(files[0], tmp_path / "in" / files[0].name, "attr", name)
    line = run_job(reading_job(kind, [str(broken), *map(str, files[1:])], good, out, log, tmp_path), log)
    assert f"{broken}: not a valid {kind} file: global attribute '{name}' missing" in line, line
    assert not out.exists() or not any(out.iterdir()), "a failed job must write nothing"


@pytest.mark.parametrize("kind", ["snapshot", "analysis", "network_measures", "diagrams", "distances", "p2_run"])
def test_files_written_by_the_pipeline_pass_their_read_check(good, kind):
    for path in good[kind]:
        read_dataset(path, kind)
    with pytest.raises(DatasetError, match=f"not a valid {kind} file"):
        other = "snapshot" if kind != "snapshot" else "analysis"
        read_dataset(good[other][0], kind)


# --- item 7: coordinates a user can select on ------------------------------------------------------------------
def test_distances_select_on_the_grid_rho_and_keep_the_measured_one(good):
    ds = read_dataset(good["distances"][0], "distances")
    assert float(ds["distance"].sel(rho=0.71, realization=1, force_kind="normal", homology_dim=0,
                                    metric="bottleneck")) == pytest.approx(2.0)  # P2 §III D worked example
    np.testing.assert_allclose(ds["rho_measured"].sel(realization=1), [0.7101, 0.72])
    assert "grid" in ds["rho"].attrs["long_name"] and "grid" in ds.attrs["rho_convention"]
    with pytest.raises(ValueError, match="do not belong to this grid"):
        distances_on_grid(ds, [0.75, 0.80])


def test_diagrams_hold_the_force_kind_their_points_index_into(good):
    ds = read_dataset(good["diagrams"][0], "diagrams")
    assert list(ds["force_kind"].values) == ["total", "normal", "tangential"]
    assert set(np.unique(ds["diagram_force_kind"].values)) <= set(range(ds.sizes["force_kind"]))
    assert ds["diagram_force_kind"].attrs["flag_meanings"] == "total normal tangential"
    normal = ds.isel(point=ds["force_kind"].values[ds["diagram_force_kind"].values] == "normal")
    assert normal.sizes["point"] > 0 and set(np.unique(normal["point_rho"].values)) == {0.80, 0.84, 0.88}
    measures = read_dataset(good["network_measures"][0], "network_measures")
    assert int(measures["n_particles"].sel(rho=0.84, realization=0)) == 4
    np.testing.assert_allclose(measures["rho_measured"].values, [[0.80, 0.84, 0.88]])


# --- item 4: permissions ----------------------------------------------------------------------------------------
@pytest.mark.parametrize("umask, mode", [(0o022, 0o644), (0o077, 0o600), (0o002, 0o664)])
def test_netcdf_outputs_honour_the_umask(tmp_path, umask, mode):
    old = os.umask(umask)
    try:
        path = write_snapshot(tmp_path / "rho0.800.nc", attrs={**attrs(), "dimension": 2}, **two_triangles_snapshot())
        plain = tmp_path / "plain.txt"
        plain.write_text("x")
    finally:
        os.umask(old)
    assert stat.S_IMODE(path.stat().st_mode) == mode == stat.S_IMODE(plain.stat().st_mode)
    assert [p.name for p in tmp_path.iterdir() if p.name.endswith(".tmp")] == []
