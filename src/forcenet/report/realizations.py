"""Reductions over realizations: the one convention for a mean and its spread, used by the P1 and P2 tables,
claims and figures.

A quantity measured in several independent realizations (compression runs with different seeds) is shown as

- the **mean** over the realizations, NaN entries skipped (a realization where the quantity is undefined, e.g.
  a ratio 0/0, does not count); NaN where every realization is NaN;
- its **spread**: the sample standard deviation over the realizations (``ddof = 1``), counted over the finite
  entries; the band a figure draws is mean ± spread (for a ratio of means, P2 Figs 7 and 10: that ratio ± the
  spread of the per-realization ratios).

A single realization (or a point where only one realization is finite) has spread 0: the band collapses onto
the mean, so a figure of one realization shows the curve alone. On a log axis (P2 Figs 6–10) the part of a band
below 0 is not drawn.

Other reductions over realizations that a paper defines itself live with that paper: P1 §5.2's averaging of the
shape parameter and P1 §4.3's majority rule for the percolating cluster are in `forcenet.report.p1`, built on
these.
"""
from __future__ import annotations

import xarray as xr

__all__ = ["REALIZATION", "realization_mean", "realization_spread", "mean_and_spread"]

REALIZATION = "realization"  # the dimension of the aggregated datasets that counts the realizations


def realization_mean(da: xr.DataArray, dim: str = REALIZATION) -> xr.DataArray:
    """Mean of `da` over `dim` (NaN skipped); `da` unchanged when it has no such dimension (one realization
    already selected). Same shape as `da` without `dim`, same units."""
    return da.mean(dim, skipna=True) if dim in da.dims else da


def realization_spread(da: xr.DataArray, dim: str = REALIZATION) -> xr.DataArray:
    """Sample standard deviation of `da` over `dim` (``ddof = 1``, NaN skipped), 0 where fewer than two
    realizations are finite and everywhere when `da` has no such dimension. Same shape and units as
    `realization_mean`."""
    if dim not in da.dims:
        return xr.zeros_like(da, dtype=float)
    count = da.notnull().sum(dim)
    return da.std(dim, skipna=True, ddof=1).where(count > 1, 0.0)


def mean_and_spread(da: xr.DataArray, dim: str = REALIZATION) -> tuple[xr.DataArray, xr.DataArray]:
    """(`realization_mean`, `realization_spread`) of `da` over `dim`."""
    return realization_mean(da, dim), realization_spread(da, dim)

