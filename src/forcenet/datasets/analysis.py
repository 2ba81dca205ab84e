"""Per-snapshot analysis files: results/analysis/{system}/r{NN}/rho{ρ}.nc (layout in `schema.py`)."""
from __future__ import annotations

from typing import Any, Mapping

import numpy as np
import xarray as xr

from forcenet.datasets.io import dataset_from_specs
from forcenet.datasets.schema import ANALYSIS_VARIABLES, FORCE_KINDS, PERSISTENCE_BINS

PER_KIND = ("betti", "cluster_count", "cluster_mean_size", "percolating_size", "percolates", "percolating_count",
            "largest_cluster_size", "shape_parameter", "shape_parameter_cluster_mean", "edge_count",
            "cluster_particle_count", "force_pdf", "mean_force", "persistence_bin_count", "total_persistence",
            "essential_count")


def analysis_dataset(measures: Mapping[str, Any], *, rho: float, attrs: Mapping[str, Any],
                     force_units: str | None = None) -> xr.Dataset:
    """Build the dataset from `SnapshotMeasures` per force kind (keys of FORCE_KINDS, all required). `force_units`:
    the unit of the snapshot's forces, which ``mean_force`` keeps (an imported state's source unit, ``units.force``);
    None, the engine's reduced unit of the schema."""
    kinds = list(FORCE_KINDS)
    first = measures[kinds[0]]
    values = {name: np.stack([np.asarray(getattr(measures[k], name)) for k in kinds]) for name in PER_KIND}
    values["percolates"] = values["percolates"].astype(np.int8)
    values.update(Z=first.Z, Z_no_rattlers=first.Z_no_rattlers, n_particles=first.n_particles, rho=rho)
    points = {"diagram_force_kind": [], "diagram_homology_dim": [], "birth": [], "death": [], "essential": []}
    for index, kind in enumerate(kinds):
        diagrams = measures[kind].diagrams
        n = diagrams.n_points
        points["diagram_force_kind"].append(np.full(n, index, dtype=np.int8))
        points["diagram_homology_dim"].append(np.asarray(diagrams.homology_dim, dtype=np.int8))
        points["birth"].append(np.asarray(diagrams.birth, dtype=float))
        points["death"].append(np.asarray(diagrams.death, dtype=float))
        points["essential"].append(np.asarray(diagrams.essential, dtype=np.int8))
    values.update({name: np.concatenate(parts) for name, parts in points.items()})
    edges = np.asarray(first.force_bin_edges, dtype=float)
    coords = {
        "force_kind": xr.Variable(("force_kind",), kinds, attrs={
            "units": "1", "long_name": "force defining the network: total |F_n+F_t| (P1), normal or tangential (P2)"}),
        "homology_dim": xr.Variable(("homology_dim",), np.arange(values["betti"].shape[1], dtype=np.int8),
                                    attrs={"units": "1", "long_name": "homology dimension k"}),
        "threshold": xr.Variable(("threshold",), np.asarray(first.thresholds, dtype=float),
                                 attrs={"units": "<F>", "long_name": "force threshold F_th"}),
        "force_bin": xr.Variable(("force_bin",), 0.5 * (edges[1:] + edges[:-1]),
                                 attrs={"units": "<F>", "long_name": "centre of the force bin"}),
        # not a CF `bounds` variable: xarray strips units from those, and every variable here carries units
        "force_bin_edges": xr.Variable(("force_bin_edge",), edges,
                                       attrs={"units": "<F>", "long_name": "edges of the force bins"}),
        "persistence_bin": xr.Variable(("persistence_bin",), list(PERSISTENCE_BINS), attrs={
            "units": "1", "long_name": "PD0 bin: rough lifespan<=0.1, weak 0.1<=b<1, medium 1<=b<2.5, strong b>=2.5"}),
    }
    ds = dataset_from_specs(ANALYSIS_VARIABLES, values, attrs, coords=coords)
    # CF flags: `ncdump -h` shows what each index of diagram_force_kind means without the force_kind values
    ds["diagram_force_kind"].attrs.update(flag_values=np.arange(len(kinds), dtype=np.int8),
                                          flag_meanings=" ".join(kinds))
    if force_units is not None:  # forces in <F> need no unit; ⟨F⟩ itself is in the snapshot's
        ds["mean_force"].attrs["units"] = force_units
    return ds
