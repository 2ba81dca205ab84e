"""P1 (compressed 2D/3D interaction networks): the reductions its figures share, and its validation table.

Inputs are the aggregated ``results/{system}/network_measures.nc`` datasets (dims ``realization``, ``rho``,
``force_kind``, ``homology_dim``, ``threshold``, ``force_bin``, ``persistence_bin``; see
`forcenet.datasets.aggregate`), keyed by system name. P1 analyses the total force |F_n + F_t| only, so every
reduction here selects ``force_kind = "total"``.

Reductions (the P1 figures in `forcenet.plotting.p1` use the same functions):

- `f_max_cut` — P1 §3: F'_max = max over ρ of the realization-mean ⟨F⟩ (in dyn, so systems compare),
  F_max = min over systems of F'_max, ρ_max = largest ρ whose mean ⟨F⟩ ≤ F_max.
- `shape_parameter_average` — P1 §5.2: S_p = 0 where S̄_p = 0 in at least half of the realizations, else the
  mean over the realizations with S̄_p ≠ 0.
- `percolation_fraction`, `percolating_size_mean` — P1 §4.3: N_per/N is shown only where at least 50 % of
  the realizations percolate.
- `jamming_point` — P1 §4: ρ_J is the inflection point of the realization-mean Z(ρ).

The table (`p1_validation`) sets the measured ρ_J, ρ_max and Z(ρ_J) beside P1's and judges P1's qualitative
claims from the data. The only typed-in numbers are P1's own: its reference values and the definitions it
states (Δρ = 0.02, "small F_th < 0.5", the 50 % percolation rule). The claim criteria (tolerances) are keyword
arguments of `p1_validation`, documented there.
"""
from __future__ import annotations

import json
import math
import os
import warnings
from dataclasses import dataclass, field
from pathlib import Path
from typing import Mapping

import numpy as np
import pandas as pd
import xarray as xr

# --- P1's reference values (the only results typed in) --------------------------------------------------------
P1_SYSTEMS = ("2d_hertz", "2d_linear", "3d_hertz")  # P1's panel order a, b, c
PAPER_RHO_J = {"2d_hertz": 0.842, "2d_linear": 0.834, "3d_hertz": 0.57}  # P1 §4 (inflection of Z)
PAPER_RHO_MAX = {"2d_hertz": 0.906, "2d_linear": 0.890, "3d_hertz": 0.710}  # P1 §3 (F_max rule)
PAPER_Z_AT_JAMMING = {2: 3.0}  # P1 §4.3: ⟨k⟩ ≈ 3 in 2D close to jamming

# --- definitions P1 states (not results) --------------------------------------------------------------------
P1_RHO_STEP = 0.02  # §3: compression step Δρ between relaxed states
P1_SMALL_THRESHOLD = 0.5  # §5.1: "for small values of F_th < 0.5" (the B0/N ridge)
P1_PERCOLATION_MAJORITY = 0.5  # §4.3: N_per/N shown only where ≥ 50 % of the realizations percolate

TOTAL = "total"  # P1 uses the total force |F_n + F_t|
HOLDS, FAILS, NOT_EVALUATED = "holds", "does not hold", "not evaluated"
COLUMNS = ("kind", "item", "system", "measured", "paper", "difference", "evidence", "verdict")


# =============================================================================================================
# Selections and realization averages
# =============================================================================================================
def select_total(ds: xr.Dataset) -> xr.Dataset:
    """The total-force analysis (P1 §3): drop the ``force_kind`` dimension by selecting ``"total"``."""
    if "force_kind" in ds.dims:
        return ds.sel(force_kind=TOTAL)
    return ds


def per_particle(ds: xr.Dataset, name: str) -> xr.DataArray:
    """``ds[name] / N`` snapshot by snapshot (N = ``n_particles`` of that snapshot)."""
    return ds[name] / ds["n_particles"]


def mean_and_spread(da: xr.DataArray, dim: str = "realization") -> tuple[xr.DataArray, xr.DataArray]:
    """Mean over realizations (NaN skipped) and the sample standard deviation (0 for a single realization)."""
    mean = da.mean(dim, skipna=True)
    count = da.notnull().sum(dim)
    spread = da.std(dim, skipna=True, ddof=1).where(count > 1, 0.0)
    return mean, spread


def system_order(names) -> list[str]:
    """P1's panel order (2D Hertzian, 2D linear, 3D) first, any other system after, alphabetically."""
    names = list(names)
    return [n for n in P1_SYSTEMS if n in names] + sorted(n for n in names if n not in P1_SYSTEMS)


def system_dimension(ds: xr.Dataset, name: str = "") -> int:
    """Spatial dimension from the global attrs (``dimension``), else the config attr, else the name."""
    if "dimension" in ds.attrs:
        return int(ds.attrs["dimension"])
    spec = _config_system(ds, name)
    if "dimension" in spec:
        return int(spec["dimension"])
    return 3 if name.lower().startswith("3d") else 2


def system_force_law(ds: xr.Dataset, name: str = "") -> str:
    """``"linear"``, ``"hertz"`` or ``"unknown"``: global attr ``force_law``, else the config attr, else the name."""
    law = ds.attrs.get("force_law") or _config_system(ds, name).get("force_law")
    if law:
        return str(law).lower()
    lower = name.lower()
    return "linear" if "linear" in lower else "hertz" if "hertz" in lower else "unknown"


def _config_system(ds: xr.Dataset, name: str) -> dict:
    try:
        config = json.loads(ds.attrs.get("config", "{}"))
        return dict(config.get("systems", {}).get(name or ds.attrs.get("system", ""), {}))
    except (TypeError, ValueError, AttributeError):
        return {}


def rho_values(ds: xr.Dataset) -> np.ndarray:
    return np.asarray(ds["rho"].values, dtype=float)


# =============================================================================================================
# P1 §3: F_max rule → ρ_max
# =============================================================================================================
@dataclass(frozen=True)
class FMaxCut:
    """P1 §3 cut: results are shown for ρ ≤ ρ_max(system).

    f_max : F_max = min over systems of F'_max [``force_units``]
    f_prime_max : F'_max per system = max over ρ of the realization-mean ⟨F⟩ [``force_units``]
    rho_max : largest ρ of each system whose realization-mean ⟨F⟩ ≤ F_max (NaN: no finite ⟨F⟩ at all)
    force_units : ``"dyn"`` (from the ``force_unit_dyn`` attrs), or reduced units when no dataset has them
    """

    f_max: float
    f_prime_max: dict[str, float]
    rho_max: dict[str, float]
    force_units: str = "dyn"
    mean_force: dict[str, xr.DataArray] = field(default_factory=dict, repr=False)


def mean_force(ds: xr.Dataset, scale: float = 1.0) -> xr.DataArray:
    """Realization-mean ⟨F⟩ of the total-force network versus ρ, times `scale` (e.g. dyn per reduced unit)."""
    return select_total(ds)["mean_force"].mean("realization", skipna=True) * scale


def f_max_cut(measures: Mapping[str, xr.Dataset]) -> FMaxCut:
    """P1 §3 F_max rule over the systems in `measures` (see `FMaxCut`).

    ⟨F⟩ is converted to dyn with each dataset's ``force_unit_dyn`` attribute so that systems with different
    reduced force units compare. Raises ValueError if only some datasets carry it (mixed units); if none does,
    reduced units are compared with a warning.
    """
    if not measures:
        raise ValueError("f_max_cut needs at least one system")
    units = {name: ds.attrs.get("force_unit_dyn") for name, ds in measures.items()}
    missing = [name for name, unit in units.items() if unit is None]
    if missing and len(missing) < len(units):
        raise ValueError(f"force_unit_dyn missing for {missing}: ⟨F⟩ cannot be compared across systems")
    if missing:
        warnings.warn("no dataset has force_unit_dyn: comparing ⟨F⟩ in reduced units", stacklevel=2)
    curves = {name: mean_force(ds, 1.0 if missing else float(units[name])) for name, ds in measures.items()}
    f_prime = {name: _nanmax(curve.values) for name, curve in curves.items()}
    finite = [value for value in f_prime.values() if np.isfinite(value)]
    f_max = min(finite) if finite else math.nan
    rho_max = {}
    for name, curve in curves.items():
        rho = rho_values(curve)
        below = np.asarray(curve.values <= f_max)  # NaN (no contacts) compares False
        rho_max[name] = float(rho[below].max()) if below.any() else math.nan
    return FMaxCut(f_max=f_max, f_prime_max=f_prime, rho_max=rho_max,
                   force_units="m_mean d_ave tau_c-2" if missing else "dyn", mean_force=curves)


def cut_at_rho_max(ds: xr.Dataset, rho_max: float) -> xr.Dataset:
    """The packing fractions ρ ≤ ρ_max (all of them when ρ_max is NaN)."""
    if rho_max is None or not np.isfinite(rho_max):
        return ds
    keep = rho_values(ds) <= rho_max + 1e-12
    return ds.isel(rho=np.flatnonzero(keep))


# =============================================================================================================
# P1 §4: jamming, percolation, force PDF
# =============================================================================================================
def jamming_point(ds: xr.Dataset, variable: str = "Z") -> float:
    """ρ_J: inflection point of Z(ρ) (P1 §4), realizations pooled (`forcenet.measures.jamming_point`, a
    logistic fit); NaN if it cannot be located (fewer than 4 ρ, or no rise inside the sampled range)."""
    from forcenet.measures.jamming import jamming_point as inflection

    if variable not in ds:
        return math.nan
    z = ds[variable].transpose("realization", "rho").values
    try:
        return float(inflection(rho_values(ds), z))
    except (ValueError, ArithmeticError):
        return math.nan


def isostatic_crossing(ds: xr.Dataset, variable: str = "Z") -> float:
    """ρ where the realization-mean Z(ρ) first rises through d + 1 (P2's definition; NaN if it never does)."""
    from forcenet.measures.jamming import isostatic_crossing as crossing

    if variable not in ds:
        return math.nan
    z = ds[variable].transpose("realization", "rho").values
    try:
        return float(crossing(rho_values(ds), z, system_dimension(ds)))
    except (ValueError, ArithmeticError):
        return math.nan


def value_at(ds: xr.Dataset, variable: str, rho: float) -> float:
    """Realization-mean `variable` linearly interpolated at packing fraction `rho`."""
    if not np.isfinite(rho) or variable not in ds:
        return math.nan
    curve = ds[variable].mean("realization", skipna=True).values
    grid = rho_values(ds)
    ok = np.isfinite(curve)
    if not ok.any() or rho < grid[ok].min() or rho > grid[ok].max():
        return math.nan
    return float(np.interp(rho, grid[ok], curve[ok]))


def percolation_fraction(ds: xr.Dataset) -> xr.DataArray:
    """Fraction of realizations with a percolating total-force cluster, per (ρ, F_th)."""
    return (select_total(ds)["percolates"] > 0).mean("realization")


def percolating_size_mean(ds: xr.Dataset,
                          majority: float = P1_PERCOLATION_MAJORITY) -> tuple[xr.DataArray, xr.DataArray]:
    """N_per/N averaged over the realizations that percolate, NaN where fewer than `majority` percolate
    (P1 §4.3); returns (mean, spread) over (ρ, F_th)."""
    total = select_total(ds)
    size = per_particle(total, "percolating_size").where(total["percolates"] > 0)
    mean, spread = mean_and_spread(size)
    shown = percolation_fraction(ds) >= majority
    return mean.where(shown), spread.where(shown)


def force_bins(ds: xr.Dataset) -> tuple[np.ndarray, np.ndarray]:
    """Centres and widths of the PDF bins [⟨F⟩]: from a CF ``bounds`` variable (force_bin, 2) or a
    ``force_bin_edges`` variable (B + 1) when the dataset has one, else the ``force_bin`` coordinate is taken
    as the centres and the widths from their spacing."""
    bounds = ds[ds["force_bin"].attrs["bounds"]] if ds["force_bin"].attrs.get("bounds") in ds else None
    if bounds is not None:  # CF: the vertex dimension is the last one; stacked copies are all alike
        bounds = bounds.isel({d: 0 for d in bounds.dims if d not in ("force_bin", bounds.dims[-1])})
        edges = np.asarray(bounds.transpose("force_bin", ...).values, dtype=float)
        return edges.mean(axis=1), edges[:, 1] - edges[:, 0]
    if "force_bin_edges" in ds:  # (…, B + 1), the same for every snapshot
        edges = np.asarray(ds["force_bin_edges"].values, dtype=float)
        edges = edges.reshape(-1, edges.shape[-1])[0]
        return 0.5 * (edges[1:] + edges[:-1]), np.diff(edges)
    centres = np.asarray(ds["force_bin"].values, dtype=float)
    return centres, (np.gradient(centres) if centres.size > 1 else np.ones_like(centres))


def force_pdf_width(ds: xr.Dataset) -> xr.DataArray:
    """Standard deviation of F/⟨F⟩ of each snapshot, from its total-force PDF [⟨F⟩], dims (realization, rho).

    Forces beyond the last bin are not counted (the PDF is renormalised over the bins).
    """
    pdf = select_total(ds)["force_pdf"]
    centres, widths = force_bins(ds)
    f = xr.DataArray(centres, dims="force_bin")
    w = xr.DataArray(widths, dims="force_bin")
    mass = (pdf * w).sum("force_bin")
    first = (pdf * w * f).sum("force_bin") / mass
    second = (pdf * w * (f - first) ** 2).sum("force_bin") / mass
    return np.sqrt(second).where(mass > 0)


# =============================================================================================================
# P1 §5.2: shape parameter averaging
# =============================================================================================================
def shape_parameter_average(shape: xr.DataArray, dim: str = "realization") -> tuple[xr.DataArray, xr.DataArray]:
    """P1 §5.2 rule (`forcenet.measures.aggregate_shape_parameter`): S_p = 0 where S̄_p = 0 in at least half
    of the realizations, otherwise the mean over the realizations with S̄_p ≠ 0; NaN entries are missing
    realizations. Returns (S_p, spread), the spread being the standard deviation over the same nonzero
    realizations (0 where S_p = 0)."""
    from forcenet.measures.clusters import aggregate_shape_parameter

    mean = xr.apply_ufunc(aggregate_shape_parameter, shape, input_core_dims=[[dim]], kwargs={"axis": -1})
    _, spread = mean_and_spread(shape.where(shape != 0), dim)
    return mean, spread.where(mean != 0, 0.0).fillna(0.0)


# =============================================================================================================
# Validation table
# =============================================================================================================
def p1_validation(measures: Mapping[str, xr.Dataset], *, rho_tolerance: float | None = None,
                  ridge_min_prominence: float = 0.2, negligible_fraction: float = 0.05) -> pd.DataFrame:
    """P1's numbers and claims beside what `measures` (system → network_measures dataset) shows.

    Rows of kind ``"value"``: per system ρ_J (inflection of mean Z), ρ_max (F_max rule), Z at ρ_J (all
    particles, and rattlers excluded), ρ where Z = d + 1, with P1's value and measured − paper; one row with
    F_max. Rows of kind ``"claim"``: P1's qualitative claims with the measured evidence and a verdict
    (``holds`` / ``does not hold`` / ``not evaluated`` when a system or a quantity is missing):

    - B0/N ridge (P1 §5.1, Fig. 6): a curve B0/N(ρ) with F_th < 0.5 peaks within `rho_tolerance` of ρ_J with a
      topographic prominence ≥ `ridge_min_prominence` × the largest B0/N over (ρ ≤ ρ_max, F_th) — expected for
      Hertzian systems, not for linear ones.
    - B1 = 0 below ρ_J (P1 §5.1, Fig. 7; B2 too in 3D): the largest mean B_k/N (over F_th) at
      ρ < ρ_J − `rho_tolerance` is ≤ `negligible_fraction` × its largest value over ρ ≤ ρ_max.
    - PDF width (P1 §4.1, Fig. 3): mean std of F/⟨F⟩ at each system's largest ρ ≤ ρ_max orders
      2D linear < 2D Hertzian < 3D Hertzian.
    - Percolation only above ρ_J (P1 §4): the smallest ρ where ≥ 50 % of the realizations percolate at the
      lowest F_th exists and is ≥ ρ_J − `rho_tolerance`.

    For a claim, ``measured`` holds its key number: the ridge's relative prominence, the largest B_k/N below
    ρ_J, the 3D − linear PDF width difference, the percolation onset ρ_p; ``evidence`` says the rest.
    `rho_tolerance` defaults to the larger of P1's Δρ = 0.02 and the system's own grid step.
    """
    present = {name: ds for name, ds in measures.items() if ds is not None}
    systems = system_order(set(P1_SYSTEMS) | set(present))
    cut = f_max_cut(present) if present else None
    rows: list[dict] = []
    if cut is not None:
        rows.append(_row("value", "F_max (min over systems of max_rho <F>)", "all", cut.f_max, math.nan,
                         f"F'_max: " + ", ".join(f"{n} {v:.4g}" for n, v in cut.f_prime_max.items())
                         + f" [{cut.force_units}]", ""))
    info = {}
    for name in systems:
        ds = present.get(name)
        info[name] = _system_values(name, ds, cut, rho_tolerance)
        rows.extend(_value_rows(name, ds, info[name]))
    for name in systems:
        rows.append(_ridge_row(name, present.get(name), info[name], ridge_min_prominence))
    for name in systems:
        ds = present.get(name)
        dims = [1, 2] if ds is not None and system_dimension(ds, name) == 3 else [1]
        for k in dims:
            rows.append(_loops_row(name, ds, info[name], k, negligible_fraction))
    rows.append(_pdf_width_row(present, info))
    for name in systems:
        rows.append(_percolation_row(name, present.get(name), info[name]))
    return pd.DataFrame(rows, columns=list(COLUMNS))


def p1_validation_markdown(table: pd.DataFrame) -> str:
    """The validation table as Markdown: one table of values, one of claims."""
    lines = ["# P1 validation", "",
             "Measured from the aggregated network measures; paper values from P1 "
             "(compressed 2D/3D interaction networks). difference = measured − paper.", "",
             "## Values", ""]
    values = table[table["kind"] == "value"]
    lines += _markdown_table(values, ["item", "system", "measured", "paper", "difference", "evidence", "verdict"])
    lines += ["", "## Claims", ""]
    claims = table[table["kind"] == "claim"]
    lines += _markdown_table(claims, ["item", "system", "measured", "evidence", "verdict"])
    return "\n".join(lines) + "\n"


def write_p1_validation(table: pd.DataFrame, csv_path: str | os.PathLike, md_path: str | os.PathLike) -> None:
    """Write the validation table as CSV and Markdown."""
    for path in (csv_path, md_path):
        Path(path).parent.mkdir(parents=True, exist_ok=True)
    table.to_csv(csv_path, index=False)
    Path(md_path).write_text(p1_validation_markdown(table))


# --- per-system quantities ------------------------------------------------------------------------------------
def _system_values(name: str, ds: xr.Dataset | None, cut: FMaxCut | None, rho_tolerance: float | None) -> dict:
    if ds is None:
        return {}
    rho = rho_values(ds)
    step = float(np.median(np.diff(rho))) if rho.size > 1 else 0.0
    rho_j = jamming_point(ds)
    return {
        "dimension": system_dimension(ds, name),
        "force_law": system_force_law(ds, name),
        "rho_j": rho_j,
        "rho_max": cut.rho_max.get(name, math.nan) if cut else math.nan,
        "tolerance": rho_tolerance if rho_tolerance is not None else max(P1_RHO_STEP, step),
    }


def _value_rows(name: str, ds: xr.Dataset | None, info: dict) -> list[dict]:
    dimension = info.get("dimension") or (3 if name.startswith("3d") else 2)
    paper_z = PAPER_Z_AT_JAMMING.get(dimension, math.nan)
    if ds is None:
        return [_row("value", item, name, math.nan, paper, "system not in the results", NOT_EVALUATED)
                for item, paper in (("rho_J (inflection of Z)", PAPER_RHO_J.get(name, math.nan)),
                                    ("rho_max (F_max rule)", PAPER_RHO_MAX.get(name, math.nan)),
                                    ("Z at rho_J", paper_z))]
    rho_j = info["rho_j"]
    rows = [
        _value_row("rho_J (inflection of Z)", name, rho_j, PAPER_RHO_J.get(name, math.nan),
                   f"inflection of the mean Z(rho) over {ds.sizes.get('realization', 1)} realizations"),
        _value_row("rho_max (F_max rule)", name, info["rho_max"], PAPER_RHO_MAX.get(name, math.nan),
                   "largest rho with mean <F> <= F_max"),
        _value_row("Z at rho_J", name, value_at(ds, "Z", rho_j), paper_z, "mean Z (all particles) at rho_J"),
    ]
    if "Z_no_rattlers" in ds:
        rows.append(_value_row("Z at rho_J (rattlers excluded)", name, value_at(ds, "Z_no_rattlers", rho_j),
                               paper_z, "mean Z without rattlers at rho_J"))
    rows.append(_value_row("rho at Z = d+1", name, isostatic_crossing(ds), math.nan,
                           f"first rho where the mean Z reaches {info['dimension'] + 1} (P2's definition)"))
    return rows


def _value_row(item: str, system: str, measured: float, paper: float, evidence: str) -> dict:
    verdict = "" if np.isfinite(measured) else NOT_EVALUATED
    return _row("value", item, system, measured, paper, evidence, verdict)


def _row(kind: str, item: str, system: str, measured: float, paper: float, evidence: str, verdict: str) -> dict:
    measured, paper = float(measured), float(paper)
    difference = measured - paper if np.isfinite(measured) and np.isfinite(paper) else math.nan
    return dict(kind=kind, item=item, system=system, measured=measured, paper=paper, difference=difference,
                evidence=evidence, verdict=verdict)


def _claim(item: str, system: str, measured: float, evidence: str, verdict: str) -> dict:
    return _row("claim", item, system, measured, math.nan, evidence, verdict)


# --- claims -------------------------------------------------------------------------------------------------
RIDGE_ITEM = "B0/N ridge near rho_J at small F_th (Hertzian only)"
PDF_ITEM = "PDF width at rho_max: 2D linear < 2D Hertzian < 3D Hertzian"
PERCOLATION_ITEM = "percolation only above rho_J"


def _loops_item(k: int) -> str:
    return f"B{k} = 0 below rho_J"


def _ridge_row(name: str, ds: xr.Dataset | None, info: dict, min_prominence: float) -> dict:
    if ds is None:
        return _claim(RIDGE_ITEM, name, math.nan, "system not in the results", NOT_EVALUATED)
    expected = {"hertz": True, "linear": False}.get(info["force_law"])
    if expected is None:
        return _claim(RIDGE_ITEM, name, math.nan, f"force law '{info['force_law']}' unknown", NOT_EVALUATED)
    if not np.isfinite(info["rho_j"]):
        return _claim(RIDGE_ITEM, name, math.nan, "rho_J could not be located", NOT_EVALUATED)
    total = cut_at_rho_max(select_total(ds), info["rho_max"])
    b0 = per_particle(total, "betti").sel(homology_dim=0).mean("realization", skipna=True)
    b0 = b0.transpose("rho", "threshold")
    thresholds = np.asarray(b0["threshold"].values, dtype=float)
    small = np.flatnonzero(thresholds < P1_SMALL_THRESHOLD)
    scale = _nanmax(b0.values)
    if small.size == 0 or not np.isfinite(scale) or scale <= 0 or total.sizes["rho"] < 3:
        return _claim(RIDGE_ITEM, name, math.nan, "no F_th < 0.5, no clusters or fewer than 3 rho", NOT_EVALUATED)
    rho = rho_values(total)
    best = None  # (near, relative prominence, threshold, rho of the peak, peak)
    for index in small:
        curve = b0.values[:, index]
        if not np.isfinite(curve).any():
            continue
        k = int(np.nanargmax(curve))
        prominence = curve[k] - max(np.nanmin(curve[:k + 1]), np.nanmin(curve[k:]))
        near = abs(rho[k] - info["rho_j"]) <= info["tolerance"] + 1e-12
        candidate = (near, prominence / scale, thresholds[index], rho[k], curve[k])
        if best is None or candidate[:2] > best[:2]:
            best = candidate
    if best is None:
        return _claim(RIDGE_ITEM, name, math.nan, "B0 is NaN for every F_th < 0.5", NOT_EVALUATED)
    near, relative, threshold, rho_peak, peak = best
    present_ = bool(near and relative >= min_prominence)
    evidence = (f"strongest peak at F_th={threshold:.3g}: B0/N={peak:.3g} at rho={rho_peak:.3f} "
                f"(rho_J={info['rho_j']:.3f}, tolerance {info['tolerance']:.3g}); prominence "
                f"{relative:.2f} of max B0/N {scale:.3g} (ridge if >= {min_prominence}); "
                f"ridge {'found' if present_ else 'absent'}, expected {'present' if expected else 'absent'} "
                f"for a {info['force_law']} force law")
    return _claim(RIDGE_ITEM, name, relative, evidence, HOLDS if present_ == expected else FAILS)


def _loops_row(name: str, ds: xr.Dataset | None, info: dict, k: int, negligible: float) -> dict:
    item = _loops_item(k)
    if ds is None:
        return _claim(item, name, math.nan, "system not in the results", NOT_EVALUATED)
    if not np.isfinite(info["rho_j"]):
        return _claim(item, name, math.nan, "rho_J could not be located", NOT_EVALUATED)
    total = cut_at_rho_max(select_total(ds), info["rho_max"])
    if k not in total["homology_dim"].values:
        return _claim(item, name, math.nan, f"no B{k} in the results", NOT_EVALUATED)
    betti = per_particle(total, "betti").sel(homology_dim=k).max("threshold", skipna=True)  # (realization, rho)
    mean = betti.mean("realization", skipna=True).values
    rho = rho_values(total)
    below = rho < info["rho_j"] - info["tolerance"] - 1e-12
    if not below.any():
        return _claim(item, name, math.nan, f"no rho below rho_J - {info['tolerance']:.3g}", NOT_EVALUATED)
    below_max, overall_max = _nanmax(mean[below]), _nanmax(mean)
    with_loops = int((betti.isel(rho=np.flatnonzero(below)) > 0).sum())
    snapshots = int(below.sum()) * total.sizes.get("realization", 1)
    holds = below_max <= negligible * overall_max or below_max == 0
    evidence = (f"max mean B{k}/N (over F_th) for rho < {info['rho_j'] - info['tolerance']:.3f}: {below_max:.3g} "
                f"vs {overall_max:.3g} over rho <= rho_max (negligible if <= {negligible} of it); "
                f"{with_loops} of {snapshots} snapshots below have B{k} > 0")
    return _claim(item, name, below_max, evidence, HOLDS if holds else FAILS)


def _pdf_width_row(present: Mapping[str, xr.Dataset], info: Mapping[str, dict]) -> dict:
    roles = {}
    for name in system_order(present):
        roles.setdefault((info[name]["dimension"], info[name]["force_law"]), name)  # P1's names come first
    order = [(2, "linear"), (2, "hertz"), (3, "hertz")]
    missing = [f"{d}D {law}" for d, law in order if (d, law) not in roles]
    if missing:
        return _claim(PDF_ITEM, "all", math.nan, f"missing system(s): {', '.join(missing)}", NOT_EVALUATED)
    widths = []
    for key in order:
        name = roles[key]
        total = cut_at_rho_max(present[name], info[name]["rho_max"])
        width = force_pdf_width(total).isel(rho=-1).mean("realization", skipna=True)
        widths.append((name, float(total["rho"].values[-1]), float(width)))
    if not all(np.isfinite(w) for _, _, w in widths):
        return _claim(PDF_ITEM, "all", math.nan, "PDF width undefined (empty PDF)", NOT_EVALUATED)
    holds = widths[0][2] < widths[1][2] < widths[2][2]
    evidence = "std of F/<F> at the largest rho <= rho_max: " + "; ".join(
        f"{name} {w:.3g} (rho={r:.3f})" for name, r, w in widths)
    return _claim(PDF_ITEM, "all", widths[2][2] - widths[0][2], evidence, HOLDS if holds else FAILS)


def _percolation_row(name: str, ds: xr.Dataset | None, info: dict) -> dict:
    if ds is None:
        return _claim(PERCOLATION_ITEM, name, math.nan, "system not in the results", NOT_EVALUATED)
    if not np.isfinite(info["rho_j"]):
        return _claim(PERCOLATION_ITEM, name, math.nan, "rho_J could not be located", NOT_EVALUATED)
    fraction = percolation_fraction(ds)
    lowest = fraction.isel(threshold=int(np.argmin(fraction["threshold"].values)))
    rho = rho_values(ds)
    percolating = np.asarray(lowest.values >= P1_PERCOLATION_MAJORITY)
    threshold = float(lowest["threshold"])
    if not percolating.any():
        evidence = (f"no rho where >= {P1_PERCOLATION_MAJORITY:.0%} of the realizations percolate at "
                    f"F_th={threshold:.3g} (rho_J={info['rho_j']:.3f})")
        return _claim(PERCOLATION_ITEM, name, math.nan, evidence, FAILS)
    rho_p = float(rho[percolating].min())
    holds = rho_p >= info["rho_j"] - info["tolerance"] - 1e-12
    evidence = (f"first rho where >= {P1_PERCOLATION_MAJORITY:.0%} of the realizations percolate at "
                f"F_th={threshold:.3g}: rho_p={rho_p:.3f}; rho_J={info['rho_j']:.3f} "
                f"(tolerance {info['tolerance']:.3g})")
    return _claim(PERCOLATION_ITEM, name, rho_p, evidence, HOLDS if holds else FAILS)


# --- helpers ---------------------------------------------------------------------------------------------------
def _nanmax(values) -> float:
    values = np.asarray(values, dtype=float)
    return float(np.nanmax(values)) if np.isfinite(values).any() else math.nan


def _format(value) -> str:
    if isinstance(value, (float, np.floating)):
        return "–" if not np.isfinite(value) else f"{value:.4g}"
    return str(value).replace("|", "\\|")


def _markdown_table(frame: pd.DataFrame, columns: list[str]) -> list[str]:
    lines = ["| " + " | ".join(columns) + " |", "|" + "|".join("---" for _ in columns) + "|"]
    for _, row in frame.iterrows():
        lines.append("| " + " | ".join(_format(row[c]) for c in columns) + " |")
    return lines
