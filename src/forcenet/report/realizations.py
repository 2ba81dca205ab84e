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

How robust a verdict is to the choice of realizations (issue 24): each claim is judged again on bootstrap
resamples of the realizations (`bootstrap_resamples`: R realizations drawn with replacement from R, seeded, so a
table is reproducible; `bootstrap_draws` for several systems at once; `resample_realizations` builds the dataset
of one draw), and the table gives the share of
resamples under which it holds. A verdict that one realization carries then holds in a visibly smaller share.

Other reductions over realizations that a paper defines itself live with that paper: P1 §5.2's averaging of the
shape parameter and P1 §4.3's majority rule for the percolating cluster are in `forcenet.report.p1`, built on
these.
"""
from __future__ import annotations

import zlib
from typing import Mapping, Sequence

import numpy as np
import xarray as xr

__all__ = ["REALIZATION", "ROBUSTNESS_RESAMPLES", "realization_mean", "realization_spread", "mean_and_spread",
           "bootstrap_resamples", "resample_realizations", "bootstrap_draws"]

REALIZATION = "realization"  # the dimension of the aggregated datasets that counts the realizations
ROBUSTNESS_RESAMPLES = 100  # bootstrap resamples behind each verdict's robustness share (standard error ≤ 0.05)


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



def bootstrap_resamples(n_realizations: int, resamples: int, seed: int | Sequence[int] = 0) -> list[np.ndarray]:
    """`resamples` draws of `n_realizations` realization indices with replacement (sorted), from a generator
    seeded by `seed` (an int or a sequence of ints, `numpy.random.SeedSequence` entropy): the same draws every
    time. Empty when there are fewer than 2 realizations (a resample of
    one realization is that realization: no robustness to measure)."""
    if n_realizations < 2 or resamples < 1:
        return []
    rng = np.random.default_rng(seed)
    return [np.sort(rng.integers(0, n_realizations, n_realizations)) for _ in range(resamples)]


def resample_realizations(ds: xr.Dataset, indices: np.ndarray, dim: str = REALIZATION) -> xr.Dataset:
    """The realizations `indices` of `ds` (repeats allowed), renumbered 0 … len − 1 along `dim`."""
    out = ds.isel({dim: np.asarray(indices, dtype=int)})
    return out.assign_coords({dim: np.arange(len(indices))})


def bootstrap_draws(datasets: Mapping[str, xr.Dataset], resamples: int, seed: int = 0,
                    dim: str = REALIZATION) -> list[dict[str, np.ndarray]]:
    """`resamples` bootstrap draws of the realizations of every dataset of `datasets` ({name: indices} each; each
    name from its own stream, seeded by (`seed`, CRC-32 of the name), so a system's draws do not depend on which
    other systems are judged beside it). A dataset with a single realization (a counterpart run, say) is in every
    draw as it is; none when no dataset has two or more."""
    per_name = {name: bootstrap_resamples(datasets[name].sizes.get(dim, 1), resamples,
                                          (int(seed), zlib.crc32(name.encode())))
                for name in sorted(datasets)}
    if not any(per_name.values()):
        return []
    single = np.zeros(1, dtype=int)
    return [{name: draws[b] if draws else single for name, draws in per_name.items()} for b in range(resamples)]
