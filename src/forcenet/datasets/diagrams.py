"""Reading persistence-diagram points: the one reader of the flat `point` layout (`schema.py`).

Two file kinds hold diagrams as points: an analysis file (one snapshot, results/analysis/{system}/r{NN}/rho{ρ}.nc)
and a stacked diagrams file (every snapshot of a system, results/{system}/diagrams.nc, whose points also carry
`point_realization` and `point_rho`). Each point has a force kind (`diagram_force_kind`, an index into the file's
`force_kind` coordinate), a homology dimension, birth ≥ death in ⟨F⟩ (super-level filtration) and an `essential`
flag; never-dying classes have death −inf.
"""
from __future__ import annotations

from typing import NamedTuple

import numpy as np
import xarray as xr

#: how far a requested ρ may lie from a point's grid ρ (`point_rho`) and still select it; grid values are written
#: from the config with three decimals at most, so any tolerance well below 10⁻³ selects exactly one grid point
RHO_TOLERANCE = 1e-6


class DiagramPoints(NamedTuple):
    """The P points of one force kind's persistence diagram(s) of one snapshot.

    homology_dim : (P,) int64, k of each point.
    birth, death : (P,) float64 [⟨F⟩], birth ≥ death; death = −inf for a class that never dies.
    essential : (P,) bool, the class never dies.
    """

    homology_dim: np.ndarray
    birth: np.ndarray
    death: np.ndarray
    essential: np.ndarray


def diagram_points(ds: xr.Dataset, kind: str, homology_dim: int | None = None, *, realization: int | None = None,
                   rho: float | None = None) -> DiagramPoints:
    """The diagram points of force network `kind` ("total", "normal" or "tangential") of one snapshot.

    Parameters
    ----------
    ds : an analysis dataset (one snapshot) or a stacked diagrams dataset (diagrams.nc).
    kind : a value of the file's `force_kind` coordinate.
    homology_dim : keep only the points of PD_k; None keeps every dimension.
    realization, rho : which snapshot of a stacked diagrams file (both required there, refused for an analysis
        file); `rho` is the config's grid value (`point_rho`). A grid ρ at which the snapshot has no points (its
        network has no edge) and a ρ off the grid both give an empty result.

    A point flagged essential or with a non-finite death comes back as never-dying, with death −inf. Raises ValueError for
    a kind the file does not hold, a homology dimension outside an analysis file's `homology_dim`, a realization
    no point carries, or a missing or superfluous snapshot selection.
    """
    kinds = [str(k) for k in ds["force_kind"].values] if "force_kind" in ds.coords else []
    if kind not in kinds:
        raise ValueError(f"force kind {kind!r} not in this file; it holds {kinds}")
    stacked = "point_realization" in ds.variables
    if stacked and (realization is None or rho is None):
        raise ValueError("a stacked diagrams file holds every snapshot: give both realization and rho")
    if not stacked and (realization is not None or rho is not None):
        raise ValueError("an analysis file holds one snapshot: realization and rho select only in diagrams.nc")
    if homology_dim is not None and "homology_dim" in ds.coords and homology_dim not in ds["homology_dim"].values:
        raise ValueError(f"homology dimension {homology_dim} not in this file; it holds "
                         f"{[int(k) for k in ds['homology_dim'].values]}")
    if "point" not in ds.dims or ds.sizes["point"] == 0:
        chosen = np.zeros(0, dtype=bool)
    else:
        chosen = ds["diagram_force_kind"].values == kinds.index(kind)
    if stacked and chosen.size:
        realizations = ds["point_realization"].values
        if realization not in realizations:
            held = np.unique(realizations).tolist()
            raise ValueError(f"realization {realization} not in this file; it holds {held}")
        chosen &= (realizations == realization) & (np.abs(ds["point_rho"].values - rho) <= RHO_TOLERANCE)
    if homology_dim is not None and chosen.size:
        chosen &= ds["diagram_homology_dim"].values == homology_dim
    if not chosen.any():
        return DiagramPoints(np.zeros(0, dtype=np.int64), np.zeros(0), np.zeros(0), np.zeros(0, dtype=bool))
    death = ds["death"].values[chosen].astype(np.float64)
    essential = ds["essential"].values[chosen].astype(bool) | ~np.isfinite(death)
    return DiagramPoints(homology_dim=ds["diagram_homology_dim"].values[chosen].astype(np.int64),
                         birth=ds["birth"].values[chosen].astype(np.float64),
                         death=np.where(essential, -np.inf, death), essential=essential)
