"""Campaign records through the workflow (config key records_dir, rule restore_{system}): the smoke build's runs,
recorded with `forcenet-campaign record`, are restored in a fresh folder with no simulation job, and their analyses
equal the simulated build's value for value; P2's runs, recorded as P2 run records, give P2's distances, Tables
I-III (and those of the readings beside), validation table and figures identical to the simulated build's; a record
made under other settings stops the dry run naming it."""
from __future__ import annotations

import subprocess
import sys

import pytest
import xarray as xr
import yaml

from conftest import REPO, snakemake
from forcenet.datasets import paths

pytestmark = pytest.mark.workflow

SYSTEMS = ("2d_linear", "3d_hertz")  # one per dimension
P2 = ("2d_poly_mu05", "2d_poly_mu0")


def campaign_command(workdir, config, *args):
    return subprocess.run([sys.executable, "-m", "forcenet.campaign_cli", "--configfile", str(config), *args],
                          cwd=workdir, capture_output=True, text=True, timeout=300)


def record_smoke_runs(smoke_run, workdir, systems, record_file):
    """Give `workdir` the smoke config with records_dir and the records (`record_file`, the record's file name) of
    the smoke build's r00 of `systems`, made with `forcenet-campaign record`."""
    config = yaml.safe_load((REPO / "config/smoke.yaml").read_text())
    config["records_dir"] = "records"
    (workdir / "smoke.yaml").write_text(yaml.safe_dump(config))
    for system in systems:
        result = campaign_command(workdir, workdir / "smoke.yaml", "--results", str(smoke_run / "results"),
                                  "record", system, "r00")
        assert result.returncode == 0, result.stderr
        assert f"recorded {system} r00: {system}/r00/{record_file}" in result.stdout
    return workdir


@pytest.fixture(scope="module")
def recorded(smoke_run, tmp_path_factory):
    """A fresh folder whose config is the smoke config with records of the smoke build's SYSTEMS runs."""
    return record_smoke_runs(smoke_run, tmp_path_factory.mktemp("campaign"), SYSTEMS, "states.nc")


def test_recorded_runs_are_restored_not_simulated_and_analyse_to_the_same_values(smoke_run, recorded):
    targets = [paths.network_measures("results", s) for s in SYSTEMS]
    dry = snakemake(recorded, "-n", *targets, config=recorded / "smoke.yaml")
    assert dry.returncode == 0, dry.stderr
    assert "restore_2d_linear" in dry.stdout and "restore_3d_hertz" in dry.stdout
    assert "simulate_" not in dry.stdout
    build = snakemake(recorded, *targets, config=recorded / "smoke.yaml")
    assert build.returncode == 0, build.stderr
    for system in SYSTEMS:
        log = (recorded / paths.run_log("results", "restore", system, "r00")).read_text()
        assert "from its campaign record (no DEM step)" in log
        with xr.open_dataset(smoke_run / paths.network_measures("results", system)) as simulated, \
                xr.open_dataset(recorded / paths.network_measures("results", system)) as restored:
            assert simulated.drop_attrs().identical(restored.drop_attrs()), system
    status = campaign_command(recorded, recorded / "smoke.yaml", "status")
    assert status.returncode == 0, status.stderr
    assert all(f"{system:<20} r00  recorded" in status.stdout for system in SYSTEMS)


def test_a_record_of_other_settings_stops_the_dry_run_naming_it(recorded):
    config = yaml.safe_load((recorded / "smoke.yaml").read_text())
    config["systems"]["2d_linear"]["wall_speed"] = 0.004  # a scale key the run depends on: another fingerprint
    (recorded / "changed.yaml").write_text(yaml.safe_dump(config))
    dry = snakemake(recorded, "-n", config=recorded / "changed.yaml")
    assert dry.returncode != 0
    assert ("campaign record records/2d_linear/r00/states.nc was made under other settings of system '2d_linear'"
            in dry.stdout + dry.stderr)
    verify = campaign_command(recorded, recorded / "changed.yaml", "verify")
    assert verify.returncode == 1 and "made under other settings of '2d_linear'" in verify.stdout


def test_recorded_p2_runs_give_every_p2_product_identical_to_the_simulated_build(smoke_run, tmp_path):
    record_smoke_runs(smoke_run, tmp_path, P2, "p2_run.nc")
    built = smoke_run / "results"
    products = sorted(str(p.relative_to(smoke_run)) for pattern in (
        "tables/p2_*.csv", "readings/*/tables/p2_*.csv", "figures/p2_*.csv", "*/distances.nc",
        "readings/*/*/distances.nc") for p in built.glob(pattern))
    assert len([p for p in products if p.endswith("distances.nc")]) == 2 * 3  # the build's and two readings'
    dry = snakemake(tmp_path, "-n", *products, config=tmp_path / "smoke.yaml")
    assert dry.returncode == 0, dry.stderr
    assert "simulate_" not in dry.stdout and all(f"restore_{system}" in dry.stdout for system in P2)
    build = snakemake(tmp_path, *products, config=tmp_path / "smoke.yaml")
    assert build.returncode == 0, build.stderr[-3000:]
    for product in products:
        if product.endswith(".nc"):
            with xr.open_dataset(smoke_run / product) as simulated, xr.open_dataset(tmp_path / product) as restored:
                assert simulated.drop_attrs().identical(restored.drop_attrs()), product
        else:
            assert (smoke_run / product).read_text() == (tmp_path / product).read_text(), product
    status = campaign_command(tmp_path, tmp_path / "smoke.yaml", "status")
    assert all(f"{system:<20} r00  recorded" in status.stdout for system in P2), status.stdout
