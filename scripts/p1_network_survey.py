#!/usr/bin/env python3
"""What sets the P1 numbers of finished runs that the P1 claims judge (forcenet.report.p1_diagnostics).

    .venv/bin/python scripts/p1_network_survey.py --results results/validation

Reads `<results>/<system>/network_measures.nc` of each system and prints, in markdown:

1. per system and ρ: Z without rattlers, the share of contacts with F ≥ F_th, S_p at those F_th, the F_th of the
   ⟨S⟩/N peak and of the last percolating network, TP0/N, the rough- and strong-bin N0/N and the share of contacts
   with F ≥ 2.5 ⟨F⟩ (the strong bin's births);
2. where 2d_linear and 2d_hertz both ran: S_p(linear) − S_p(Hertz) at the ρ both sampled beyond their ρ_J;
3. the verdicts of P1 §5.2's S_p claims under the two readings of P1's definition (pooled over the clusters of a
   realization, as the tables; or the mean over clusters);
4. per realization: its own ρ_J (inflection of its Z), Z without rattlers and the particles of the rattler-free
   network at the system's last state before the jump of Z and its first jammed state, and near its ρ_J the
   readings of the damping series (`forcenet.research.damping_series.network_readings`: the largest B0/N at
   F_th < 0.5, weak- and strong-bin N0/N, ⟨S⟩/N at the lowest F_th);
5. below jamming (the states up to the last one before the jump of Z, as the judges take them): per system the
   contacts per state, the std of F/⟨F⟩ of the mean force PDF, the largest B0/N and ⟨S⟩/N at F_th < 0.5 of the
   last states before the jump and the first jammed one, and the total-variation distance between the mean PDFs
   of every two systems (p1-6-pdf-2d-3d-differ-below-jamming's measure);
6. where the snapshots are under `<results>/sim/`: per realization, at the state p1-3-overlap judges (nearest
   ρ_J + P1's depth above jamming), the largest relative overlap, whether its pair touches a wall, the largest
   one away from the walls, and the 99th percentile and median over the contacts (`overlap_survey.py` gives
   them at the largest ρ).
"""
from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np
import pandas as pd

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "src"))

from forcenet.datasets import read_dataset, read_snapshot  # noqa: E402
from forcenet.datasets.paths import format_rho, network_measures, realization_name, rho_file, run_dir  # noqa: E402
from forcenet.measures.jamming import jamming_point  # noqa: E402
from forcenet.report.claims_table import markdown_table  # noqa: E402
from forcenet.report.p1 import P1_LARGE_THRESHOLD, force_bins, relative_overlaps  # noqa: E402
from forcenet.report.p1_claims import P1_OVERLAP_DEPTH  # noqa: E402
from forcenet.report.p1_diagnostics import (SHAPE_READINGS, common_rho, network_rows, shape_readings,  # noqa: E402
                                            with_shape_reading)
from forcenet.report.p1_judging import SystemData  # noqa: E402
from forcenet.report.p1_validation import p1_validation, system_data  # noqa: E402
from forcenet.report.realizations import realization_mean  # noqa: E402
from forcenet.research.damping_series import SeriesRun, network_readings  # noqa: E402


def per_realization_rows(results: str, system: SystemData) -> pd.DataFrame:
    """One row per realization of `system`: its own ρ_J (inflection of its Z), Z without rattlers and the
    particles of the rattler-free network (at the lowest F_th) at the system's last state before the jump of Z
    and its first jammed state, and the damping series' readings near its ρ_J (`network_readings`)."""
    before, after = (int(np.argmin(np.abs(system.rho - rho))) for rho in system.jump)
    rows = []
    for realization in system.data["realization"].values:
        run = system.data.sel(realization=realization)
        rho_j = float(jamming_point(run["rho_measured"].values, run["Z"].values[None, :]))
        particles = run["cluster_particle_count"].isel(threshold=int(np.argmin(system.thresholds))).values
        row = {"system": system.name, "run": realization_name(int(realization)), "rho_J": round(rho_j, 4),
               "Z_no_rattlers before -> after the jump": f"{run['Z_no_rattlers'].values[before]:.3g} -> "
                                                          f"{run['Z_no_rattlers'].values[after]:.3g}",
               "network particles before -> after": f"{particles[before]:.0f} -> {particles[after]:.0f}"}
        readings = network_readings(SeriesRun(Path(results), system.name, int(realization)), rho_j)
        row.update({key: f"{value:.4g}" for key, value in readings.items()})
        rows.append(row)
    return pd.DataFrame(rows)


def below_jamming_pdf(system: SystemData) -> tuple[np.ndarray, np.ndarray]:
    """The mean PDF of F/⟨F⟩ over the realizations and the states below jamming, normalised over the bins, as
    p1-6-pdf-2d-3d-differ-below-jamming's judge takes it: (bin centres, probability per bin)."""
    pdf = system.data["force_pdf"].isel(rho=np.flatnonzero(system.below)).mean(("realization", "rho"), skipna=True)
    centres, widths = force_bins(system.data)
    mass = np.asarray(pdf.values, dtype=float) * widths
    return centres, mass / mass.sum()


def near_jump_curves(system: SystemData, before: int = 6) -> str:
    """The largest mean B0/N and ⟨S⟩/N over F_th < 0.5 ⟨F⟩ (the curves of p1-5.1-b0-ridge and
    p1-6-cluster-size-peak-small-threshold) at the `before` states up to the last one before the jump of Z and at the
    first jammed state, as text."""
    small = system.thresholds < 0.5
    b0 = system.mean("betti", homology_dim=0).transpose("rho", "threshold").values[:, small]
    size = system.mean("cluster_mean_size").transpose("rho", "threshold").values[:, small]
    last = int(np.argmin(np.abs(system.rho - system.jump[0])))
    return ", ".join(f"{system.rho[k]:.2f}: {np.nanmax(b0[k]):.2g} | {np.nanmax(size[k]):.2g}"
                     for k in range(max(0, last - before + 1), min(system.rho.size, last + 2)))


def below_jamming_lines(systems: dict[str, SystemData]) -> list[str]:
    """Per system with states below jamming: those states, the contacts per state (realization mean, lowest F_th),
    the std of F/⟨F⟩ of the mean PDF and `near_jump_curves`; then the total-variation distance between the mean
    PDFs of every two of them (`below_jamming_pdf`)."""
    lines, pdfs = [], {}
    for name, system in systems.items():
        if not system.below.any():
            lines.append(f"- {name}: no state below jamming")
            continue
        centres, mass = pdfs[name] = below_jamming_pdf(system)
        contacts = realization_mean(system.data["edge_count"].isel(threshold=int(np.argmin(system.thresholds))))
        below = contacts.values[system.below]
        std = float(np.sqrt((mass * (centres - (mass * centres).sum()) ** 2).sum()))
        lines.append(f"- {name}: {system.states(system.below)}, contacts per state (realization mean) "
                     f"{below.min():.0f}-{below.max():.0f}, std of F/<F> {std:.3f}")
        lines.append(f"  - largest B0/N | <S>/N at F_th < 0.5 by rho, up to the first jammed state: "
                     f"{near_jump_curves(system)}")
    names = list(pdfs)
    for i, first in enumerate(names):
        for second in names[i + 1:]:
            if pdfs[first][0].shape == pdfs[second][0].shape and np.allclose(pdfs[first][0], pdfs[second][0]):
                distance = 0.5 * float(np.abs(pdfs[first][1] - pdfs[second][1]).sum())
                lines.append(f"- total-variation distance {first} - {second}: {distance:.3f}")
    return lines


def overlap_rows(results: str, system: SystemData) -> pd.DataFrame:
    """Per realization with snapshots under `results`/sim, at the grid state nearest ρ_J + `P1_OVERLAP_DEPTH`
    (the one p1-3-overlap judges): the largest relative overlap, whether its pair touches a wall, the largest one
    away from the walls, the 99th percentile and the median (`relative_overlaps`)."""
    rho = float(system.rho[int(np.argmin(np.abs(system.rho - (system.rho_j + P1_OVERLAP_DEPTH))))])
    rows = []
    for realization in system.data["realization"].values:
        path = Path(run_dir(results, system.name, realization_name(int(realization)))) / rho_file(format_rho(rho))
        if not path.exists():
            continue
        with read_snapshot(path) as snapshot:
            overlaps, at_wall = relative_overlaps(snapshot)
        k = int(np.argmax(overlaps))
        rows.append({"system": system.name, "run": realization_name(int(realization)), "rho": f"{rho:.3f}",
                     "largest": f"{overlaps[k]:.4f}", "its pair touches a wall": "yes" if at_wall[k] else "no",
                     "largest away from the walls": f"{overlaps[~at_wall].max():.4f}" if (~at_wall).any() else "–",
                     "99th percentile": f"{np.percentile(overlaps, 99):.4f}", "median": f"{np.median(overlaps):.4f}"})
    return pd.DataFrame(rows)


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

    print("\n## Per realization: its own rho_J; near it (|rho - rho_J| <= 0.02) the damping series' readings\n")
    table = pd.concat([per_realization_rows(args.results, system) for system in systems.values()], ignore_index=True)
    print("\n".join(markdown_table(table, list(table.columns))))

    print("\n## Below jamming (the states up to the last one before the jump of Z): the mean force PDFs\n")
    print("\n".join(below_jamming_lines(systems)))

    overlaps = [overlap_rows(args.results, system) for system in systems.values()]
    overlaps = [frame for frame in overlaps if len(frame)]
    if overlaps:
        print(f"\n## Overlaps at the state nearest rho_J + {P1_OVERLAP_DEPTH:g} (p1-3-overlap's), per realization\n")
        table = pd.concat(overlaps, ignore_index=True)
        print("\n".join(markdown_table(table, list(table.columns))))


if __name__ == "__main__":
    main()
