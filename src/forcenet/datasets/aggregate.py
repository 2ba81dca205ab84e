"""Aggregated datasets: one system's analyses stacked over (realization, ρ).

results/{system}/network_measures.nc   every ANALYSIS_VARIABLES entry except the diagram points, with dims
                                       (realization, rho, ...); coordinates rho, realization, threshold,
                                       homology_dim, force_kind, force_bin, persistence_bin
results/{system}/diagrams.nc           all persistence points with realization(point), rho(point) added

Besides the provenance attributes, both carry the system's ``dimension`` and ``force_law`` and the constants in which
P1's F_max rule (§3) compares ⟨F⟩ across systems (`forcenet.pipeline.force_constants`, from `forcenet.units`):
``force_unit_dyn`` (one reduced force unit m̄ d_ave τ_c⁻², in dyn), ``stiffness_scale_reduced`` (k_n d_ave^(1+β)
in reduced force units) and ``normal_stiffness_cgs`` (k_n in dyn cm^-(1+β), P1 Eq. 1); NaN where a system has
no `material` (P2 units).
"""
from __future__ import annotations

from typing import Sequence

import numpy as np
import xarray as xr

DIAGRAM_VARIABLES = ("diagram_force_kind", "diagram_homology_dim", "birth", "death", "essential")


def stack_network_measures(analyses: Sequence[xr.Dataset], realizations: Sequence[int],
                           rhos: Sequence[float], attrs: dict) -> xr.Dataset:
    """Stack per-snapshot analysis datasets (given in realization-major order) into (realization, rho)."""
    realizations = list(dict.fromkeys(int(r) for r in realizations))
    rhos = list(dict.fromkeys(float(r) for r in rhos))
    if len(analyses) != len(realizations) * len(rhos):
        raise ValueError(f"expected {len(realizations)} x {len(rhos)} analyses, got {len(analyses)}")
    measures = [ds.drop_vars([v for v in DIAGRAM_VARIABLES if v in ds.variables] + ["rho"], errors="ignore")
                .drop_dims("point", errors="ignore") for ds in analyses]
    rows = []
    for i, _ in enumerate(realizations):
        row = xr.concat(measures[i * len(rhos):(i + 1) * len(rhos)], dim="rho", combine_attrs="drop")
        rows.append(row)
    stacked = xr.concat(rows, dim="realization", combine_attrs="drop")
    stacked = stacked.assign_coords(
        realization=xr.Variable(("realization",), np.array(realizations, dtype=np.int32),
                                attrs={"units": "1", "long_name": "realization index"}),
        rho=xr.Variable(("rho",), np.array(rhos), attrs={"units": "1", "long_name": "packing fraction"}),
    )
    for name, var in analyses[0].variables.items():  # keep units/long_name of coordinates and variables
        if name in stacked.variables:
            stacked[name].attrs.update(var.attrs)
    stacked.attrs = dict(attrs)
    return stacked


def stack_diagrams(analyses: Sequence[xr.Dataset], realizations: Sequence[int], rhos: Sequence[float],
                   attrs: dict) -> xr.Dataset:
    """Concatenate the diagram points of every snapshot, tagging each with its realization and ρ."""
    pieces = []
    for ds, realization, rho in zip(analyses, realizations, rhos):
        points = ds[list(DIAGRAM_VARIABLES)]
        n = points.sizes.get("point", 0)
        points = points.assign(
            point_realization=xr.Variable(("point",), np.full(n, realization, dtype=np.int32),
                                          attrs={"units": "1", "long_name": "realization of the point"}),
            point_rho=xr.Variable(("point",), np.full(n, rho), attrs={"units": "1",
                                                                      "long_name": "packing fraction of the point"}),
        )
        pieces.append(points)
    stacked = xr.concat(pieces, dim="point", combine_attrs="drop_conflicts")
    stacked.attrs = dict(attrs)
    return stacked
