#!/usr/bin/env python3
"""Judge P1's claims on the runs recorded under data/validation/, without the workflow: each record's states are
restored to a temporary folder, analysed as the analysis jobs do (`forcenet.pipeline.snapshot_measures`, the
config's analysis keys and P1's rattler rule), stacked over (realization, ρ) and judged by
`forcenet.report.p1_validation.p1_validation` with every state's overlaps (`overlaps_by_state`).

    .venv/bin/python scripts/judge_records.py --systems 2d_linear 2d_hertz --csv /tmp/p1_records.csv
    .venv/bin/python scripts/judge_records.py --systems 2d_linear_plexiglass 2d_hertz_plexiglass --realizations 0 \
        --csv /tmp/plexiglass.csv

Reads the records, writes only `--csv` (and `--md`): a check that the judges run on real data before the tables
are regenerated (docs/validation/README.md). Systems left out, counterparts and readings beside are not judged;
TP and the persistence bins leave never-dying classes out (no diagrams.nc is stacked). The rows printed are the
claims whose judge changed after their verdicts were read (`forcenet.report.judge_changes`) and the φ_c values.
"""
from __future__ import annotations

import argparse
import sys
import tempfile
from pathlib import Path

import pandas as pd

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "src"))

from forcenet import pipeline  # noqa: E402
from forcenet.campaign_cli import load_config  # noqa: E402
from forcenet.datasets import provenance_attrs, read_snapshot  # noqa: E402
from forcenet.datasets.aggregate import stack_network_measures  # noqa: E402
from forcenet.datasets.analysis import analysis_dataset  # noqa: E402
from forcenet.datasets.records import read_dataset, restore_snapshots  # noqa: E402
from forcenet.report.claims_table import read_validation_csv  # noqa: E402
from forcenet.report.p1_validation import overlaps_by_state, p1_validation, write_p1_validation  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]


def system_measures(config: dict, system: str, records: Path, folder: Path,
                    only: list[int] | None = None) -> tuple[object, dict]:
    """(network measures stacked over the system's recorded runs — those numbered in `only` where given — and
    {ρ: largest overlap})."""
    analysis = pipeline.snapshot_analysis_params(config, system)
    analyses, realizations, snaps, grid = [], [], [], []
    for record in sorted((records / system).glob("r*/states.nc")):
        realization = int(record.parent.name[1:])
        if only is not None and realization not in only:
            continue
        labels = [str(label) for label in read_dataset(record, "run_record")["state"].values]
        outputs = [folder / system / record.parent.name / f"rho{label}.nc" for label in labels]
        for output in outputs:
            output.parent.mkdir(parents=True, exist_ok=True)
        for path in restore_snapshots(record, outputs):
            snap = read_snapshot(path)
            snaps.append(snap)
            analyses.append(analysis_dataset(pipeline.snapshot_measures(snap, analysis), rho=float(snap.rho),
                                             attrs=pipeline.analysis_attrs(snap, str(path), analysis)))
        realizations.append(realization)
        grid += [float(label) for label in labels]
        print(f"{system} r{realization:02d}: {len(labels)} states analysed", flush=True)
    spec = config["systems"][system]
    attrs = provenance_attrs(system=system, realization=-1, seed=0, config=config,
                             title=f"{system} from its campaign records")
    attrs.update(dimension=spec["dimension"], force_law=spec["force_law"],
                 **pipeline.force_constants(config, system))
    attrs.update(pipeline.common_analysis_attrs(analyses))
    per_run = len(analyses) // len(realizations)
    stacked = stack_network_measures(analyses, [r for r in realizations for _ in range(per_run)], grid, attrs)
    return stacked, overlaps_by_state(snaps).get(system, {})


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--config", default=str(ROOT / "config" / "validation.yaml"))
    parser.add_argument("--records", default=str(ROOT / "data" / "validation"))
    parser.add_argument("--systems", nargs="+", default=["2d_linear", "2d_hertz"])
    parser.add_argument("--realizations", type=int, nargs="+", default=None,
                        help="judge these recorded realizations alone (e.g. 0: a one-run control beside its base's r00)")
    parser.add_argument("--resamples", type=int, default=20)
    parser.add_argument("--csv", required=True)
    parser.add_argument("--md", default=None)
    args = parser.parse_args(argv)
    config = load_config(args.config)
    measures, overlaps = {}, {}
    with tempfile.TemporaryDirectory() as folder:
        for system in args.systems:
            measures[system], overlaps[system] = system_measures(config, system, Path(args.records), Path(folder),
                                                                  args.realizations)
    table = p1_validation(measures, resamples=args.resamples, overlaps=overlaps)
    write_p1_validation(table, args.csv, args.md or str(Path(args.csv).with_suffix(".md")))
    rows = read_validation_csv(args.csv)
    shown = rows[((rows["judge_changed_after_reading"] != "") & (rows["reading"] == "")
                  & rows["system"].isin([*args.systems, "all"]) & (rows["verdict"] != "not evaluated"))
                 | rows["id"].isin(["phi_c", "phi_c_first_jammed"])]
    with pd.option_context("display.max_colwidth", 160, "display.width", 250):
        print(shown[["id", "system", "measured", "verdict", "marker", "robustness", "states"]].to_string(index=False))
    return 0


if __name__ == "__main__":
    sys.exit(main())
