"""What the workflow's scripts call: one function per rule, taking plain paths and the config.

Workflow scripts (`workflow/scripts/*.py`) are one call into this module, so every step can also be run and
tested without Snakemake. Heavy modules (numba engine, dionysus, matplotlib) are imported inside the functions
that need them, keeping the per-job start-up of light rules small.
"""
from __future__ import annotations

import logging
import os
import shutil
from contextlib import contextmanager
from pathlib import Path
from typing import Any, Iterator, Mapping, Sequence

from forcenet.systems import realization_seed, system_from_config


@contextmanager
def job_logger(log_path: str | os.PathLike | None, name: str) -> Iterator[logging.Logger]:
    """A logger writing to the job's log file (and stderr), closed afterwards."""
    logger = logging.getLogger(f"forcenet.{name}")
    logger.setLevel(logging.INFO)
    logger.propagate = False
    handlers: list[logging.Handler] = [logging.StreamHandler()]
    if log_path:
        Path(log_path).parent.mkdir(parents=True, exist_ok=True)
        handlers.append(logging.FileHandler(log_path, mode="a"))
    formatter = logging.Formatter("%(asctime)s %(levelname)s %(message)s", "%Y-%m-%d %H:%M:%S")
    for handler in handlers:
        handler.setFormatter(formatter)
        logger.addHandler(handler)
    try:
        yield logger
    except BaseException:
        logger.exception("job failed")  # the traceback belongs in the job's log, not only on the console
        raise
    finally:
        for handler in handlers:
            logger.removeHandler(handler)
            handler.close()


def realization_index(label: str) -> int:
    """'r03' → 3."""
    return int(str(label).lstrip("r"))


def run_attrs(config: Mapping[str, Any], system: str, realization: int, title: str) -> dict[str, Any]:
    from forcenet.datasets import provenance_attrs

    seed = realization_seed(config["seed"], system, realization)
    return provenance_attrs(system=system, realization=realization, seed=seed, config=config, title=title)


def staging_dir(output: str | os.PathLike) -> Path:
    """Where a run keeps its snapshots and checkpoint until it completes: {run dir}/.partial/."""
    return Path(output).parent / ".partial"


def simulate(*, config: Mapping[str, Any], system: str, realization: str, outputs: Sequence[str],
             log_path: str | None = None) -> None:
    """One compression run of `system`: snapshots at every ρ of its grid, published only when all exist.

    Snapshots and the checkpoint live in `.partial/` while the run is in progress (Snakemake deletes declared
    outputs of an interrupted job; the staged ones survive, so a rerun resumes from the checkpoint).
    """
    from forcenet.dem.protocol import run_compression

    spec = system_from_config(system, config)
    index = realization_index(realization)
    attrs = run_attrs(config, system, index, title=f"forcenet DEM snapshot, {system}")
    stage = staging_dir(outputs[0])
    marker = stage / "config_sha256"
    if stage.exists() and (not marker.exists() or marker.read_text() != attrs["config_sha256"]):
        shutil.rmtree(stage)  # a checkpoint from another config must not be resumed
    stage.mkdir(parents=True, exist_ok=True)
    marker.write_text(attrs["config_sha256"])
    staged = [stage / Path(path).name for path in outputs]
    with job_logger(log_path, f"simulate.{system}.{realization}") as log:
        log.info("system %s realization %s seed %d: %d snapshots, staging in %s", system, realization,
                 attrs["seed"], len(outputs), stage)
        run_compression(spec, seed=attrs["seed"], snapshot_paths=staged, checkpoint_path=stage / "checkpoint.npz",
                        attrs=attrs, log=log)
        for source, target in zip(staged, outputs):
            os.replace(source, target)
        shutil.rmtree(stage, ignore_errors=True)
        log.info("published %d snapshots", len(outputs))


def force_unit_dyn(config: Mapping[str, Any], system: str) -> float:
    """One reduced force unit m̄ d_ave / τ_c² in dyn (P1 systems; NaN when the system has no material).

    Lets P1's F_max rule (§3) compare ⟨F⟩ across systems whose τ_c differ (linear vs Hertzian)."""
    from forcenet import units

    entry = config["systems"][system]
    if entry["stiffness"] != "material":
        return float("nan")
    material = units.Material(**config["material"])
    tau_c = units.collision_time_seconds(material, units.FORCE_LAW_BETA[entry["force_law"]])
    return material.mean_mass * material.mean_diameter / tau_c ** 2


def aggregate(*, analyses: Sequence[str], realizations: Sequence[int], rhos: Sequence[float], measures_path: str,
              diagrams_path: str, config: Mapping[str, Any], system: str, log_path: str | None = None) -> None:
    """Stack one system's per-snapshot analyses over (realization, ρ) into network_measures.nc and diagrams.nc."""
    from forcenet.datasets import open_dataset, provenance_attrs, write_netcdf
    from forcenet.datasets.aggregate import stack_diagrams, stack_network_measures

    spec = system_from_config(system, config)
    with job_logger(log_path, f"aggregate.{system}") as log:
        datasets = [open_dataset(path) for path in analyses]
        attrs = provenance_attrs(system=system, realization=-1, seed=config["seed"], config=config,
                                 title=f"forcenet network measures, {system}, stacked over realization and rho")
        attrs.update(dimension=spec.dimension, force_law=spec.force_law, force_unit_dyn=force_unit_dyn(config, system))
        attrs.update(rattler_attrs(common_rattler_rule(datasets)))
        write_netcdf(stack_network_measures(datasets, realizations, rhos, attrs), measures_path)
        attrs["title"] = f"forcenet persistence diagrams, {system}, all realizations and rho"
        write_netcdf(stack_diagrams(datasets, realizations, rhos, attrs), diagrams_path)
        log.info("stacked %d analyses of %s", len(datasets), system)


#: the `analysis:` config keys that the per-snapshot analysis reads (`snapshot_measures`, `analysis_attrs`); the
#: workflow passes only these to the analysis jobs, so that other keys do not rerun every snapshot analysis
SNAPSHOT_ANALYSIS_KEYS = ("thresholds", "remove_rattlers", "force_pdf")


def snapshot_analysis_params(config: Mapping[str, Any], system: str) -> dict[str, Any]:
    """What the analysis jobs of `system` read: the `SNAPSHOT_ANALYSIS_KEYS` of ``analysis:``, with
    ``remove_rattlers`` replaced by the rule of the system's study (`forcenet.systems.study_rattler_rule`:
    P1 removes rattlers, P2 keeps them), so that changing one study's rule reruns only its systems' analyses."""
    from forcenet.systems import study_rattler_rule

    params = {key: config["analysis"][key] for key in SNAPSHOT_ANALYSIS_KEYS}
    params["remove_rattlers"] = study_rattler_rule(config, system)
    return params


def analyze_run(*, snapshots: Sequence[str], outputs: Sequence[str], analysis: Mapping[str, Any],
                log_path: str | None = None) -> None:
    """Analyse every snapshot of one compression run (one process: imports and JIT paid once)."""
    with job_logger(log_path, "analyze") as log:
        for snapshot, output in zip(snapshots, outputs, strict=True):
            analyze_snapshot(snapshot, output, analysis, log)


def analyze_snapshot(snapshot: str, output: str, analysis: Mapping[str, Any], log: logging.Logger) -> None:
    """Analyse one snapshot file and write its analysis file (see `snapshot_measures`)."""
    import time

    from forcenet.datasets import read_snapshot, write_netcdf
    from forcenet.datasets.analysis import analysis_dataset

    start = time.perf_counter()
    snap = read_snapshot(snapshot)
    ds = analysis_dataset(snapshot_measures(snap, analysis), rho=float(snap.rho),
                          attrs=analysis_attrs(snap, snapshot, analysis))
    write_netcdf(ds, output)
    log.info("%s: rho %.3f, Z %.3f, %d diagram points, %.2f s", snapshot, float(snap.rho), float(snap.Z),
             ds.sizes["point"], time.perf_counter() - start)


def snapshot_measures(snap, analysis: Mapping[str, Any]) -> dict[str, Any]:
    """Every single-snapshot measure of the total (P1), normal and tangential (P2) force networks of a snapshot
    dataset, each network normalised by its own mean: {kind: SnapshotMeasures}."""
    from forcenet.datasets.schema import FORCE_KINDS
    from forcenet.measures.forces import default_force_bin_edges
    from forcenet.measures.snapshot import compute_snapshot_measures
    from forcenet.network import build_force_network
    from forcenet.topology.betti import default_thresholds

    thresholds = default_thresholds(**analysis["thresholds"])
    edges = default_force_bin_edges(analysis["force_pdf"]["max"], analysis["force_pdf"]["bins"])
    measures = {}
    for kind in FORCE_KINDS:
        network = build_force_network(
            snap.position.values, snap.contact_i.values, snap.contact_j.values, snap.force_normal.values,
            snap.force_tangential.values, kind=kind, remove_rattlers=analysis["remove_rattlers"],
            wall_particle=snap.wall_contact_particle.values, wall_id=snap.wall_contact_wall.values,
            wall_force=snap.wall_contact_force.values)
        measures[kind] = compute_snapshot_measures(network, thresholds=thresholds, force_bin_edges=edges)
    return measures


def analysis_attrs(snap, source: str, analysis: Mapping[str, Any]) -> dict[str, Any]:
    """Global attributes of an analysis file: the snapshot's provenance plus what the analysis used."""
    attrs = {key: snap.attrs[key] for key in ("system", "realization", "seed", "forcenet_version", "git_commit",
                                               "config_sha256", "config", "Conventions", "dimension")}
    attrs["title"] = f"forcenet analysis of one snapshot, {attrs['system']}"
    attrs["source"] = str(source)
    attrs.update(rattler_attrs(analysis["remove_rattlers"]))
    return attrs


def rattler_attrs(remove_rattlers: bool | str) -> dict[str, str]:
    """Global attributes naming the rattler rule that made a file's force networks (analysis, stacked and
    distance files, P2 tables)."""
    from forcenet.network import RATTLER_RULE_DESCRIPTIONS, resolve_rattler_rule

    rule = resolve_rattler_rule(remove_rattlers)
    return {"rattler_rule": rule, "rattler_rule_description": RATTLER_RULE_DESCRIPTIONS[rule]}


def common_rattler_rule(datasets: Sequence[Any]) -> str:
    """The `rattler_rule` attribute shared by every dataset (analysis files); ValueError when they differ or
    one lacks it (a product must not mix networks made by different rules)."""
    rules = {ds.attrs.get("rattler_rule", "missing") for ds in datasets}
    if len(rules) != 1 or "missing" in rules:
        raise ValueError(f"analyses were made with different or unrecorded rattler rules: {sorted(rules)}")
    return rules.pop()


def _open_by_system(paths: Sequence[str]) -> dict[str, Any]:
    from forcenet.datasets import open_dataset

    datasets = [open_dataset(path) for path in paths]
    return {ds.attrs["system"]: ds for ds in datasets}


def figure(*, name: str, systems: Sequence[str], inputs: Mapping[str, Sequence[str]], pdf: str, png: str,
           log_path: str | None = None) -> None:
    """Draw one P1 figure from the aggregated datasets (and example snapshots for figure 1)."""
    from forcenet.plotting.p1 import make_p1_figure
    from forcenet.plotting.style import apply_style, save_figure

    with job_logger(log_path, f"figure.{name}") as log:
        apply_style()
        figure_ = make_p1_figure(name, measures=_open_by_system(inputs.get("measures", [])),
                                 diagrams=_open_by_system(inputs.get("diagrams", [])),
                                 snapshots=_open_by_system(inputs.get("snapshots", [])))
        save_figure(figure_, pdf, png)
        log.info("%s drawn for %s", name, ", ".join(systems))


def p1_validation_table(*, measures: Sequence[str], systems: Sequence[str], csv: str, md: str,
                        log_path: str | None = None) -> None:
    """P1's numbers and claims next to ours (results/tables/p1_validation.{csv,md})."""
    from forcenet.report.p1 import p1_validation, write_p1_validation

    with job_logger(log_path, "p1_validation") as log:
        table = p1_validation(_open_by_system(measures))
        write_p1_validation(table, csv, md)
        log.info("P1 validation: %d rows, verdicts %s", len(table), table["verdict"].value_counts().to_dict())


def p2_distances(*, analyses: Sequence[str], realizations: Sequence[int], output: str, essential_convention: str,
                 config: Mapping[str, Any], system: str, log_path: str | None = None) -> None:
    """P2 §III D: d_B, d_W1, d_W2 between consecutive snapshots of every realization → distances.nc."""
    from forcenet.datasets import open_dataset, provenance_attrs, write_netcdf
    from forcenet.report.p2 import consecutive_distances, stack_distances

    with job_logger(log_path, f"p2_distances.{system}") as log:
        per_realization_count, left = divmod(len(analyses), len(realizations))
        if left or not per_realization_count:
            raise ValueError(f"{len(analyses)} analyses cannot be split evenly over realizations {list(realizations)}")
        results, opened = [], []
        for index, realization in enumerate(realizations):
            paths = analyses[index * per_realization_count:(index + 1) * per_realization_count]
            datasets = [open_dataset(p) for p in paths]
            opened += datasets
            results.append(consecutive_distances(datasets, essential_convention))
            log.info("%s realization %d: %d consecutive pairs", system, realization, len(paths) - 1)
        spec = system_from_config(system, config)
        attrs = provenance_attrs(system=system, realization=-1, seed=config["seed"], config=config,
                                 title=f"forcenet distances between consecutive persistence diagrams, {system}")
        attrs["dimension"] = spec.dimension
        attrs.update(rattler_attrs(common_rattler_rule(opened)))  # the rule that made every compared diagram
        write_netcdf(stack_distances(results, realizations, attrs), output)


def p2_table_states(*, analyses: Sequence[str], csv: str, log_path: str | None = None) -> None:
    """Which realization gives the states a, b, c of Tables I–III and Figs 1, 3 (P2 Fig. 1's criterion,
    `forcenet.report.p2.TABLE_STATE_CRITERION`): one row per realization, written to `csv`."""
    from forcenet.datasets import open_dataset
    from forcenet.report.p2 import table_state_candidates

    with job_logger(log_path, "p2_table_states") as log:
        table = table_state_candidates([open_dataset(p) for p in analyses])
        Path(csv).parent.mkdir(parents=True, exist_ok=True)
        table.to_csv(csv, index=False)
        chosen = table[table["chosen"]].iloc[0]
        log.info("states a, b, c: realization %d (score %.3g of %s)", chosen["realization"], chosen["score"],
                 ", ".join(f"{s:.3g}" for s in table["score"]))


def _chosen(paths: Sequence[str], states_csv: str, reader) -> list:
    """The datasets among `paths` (read with `reader`) of the realization `states_csv` chose, in increasing ρ."""
    import pandas as pd

    from forcenet.report.p2 import chosen_states

    return chosen_states([reader(p) for p in paths], pd.read_csv(states_csv))


def p2_tables(*, snapshots: Sequence[str], states: str, csv: Sequence[str], md: Sequence[str],
              rattler_rule: bool | str, essential_convention: str, log_path: str | None = None) -> None:
    """P2 Tables I–III from the states a, b, c of the realization `states` (the `p2_table_states` CSV) chose,
    whole box and quadrants, networks made with the P2 study's `rattler_rule`; `csv` and `md` are the paths
    `forcenet.report.p2.write_p2_tables` writes (``{directory}/p2_table{1,2,3}.{csv,md}``)."""
    from forcenet.datasets import read_snapshot
    from forcenet.report.p2 import p2_tables as compute_tables, write_p2_tables

    with job_logger(log_path, "p2_tables") as log:
        chosen = _chosen(snapshots, states, read_snapshot)
        tables = compute_tables(chosen, remove_rattlers=rattler_rule, essential_convention=essential_convention)
        written = write_p2_tables(tables, Path(csv[0]).parent)
        expected = sorted(Path(p).resolve() for p in (*csv, *md))
        if sorted(p.resolve() for p in written) != expected:
            raise ValueError(f"P2 tables written as {[str(p) for p in written]}, expected {[str(p) for p in expected]}")
        log.info("P2 tables from realization %s, rho %s", chosen[0].attrs.get("realization"),
                 ", ".join(f"{float(s.rho):.4f}" for s in chosen))


def p2_figure(*, name: str, system: str, inputs: Mapping[str, Sequence[str]], pdf: str, png: str,
              rattler_rule: bool | str = False, log_path: str | None = None) -> None:
    """Draw one P2 figure: the snapshots a, b, c (Fig. 1, networks made with `rattler_rule`) or the analysis of
    state a (Fig. 3) of the realization ``inputs["states"]`` chose, or one system's distances (Figs 6–10)."""
    from forcenet.datasets import open_dataset
    from forcenet.plotting.p2 import P2_FIGURES
    from forcenet.plotting.style import apply_style, save_figure

    with job_logger(log_path, f"figure.{name}") as log:
        apply_style()
        function = P2_FIGURES[name]
        if inputs.get("snapshots"):
            figure_ = function(_chosen(inputs["snapshots"], inputs["states"][0], open_dataset), system=system,
                               remove_rattlers=rattler_rule)
        elif inputs.get("analysis"):
            figure_ = function(_chosen(inputs["analysis"], inputs["states"][0], open_dataset)[0], system=system)
        else:
            figure_ = function(open_dataset(inputs["distances"][0]), system=system)
        save_figure(figure_, pdf, png)
        log.info("%s drawn for %s", name, system)


def p2_validation_table(*, distances: Sequence[str], tables: Sequence[str], measures: Sequence[str], states: str,
                        frictional: str, frictionless: str | None, md: str, csv: str,
                        log_path: str | None = None) -> None:
    """Each claim of P2 §IV with its measured evidence, verdict and, where it does not hold, the explanation
    (results/tables/p2_validation.md); `measures` (network_measures.nc) and `states` (the p2_table_states CSV)
    feed the explanations' diagnostics."""
    import pandas as pd

    from forcenet.report.p2 import p2_validation, read_table, write_p2_validation

    with job_logger(log_path, "p2_validation") as log:
        table = p2_validation(_open_by_system(distances),
                              {f"table{i + 1}": read_table(path) for i, path in enumerate(sorted(tables))},
                              frictional=frictional, frictionless=frictionless or "",
                              measures=_open_by_system(measures), states=pd.read_csv(states))
        write_p2_validation(table, md, csv)
        log.info("P2 validation: verdicts %s", table["verdict"].value_counts().to_dict())


def p2_sampling_study(*, config: Mapping[str, Any], system: str, wall_speeds: Sequence[float], count: int,
                      lags: Sequence[int], rattler_rule: str, out: str | os.PathLike,
                      simulate_only: bool = False) -> str:
    """Distances between states k samples apart at several wall speeds, one realization (docs/p2_sampling.md).

    For each speed, realization 0 of `system` (its config entry with ``wall_speed`` and a ρ grid of `count`
    states from 0.63 to 0.90) is compressed into ``{out}/v{speed}/`` (reused when complete); the normal-force
    diagrams of every state (rattler rule `rattler_rule`) are compared at each lag. Returns the Markdown
    table of `forcenet.report.p2.lagged_distance_summary` (also written to ``{out}/p2_sampling.md``), or ""
    when `simulate_only`.
    """
    import time

    from forcenet.datasets import read_snapshot
    from forcenet.report.p2 import lagged_distance_markdown, lagged_distance_summary, snapshot_diagrams

    runs = {}
    for speed in wall_speeds:
        entry = {**config["systems"][system], "wall_speed": float(speed),
                 "rho": {"start": 0.63, "stop": 0.90, "count": int(count)}}
        run_config = {**config, "realizations": 1, "systems": {system: entry}}
        spec = system_from_config(system, run_config)
        directory = Path(out) / f"v{speed:g}"
        paths = [str(directory / f"rho{label}.nc") for label in spec.rho_labels]
        seconds = float("nan")
        if not all(Path(p).exists() for p in paths):
            start = time.perf_counter()
            simulate(config=run_config, system=system, realization="r00", outputs=paths,
                     log_path=str(directory / "simulate.log"))
            seconds = time.perf_counter() - start
        runs[float(speed)] = (paths, seconds)
    if simulate_only:
        return ""
    summaries = {}
    for speed, (paths, seconds) in runs.items():
        snapshots = [read_snapshot(p) for p in paths]
        diagrams = [snapshot_diagrams(s, "normal", rattler_rule) for s in snapshots]
        rho = [float(s["rho"]) for s in snapshots]
        z = [float(s["Z"]) for s in snapshots]
        summaries[speed] = (rho, z, diagrams, seconds)
    table = lagged_distance_markdown(lagged_distance_summary(summaries, lags,
                                                             dimension=int(config["systems"][system]["dimension"])))
    Path(out).mkdir(parents=True, exist_ok=True)
    (Path(out) / "p2_sampling.md").write_text(table)
    return table
