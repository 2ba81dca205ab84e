"""config/example_import.yaml end to end (issue 26): the shipped LAMMPS dumps and contact table are imported,
analysed, stacked, drawn and judged like simulated systems; a malformed source passes the dry run (which reads no
source contents) and stops its import job with one line;
a snapshot copied from another system is refused by the analysis job, naming the attribute (issue 27)."""
from __future__ import annotations

import json
import shutil
from pathlib import Path

import pandas as pd
import pytest

from conftest import REPO, snakemake
from forcenet.datasets import paths, read_dataset, read_snapshot

pytestmark = pytest.mark.workflow
CONFIG = REPO / "config" / "example_import.yaml"
RESULTS = "results/example_import"


def workdir_with_examples(root: Path) -> Path:
    """A scratch directory in which the example config's relative paths (data/examples/…) resolve."""
    root.mkdir(parents=True, exist_ok=True)
    shutil.copytree(REPO / "data", root / "data")
    return root


@pytest.fixture(scope="module")
def example_run(tmp_path_factory) -> Path:
    workdir = workdir_with_examples(tmp_path_factory.mktemp("example_import"))
    result = snakemake(workdir, config=CONFIG)
    assert result.returncode == 0, result.stderr[-6000:]
    return workdir


def test_the_example_config_imports_analyses_and_draws_its_systems(example_run):
    results = example_run / RESULTS
    for system, labels in {"lammps_2d": ("0.820", "0.840", "0.860"), "table_2d": ("0.229", "0.233", "0.237")}.items():
        for label in labels:
            snap = read_snapshot(paths.snapshot(results, system, "r00", label))  # the contract, values included
            assert snap.attrs["source_format"] in ("lammps", "table")
            assert len(json.loads(snap.attrs["source_sha256"])) == 2
            read_dataset(paths.analysis(results, system, "r00", label), "analysis")
        measures = read_dataset(paths.network_measures(results, system), "network_measures")
        assert measures.attrs["force_law"] == "imported" and measures.sizes["rho"] == 3
    # LAMMPS's sheared run: a periodic box tilted by xy = 3, 4, 5, recorded in the snapshots and their analyses, in
    # which the force network winds around the box at F_th = 0
    for label, tilt in zip(("0.825", "0.845", "0.864"), (3.0, 4.0, 5.0)):
        snap = read_snapshot(paths.snapshot(results, "lammps_sheared_2d", "r00", label))
        assert snap.attrs["periodic_axes"] == "xy" and float(snap.attrs["box_tilt"]) == tilt
        analysis = read_dataset(paths.analysis(results, "lammps_sheared_2d", "r00", label), "analysis")
        assert float(analysis.attrs["box_tilt"]) == tilt
        assert analysis["percolates"].sel(force_kind="total").values[0] == 1
    read_dataset(paths.distances(results, "lammps_2d_p2"), "distances")
    for name in ("p1_fig01_networks", "p1_fig06_betti0", "p2_fig06_distances_normal_mu05"):
        assert (Path(paths.figure(results, name, "pdf"))).stat().st_size > 0
    # issue 56 item 5: no claim of P2 applies to imports: one row says why instead of a "not evaluated" row per claim
    p2 = pd.read_csv(paths.p2_validation_table(results, "csv"))
    assert len(p2) == 1 and p2["claim_id"].iloc[0] == "left_out" and "imported states" in p2["claim"].iloc[0]
    assert "imported states" in Path(paths.p2_validation_table(results, "md")).read_text().splitlines()[2]
    # P1: the claims about its compression protocol, the comparisons of its systems and the rows of its systems the
    # study lacks are left out, the first row saying so; the claims without ρ_J are judged
    p1 = pd.read_csv(paths.p1_validation_table(results, "csv"))
    note = p1[p1["kind"] == "note"]
    assert len(note) == 1 and note.index[0] == 0 and "Left out for the imported systems" in note["item"].iloc[0]
    assert not p1["evidence"].str.contains("imported states|not in the results", na=False).any()
    assert set(p1["system"]) == {"all", "lammps_2d", "lammps_sheared_2d"} and len(p1) < 40
    assert (p1[p1["system"] == "lammps_2d"]["verdict"] == "holds").any()  # claims without ρ_J are judged
    assert note["item"].iloc[0] in Path(paths.p1_validation_table(results, "md")).read_text()
    # issue 56 item 4: the source's units downstream (no `units:` here: the source's own, unnamed), and seed −1
    measures = read_dataset(paths.network_measures(results, "lammps_2d"), "network_measures")
    assert measures["mean_force"].attrs["units"] == "source force unit" and measures.attrs["seed"] == -1
    networks = pd.read_csv(Path(paths.figure(results, "p1_fig01_networks", "csv")))
    assert "x_i [source length unit]" in networks and "radius [source length unit]" in networks
    assert not any("d_ave" in column for column in networks)


def test_a_snapshot_copied_from_another_system_is_refused_by_the_analysis(example_run, tmp_path):
    workdir = tmp_path / "copy"
    shutil.copytree(example_run, workdir, symlinks=True)
    source = workdir / paths.snapshot(RESULTS, "lammps_2d", "r00", "0.840")
    target = workdir / paths.snapshot(RESULTS, "lammps_2d_p2", "r00", "0.840")
    shutil.copy(source, target)
    result = snakemake(workdir, paths.network_measures(RESULTS, "lammps_2d_p2"), "--forcerun",
                       "analyze_lammps_2d_p2", config=CONFIG)
    output = result.stdout + result.stderr
    lines = [line for line in output.splitlines() if "not of this run" in line and " ERROR " in line]
    assert result.returncode != 0 and "Traceback" not in output
    assert len(lines) == 1 and (f"{target.relative_to(workdir)}: not of this run: global attribute 'system' is "
                                "'lammps_2d', but this run is 'lammps_2d_p2'") in lines[0], output[-3000:]


def test_a_malformed_source_passes_the_dry_run_and_stops_its_import_job_with_one_line(tmp_path):
    """The dry run reads no source file's contents (issue 55 item 3); the import job reads the file, stops with one
    line naming it and the line, and writes no snapshot."""
    workdir = workdir_with_examples(tmp_path / "bad")
    atoms = workdir / "data" / "examples" / "lammps_2d" / "atoms.dump"
    lines = atoms.read_text().splitlines()
    lines[10] = " ".join("nan" if k == 2 else value for k, value in enumerate(lines[10].split()))
    atoms.write_text("\n".join(lines) + "\n")
    assert snakemake(workdir, "-n", config=CONFIG).returncode == 0
    target = paths.snapshot(RESULTS, "lammps_2d", "r00", "0.840")
    result = snakemake(workdir, target, config=CONFIG)
    output = result.stdout + result.stderr
    assert result.returncode != 0 and "Traceback" not in output
    expected = "data/examples/lammps_2d/atoms.dump, line 11, column 'x': NaN or infinite value"
    assert any(expected in line for line in output.splitlines()), output[-3000:]
    assert not list((workdir / RESULTS / "sim" / "lammps_2d").glob("r00/*.nc"))
