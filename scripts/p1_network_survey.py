#!/usr/bin/env python3
"""What sets the P1 numbers of finished runs that the P1 claims judge (forcenet.report.p1_diagnostics).

    .venv/bin/python scripts/p1_network_survey.py --results results/validation

Reads `<results>/<system>/network_measures.nc` of each system and prints, in markdown:

1. per system and ρ: Z without rattlers, the share of contacts with F ≥ F_th, S_p at those F_th, the F_th of the
   ⟨S⟩/N peak and of the last percolating network, TP0/N, the rough- and strong-bin N0/N and the share of contacts
   with F ≥ 2.5 ⟨F⟩ (the strong bin's births);
2. where 2d_linear and 2d_hertz both ran: S_p(linear) − S_p(Hertz) at the ρ both sampled beyond their ρ_J;
3. the verdicts of P1 §5.2's S_p claims under the two readings of P1's definition (pooled over the clusters of a
   realization, as the tables; or the mean over clusters).
"""
from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "src"))

from forcenet.datasets import read_dataset  # noqa: E402
from forcenet.datasets.paths import network_measures  # noqa: E402
from forcenet.report.claims_table import markdown_table  # noqa: E402
from forcenet.report.p1 import P1_LARGE_THRESHOLD  # noqa: E402
from forcenet.report.p1_diagnostics import (SHAPE_READINGS, common_rho, network_rows, shape_readings,  # noqa: E402
                                            with_shape_reading)
from forcenet.report.p1_validation import p1_validation, system_data  # noqa: E402


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--results", default="results/validation", help="the results_dir of the runs' config")
    parser.add_argument("--systems", nargs="+", default=["2d_linear", "2d_hertz", "3d_hertz"])
    args = parser.parse_args()

    measures = {name: read_dataset(network_measures(args.results, name), "network_measures").load()
                for name in args.systems}
    systems = {name: system_data(name, ds) for name, ds in measures.items()}
    for name, system in systems.items():
        keep = system.rho >= system.rho_j - system.tolerance
        print(f"\n## {name}: rho_J = {system.rho_j:.3f}, beyond rho_J + {system.tolerance:g} judged as jammed\n")
        rows = network_rows(system)[keep]
        print("\n".join(markdown_table(rows, list(rows.columns))))

    if {"2d_linear", "2d_hertz"} <= systems.keys():
        linear, hertz = systems["2d_linear"], systems["2d_hertz"]
        rho = common_rho(linear, hertz)
        print(f"\n## S_p(2d_linear) - S_p(2d_hertz) at the common rho beyond both rho_J: {np.round(rho, 3).tolist()}\n")
        for reading in SHAPE_READINGS:
            a, b = (shape_readings(s)[reading][0].sel(rho=rho, method="nearest") for s in (linear, hertz))
            difference = (a - b).where((a != 0) & (b != 0))
            small = difference.where(difference.threshold < P1_LARGE_THRESHOLD - 1e-12)
            cells = ", ".join(f"F_th {t:g}: " + " ".join(f"{v:+.3f}" for v in difference.sel(threshold=t).values)
                              for t in (0.5, 1.0, 1.5))
            print(f"- {reading}: mean over F_th < 2 {float(small.mean()):+.3f}; per rho at {cells}")

    print("\n## P1 §5.2 claims under each reading of S_p\n")
    print("| claim | system | reading | measured | verdict |\n|---|---|---|---|---|")
    for reading in SHAPE_READINGS:
        table = p1_validation({n: with_shape_reading(ds, reading) for n, ds in measures.items()})
        for row in table[table["id"].str.startswith("p1-5.2-shape")].itertuples():
            print(f"| {row.id} | {row.system} | {reading} | {row.measured:.3g} | {row.verdict} |")


if __name__ == "__main__":
    main()
