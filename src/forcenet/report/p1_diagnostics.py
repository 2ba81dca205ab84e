"""Measurements behind docs/validation/README.md's account of the P1 claims that do not hold: what in a
system's own data sets the number a claim judges.

Inputs are the aggregated total-force measures of one system as the judges see them (`SystemData`, from
`forcenet.report.p1_validation.system_data`), so every mask (ρ beyond ρ_J + tol, F_th < 2) is the judges' one.
Per packing fraction ρ and force threshold F_th [⟨F⟩]:

- `contact_share_above` — share of the contacts of the rattler-free network with F ≥ F_th (edges at F_th over
  edges at the lowest F_th); the super-level set every cluster measure is taken on.
- `percolation_threshold_per_rho` — the largest F_th at which at least half of the realizations still hold a
  percolating cluster (P1 §4.3's majority rule), i.e. where the spanning network breaks up.
- `size_peak_threshold_per_rho` — the F_th of the largest realization-mean ⟨S⟩/N (P1 §4.2, percolating clusters
  excluded): it sits at the percolation threshold, as for finite clusters in percolation theory.
- `shape_readings` — the shape parameter under P1 §5.2's two readings: S̄_p pooled over the clusters of a
  realization (edges / particles, `shape_parameter`, the one the tables and figures use) and the mean over
  clusters of each cluster's edges / particles (`shape_parameter_cluster_mean`), each averaged over the
  realizations by P1's rule.
- `with_shape_reading` — a measures dataset whose `shape_parameter` is the other reading, so the tables' S_p
  judges can be run on it.
- `network_rows` — one row per ρ with all of the above, Z without rattlers and TP0/N.
- `common_rho` — the ρ two systems both sampled beyond their ρ_J (to compare them at equal ρ).

`scripts/p1_network_survey.py` prints them for finished runs.
"""
from __future__ import annotations

from typing import Sequence

import numpy as np
import pandas as pd
import xarray as xr

from forcenet.measures.persistence_stats import STRONG_BIRTH
from forcenet.report.p1 import (P1_PERCOLATION_MAJORITY, first_max_index, per_particle, percolation_fraction,
                                rho_values)
from forcenet.report.p1_judging import SystemData, bin_curve
from forcenet.report.realizations import realization_mean

__all__ = ["SHAPE_READINGS", "contact_share_above", "percolation_threshold_per_rho", "size_peak_threshold_per_rho",
           "shape_readings", "with_shape_reading", "network_rows", "common_rho"]

#: P1 §5.2's two readings of "edges in the clusters divided by participating particles" → measure variable
SHAPE_READINGS = {"pooled": "shape_parameter", "cluster_mean": "shape_parameter_cluster_mean"}


def contact_share_above(system: SystemData) -> xr.DataArray:
    """Realization-mean share of the network's contacts with F ≥ F_th, dims (rho, threshold) [-]: edges at F_th
    over edges at the lowest F_th (NaN where the network has no contact)."""
    edges = system.data["edge_count"].astype(float)
    whole = edges.isel(threshold=int(np.argmin(system.thresholds)))
    return realization_mean((edges / whole.where(whole > 0)).transpose(..., "rho", "threshold"))


def percolation_threshold_per_rho(system: SystemData, majority: float = P1_PERCOLATION_MAJORITY) -> xr.DataArray:
    """Largest F_th [⟨F⟩] at which at least `majority` of the realizations percolate, dims (rho,); NaN where
    none percolates even at the lowest F_th."""
    share = percolation_fraction(system.data).transpose("rho", "threshold").values
    thresholds = system.thresholds
    values = [thresholds[row >= majority - 1e-12].max() if (row >= majority - 1e-12).any() else np.nan
              for row in share]
    return xr.DataArray(np.asarray(values, dtype=float), dims="rho", coords={"rho": system.data["rho"]})


def size_peak_threshold_per_rho(system: SystemData) -> xr.DataArray:
    """F_th [⟨F⟩] of the largest realization-mean ⟨S⟩/N at each ρ, dims (rho,); NaN where no finite cluster
    is left at any F_th (P1 §4.2)."""
    size = system.mean("cluster_mean_size").transpose("rho", "threshold").values
    thresholds = system.thresholds
    values = [thresholds[first_max_index(row)] if np.isfinite(row).any() and np.nanmax(row) > 0 else np.nan
              for row in size]
    return xr.DataArray(np.asarray(values, dtype=float), dims="rho", coords={"rho": system.data["rho"]})


def shape_readings(system: SystemData) -> dict[str, tuple[xr.DataArray, xr.DataArray]]:
    """{reading: (S_p, spread)} over (rho, threshold) for each of `SHAPE_READINGS`, averaged over the
    realizations by P1 §5.2's rule (`shape_parameter_average`)."""
    return {reading: system.shape_average(name) for reading, name in SHAPE_READINGS.items()
            if name in system.data}


def with_shape_reading(ds: xr.Dataset, reading: str) -> xr.Dataset:
    """`ds` (an aggregated network_measures dataset) with its ``shape_parameter`` replaced by the variable of
    `reading` (a key of `SHAPE_READINGS`), for judging P1 §5.2's claims under that reading."""
    if reading not in SHAPE_READINGS:
        raise ValueError(f"unknown shape-parameter reading {reading!r}; known: {', '.join(SHAPE_READINGS)}")
    return ds.assign(shape_parameter=ds[SHAPE_READINGS[reading]])


def network_rows(system: SystemData, thresholds: Sequence[float] = (0.5, 1.0, 1.5, 2.0)) -> pd.DataFrame:
    """One row per ρ of `system`: ρ, Z without rattlers, the share of contacts with F ≥ F_th and S_p (pooled; the
    cluster mean at F_th = 1) at `thresholds`, the ⟨S⟩/N peak and percolation thresholds, TP0/N, and where the
    results have P1 §5.3's persistence bins the rough- and strong-bin N0/N beside the share of contacts with
    F ≥ 2.5 ⟨F⟩ (the strong bin's births)."""
    share = contact_share_above(system)
    shapes = shape_readings(system)
    pooled = shapes["pooled"][0]
    rows = pd.DataFrame({"rho": rho_values(system.data)})
    rows["Z_no_rattlers"] = realization_mean(system.data["Z_no_rattlers"]).values
    for threshold in thresholds:
        rows[f"share_F>={threshold:g}"] = share.sel(threshold=threshold, method="nearest").values
    for threshold in thresholds:
        rows[f"S_p({threshold:g})"] = pooled.sel(threshold=threshold, method="nearest").values
    if "cluster_mean" in shapes:
        rows["S_p cluster mean(1)"] = shapes["cluster_mean"][0].sel(threshold=1.0, method="nearest").values
    rows["<S>/N peak F_th"] = size_peak_threshold_per_rho(system).values
    rows["percolation F_th"] = percolation_threshold_per_rho(system).values
    tp0 = per_particle(system.data, "total_persistence").sel(homology_dim=0)
    rows["TP0/N"] = realization_mean(tp0).values
    if "persistence_bin_count" in system.data:
        if np.isclose(system.thresholds, STRONG_BIRTH).any():
            rows[f"share_F>={STRONG_BIRTH:g}"] = share.sel(threshold=STRONG_BIRTH, method="nearest").values
        for bin_name in ("rough", "strong"):
            rows[f"{bin_name} N0/N"] = bin_curve(system, bin_name).values
    return rows


def common_rho(first: SystemData, second: SystemData) -> np.ndarray:
    """The ρ both systems sampled beyond both their ρ_J + tol (the judges' `beyond`), ascending."""
    a = set(np.round(rho_values(first.data)[first.beyond], 6))
    b = set(np.round(rho_values(second.data)[second.beyond], 6))
    return np.array(sorted(a & b), dtype=float)
