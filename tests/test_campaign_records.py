"""The committed campaign records (data/validation/, data/validation/README.md): every record can be restored under
config/validation.yaml (file present, its sha256 the manifest's, made under the config's settings of its system,
one state per ρ of the grid), and the workflow analyses recorded runs from their records with no simulation job,
giving back the recorded states (ρ and Z of every state)."""
from __future__ import annotations

import os
import re

import numpy as np
import pytest
import xarray as xr
import yaml

from conftest import REPO, load_config, snakemake
from forcenet import campaign
from forcenet.datasets import paths, read_dataset
from forcenet.datasets.records import p2_record_summary
from forcenet.systems import system_from_config

CONFIG = load_config("validation.yaml")
RECORDS = REPO / CONFIG["records_dir"]
ROWS = campaign.read_manifest(RECORDS)


def test_the_validation_config_keeps_its_records_in_the_repository():
    assert CONFIG["records_dir"] == "data/validation" and (RECORDS / "README.md").exists()
    readme = (RECORDS / "README.md").read_text()
    assert campaign.SIZE_TABLE_START in readme and campaign.SIZE_TABLE_END in readme


def test_the_size_table_in_the_records_readme_is_the_manifests(monkeypatch):
    # records imported from another branch (or a manifest edited by hand) must not leave the README's sizes behind
    monkeypatch.chdir(REPO)  # records_dir is relative to the repository root
    readme = (RECORDS / "README.md").read_text()
    committed = readme.partition(campaign.SIZE_TABLE_START)[2].partition(campaign.SIZE_TABLE_END)[0].strip()
    assert committed == campaign.size_table(CONFIG), "run forcenet-campaign sizes --write"


def test_every_committed_record_can_be_restored_under_the_validation_config(monkeypatch):
    monkeypatch.chdir(REPO)  # records_dir is relative to the repository root
    assert campaign.verify_records(CONFIG) == []
    for row in ROWS:
        spec = system_from_config(row["system"], CONFIG)
        assert int(row["states"]) == len(spec.rho_grid), row["file"]
        assert row["realization"] in [paths.realization_name(i) for i in range(CONFIG["realizations"][row["system"]])]


@pytest.mark.workflow
def test_recorded_runs_are_analysed_from_their_records_with_no_simulation(tmp_path):
    if not ROWS:
        pytest.skip("no campaign record is committed yet (forcenet-campaign status)")
    states = [row for row in ROWS if row["file"].endswith("/states.nc")]  # P1 runs: every state kept
    chosen = sorted(states, key=lambda row: int(row["bytes"]))[:2]  # the two smallest: about a minute
    # a P2 run keeps its summary (and Tables I-III's states): restored as its p2_runs file
    p2 = sorted((row for row in ROWS if row["file"].endswith("/p2_run.nc")), key=lambda row: int(row["bytes"]))[:1]
    (tmp_path / "data").mkdir()
    os.symlink(RECORDS, tmp_path / "data" / "validation")
    config = {**CONFIG, "results_dir": "results"}
    (tmp_path / "validation.yaml").write_text(yaml.safe_dump(config))
    targets = [paths.p2_run("results", row["system"], row["realization"]) for row in p2]
    for row in chosen:
        labels = system_from_config(row["system"], CONFIG).rho_labels
        targets += [paths.analysis("results", row["system"], row["realization"], label) for label in labels]
    dry = snakemake(tmp_path, "-n", *targets, config=tmp_path / "validation.yaml")
    assert dry.returncode == 0, dry.stderr[-3000:]
    assert "simulate_" not in dry.stdout and all(f"restore_{row['system']}" in dry.stdout for row in chosen + p2)
    build = snakemake(tmp_path, *targets, config=tmp_path / "validation.yaml")
    assert build.returncode == 0, build.stderr[-3000:]
    for row in chosen:
        with xr.open_dataset(RECORDS / row["file"]) as record:
            labels = [str(label) for label in record["state"].values]
            analysed = [read_dataset(tmp_path / paths.analysis("results", row["system"], row["realization"], label),
                                     "analysis") for label in labels]
            restored = [read_dataset(tmp_path / paths.snapshot("results", row["system"], row["realization"], label),
                                     "snapshot") for label in labels]
            assert np.array_equal([float(a["rho"]) for a in analysed], record["rho"].values), row["file"]
            assert {int(a["n_particles"]) for a in analysed} == {int(row["particles"])}, row["file"]
            assert np.array_equal([float(s["Z"]) for s in restored], record["Z"].values), row["file"]
            assert [s.sizes["contact"] for s in restored] == list(record["contact_count"].values), row["file"]
    for row in p2:
        with xr.open_dataset(RECORDS / row["file"]) as record:
            summary = read_dataset(tmp_path / paths.p2_run("results", row["system"], row["realization"]), "p2_run")
            for name, variable in p2_record_summary(record).data_vars.items():
                assert np.array_equal(summary[name].values, variable.values, equal_nan=True), (row["file"], name)


def _study_systems(study: str) -> list[str]:
    """The systems whose runs a study's committed table is made from (P1: its systems and counterparts)."""
    entry = CONFIG["studies"][study]
    return list(entry["systems"]) + list(entry.get("counterparts", []))


def _without_provenance_of_the_day(text: str) -> str:
    """A committed table without what differs between two generations of the same records: the date and the
    commit it was generated from (the commit that adds the table is necessarily a later one)."""
    kept = []
    for line in text.splitlines():
        if line.startswith(("# git_commit:", "# date:")):
            continue
        kept.append(re.sub(r" on \d{4}-\d\d-\d\d \d\d:\d\d UTC from commit `[0-9a-f]+`", "", line))
    return "\n".join(kept)


@pytest.mark.workflow
@pytest.mark.parametrize("study", ["p1", "p2"])
def test_the_committed_tables_are_regenerated_from_the_records_alone(study, tmp_path, monkeypatch):
    """data/validation/README.md: with every run of a study recorded, `snakemake validation_report_{study}` in a
    folder with the records and no results/ simulates nothing and writes docs/validation/{study}.{md,csv} equal to
    the committed ones."""
    monkeypatch.chdir(REPO)  # records_dir is relative to the repository root
    statuses = campaign.campaign_status(CONFIG, results=tmp_path / "no-results")
    missing = [f"{s.system} {s.realization}" for s in statuses
               if s.system in _study_systems(study) and s.state not in ("recorded", "excluded")]
    if missing:
        pytest.skip(f"{len(missing)} of {study}'s runs have no record yet, so its committed table is not made from "
                    f"records alone (forcenet-campaign status): {', '.join(missing[:3])}, …")
    (tmp_path / "data").mkdir()
    os.symlink(RECORDS, tmp_path / "data" / "validation")
    target = f"validation_report_{study}"
    dry = snakemake(tmp_path, "-n", target, config=REPO / "config/validation.yaml")
    assert dry.returncode == 0, dry.stderr[-3000:]
    assert "restore_" in dry.stdout and "simulate_" not in dry.stdout  # zero DEM steps
    build = snakemake(tmp_path, target, config=REPO / "config/validation.yaml")
    assert build.returncode == 0, build.stderr[-3000:]
    for suffix in ("md", "csv"):
        committed = (REPO / paths.campaign_table(study, suffix)).read_text()
        regenerated = (tmp_path / paths.campaign_table(study, suffix)).read_text()
        assert _without_provenance_of_the_day(regenerated) == _without_provenance_of_the_day(committed), suffix
