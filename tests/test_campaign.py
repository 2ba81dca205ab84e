"""Campaign records (`forcenet.datasets.records`, `forcenet.campaign`): a finished run recorded gives back every kept
value of every snapshot, bit for bit; a record of other settings, a changed file or an unfinished run is refused by
name; the status command tells recorded / finished / running / stopped / missing runs apart."""
from __future__ import annotations

import copy
import subprocess
import fcntl
import json
import re
from pathlib import Path

import numpy as np
import pytest

from conftest import load_config
from forcenet import campaign, pipeline
from forcenet.campaign import CampaignError
from forcenet.datasets import paths, read_dataset, read_snapshot, write_netcdf, write_snapshot
from forcenet.datasets.records import (DROPPED_VARIABLES, RecordError, record_dataset, record_differences,
                                       state_snapshot)
from forcenet.datasets.runs import simulation_sha256
from forcenet.systems import system_from_config
from test_datasets import two_triangles_snapshot

SYSTEM = "2d_linear"


@pytest.fixture
def config(tmp_path, monkeypatch):
    """The smoke config with its records and results under tmp_path (the working directory)."""
    monkeypatch.chdir(tmp_path)
    config = copy.deepcopy(load_config("smoke.yaml"))
    config["records_dir"] = "records"
    config["results_dir"] = "results"
    return config


def fake_run(config, realization="r00", cpu_seconds=1800.0, shift=0.0):
    """A finished run of SYSTEM in the config's results folder: one snapshot per grid ρ (four disks whose positions,
    forces and contacts change from state to state) and its cost record."""
    spec = system_from_config(SYSTEM, config)
    attrs = pipeline.run_attrs(config, SYSTEM, paths.realization_index(realization), title="test")
    outputs = []
    for k, label in enumerate(spec.rho_labels):
        arrays = two_triangles_snapshot(rho=float(label))
        arrays["position"] = arrays["position"] + 0.01 * k + shift + 1e-13 * np.arange(8).reshape(4, 2)
        keep = 5 - (k % 3)  # 5, 4, 3 contacts: the ragged arrays must keep each state's own
        for name in ("contact_i", "contact_j", "force_normal", "force_tangential"):
            arrays[name] = np.asarray(arrays[name])[:keep] * (1 if name.startswith("contact") else 1 + np.pi * k)
        path = paths.snapshot(config["results_dir"], SYSTEM, realization, label)
        write_snapshot(path, attrs={**attrs, "dem_damping_rate_time_step": 0.1 * k}, **arrays)
        outputs.append(path)
    Path(paths.run_cost(config["results_dir"], SYSTEM, realization)).write_text(json.dumps(
        {"system": SYSTEM, "realization": paths.realization_index(realization), "cpu_seconds": cpu_seconds,
         "particles": 4, "snapshots": len(outputs)}))
    return outputs


def test_a_record_gives_back_every_kept_value_of_every_snapshot_bit_for_bit(config, tmp_path):
    outputs = fake_run(config)
    row = campaign.record_run(config, SYSTEM, "r00", results="results")
    assert row["states"] == str(len(outputs)) and row["cpu_hours"] == "0.500" and row["particles"] == "4"
    assert campaign.read_manifest("records") == [row]
    restored = [str(tmp_path / "again" / Path(p).name) for p in outputs]
    campaign.restore_run(config=config, system=SYSTEM, realization="r00", outputs=restored,
                         cost_path=str(tmp_path / "again" / "run_cost.json"))
    for before, after in zip(outputs, restored):
        a, b = read_snapshot(before), read_snapshot(after)
        assert dict(a.attrs) == dict(b.attrs)  # the per-state λΔt too
        for name in b.data_vars:
            assert a[name].dtype == b[name].dtype and np.array_equal(a[name].values, b[name].values), name
        assert set(a.data_vars) - set(b.data_vars) == set(DROPPED_VARIABLES)
    cost = json.loads((tmp_path / "again" / "run_cost.json").read_text())
    assert cost == {"system": SYSTEM, "realization": 0, "cpu_seconds": 1800.0, "particles": 4,
                    "snapshots": len(outputs)}


def test_record_differences_finds_a_changed_force_and_a_record_refuses_other_radii(config):
    snapshots = [read_snapshot(p) for p in fake_run(config)]
    labels = system_from_config(SYSTEM, config).rho_labels
    record = record_dataset(snapshots, labels, simulation_sha256="x", cpu_seconds=1.0, title="t")
    assert record_differences(record, snapshots) == []
    record["force_tangential_residual"].values[-1, 1] += 1  # one unit in the last place of one component
    assert record_differences(record, snapshots) == [f"state {labels[-1]}: 'force_tangential' differs"]
    snapshots[1]["radius"].values[2] = 0.7
    with pytest.raises(RecordError, match=f"state {labels[1]}: other radii"):
        record_dataset(snapshots, labels, simulation_sha256="x", cpu_seconds=1.0, title="t")


def test_snapshots_of_two_realizations_do_not_make_one_record(config):
    first = [read_snapshot(p) for p in fake_run(config, "r00")]
    second = [read_snapshot(p) for p in fake_run(config, "r01")]
    with pytest.raises(RecordError, match=r"disagree in global attributes \[.*'realization'"):
        record_dataset([first[0], *second[1:]], system_from_config(SYSTEM, config).rho_labels,
                       simulation_sha256="x", cpu_seconds=1.0, title="t")


def test_state_snapshot_slices_each_states_own_contacts(config):
    snapshots = [read_snapshot(p) for p in fake_run(config)]
    record = record_dataset(snapshots, system_from_config(SYSTEM, config).rho_labels, simulation_sha256="x",
                            cpu_seconds=1.0, title="t")
    counts = [int(s.sizes["contact"]) for s in snapshots]
    assert counts[:3] == [5, 4, 3]
    for index, snapshot in enumerate(snapshots):
        _, arrays = state_snapshot(record, index)
        assert np.array_equal(arrays["contact_j"], snapshot["contact_j"].values)
        assert np.array_equal(arrays["force_normal"], snapshot["force_normal"].values)


def test_an_unfinished_run_is_not_recorded(config):
    outputs = fake_run(config)
    Path(outputs[-1]).unlink()
    with pytest.raises(CampaignError, match=rf"{SYSTEM} r00 has not finished in results: 1 of its files are missing"):
        campaign.record_run(config, SYSTEM, "r00", results="results")


def test_a_record_of_other_settings_is_refused_by_name_and_a_matching_one_restores(config):
    fake_run(config)
    campaign.record_run(config, SYSTEM, "r00", results="results")
    assert campaign.recorded_realizations(config, SYSTEM) == ["r00"]
    assert campaign.recorded_realizations(config, "2d_hertz") == []
    changed = copy.deepcopy(config)
    changed["systems"][SYSTEM]["friction"] = 0.25
    with pytest.raises(CampaignError, match=rf"records/{SYSTEM}/r00/states.nc was made under other settings of "
                                            rf"system '{SYSTEM}' .*forcenet-campaign drop {SYSTEM} r00"):
        campaign.recorded_realizations(changed, SYSTEM)
    # what the run does not depend on (analysis keys, other systems) keeps the record
    other = copy.deepcopy(config)
    other["analysis"]["thresholds"]["step"] = 0.1
    other["systems"]["2d_hertz"]["friction"] = 0.25
    assert campaign.recorded_realizations(other, SYSTEM) == ["r00"]
    # a record beyond the config's realization count is not restored
    without = copy.deepcopy(config)
    without.pop("records_dir")
    assert campaign.recorded_realizations(without, SYSTEM) == []


def test_a_changed_record_file_is_refused_with_both_digests(config, tmp_path):
    fake_run(config)
    row = campaign.record_run(config, SYSTEM, "r00", results="results")
    record = Path("records") / row["file"]
    record.write_bytes(record.read_bytes() + b"\0")
    with pytest.raises(CampaignError, match=r"states.nc: sha256 [0-9a-f]{12}, the manifest's [0-9a-f]{12}: the record "
                                            r"was changed"):
        campaign.restore_run(config=config, system=SYSTEM, realization="r00", outputs=[str(tmp_path / "x.nc")])
    assert campaign.verify_records(config) == [f"{record}: sha256 differs from the manifest's"]


def test_restoring_onto_another_grid_is_refused(config, tmp_path):
    fake_run(config)
    campaign.record_run(config, SYSTEM, "r00", results="results")
    labels = system_from_config(SYSTEM, config).rho_labels
    outputs = [str(tmp_path / "again" / f"rho{label}.nc") for label in labels]
    outputs[0] = str(tmp_path / "again" / "rho0.123.nc")
    with pytest.raises(RecordError, match=f"state 0 is ρ = {labels[0]}, but its output is .*rho0.123.nc"):
        campaign.restore_run(config=config, system=SYSTEM, realization="r00", outputs=outputs)


def test_status_tells_recorded_finished_running_stopped_and_missing_runs_apart(config):
    config["realizations"] = {name: 1 for name in config["systems"]} | {SYSTEM: 5}
    fake_run(config, "r00", cpu_seconds=3600.0)
    campaign.record_run(config, SYSTEM, "r00", results="results")
    fake_run(config, "r01", cpu_seconds=1800.0)
    labels = system_from_config(SYSTEM, config).rho_labels
    locks = []  # open while the status is read: a closed file releases its lock
    for name, held in (("r02", True), ("r03", False)):
        stage = Path(paths.run_dir("results", SYSTEM, name)) / paths.STAGING_DIR
        stage.mkdir(parents=True)
        (stage / f"rho{labels[0]}.nc").write_bytes(b"")
        locks.append(open(stage.parent / paths.STAGE_LOCK, "a+"))
        if held:
            fcntl.flock(locks[-1], fcntl.LOCK_EX | fcntl.LOCK_NB)
    statuses = {s.realization: s for s in campaign.campaign_status(config, results="results")
                if s.system == SYSTEM}
    assert [statuses[r].state for r in ("r00", "r01", "r02", "r03", "r04")] == [
        "recorded", "finished", "running", "stopped", "missing"]
    assert statuses["r00"].cpu_hours_done == 1.0 and statuses["r01"].cpu_hours_done == 0.5
    # to go: the recorded run's 1.0 CPU-hour, less the share of states already staged
    assert statuses["r04"].cpu_hours_to_go == 1.0
    assert statuses["r02"].cpu_hours_to_go == pytest.approx(1.0 * (1 - 1 / len(labels)))
    assert "forcenet-campaign record 2d_linear r01" in statuses["r01"].detail
    text = campaign.status_table(list(statuses.values()))
    assert text.splitlines()[-1].startswith("1 recorded, 1 finished, 1 running, 1 stopped, 1 missing")


def test_an_excluded_run_is_shown_with_its_reason_and_never_started(config, monkeypatch):
    """records/excluded.csv: a run that cannot be made here (it cannot integrate, or is a cluster's) is shown as
    excluded with its reason and nothing to go, and `run` does not start it; a stopped stage of it is not resumed,
    a held one still shows as running."""
    from forcenet import campaign_cli

    monkeypatch.setattr(campaign_cli, "POLL_SECONDS", 0.0)
    config["systems"] = {SYSTEM: config["systems"][SYSTEM]}
    config["realizations"] = {SYSTEM: 3}
    Path("records").mkdir()
    Path("records/excluded.csv").write_text(f"system,realization,reason\n{SYSTEM},r01,blows up at step 65\n")
    stage = Path(paths.run_dir("results", SYSTEM, "r01")) / paths.STAGING_DIR
    stage.mkdir(parents=True)
    statuses = {s.realization: s for s in campaign.campaign_status(config, results="results")}
    assert [statuses[r].state for r in ("r00", "r01", "r02")] == ["missing", "excluded", "missing"]
    assert statuses["r01"].detail.startswith("blows up at step 65") and statuses["r01"].cpu_hours_to_go == 0.0
    started = []

    def start(command, log):
        realization = Path(command[command.index("-m") + 2]).parent.name
        started.append(realization)
        fake_run(config, realization)
        return subprocess.Popen(["true"])

    campaign_cli.run_missing(config, configfile="c.yaml", results="results", say=lambda line: None, start=start)
    assert sorted(started) == ["r00", "r02"]
    assert "1 excluded" in campaign.status_table(campaign.campaign_status(config, results="results"))
    Path("records/excluded.csv").write_text(f"system,run\n{SYSTEM},r01\n")
    with pytest.raises(CampaignError, match=r"excluded\.csv: columns \['run', 'system'\]"):
        campaign.campaign_status(config, results="results")


def test_the_tabled_cpu_hours_are_per_run(tmp_path):
    (tmp_path / "p1.csv").write_text("# study: p1\n# system 2d_linear: N=2025 realizations=5 cpu_hours=0.73\n"
                                     "# system box: N=484 realizations=1 cpu_hours=0.04\nclaim,verdict\n")
    assert campaign.tabled_cpu_hours(tmp_path) == {"2d_linear": pytest.approx(0.146), "box": 0.04}


@pytest.mark.parametrize("recorded, matches, refuses", [
    ([], ["r00", "r01", "r10", "r100"], []),
    (["r00", "r01"], ["r02", "r10", "r100", "r010"], ["r00", "r01"]),
    (["r1"], ["r10", "r11", "r01"], ["r1"]),
])
def test_the_simulate_rules_constraint_leaves_out_exactly_the_recorded_runs(recorded, matches, refuses):
    pattern = re.compile(rf"(?P<realization>{campaign.realizations_except(recorded)})/run_cost\.json$")
    assert all(pattern.match(f"{name}/run_cost.json") for name in matches)
    assert not any(pattern.match(f"{name}/run_cost.json") for name in refuses)


def test_the_record_is_a_valid_run_record_file_with_units_everywhere(config):
    fake_run(config)
    row = campaign.record_run(config, SYSTEM, "r00", results="results")
    record = read_dataset(Path("records") / row["file"], "run_record")
    assert all("units" in v.attrs and "long_name" in v.attrs for v in record.variables.values())
    assert record.attrs["simulation_sha256"] == simulation_sha256(config, SYSTEM)
    assert json.loads(record.attrs["snapshot_attrs"])["system"] == SYSTEM


def test_the_size_table_and_drop_follow_the_manifest(config):
    fake_run(config)
    row = campaign.record_run(config, SYSTEM, "r00", results="results")
    megabytes = int(row["bytes"]) / 1e6
    count = len(campaign.realization_indices(config, SYSTEM))
    Path("records/README.md").write_text(f"intro\n{campaign.SIZE_TABLE_START}\nold\n{campaign.SIZE_TABLE_END}\nafter\n")
    campaign.write_size_table(config)
    text = Path("records/README.md").read_text()
    assert text.startswith("intro\n") and text.endswith("after\n") and "old" not in text
    assert f"| {SYSTEM} | 1 of {count} | {megabytes:.1f} | {megabytes:.2f} | {megabytes * count:.1f} |" in text
    assert "| 2d_hertz | 0 of 1 | 0.0 | – | – |" in text
    campaign.drop_record(config, SYSTEM, "r00")
    assert campaign.read_manifest("records") == [] and not Path("records", row["file"]).exists()
    assert campaign.recorded_realizations(config, SYSTEM) == []


def test_run_missing_records_each_run_as_it_lands_and_starts_none_that_cannot_finish(config, monkeypatch):
    from forcenet import campaign_cli

    monkeypatch.setattr(campaign_cli, "POLL_SECONDS", 0.0)
    config["systems"] = {SYSTEM: config["systems"][SYSTEM]}
    config["realizations"] = {SYSTEM: 4}
    fake_run(config, "r00", cpu_seconds=360.0)  # finished before: recorded first
    started, said = [], []

    def start(command, log):
        realization = Path(command[command.index("-m") + 2]).parent.name  # …/sim/{system}/{realization}/run_cost.json
        started.append((realization, command[:3], "--nolock" in command, Path(log).name))
        if realization == "r02":
            return subprocess.Popen(["false"])  # this run fails: named, not recorded
        fake_run(config, realization, cpu_seconds=720.0)
        return subprocess.Popen(["true"])

    rows = campaign_cli.run_missing(config, configfile="c.yaml", results="results", jobs=2, systems=[SYSTEM],
                                    say=said.append, start=start)
    assert [row["realization"] for row in rows] == ["r00", "r01", "r03"]
    assert [s[0] for s in started] == ["r01", "r02", "r03"]
    # r02 and r03 were started once r00 (0.1 h) and r01 (0.2 h) had landed: their estimate is the recorded mean
    assert any(line.startswith(f"started {SYSTEM} r03 (missing; about 0.15 CPU-hours") for line in said)
    assert all(s[1] == ["nice", "-n", "10"] and s[2] and s[3] == f"{s[0]}.log" for s in started)
    assert any(line.startswith(f"failed: {SYSTEM} r02 (exit 1") for line in said)
    assert [row["realization"] for row in campaign.read_manifest("records")] == ["r00", "r01", "r03"]
    # the budget: r02 still missing, its estimate (the mean of the recorded 0.1, 0.2, 0.2 h) × margin does not fit
    said.clear()
    assert campaign_cli.run_missing(config, configfile="c.yaml", results="results", hours=0.1, margin=1.5,
                                    say=said.append, start=start) == []
    assert said == [f"not started: {SYSTEM} r02 needs about 0.25 h (0.17 × 1.5), 0.10 h left"]
    # --only: nothing but the named runs is started (another process makes the others)
    said.clear()
    fake_run(config, "r03", cpu_seconds=720.0)  # a finished run outside --only: not recorded here
    campaign.drop_record(config, SYSTEM, "r03")
    assert campaign_cli.run_missing(config, configfile="c.yaml", results="results", hours=0.1,
                                    only=[f"{SYSTEM}:r02"], say=said.append, start=start) == []
    assert said == [f"not started: {SYSTEM} r02 needs about 0.23 h (0.15 × 1.5), 0.10 h left"]  # mean of 0.1, 0.2


def test_run_skips_a_queued_run_that_another_runner_took_meanwhile(config, monkeypatch):
    from forcenet import campaign_cli

    monkeypatch.setattr(campaign_cli, "POLL_SECONDS", 0.0)
    config["systems"] = {SYSTEM: config["systems"][SYSTEM]}
    config["realizations"] = {SYSTEM: 3}
    started, said, held = [], [], []

    def start(command, log):
        realization = Path(command[command.index("-m") + 2]).parent.name
        started.append(realization)
        if realization == "r00":  # meanwhile another runner starts r01: it holds r01's stage lock
            run_dir = Path(paths.run_dir("results", SYSTEM, "r01"))
            (run_dir / paths.STAGING_DIR).mkdir(parents=True)
            held.append(open(run_dir / paths.STAGE_LOCK, "a+"))
            fcntl.flock(held[-1], fcntl.LOCK_EX | fcntl.LOCK_NB)
        fake_run(config, realization, cpu_seconds=360.0)
        return subprocess.Popen(["true"])

    rows = campaign_cli.run_missing(config, configfile="c.yaml", results="results", jobs=1, systems=[SYSTEM],
                                    say=said.append, start=start)
    assert started == ["r00", "r02"] and [row["realization"] for row in rows] == ["r00", "r02"]
    assert f"skipped: {SYSTEM} r01 is running (another process)" in said


def test_a_variant_without_runs_is_estimated_from_its_base_of_the_same_size(config):
    """A control of the catalog (`like:` its system, one size and grid) costs about what its system's runs cost;
    one of another size does not borrow their figure."""
    fake_run(config, "r00", cpu_seconds=720.0)
    campaign.record_run(config, SYSTEM, "r00", results="results")
    variant, resized = f"{SYSTEM}_variant", f"{SYSTEM}_resized"
    config["systems"][variant] = dict(config["systems"][SYSTEM], friction=0.0)
    config["systems"][resized] = dict(config["systems"][SYSTEM], box_length=config["systems"][SYSTEM]["box_length"] + 2)
    config["system_info"] = {**config.get("system_info", {}), variant: {"like": SYSTEM}, resized: {"like": SYSTEM}}
    config["realizations"] = {name: 1 for name in config["systems"]}
    statuses = {s.system: s for s in campaign.campaign_status(config, results="results")}
    assert statuses[variant].cpu_hours_to_go == 0.2
    assert statuses[variant].detail == f"estimate: mean of the recorded runs of {SYSTEM} (same size and grid)"
    assert statuses[resized].detail.startswith("estimate: cost model")


def test_a_run_recorded_again_keeps_its_record(config):
    """Recording a run that already has an intact record of the same settings rewrites nothing (the same run with
    another date would be a new file in git); `replace` records it again."""
    fake_run(config, "r00", cpu_seconds=360.0)
    first = campaign.record_run(config, SYSTEM, "r00", results="results")
    path = Path("records", first["file"])
    written = path.stat().st_mtime_ns
    assert campaign.record_run(config, SYSTEM, "r00", results="results") == first
    assert path.stat().st_mtime_ns == written
    path.write_bytes(path.read_bytes()[:-10])  # a damaged record is not kept
    assert campaign.recorded_row(config, "records", SYSTEM, "r00") is None
    again = campaign.record_run(config, SYSTEM, "r00", results="results")
    assert again["sha256"] == campaign.file_sha256(path)


def chain_state(wall_force: float):
    """A jammed state (Z = 4) of three disks in a row pressed between two walls: each pair pushes with 1 along x, the
    walls with `wall_force` (at rest only for 1)."""
    import xarray as xr

    return xr.Dataset({"Z": 4.0, "radius": ("particle", np.ones(3)),
                       "contact_i": ("contact", [1, 2]), "contact_j": ("contact", [0, 1]),
                       "force_normal": (("contact", "spatial"), [[1.0, 0.0], [1.0, 0.0]]),
                       "force_tangential": (("contact", "spatial"), np.zeros((2, 2))),
                       "wall_contact_particle": ("wall_contact", [0, 2]),
                       "wall_contact_force": (("wall_contact", "spatial"), [[wall_force, 0.0], [-wall_force, 0.0]])})


def test_a_jammed_state_not_at_rest_under_its_recorded_forces_is_not_recorded(config):
    campaign.out_of_balance([chain_state(1.0)], ["0.850"], SYSTEM, "r00")  # at rest: nothing to say
    with pytest.raises(CampaignError, match=r"2d_linear r00: the state at rho = 0\.850 is not at rest .*\(particle 0 "
                                            r"feels 1 x the mean normal force"):
        campaign.out_of_balance([chain_state(2.0)], ["0.850"], SYSTEM, "r00")
    # a finished run whose last state is jammed but out of balance (the fake run's forces are arbitrary) is refused
    outputs = fake_run(config)
    last = read_snapshot(outputs[-1]).load()
    last.close()
    last["Z"] = last["Z"].copy(data=4.0)  # its units and long name kept
    write_netcdf(last, outputs[-1], kind="snapshot")
    with pytest.raises(CampaignError, match="is not at rest under its recorded forces"):
        campaign.record_run(config, SYSTEM, "r00", results="results")
    assert not Path(config["records_dir"], campaign.record_path(config, config["records_dir"], SYSTEM, "r00")).exists()


def test_a_stopped_runner_stops_its_runs_and_records_none(config):
    """Ctrl-C or SIGTERM while runs are in progress: each run's process is stopped (SIGTERM; it keeps its
    checkpoint), nothing is recorded, and the runner does not hang."""
    from forcenet import campaign_cli

    config["systems"] = {SYSTEM: config["systems"][SYSTEM]}
    config["realizations"] = {SYSTEM: 2}
    processes, said = [], []

    def start(command, log):
        processes.append(subprocess.Popen(["sleep", "300"]))
        return processes[-1]

    def say(line):
        said.append(line)
        if line.startswith(f"started {SYSTEM} r01"):  # both runs in progress: Ctrl-C
            raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        campaign_cli.run_missing(config, configfile="c.yaml", results="results", jobs=2, say=say, start=start)
    assert len(processes) == 2 and all(p.poll() == -15 for p in processes)  # ended by SIGTERM, none left running
    assert said[-2:] == [f"stopped {SYSTEM} r00 (resumes from its checkpoint)",
                         f"stopped {SYSTEM} r01 (resumes from its checkpoint)"]
    assert campaign.read_manifest("records") == []


def test_a_record_of_the_earlier_layout_is_rewritten_with_the_same_values(config):
    """`forcenet-campaign recode`: a record whose forces are raw vectors (forcenet-run-record-1) becomes one of
    this layout, every state giving back the same snapshot, and its manifest row follows the new file."""
    from forcenet.datasets.force_codec import decode_forces
    from forcenet.datasets.records import FORCE_STORAGE, RECORD_FORMAT, recoded_record

    snapshots = [read_snapshot(path) for path in fake_run(config)]
    row = campaign.record_run(config, SYSTEM, "r00", results="results")
    path = Path("records") / row["file"]
    record = read_dataset(path, "run_record")
    earlier = record.drop_vars(list(FORCE_STORAGE))
    starts = np.concatenate([[0], np.cumsum(record["contact_count"].values)])
    raw = [decode_forces(record["position"].values[k], record["contact_i"].values[a:b], record["contact_j"].values[a:b],
                         {name: record[name].values[a:b] for name in FORCE_STORAGE})
           for k, (a, b) in enumerate(zip(starts[:-1], starts[1:]))]
    earlier["force_normal"] = (("contact", "spatial"), np.concatenate([n for n, _ in raw]))
    earlier["force_tangential"] = (("contact", "spatial"), np.concatenate([t for _, t in raw]))
    earlier.attrs["record_format"] = "forcenet-run-record-1"
    assert recoded_record(record) is record  # this layout already: kept as it is
    recoded = recoded_record(earlier)
    assert recoded.attrs["record_format"] == RECORD_FORMAT
    assert record_differences(recoded, snapshots) == []
    earlier.to_netcdf(path)  # the folder holds the earlier layout; the manifest row is made to match it
    manifest = campaign.read_manifest("records")
    manifest[0].update(sha256=campaign.file_sha256(path), bytes=str(path.stat().st_size))
    campaign.write_manifest("records", manifest)
    assert [r["realization"] for r in campaign.recode_records(config, say=lambda line: None)] == ["r00"]
    assert campaign.verify_records(config) == []
    assert record_differences(read_dataset(path, "run_record"), snapshots) == []
    assert campaign.recode_records(config, say=lambda line: None) == []  # nothing left to rewrite
