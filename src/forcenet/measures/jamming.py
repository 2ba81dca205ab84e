"""Jamming point from a compression sequence Z(ρ) (P1 §4, P2 §IV A).

P1 defines ρ_J as the inflection point of Z(ρ); P2 loosely as the ρ where Z ≈ 3 (= d + 1 in 2D).

Locating an inflection on noisy data by differencing twice is unstable (one noisy snapshot moves it by a grid
step). The default method fits a logistic step

    Z(ρ) = Z_low + (Z_high − Z_low) / (1 + exp(−(ρ − ρ_J) / w)),

whose inflection is ρ_J, by least squares with numpy only: for fixed (ρ_J, w) the model is linear in
(Z_low, Z_high), solved in closed form (variable projection), and (ρ_J, log w) are found by a grid search
over the sampled ρ range refined by successive zooms. Every sample weighs in, so noise averages out. The
alternative ``"smoothed_derivative"`` takes the maximum of the slope of a Gaussian-weighted local linear
regression (bandwidth a few ρ steps). Both return NaN when the data do not bracket a rise of at least
`MIN_RISE` (best centre on the edge of the sampled range, or Z flat within noise).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

JAMMING_METHODS = ("logistic", "smoothed_derivative")


@dataclass(frozen=True)
class LogisticFit:
    """Least-squares logistic fit of Z(ρ): centre ρ_J (the inflection), width w, plateaus, rms residual."""

    rho_j: float
    width: float
    z_low: float
    z_high: float
    rms_residual: float

    def __call__(self, rho) -> np.ndarray:
        return self.z_low + (self.z_high - self.z_low) * _logistic((np.asarray(rho) - self.rho_j) / self.width)


def _logistic(x):
    return 0.5 * (1.0 + np.tanh(0.5 * x))  # = 1/(1+e^−x), without overflow


def _clean(rho, z) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Distinct ρ (sorted), mean Z at each, and how many samples it averages (weights of the fits).

    z may be (n,) or (R, n) against rho (n,) (realizations pooled); NaNs are dropped. Least squares on the
    per-ρ means with these weights equals least squares on all pooled samples, at a fraction of the memory.
    """
    rho = np.asarray(rho, dtype=np.float64)
    z = np.asarray(z, dtype=np.float64)
    if z.ndim == 2:
        rho = np.broadcast_to(rho, z.shape)
    rho, z = rho.reshape(-1), z.reshape(-1)
    ok = np.isfinite(rho) & np.isfinite(z)
    unique, index = np.unique(rho[ok], return_inverse=True)
    count = np.bincount(index, minlength=unique.size).astype(np.float64)
    mean = np.bincount(index, weights=z[ok], minlength=unique.size) / np.maximum(count, 1)
    return unique, mean, count


def fit_logistic(rho, z, *, n_centres: int = 101, n_widths: int = 41, n_zooms: int = 6) -> LogisticFit:
    """Logistic least-squares fit of Z(ρ) (module docstring).

    Parameters
    ----------
    rho : array, shape (n,) — packing fractions.
    z : array, shape (n,) or (R, n) — contact numbers (realizations pooled).
    n_centres, n_widths : grid sizes for ρ_J and log w.
    n_zooms : refinement rounds, each shrinking the search box around the best grid point 4-fold.
    """
    rho, z, weight = _clean(rho, z)
    if rho.size < 4:
        raise ValueError("need Z at four or more distinct packing fractions")
    weight = weight / weight.sum()
    lo, hi = rho[0], rho[-1]
    centre_range = np.array([lo, hi])
    log_width_range = np.log([np.min(np.diff(rho)) / 4.0, (hi - lo) / 2.0])
    z_mean = np.sum(weight * z)
    z_dev = z - z_mean
    best = None
    for _ in range(n_zooms + 1):
        centres = np.linspace(*centre_range, n_centres)
        log_widths = np.linspace(*log_width_range, n_widths)
        c, log_w = np.meshgrid(centres, log_widths, indexing="ij")
        s = _logistic((rho - c[..., None]) / np.exp(log_w)[..., None])  # (C, W, n)
        s_mean = (s * weight).sum(axis=-1)
        s_dev = s - s_mean[..., None]
        s_var = (weight * s_dev ** 2).sum(axis=-1)
        covariance = (weight * s_dev * z_dev).sum(axis=-1)
        # closed-form rise for fixed (ρ_J, w), kept ≥ 0 since Z rises through jamming
        rise = np.maximum(np.divide(covariance, s_var, out=np.zeros_like(s_var), where=s_var > 1e-300), 0.0)
        mse = (weight * z_dev ** 2).sum() - 2 * rise * covariance + rise ** 2 * s_var
        k = np.unravel_index(np.argmin(mse), mse.shape)
        best = (centres[k[0]], np.exp(log_widths[k[1]]), rise[k], z_mean - rise[k] * s_mean[k], mse[k])
        half_c = (centre_range[1] - centre_range[0]) / 8.0
        half_w = (log_width_range[1] - log_width_range[0]) / 8.0
        centre_range = np.clip([best[0] - half_c, best[0] + half_c], lo, hi)
        log_width_range = np.array([np.log(best[1]) - half_w, np.log(best[1]) + half_w])
    rho_j, width, rise, z_low, mse = best
    return LogisticFit(rho_j=float(rho_j), width=float(width), z_low=float(z_low), z_high=float(z_low + rise),
                       rms_residual=float(np.sqrt(max(mse, 0.0))))


def smoothed_slope(rho, z, grid, bandwidth: float) -> np.ndarray:
    """dZ/dρ on `grid` from a Gaussian-weighted local linear regression with the given bandwidth."""
    rho, z, count = _clean(rho, z)
    weight = count[None, :] * np.exp(-0.5 * ((rho[None, :] - grid[:, None]) / bandwidth) ** 2)
    total = weight.sum(axis=1)
    mean_rho = (weight * rho).sum(axis=1) / total
    mean_z = (weight * z).sum(axis=1) / total
    d_rho = rho[None, :] - mean_rho[:, None]
    return (weight * d_rho * (z - mean_z[:, None])).sum(axis=1) / (weight * d_rho ** 2).sum(axis=1)


MIN_RISE = 1.0  # contacts per particle: Z rises from ≈ 0 to ≈ d + 1 through jamming (P1 §4.3)


def jamming_point(rho, z, *, method: str = "logistic", bandwidth: float | None = None,
                  min_rise: float = MIN_RISE) -> float:
    """ρ_J, the inflection of Z(ρ) (P1 §4), located robustly (module docstring).

    Parameters
    ----------
    rho : array, shape (n,) — packing fractions.
    z : array, shape (n,) or (R, n) — Z per snapshot (realizations pooled).
    method : "logistic" (default) or "smoothed_derivative".
    bandwidth : Gaussian bandwidth in ρ for "smoothed_derivative" (default 2 × the typical ρ step).
    min_rise : smallest rise of Z across the transition that counts as jamming (default 1 contact per
        particle), so that noise on a flat Z(ρ) is not mistaken for an inflection.

    Returns
    -------
    float — ρ_J, NaN when there is no rise of at least `min_rise` inside the sampled range.
    """
    if method not in JAMMING_METHODS:
        raise ValueError(f"method must be one of {JAMMING_METHODS}, got {method!r}")
    unique, _, _ = _clean(rho, z)
    if method == "logistic":
        fit = fit_logistic(rho, z)
        inside = unique[0] < fit.rho_j < unique[-1] and fit.z_high - fit.z_low >= min_rise
        return fit.rho_j if inside else float("nan")
    if unique.size < 4:
        raise ValueError("need Z at four or more distinct packing fractions")
    bandwidth = 2.0 * float(np.median(np.diff(unique))) if bandwidth is None else float(bandwidth)
    grid = np.linspace(unique[0], unique[-1], 20 * unique.size)
    slope = smoothed_slope(rho, z, grid, bandwidth)
    k = int(np.argmax(slope))
    rise = np.sum(np.clip(slope, 0.0, None)) * (grid[1] - grid[0])  # total increase of the smoothed Z
    return float(grid[k]) if 0 < k < grid.size - 1 and rise >= min_rise else float("nan")


def isostatic_crossing(rho, z, dimension: int = 2) -> float:
    """ρ where Z(ρ) first rises through d + 1 (P2 §IV A: ρ_J "loosely defined as the ρ at which Z ≈ 3").

    Linear interpolation between the last sample below and the first at or above d + 1. Realizations
    (z of shape (R, n)) are averaged first. NaN when Z never reaches d + 1 or already starts at or above it.
    """
    rho = np.asarray(rho, dtype=np.float64)
    z = np.asarray(z, dtype=np.float64)
    if z.ndim == 2:
        z = np.nanmean(z, axis=0)
    ok = np.isfinite(rho) & np.isfinite(z)
    order = np.argsort(rho[ok], kind="stable")
    rho, z = rho[ok][order], z[ok][order]
    target = dimension + 1.0
    above = np.flatnonzero(z >= target)
    if above.size == 0 or above[0] == 0:
        return float("nan")
    k = int(above[0])
    return float(rho[k - 1] + (target - z[k - 1]) * (rho[k] - rho[k - 1]) / (z[k] - z[k - 1]))
