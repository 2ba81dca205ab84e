"""Config validation: the JSON schema plus forcenet.systems, and the workflow refusing bad configs."""
from __future__ import annotations

import copy
import subprocess
import sys
from pathlib import Path

import jsonschema
import pytest
import yaml

from conftest import REPO, load_config
from forcenet.pipeline import snapshot_analysis_params
from forcenet.systems import ConfigError, rho_grid, study_rattler_rule, validate_config

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
