"""The whole workflow on config/smoke.yaml in a scratch directory: every figure, table and valid netCDF."""
from __future__ import annotations

import pandas as pd
import pytest
import yaml

from conftest import REPO, snakemake
from forcenet.datasets import open_dataset, validate_dataset

pytestmark = pytest.mark.workflow


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
        table = pd.read_csv(smoke_run / "results/figures" / f"{name}.csv")  # the figure's source data
        assert len(table) and {"panel", "system"} <= set(table.columns), name
    tables = sorted(p.name for p in (smoke_run / "results/tables").iterdir())
    assert "p1_validation.csv" in tables and "p1_validation.md" in tables


def test_no_op_rerun_does_nothing(smoke_run):
    result = snakemake(smoke_run, "-n")
    assert "Nothing to be done" in result.stdout + result.stderr
