"""Write the shipped sequence example: 12 states of one 2D packing sheared at constant packing fraction, as contact
tables (`source.format: table`, `forces: magnitudes`), in millimetres and newtons (config/example_sequence.yaml).

    .venv/bin/python data/examples/table_shear_2d/make_sequence.py      # rewrites state*.csv beside this script

100 disks of radius 0.52 ± 0.01 mm on a 10 × 10 square lattice of spacing 1 mm in the box [0, 10]² mm: every state
has the same disks and box, so the same ρ (0.8525). State k is the lattice sheared by the strain γ_k = 0.002 k
(x ← x + γ_k (y − 5)) plus a random walk of the centres (0.004 mm per state, seed 56), so consecutive states differ a
little and the force network changes along the strain. Contacts: lattice neighbours that overlap, and disks that
cross a wall (x_lo, x_hi, y_lo, y_hi); the normal force is 25 N/mm times the overlap, the tangential force's
magnitude 0.3 of it times |sin| of the contact's angle. Standard library and numpy only; the output is identical on
every run (the seed).
"""
from __future__ import annotations

import math
from pathlib import Path

import numpy as np

STATES = 12
STRAIN_STEP = 0.002
SIDE = 10
STIFFNESS = 25.0  # N/mm
SEED = 56
FOLDER = Path(__file__).resolve().parent


def strains() -> list[float]:
    """The strain of each state (config/example_sequence.yaml's source.sequence.values)."""
    return [round(STRAIN_STEP * k, 6) for k in range(STATES)]


def states():
    """(positions (N, 2), radii (N,)) of every state, in order."""
    rng = np.random.default_rng(SEED)
    grid = np.array([(i + 0.5, j + 0.5) for j in range(SIDE) for i in range(SIDE)], dtype=float)
    radius = 0.52 + 0.01 * rng.uniform(-1.0, 1.0, len(grid))
    walk = np.zeros_like(grid)
    for gamma in strains():
        walk += 0.004 * rng.standard_normal(grid.shape)
        position = grid + walk
        position[:, 0] += gamma * (grid[:, 1] - SIDE / 2)
        yield position, radius


def contacts(position: np.ndarray, radius: np.ndarray) -> list[tuple[str, str, float, float]]:
    """(i, j, fn, ft) of every overlapping lattice neighbour pair and wall contact (ids from 1)."""
    rows = []
    for a in range(len(position)):
        i, j = a % SIDE, a // SIDE
        for b in ([a + 1] if i + 1 < SIDE else []) + ([a + SIDE] if j + 1 < SIDE else []):
            branch = position[a] - position[b]
            overlap = radius[a] + radius[b] - math.hypot(*branch)
            if overlap > 0:
                fn = STIFFNESS * overlap
                rows.append((str(a + 1), str(b + 1), fn, 0.3 * fn * abs(math.sin(math.atan2(branch[1], branch[0])))))
        for axis, name in ((0, "x"), (1, "y")):
            for side, gap in (("lo", position[a, axis] - radius[a]), ("hi", SIDE - position[a, axis] - radius[a])):
                if gap < 0:
                    rows.append((str(a + 1), f"{name}_{side}", -STIFFNESS * gap, 0.0))
    return rows


def main() -> None:
    for k, (position, radius) in enumerate(states()):
        with open(FOLDER / f"state{k:02d}_particles.csv", "w", encoding="utf-8") as out:
            out.write(f"# state {k} of the sheared sequence: strain {strains()[k]:g}, lengths in mm (make_sequence.py)\n")
            out.write("id,x,y,radius\n")
            out.writelines(f"{n + 1},{x:.6f},{y:.6f},{r:.6f}\n" for n, ((x, y), r) in enumerate(zip(position, radius)))
        with open(FOLDER / f"state{k:02d}_contacts.csv", "w", encoding="utf-8") as out:
            out.write(f"# state {k}: forces in N, fn = {STIFFNESS:g} N/mm x overlap, ft its tangential magnitude\n")
            out.write("i,j,fn,ft\n")
            out.writelines(f"{i},{j},{fn:.6f},{ft:.6f}\n" for i, j, fn, ft in contacts(position, radius))


if __name__ == "__main__":
    main()
