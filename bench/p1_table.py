"""Benchmark (not a test): the cost of judging P1's claims, the work of the `p1_validation_table` job.

Reads the aggregated measures and diagrams a build left (``RESULTS/<system>/network_measures.nc`` and
``diagrams.nc`` of every system found there, P1's systems and their counterparts; the main job's
``results/`` by default) and times `forcenet.report.p1_validation.p1_validation` on them:

- pass_s: one judging pass, no bootstrap (every claim, every system, the readings beside not included);
- resample_s: the extra cost of one bootstrap resample of the realizations, from a run with ``--resamples``
  resamples (the job makes `ROBUSTNESS_RESAMPLES` = 100 of them). Not timed (null) when every system has one
  realization, as in a smoke build: there is nothing to resample.

Medians over ``--repeat`` runs after one warm-up pass. To A/B a change, run this file from both trees on the same
results, alternately, pinned to one core (``taskset -c 1``), with ``PYTHONPATH=<tree>/src``. The last line printed
is one JSON object; the run's record goes to bench/results/p1_table.json (bench/records.py), with the input it
read (systems, realizations, ρ points, the build config's SHA-256); with no build's results there, the record says
so. Run: ``.venv/bin/python bench/p1_table.py [--results results] [--no-record]``.
"""
from __future__ import annotations

import argparse
import json
import statistics
import time
from pathlib import Path

from forcenet.datasets import read_dataset
from forcenet.report.p1 import P1_SYSTEMS
from forcenet.report.p1_validation import p1_validation
from forcenet.report.realizations import ROBUSTNESS_RESAMPLES

import records  # bench/records.py


def counterparts_of(ds) -> list[str]:
    """``studies.p1.counterparts`` of the config a measures file records."""
    return list(json.loads(ds.attrs["config"]).get("studies", {}).get("p1", {}).get("counterparts", []))


def read_results(results: Path) -> tuple[dict, dict, list]:
    """({system: network measures}, {system: diagrams}, counterparts) of every system under `results` that has
    both files; the counterparts (``studies.p1.counterparts``) from the config the measures record."""
    measures, diagrams, counterparts = {}, {}, set()
    for path in sorted(results.glob("*/network_measures.nc")):
        diagram_path = path.with_name("diagrams.nc")
        if not diagram_path.exists():
            continue
        ds = read_dataset(path, "network_measures")
        if ds.attrs["system"] not in P1_SYSTEMS and ds.attrs["system"] not in counterparts_of(ds):
            continue  # P2's systems: not P1's table
        measures[ds.attrs["system"]] = ds.load()
        diagrams[ds.attrs["system"]] = read_dataset(diagram_path, "diagrams").load()
        counterparts |= set(counterparts_of(ds))
    return measures, diagrams, sorted(counterparts & set(measures))


def timed(measures: dict, diagrams: dict, counterparts: list, resamples: int) -> float:
    """Seconds of one `p1_validation` call."""
    start = time.perf_counter()
    p1_validation(measures, diagrams=diagrams, counterparts=counterparts, resamples=resamples, seed=0)
    return time.perf_counter() - start


def describe_input(measures: dict) -> dict:
    """What the timed results are: per system its realizations and ρ points, and the build's config (the file under
    config/ whose hash the measures record, where one matches; else its SHA-256)."""
    import yaml

    from forcenet.datasets.runs import config_sha256

    shipped = {config_sha256(yaml.safe_load(path.read_text())): f"config/{path.name}"
               for path in sorted((records.REPO / "config").glob("*.yaml"))}
    hashes = sorted({ds.attrs.get("config_sha256", "") for ds in measures.values()})
    return {"systems": {name: {"realizations": int(ds.sizes.get("realization", 1)), "rho_points": int(ds.sizes["rho"])}
                        for name, ds in sorted(measures.items())},
            "config": [shipped.get(sha, sha) for sha in hashes]}


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--results", type=Path, default=Path("results"), help="a build's results folder")
    parser.add_argument("--resamples", type=int, default=20, help="bootstrap resamples of the timed run")
    parser.add_argument("--repeat", type=int, default=3)
    records.add_no_record(parser)
    args = parser.parse_args(argv)
    run = records.Run("p1_table", enabled=records.wanted(args, argv),
                      settings=dict(resamples=args.resamples, repeat=args.repeat,
                                    job_resamples=ROBUSTNESS_RESAMPLES))
    measures, diagrams, counterparts = read_results(args.results)
    if not measures:
        run.not_measured(f"no build's results (<system>/network_measures.nc with diagrams.nc) under {args.results}")
        raise SystemExit(f"no <system>/network_measures.nc with its diagrams.nc under {args.results}: build first "
                         f"(.venv/bin/snakemake --cores 2)")
    timed(measures, diagrams, counterparts, 0)  # warm-up: imports, first-touch caches
    passes = [timed(measures, diagrams, counterparts, 0) for _ in range(args.repeat)]
    pass_s = statistics.median(passes)
    realizations = {name: int(ds.sizes.get("realization", 1)) for name, ds in sorted(measures.items())}
    result = {"systems": sorted(measures), "realizations": realizations, "pass_s": round(pass_s, 3),
              "resample_s": None, "job_estimate_s": None}
    if max(realizations.values()) < 2:  # one realization per system: a resample is the same sample, not timed
        print(f"one pass {pass_s:.2f} s; one realization per system, so no resample is timed")
    else:
        with_resamples = [timed(measures, diagrams, counterparts, args.resamples) for _ in range(args.repeat)]
        resample_s = (statistics.median(with_resamples) - pass_s) / max(args.resamples, 1)
        result.update(resample_s=round(resample_s, 3),
                      job_estimate_s=round(pass_s + ROBUSTNESS_RESAMPLES * resample_s, 1))
        print(f"one pass {pass_s:.2f} s, one resample {resample_s:.3f} s, so about "
              f"{result['job_estimate_s']:.0f} s for {ROBUSTNESS_RESAMPLES} resamples")
    run.write(measured={**result, "input": describe_input(measures)})
    print(json.dumps(result))


if __name__ == "__main__":
    main()
