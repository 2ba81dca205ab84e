"""forcenet.datasets.paths, the one definition of every file a build writes: each function gives the documented path
of a hand-written example, a Snakemake wildcard pattern formats to the concrete path the scripts use, the module
loads without numpy or xarray (the workflow imports it at parse time), and a smoke dry run plans exactly the files
the module lists for its config — no rule writes a path defined elsewhere."""
from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

from conftest import load_config, snakemake
from forcenet.checks import validate_config
from forcenet.datasets import paths
from forcenet.pipeline import readings_beside
from forcenet.plotting.registry import FIGURES

#: (function, arguments, the path the docstring of forcenet.datasets.paths documents)
EXAMPLES = [
    (paths.resolved_config, ("results",), "results/config/resolved.yaml"),
    (paths.snapshot, ("results", "2d_hertz", "r01", "0.840"), "results/sim/2d_hertz/r01/rho0.840.nc"),
    (paths.run_cost, ("results", "2d_hertz", "r01"), "results/sim/2d_hertz/r01/run_cost.json"),
    (paths.run_dir, ("results", "3d_hertz", "r00"), "results/sim/3d_hertz/r00"),
    (paths.analysis, ("results", "2d_hertz", "r01", "0.840"), "results/analysis/2d_hertz/r01/rho0.840.nc"),
    (paths.network_measures, ("results", "2d_linear"), "results/2d_linear/network_measures.nc"),
    (paths.diagrams, ("results", "2d_linear"), "results/2d_linear/diagrams.nc"),
    (paths.distances, ("results", "2d_poly_mu05"), "results/2d_poly_mu05/distances.nc"),
    (paths.figure, ("results", "p1_fig06_betti0", "png"), "results/figures/p1_fig06_betti0.png"),
    (paths.p1_validation_table, ("results", "md"), "results/tables/p1_validation.md"),
    (paths.p2_table, ("results", 2, "csv"), "results/tables/p2_table2.csv"),
    (paths.p2_table_states, ("results",), "results/tables/p2_table_states.csv"),
    (paths.p2_validation_table, ("results", "csv"), "results/tables/p2_validation.csv"),
    (paths.movie, ("results", paths.movie_name("b0_surface", "3d_hertz")), "results/movies/b0_surface_3d_hertz.mp4"),
    (paths.log, ("results", "aggregate", "2d_linear"), "results/logs/aggregate/2d_linear.log"),
    (paths.log, ("results", "", "resolved_config"), "results/logs/resolved_config.log"),
    (paths.run_log, ("results", "simulate", "2d_linear", "r00"), "results/logs/simulate/2d_linear/r00.log"),
    (paths.campaign_table, ("p2", "csv"), "docs/validation/p2.csv"),
]


@pytest.mark.parametrize("function, args, expected", EXAMPLES, ids=[f"{f.__name__}:{e}" for f, _, e in EXAMPLES])
def test_each_path_is_the_documented_one(function, args, expected):
    assert function(*args) == expected
    if args and args[0] == "results":  # another results folder, given as a Path, moves the whole path
        assert function(Path("/tmp/run"), *args[1:]) == "/tmp/run" + expected[len("results"):]


#: each function with symbolic arguments: the line of the module docstring's layout it must give
SYMBOLIC = [
    (paths.resolved_config, ()), (paths.snapshot, ("{system}", "{realization}", "{ρ}")),
    (paths.run_cost, ("{system}", "{realization}")), (paths.analysis, ("{system}", "{realization}", "{ρ}")),
    (paths.network_measures, ("{system}",)), (paths.diagrams, ("{system}",)), (paths.distances, ("{system}",)),
    (paths.p2_run, ("{system}", "{realization}")), (paths.figure, ("{figure}", "{pdf,png,csv}")), (paths.p1_validation_table, ("{csv,md}",)),
    (paths.p2_table, ("{1,2,3}", "{csv,md}")), (paths.p2_table_states, ()), (paths.p2_validation_table, ("{csv,md}",)),
    (paths.skipped_products, ()),
    (paths.movie, (paths.movie_name("{kind}", "{system}"),)), (paths.log, ("{step}", "{name}")),
    (paths.reading, ("{reading}",)),
]


def test_the_documented_layout_is_what_the_functions_give():
    """Every line of the layout in the module docstring is what its function gives (the docs cannot drift)."""
    results_doc, _, records_doc = paths.__doc__.partition("``records_dir``")
    layout, records_layout = ({line.split()[0] for line in doc.splitlines() if line.startswith("    ") and line.strip()}
                              for doc in (results_doc, records_doc))
    given = {function("results", *args).removeprefix("results/") for function, args in SYMBOLIC}
    given.add(str(paths.staging_dir(paths.snapshot("results", "{system}", "{realization}", "{ρ}")))
              .removeprefix("results/") + "/")
    assert given == layout
    assert records_layout == {paths.record_manifest("records").removeprefix("records/"),
                              paths.record_file("records", "{system}", "{realization}").removeprefix("records/"),
                              paths.p2_record_file("records", "{system}", "{realization}").removeprefix("records/")}
    assert f"``{paths.campaign_table('{p1,p2}', '{md,csv}')}``" in paths.__doc__


def test_a_wildcard_pattern_formats_to_the_concrete_path():
    """A rule declares `snapshot(RESULTS, name, "{realization}", ρ)`; the script of its job reads the path Snakemake
    fills in: both must be the same string."""
    wildcards = {"system": "2d_hertz", "realization": "r03"}
    for function, args in [(paths.snapshot, ("{system}", "{realization}", "0.800")),
                           (paths.analysis, ("{system}", "{realization}", "0.800")),
                           (paths.run_cost, ("{system}", "{realization}")),
                           (paths.network_measures, ("{system}",)), (paths.diagrams, ("{system}",)),
                           (paths.distances, ("{system}",)), (paths.log, ("aggregate", "{system}")),
                           (paths.run_log, ("analyze", "{system}", "{realization}"))]:
        pattern = function("results", *args)
        assert "{system}" in pattern
        concrete = function("results", *[a.format(**wildcards) for a in args])
        assert pattern.format(**wildcards) == concrete


def test_names_of_realizations_and_states():
    assert [paths.realization_name(i) for i in (0, 7, 12)] == ["r00", "r07", "r12"]
    assert [paths.realization_index(paths.realization_name(i)) for i in (0, 7, 12, 123)] == [0, 7, 12, 123]
    assert paths.rho_file("0.842") == "rho0.842.nc"
    # the run in progress is staged beside its snapshots, where pipeline.simulate looks for the checkpoint
    staged = paths.staging_dir(paths.snapshot("results", "2d_hertz", "r00", "0.800")) / paths.CHECKPOINT
    assert staged == Path("results/sim/2d_hertz/r00/.partial/checkpoint.npz")


def test_the_module_loads_without_numpy_or_xarray():
    """The workflow imports it when it is parsed (thousands of jobs in a dry run): standard library only."""
    code = ("import sys; import forcenet.datasets.paths; "
            "print(sorted({'numpy', 'xarray', 'numba', 'pandas'} & set(sys.modules)))")
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert done.stdout.strip() == "[]"


def expected_smoke_outputs(results: str = "results") -> set[str]:
    """Every file a full smoke build writes, from this module and the smoke config alone."""
    config = load_config("smoke.yaml")
    specs = validate_config(config)
    p1, p2 = config["studies"]["p1"]["systems"], config["studies"]["p2"]["systems"]
    realizations = [paths.realization_name(r) for r in range(config["realizations"])]
    files = {paths.resolved_config(results), paths.log(results, "", "resolved_config")}
    for system, spec in specs.items():
        for r in realizations:
            files |= {paths.run_cost(results, system, r), paths.run_log(results, "simulate", system, r),
                      paths.run_log(results, "analyze", system, r)}
            files |= {f(results, system, r, rho) for f in (paths.snapshot, paths.analysis) for rho in spec.rho_labels}
        files |= {paths.network_measures(results, system), paths.diagrams(results, system),
                  paths.log(results, "aggregate", system)}
    for system in p2:
        files |= {paths.distances(results, system), paths.log(results, "distances", system)}
        for r in realizations:  # each run's summary (what P2's products read)
            files |= {paths.p2_run(results, system, r), paths.run_log(results, "p2_run", system, r)}
    for entry in FIGURES:  # the smoke config has both studies and both P2 systems: every figure
        files |= {paths.figure(results, entry.id, fmt) for fmt in paths.FIGURE_FORMATS}
        files.add(paths.log(results, "figures", entry.id))
    for system in p1:
        for kind in ("network", "b0_surface"):
            name = paths.movie_name(kind, system)
            files |= {paths.movie(results, name), paths.log(results, "movies", name)}
    files |= {paths.p1_validation_table(results, fmt) for fmt in ("csv", "md")}
    files |= {paths.p2_validation_table(results, fmt) for fmt in ("csv", "md")}
    files |= {paths.p2_table(results, i, fmt) for i in paths.P2_TABLE_NUMBERS for fmt in ("csv", "md")}
    files.add(paths.p2_table_states(results))
    files |= {paths.log(results, "tables", name) for name in ("p1_validation", "p2_tables", "p2_table_states",
                                                                  "p2_validation")}
    # the readings beside (forcenet.pipeline.readings_beside), each a results folder of its own
    reading = {key: paths.reading(results, value.folder) for key, value in readings_beside(config).items()}
    for system, spec in specs.items():
        if system in p1 and spec.dimension == 3:  # the 3D P1 systems analysed with the other complex
            folder = reading["tetrahedra"]
            for r in realizations:
                files.add(paths.run_log(folder, "analyze", system, r))
                files |= {paths.analysis(folder, system, r, rho) for rho in spec.rho_labels}
            files |= {paths.network_measures(folder, system), paths.diagrams(folder, system),
                      paths.log(folder, "aggregate", system)}
    for system in p2:  # P2's distances under the other never-dying conventions
        for key in ("essential", "essential_drop"):  # never-dying classes apart, and left out
            files |= {paths.distances(reading[key], system), paths.log(reading[key], "distances", system)}
    for entry in FIGURES:  # P2's distance figures (Figs 6-10) again under `drop` (docs/validation/controls.md §3)
        if entry.study == "p2" and entry.inputs == ("distances",):
            drawn = f"{entry.id}_essential_drop"  # named apart: the HTML report links a PDF by its file name
            files |= {paths.figure(reading["essential_drop"], drawn, fmt) for fmt in paths.FIGURE_FORMATS}
            files.add(paths.log(reading["essential_drop"], "figures", drawn))
    for key in ("essential", "essential_drop", "table_states"):  # Tables I-III under each, and from other a, b, c
        files |= {paths.p2_table(reading[key], i, fmt) for i in paths.P2_TABLE_NUMBERS for fmt in ("csv", "md")}
        files.add(paths.log(reading[key], "tables", "p2_tables"))
    files |= {paths.p2_table_states(reading["table_states"]), paths.log(reading["table_states"], "tables",
                                                                         "p2_table_states")}
    return files


def planned_files(workdir: Path) -> set[str]:
    """Every output and log of every job of a forced dry run of the smoke build."""
    dry = snakemake(workdir, "all", "-n", "--forceall")
    assert dry.returncode == 0, dry.stderr[-3000:]
    return {path.strip() for line in dry.stdout.splitlines() for field in ("output:", "log:")
            if line.strip().startswith(field) for path in line.split(field, 1)[1].split(",")}


def test_the_smoke_build_writes_exactly_the_files_this_module_lists(tmp_path):
    planned, expected = planned_files(tmp_path), expected_smoke_outputs()
    assert not planned - expected, f"written by a rule but not listed from paths: {sorted(planned - expected)}"
    assert not expected - planned, f"listed from paths but not written: {sorted(expected - planned)}"

