"""The P2 study's workflow steps (one function per rule of workflow/rules/p2.smk, taking plain paths and the config):
distances between consecutive diagrams, the states a, b, c of Tables I–III, the tables, the validation table, and
the sampling study behind docs/p2_sampling.md. The steps both studies share are in `forcenet.pipeline`."""
from __future__ import annotations

import os
from pathlib import Path
from typing import Any, Mapping, Sequence

from forcenet.datasets.paths import rho_file
from forcenet.pipeline import (chosen_datasets, common_analysis_attrs, job_logger, open_by_system, simulate,
                               stacked_seed)
from forcenet.systems import system_from_config


def p2_distances(*, analyses: Sequence[str], realizations: Sequence[int], output: str, essential_convention: str,
                 config: Mapping[str, Any], system: str, log_path: str | None = None) -> None:
    """P2 §III D: d_B, d_W1, d_W2 between consecutive snapshots of every realization → distances.nc, with the
    config's ρ grid as the `rho` coordinate (`forcenet.datasets.aggregate.distances_on_grid`)."""
    from forcenet.datasets import provenance_attrs, read_dataset, run_expectation, write_netcdf
    from forcenet.datasets.aggregate import distances_on_grid
    from forcenet.report.p2_distances import consecutive_distances, stack_distances

    with job_logger(log_path, f"p2_distances.{system}") as log:
        per_realization_count, left = divmod(len(analyses), len(realizations))
        if left or not per_realization_count:
            raise ValueError(f"{len(analyses)} analyses cannot be split evenly over realizations {list(realizations)}")
        expect = run_expectation(config, system)  # every file checked, and of this run, before any work
        datasets = [read_dataset(path, "analysis", expect=expect) for path in analyses]
        results = []
        for index, realization in enumerate(realizations):
            run = datasets[index * per_realization_count:(index + 1) * per_realization_count]
            results.append(consecutive_distances(run, essential_convention))
            log.info("%s realization %d: %d consecutive pairs", system, realization, len(run) - 1)
        spec = system_from_config(system, config)
        attrs = provenance_attrs(system=system, realization=-1, seed=stacked_seed(config, spec), config=config,
                                 title=f"forcenet distances between consecutive persistence diagrams, {system}")
        attrs.update(dimension=spec.dimension, force_law=spec.force_law)
        attrs.update(common_analysis_attrs(datasets))  # the rule and complex that made every compared diagram
        stacked = distances_on_grid(stack_distances(results, realizations, attrs), spec.rho_grid[1:])
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
        log.info("P2 tables from realization %s, rho %s", chosen[0].attrs.get("realization"),
                 ", ".join(f"{float(s.rho):.4f}" for s in chosen))


def p2_validation_table(*, distances: Sequence[str], tables: Sequence[str], measures: Sequence[str], states: str,
                        frictional: str, frictionless: str | None, md: str, csv: str, paper_size: str | None = None,
                        diagrams: Sequence[str] = (), beside: Mapping[str, Mapping[str, Sequence[str]]] | None = None,
                        log_path: str | None = None) -> None:
    """Each claim of P2 §IV with its measured evidence, verdict and, where it does not hold, the explanation
    (results/tables/p2_validation.md); `measures` (network_measures.nc) and `states` (the p2_table_states CSV)
    feed the explanations' diagnostics; `diagrams` (diagrams.nc) the PD point counts; `paper_size` (the campaign's
    ``docs/validation/p2.csv``, or None in a paper-size config) adds our paper-size values beside P2's; `beside`
    ({reading label: {"distances": […], "tables": […]}}, `readings_beside`; either key may be left out) the
    readings judged beside P2's conventions."""
    import pandas as pd

    from forcenet.report.claims import verdict_counts
    from forcenet.report.p2_tables import read_table
    from forcenet.report.realizations import ROBUSTNESS_RESAMPLES
    from forcenet.report.p2_validation import p2_validation, write_p2_validation

    with job_logger(log_path, "p2_validation") as log:
        def read_tables(paths: Sequence[str]) -> dict[str, pd.DataFrame]:
            return {f"table{i + 1}": read_table(path) for i, path in enumerate(sorted(paths))}

        readings = {label: {**({"distances": open_by_system(files["distances"], "distances")}
                               if files.get("distances") else {}),
                            **({"tables": read_tables(files["tables"])} if files.get("tables") else {})}
                    for label, files in (beside or {}).items()}
        table = p2_validation(open_by_system(distances, "distances"), read_tables(tables),
                              frictional=frictional, frictionless=frictionless or "",
                              measures=open_by_system(measures, "network_measures"), states=pd.read_csv(states),
                              diagrams=open_by_system(diagrams, "diagrams"), resamples=ROBUSTNESS_RESAMPLES,
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

    from forcenet.datasets import read_snapshot
    from forcenet.report.p2_distances import lagged_distance_markdown, lagged_distance_summary, snapshot_diagrams

    runs = {}
    for speed in wall_speeds:
        entry = {**config["systems"][system], "wall_speed": float(speed),
                 "rho": {"start": 0.63, "stop": 0.90, "count": int(count)}}
        run_config = {**config, "realizations": 1, "systems": {system: entry}}
        spec = system_from_config(system, run_config)
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
