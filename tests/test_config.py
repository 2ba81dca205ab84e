"""Config validation: the JSON schema plus forcenet.systems, and the workflow refusing bad configs."""
from __future__ import annotations

import copy
import re
import shutil
import subprocess
import sys
from pathlib import Path

import jsonschema
import pytest
import yaml

from conftest import REPO, load_config
from forcenet.checks import validate_config
from forcenet.datasets.runs import simulation_params
from forcenet.pipeline import snapshot_analysis_params
from forcenet.systems import ConfigError, realization_indices, realization_seed, rho_grid, study_rattler_rule

SCHEMA = yaml.safe_load((REPO / "workflow/schemas/config.schema.yaml").read_text())
CONFIGS = ["config.yaml", "paper.yaml", "smoke.yaml"]


def schema_errors(config):
    validator = jsonschema.Draft202012Validator(SCHEMA)
    return [".".join(str(p) for p in e.absolute_path) + ": " + e.message for e in validator.iter_errors(config)]


@pytest.mark.parametrize("name", CONFIGS)
def test_shipped_configs_are_valid(name):
    config = load_config(name)
    assert schema_errors(config) == []
    systems = validate_config(config)
    assert set(systems) == set(config["systems"])
    for spec in systems.values():
        assert len(spec.rho_grid) >= 1


def _mutate(path, value, config=None):
    config = copy.deepcopy(config or load_config())
    *parents, last = path
    node = config
    for key in parents:
        node = node[key]
    if value is KeyError:
        del node[last]
    else:
        node[last] = value
    return config


BAD_CONFIGS = {
    "wrong_type": (["systems", "2d_hertz", "box_length"], "big", "box_length"),
    "unknown_key": (["systems", "2d_hertz", "frction"], 0.5, "frction"),
    "missing_key": (["systems", "2d_hertz", "friction"], KeyError, "friction"),
    "negative_count": (["realizations"], -2, "realizations"),
    "empty_rho_list": (["systems", "2d_hertz", "rho"], [], "rho"),
    "unknown_force_law": (["systems", "3d_hertz", "force_law"], "hooke", "force_law"),
    "unknown_damping_model": (["systems", "3d_hertz", "damping_model"], "implicit", "damping_model"),
    "missing_damping_model": (["systems", "2d_linear", "damping_model"], KeyError, "damping_model"),
    "explicit_damping_without_value": (["systems", "2d_linear", "damping_model"], "explicit", "normal_damping"),
    "box_lattice_without_sites": (["systems", "2d_linear", "initial_state"], {"lattice": "box"}, "sites_per_axis"),
    "unknown_lattice": (["systems", "2d_linear", "initial_state"], {"lattice": "hexagonal"}, "initial_state"),
    "unknown_p1_force_unit": (["analysis", "p1_force_unit"], "newton", "p1_force_unit"),
    "missing_p1_force_unit": (["analysis", "p1_force_unit"], KeyError, "p1_force_unit"),
    "string_fill_tetrahedra": (["analysis", "fill_tetrahedra"], "no", "fill_tetrahedra"),
    "numeric_fill_tetrahedra": (["analysis", "fill_tetrahedra"], 0, "fill_tetrahedra"),
    "missing_fill_tetrahedra": (["analysis", "fill_tetrahedra"], KeyError, "fill_tetrahedra"),
}


@pytest.mark.parametrize("case", sorted(BAD_CONFIGS))
def test_schema_rejects_bad_config_naming_key(case):
    path, value, key = BAD_CONFIGS[case]
    errors = schema_errors(_mutate(path, value))
    assert errors, case
    assert any(key in e for e in errors), errors


def test_semantic_errors_name_the_key(default_config):
    config = _mutate(["studies", "p1", "systems"], ["2d_hertz", "4d_magic"], default_config)
    with pytest.raises(ConfigError, match=r"studies\.p1\.systems\[1\]"):
        validate_config(config)
    config = _mutate(["systems", "2d_hertz", "rho"], {"start": 0.9, "stop": 0.8, "step": 0.02}, default_config)
    with pytest.raises(ConfigError, match=r"systems\.2d_hertz\.rho"):
        validate_config(config)
    config = _mutate(["systems", "2d_hertz", "time_step"], 0.5, default_config)
    with pytest.raises(ConfigError, match=r"systems\.2d_hertz\.time_step"):
        validate_config(config)
    config = _mutate(["systems", "2d_linear", "normal_damping"], 5.0, default_config)
    with pytest.raises(ConfigError, match=r"systems\.2d_linear\.normal_damping.*only with damping_model: explicit"):
        validate_config(config)


def test_walls_of_their_own_material(default_config):
    """`wall_material` (P1 §2: plexiglass) gives the wall factor of the two-material modulus and a new simulation
    fingerprint; it needs flat walls and the material block; a system without it keeps its fingerprint."""
    from forcenet import units
    from forcenet.datasets.runs import simulation_sha256
    from forcenet.systems import material_from_config, system_from_config

    plexiglass = {"young_modulus": 3.0e9, "poisson_ratio": 0.35}
    config = _mutate(["systems", "2d_hertz", "wall_material"], plexiglass, default_config)
    assert schema_errors(config) == []
    validate_config(config)
    expected = units.wall_stiffness_factor(material_from_config(config), 3.0e9, 0.35)
    assert system_from_config("2d_hertz", config).wall_stiffness_factor == expected
    assert system_from_config("2d_hertz", default_config).wall_stiffness_factor == 1.0
    assert simulation_sha256(config, "2d_hertz") != simulation_sha256(default_config, "2d_hertz")
    assert simulation_sha256(config, "2d_linear") == simulation_sha256(default_config, "2d_linear")
    rough = _mutate(["systems", "2d_poly_mu05", "wall_material"], plexiglass, default_config)
    with pytest.raises(ConfigError, match=r"systems\.2d_poly_mu05\.wall_material.*walls: flat"):
        validate_config(rough)
    assert schema_errors(_mutate(["systems", "2d_hertz", "wall_material"], {"young_modulus": 3.0e9}, default_config))
    assert schema_errors(_mutate(["systems", "2d_hertz", "wall_material"], dict(plexiglass, poisson_ratio=0.5),
                                 default_config))


def test_rattler_rule_is_chosen_per_study(default_config):
    # shipped: P1 removes rattlers (analysis.remove_rattlers), P2 keeps them (studies.p2.remove_rattlers: false)
    assert {s: study_rattler_rule(default_config, s) for s in default_config["studies"]["p1"]["systems"]} == {
        "2d_linear": "once", "2d_hertz": "once", "3d_hertz": "once"}
    assert {s: study_rattler_rule(default_config, s) for s in default_config["studies"]["p2"]["systems"]} == {
        "2d_poly_mu05": "none", "2d_poly_mu0": "none"}
    assert snapshot_analysis_params(default_config, "2d_poly_mu0")["remove_rattlers"] == "none"
    assert snapshot_analysis_params(default_config, "2d_hertz")["remove_rattlers"] == "once"
    # a study without the key uses analysis.remove_rattlers; a system in no study too
    config = _mutate(["studies", "p2", "remove_rattlers"], KeyError, default_config)
    assert study_rattler_rule(config, "2d_poly_mu05") == "once"
    config = _mutate(["studies", "p2", "systems"], ["2d_poly_mu05"], default_config)
    config["analysis"]["remove_rattlers"] = "iterative"
    assert study_rattler_rule(config, "2d_poly_mu0") == "iterative"


@pytest.mark.parametrize("name", CONFIGS + ["validation.yaml"])
def test_shipped_configs_leave_tetrahedra_hollow(name):
    # the convention of docs/decisions.md (issue 25): P1 §5.1's B2 ("vanishes below rho_J, grows beyond") has
    # content only when each 4-clique is a void; the filled reading is judged beside it
    assert load_config(name)["analysis"]["fill_tetrahedra"] is False


def test_realizations_are_one_count_or_one_per_system(default_config):
    per_system = {name: 2 for name in default_config["systems"]}
    per_system["3d_hertz"] = 1
    config = _mutate(["realizations"], per_system, default_config)
    assert schema_errors(config) == []
    validate_config(config)
    assert realization_indices(config, "2d_hertz") == [0, 1] and realization_indices(config, "3d_hertz") == [0]
    assert realization_indices(default_config, "3d_hertz") == list(range(default_config["realizations"]))
    # raising a count adds realizations: the existing ones keep their index, name and seed (no run restarts)
    raised = _mutate(["realizations", "3d_hertz"], 3, config)
    assert realization_indices(raised, "3d_hertz")[:1] == realization_indices(config, "3d_hertz")
    assert realization_seed(raised["seed"], "3d_hertz", 0) == realization_seed(config["seed"], "3d_hertz", 0)
    assert simulation_params(raised, "3d_hertz") == simulation_params(config, "3d_hertz")
    # a mapping names every system, and only systems
    with pytest.raises(ConfigError, match=r"realizations\.nope"):
        validate_config(_mutate(["realizations", "nope"], 2, config))
    missing = dict(per_system)
    del missing["2d_hertz"]
    with pytest.raises(ConfigError, match=r"realizations.*2d_hertz"):
        validate_config(_mutate(["realizations"], missing, default_config))
    assert schema_errors(_mutate(["realizations", "2d_hertz"], 0, config))  # at least one realization
    assert schema_errors(_mutate(["realizations"], "five", default_config))


@pytest.mark.parametrize("fill", [True, False])
def test_fill_tetrahedra_reaches_only_the_3d_analyses(default_config, fill):
    config = _mutate(["analysis", "fill_tetrahedra"], fill, default_config)
    assert schema_errors(config) == []
    assert snapshot_analysis_params(config, "3d_hertz")["fill_tetrahedra"] is fill
    # a 2D complex has no tetrahedra either way: its analysis params (Snakemake's rerun key) do not change
    for system in ("2d_hertz", "2d_poly_mu0"):
        assert snapshot_analysis_params(config, system) == snapshot_analysis_params(default_config, system)


def test_a_system_in_two_studies_with_different_rattler_rules_is_refused(default_config):
    config = _mutate(["studies", "p1", "systems"], ["2d_linear", "2d_poly_mu05"], default_config)
    with pytest.raises(ConfigError, match=r"studies\.p2\.remove_rattlers|analysis\.remove_rattlers"):
        validate_config(config)
    config["studies"]["p1"]["remove_rattlers"] = False  # both keep rattlers: one analysis serves both
    assert study_rattler_rule(config, "2d_poly_mu05") == "none"
    assert schema_errors(_mutate(["studies", "p2", "remove_rattlers"], "sometimes", default_config))


def test_rho_grid_forms():
    assert rho_grid({"start": 0.80, "stop": 0.86, "step": 0.02}, "k") == (0.80, 0.82, 0.84, 0.86)
    assert rho_grid({"start": 0.63, "stop": 0.90, "count": 4}, "k") == (0.63, 0.72, 0.81, 0.90)
    assert rho_grid([0.5, 0.6], "k") == (0.5, 0.6)
    with pytest.raises(ConfigError):
        rho_grid([0.6, 0.5], "k")


def _snakemake(*args, cwd=REPO):
    return subprocess.run([sys.executable, "-m", "snakemake", *args], cwd=cwd, capture_output=True, text=True,
                          timeout=300)


@pytest.mark.parametrize("name", CONFIGS)
def test_dry_run_works_on_every_shipped_config(name):
    result = _snakemake("-n", "--cores", "2", "--configfile", f"config/{name}")
    assert result.returncode == 0, result.stdout[-3000:] + result.stderr[-3000:]


@pytest.mark.parametrize("case,key", [("unknown_key", "frction"), ("negative_count", "realizations"),
                                      ("empty_rho_list", "rho"), ("unknown_system", "studies.p2.systems")])
def test_workflow_stops_before_any_job_naming_the_key(tmp_path: Path, case, key):
    if case == "unknown_system":
        config = _mutate(["studies", "p2", "systems"], ["2d_poly_mu05", "nope"])
    else:
        path, value, _ = BAD_CONFIGS[case]
        config = _mutate(path, value)
    bad = tmp_path / "bad.yaml"
    bad.write_text(yaml.safe_dump(config))
    result = _snakemake("--cores", "1", "--configfile", str(bad), "--directory", str(tmp_path / "work"),
                        "--snakefile", str(REPO / "Snakefile"))
    assert result.returncode != 0
    output = result.stdout + result.stderr
    assert key in output, output[-3000:]
    assert not (tmp_path / "work" / "results").exists(), "a job ran despite the invalid config"


# --- a --configfile stands alone; every bad input is one readable line before any job ------------------------------
def _dry_run_jobs(result) -> dict[str, int]:
    """{rule: count} from the job-stats table of a dry run."""
    jobs, table = {}, False
    for line in result.stdout.splitlines():
        parts = line.split()
        if parts[:2] == ["job", "count"]:
            table = True
        elif table and len(parts) == 2 and parts[1].isdigit() and parts[0] != "total":
            jobs[parts[0]] = int(parts[1])
        elif table and parts[:1] == ["total"]:
            break
    return jobs


def test_a_configfile_stands_alone(tmp_path: Path):
    """A complete config with one system, its ρ grid as {start, stop, count}, only P1: it validates (the default's
    `step` is not merged in) and builds that system alone. Without --configfile the default builds all five."""
    config = load_config("smoke.yaml")
    config["systems"] = {"2d_linear": config["systems"]["2d_linear"]}
    config["systems"]["2d_linear"]["rho"] = {"start": 0.8, "stop": 0.88, "count": 3}
    config["studies"] = {"p1": {"systems": ["2d_linear"]}}
    path = tmp_path / "one.yaml"
    path.write_text(yaml.safe_dump(config))
    result = _snakemake("-n", "--cores", "1", "--configfile", str(path), "--directory", str(tmp_path / "work"),
                        "--snakefile", str(REPO / "Snakefile"))
    assert result.returncode == 0, result.stdout[-3000:] + result.stderr[-3000:]
    jobs = _dry_run_jobs(result)
    assert jobs["simulate_2d_linear"] == 1 and jobs["analyze_2d_linear"] == 1
    assert not [rule for rule in jobs if rule.startswith(("p2_", "simulate_2d_hertz", "simulate_3d", "simulate_2d_poly"))]
    default = _dry_run_jobs(_snakemake("-n", "--cores", "1", "--directory", str(tmp_path / "work"),
                                       "--snakefile", str(REPO / "Snakefile")))
    assert {f"simulate_{name}" for name in load_config()["systems"]} <= set(default)


def _one_line_failure(result, *needles: str) -> str:
    """The run failed before any job with one readable message containing every needle: no traceback, no schema
    or config dump."""
    output = result.stdout + result.stderr
    assert result.returncode != 0
    assert "Traceback" not in output and len(output) < 1500, output[-3000:]
    lines = [line for line in output.splitlines() if all(needle in line for needle in needles)]
    assert len(lines) == 1, output
    return lines[0]


PHYSICAL_CASES = {
    # (path, value, key named, words of the message)
    "rho_2d_above_close_packing": (["systems", "2d_linear", "rho"], [0.8, 0.9, 0.92], "systems.2d_linear.rho",
                                   "the last ρ = 0.92 is above 0.9105, the densest packing of equal disks"),
    "rho_3d_above_close_packing": (["systems", "3d_hertz", "rho"], {"start": 0.5, "stop": 0.76, "step": 0.02},
                                   "systems.3d_hertz.rho", "the last ρ = 0.76 is at or above the densest packing"),
    "rho_3d_at_densest_packing": (["systems", "3d_hertz", "rho"], [0.6, 0.7, 0.74], "systems.3d_hertz.rho",
                                  "the last ρ = 0.74 is at or above the densest packing of equal spheres"),
    "rho_nan": (["systems", "2d_linear", "rho"], [0.8, float("nan")], "systems.2d_linear.rho[1]",
                "is nan, not a finite number"),
    "p2_two_snapshots": (["systems", "2d_poly_mu05", "rho"], [0.7, 0.8], "systems.2d_poly_mu05.rho",
                         "has 2 snapshot(s), but a system of study p2 needs at least 3"),
    "results_dir_outside": (["results_dir"], "results/../../escape", "results_dir",
                            "which is not a folder inside the working directory"),
    "rho_below_the_lattice": (["systems", "2d_hertz", "rho"], [0.3, 0.8], "systems.2d_hertz.rho", "initial lattice"),
    "time_step_above_the_collision": (["systems", "2d_hertz", "time_step"], 0.05, "systems.2d_hertz.time_step",
                                      "shortest collision"),
    "unknown_key": (["systems", "2d_hertz", "frction"], 0.5, "systems.2d_hertz", "'frction' was unexpected"),
}


@pytest.mark.parametrize("case", sorted(PHYSICAL_CASES))
def test_bad_config_is_one_line_naming_the_key_before_any_job(tmp_path: Path, case):
    path, value, key, words = PHYSICAL_CASES[case]
    bad = tmp_path / "bad.yaml"
    bad.write_text(yaml.safe_dump(_mutate(path, value, load_config("smoke.yaml"))))
    result = _snakemake("-n", "--cores", "1", "--configfile", str(bad), "--directory", str(tmp_path / "work"),
                        "--snakefile", str(REPO / "Snakefile"))
    _one_line_failure(result, key, words)
    assert not (tmp_path / "work" / "results").exists()


def test_yaml_error_in_the_default_config_names_file_and_line(tmp_path: Path):
    """The default config is read by the workflow: a syntax error names the file and line. (A --configfile is read by
    Snakemake before the workflow, which reports no line: forcenet-check-config does.)"""
    for part in ("Snakefile", "workflow", "config"):
        source = REPO / part
        (shutil.copytree if source.is_dir() else shutil.copy)(source, tmp_path / part)
    text = (tmp_path / "config/config.yaml").read_text().splitlines()
    line = next(i for i, row in enumerate(text) if row.startswith("realizations:"))
    text[line] = "realizations: 3: 4"  # a mapping value where none may be: YAML stops on this line
    (tmp_path / "config/config.yaml").write_text("\n".join(text) + "\n")
    result = _snakemake("-n", "--cores", "1", cwd=tmp_path)
    message = _one_line_failure(result, "config/config.yaml")
    assert re.search(rf"line {line + 1}, column \d+: not valid YAML", message), message
    checked = subprocess.run([sys.executable, "-m", "forcenet.workflow_io", str(tmp_path / "config/config.yaml")],
                             capture_output=True, text=True)
    assert checked.returncode == 1 and f"line {line + 1}" in checked.stderr
    good = subprocess.run([sys.executable, "-m", "forcenet.workflow_io", str(REPO / "config/smoke.yaml")],
                          capture_output=True, text=True)
    assert good.returncode == 0 and "valid (5 systems" in good.stdout


def test_check_config_names_a_non_boolean_fill_tetrahedra(tmp_path: Path, capsys):
    # a quoted "false" is a string, not YAML's false: refused naming the key, not read as true
    from forcenet.workflow_io import check_config_main

    text = (REPO / "config/smoke.yaml").read_text()
    assert "  fill_tetrahedra: false" in text
    bad = tmp_path / "bad.yaml"
    bad.write_text(text.replace("  fill_tetrahedra: false", '  fill_tetrahedra: "false"'))
    assert check_config_main([str(bad)]) == 1
    error = capsys.readouterr().err
    assert "analysis.fill_tetrahedra" in error and "boolean" in error, error
    good = tmp_path / "good.yaml"
    good.write_text(text.replace("  fill_tetrahedra: false", "  fill_tetrahedra: true"))  # a YAML boolean either way
    assert check_config_main([str(good)]) == 0


# --- NaN and infinities, keys given twice, results_dir, P2's three states, what Snakemake reports first -------------
NAN, INF = float("nan"), float("inf")
NON_FINITE_CASES = {
    # (path, non-finite value, finite value, key named, the value as the message shows it): every kind of place a
    # number sits in a config
    "rho_list": (["systems", "2d_linear", "rho"], [0.8, NAN], [0.8, 0.85], "systems.2d_linear.rho[1]", "nan"),
    "rho_range_stop": (["systems", "2d_hertz", "rho", "stop"], NAN, 0.85, "systems.2d_hertz.rho.stop", "nan"),
    "rho_range_step": (["systems", "2d_hertz", "rho", "step"], INF, 0.02, "systems.2d_hertz.rho.step", "inf"),
    "relaxation_tolerance": (["systems", "3d_hertz", "relaxation", "tolerance"], NAN, 0.2,
                             "systems.3d_hertz.relaxation.tolerance", "nan"),
    "thresholds_step": (["analysis", "thresholds", "step"], NAN, 0.1, "analysis.thresholds.step", "nan"),
    "force_pdf_max": (["analysis", "force_pdf", "max"], INF, 5.0, "analysis.force_pdf.max", "inf"),
    "table_rho": (["studies", "p2", "table_rho"], NAN, 0.8, "studies.p2.table_rho", "nan"),
    "material": (["material", "young_modulus"], -INF, 2e4, "material.young_modulus", "-inf"),
}


@pytest.mark.parametrize("case", sorted(NON_FINITE_CASES))
def test_nan_and_infinity_anywhere_are_refused_naming_the_key(default_config, case):
    from forcenet.workflow_io import checked_config

    path, bad, good, key, shown = NON_FINITE_CASES[case]
    schema = REPO / "workflow/schemas/config.schema.yaml"
    config = _mutate(path, bad, default_config)
    with pytest.raises(ConfigError) as error:
        checked_config(config, schema)
    assert str(error.value) == (f"config key '{key}': is {shown}, not a finite number: every number in a config must "
                                "be finite")
    with pytest.raises(ConfigError, match=re.escape(key)):  # the DEM driver's own check, without the schema
        validate_config(config)
    assert checked_config(_mutate(path, good, default_config), schema)  # a finite number in the same place passes


def test_check_config_refuses_yaml_nan_naming_the_key(tmp_path: Path, capsys):
    from forcenet.workflow_io import check_config_main

    text = (REPO / "config/smoke.yaml").read_text()
    assert "    rho: [0.8, 0.84, 0.88]\n" in text
    bad = tmp_path / "nan.yaml"
    bad.write_text(text.replace("    rho: [0.8, 0.84, 0.88]\n", "    rho: [0.8, .nan]\n", 1))
    assert check_config_main([str(bad)]) == 1
    assert capsys.readouterr().err == (f"{bad}: invalid: config key 'systems.2d_linear.rho[1]': is nan, not a finite "
                                       "number: every number in a config must be finite\n")
    good = tmp_path / "good.yaml"
    good.write_text(text)
    assert check_config_main([str(good)]) == 0


DUPLICATED = """seed: 1
systems:
  2d_hertz:
    friction: 0.5
    dimension: 2
    friction: 0.0
"""


def test_a_key_given_twice_is_refused_naming_file_line_and_key(tmp_path: Path):
    from forcenet.workflow_io import ConfigFileError, read_config_file

    path = tmp_path / "twice.yaml"
    path.write_text(DUPLICATED)
    with pytest.raises(ConfigFileError) as error:
        read_config_file(path)
    assert str(error.value) == (f"config file {path}, line 6: key 'systems.2d_hertz.friction' is given twice (first at "
                                "line 4); YAML would keep the last value silently: remove one")
    path.write_text(DUPLICATED.replace("    friction: 0.0\n", "    walls: flat\n"))
    assert read_config_file(path)["systems"]["2d_hertz"] == {"friction": 0.5, "dimension": 2, "walls": "flat"}
    # the same key in two different mappings is no repetition
    path.write_text("a: {x: 1}\nb: {x: 2}\nc: [{x: 1}, {x: 2}]\n")
    assert read_config_file(path)["c"] == [{"x": 1}, {"x": 2}]


def test_check_config_refuses_a_key_given_twice(tmp_path: Path, capsys):
    from forcenet.workflow_io import check_config_main

    text = (REPO / "config/smoke.yaml").read_text()
    realizations = next(row for row in text.splitlines() if row.startswith("realizations:"))
    line = text.splitlines().index(realizations) + 1
    bad = tmp_path / "twice.yaml"
    bad.write_text(text.replace(realizations + "\n", realizations + "\nrealizations: 9\n", 1))
    assert check_config_main([str(bad)]) == 1
    assert capsys.readouterr().err == (f"{bad}: invalid: config file {bad}, line {line + 1}: key 'realizations' is "
                                       f"given twice (first at line {line}); YAML would keep the last value silently: "
                                       "remove one\n")
    good = tmp_path / "good.yaml"
    good.write_text(text)
    assert check_config_main([str(good)]) == 0
    assert f"results_dir {Path.cwd() / 'results'}" in capsys.readouterr().out


@pytest.mark.parametrize("value, rules, absolute", [
    (None, "results", "WD/results"),
    ("results/validation", "results/validation", "WD/results/validation"),
    ("./results//quick/", "results/quick", "WD/results/quick"),
    ("results/../elsewhere", "elsewhere", "WD/elsewhere"),
    ("/scratch/me/forcenet/../run1", "/scratch/me/run1", "/scratch/me/run1"),
])
def test_results_dir_is_resolved_once(tmp_path: Path, value, rules, absolute):
    from forcenet.workflow_io import resolve_results_dir

    assert resolve_results_dir(value, tmp_path) == (rules, Path(absolute.replace("WD", str(tmp_path))))


def test_results_dir_home_is_expanded(tmp_path: Path):
    from forcenet.workflow_io import resolve_results_dir

    assert resolve_results_dir("~/forcenet", tmp_path)[1] == Path.home() / "forcenet"


@pytest.mark.parametrize("value, words", [
    ("results/../../escape", "resolves to WD_PARENT/escape, which is not a folder inside the working directory WD: "
                             "give a relative path below it, or an absolute path to write elsewhere"),
    ("results/..", "resolves to WD, which is not a folder inside the working directory"),
    ("$SCRATCH/run", "contains '$' (environment variables are not expanded): write the folder's path itself"),
    ("results/{system}", "contains '{' (braces are Snakemake wildcards)"),
    (" ", "is empty"),
])
def test_results_dir_outside_the_working_directory_is_refused(tmp_path: Path, value, words):
    from forcenet.workflow_io import resolve_results_dir

    workdir = tmp_path / "repo"
    with pytest.raises(ConfigError) as error:
        resolve_results_dir(value, workdir)
    words = words.replace("WD_PARENT", str(tmp_path)).replace("WD", str(workdir))
    assert str(error.value).startswith("config key 'results_dir': ") and words in str(error.value), str(error.value)


def test_resolved_config_records_the_absolute_results_dir(tmp_path: Path):
    from forcenet.workflow_io import write_resolved_config

    path = tmp_path / "resolved.yaml"
    write_resolved_config(load_config("smoke.yaml"), path, "/scratch/me/run1")
    resolved = yaml.safe_load(path.read_text())
    assert resolved["results_dir"] == "/scratch/me/run1"
    assert set(resolved["systems"]) == set(load_config("smoke.yaml")["systems"])


def test_a_p2_system_needs_three_snapshots(default_config):
    config = _mutate(["systems", "2d_poly_mu0", "rho"], [0.7, 0.8], default_config)
    with pytest.raises(ConfigError) as error:
        validate_config(config)
    assert str(error.value) == ("config key 'systems.2d_poly_mu0.rho': has 2 snapshot(s), but a system of study p2 "
                                "needs at least 3 (the consecutive states a, b, c of Tables I–III): "
                                "extend the ρ grid")
    assert len(validate_config(_mutate(["systems", "2d_poly_mu0", "rho"], [0.7, 0.75, 0.8], default_config))[
        "2d_poly_mu0"].rho_grid) == 3
    # a system outside study p2 may have fewer
    config = _mutate(["studies", "p2", "systems"], ["2d_poly_mu05"], config)
    assert validate_config(config)["2d_poly_mu0"].rho_grid == (0.7, 0.8)


def test_a_key_given_twice_in_a_configfile_stops_the_workflow(tmp_path: Path):
    text = (REPO / "config/smoke.yaml").read_text()
    seed = next(row for row in text.splitlines() if row.startswith("seed:"))
    line = text.splitlines().index(seed) + 1
    bad = tmp_path / "twice.yaml"
    bad.write_text(text.replace(seed + "\n", seed + "\nseed: 7\n", 1))
    result = _snakemake("-n", "--cores", "1", "--configfile", str(bad), "--directory", str(tmp_path / "work"),
                        "--snakefile", str(REPO / "Snakefile"))
    _one_line_failure(result, f"config file {bad}, line {line + 1}: key 'seed' is given twice (first at line {line})")


def test_an_absolute_results_dir_is_printed_and_receives_every_output(tmp_path: Path):
    config = load_config("smoke.yaml")
    config["results_dir"] = str(tmp_path / "scratch" / ".." / "run1")  # resolved once: `..` removed
    path = tmp_path / "absolute.yaml"
    path.write_text(yaml.safe_dump(config))
    result = _snakemake("-n", "--cores", "1", "--configfile", str(path), "--directory", str(tmp_path / "work"),
                        "--snakefile", str(REPO / "Snakefile"))
    assert result.returncode == 0, result.stderr[-3000:]
    assert f"forcenet: results_dir = {tmp_path / 'run1'} (every output is written there)" in result.stderr.splitlines()
    outputs = [word.rstrip(",") for line in result.stdout.splitlines() if line.strip().startswith("output:")
               for word in line.split()[1:]]
    assert outputs and all(word.startswith(f"{tmp_path / 'run1'}/") for word in outputs), outputs[:5]
    default = _snakemake("-n", "--cores", "1", "--directory", str(tmp_path / "work"),
                         "--snakefile", str(REPO / "Snakefile"))
    assert f"forcenet: results_dir = {tmp_path / 'work' / 'results'} (every output" in default.stderr


def test_what_snakemake_reports_before_the_workflow(tmp_path: Path):
    """Snakemake reads every --configfile before the workflow runs, so these messages are Snakemake's;
    docs/configuration.md's "When a job fails" quotes them and says what to do."""
    bad = tmp_path / "bad.yaml"
    bad.write_text("seed: 1\nrealizations: 3: 4\n")
    result = _snakemake("-n", "--cores", "1", "--configfile", str(bad), "--directory", str(tmp_path / "work"))
    output = result.stdout + result.stderr
    assert result.returncode != 0 and "WorkflowError:\nConfig file is not valid JSON or YAML" in output, output
    # a target after --configfile (which takes several files) is read as a config file
    target = tmp_path / "rho0.800.nc"
    target.write_bytes(b"\x89HDF\r\n\x1a\n" + bytes(range(256)))
    result = _snakemake("-n", "--cores", "1", "--configfile", "config/smoke.yaml", str(target))
    output = result.stdout + result.stderr
    assert result.returncode != 0 and "UnicodeDecodeError: 'utf-8' codec can't decode" in output, output[-2000:]
    result = _snakemake("-n", "--cores", "1", "--configfile", "config/smoke.yaml", "results/sim/nothing.nc")
    output = result.stdout + result.stderr
    assert "FileNotFoundError: [Errno 2] No such file or directory: 'results/sim/nothing.nc'" in output, output[-2000:]


def test_the_readings_beside_take_the_other_value_of_each_convention():
    from forcenet.pipeline import readings_beside

    config = load_config("config.yaml")
    readings = readings_beside(config)
    assert (readings["tetrahedra"].value, readings["tetrahedra"].folder) == (True, "fill_tetrahedra-true")
    assert (readings["essential"].value, readings["table_states"].value) == ("apart", "literal")
    assert (readings["essential_drop"].value, readings["essential_drop"].folder) == ("drop", "essential_convention-drop")
    config["analysis"].update(fill_tetrahedra=True, essential_convention="apart")
    config["studies"]["p2"]["table_states"] = "literal"
    readings = readings_beside(config)
    # beside the literal states no jammed ones are set: states that never jam (imported ones) have none
    assert (readings["tetrahedra"].value, readings["essential"].value) == (False, "minus_one")
    assert "table_states" not in readings
    config["analysis"]["essential_convention"] = "drop"  # a build under drop sets no drop reading beside itself
    assert "essential_drop" not in readings_beside(config)


def test_p1_counterparts_are_defined_systems_beside_the_studys_own_with_its_rattler_rule():
    config = load_config("validation.yaml")
    counterparts = config["studies"]["p1"]["counterparts"]
    assert counterparts and not set(counterparts) & set(config["studies"]["p1"]["systems"])
    validate_config(config)
    assert {study_rattler_rule(config, name) for name in counterparts} == {"once"}  # P1's rule, as its systems
    jsonschema.validate(config, SCHEMA)
    unknown = copy.deepcopy(config)
    unknown["studies"]["p1"]["counterparts"].append("2d_nowhere")
    with pytest.raises(ConfigError, match=r"studies\.p1\.counterparts\[\d+\].*unknown system '2d_nowhere'"):
        validate_config(unknown)
    both = copy.deepcopy(config)
    both["studies"]["p1"]["counterparts"].append("2d_hertz")
    with pytest.raises(ConfigError, match=r"studies\.p1\.counterparts\[\d+\].*one of the study's own systems"):
        validate_config(both)
    p2 = copy.deepcopy(config)
    p2["studies"]["p2"]["counterparts"] = ["2d_linear_mu0"]
    with pytest.raises(ConfigError, match=r"studies\.p2\.counterparts': only P1's"):
        validate_config(p2)
