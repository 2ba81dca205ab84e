#!/usr/bin/env python3
"""Compress one system of a config under overrides and print each snapshot's state (forcenet.research.survey).

    .venv/bin/python scripts/compression_survey.py --config config/config.yaml --system 2d_hertz \
        --set time_step=0.02 --set damping_model=linear_law --realizations 0 1

prints, per run, a markdown table (ρ, bulk ρ, Z, E_kin, pressure, λΔt, largest and mean overlap / smaller
diameter, relaxation steps), the CPU-seconds and ρ_J (logistic fit of Z(ρ); also with ρ over the centres' domain
and with the bulk ρ, the inner box at least `--bulk-margin` d_ave from every wall); `--summary` prints one line per
run instead (system, overrides, realization, the three ρ_J, CPU-s, top-of-grid ρ and Z, outcome). Overrides
replace keys of `systems.<system>` (dotted keys reach into nested ones; values are YAML).
"""
from __future__ import annotations

import argparse
import logging
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "src"))

from forcenet.catalog import load_run_config  # noqa: E402
from forcenet.research.survey import BULK_MARGIN, apply_overrides, run_survey  # noqa: E402


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--config", default="config/config.yaml")
    parser.add_argument("--system", required=True)
    parser.add_argument("--set", action="append", default=[], metavar="KEY=VALUE", dest="overrides")
    parser.add_argument("--realizations", type=int, nargs="+", default=[0])
    parser.add_argument("--summary", action="store_true", help="one line per run (ρ_J, CPU-s, top-of-grid state)")
    parser.add_argument("--verbose", action="store_true", help="show the engine's progress log")
    parser.add_argument("--bulk-margin", type=float, default=BULK_MARGIN,
                        help="bulk ρ: the inner box at least this far from every wall [d_ave]")
    args = parser.parse_args()

    logging.basicConfig(level=logging.INFO if args.verbose else logging.WARNING, format="%(message)s")
    config = apply_overrides(load_run_config(args.config), args.system, args.overrides)
    label = " ".join(args.overrides) or "as configured"
    for realization in args.realizations:
        run = run_survey(config, args.system, realization, bulk_margin=args.bulk_margin)
        top = run.rows[-1] if run.rows else {}
        if args.summary:
            print(f"| {args.system} | {label} | r{realization:02d} | {run.rho_j:.4f} | {run.rho_j_centres:.4f} | "
                  f"{run.rho_j_bulk:.4f} | "
                  f"{run.cpu_seconds:.1f} | "
                  f"{top.get('rho', float('nan')):.3f} | {top.get('Z', float('nan')):.2f} | "
                  f"{'stopped: ' + run.failure if run.failure else 'completed'} |", flush=True)
            continue
        print(f"\n{args.system} ({label}), realization {realization}: {run.cpu_seconds:.1f} CPU-s, "
              f"ρ_J = {run.rho_j:.4f} (ρ over the centres' domain: {run.rho_j_centres:.4f}; "
              f"bulk ρ: {run.rho_j_bulk:.4f})" + (f"\nSTOPPED: {run.failure}" if run.failure else ""))
        print("| ρ | bulk ρ | Z | E_kin | pressure | λΔt | overlap max | overlap mean | relaxation steps |")
        print("|---|---|---|---|---|---|---|---|---|")
        for row in run.rows:
            print(f"| {row['rho']:.3f} | {row['rho_bulk']:.4f} | {row['Z']:.2f} | {row['kinetic_energy']:.2e} | "
                  f"{row['pressure']:.3g} | "
                  f"{row['damping_dt']:.2f} | {row['overlap_max']:.3f} | {row['overlap_mean']:.4f} | "
                  f"{row['relaxation_steps']} |", flush=True)


if __name__ == "__main__":
    main()
