"""P2 run records (`forcenet.datasets.records.p2_record_dataset`, kind "p2_run_record"): a finished P2 run recorded
gives back its summary (distances under every never-dying convention, Z, never-dying class and point counts) value
for value and the states Tables I-III read bit for bit; a record of other settings, or one lacking a convention the
config reads, is refused by name; the campaign runner makes a P2 run with its summary."""
from __future__ import annotations

import copy
import json
from pathlib import Path

import numpy as np
import pytest

from forcenet import campaign, pipeline
from forcenet.campaign import CampaignError
from forcenet.datasets import paths, read_dataset, read_snapshot, write_snapshot
from forcenet.datasets.records import DROPPED_VARIABLES
from forcenet.pipeline_p2 import p2_conventions, p2_read_state_indices, p2_run_summary
from forcenet.report.p2_distances import consecutive_distances, summary_distances
from forcenet.systems import system_from_config
from test_campaign import config  # noqa: F401 — the fixture: the smoke config with records and results in tmp_path
from test_datasets import two_triangles_snapshot

FRICTIONAL, FRICTIONLESS = "2d_poly_mu05", "2d_poly_mu0"


def fake_p2_run(config, system=FRICTIONAL, realization="r00", cpu_seconds=900.0):
    """A finished, analysed and summed-up run of `system`: one four-disk snapshot per grid ρ (forces changing from
    state to state), its analyses, cost record and summary; the analysis datasets."""
    spec = system_from_config(system, config)
    attrs = pipeline.run_attrs(config, system, paths.realization_index(realization), title="test")
    snapshots, analyses = [], []
    for k, label in enumerate(spec.rho_labels):
        arrays = two_triangles_snapshot(rho=float(label))
        arrays["position"] = arrays["position"] + 0.01 * k
        arrays["force_normal"] = arrays["force_normal"] * (1 + 0.37 * k) ** np.arange(1, 6)[:, None] % 1.3
        arrays["Z"] = 2.0 + 0.25 * k
        path = paths.snapshot(config["results_dir"], system, realization, label)
        write_snapshot(path, attrs=attrs, **arrays)
        snapshots.append(path)
        analyses.append(paths.analysis(config["results_dir"], system, realization, label))
    pipeline.analyze_run(snapshots=snapshots, outputs=analyses, analysis=pipeline.snapshot_analysis_params(config, system))
    Path(paths.run_cost(config["results_dir"], system, realization)).write_text(json.dumps(
        {"system": system, "realization": paths.realization_index(realization), "cpu_seconds": cpu_seconds,
         "particles": 4, "snapshots": len(snapshots)}))
    p2_run_summary(analyses=analyses, output=paths.p2_run(config["results_dir"], system, realization), config=config,
                   system=system, realization=realization, conventions=p2_conventions(config))
    return [read_dataset(path, "analysis") for path in analyses]


def restore(config, system, tmp_path, labels):
    summary = tmp_path / "again" / "summary.nc"
    outputs = [str(tmp_path / "again" / f"rho{label}.nc") for label in labels]
    campaign.restore_run(config=config, system=system, realization="r00", outputs=outputs,
                         cost_path=str(tmp_path / "again" / "run_cost.json"), summary_path=str(summary))
    return read_dataset(summary, "p2_run"), outputs


def test_a_p2_record_gives_back_the_summary_and_the_states_tables_i_to_iii_read(config, tmp_path):
    analyses = fake_p2_run(config)
    row = campaign.record_run(config, FRICTIONAL, "r00", results="results")
    spec = system_from_config(FRICTIONAL, config)
    assert row["file"] == f"{FRICTIONAL}/r00/p2_run.nc" and row["states"] == str(len(spec.rho_grid))
    p2 = config["studies"]["p2"]
    kept = [spec.rho_labels[i] for i in p2_read_state_indices(spec.rho_grid, p2["table_rho"], p2["table_states"])]
    assert campaign.p2_kept_labels(config, FRICTIONAL) == kept and kept[0] < f"{p2['table_rho']:.3f}" < kept[-1]
    summary, outputs = restore(config, FRICTIONAL, tmp_path, kept)
    original = read_dataset(paths.p2_run("results", FRICTIONAL, "r00"), "p2_run")
    assert summary.drop_attrs().identical(original.drop_attrs())
    for convention in p2_conventions(config):  # the distances the analyses give, value for value
        assert summary_distances(summary, convention).identical(consecutive_distances(analyses, convention))
    for label, output in zip(kept, outputs):
        a, b = read_snapshot(paths.snapshot("results", FRICTIONAL, "r00", label)), read_snapshot(output)
        assert dict(a.attrs) == dict(b.attrs)
        for name in b.data_vars:
            assert a[name].dtype == b[name].dtype and np.array_equal(a[name].values, b[name].values), name
        assert set(a.data_vars) - set(b.data_vars) == set(DROPPED_VARIABLES)
    cost = json.loads((tmp_path / "again" / "run_cost.json").read_text())
    assert cost == {"system": FRICTIONAL, "realization": 0, "cpu_seconds": 900.0, "particles": 4,
                    "snapshots": len(spec.rho_grid)}
    with pytest.raises(CampaignError, match=f"keeps the states .*, not rho{spec.rho_labels[0]}.nc"):
        restore(config, FRICTIONAL, tmp_path, [spec.rho_labels[0]])


def test_the_frictionless_record_keeps_no_state(config, tmp_path):
    fake_p2_run(config, FRICTIONLESS)
    campaign.record_run(config, FRICTIONLESS, "r00", results="results")
    assert campaign.p2_kept_labels(config, FRICTIONLESS) == []
    record = read_dataset(Path("records") / FRICTIONLESS / "r00" / "p2_run.nc", "p2_run_record")
    assert "state" not in record.dims and "position" not in record
    summary, _ = restore(config, FRICTIONLESS, tmp_path, [])
    assert summary.drop_attrs().identical(read_dataset(paths.p2_run("results", FRICTIONLESS, "r00"),
                                                       "p2_run").drop_attrs())


def test_a_p2_record_of_other_settings_is_refused_by_name(config, tmp_path):
    fake_p2_run(config)
    campaign.record_run(config, FRICTIONAL, "r00", results="results")
    changed = copy.deepcopy(config)
    changed["systems"][FRICTIONAL]["friction"] = 0.25
    with pytest.raises(CampaignError, match=rf"records/{FRICTIONAL}/r00/p2_run.nc was made under other settings of "
                                            rf"system '{FRICTIONAL}'"):
        campaign.recorded_realizations(changed, FRICTIONAL)
    with pytest.raises(CampaignError, match="its simulation fingerprint is not this config's"):
        restore(changed, FRICTIONAL, tmp_path, campaign.p2_kept_labels(changed, FRICTIONAL))
    assert campaign.verify_records(changed) == [f"records/{FRICTIONAL}/r00/p2_run.nc: made under other settings of "
                                                f"'{FRICTIONAL}' than the config's"]


def test_a_p2_record_lacking_a_convention_the_config_reads_is_refused_by_name(config, tmp_path):
    fake_p2_run(config)
    campaign.record_run(config, FRICTIONAL, "r00", results="results")
    other = copy.deepcopy(config)
    other["analysis"]["essential_convention"] = "zero"  # an analysis key: the record still matches the run
    assert campaign.recorded_realizations(other, FRICTIONAL) == ["r00"]
    with pytest.raises(CampaignError, match=r"p2_run.nc: .*never-dying conventions \['minus_one', 'apart', 'drop'\], "
                                            r"not under \['zero'\]"):
        restore(other, FRICTIONAL, tmp_path, campaign.p2_kept_labels(other, FRICTIONAL))
    # nor is a summary lacking one recorded (again: the run has an intact record, kept unless replaced)
    assert campaign.record_run(other, FRICTIONAL, "r00", results="results")["realization"] == "r00"
    with pytest.raises(CampaignError, match=r"no distances under the never-dying conventions \['zero'\]"):
        campaign.record_run(other, FRICTIONAL, "r00", results="results", replace=True)


def test_a_p2_run_without_its_summary_is_not_recorded_and_the_runner_makes_it_with_its_summary(config):
    from forcenet import campaign_cli

    fake_p2_run(config)
    Path(paths.p2_run("results", FRICTIONAL, "r00")).unlink()
    with pytest.raises(CampaignError, match=rf"{FRICTIONAL} r00: its summary .*p2_runs/r00.nc is missing"):
        campaign.record_run(config, FRICTIONAL, "r00", results="results")
    status = {s.system: s for s in campaign.campaign_status(config, results="results")}
    assert status[FRICTIONLESS].state == "missing"
    started = []

    class Failed:  # the run the runner starts: it ends at once, failed (nothing to record)
        returncode = 1

        def poll(self):
            return 1

    def start(command, log):
        started.append(command)
        return Failed()

    campaign_cli.run_missing(config, configfile="c.yaml", results="results", only=[FRICTIONLESS], say=lambda _: None,
                             start=start)
    assert started and started[0][started[0].index("snakemake") + 1] == paths.p2_run("results", FRICTIONLESS, "r00")
