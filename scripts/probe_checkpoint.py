#!/usr/bin/env python3
"""Continue a compression run from its checkpoint under other normal dampings, to see what a blow-up depends on.

    .venv/bin/python scripts/probe_checkpoint.py config/validation.yaml 2d_hertz \
        results/validation/sim/2d_hertz/r04/.partial/checkpoint.npz --gamma-n 22.1807 15.6841 1.3863 [--grid-steps 2]

The checkpoint's state (written after its last snapshot) is continued through the next `--grid-steps` values of
the system's ρ grid with the run's protocol, once per γ_n (`forcenet.dem.protocol.continue_with_damping`; the
tangential damping scaled with it); nothing is written. For each it prints the last ρ reached, the largest λΔt of
the stability check, the blow-up message if one came, and the CPU seconds. The run's own γ_n reproduces the run.
"""
from __future__ import annotations

import argparse
import logging
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "src"))

import numpy as np  # noqa: E402

from forcenet.checks import checked_system  # noqa: E402
from forcenet.dem.protocol import continue_with_damping  # noqa: E402
from forcenet.workflow_io import read_config_file  # noqa: E402


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("config")
    parser.add_argument("system")
    parser.add_argument("checkpoint")
    parser.add_argument("--gamma-n", type=float, nargs="+", required=True)
    parser.add_argument("--grid-steps", type=int, default=2)
    args = parser.parse_args()
    logging.basicConfig(level=logging.WARNING, format="%(asctime)s %(levelname)s %(message)s")
    system = checked_system(args.system, read_config_file(args.config))
    with np.load(args.checkpoint, allow_pickle=False) as data:
        state = {key: data[key] for key in data.files}
    print(f"{args.system}: from step {int(state['step'])}, next grid value "
          f"{system.rho_grid[int(state['next_index'])]}")
    for gamma_n in args.gamma_n:
        cpu = time.process_time()
        _, row = continue_with_damping(system, state, gamma_n, args.grid_steps)
        print(f"γ_n {gamma_n:.6g}: last ρ {row['last_rho']:.4f}, max λΔt {row['max_damping_dt']:.2f}, "
              f"{time.process_time() - cpu:.0f} CPU-s, {row['blow_up'] or 'no blow-up'}", flush=True)


if __name__ == "__main__":
    main()
