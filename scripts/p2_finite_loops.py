#!/usr/bin/env python3
"""How much of P2's loop (β1) curves before jamming is made of never-dying classes: the measurement behind the
reading of the `drop` control (docs/validation/controls.md §3).

    .venv/bin/snakemake validation_report_p2 --configfile config/validation.yaml --cores 2
    .venv/bin/python scripts/p2_finite_loops.py results/validation

Per P2 system, from its distances under P2's death −1 (`<results>/<system>/distances.nc`) and with never-dying
classes left out (`<results>/readings/essential_convention-drop/<system>/distances.nc`): ρ_J (the realization-mean Z
reaching d + 1, `forcenet.report.p2.jamming_density`); the share of consecutive pairs (realization × ρ) before ρ_J
whose normal-force β1 d_B is above zero under each convention; and the first ρ where the realization-mean β1 d_B is
above zero. A share near 0 under `drop` means that the β1 distances before jamming come from never-dying loops alone
(loops no force level fills with triangles), so every β1 claim before jamming is judged on them.
"""
from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "src"))

from forcenet.datasets.io import open_dataset  # noqa: E402
from forcenet.report.p2 import jamming_density  # noqa: E402
from forcenet.report.realizations import realization_mean  # noqa: E402

SYSTEMS = ("2d_poly_mu05", "2d_poly_mu0")
DROP_FOLDER = "readings/essential_convention-drop"


def loop_row(results: Path, system: str) -> str:
    """One Markdown row: ρ_J, then per convention the share of pairs before ρ_J with β1 d_B > 0 and the first ρ
    with a realization-mean β1 d_B > 0."""
    cells = []
    rho_j = np.nan
    for folder in (results, results / DROP_FOLDER):
        path = folder / system / "distances.nc"
        if not path.exists():
            raise SystemExit(f"error: {path} is missing: make it with `snakemake validation_report_p2 "
                             "--configfile config/validation.yaml` (or pass that build's results folder)")
        with open_dataset(path) as ds:
            rho_j = jamming_density(ds, 2) if folder == results else rho_j
            d_b = ds["distance"].sel(force_kind="normal", homology_dim=1, metric="bottleneck")
            rho = ds["rho"].values
            before = d_b.sel(rho=rho[rho < rho_j]).values
            mean = realization_mean(d_b).values
            first = rho[mean > 0][0] if (mean > 0).any() else np.nan
            cells += [f"{100 * np.mean(before > 0):.1f} %", f"{first:.3f}"]
    return f"| {system} | {rho_j:.4f} | " + " | ".join(cells) + " |"


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("results", type=Path, help="results folder of config/validation.yaml (results/validation)")
    args = parser.parse_args(argv)
    print("| system | ρ_J | β1 d_B > 0 before ρ_J, death −1 | first ρ, death −1 | β1 d_B > 0 before ρ_J, drop "
          "| first ρ, drop |")
    print("|---|---|---|---|---|---|")
    for system in SYSTEMS:
        print(loop_row(args.results, system))


if __name__ == "__main__":
    main()
