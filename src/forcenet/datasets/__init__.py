"""netCDF data model of forcenet: schema, provenance, atomic writing, validation at write and read time, the
readers of what the files hold (snapshots, diagram points) and the paths of every file a build writes (`paths`).

The names below are imported on first use (PEP 562), so that `forcenet.datasets.paths` and
`forcenet.datasets.schema` load without xarray: the workflow imports `paths` when it is parsed."""
from __future__ import annotations

from forcenet._lazy import lazy_exports

#: public name → the submodule that defines it
_EXPORTS = {
    "DiagramPoints": "diagrams", "diagram_points": "diagrams",
    "DatasetError": "io", "SchemaError": "io", "git_commit": "io", "open_dataset": "io", "optional_attr": "io",
    "provenance_attrs": "io", "read_dataset": "io", "validate_dataset": "io", "write_netcdf": "io",
    "read_snapshot": "snapshot", "snapshot_dataset": "snapshot", "write_snapshot": "snapshot",
    "run_expectation": "runs", "run_mismatch": "runs",
}

__all__ = sorted(_EXPORTS)


__getattr__, __dir__ = lazy_exports(__name__, _EXPORTS, globals())
