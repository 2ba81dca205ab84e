#!/usr/bin/env python3
"""The overlaps that decide P1's overlap rows, at the last state of recorded runs: the reading of the wall control
(docs/validation/controls.md, "Plexiglass walls").

    .venv/bin/python scripts/control_walls.py 2d_linear:0 2d_linear_plexiglass:0 2d_hertz:0 2d_hertz_plexiglass:0

Per run (`SYSTEM:REALIZATION`, its record under data/validation/): ρ of its last state; the largest overlap of two
particles relative to r_i + r_j and whether that pair touches a wall (`forcenet.report.p1.relative_overlaps`); the
largest one between particles that touch no wall; the largest overlap of a particle with a wall relative to its
diameter d_i and the median wall stiffness seen, |F_n| / overlap [force unit / d_ave]
(`forcenet.report.p1.relative_wall_overlaps`); the total normal force on each wall; and the largest net force on a
particle over the mean normal force (`forcenet.measures.forces.force_imbalance`, ~0 at rest). Reads the records only.
"""
from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "src"))

from forcenet.datasets.records import read_dataset, state_snapshot  # noqa: E402
from forcenet.datasets.snapshot import snapshot_dataset  # noqa: E402
from forcenet.measures.forces import force_imbalance  # noqa: E402
from forcenet.report.p1 import relative_overlaps, relative_wall_overlaps  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]


def last_state_row(record_path: Path, name: str) -> str:
    """One Markdown row of the table for the last state of the record at `record_path`."""
    record = read_dataset(record_path, "run_record")
    attrs, values = state_snapshot(record, record.sizes["state"] - 1)
    arrays = snapshot_dataset(attrs=attrs, **values)
    pair, at_wall = relative_overlaps(arrays)
    largest = int(np.argmax(pair))
    inner = pair[~at_wall].max() if (~at_wall).any() else float("nan")
    wall, normal = relative_wall_overlaps(arrays)
    touching = wall > 0
    diameter = 2.0 * arrays["radius"].values[arrays["wall_contact_particle"].values]
    stiffness = np.median(normal[touching] / (wall[touching] * diameter[touching]))
    per_wall = [normal[arrays["wall_contact_wall"].values == w].sum() for w in range(2 * arrays.sizes["spatial"])]
    imbalance, _ = force_imbalance(arrays)
    return (f"| {name} | {float(arrays['rho']):.2f} | {pair[largest]:.3f} | {'yes' if at_wall[largest] else 'no'} | "
            f"{inner:.3f} | {wall.max():.3f} | {stiffness:.4g} | {', '.join(f'{f:.4g}' for f in per_wall)} | "
            f"{imbalance:.1e} |")


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("runs", nargs="+", help="SYSTEM:REALIZATION")
    parser.add_argument("--records", type=Path, default=ROOT / "data" / "validation")
    args = parser.parse_args(argv)
    print("| run | rho | largest pair overlap / (r_i + r_j) | its pair touches a wall | largest away from the walls "
          "| largest wall overlap / d_i | median wall F_n / overlap | normal force on each wall | largest net force "
          "/ mean F_n |")
    print("|---|---|---|---|---|---|---|---|---|")
    for run in args.runs:
        system, realization = run.split(":")
        name = f"{system} r{int(realization):02d}"
        print(last_state_row(args.records / system / f"r{int(realization):02d}" / "states.nc", name))
    return 0


if __name__ == "__main__":
    sys.exit(main())
