"""Aggregated datasets: one system's analyses stacked over (realization, ρ) (layout in `schema.py`).

results/{system}/network_measures.nc   every NETWORK_MEASURES_VARIABLES entry, dims (realization, rho, ...);
                                       coordinates rho (the config's grid), realization, threshold,
                                       homology_dim, force_kind, force_bin, persistence_bin; the measured ρ of
                                       each snapshot is the variable rho_measured(realization, rho)
results/{system}/diagrams.nc           all persistence points with point_realization, point_rho (grid) and
                                       point_rho_measured added, and the force_kind coordinate that
                                       diagram_force_kind indexes into

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

from forcenet.datasets.schema import DIAGRAM_VARIABLES, DIAGRAMS_VARIABLES, DIMENSIONLESS, NETWORK_MEASURES_VARIABLES

__all__ = ["DIAGRAM_VARIABLES", "stack_network_measures", "stack_diagrams", "distances_on_grid"]


def _spec_attrs(spec) -> dict:
    return {"units": spec.units, "long_name": spec.long_name}


def _grid_rho(rhos: Sequence[float]) -> xr.Variable:
    return xr.Variable(("rho",), np.asarray(rhos, dtype=float), attrs={
        "units": DIMENSIONLESS, "long_name": "packing fraction on the config's grid (systems.<name>.rho)"})


def stack_network_measures(analyses: Sequence[xr.Dataset], realizations: Sequence[int],
                           rhos: Sequence[float], attrs: dict) -> xr.Dataset:
    """Stack per-snapshot analysis datasets (given in realization-major order) into (realization, rho).

    `rhos` are the grid values (the `rho` coordinate); each analysis's own measured ρ goes to `rho_measured`."""
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
        rho=_grid_rho(rhos),
    )
    for name, var in analyses[0].variables.items():  # keep units/long_name of coordinates and variables
        if name in stacked.variables and name != "rho":
            stacked[name].attrs.update(var.attrs)
    measured = np.array([float(ds["rho"]) for ds in analyses]).reshape(len(realizations), len(rhos))
    stacked["rho_measured"] = xr.Variable(("realization", "rho"), measured,
                                          attrs=_spec_attrs(NETWORK_MEASURES_VARIABLES["rho_measured"]))
    stacked.attrs = dict(attrs)
    return stacked


def stack_diagrams(analyses: Sequence[xr.Dataset], realizations: Sequence[int], rhos: Sequence[float],
                   attrs: dict) -> xr.Dataset:
    """Concatenate the diagram points of every snapshot, tagging each with its realization, grid ρ (`rhos`) and
    measured ρ; the `force_kind` coordinate of the analyses comes along, so `diagram_force_kind` indexes into a
    dimension of this file."""
    pieces = []
    for ds, realization, rho in zip(analyses, realizations, rhos):
        points = ds[list(DIAGRAM_VARIABLES)]
        n = points.sizes.get("point", 0)
        points = points.assign(
            point_realization=xr.Variable(("point",), np.full(n, realization, dtype=np.int32),
                                          attrs=_spec_attrs(DIAGRAMS_VARIABLES["point_realization"])),
            point_rho=xr.Variable(("point",), np.full(n, float(rho)),
                                  attrs=_spec_attrs(DIAGRAMS_VARIABLES["point_rho"])),
            point_rho_measured=xr.Variable(("point",), np.full(n, float(ds["rho"])),
                                           attrs=_spec_attrs(DIAGRAMS_VARIABLES["point_rho_measured"])),
        )
        pieces.append(points)
    stacked = xr.concat(pieces, dim="point", combine_attrs="drop_conflicts")
    stacked = stacked.assign_coords(force_kind=analyses[0]["force_kind"].variable.copy())
    stacked.attrs = dict(attrs)
    return stacked


def distances_on_grid(distances: xr.Dataset, grid_rhos: Sequence[float], measured_on_grid: bool = True) -> xr.Dataset:
    """P2 distances (`forcenet.report.p2_distances.stack_distances`) with `rho` set to the config's grid value of the later
    snapshot of each pair (`grid_rhos`, one per pair), so that ``sel(rho=0.78)`` selects; the measured values stay in
    `rho_measured` and `rho_previous` (per realization). A sequence (`measured_on_grid` false) gives its coordinate
    of each pair's later state as `grid_rhos`, which its measured ρ need not be near."""
    grid_rhos = np.asarray(grid_rhos, dtype=float)
    if grid_rhos.shape != (distances.sizes["rho"],):
        raise ValueError(f"{grid_rhos.size} grid values for {distances.sizes['rho']} snapshot pairs")
    measured = distances["rho_measured"].values
    worst = float(np.max(np.abs(measured - grid_rhos))) if measured.size and measured_on_grid else 0.0
    spacing = float(np.min(np.diff(grid_rhos))) if grid_rhos.size > 1 else np.inf
    if worst >= 0.5 * spacing:
        raise ValueError(f"measured packing fractions lie up to {worst:.4f} from the grid (spacing {spacing:.4f}): "
                         "the snapshots do not belong to this grid")
    out = distances.assign_coords(rho=_grid_rho(grid_rhos))
    out["rho"].attrs["long_name"] = "packing fraction of the later snapshot of each pair, on the config's grid"
    out.attrs["rho_convention"] = ("rho is the grid packing fraction (systems.<name>.rho) of the later snapshot of "
                                   "each consecutive pair; rho_measured and rho_previous hold the measured packing "
                                   "fractions of the later and earlier snapshot, per realization")
    return out
