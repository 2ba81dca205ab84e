#!/usr/bin/env python3
"""Continue a compression run from its checkpoint under other normal dampings, to see what a blow-up depends on.

    .venv/bin/python scripts/probe_checkpoint.py config/validation.yaml 2d_hertz \
        results/validation/sim/2d_hertz/r04/.partial/checkpoint.npz --gamma-n 22.1807 15.6841 1.3863 [--grid-steps 2]

The checkpoint's state (written after its last snapshot) is continued through the next `--grid-steps` values of
the system's ρ grid with P1's protocol (compression at the wall speed, relaxation), once per γ_n (the tangential
damping scaled with it, as the config ties them); nothing is written. For each it prints the last ρ reached, the
largest λΔt of the stability check, the blow-up message if one came, and the CPU seconds. The first γ_n given
should be the run's own: it must reproduce the run.
"""
from __future__ import annotations

import argparse
import logging
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "src"))

import numpy as np  # noqa: E402

from forcenet.dem._kernels.law import LAW_GAMMA_N, LAW_GAMMA_T  # noqa: E402
from forcenet.dem.engine import Simulation, SimulationBlowUp  # noqa: E402
from forcenet.dem import protocol  # noqa: E402
from forcenet.systems import system_from_config  # noqa: E402
from forcenet.workflow_io import read_config_file  # noqa: E402


def probe(system, state: dict, gamma_n: float, grid_steps: int, log: logging.Logger) -> dict:
    """Continue `state` (a checkpoint's arrays) with normal damping `gamma_n` through `grid_steps` grid values."""
    sim = Simulation.from_state_dict(state)
    ratio = sim.law[LAW_GAMMA_T] / sim.law[LAW_GAMMA_N] if sim.law[LAW_GAMMA_N] else 0.0
    sim.law[LAW_GAMMA_N], sim.law[LAW_GAMMA_T] = gamma_n, gamma_n * ratio
    start = int(state["next_index"])
    progress = protocol._Progress(log, system, sim, start)
    reached, largest, message = float(sim.packing_fraction), 0.0, ""
    cpu = time.process_time()
    for index in range(start, min(start + grid_steps, len(system.rho_grid))):
        try:
            protocol._compress_to(sim, protocol.wall_shift_for(sim, system.rho_grid[index]), index, progress,
                                  system.wall_speed, stop_walls=True)
            protocol._relax(sim, system, index, progress, log)
            largest = max(largest, protocol.check_damping_is_integrable(sim, system))
        except SimulationBlowUp as error:
            message = f"{error} (step {error.step}, particle {error.particle}, ρ {error.rho:.4f})"
            break
        reached = float(sim.packing_fraction)
    return {"gamma_n": gamma_n, "last_rho": reached, "max_damping_dt": largest, "blow_up": message,
            "cpu_s": time.process_time() - cpu}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("config")
    parser.add_argument("system")
    parser.add_argument("checkpoint")
    parser.add_argument("--gamma-n", type=float, nargs="+", required=True)
    parser.add_argument("--grid-steps", type=int, default=2)
    args = parser.parse_args()
    logging.basicConfig(level=logging.WARNING, format="%(asctime)s %(levelname)s %(message)s")
    log = logging.getLogger("probe")
    system = system_from_config(args.system, read_config_file(args.config))
    with np.load(args.checkpoint, allow_pickle=False) as data:
        state = {key: data[key] for key in data.files}
    print(f"{args.system}: from step {int(state['step'])}, next grid value "
          f"{system.rho_grid[int(state['next_index'])]}, γ_n of the run {float(state['law'][LAW_GAMMA_N]):.6g}")
    for gamma_n in args.gamma_n:
        row = probe(system, state, gamma_n, args.grid_steps, log)
        print(f"γ_n {row['gamma_n']:.6g}: last ρ {row['last_rho']:.4f}, max λΔt {row['max_damping_dt']:.2f}, "
              f"{row['cpu_s']:.0f} CPU-s, {row['blow_up'] or 'no blow-up'}", flush=True)


if __name__ == "__main__":
    main()
