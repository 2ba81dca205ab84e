"""How P2's distances depend on the sampling: the measurement behind docs/p2_sampling.md.

One realization of a P2 system (its `config/config.yaml` entry: box, particles, seed of realization 0) is
compressed at each given wall speed through P2's sampling grid (`--count` states from ρ = 0.63 to 0.90);
then d_B, d_W1, d_W2 between the normal-force diagrams of states k samples apart (k = `--lags`) are summarised
over three ρ windows (`forcenet.report.p2_distances.lagged_distance_summary`). Snapshots are kept under `--out` and
reused by a rerun with the same settings (`pipeline.simulate` resumes or skips).

    .venv/bin/python scripts/p2_sampling.py --speeds 2e-3 2.5e-4 2.5e-5 --out results/p2_sampling

prints the Markdown table (and writes it to ``{out}/p2_sampling.md``).
"""
from __future__ import annotations

import argparse

from forcenet.catalog import load_run_config
from forcenet.pipeline_p2 import p2_sampling_study


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--config", default="config/config.yaml", help="config whose system entry is used")
    parser.add_argument("--system", default="2d_poly_mu05")
    parser.add_argument("--speeds", type=float, nargs="+", default=[2e-3, 2.5e-4], help="wall speeds [d_ave/τ_c]")
    parser.add_argument("--count", type=int, default=100, help="states from ρ = 0.63 to 0.90 (P2: ~100)")
    parser.add_argument("--lags", type=int, nargs="+", default=[1, 2, 4, 8, 16])
    parser.add_argument("--rattlers", default="none", help="rattler rule (P2: none, i.e. kept)")
    parser.add_argument("--out", default="results/p2_sampling")
    parser.add_argument("--simulate-only", action="store_true", help="stop after the compression runs")
    args = parser.parse_args()
    config = load_run_config(args.config)
    table = p2_sampling_study(config=config, system=args.system, wall_speeds=args.speeds, count=args.count,
                              lags=args.lags, rattler_rule=args.rattlers, out=args.out,
                              simulate_only=args.simulate_only)
    if table:
        print(table)


if __name__ == "__main__":
    main()
