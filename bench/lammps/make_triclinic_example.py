#!/usr/bin/env python
"""The shipped triclinic LAMMPS example (data/examples/lammps_triclinic_2d/): a packing LAMMPS itself compresses and
shears in a periodic, tilted box, dumped as a physicist's LAMMPS run would dump it, so that a test can check that
`forcenet.importers.lammps` reads LAMMPS's triclinic box and joins each contact to the image of its partner that
LAMMPS used.

usage: python bench/lammps/make_triclinic_example.py [--out DIR]

LAMMPS (bench/lammps/setup.sh) places 200 disks at random (half of diameter 1, half 1.4) in a 2D periodic box
(boundary p p p, a `prism` region), gives them the granular law gran/hooke/history with friction 0.5 and a viscous
drag, and with fix deform shrinks the box and tilts it (xy) in three stages: to ρ 0.85, 0.87, 0.89 at xy = 3, 4, 5
(simple shear of up to 0.33 of the box height). After each stage it relaxes and writes

- ``atoms.dump`` — ``dump custom``: id type x y z radius; its BOX BOUNDS are LAMMPS's triclinic form, the bounding
  box with the tilt factors ("xy xz yz pp pp pp");
- ``pairs.dump`` — ``dump local``: c_pid[1] c_pid[2] (property/local patom1 patom2), c_pf[1] (pair/local force:
  the normal force's magnitude), c_pf[2] c_pf[3] (pair/local fx fy: the same force as a vector on the first atom,
  along the branch vector to the image of the second atom that LAMMPS's neighbour list holds) and c_pf[4..6]
  (pair/local p1 p2 p3: the tangential force on the first atom);
- ``in.lammps`` — the input that made them.

The test reads the normal force once as the magnitude (its direction then comes from forcenet's nearest image in
the tilted box) and once as LAMMPS's vector, and asks for the same forces to the dumps' 10 printed digits. Takes ~3 s.
"""
from __future__ import annotations

import argparse
import math
import shutil
import sys
import tempfile
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
sys.path.insert(0, str(HERE.parent))
from lammps_same_state import LammpsUnavailable, find_lammps  # noqa: E402
from run_lammps import run_lmp  # noqa: E402

REPO = HERE.parent.parent
DISKS = 200
DIAMETERS = (1.0, 1.4)  # half of each, as P1's bidisperse systems
#: (ρ, tilt xy) at the end of each stage
STAGES = ((0.85, 3.0), (0.87, 4.0), (0.89, 5.0))
SEED = 20261128


def lammps_input() -> str:
    """The whole run (module docstring)."""
    area = DISKS / 2 * sum(math.pi * (d / 2) ** 2 for d in DIAMETERS)
    side0 = math.sqrt(area / 0.35)  # start at ρ 0.35, where every disk finds a place
    lines = [
        "units lj", "dimension 2", "atom_style sphere", "boundary p p p", "newton off", "comm_modify vel yes",
        f"region box prism 0 {side0:.6f} 0 {side0:.6f} -0.5 0.5 0 0 0 units box", "create_box 2 box",
        f"create_atoms 1 random {DISKS} {SEED} NULL overlap {DIAMETERS[1]} maxtry 500",
        f"set type 1 type/fraction 2 0.5 {SEED % 100000 + 1}",
        f"set type 1 diameter {DIAMETERS[0]}", f"set type 2 diameter {DIAMETERS[1]}", "set type * density 1.0",
        "velocity all create 0.01 777 dist gaussian",
        "pair_style gran/hooke/history 2000.0 NULL 40.0 NULL 0.5 1", "pair_coeff * *",
        "neighbor 0.3 bin", "neigh_modify delay 0 every 1 check yes", "timestep 0.002",
        "fix integrate all nve/sphere disc", "fix plane all enforce2d", "fix drag all viscous 0.5",
        "compute pid all property/local patom1 patom2", "compute pf all pair/local force fx fy p1 p2 p3",
    ]
    for k, (rho, tilt) in enumerate(STAGES):
        side = math.sqrt(area / rho)
        append = " append yes" if k else ""
        lines += [
            f"fix squeeze all deform 1 x final 0 {side:.6f} y final 0 {side:.6f} xy final {tilt} remap x",
            "run 40000", "unfix squeeze", "run 30000",
            f"write_dump all custom atoms.dump id type x y z radius modify format float %.10g{append}",
            "write_dump all local pairs.dump c_pid[1] c_pid[2] c_pf[1] c_pf[2] c_pf[3] c_pf[4] c_pf[5] c_pf[6] "
            f"modify format float %.10g{append}",
        ]
    return "\n".join(lines) + "\n"


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--out", help="default data/examples/lammps_triclinic_2d")
    args = ap.parse_args(argv)
    try:
        lmp = find_lammps()
    except LammpsUnavailable as error:
        print(f"error: LAMMPS is not available: {error}", file=sys.stderr)
        return 3
    out = Path(args.out or REPO / "data" / "examples" / "lammps_triclinic_2d")
    out.mkdir(parents=True, exist_ok=True)
    with tempfile.TemporaryDirectory(prefix="forcenet_triclinic_") as work:
        work = Path(work)
        (work / "in.lammps").write_text(lammps_input())
        run_lmp(str(lmp), work / "in.lammps", work / "log.lammps")
        for name in ("atoms.dump", "pairs.dump", "in.lammps"):
            shutil.copy(work / name, out / name)
    print(f"wrote {out}/atoms.dump, pairs.dump, in.lammps")
    return 0


if __name__ == "__main__":
    sys.exit(main())
