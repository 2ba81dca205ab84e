"""Child process for `distances.dionysus_distances`: reads an .npz on stdin, prints a JSON object.

Kept apart so that a hang inside hera (dionysus' Wasserstein) can be ended by killing this process.
Input arrays are sub-level diagrams (negated super-level points, birth < death), shape (n, 2).
"""
import io
import json
import sys

import dionysus
import numpy as np


def main() -> None:
    data = np.load(io.BytesIO(sys.stdin.buffer.read()))
    diagram_a = dionysus.Diagram([tuple(p) for p in data["a"].tolist()])
    diagram_b = dionysus.Diagram([tuple(p) for p in data["b"].tolist()])
    delta = float(data["hera_delta"])
    # internal_p=-1 is hera's L∞ ground metric (np.inf is NOT understood); delta=0: exact bottleneck
    result = {"bottleneck": dionysus.bottleneck_distance(diagram_a, diagram_b, delta=0),
              "wasserstein_1": dionysus.wasserstein_distance(diagram_a, diagram_b, q=1, delta=delta, internal_p=-1),
              "wasserstein_2": dionysus.wasserstein_distance(diagram_a, diagram_b, q=2, delta=delta, internal_p=-1)}
    json.dump(result, sys.stdout)


if __name__ == "__main__":
    main()
