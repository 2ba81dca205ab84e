"""netCDF data model of forcenet: schema, provenance, atomic writing, validation at write and read time, and the
readers of what the files hold (snapshots, diagram points)."""
from forcenet.datasets.diagrams import DiagramPoints, diagram_points
from forcenet.datasets.io import (DatasetError, SchemaError, git_commit, open_dataset, provenance_attrs, read_dataset,
                                  validate_dataset, write_netcdf)
from forcenet.datasets.snapshot import read_snapshot, snapshot_dataset, write_snapshot

__all__ = ["DatasetError", "DiagramPoints", "SchemaError", "diagram_points", "git_commit", "open_dataset",
           "provenance_attrs", "read_dataset", "read_snapshot", "snapshot_dataset", "validate_dataset", "write_netcdf",
           "write_snapshot"]
