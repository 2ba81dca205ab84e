"""The figure registry (forcenet.plotting.registry): every entry names functions that exist and take its inputs,
input kinds the workflow can find and open, unique ids; and the default build makes every registered figure."""
from __future__ import annotations

import dataclasses
import re

import pytest
import yaml

from conftest import REPO, snakemake, load_config
from forcenet.pipeline_figures import FIGURE_INPUT_READERS
from forcenet.plotting import registry


def test_every_entry_is_well_formed():
    assert registry.registry_problems() == []
    assert len(registry.FIGURES_BY_ID) == len(registry.FIGURES)


def entry(**changes):
    return dataclasses.replace(registry.figure_entry("p1_fig04_cluster_size"), **changes)


@pytest.mark.parametrize("bad, problem", [
    (entry(inputs=("measures", "stress_maps")), "unknown input kind 'stress_maps'"),
    (entry(prepare="p1:prepare_p1_fig99"), "not found"),
    (entry(inputs=("measures", "diagrams")), "takes 1 inputs, the entry names 2"),
    (entry(options={"kind": "normal"}), "takes no option 'kind'"),
    (entry(id="fig04_cluster_size"), "must start with its study"),
    (entry(systems="frictional_ones"), "systems must be one of"),
    (entry(prepare="p1:prepare_p1_fig03_force_pdf"), "neither prepare_p1_fig04_cluster_size nor shared"),
    (entry(systems="frictional"), "must take `system`"),
    (dataclasses.replace(registry.figure_entry("p2_fig03_diagrams"), id="p1_fig03_diagrams", systems="all",
                         prepare="p2:prepare_p2_fig03_diagrams"), "is given no `system`"),
])
def test_a_malformed_entry_is_named(bad, problem):
    problems = registry.registry_problems([bad])
    assert any(problem in line for line in problems), problems
    assert "used twice" in " ".join(registry.registry_problems(registry.FIGURES + (registry.FIGURES[0],)))


def test_the_pipeline_opens_every_input_kind():
    assert set(FIGURE_INPUT_READERS) == set(registry.INPUT_KINDS)


def test_the_report_caption_names_the_paper_figure():
    assert registry.figure_entry("p2_fig07_ratios_mu05").report_caption.endswith("(P2 Fig. 7).")
    with pytest.raises(KeyError, match="unknown figure"):
        registry.figure_entry("p2_fig02")


@pytest.mark.workflow
def test_the_default_build_makes_every_registered_figure(tmp_path):
    """A dry run of config/config.yaml (both studies) schedules the rule figure_<id> of every entry, and rule all
    asks for its PDF; the rule reads the files of the entry's inputs."""
    result = snakemake(tmp_path, "-n", config=REPO / "config/config.yaml")
    assert result.returncode == 0, result.stderr[-3000:]
    jobs = {name: (inputs.split(", "), outputs.split(", ")) for name, inputs, outputs in re.findall(
        r"^(?:local)?rule (\S+):\n    input: (.*)\n(?:    output: (.*)$)?", result.stdout, flags=re.M)}
    scheduled = {name for name in jobs if name.startswith("figure_")}
    # and P2's distance figures (Figs 6-10) again under the `drop` reading beside (docs/validation/controls.md §3)
    drop = {entry.id: f"figure_{entry.id}_essential_drop" for entry in registry.FIGURES
            if entry.study == "p2" and entry.inputs == ("distances",)}
    assert len(drop) == 5 and scheduled == {f"figure_{entry.id}" for entry in registry.FIGURES} | set(drop.values())
    for figure, rule in drop.items():
        drawn = f"results/readings/essential_convention-drop/figures/{figure}_essential_drop.pdf"
        assert drawn in jobs[rule][1] and drawn in jobs["all"][0], (rule, jobs[rule][1])
    studies = load_config("config.yaml")["studies"]
    # where each input kind lies (INPUT_KINDS): an aggregate per system, or a run's snapshots or analyses
    kind_paths = {"measures": "results/{system}/network_measures.nc", "diagrams": "results/{system}/diagrams.nc",
                  "distances": "results/{system}/distances.nc", "example_snapshots": "results/sim/{system}/r00/",
                  "state_snapshots": "results/sim/{system}/r", "state_analysis": "results/analysis/{system}/r"}
    assert set(kind_paths) == set(registry.INPUT_KINDS)
    for entry in registry.FIGURES:
        inputs, outputs = jobs[f"figure_{entry.id}"]
        assert f"results/figures/{entry.id}.pdf" in outputs and f"results/figures/{entry.id}.pdf" in jobs["all"][0]
        systems = studies[entry.study]["systems"]
        systems = {"all": systems, "frictional": systems[:1], "frictionless": systems[1:2]}[entry.systems]
        for kind in entry.inputs:
            for system in systems:
                where = kind_paths[kind].format(system=system)
                assert any(path.startswith(where) for path in inputs), (entry.id, kind, where, inputs)
