"""The system catalog (`forcenet.catalog`, `config/systems.yaml`): each system described once, run configs that
change only scale keys, the fingerprints of every shipped run config unchanged by the loader."""
from __future__ import annotations

import json

import pytest
import yaml

from conftest import REPO
from forcenet.catalog import (SCALE_KEYS, CatalogError, expand_config, load_run_config, p2_roles, resolve_entry)
from forcenet.datasets.runs import simulation_sha256
from forcenet.report.p1 import system_order
from forcenet.systems import run_seed, realization_seed

#: every run config of the repository and the simulation fingerprint of each of its systems
#: (`forcenet.datasets.runs.simulation_sha256`: what a campaign record is matched against)
GOLDEN = json.loads((REPO / "tests/data/golden/system_fingerprints.json").read_text())

CATALOG = """
material: {young_modulus: 23450.0, poisson_ratio: 0.5, mean_diameter: 1.735, mean_mass: 3.0, velocity_scale: 0.01}
systems:
  base:
    role: p1_linear_2d
    label: "base"
    colour: "#000000"
    friction: 0.5
    box_length: 50
    initial_state: {lattice: box, sites_per_axis: 45, relax_first: true}
    relaxation: {window_steps: 150000, tolerance: 0.1, max_steps: 3000000, criterion: contact_number}
  variant: {like: base, label: "variant", friction: 0.0, initial_state: null}
  twice: {like: variant, label: "twice", box_length: 25}
"""


def write_catalog(tmp_path, text=CATALOG, name="systems.yaml"):
    path = tmp_path / name
    path.write_text(text)
    return str(path)


def run_config(catalog, systems, **extra):
    return {"catalog": [catalog], "seed": 1, "realizations": 1, "systems": systems, **extra}


@pytest.mark.parametrize("path", sorted(GOLDEN))
def test_every_run_config_keeps_the_fingerprints_of_its_systems(path):
    """The loader gives each system the entry its runs were made with: a restructuring of the configs leaves every
    campaign record valid (the fingerprints are those the records' manifest holds, for the systems recorded)."""
    config = load_run_config(REPO / path, root=REPO)
    assert {name: simulation_sha256(config, name) for name in config["systems"]} == GOLDEN[path]


def test_the_committed_records_match_the_catalog():
    config = load_run_config(REPO / "config/validation.yaml", root=REPO)
    manifest = (REPO / "data/validation/manifest.csv").read_text().splitlines()
    header = manifest[0].split(",")
    rows = [dict(zip(header, line.split(","))) for line in manifest[1:]]
    assert rows
    for row in rows:
        assert row["simulation_sha256"] == simulation_sha256(config, row["system"]), row["system"]


def test_a_variant_is_its_base_with_its_own_keys(tmp_path):
    catalog = write_catalog(tmp_path)
    config = expand_config(run_config(catalog, {"base": None, "variant": None, "twice": None}))
    assert config["systems"]["base"]["friction"] == 0.5 and config["systems"]["variant"]["friction"] == 0.0
    assert "initial_state" not in config["systems"]["variant"]  # null removes a key of the base
    assert config["systems"]["twice"]["box_length"] == 25 and config["systems"]["twice"]["friction"] == 0.0
    assert config["system_info"]["twice"] == {"role": "p1_linear_2d", "label": "twice", "colour": "#000000",
                                              "like": "variant"}
    assert not {"role", "label", "colour", "like"} & set(config["systems"]["twice"])  # out of the fingerprint
    assert config["material"]["young_modulus"] == 23450.0 and config["systems_from"] == [catalog]


def test_a_run_config_changes_scale_keys_only(tmp_path):
    catalog = write_catalog(tmp_path)
    config = expand_config(run_config(catalog, {"base": {"box_length": 25, "initial_state": None,
                                                          "relaxation": {"window_steps": 4000}}}))
    entry = config["systems"]["base"]
    assert entry["box_length"] == 25 and "initial_state" not in entry
    # the relaxation's windows are scale, its criterion the catalog's
    assert entry["relaxation"] == {"window_steps": 4000, "tolerance": 0.1, "max_steps": 3000000,
                                   "criterion": "contact_number"}
    with pytest.raises(CatalogError, match=r"c\.yaml: config key 'systems\.base\.friction': a run config changes "
                                           r"only the scale keys"):
        expand_config(run_config(catalog, {"base": {"friction": 0.1}}), source="c.yaml")
    with pytest.raises(CatalogError, match=r"systems\.base\.relaxation\.criterion': the relaxation's scale keys"):
        expand_config(run_config(catalog, {"base": {"relaxation": {"criterion": "kinetic_energy_fluctuation"}}}))
    with pytest.raises(CatalogError, match=r"config key 'material': the particles' material is the catalog's"):
        expand_config(run_config(catalog, {"base": None}, material={"young_modulus": 1.0}))
    assert set(SCALE_KEYS) == {"box_length", "initial_state", "rho", "relaxation", "wall_speed", "initial_speed"}


def test_a_run_config_may_list_the_systems_it_runs_at_the_catalogs_sizes(tmp_path):
    catalog = write_catalog(tmp_path)
    listed = expand_config(run_config(catalog, ["twice", "base"]))
    mapped = expand_config(run_config(catalog, {"twice": None, "base": None}))
    assert listed == mapped and list(listed["systems"]) == ["twice", "base"]
    with pytest.raises(CatalogError, match=r"c\.yaml: config key 'systems' must list the systems it runs"):
        expand_config(run_config(catalog, [{"base": None}]), source="c.yaml")


def test_catalog_mistakes_are_named(tmp_path):
    catalog = write_catalog(tmp_path)
    with pytest.raises(CatalogError, match=r"system 'nowhere' is not described there \(described: base, twice, "
                                           r"variant\)"):
        expand_config(run_config(catalog, {"nowhere": None}))
    circle = write_catalog(tmp_path, "systems:\n  a: {like: b}\n  b: {like: a}\n", "circle.yaml")
    with pytest.raises(CatalogError, match=r"'like:' goes round in a circle \(a → b\)"):
        expand_config(run_config(circle, {"a": None}))
    unlabelled = write_catalog(tmp_path, "systems:\n  a: {role: p1_linear_2d, colour: '#000000'}\n", "u.yaml")
    with pytest.raises(CatalogError, match=r"system 'a' has no label"):
        expand_config(run_config(unlabelled, {"a": None}))
    other = write_catalog(tmp_path, "systems:\n  base: {role: p1_linear_2d, label: x, colour: '#000000'}\n", "o.yaml")
    with pytest.raises(CatalogError, match=r"o\.yaml: system 'base' is described in .*systems\.yaml already"):
        expand_config({**run_config(catalog, {"base": None}), "catalog": [catalog, other]})
    with pytest.raises(CatalogError, match=r"role is 'p3_magic'"):
        expand_config(run_config(write_catalog(tmp_path, "systems:\n  a: {role: p3_magic, label: x, colour: "
                                                         "'#000000'}\n", "r.yaml"), {"a": None}))


def test_an_expanded_config_runs_again_as_it_is(tmp_path):
    """Every output records the expanded config; read back, it is the same config (no second expansion)."""
    config = load_run_config(REPO / "config/smoke.yaml", root=REPO)
    assert expand_config(yaml.safe_load(yaml.safe_dump(config))) == config


def test_a_config_and_an_imported_system_need_no_catalog_entry(tmp_path):
    catalog = write_catalog(tmp_path)
    source = {"source": {"format": "table", "runs": ["x"]}}
    config = expand_config(run_config(catalog, {"mine": source}))
    assert config["systems"]["mine"] == source and config["system_info"] == {} and "material" not in config


def test_seeds_of_pairs_a_control_with_its_system():
    config = load_run_config(REPO / "config/validation.yaml", root=REPO)
    for control, base in (("2d_linear_plexiglass", "2d_linear"), ("2d_linear_literal", "2d_linear"),
                          ("3d_hertz_plexiglass", "3d_hertz")):
        assert run_seed(config, control, 0) == run_seed(config, base, 0) == realization_seed(config["seed"], base, 0)
    assert run_seed(config, "2d_linear_mu0", 0) != run_seed(config, "2d_linear", 0)  # its own name's seeds


def test_roles_come_from_the_catalog_not_from_names_or_positions():
    config = load_run_config(REPO / "config/smoke.yaml", root=REPO)
    assert p2_roles(config, ["2d_poly_mu0", "2d_poly_mu05"]) == ("2d_poly_mu05", "2d_poly_mu0")
    assert p2_roles({"system_info": {}}, ["a", "b"]) == ("a", "b")  # imported: the listed order
    series = load_run_config(REPO / "config/p1_start/config.yaml", root=REPO)
    assert series["system_info"]["2d_hertz_g22_1807"]["role"] == "p1_hertz_2d"
    assert system_order(["3d_hertz", "2d_linear", "2d_hertz"]) == ["2d_hertz", "2d_linear", "3d_hertz"]


def test_the_shipped_catalog_describes_each_variant_by_its_difference():
    from forcenet.catalog import read_catalog

    _, entries = read_catalog([REPO / "config/systems.yaml"])
    assert entries["2d_linear_mu0"] == {"like": "2d_linear", "label": "2D linear, μ = 0", "friction": 0.0}
    assert resolve_entry("2d_linear_mu0", entries)["box_length"] == 50


def test_the_recorded_config_names_the_shipped_catalog_relative_to_the_repository(tmp_path, monkeypatch):
    """Every output records the expanded config and its sha256: they must not depend on where the repository was
    cloned or where the workflow runs, so the shipped catalog is recorded as config/systems.yaml (a catalog outside
    the repository keeps its absolute path) and read back from there."""
    from forcenet.catalog import catalog_files, repository_root
    from forcenet.datasets.runs import config_sha256

    monkeypatch.chdir(tmp_path)
    config = load_run_config(repository_root() / "config/validation.yaml")
    assert config["systems_from"] == ["config/systems.yaml"]
    assert catalog_files(config) == [repository_root() / "config/systems.yaml"]
    monkeypatch.chdir(repository_root())
    assert config_sha256(load_run_config("config/validation.yaml")) == config_sha256(config)
