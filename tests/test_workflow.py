"""The whole workflow on config/smoke.yaml in a scratch directory: every figure, table and valid netCDF."""
from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest
import yaml

from conftest import REPO
from forcenet.datasets import open_dataset, validate_dataset

pytestmark = pytest.mark.workflow


def snakemake(workdir: Path, *args: str) -> subprocess.CompletedProcess:
    command = [sys.executable, "-m", "snakemake", "--snakefile", str(REPO / "Snakefile"), "--directory",
               str(workdir), "--configfile", str(REPO / "config/smoke.yaml"), "--cores", "2", *args]
    return subprocess.run(command, capture_output=True, text=True, timeout=900)


@pytest.fixture(scope="module")
def smoke_run(tmp_path_factory) -> Path:
    workdir = tmp_path_factory.mktemp("smoke")
    result = snakemake(workdir)
    assert result.returncode == 0, result.stderr[-6000:]
    return workdir


def test_every_netcdf_output_validates(smoke_run):
    files = sorted((smoke_run / "results").rglob("*.nc"))
    config = yaml.safe_load((REPO / "config/smoke.yaml").read_text())
    n_snapshots = sum(1 for _ in (smoke_run / "results/sim").rglob("rho*.nc"))
    assert n_snapshots >= len(config["systems"]) * config["realizations"] * 3
    assert len(files) >= 2 * n_snapshots
    for path in files:
        validate_dataset(open_dataset(path))


def test_every_figure_and_table_exists(smoke_run):
    dry = snakemake(smoke_run, "-n", "--forceall", "--quiet", "rules")
    figure_rules = [line.split()[0] for line in dry.stdout.splitlines() if line.startswith("figure_")]
    assert figure_rules, dry.stdout
    for rule in figure_rules:
        name = rule.removeprefix("figure_")
        for suffix in (".pdf", ".png"):
            path = smoke_run / "results/figures" / f"{name}{suffix}"
            assert path.stat().st_size > 1000, path
    tables = sorted(p.name for p in (smoke_run / "results/tables").iterdir())
    assert "p1_validation.csv" in tables and "p1_validation.md" in tables


def test_no_op_rerun_does_nothing(smoke_run):
    result = snakemake(smoke_run, "-n")
    assert "Nothing to be done" in result.stdout + result.stderr


def test_each_study_uses_its_rattler_rule_and_p2_products_show_p2(smoke_run):
    results = smoke_run / "results"
    config = yaml.safe_load((REPO / "config/smoke.yaml").read_text())
    rules = {s: "once" for s in config["studies"]["p1"]["systems"]} | {
        s: "none" for s in config["studies"]["p2"]["systems"]}  # smoke: P1 removes rattlers, P2 keeps them
    for system, rule in rules.items():
        analysis = next((results / "analysis" / system).rglob("rho*.nc"))
        assert open_dataset(analysis).attrs["rattler_rule"] == rule, system
        assert open_dataset(results / system / "network_measures.nc").attrs["rattler_rule"] == rule, system
    for system in config["studies"]["p2"]["systems"]:
        assert open_dataset(results / system / "distances.nc").attrs["rattler_rule"] == "none"
    table1 = (results / "tables/p2_table1.md").read_text()
    assert "(a,b), P2 | 0.089" in table1 and "ours / P2" in table1 and "rattler rule 'none'" in table1
    states = (results / "tables/p2_table_states.csv").read_text().splitlines()
    assert states[0].startswith("realization,rho_a") and len(states) == 1 + config["realizations"]
