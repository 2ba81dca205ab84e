#!/usr/bin/env python3
"""What a float32 campaign record would change: every state of a record analysed as recorded and with positions and
forces rounded to float32, the measures that move listed (forcenet.research.record_precision).

    .venv/bin/python scripts/record_precision.py data/validation/2d_linear_contacts/r00/states.nc 2d_linear_contacts
    .venv/bin/python scripts/record_precision.py data/validation/2d_hertz/r00/states.nc 2d_hertz --round position
"""
from __future__ import annotations

import argparse
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "src"))

from forcenet.research.record_precision import ROUNDED, float32_differences  # noqa: E402


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("record", type=Path)
    parser.add_argument("system")
    parser.add_argument("--round", nargs="+", default=list(ROUNDED), metavar="ARRAY",
                        help=f"the snapshot arrays to round (default: {' '.join(ROUNDED)})")
    args = parser.parse_args()
    differences = float32_differences(args.record, args.system, rounded_arrays=tuple(args.round))
    print("| network | measure | largest relative difference over the states |\n|---|---|---|")
    for (kind, name), value in sorted(differences.items()):
        if value:
            print(f"| {kind} | {name} | {value:.3g} |")
    print(f"\n{sum(1 for v in differences.values() if not v)} of {len(differences)} measures identical")
    return 0


if __name__ == "__main__":
    sys.exit(main())
