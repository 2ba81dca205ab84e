"""What storing a campaign record's positions and forces in float32 would change (data/validation/README.md, "Size"):
every state of a record analysed as recorded (float64) and with its positions and forces rounded to float32, each
single-snapshot measure compared (`forcenet.pipeline.snapshot_measures`). Run by scripts/record_precision.py."""
from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import xarray as xr

#: the snapshot arrays a float32 record would round
ROUNDED = ("position", "force_normal", "force_tangential", "wall_contact_force")


def numeric_parts(measures, prefix: str = "") -> dict[str, np.ndarray]:
    """Every numeric array of a `SnapshotMeasures` by dotted name, its cluster curves and diagrams included
    (``clusters.cluster_count``, ``diagrams.birth``)."""
    parts = {}
    for name, value in vars(measures).items():
        if hasattr(value, "__dataclass_fields__"):
            parts.update(numeric_parts(value, f"{prefix}{name}."))
            continue
        try:
            parts[prefix + name] = np.asarray(value, dtype=float)
        except (TypeError, ValueError):
            continue  # not a numeric measure
    return parts


def float32_differences(record_path: str | Path, system: str, dtype: type = np.float32,
                        rounded_arrays: tuple[str, ...] = ROUNDED) -> dict[tuple[str, str], float]:
    """{(force kind, measure): the largest relative difference over the record's states} between the analysis of each
    state as recorded and of the same state with `rounded_arrays` (default `ROUNDED`) rounded to `dtype` (0: identical; a count that
    moves by one of ten gives 0.1; inf: a diagram with another number of points). The analysis settings are those of the config the record's snapshots record."""
    from forcenet import pipeline
    from forcenet.datasets.records import state_snapshot
    from forcenet.datasets.snapshot import snapshot_dataset

    with xr.open_dataset(record_path) as opened:
        record = opened.load()
    config = json.loads(json.loads(record.attrs["snapshot_attrs"])["config"])
    params = pipeline.snapshot_analysis_params(config, system)
    largest: dict[tuple[str, str], float] = {}
    for index in range(record.sizes["state"]):
        attrs, arrays = state_snapshot(record, index)
        rounded = {name: np.asarray(value, dtype=dtype).astype(float) if name in rounded_arrays else value
                   for name, value in arrays.items()}
        exact = pipeline.snapshot_measures(snapshot_dataset(attrs=attrs, **arrays), params)
        approximate = pipeline.snapshot_measures(snapshot_dataset(attrs=attrs, **rounded), params)
        for kind, measures in exact.items():
            others = numeric_parts(approximate[kind])
            for name, a in numeric_parts(measures).items():
                b = others[name]
                if a.shape != b.shape or not np.array_equal(np.isfinite(a), np.isfinite(b)):
                    difference = np.inf
                else:
                    both = np.isfinite(a)
                    difference = float(np.max(np.abs(a[both] - b[both]) / np.maximum(np.abs(a[both]), 1e-300),
                                              initial=0.0))
                largest[(kind, name)] = max(largest.get((kind, name), 0.0), difference)
    return largest
