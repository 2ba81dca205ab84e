"""The whole workflow on config/smoke.yaml in a scratch directory: every figure, table and valid netCDF, files
readable as the umask allows, the HTML report drawn by a browser, a bad input stopping a job in one line, and the
README's resume commands after a SIGKILL."""
from __future__ import annotations

import glob
import os
import re
import shutil
import signal
import stat
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
import xarray as xr
import yaml

from conftest import REPO, snakemake, load_config
from forcenet.datasets import open_dataset, paths, validate_dataset, write_netcdf

pytestmark = pytest.mark.workflow


def test_every_netcdf_output_validates(smoke_run):
    files = sorted((smoke_run / "results").rglob("*.nc"))
    config = load_config("smoke.yaml")
    n_snapshots = len(glob.glob(paths.snapshot(smoke_run / "results", "*", "*", "*")))
    assert n_snapshots >= len(config["systems"]) * config["realizations"] * 3
    assert len(files) >= 2 * n_snapshots
    for path in files:
        validate_dataset(open_dataset(path))


def test_every_figure_and_table_exists(smoke_run):
    dry = snakemake(smoke_run, "-n", "--forceall", "--quiet", "rules")
    figure_rules = [line.split()[0] for line in dry.stdout.splitlines() if line.startswith("figure_")]
    assert figure_rules, dry.stdout
    # a figure drawn again under a reading beside lies in that reading's folder (results/readings/<reading>/figures)
    folders = [smoke_run / "results/figures", *sorted(smoke_run.glob("results/readings/*/figures"))]
    for rule in figure_rules:
        name = rule.removeprefix("figure_")
        folder = next((f for f in folders if (f / f"{name}.pdf").exists()), folders[0])
        for suffix in (".pdf", ".png"):
            path = folder / f"{name}{suffix}"
            assert path.stat().st_size > 1000, path
        table = pd.read_csv(folder / f"{name}.csv")  # the figure's source data
        assert len(table) and {"panel", "system"} <= set(table.columns), name
    tables = sorted(p.name for p in (smoke_run / "results/tables").iterdir())
    assert "p1_validation.csv" in tables and "p1_validation.md" in tables


def test_no_op_rerun_does_nothing(smoke_run):
    result = snakemake(smoke_run, "-n")
    assert "Nothing to be done" in result.stdout + result.stderr


def test_every_output_is_readable_as_the_umask_allows(smoke_run):
    """Under umask 022 every output, netCDF included, is rw-r--r-- like the figures and tables."""
    modes = {path.relative_to(smoke_run): stat.S_IMODE(path.stat().st_mode)
             for path in (smoke_run / "results").rglob("*") if path.is_file()}
    assert any(str(path).endswith(".nc") for path in modes)
    assert {path: mode for path, mode in modes.items() if mode != 0o644} == {}


def test_the_html_report_shows_every_figure_inline(smoke_run):
    """`snakemake --report`: each figure is a PNG result whose caption links its PDF, and headless Chromium draws
    every PNG (scripts/check_report.py; the rendering is skipped with a message where no Chromium is installed)."""
    sys.path.insert(0, str(REPO / "scripts"))
    import check_report

    report = smoke_run / "report.html"
    result = snakemake(smoke_run, "--report", str(report))
    assert result.returncode == 0, result.stderr[-3000:]
    results = check_report.report_results(report.read_text())
    figures = {entry["labels"]["figure"] for entry in results.values() if (entry.get("labels") or {}).get("figure")}
    assert len(figures) >= 20 and check_report.data_problems(results) == []
    chromium = check_report.find_chromium()
    if chromium is None:
        pytest.skip("no Chromium: the report's data were checked, its rendering was not (apt-get install chromium)")
    drawn = check_report.render_in_chromium(report, chromium)
    assert check_report.render_problems(drawn, results) == []
    assert len([path for path in drawn if path.endswith(".png")]) == len(figures)
    # the check can fail: a report whose PNG does not decode is caught
    broken = smoke_run / "broken_report.html"
    first = next(entry for entry in results.values() if entry["mime_type"] == "image/png")
    broken.write_text(report.read_text().replace(first["data_uri"], "data:image/png;base64,iVBORw0KGgo="))
    problems = check_report.render_problems(check_report.render_in_chromium(broken, chromium), results)
    assert len(problems) == 1 and ("drew no picture" in problems[0] or "drawn empty" in problems[0]), problems


def test_a_broken_input_stops_its_job_with_one_line(smoke_run, tmp_path):
    """Through Snakemake: an analysis file without `betti` fed to the aggregation stops it (not rc 0 and NaN)."""
    workdir = tmp_path / "copy"
    shutil.copytree(smoke_run, workdir, symlinks=True)
    target = workdir / paths.analysis("results", "2d_linear", "r00", "0.880")
    ds = open_dataset(target).drop_vars("betti")
    ds.to_netcdf(target)
    measures = paths.network_measures("results", "2d_linear")
    result = snakemake(workdir, measures, "--forcerun", "aggregate_system")
    output = result.stdout + result.stderr
    assert result.returncode != 0 and "Traceback" not in output
    relative = target.relative_to(workdir)
    lines = [line for line in output.splitlines() if f"{relative}: not a valid analysis file" in line]
    assert len(lines) == 1 and "variable 'betti' missing" in lines[0], output[-3000:]
    assert not (workdir / measures).exists()


def readme_resume_commands() -> list[list[str]]:
    """The commands of the README's resume instructions (the bash block after "**Resuming.**"), each split into its
    arguments without comments."""
    text = (REPO / "README.md").read_text()
    block = re.search(r"\*\*Resuming\.\*\*.*?```bash\n(.*?)```", text, re.S).group(1)
    return [line.split("#")[0].split() for line in block.splitlines() if line.split("#")[0].strip()]


@pytest.mark.slow
def test_the_readme_resume_instructions_work_after_sigkill(tmp_path):
    """Kill a whole `snakemake` (SIGKILL to its process group) after the first checkpoint of a run, then run what the
    README says: the lock is released and the run resumes to snapshots bit-identical to an uninterrupted run's."""
    commands = readme_resume_commands()
    assert [command[:2] for command in commands] == [[".venv/bin/snakemake", "--unlock"],
                                                     [".venv/bin/snakemake", "--cores"]]
    config = load_config("config.yaml")
    config["systems"] = {"2d_linear": config["systems"]["2d_linear"]}
    config["studies"] = {"p1": {"systems": ["2d_linear"]}}
    config["realizations"] = 1
    path = tmp_path / "one.yaml"
    path.write_text(yaml.safe_dump(config))
    grid = {"start": 0.74, "stop": 0.88, "step": 0.01}
    assert config["systems"]["2d_linear"]["rho"] == grid
    target = paths.snapshot("results", "2d_linear", "r00", "0.880")

    def run_readme_command(command, workdir, **kwargs):
        """One README command, `.venv/bin/snakemake` being this interpreter's Snakemake, in `workdir` with `config`
        (the config and target of the killed command, as the README asks)."""
        args = [sys.executable, "-m", "snakemake", *command[1:]]
        if "--unlock" not in command:
            args.insert(3, target)
        args += ["--snakefile", str(REPO / "Snakefile"), "--directory", str(workdir), "--configfile", str(path)]
        return subprocess.run(args, capture_output=True, text=True, timeout=600, **kwargs)

    reference = tmp_path / "reference"
    assert run_readme_command(commands[1], reference).returncode == 0
    killed = tmp_path / "killed"
    proc = subprocess.Popen([sys.executable, "-m", "snakemake", target, "--cores", "2", "--snakefile",
                             str(REPO / "Snakefile"), "--directory", str(killed), "--configfile", str(path)],
                            stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, start_new_session=True)
    checkpoint = paths.staging_dir(killed / target) / paths.CHECKPOINT
    deadline = time.monotonic() + 300
    while not checkpoint.exists() and time.monotonic() < deadline and proc.poll() is None:
        time.sleep(0.01)
    os.killpg(proc.pid, signal.SIGKILL)
    proc.wait()
    time.sleep(0.5)
    assert not (killed / target).exists(), "the kill should interrupt the run"
    locked = run_readme_command(commands[1], killed)  # the second command alone: the lock stops it
    assert locked.returncode != 0 and "LockException" in locked.stdout + locked.stderr
    for command in commands:
        done = run_readme_command(command, killed)
        assert done.returncode == 0, done.stderr[-3000:]
    log = (killed / paths.run_log("results", "simulate", "2d_linear", "r00")).read_text()
    assert "resuming from" in log
    run = killed / paths.run_dir("results", "2d_linear", "r00")  # the killed job's stage lock did not block it,
    assert not (run / paths.STAGE_LOCK).exists() and not (run / paths.STAGING_DIR).exists()  # and is gone with it
    for reference_file in sorted((reference / paths.run_dir("results", "2d_linear", "r00")).glob(paths.rho_file("*"))):
        resumed = killed / reference_file.relative_to(reference)
        with xr.open_dataset(reference_file) as a, xr.open_dataset(resumed) as b:
            for name in a.data_vars:
                np.testing.assert_array_equal(a[name].values, b[name].values, err_msg=f"{resumed.name}: {name}")

def test_each_study_uses_its_rattler_rule_and_p2_products_show_p2(smoke_run):
    results = smoke_run / "results"
    config = load_config("smoke.yaml")
    rules = {s: "once" for s in config["studies"]["p1"]["systems"]} | {
        s: "none" for s in config["studies"]["p2"]["systems"]}  # smoke: P1 removes rattlers, P2 keeps them
    for system, rule in rules.items():
        analysis = sorted(glob.glob(paths.analysis(results, system, "r00", "*")))[0]
        assert open_dataset(analysis).attrs["rattler_rule"] == rule, system
        assert open_dataset(paths.network_measures(results, system)).attrs["rattler_rule"] == rule, system
    for system in config["studies"]["p2"]["systems"]:
        assert open_dataset(paths.distances(results, system)).attrs["rattler_rule"] == "none"
        assert open_dataset(paths.distances(results, system)).attrs["flag_complex"] == "triangles"
    for system, spec in config["systems"].items():  # analysis.fill_tetrahedra: false (issue 25): 4-cliques hollow
        complex_ = "triangles"
        analysis = sorted(glob.glob(paths.analysis(results, system, "r00", "*")))[0]
        for path in (analysis, paths.network_measures(results, system), paths.diagrams(results, system)):
            assert open_dataset(path).attrs["flag_complex"] == complex_, (system, path)
    table1 = Path(paths.p2_table(results, 1, "md")).read_text()
    assert "(a,b), P2 | 0.089" in table1 and "ours / P2" in table1 and "rattler rule 'none'" in table1
    states = Path(paths.p2_table_states(results)).read_text().splitlines()
    assert states[0].startswith("realization,rho_a") and len(states) == 1 + config["realizations"]
    assert "mean_normal_force_a [m_mean d_ave tau_c-2]" in states[0].split(",")  # DEM runs: the reduced unit


def test_changing_fill_tetrahedra_reruns_the_3d_analyses_only(smoke_run):
    # the text edited, not re-dumped: Snakemake compares params by their text, so sorted keys would look changed
    text = (REPO / "config/smoke.yaml").read_text()
    assert "  fill_tetrahedra: false" in text
    filled = smoke_run / "filled.yaml"
    filled.write_text(text.replace("  fill_tetrahedra: false", "  fill_tetrahedra: true"))
    dry = snakemake(smoke_run, "-n", config=filled)
    assert dry.returncode == 0, dry.stderr[-3000:]
    rules = set(re.findall(r"^\s*rule (\w+):", dry.stdout, re.M))  # grouped jobs are indented
    assert "analyze_3d_hertz" in rules and "aggregate_system" in rules
    assert not {rule for rule in rules if rule.startswith(("simulate_", "analyze_2d"))}, sorted(rules)


def test_a_changed_judge_reruns_the_claim_tables_and_nothing_else(smoke_run, tmp_path):
    """common.smk's JUDGES_DIGEST: a checkout whose `src/forcenet/report/` differs (one comment added to a judge)
    plans the claim tables of the smoke build again and no analysis; the same checkout unchanged plans no table."""
    checkout = tmp_path / "checkout"
    checkout.mkdir()
    shutil.copy2(REPO / "Snakefile", checkout)
    for folder in ("workflow", "src", "config"):
        shutil.copytree(REPO / folder, checkout / folder, ignore=shutil.ignore_patterns("__pycache__"))

    def planned_rules() -> set[str]:
        command = [sys.executable, "-m", "snakemake", "-n", "--snakefile", str(checkout / "Snakefile"), "--directory",
                   str(smoke_run), "--cores", "1", "--configfile", str(REPO / "config/smoke.yaml")]
        dry = subprocess.run(command, capture_output=True, text=True, timeout=300,
                             env=dict(os.environ, PYTHONPATH=str(checkout / "src")))
        assert dry.returncode == 0, dry.stderr[-3000:]
        return set(re.findall(r"^\s*rule (\w+):", dry.stdout, re.M))

    tables = {"p1_validation_table", "p2_tables", "p2_validation"}
    unchanged = planned_rules()  # a copy elsewhere: at most the rules that record where the workflow lies
    assert not unchanged & tables and not {r for r in unchanged if r.startswith(("simulate_", "analyze_"))}, unchanged
    judge = checkout / "src/forcenet/report/p1_judging.py"
    judge.write_text(judge.read_text() + "# a changed judge\n")
    rules = planned_rules()
    assert tables <= rules, sorted(rules)
    assert not {rule for rule in rules if rule.startswith(("simulate_", "analyze_", "aggregate_"))}, sorted(rules)


def planned_jobs(workdir: Path, target: str, config: Path) -> dict[str, list[str]]:
    """{rule: inputs of its (last) job} in a dry run of `target` on `config`."""
    dry = snakemake(workdir, target, "-n", "--forceall", config=config)
    assert dry.returncode == 0, dry.stderr[-3000:]
    lines, jobs = dry.stdout.splitlines(), {}
    for index, line in enumerate(lines):
        if line.startswith("rule ") and line.rstrip().endswith(":"):
            following = lines[index + 1] if index + 1 < len(lines) else ""
            inputs = following.split("input:", 1)[1] if "input:" in following else ""
            jobs[line.split()[1].rstrip(":")] = [p.strip() for p in inputs.split(",") if p.strip()]
    return jobs


def test_the_campaign_tables_are_read_by_the_quick_build_and_written_only_at_paper_size(tmp_path):
    """docs/validation/p2.csv is an input of the quick build's P2 validation table (a regenerated campaign table
    rebuilds it) and no rule of the quick build can overwrite it; config/validation.yaml, whose tables are those
    values, writes it and does not read it."""
    campaign = tmp_path / "docs/validation/p2.csv"
    campaign.parent.mkdir(parents=True)
    shutil.copy(REPO / "docs/validation/p2.csv", campaign)
    quick = planned_jobs(tmp_path, "all", REPO / "config/smoke.yaml")
    assert "docs/validation/p2.csv" in quick["p2_validation"] and "validation_report_p2" not in quick
    paper_size = planned_jobs(tmp_path, "validation_report", REPO / "config/validation.yaml")
    assert "validation_report_p2" in paper_size
    assert not any(path.startswith("docs/") for path in paper_size["p2_validation"])


def test_each_reading_beside_is_built_with_the_other_convention_and_judged(smoke_run):
    # issue 25: the other value of fill_tetrahedra, of the never-dying convention and of the states a, b, c, each
    # built from the same runs into results/readings/ and set beside the claims it changes
    from forcenet.pipeline import readings_beside

    results = smoke_run / "results"
    config = load_config("smoke.yaml")
    readings = readings_beside(config)
    folder = {key: paths.reading(results, reading.folder) for key, reading in readings.items()}
    for system, spec in config["systems"].items():
        if spec["dimension"] == 3 and system in config["studies"]["p1"]["systems"]:
            for path in (paths.network_measures(folder["tetrahedra"], system), paths.diagrams(folder["tetrahedra"], system)):
                assert open_dataset(path).attrs["flag_complex"] == "tetrahedra", path  # smoke: hollow primary
        else:
            assert not Path(paths.network_measures(folder["tetrahedra"], system)).exists()
    for system in config["studies"]["p2"]["systems"]:
        assert open_dataset(paths.distances(folder["essential"], system)).attrs["essential_convention"] == "apart"
        assert open_dataset(paths.distances(folder["essential_drop"], system)).attrs["essential_convention"] == "drop"
        assert open_dataset(paths.distances(results, system)).attrs["essential_convention"] == "minus_one"
    # P2's Figs 6-10 drawn again from the `drop` distances (docs/validation/controls.md §3), values as those read
    from forcenet.plotting.p2 import METRIC_QUANTITY

    drop_csv = pd.read_csv(paths.figure(folder["essential_drop"], "p2_fig06_distances_normal_mu05_essential_drop", "csv"))
    bottleneck = drop_csv[(drop_csv["panel"] == 0) & (drop_csv["quantity"] == METRIC_QUANTITY["bottleneck"])]
    drop_d = open_dataset(paths.distances(folder["essential_drop"], bottleneck["system"].iloc[0]))["distance"]
    np.testing.assert_allclose(bottleneck["realization_mean"].to_numpy(), drop_d.sel(
        force_kind="normal", homology_dim=0, metric="bottleneck").mean("realization").values)
    literal = pd.read_csv(paths.p2_table_states(folder["table_states"]))
    jammed = pd.read_csv(paths.p2_table_states(results))
    assert literal["rho_b"].iloc[0] == pytest.approx(config["studies"]["p2"]["table_rho"], abs=0.011)
    assert jammed["rho_a"].iloc[0] >= config["studies"]["p2"]["table_rho"] - 1e-9
    assert "rho_a = %.4f" % literal["rho_a"].iloc[0] in Path(paths.p2_table(folder["table_states"], 1, "md")).read_text()
    table = pd.read_csv(paths.p2_validation_table(results, "csv"), comment="#", keep_default_na=False)
    assert {readings["essential"].label, readings["table_states"].label, readings["essential_drop"].label} <= set(
        table["reading"])
    # apart: a pair whose numbers of never-dying classes differ is infinitely far apart, printed so
    assert "inf" in Path(paths.p2_table(folder["essential"], 1, "md")).read_text()


def test_the_subset_table_script_judges_a_builds_systems_as_its_table_job_does(smoke_run, tmp_path):
    # scripts/p1_subset_table.py (checking part of a campaign): the build's own rows for the systems it is given;
    # a system left out has its rows "not evaluated" or none
    results = smoke_run / "results"
    built = pd.read_csv(paths.p1_validation_table(results, "csv"), comment="#", keep_default_na=False)
    built = built[built["reading"] == ""]
    key = ["kind", "id", "system"]
    def subset_table(systems, counts, csv):
        return subprocess.run([sys.executable, str(REPO / "scripts/p1_subset_table.py"), "--results", str(results),
                               "--systems", *systems, "--realizations", *counts, "--csv", str(csv),
                               "--md", str(tmp_path / "t.md")], capture_output=True, text=True)

    # the counts per system as config/validation.yaml gives them (one for all, SYSTEM=N for one); none is a usage error
    refused = subset_table(["2d_linear", "3d_hertz"], ["3d_hertz=1"], tmp_path / "refused.csv")
    assert refused.returncode == 2 and "no count for 2d_linear" in refused.stderr
    # SYSTEM=N overrides the common count: the build has one run per system, so asking 3d_hertz for two names its r01
    too_many = subset_table(["2d_linear", "3d_hertz"], ["1", "3d_hertz=2"], tmp_path / "too_many.csv")
    assert too_many.returncode == 2 and "3d_hertz/r01: no snapshot" in too_many.stderr
    for systems, counts in ((["2d_linear", "2d_hertz", "3d_hertz"], ["1", "3d_hertz=1"]),
                            (["2d_linear", "2d_hertz"], ["2d_linear=1", "2d_hertz=1"])):
        csv = tmp_path / f"{len(systems)}.csv"
        run = subset_table(systems, counts, csv)
        assert run.returncode == 0, run.stderr
        subset = pd.read_csv(csv, comment="#", keep_default_na=False)
        merged = built.merge(subset[subset["reading"] == ""], on=key, how="left", suffixes=("_built", "_subset"))
        judged = merged[merged["verdict_subset"].notna() & (merged["verdict_subset"] != "not evaluated")]
        pd.testing.assert_series_equal(judged["measured_built"], judged["measured_subset"], check_names=False)
        pd.testing.assert_series_equal(judged["verdict_built"], judged["verdict_subset"], check_names=False)
        left_out = merged[merged["system"] == "3d_hertz"]
        if "3d_hertz" in systems:
            assert len(judged) == (built["verdict"] != "not evaluated").sum()
        else:
            assert (left_out["verdict_subset"].isna() | (left_out["verdict_subset"] == "not evaluated")).all()
            assert (left_out["verdict_built"].isin(["holds", "does not hold"])).any()
            assert judged["system"].isin(["2d_linear", "2d_hertz", "all"]).all() and len(judged) >= 10


def test_the_subset_table_script_judges_the_first_realizations_of_a_larger_aggregate(smoke_run, tmp_path):
    # five runs on disk read as the first three were: an aggregate with more realizations than --realizations
    # asks is cut to its first N (measures and diagram points), so the table is that of the N alone
    results = smoke_run / "results"
    aggregates = tmp_path / "aggregates"
    for system in ("2d_linear", "2d_hertz"):
        with xr.open_dataset(paths.network_measures(results, system)) as ds, \
                xr.open_dataset(paths.diagrams(results, system)) as diagrams:
            measures, points = ds.load(), diagrams.load()
        # a second realization whose networks differ everywhere: judged with it, the table would change
        other = measures.assign_coords(realization=measures["realization"].copy(data=[1]))
        other["betti"] = 3 * other["betti"] + 7
        other["Z"] = other["Z"] + 1.0
        moved = points.copy()
        moved["point_realization"] = xr.full_like(points["point_realization"], 1)
        write_netcdf(xr.concat([measures, other], dim="realization"), paths.network_measures(aggregates, system),
                     "network_measures")
        write_netcdf(xr.concat([points, moved], dim="point"), paths.diagrams(aggregates, system), "diagrams")
        write_netcdf(other, paths.network_measures(tmp_path / "second_only", system), "network_measures")
        write_netcdf(moved, paths.diagrams(tmp_path / "second_only", system), "diagrams")

    def subset_table(folder, csv):
        return subprocess.run([sys.executable, str(REPO / "scripts/p1_subset_table.py"), "--results", str(results),
                               "--aggregates", str(folder), "--systems", "2d_linear", "2d_hertz",
                               "--realizations", "1", "--csv", str(csv), "--md", str(tmp_path / "t.md")],
                              capture_output=True, text=True)

    whole, cut = tmp_path / "whole.csv", tmp_path / "cut.csv"
    assert subset_table(results, whole).returncode == 0
    run = subset_table(aggregates, cut)
    assert run.returncode == 0, run.stderr
    columns = ["id", "system", "reading", "measured", "verdict", "robustness"]
    read = lambda path: pd.read_csv(path, comment="#", keep_default_na=False)[columns]
    pd.testing.assert_frame_equal(read(cut), read(whole))
    refused = subset_table(tmp_path / "second_only", tmp_path / "refused.csv")
    assert refused.returncode == 2 and "holds realizations [1], not [0]" in refused.stderr
    assert not (tmp_path / "refused.csv").exists()
