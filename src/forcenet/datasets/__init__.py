"""netCDF data model of forcenet: schema, provenance, atomic writing, validation."""
from forcenet.datasets.io import (SchemaError, git_commit, open_dataset, provenance_attrs, validate_dataset,
                                  write_netcdf)
from forcenet.datasets.snapshot import read_snapshot, snapshot_dataset, write_snapshot

__all__ = ["SchemaError", "git_commit", "open_dataset", "provenance_attrs", "read_snapshot", "snapshot_dataset",
           "validate_dataset", "write_netcdf", "write_snapshot"]
