"""The P2 study's workflow steps (one function per rule of workflow/rules/p2.smk, taking plain paths and the config):
distances between consecutive diagrams, the states a, b, c of Tables I–III, the tables, the validation table, and
the sampling study behind docs/p2_sampling.md. The steps both studies share are in `forcenet.pipeline`."""
from __future__ import annotations

import os
from pathlib import Path
from typing import Any, Mapping, Sequence

from forcenet.datasets.paths import rho_file
from forcenet.pipeline import (chosen_datasets, common_analysis_attrs, job_logger, open_by_system, readings_beside,
                               run_attrs, sequence_attrs, simulate, stacked_seed)
from forcenet.systems import select_table_snapshots

#: how many states of the grid, from the first at or above ``studies.p2.table_rho``, are the candidates for the states
#: a, b, c of Tables I-III under the "jammed" rule (the first three consecutive ones among them with mean Z >= d + 1):
#: at the papers' grid (100 states on 0.63-0.90, step 0.0027) nine states reach 0.79 + 0.022, past the jamming point
#: of every paper-size run (rho_J 0.798-0.807, docs/validation/p2.md) and the two states after it; a campaign record
#: of a P2 run keeps these states (data/validation/README.md), so a build from records reads the same candidates
P2_JAMMED_WINDOW = 9


def p2_candidate_indices(rho_grid: Sequence[float], table_rho: float, rule: str) -> list[int]:
    """Indices into the ascending `rho_grid` of the candidate states a, b, c of every realization under `rule`
    (``studies.p2.table_states``): "jammed", the first `P2_JAMMED_WINDOW` states at or above `table_rho`; "literal",
    the three around it (`forcenet.systems.select_table_snapshots`)."""
    if rule == "jammed":
        return [int(i) for i, rho in enumerate(rho_grid) if rho >= table_rho - 1e-9][:P2_JAMMED_WINDOW]
    return sorted(select_table_snapshots(rho_grid, table_rho))


def p2_read_state_indices(rho_grid: Sequence[float], table_rho: float, rule: str) -> list[int]:
    """The states of a run of P2's frictional system that Tables I-III and their state choice can read: the
    candidates of the config's `rule` and, beside the "jammed" rule, those of the literal reading
    (`forcenet.pipeline.readings_beside`); a P2 run record keeps these and no other."""
    indices = set(p2_candidate_indices(rho_grid, table_rho, rule))
    if rule == "jammed":
        indices |= set(p2_candidate_indices(rho_grid, table_rho, "literal"))
    return sorted(indices)


def p2_conventions(config: Mapping[str, Any]) -> list[str]:
    """The never-dying conventions a build's P2 distances are made under: the config's ``essential_convention`` and
    those of the essential readings beside it (`forcenet.pipeline.readings_beside`)."""
    readings = readings_beside(config)
    return list(dict.fromkeys([config["analysis"]["essential_convention"],
                               *(readings[key].value for key in ("essential", "essential_drop") if key in readings)]))


def p2_run_summary(*, analyses: Sequence[str], output: str, config: Mapping[str, Any], system: str,
                   realization: str, conventions: Sequence[str], log_path: str | None = None) -> None:
    """What P2's products read from one run, its diagrams apart (`forcenet.report.p2_distances.run_summary`, kind
    "p2_run"): the run's analyses, in grid order, summed up under every never-dying convention of `conventions`."""
    from forcenet.checks import checked_system
    from forcenet.datasets import read_dataset, run_expectation, write_netcdf
    from forcenet.datasets.paths import realization_index
    from forcenet.report.p2_distances import run_summary

    with job_logger(log_path, f"p2_run.{system}.{realization}") as log:
        spec = checked_system(system, config)
        expect = run_expectation(spec, config)
        datasets = [read_dataset(path, "analysis", expect=expect) for path in analyses]
        attrs = run_attrs(config, system, realization_index(realization),
                          title=f"forcenet P2 run summary, {system} {realization}")
        attrs.update(dimension=spec.dimension, simulation_sha256=expect["simulation_sha256"],
                     **common_analysis_attrs(datasets))
        write_netcdf(run_summary(datasets, conventions, spec.rho_grid, attrs, sequence=bool(sequence_attrs(spec))),
                     output, kind="p2_run")
        log.info("%s %s: %d states, distances under %s", system, realization, len(datasets), ", ".join(conventions))


def read_run_summaries(paths: Sequence[str], config: Mapping[str, Any] | None = None) -> dict[str, dict[int, Any]]:
    """{system: {realization: P2 run summary}} of the files `paths` (kind "p2_run"); with `config`, a summary of
    other simulation settings than its system's in `config` is refused, naming the file."""
    from forcenet.datasets import DatasetError, read_dataset
    from forcenet.datasets.runs import simulation_sha256

    runs: dict[str, dict[int, Any]] = {}
    for path in paths:
        ds = read_dataset(path, "p2_run")
        system = str(ds.attrs["system"])
        if config is not None and ds.attrs["simulation_sha256"] != simulation_sha256(config, system):
            raise DatasetError(path, f"made from a run of other settings of system '{system}' than this config's")
        runs.setdefault(system, {})[int(ds.attrs["realization"])] = ds
    return runs


def p2_distances(*, runs: Sequence[str], realizations: Sequence[int], output: str, essential_convention: str,
                 config: Mapping[str, Any], system: str, log_path: str | None = None) -> None:
    """P2 §III D: d_B, d_W1, d_W2 between consecutive snapshots of every realization → distances.nc, with the
    config's ρ grid as the `rho` coordinate (`forcenet.datasets.aggregate.distances_on_grid`), from each run's
    summary (`runs`, kind "p2_run", in the order of `realizations`: made from its analyses or restored from its
    campaign record)."""
    from forcenet.checks import checked_system
    from forcenet.datasets import DatasetError, provenance_attrs, write_netcdf
    from forcenet.datasets.aggregate import distances_on_grid
    from forcenet.report.p2_distances import stack_distances, summary_distances

    with job_logger(log_path, f"p2_distances.{system}") as log:
        if len(runs) != len(realizations):
            raise ValueError(f"{len(runs)} run summaries for realizations {list(realizations)}")
        by_system = read_run_summaries(runs, config)  # every file checked, and of this system's settings
        summaries = by_system.get(system, {})
        if sorted(summaries) != sorted(int(r) for r in realizations) or set(by_system) != {system}:
            raise ValueError(f"run summaries {list(runs)} are not realizations {list(realizations)} of {system}")
        results = []
        for path, realization in zip(runs, realizations):
            try:
                results.append(summary_distances(summaries[int(realization)], essential_convention))
            except KeyError as error:
                raise DatasetError(path, error.args[0]) from None
            log.info("%s realization %d: %d consecutive pairs", system, realization, results[-1].sizes["rho"])
        spec = checked_system(system, config)
        attrs = provenance_attrs(system=system, realization=-1, seed=stacked_seed(config, spec), config=config,
                                 title=f"forcenet distances between consecutive persistence diagrams, {system}")
        attrs.update(dimension=spec.dimension, force_law=spec.force_law)
        attrs.update(common_analysis_attrs(list(summaries.values())))  # the rule and complex of every diagram
        attrs.update(sequence_attrs(spec))  # a sequence's pairs lie along its coordinate, not along ρ
        stacked = distances_on_grid(stack_distances(results, realizations, attrs), spec.rho_grid[1:],
                                    measured_on_grid=not sequence_attrs(spec))
        write_netcdf(stacked, output, kind="distances")


def p2_table_states(*, analyses: Sequence[str], csv: str, rule: str = "jammed", table_rho: float = 0.79,
                    dimension: int = 2, log_path: str | None = None) -> None:
    """Which states a, b, c (`rule` of `forcenet.report.p2_tables.TABLE_STATE_RULES`, config key
    ``studies.p2.table_states``) and which realization give Tables I–III and Figs 1, 3 (P2 Fig. 1's criterion,
    `forcenet.report.p2_tables.TABLE_STATE_CRITERION`): one row per realization, written to `csv`."""
    from forcenet.datasets import read_dataset
    from forcenet.report.p2_tables import table_state_candidates

    with job_logger(log_path, "p2_table_states") as log:
        table = table_state_candidates([read_dataset(p, "analysis") for p in analyses], rule, table_rho, dimension)
        Path(csv).parent.mkdir(parents=True, exist_ok=True)
        table.to_csv(csv, index=False)
        chosen = table[table["chosen"]].iloc[0]
        log.info("states a, b, c: realization %d (score %.3g of %s)", chosen["realization"], chosen["score"],
                 ", ".join(f"{s:.3g}" for s in table["score"]))


def p2_tables(*, snapshots: Sequence[str], states: str, csv: Sequence[str], md: Sequence[str],
              rattler_rule: bool | str, essential_convention: str, log_path: str | None = None) -> None:
    """P2 Tables I–III from the states a, b, c of the realization `states` (the `p2_table_states` CSV) chose,
    whole box and quadrants, networks made with the P2 study's `rattler_rule`; `csv` and `md` are the paths
    `forcenet.report.p2_tables.write_p2_tables` writes (``{directory}/p2_table{1,2,3}.{csv,md}``)."""
    from forcenet.datasets import read_snapshot
    from forcenet.report.p2_tables import p2_tables as compute_tables, write_p2_tables

    with job_logger(log_path, "p2_tables") as log:
        chosen = chosen_datasets(snapshots, states, read_snapshot)
        tables = compute_tables(chosen, remove_rattlers=rattler_rule, essential_convention=essential_convention)
        written = write_p2_tables(tables, Path(csv[0]).parent)
        expected = sorted(Path(p).resolve() for p in (*csv, *md))
        if sorted(p.resolve() for p in written) != expected:
            raise ValueError(f"P2 tables written as {[str(p) for p in written]}, expected {[str(p) for p in expected]}")
        log.info("P2 tables from realization %s, rho %s", chosen[0].attrs["realization"],
                 ", ".join(f"{float(s.rho):.4f}" for s in chosen))


def p2_validation_table(*, distances: Sequence[str], tables: Sequence[str], states: str, frictional: str,
                        frictionless: str | None, md: str, csv: str, runs: Sequence[str] = (),
                        paper_size: str | None = None,
                        beside: Mapping[str, Mapping[str, Sequence[str]]] | None = None,
                        log_path: str | None = None) -> None:
    """Each claim of P2 §IV with its measured evidence, verdict and, where it does not hold, the explanation
    (results/tables/p2_validation.md); `runs` (every run's summary, kind "p2_run": never-dying class counts and
    PD point counts) and `states` (the p2_table_states CSV) feed the explanations' diagnostics and the PD1 point
    counts of IV.C-8; `paper_size` (the campaign's
    ``docs/validation/p2.csv``, or None in a paper-size config) adds our paper-size values beside P2's; `beside`
    ({reading label: {"distances": […], "tables": […]}}, `readings_beside`; either key may be left out) the
    readings judged beside P2's conventions."""
    import pandas as pd

    from forcenet.report.claims import verdict_counts
    from forcenet.report.p2_tables import read_table
    from forcenet.report.realizations import ROBUSTNESS_RESAMPLES
    from forcenet.report.p2_distances import summary_essential_counts, summary_point_counts
    from forcenet.report.p2_validation import p2_validation, write_p2_validation

    with job_logger(log_path, "p2_validation") as log:
        summaries = read_run_summaries(runs)
        def read_tables(paths: Sequence[str]) -> dict[str, pd.DataFrame]:
            return {f"table{i + 1}": read_table(path) for i, path in enumerate(sorted(paths))}

        readings = {label: {**({"distances": open_by_system(files["distances"], "distances")}
                               if files.get("distances") else {}),
                            **({"tables": read_tables(files["tables"])} if files.get("tables") else {})}
                    for label, files in (beside or {}).items()}
        table = p2_validation(open_by_system(distances, "distances"), read_tables(tables),
                              frictional=frictional, frictionless=frictionless or "",
                              measures={name: summary_essential_counts(r) for name, r in summaries.items()},
                              states=pd.read_csv(states),
                              point_counts={name: summary_point_counts(r) for name, r in summaries.items()},
                              resamples=ROBUSTNESS_RESAMPLES,
                              beside=readings)
        write_p2_validation(table, csv, md, paper_size=paper_size)
        log.info("P2 validation: claim verdicts %s", verdict_counts(table))


def p2_sampling_study(*, config: Mapping[str, Any], system: str, wall_speeds: Sequence[float], count: int,
                      lags: Sequence[int], rattler_rule: str, out: str | os.PathLike,
                      simulate_only: bool = False) -> str:
    """Distances between states k samples apart at several wall speeds, one realization (docs/p2_sampling.md).

    For each speed, realization 0 of `system` (its config entry with ``wall_speed`` and a ρ grid of `count`
    states from 0.63 to 0.90) is compressed into ``{out}/v{speed}/`` (reused when complete); the normal-force
    diagrams of every state (rattler rule `rattler_rule`) are compared at each lag. Returns the Markdown
    table of `forcenet.report.p2_distances.lagged_distance_summary` (also written to ``{out}/p2_sampling.md``), or ""
    when `simulate_only`.
    """
    import time

    from forcenet.checks import checked_system
    from forcenet.datasets import read_snapshot
    from forcenet.report.p2_distances import lagged_distance_markdown, lagged_distance_summary, snapshot_diagrams

    runs = {}
    for speed in wall_speeds:
        entry = {**config["systems"][system], "wall_speed": float(speed),
                 "rho": {"start": 0.63, "stop": 0.90, "count": int(count)}}
        run_config = {**config, "realizations": 1, "systems": {system: entry}}
        spec = checked_system(system, run_config)
        directory = Path(out) / f"v{speed:g}"
        files = [str(directory / rho_file(label)) for label in spec.rho_labels]
        seconds = float("nan")
        if not all(Path(p).exists() for p in files):
            start = time.perf_counter()
            simulate(config=run_config, system=system, realization="r00", outputs=files,
                     log_path=str(directory / "simulate.log"))
            seconds = time.perf_counter() - start
        runs[float(speed)] = (files, seconds)
    if simulate_only:
        return ""
    summaries = {}
    for speed, (files, seconds) in runs.items():
        snapshots = [read_snapshot(p) for p in files]
        diagrams = [snapshot_diagrams(s, "normal", rattler_rule) for s in snapshots]
        rho = [float(s["rho"]) for s in snapshots]
        z = [float(s["Z"]) for s in snapshots]
        summaries[speed] = (rho, z, diagrams, seconds)
    table = lagged_distance_markdown(lagged_distance_summary(summaries, lags,
                                                             dimension=int(config["systems"][system]["dimension"])))
    Path(out).mkdir(parents=True, exist_ok=True)
    (Path(out) / "p2_sampling.md").write_text(table)
    return table
