#!/usr/bin/env python3
"""Tabulate the Hertz damping series (docs/validation/damping.md): one row per series run folder.

    .venv/bin/python scripts/damping_series.py results/damping/2d_hertz_g*/ results/damping/3d_hertz_g*_n512/ \
        [--linear results/validation] [--markdown docs/validation/damping_runs.md]

Each folder is a `results_dir` made with `config/damping/base.yaml` and one overlay of `config/damping/` (system
taken from the folder name, up to `_g`), or `FOLDER:SYSTEM` for any other run folder (e.g. P1's start,
`results/p1_start:2d_linear`, docs/validation/p1_start.md), or `FOLDER:SYSTEM:REALIZATION` for one realization of
a campaign (`results/validation:2d_hertz:3`). `--linear` names a results folder holding the linear
system's `2d_linear/network_measures.nc` (P1's paper-size protocol), whose B0/N ridge is printed beside the Hertz
rows. `--verdicts` adds each folder's P1 verdicts (from its `tables/p1_validation.csv`). What each column means:
`forcenet.research.damping_series`.
"""
from __future__ import annotations

import argparse
import math
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "src"))

import pandas as pd  # noqa: E402

from forcenet.report.claims_table import markdown_table, read_validation_csv  # noqa: E402
from forcenet.research.damping_series import SeriesRun, network_readings, series_row  # noqa: E402

COLUMNS = [
    ("system", "system"), ("realization", "run"), ("N", "N"), ("gamma_n", "γ_n"), ("e_at_v0", "e (mean pair, v0)"),
    ("e_at_median_speed", "e (median approach speed near ρ_J)"), ("median_approach_speed", "median approach speed"),
    ("completed", "whole grid"), ("top_rho", "last ρ"), ("capped_relaxations", "capped relaxations"),
    ("max_damping_dt", "max λΔt"),
    ("passes_rule", "passes the rule"), ("rho_J", "ρ_J"), ("rho_J_bulk", "ρ_J bulk"),
    ("connected_below_rho_J", "particles ≥ 2 contacts, last 2 states before the jump"),
    ("rho_below_rho_J", "their ρ"),
    ("b0_small_near_jamming", "B0/N F_th<0.5 near ρ_J"), ("b0_small_beyond", "same curve beyond ρ_J+0.03"),
    ("weak_bin_near_jamming", "weak N0/N near ρ_J"), ("strong_bin_near_jamming", "strong N0/N near ρ_J"),
    ("cluster_size_near_jamming", "⟨S⟩/N F_th=0 near ρ_J"), ("cpu_hours", "CPU-h"),
]


def _format(value) -> str:
    if isinstance(value, bool):
        return "yes" if value else "no"
    if isinstance(value, float):
        if not math.isfinite(value):
            return "–"
        return f"{value:.4g}"
    if isinstance(value, list):
        return ", ".join(str(v) for v in value) or "–"
    return str(value)


#: the Hertz results P1 calls prominent, whose verdicts the second table shows per setting
TARGET_CLAIMS = ("p1-3-clusters-below-jamming", "p1-5.1-b0-ridge", "p1-5.1-b0-ridge-law-contrast",
                 "p1-5.3-weak-peak-nonlinear-only", "p1-5.3-weak-peak-at-ridge",
                 "p1-6-cluster-size-peak-small-threshold")


def verdict_rows(folders: list[tuple[Path, str]]) -> pd.DataFrame:
    """Per run folder with a P1 table (`tables/p1_validation.csv`, made by the P1 report rule on that folder): the
    counts of the primary verdicts about the folder's system and across systems, and the verdicts of
    `TARGET_CLAIMS` (marker in brackets)."""
    rows = []
    for folder, system in folders:
        path = folder / "tables" / "p1_validation.csv"
        if not path.exists():
            continue
        table = read_validation_csv(path, as_text=False)
        claims = table[(table["kind"] == "claim") & table["reading"].isna() & table["system"].isin([system, "all"])]
        counts = claims["verdict"].value_counts()
        row = {"run": str(folder), "system": system, "holds": int(counts.get("holds", 0)),
               "does not hold": int(counts.get("does not hold", 0)),
               "not evaluated": int(counts.get("not evaluated", 0)),
               "marginal": int((claims["marker"] == "marginal").sum())}
        for claim in TARGET_CLAIMS:
            hit = claims[claims["id"] == claim]
            row[claim] = "; ".join(f"{v}{' (' + m + ')' if isinstance(m, str) else ''}, {x:.3g}"
                                   for v, m, x in zip(hit["verdict"], hit["marker"], hit["measured"])) or "–"
        rows.append(row)
    return pd.DataFrame(rows)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("folders", nargs="+",
                        help="series run folders (FOLDER, FOLDER:SYSTEM or FOLDER:SYSTEM:REALIZATION)")
    parser.add_argument("--linear", type=Path, help="results folder with 2d_linear/network_measures.nc")
    parser.add_argument("--markdown", type=Path, help="also write the table to this file")
    parser.add_argument("--verdicts", action="store_true",
                        help="also tabulate the P1 verdicts of every folder that has tables/p1_validation.csv")
    args = parser.parse_args()
    rows = []
    runs = []
    for argument in args.folders:
        run = SeriesRun.parse(argument)
        runs.append((run.results, run.system))
        rows.append(series_row(run))
    if args.linear is not None:
        from forcenet.report.p1 import jamming_point
        import xarray as xr
        from forcenet.datasets.paths import network_measures

        with xr.open_dataset(network_measures(str(args.linear), "2d_linear")) as ds:
            rho_j = jamming_point(ds)
        row = {"system": "2d_linear (reference)", "rho_J": rho_j}
        row.update(network_readings(SeriesRun(args.linear, "2d_linear"), rho_j))
        rows.append(row)
    rows.sort(key=lambda r: (r["system"], r.get("gamma_n", math.inf), r.get("realization", "")))
    frame = pd.DataFrame([{key: _format(row.get(key, math.nan)) for key, _ in COLUMNS} for row in rows])
    text = "\n".join(markdown_table(frame, [key for key, _ in COLUMNS], dict(COLUMNS)))
    if args.verdicts:
        verdicts = verdict_rows(runs)
        if len(verdicts):
            text += "\n\n" + "\n".join(markdown_table(verdicts, list(verdicts.columns)))
    print(text)
    if args.markdown:
        args.markdown.write_text(text + "\n")


if __name__ == "__main__":
    main()
