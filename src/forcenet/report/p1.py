"""P1 (compressed 2D/3D interaction networks): the reductions its figures share, and its validation table.

Inputs are the aggregated ``results/{system}/network_measures.nc`` datasets (dims ``realization``, ``rho``,
``force_kind``, ``homology_dim``, ``threshold``, ``force_bin``, ``persistence_bin``; see
`forcenet.datasets.aggregate`), keyed by system name. P1 analyses the total force |F_n + F_t| only, so every
reduction here selects ``force_kind = "total"``.

Reductions (the P1 figures in `forcenet.plotting.p1` use the same functions):

- `f_max_cut` — P1 §3: F'_max = max over ρ of the realization-mean ⟨F⟩, F_max = min over systems of F'_max,
  ρ_max = largest ρ whose mean ⟨F⟩ ≤ F_max. ⟨F⟩ is compared in one of `P1_FORCE_UNITS` (config key
  ``analysis.p1_force_unit``): ``dyn``, each system's ``reduced`` unit m̄ d_ave τ_c⁻², or ``stiffness_scale``
  k_n d_ave^(1+β).
- `shape_parameter_average` — P1 §5.2: S_p = 0 where S̄_p = 0 in at least half of the realizations, else the
  mean over the realizations with S̄_p ≠ 0.
- `percolation_fraction`, `percolating_size_mean` — P1 §4.3: N_per/N is shown only where at least 50 % of
  the realizations percolate.
- `jamming_point` — P1 §4: ρ_J is the inflection point of the realization-mean Z(ρ).

The validation table (`p1_validation`) sets the measured ρ_J, ρ_max (under each force unit), Z(ρ_J) and the
percolation threshold φ_c of P1 Eq. 6 beside P1's, and judges every claim P1 makes about its results in
§3–6 (`CLAIMS`: one `Claim` record and one judging function per claim) with a computed criterion whose
tolerances are the documented fields of `ClaimTolerances`. The only typed-in numbers are P1's own: its
reference values and the definitions it states (Δρ = 0.02, "small F_th < 0.5", "twice the average force", the
50 % percolation rule, the S_p bounds 4 and 7).
"""
from __future__ import annotations

import json
import math
import os
from dataclasses import asdict, dataclass, field
from pathlib import Path
from typing import Callable, Mapping

import numpy as np
import pandas as pd
import xarray as xr

# --- P1's reference values (the only results typed in) --------------------------------------------------------
P1_SYSTEMS = ("2d_hertz", "2d_linear", "3d_hertz")  # P1's panel order a, b, c
HERTZ_2D, LINEAR_2D, HERTZ_3D = (2, "hertz"), (2, "linear"), (3, "hertz")  # roles: (dimension, force law)
P1_ROLES = {"2d_hertz": HERTZ_2D, "2d_linear": LINEAR_2D, "3d_hertz": HERTZ_3D}
PAPER_RHO_J = {"2d_hertz": 0.842, "2d_linear": 0.834, "3d_hertz": 0.57}  # P1 §4 (inflection of Z)
PAPER_RHO_MAX = {"2d_hertz": 0.906, "2d_linear": 0.890, "3d_hertz": 0.710}  # P1 §3 (F_max rule)
PAPER_Z_AT_JAMMING = {2: 3.0, 3: 6.0}  # P1 §4.3: ⟨k⟩ ≈ 3 (2D) and ≈ 6 (3D) close to jamming
PAPER_PHI_C = {2: 0.5, 3: 0.2}  # P1 §4.3, Eq. 6 with ⟨k²⟩ ≈ ⟨k⟩²: φ_c ≃ 0.5 (2D), 0.2 (3D) at ρ_J
PAPER_CLUSTER_SIZE_PEAK = {LINEAR_2D: 1.25, HERTZ_2D: 1.5, HERTZ_3D: 2.0}  # P1 §4.2: F_th of the ⟨S⟩/N maximum

# --- definitions P1 states (not results) --------------------------------------------------------------------
P1_RHO_STEP = 0.02  # §3: compression step Δρ between relaxed states
P1_SMALL_THRESHOLD = 0.5  # §5.1: "for small values of F_th < 0.5" (the B0/N ridge)
P1_LARGE_THRESHOLD = 2.0  # §5.2: "large force thresholds (considering forces larger than twice the average force)"
P1_PERCOLATION_MAJORITY = 0.5  # §4.3: N_per/N shown only where ≥ 50 % of the realizations percolate
P1_HALF = 0.5  # §6: the 2D percolating cluster holds "often at least half of the total number of particles"
P1_SHAPE_BOUNDS = {2: 4.0, 3: 7.0}  # §5.2: S̄_p ≤ 4 (2D), ≤ 7 (3D); open paths S̄_p ≥ 0.5
P1_OPEN_PATH_MIN = 0.5

# --- the force unit of the F_max rule (config key analysis.p1_force_unit) -----------------------------------
#: unit → its label; the per-system constants come from the network_measures attributes written by the
#: aggregation (`forcenet.pipeline.force_constants`)
P1_FORCE_UNITS = {
    "dyn": "dyn",  # ⟨F⟩ × force_unit_dyn (m̄ d_ave τ_c⁻² in dyn; τ_c differs between the laws)
    "reduced": "m_mean d_ave tau_c-2 (each system's own)",  # ⟨F⟩ as stored
    "stiffness_scale": "k_n d_ave^(1+beta)",  # ⟨F⟩ / stiffness_scale_reduced; for P1's material the same in dyn
}
DEFAULT_P1_FORCE_UNIT = "dyn"
_UNIT_ATTRS = {"dyn": "force_unit_dyn", "reduced": None, "stiffness_scale": "stiffness_scale_reduced"}

TOTAL = "total"  # P1 uses the total force |F_n + F_t|
HOLDS, FAILS, NOT_EVALUATED = "holds", "does not hold", "not evaluated"
COLUMNS = ("kind", "id", "section", "item", "system", "measured", "paper", "difference", "criterion", "evidence",
           "verdict")


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
    unit : the key of `P1_FORCE_UNITS` the forces were compared in; force_units : its label
    mean_force : per system, the realization-mean ⟨F⟩(ρ) in that unit
    """

    f_max: float
    f_prime_max: dict[str, float]
    rho_max: dict[str, float]
    unit: str = DEFAULT_P1_FORCE_UNIT
    force_units: str = P1_FORCE_UNITS[DEFAULT_P1_FORCE_UNIT]
    mean_force: dict[str, xr.DataArray] = field(default_factory=dict, repr=False)

    def below_grid(self, name: str) -> bool:
        """True when every ρ of system `name` has a mean ⟨F⟩ above F_max: its ρ_max lies below its ρ grid."""
        curve = self.mean_force.get(name)
        return bool(np.isnan(self.rho_max.get(name, math.nan)) and curve is not None
                    and np.isfinite(curve.values).any())


def force_scale(ds: xr.Dataset, unit: str = DEFAULT_P1_FORCE_UNIT, name: str = "") -> float:
    """The factor taking the stored ⟨F⟩ (reduced units m̄ d_ave τ_c⁻²) to `unit` (a key of `P1_FORCE_UNITS`):
    ``force_unit_dyn`` for dyn, 1 for reduced, 1 / ``stiffness_scale_reduced`` for k_n d_ave^(1+β).

    Raises ValueError when the dataset lacks the attribute (or it is NaN: a system without a material has no
    dyn), naming the system and the attribute."""
    if unit not in P1_FORCE_UNITS:
        raise ValueError(f"unknown P1 force unit {unit!r}; known: {', '.join(P1_FORCE_UNITS)}")
    attr = _UNIT_ATTRS[unit]
    if attr is None:
        return 1.0
    value = float(ds.attrs.get(attr, math.nan))
    if not np.isfinite(value) or value <= 0:
        raise ValueError(f"{name or ds.attrs.get('system', 'a system')}: attribute {attr} missing or NaN in its "
                         f"network measures: <F> cannot be compared in {unit!r} (analysis.p1_force_unit)")
    return value if unit == "dyn" else 1.0 / value


def mean_force(ds: xr.Dataset, scale: float = 1.0) -> xr.DataArray:
    """Realization-mean ⟨F⟩ of the total-force network versus ρ, times `scale` (e.g. dyn per reduced unit)."""
    return select_total(ds)["mean_force"].mean("realization", skipna=True) * scale


def f_max_cut(measures: Mapping[str, xr.Dataset], unit: str = DEFAULT_P1_FORCE_UNIT) -> FMaxCut:
    """P1 §3 F_max rule over the systems in `measures`, ⟨F⟩ compared in `unit` (see `FMaxCut`, `force_scale`).

    Raises ValueError if a system lacks the constant the unit needs."""
    if not measures:
        raise ValueError("f_max_cut needs at least one system")
    curves = {name: mean_force(ds, force_scale(ds, unit, name)) for name, ds in measures.items()}
    f_prime = {name: _nanmax(curve.values) for name, curve in curves.items()}
    finite = [value for value in f_prime.values() if np.isfinite(value)]
    f_max = min(finite) if finite else math.nan
    rho_max = {}
    for name, curve in curves.items():
        rho = rho_values(curve)
        below = np.asarray(curve.values <= f_max)  # NaN (no contacts) compares False
        rho_max[name] = float(rho[below].max()) if below.any() else math.nan
    return FMaxCut(f_max=f_max, f_prime_max=f_prime, rho_max=rho_max, unit=unit, force_units=P1_FORCE_UNITS[unit],
                   mean_force=curves)


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
# Claims: the record, the tolerances, the data a judge sees
# =============================================================================================================
@dataclass(frozen=True)
class ClaimTolerances:
    """Tolerances of the claim criteria; each is a keyword argument of `p1_validation`.

    rho_tolerance : "near ρ_J" means |ρ − ρ_J| ≤ this; "below" and "beyond ρ_J" mean ρ < ρ_J − this and
        ρ > ρ_J + this.
        None: the larger of P1's Δρ = 0.02 and the system's own ρ step.
    rho_window : width of the ρ window of "a rise close to ρ_J" (ρ_J ± this) and of "a plateau near ρ_max"
        (the last window before ρ_max). None: twice the system's rho_tolerance.
    min_prominence : a peak of a curve versus ρ needs a topographic prominence ≥ this fraction of its scale
        (B0/N ridge and ⟨S⟩/N peak: the largest value over (ρ, F_th); persistence bins: the curve's maximum).
    negligible_fraction : "B_k = 0", "TP2 ≈ 0": the largest value below ρ_J ≤ this fraction of the largest
        value of the curve; a rise is real when it exceeds this fraction of the maximum.
    monotone_tolerance : "grows monotonically": no drop between consecutive ρ beyond ρ_J larger than this
        fraction of the curve's maximum.
    plateau_fraction : "plateaus near ρ_max": the change over the last `rho_window` before ρ_max ≤ this
        fraction of the whole rise up to ρ_max.
    threshold_tolerance : an F_th P1 quotes (1.25, 1.5, 2.0) is met within this (P1 quotes multiples of 0.25).
    unity_tolerance : "S_p ≈ 1": |median S_p − 1| ≤ this.
    shape_difference : "S_p significantly larger": the means differ by at least this.
    almost_all : "almost all the particles" in the percolating cluster: median N_per/N ≥ this.
    small_share : "a very small number of particles" in the percolating cluster: N_per/N ≤ this (P1's own
        estimate φ_c ≈ 0.2 in 3D sets the scale).
    similar_ratio : "very similar" across systems: largest / smallest ≤ this.
    jump_factor : "a sudden increase beyond jamming": the value at the first ρ beyond ρ_J ≥ this × the value at
        the last ρ below it.
    steeper_factor : "a significantly more prominent increase close to ρ_J" in 3D: its rise over ρ_J ±
        rho_window ≥ this × the larger 2D rise.
    pdf_distance : "significantly different" force PDFs: total-variation distance ½ ∫|p − q| dF ≥ this.
    min_clusters : "a non-vanishing number of clusters": realization-mean count per snapshot ≥ this.
    """

    rho_tolerance: float | None = None
    rho_window: float | None = None
    min_prominence: float = 0.2
    negligible_fraction: float = 0.05
    monotone_tolerance: float = 0.1
    plateau_fraction: float = 0.25
    threshold_tolerance: float = 0.25
    unity_tolerance: float = 0.25
    shape_difference: float = 0.1
    almost_all: float = 0.8
    small_share: float = 0.3
    similar_ratio: float = 1.5
    jump_factor: float = 2.0
    steeper_factor: float = 1.5
    pdf_distance: float = 0.1
    min_clusters: float = 1.0


class NotEvaluated(Exception):
    """Raised by a judge when the claim cannot be judged from the data; the message says why."""


@dataclass(frozen=True)
class Judgement:
    """What a judge found: the key number, the evidence (numbers behind the verdict) and whether the claim holds."""

    measured: float
    evidence: str
    holds: bool


@dataclass(frozen=True)
class Claim:
    """One claim P1 makes about its results.

    id : stable identifier ``p1-<section>-<topic>``; section : P1's section; statement : the claim in short
    (P1's words where possible); criterion : how it is judged here, with ``{tolerance}`` placeholders filled
    from `ClaimTolerances`; paper : the number P1 states, per role (dimension, force law) or one for all, NaN
    when the claim is qualitative; roles : the systems it is about (None: every system) — per-system claims
    give one row per system of those roles, cross-system claims (``per_system=False``) one row; needs_rho_j :
    the judge needs the system's ρ_J; judge : the function judging it, (SystemData, ClaimTolerances) →
    Judgement per system, or (ClaimContext) → Judgement across systems.
    """

    id: str
    section: str
    statement: str
    criterion: str
    judge: Callable = field(repr=False)
    per_system: bool = True
    roles: tuple[tuple[int, str], ...] | None = None
    paper: float | Mapping[tuple[int, str], float] = math.nan
    needs_rho_j: bool = True

    def paper_value(self, role: tuple[int, str] | None) -> float:
        if isinstance(self.paper, Mapping):
            return float(self.paper.get(role, math.nan))
        return float(self.paper)

    def criterion_text(self, tolerances: ClaimTolerances) -> str:
        values = {k: ("per system" if v is None else v) for k, v in asdict(tolerances).items()}
        return self.criterion.format(**values)


@dataclass(frozen=True)
class SystemData:
    """One system as the judges see it.

    data : total-force measures over the judged ρ range (all ρ, or ρ ≤ ρ_max with ``judge_up_to_rho_max``);
    full : total-force measures over every simulated ρ; rho_j : ρ_J (inflection of Z, from every ρ); rho_max :
    ρ_max under the table's force unit; tolerance, window : `ClaimTolerances.rho_tolerance`/`rho_window` resolved
    for this system.
    """

    name: str
    dimension: int
    force_law: str
    data: xr.Dataset
    full: xr.Dataset
    rho_j: float
    rho_max: float
    tolerance: float
    window: float

    @property
    def role(self) -> tuple[int, str]:
        return (self.dimension, self.force_law)

    @property
    def rho(self) -> np.ndarray:
        return rho_values(self.data)

    @property
    def below(self) -> np.ndarray:
        """ρ < ρ_J − tolerance (mask over `data`'s ρ)."""
        return self.rho < self.rho_j - self.tolerance - 1e-12

    @property
    def beyond(self) -> np.ndarray:
        """ρ > ρ_J + tolerance (mask over `data`'s ρ)."""
        return self.rho > self.rho_j + self.tolerance + 1e-12

    @property
    def thresholds(self) -> np.ndarray:
        return np.asarray(self.data["threshold"].values, dtype=float)

    @property
    def lowest_threshold(self) -> float:
        return float(self.thresholds.min())

    def mean(self, name: str, per_n: bool = True, full: bool = False, **selection) -> xr.DataArray:
        """Realization mean of ``name`` (divided by N when `per_n`), with `selection` applied."""
        ds = self.full if full else self.data
        values = per_particle(ds, name) if per_n else ds[name]
        return values.sel(**selection).mean("realization", skipna=True)

    def label(self) -> str:
        return f"{self.name} (rho_J={self.rho_j:.3f})"


@dataclass(frozen=True)
class ClaimContext:
    """Every system present, for claims that compare systems."""

    systems: Mapping[str, SystemData]
    tolerances: ClaimTolerances

    def role(self, role: tuple[int, str]) -> SystemData:
        """The first system (P1's order) with this role; NotEvaluated when none is present or its ρ_J is NaN."""
        for name in system_order(self.systems):
            system = self.systems[name]
            if system.role == role:
                if not np.isfinite(system.rho_j):
                    raise NotEvaluated(f"rho_J of {name} could not be located")
                return system
        raise NotEvaluated(f"no {role[0]}D {role[1]} system in the results")

    def nonlinear(self) -> list[SystemData]:
        """The non-linear (Hertzian) systems present, one per dimension, each with a located ρ_J."""
        found = []
        for role in (HERTZ_2D, HERTZ_3D):
            try:
                found.append(self.role(role))
            except NotEvaluated:
                pass
        if not found:
            raise NotEvaluated("no non-linear system with a located rho_J in the results")
        return found


CLAIMS: list[Claim] = []


def claim(id: str, section: str, statement: str, criterion: str, **options) -> Callable:
    """Register the decorated judge as the claim `id` in `CLAIMS` (see `Claim` for the fields)."""
    def register(judge: Callable) -> Callable:
        CLAIMS.append(Claim(id=id, section=section, statement=statement, criterion=criterion, judge=judge,
                            **options))
        return judge
    return register


ALL_2D = (HERTZ_2D, LINEAR_2D)


# --- helpers the judges share ---------------------------------------------------------------------------------
@dataclass(frozen=True)
class Peak:
    """The highest point of a curve versus ρ: where, how high, its topographic prominence relative to a scale,
    and whether it lies within the tolerance of ρ_J."""

    rho: float
    value: float
    relative_prominence: float
    near: bool


def _peak(curve, rho: np.ndarray, rho_j: float, tolerance: float, scale: float) -> Peak | None:
    """The maximum of `curve` (ρ,) and its prominence: height above the higher of the lowest points on its two
    sides (0 when the maximum is at an end of a monotonic curve), divided by `scale`. None if all NaN."""
    curve = np.asarray(curve, dtype=float)
    if not np.isfinite(curve).any() or not np.isfinite(scale) or scale <= 0:
        return None
    k = int(np.nanargmax(curve))
    prominence = curve[k] - max(np.nanmin(curve[:k + 1]), np.nanmin(curve[k:]))
    return Peak(float(rho[k]), float(curve[k]), float(prominence / scale),
                bool(abs(rho[k] - rho_j) <= tolerance + 1e-12))


def _strongest_peak(values: xr.DataArray, system: SystemData, thresholds: np.ndarray,
                    scale: float) -> tuple[Peak, float] | None:
    """Among the curves values(ρ) at each F_th in `thresholds`, the peak that is near ρ_J with the largest
    prominence (else the most prominent one); returns (peak, its F_th) or None."""
    best = None
    for threshold in thresholds:
        peak = _peak(values.sel(threshold=threshold).transpose("rho").values, system.rho, system.rho_j,
                     system.tolerance, scale)
        if peak is not None and (best is None or (peak.near, peak.relative_prominence)
                                 > (best[0].near, best[0].relative_prominence)):
            best = (peak, float(threshold))
    return best


def _peak_verdict(peak: Peak | None, what: str, system: SystemData, tolerances: ClaimTolerances,
                  expected: bool, threshold: float | None = None) -> Judgement:
    """A peak near ρ_J is present iff near and relative prominence ≥ min_prominence; holds iff as expected."""
    if peak is None:
        raise NotEvaluated(f"{what} is NaN or zero everywhere")
    present = peak.near and peak.relative_prominence >= tolerances.min_prominence
    at = f" at F_th={threshold:.3g}" if threshold is not None else ""
    evidence = (f"highest {what}{at}: {peak.value:.3g} at rho={peak.rho:.3f} ({system.label()}, tolerance "
                f"{system.tolerance:.3g}), relative prominence {peak.relative_prominence:.2f}; peak "
                f"{'present' if present else 'absent'}, expected {'present' if expected else 'absent'} for a "
                f"{system.force_law} law")
    return Judgement(peak.relative_prominence, evidence, present == expected)


def _expected_for_law(system: SystemData, nonlinear: bool) -> bool:
    """True where P1 expects the feature: for the non-linear (Hertz) laws if `nonlinear`, else for the linear law."""
    if system.force_law not in ("hertz", "linear"):
        raise NotEvaluated(f"force law '{system.force_law}' unknown")
    return (system.force_law == "hertz") == nonlinear


def _betti_curve(system: SystemData, k: int, full: bool = False) -> xr.DataArray:
    """Realization mean of max over F_th of B_k/N, versus ρ."""
    ds = system.full if full else system.data
    if k not in ds["homology_dim"].values:
        raise NotEvaluated(f"no B{k} in the results")
    return per_particle(ds, "betti").sel(homology_dim=k).max("threshold", skipna=True).mean("realization",
                                                                                           skipna=True)


def _persistence_curve(system: SystemData, k: int) -> xr.DataArray:
    """Realization mean of TP_k/N versus ρ."""
    if k not in system.data["homology_dim"].values:
        raise NotEvaluated(f"no TP{k} in the results")
    return system.mean("total_persistence", homology_dim=k)


def _bin_curve(system: SystemData, bin_name: str) -> xr.DataArray:
    """Realization mean of the PD0 points per particle in a P1 §5.3 persistence bin, versus ρ."""
    return system.mean("persistence_bin_count", persistence_bin=bin_name)


def _require(mask: np.ndarray, what: str) -> np.ndarray:
    if not np.any(mask):
        raise NotEvaluated(f"no {what}")
    return mask


def _finite(values, what: str) -> np.ndarray:
    values = np.asarray(values, dtype=float).ravel()
    values = values[np.isfinite(values)]
    if values.size == 0:
        raise NotEvaluated(f"{what}: no finite values")
    return values


def _interp(curve: xr.DataArray, rho: float) -> float:
    """Linear interpolation of a curve versus ρ at `rho`, clipped to its finite range."""
    grid, values = rho_values(curve), np.asarray(curve.values, dtype=float)
    ok = np.isfinite(values)
    if not ok.any():
        return math.nan
    return float(np.interp(np.clip(rho, grid[ok].min(), grid[ok].max()), grid[ok], values[ok]))


def _fmt(values, digits: int = 3) -> str:
    return "[" + ", ".join("nan" if not np.isfinite(v) else f"{v:.{digits}g}" for v in np.asarray(values, float)) + "]"


def _zero_below(curve: xr.DataArray, system: SystemData, tolerances: ClaimTolerances, what: str) -> Judgement:
    """`what` ≈ 0 below ρ_J: its largest value at ρ < ρ_J − tolerance ≤ negligible_fraction × its maximum."""
    below = _require(system.below, f"rho below rho_J - {system.tolerance:.3g}")
    values = np.asarray(curve.values, dtype=float)
    below_max, overall = _nanmax(values[below]), _nanmax(values)
    if not np.isfinite(overall):
        raise NotEvaluated(f"{what} is NaN everywhere")
    holds = below_max == 0 or below_max <= tolerances.negligible_fraction * overall
    evidence = (f"max {what} for rho < {system.rho_j - system.tolerance:.3f}: {below_max:.3g}; max over all rho "
                f"{overall:.3g} ({system.label()})")
    return Judgement(below_max, evidence, bool(holds))


def _grows_beyond(curve: xr.DataArray, system: SystemData, tolerances: ClaimTolerances, what: str) -> Judgement:
    """`what` grows monotonically beyond ρ_J: over ρ ≥ ρ_J − tolerance it rises by more than negligible_fraction
    of its maximum and never drops between consecutive ρ by more than monotone_tolerance of it."""
    _require(system.beyond, "rho beyond rho_J")
    from_jamming = system.rho >= system.rho_j - system.tolerance - 1e-12
    values = np.asarray(curve.values, dtype=float)[from_jamming]
    values = values[np.isfinite(values)]
    if values.size < 2:
        raise NotEvaluated(f"fewer than 2 rho from rho_J - {system.tolerance:.3g} on")
    top = float(values.max())
    growth = float(values[-1] - values[0])
    drop = float(max(0.0, np.max(values[:-1] - values[1:])))
    holds = top > 0 and growth > tolerances.negligible_fraction * top and drop <= tolerances.monotone_tolerance * top
    evidence = (f"{what} from rho={system.rho[from_jamming][0]:.3f} on: {_fmt(values)} ({system.label()}); growth "
                f"{growth:.3g}, largest drop {drop:.3g}, max {top:.3g}")
    return Judgement(growth, evidence, bool(holds))


# =============================================================================================================
# The claims of P1 §3–6, one function each
# =============================================================================================================
# --- §3 Protocol and methods ------------------------------------------------------------------------------------
@claim("p1-3-clusters-below-jamming", "3",
       "a relatively small but non-vanishing number of clusters below jamming, in particular in 2D (Figs. 2, 4, 6)",
       "at F_th = min: max over rho < rho_J - tol of the mean cluster count >= {min_clusters}, and its B0/N <= the "
       "largest mean B0/N (any F_th) beyond rho_J + tol", roles=ALL_2D)
def clusters_below_jamming(system: SystemData, tolerances: ClaimTolerances) -> Judgement:
    below = _require(system.below, "rho below rho_J")
    beyond = _require(system.beyond, "rho beyond rho_J")
    count = system.mean("cluster_count", per_n=False, threshold=system.lowest_threshold).values
    share = system.mean("cluster_count", threshold=system.lowest_threshold).values
    most_below, share_below = _nanmax(count[below]), _nanmax(share[below])
    share_beyond = _nanmax(system.mean("cluster_count").transpose("rho", "threshold").values[beyond])
    holds = most_below >= tolerances.min_clusters and share_below <= share_beyond
    evidence = (f"mean clusters at F_th={system.lowest_threshold:.3g} below rho_J: {_fmt(count[below])} "
                f"(B0/N up to {share_below:.3g}); largest B0/N beyond rho_J {share_beyond:.3g} ({system.label()})")
    return Judgement(most_below, evidence, bool(holds))


def _not_measured(reason: str) -> Callable:
    def judge(context: ClaimContext) -> Judgement:
        raise NotEvaluated(reason)
    return judge


for _id, _statement, _reason in (
        ("p1-3-overlap", "at the largest rho the particles overlap by up to 10 % of the sum of the radii",
         "the overlaps are not among the network measures (they are in the snapshots)"),
        ("p1-3-system-size", "the results stay qualitatively the same for 25x25 and 75x75 (2D), 10^3 and 30^3 (3D)",
         "needs runs at several box sizes"),
        ("p1-3-friction", "friction (mu = 0, 0.03, 0.5) changes only rho_J and the precise values (also §6)",
         "needs runs at several friction coefficients"),
        ("p1-3-relaxation", "stricter or other relaxation criteria change neither conclusions nor measured values",
         "needs runs under several relaxation protocols")):
    claim(_id, "3", _statement, "not computable from one set of runs", per_system=False,
          needs_rho_j=False)(_not_measured(_reason))


# --- §4 Force distribution, percolation and jamming -------------------------------------------------------------
@claim("p1-4-percolation-at-jamming", "4",
       "a stable percolating cluster forms for any and only when rho > rho_J: rho_p = rho_J",
       "rho_p = first rho where >= 50 % of the realizations percolate at F_th = min; |rho_p - rho_J| <= tol and "
       "the majority percolates at every rho > rho_J + tol")
def percolation_at_jamming(system: SystemData, tolerances: ClaimTolerances) -> Judgement:
    fraction = percolation_fraction(system.data).sel(threshold=system.lowest_threshold).values
    percolating = fraction >= P1_PERCOLATION_MAJORITY
    if not percolating.any():
        return Judgement(math.nan, f"no rho where >= 50 % of the realizations percolate at F_th="
                                   f"{system.lowest_threshold:.3g} ({system.label()})", False)
    rho_p = float(system.rho[percolating].min())
    gaps = system.rho[system.beyond & ~percolating]
    holds = abs(rho_p - system.rho_j) <= system.tolerance + 1e-12 and gaps.size == 0
    evidence = (f"rho_p={rho_p:.3f}, {system.label()}, tolerance {system.tolerance:.3g}; fraction percolating "
                f"{_fmt(fraction, 2)} at rho {_fmt(system.rho)}"
                + (f"; no majority at rho {_fmt(gaps)}" if gaps.size else ""))
    return Judgement(rho_p, evidence, bool(holds))


@claim("p1-4.1-pdf-order-at-rho-max", "4.1",
       "at rho ~ rho_max the force PDF is narrowest for 2D linear, wider for 2D Hertz, widest in 3D (Fig. 3)",
       "std of F/<F> (mean over realizations) at each system's largest rho <= rho_max: 2D linear < 2D Hertz < 3D",
       per_system=False)
def pdf_order_at_rho_max(context: ClaimContext) -> Judgement:
    widths = []
    for role in (LINEAR_2D, HERTZ_2D, HERTZ_3D):
        system = context.role(role)
        if not np.isfinite(system.rho_max):
            raise NotEvaluated(f"rho_max of {system.name} undefined")
        top = cut_at_rho_max(system.full, system.rho_max)
        width = float(force_pdf_width(top).isel(rho=-1).mean("realization", skipna=True))
        widths.append((system.name, float(top["rho"].values[-1]), width))
    if not all(np.isfinite(w) for _, _, w in widths):
        raise NotEvaluated("PDF width undefined (empty PDF)")
    holds = widths[0][2] < widths[1][2] < widths[2][2]
    evidence = "std of F/<F> at the largest rho <= rho_max: " + "; ".join(
        f"{name} {w:.3g} (rho={r:.3f})" for name, r, w in widths)
    return Judgement(widths[2][2] - widths[0][2], evidence, holds)


def _jammed_pdf_width(system: SystemData) -> float:
    beyond = _require(system.beyond, f"rho beyond rho_J for {system.name}")
    width = force_pdf_width(system.data).mean("realization", skipna=True).values
    return float(np.nanmean(_finite(width[beyond], f"PDF width of {system.name} beyond rho_J")))


@claim("p1-5.3-pdf-wider-nonlinear", "5.3",
       "beyond jamming the force PDFs of the non-linear systems are wider than the linear one, in 2D and 3D "
       "(§4.1, §5.3, §6)",
       "mean std of F/<F> over rho > rho_J + tol: every non-linear system > 2D linear", per_system=False)
def pdf_wider_nonlinear(context: ClaimContext) -> Judgement:
    linear = _jammed_pdf_width(context.role(LINEAR_2D))
    widths = {system.name: _jammed_pdf_width(system) for system in context.nonlinear()}
    margin = min(widths.values()) - linear
    evidence = (f"mean std of F/<F> beyond rho_J: 2D linear {linear:.3g}; "
                + ", ".join(f"{name} {w:.3g}" for name, w in widths.items()))
    return Judgement(margin, evidence, margin > 0)


def _mean_pdf_below(system: SystemData) -> tuple[np.ndarray, np.ndarray]:
    """Mean PDF of F/⟨F⟩ over the realizations and the ρ below ρ_J, normalised over the bins:
    (bin centres, probability per bin)."""
    below = _require(system.below, f"rho below rho_J for {system.name}")
    pdf = system.data["force_pdf"].isel(rho=np.flatnonzero(below)).mean(("realization", "rho"), skipna=True)
    centres, widths = force_bins(system.data)
    mass = np.asarray(pdf.values, dtype=float) * widths
    if not np.isfinite(mass).all() or mass.sum() <= 0:
        raise NotEvaluated(f"no force PDF below rho_J for {system.name}")
    return centres, mass / mass.sum()


@claim("p1-6-pdf-2d-3d-differ-below-jamming", "6",
       "at small rho the force distributions differ significantly between 2D and 3D systems",
       "total-variation distance between the mean PDFs of F/<F> over rho < rho_J - tol of 3D and of each 2D "
       "system >= {pdf_distance}", per_system=False)
def pdf_2d_3d_differ(context: ClaimContext) -> Judgement:
    centres_3d, pdf_3d = _mean_pdf_below(context.role(HERTZ_3D))
    distances = {}
    for role in ALL_2D:
        system = context.role(role)
        centres, pdf = _mean_pdf_below(system)
        if centres.shape != centres_3d.shape or not np.allclose(centres, centres_3d):
            raise NotEvaluated("the systems' force PDFs have different bins")
        distances[system.name] = 0.5 * float(np.abs(pdf - pdf_3d).sum())
    smallest = min(distances.values())
    evidence = "total-variation distance to 3D below rho_J: " + ", ".join(f"{n} {d:.3g}" for n, d in distances.items())
    return Judgement(smallest, evidence, smallest >= context.tolerances.pdf_distance)


# --- §4.2 Non-percolating clusters ---------------------------------------------------------------------------
def _cluster_size_peak_threshold(system: SystemData) -> tuple[float, np.ndarray]:
    """Median over ρ > ρ_J + tol of the F_th where the mean ⟨S⟩/N is largest; and those F_th per ρ."""
    beyond = _require(system.beyond, f"rho beyond rho_J for {system.name}")
    size = system.mean("cluster_mean_size").transpose("rho", "threshold").values[beyond]
    rows = [row for row in size if np.isfinite(row).any() and np.nanmax(row) > 0]
    if not rows:
        raise NotEvaluated(f"no clusters beyond rho_J for {system.name}")
    best = np.array([system.thresholds[int(np.nanargmax(row))] for row in rows])
    return float(np.median(best)), best


@claim("p1-4.2-cluster-size-peak-threshold", "4.2",
       "beyond jamming <S>/N is largest at F_th = 1.25 (2D linear), 1.5 (2D Hertz), ~2.0 (3D)",
       "median over rho > rho_J + tol of the F_th maximising the mean <S>/N within {threshold_tolerance} of P1's",
       paper=PAPER_CLUSTER_SIZE_PEAK)
def cluster_size_peak_threshold(system: SystemData, tolerances: ClaimTolerances) -> Judgement:
    paper = PAPER_CLUSTER_SIZE_PEAK.get(system.role, math.nan)
    if not np.isfinite(paper):
        raise NotEvaluated(f"P1 gives no value for a {system.dimension}D {system.force_law} system")
    median, best = _cluster_size_peak_threshold(system)
    evidence = f"F_th of the largest <S>/N at each rho beyond rho_J: {_fmt(best)} ({system.label()}); P1 {paper:g}"
    return Judgement(median, evidence, abs(median - paper) <= tolerances.threshold_tolerance + 1e-12)


def _cluster_size_decay(system: SystemData) -> float:
    """Mean over ρ > ρ_J + tol of (mean ⟨S⟩/N over F_th ≥ 2) / (max ⟨S⟩/N over F_th)."""
    beyond = _require(system.beyond, f"rho beyond rho_J for {system.name}")
    size = system.mean("cluster_mean_size").transpose("rho", "threshold").values[beyond]
    large = system.thresholds >= P1_LARGE_THRESHOLD - 1e-12
    if not large.any():
        raise NotEvaluated("no F_th >= 2")
    with np.errstate(invalid="ignore", divide="ignore"):
        ratios = np.nanmean(size[:, large], axis=1) / np.nanmax(size, axis=1)
    return float(np.nanmean(_finite(ratios, f"<S>/N of {system.name} beyond rho_J")))


@claim("p1-4.2-cluster-size-decays-faster-linear", "4.2",
       "in 2D beyond jamming, for F_th >= 2, <S>/N decays faster for the linear law than for the non-linear one",
       "mean over rho > rho_J + tol of (mean <S>/N over F_th >= 2) / (max over F_th): 2D linear < 2D Hertz",
       per_system=False)
def cluster_size_decays_faster_linear(context: ClaimContext) -> Judgement:
    linear, hertz = _cluster_size_decay(context.role(LINEAR_2D)), _cluster_size_decay(context.role(HERTZ_2D))
    evidence = f"<S>/N at F_th >= 2 relative to its maximum: 2D linear {linear:.3g}, 2D Hertz {hertz:.3g}"
    return Judgement(hertz - linear, evidence, linear < hertz)


@claim("p1-4.2-cluster-size-3d-larger-forces", "4.2",
       "3D networks hold more clusters of large forces: <S>/N peaks at a larger F_th than in 2D (also §6)",
       "median F_th of the <S>/N maximum beyond rho_J: 3D > 2D Hertz", per_system=False)
def cluster_size_3d_larger_forces(context: ClaimContext) -> Judgement:
    three, _ = _cluster_size_peak_threshold(context.role(HERTZ_3D))
    two, _ = _cluster_size_peak_threshold(context.role(HERTZ_2D))
    return Judgement(three - two, f"F_th of the <S>/N maximum: 3D {three:.3g}, 2D Hertz {two:.3g}", three > two)


@claim("p1-6-cluster-size-peak-small-threshold", "6",
       "<S>/N peaks close to jamming for small F_th ~ 0, for the non-linear laws only",
       "the strongest peak of mean <S>/N(rho) over F_th < 0.5 lies within tol of rho_J with prominence >= "
       "{min_prominence} of the largest <S>/N; present for Hertz, absent for linear")
def cluster_size_peak_small_threshold(system: SystemData, tolerances: ClaimTolerances) -> Judgement:
    expected = _expected_for_law(system, nonlinear=True)
    size = system.mean("cluster_mean_size")
    small = system.thresholds[system.thresholds < P1_SMALL_THRESHOLD]
    if small.size == 0:
        raise NotEvaluated("no F_th < 0.5")
    found = _strongest_peak(size, system, small, _nanmax(size.values))
    peak, threshold = found if found else (None, None)
    return _peak_verdict(peak, "<S>/N", system, tolerances, expected, threshold)


# --- §4.3 The percolating cluster -----------------------------------------------------------------------------
def _percolating_share(system: SystemData) -> xr.DataArray:
    """N_per/N (ρ, F_th) where ≥ 50 % of the realizations percolate (P1 §4.3), NaN elsewhere."""
    return percolating_size_mean(system.data)[0].transpose("rho", "threshold")


def _onset_share(system: SystemData) -> tuple[float, float]:
    """(ρ, N_per/N) at the first ρ where N_per/N is shown at F_th = min."""
    share = _percolating_share(system).sel(threshold=system.lowest_threshold).values
    shown = np.isfinite(share)
    if not shown.any():
        raise NotEvaluated(f"{system.name} never percolates in >= 50 % of the realizations")
    first = int(np.flatnonzero(shown)[0])
    return float(system.rho[first]), float(share[first])


@claim("p1-4.3-percolating-almost-all-2d", "4.3",
       "in 2D at F_th ~ 0 the percolating cluster contains almost all the particles",
       "median N_per/N at F_th = min over rho > rho_J + tol (where shown) >= {almost_all}", roles=ALL_2D)
def percolating_almost_all(system: SystemData, tolerances: ClaimTolerances) -> Judgement:
    beyond = _require(system.beyond, "rho beyond rho_J")
    share = _percolating_share(system).sel(threshold=system.lowest_threshold).values[beyond]
    values = _finite(share, "N_per/N beyond rho_J")
    median = float(np.median(values))
    evidence = f"N_per/N at F_th={system.lowest_threshold:.3g} beyond rho_J: {_fmt(values)} ({system.label()})"
    return Judgement(median, evidence, median >= tolerances.almost_all)


@claim("p1-4.3-percolating-significant-2d", "4.3",
       "in 2D, whenever a percolating cluster exists it holds a significant share of the particles, often at "
       "least half (also §6)",
       "median of N_per/N over every shown (rho, F_th) >= 0.5 (P1: 'often at least half')", roles=ALL_2D)
def percolating_significant(system: SystemData, tolerances: ClaimTolerances) -> Judgement:
    values = _finite(_percolating_share(system).values, "N_per/N")
    median = float(np.median(values))
    evidence = (f"N_per/N over {values.size} shown (rho, F_th): min {values.min():.3g}, median {median:.3g}, "
                f"max {values.max():.3g} ({system.label()})")
    return Judgement(median, evidence, median >= P1_HALF)


@claim("p1-4.3-percolating-small-3d-near-jamming", "4.3",
       "in 3D near rho_J the percolating cluster contains only a very small share of the particles (also §6)",
       "N_per/N at F_th = min at the first shown rho (<= rho_J + tol) <= {small_share}", roles=(HERTZ_3D,))
def percolating_small_near_jamming(system: SystemData, tolerances: ClaimTolerances) -> Judgement:
    rho, share = _onset_share(system)
    if rho > system.rho_j + system.tolerance + 1e-12:
        raise NotEvaluated(f"percolation first shown at rho={rho:.3f}, beyond rho_J + tol ({system.label()})")
    evidence = f"N_per/N={share:.3g} at F_th={system.lowest_threshold:.3g}, rho={rho:.3f} ({system.label()})"
    return Judgement(share, evidence, share <= tolerances.small_share)


@claim("p1-4.3-percolating-small-3d-large-threshold", "4.3",
       "in 3D the percolating cluster is a very small share of the particles for F_th > 2 (also §6)",
       "median N_per/N over shown (rho, F_th > 2) <= {small_share}", roles=(HERTZ_3D,), needs_rho_j=False)
def percolating_small_large_threshold(system: SystemData, tolerances: ClaimTolerances) -> Judgement:
    large = system.thresholds > P1_LARGE_THRESHOLD + 1e-12
    values = _finite(_percolating_share(system).values[:, large], "N_per/N at F_th > 2 (no percolation shown)")
    median = float(np.median(values))
    evidence = f"N_per/N at F_th > 2 over {values.size} shown (rho, F_th): median {median:.3g}, max {values.max():.3g}"
    return Judgement(median, evidence, median <= tolerances.small_share)


@claim("p1-4.3-percolating-smaller-in-3d", "4.3",
       "near rho_J the percolating cluster is smaller (relative to N) in 3D than in 2D (Eq. 6: phi_c ~ 0.2 vs 0.5)",
       "N_per/N at F_th = min at the first shown rho: 3D < each 2D system", per_system=False)
def percolating_smaller_in_3d(context: ClaimContext) -> Judgement:
    three = _onset_share(context.role(HERTZ_3D))[1]
    two = {context.role(role).name: _onset_share(context.role(role))[1] for role in ALL_2D}
    evidence = f"N_per/N at the percolation onset: 3D {three:.3g}; " + ", ".join(f"{n} {v:.3g}" for n, v in two.items())
    return Judgement(three / min(two.values()) if min(two.values()) > 0 else math.inf, evidence,
                     three < min(two.values()))


@claim("p1-4.3-phi-c-lower-bound", "4.3",
       "phi_c of Eq. 6 (<k^2> ~ <k>^2, so phi_c = 1/(Z - 1)) is a lower bound for N_per/N",
       "at F_th = min and every shown rho: N_per/N >= 1/(Z - 1), Z the mean coordination number", needs_rho_j=False)
def phi_c_lower_bound(system: SystemData, tolerances: ClaimTolerances) -> Judgement:
    share = _percolating_share(system).sel(threshold=system.lowest_threshold).values
    z = system.data["Z"].mean("realization", skipna=True).values
    shown = np.isfinite(share) & np.isfinite(z)
    if not shown.any():
        raise NotEvaluated("no percolation shown")
    with np.errstate(divide="ignore"):
        phi_c = np.where(z[shown] > 1, 1.0 / (z[shown] - 1.0), np.inf)  # P1 Eq. 6 with <k^2> = <k>^2
    margin = share[shown] - phi_c
    evidence = (f"at rho {_fmt(system.rho[shown])}: N_per/N {_fmt(share[shown])} vs phi_c {_fmt(phi_c)} "
                f"({system.name})")
    return Judgement(float(margin.min()), evidence, bool(margin.min() >= 0))


# --- §5.1 Betti numbers -----------------------------------------------------------------------------------------
@claim("p1-5.1-b0-ridge", "5.1",
       "for F_th < 0.5 the non-linear systems develop a pronounced B0/N peak (ridge) near rho_J; for the linear "
       "law it is insignificant (Figs. 2, 6)",
       "the strongest peak of mean B0/N(rho) over F_th < 0.5 lies within tol of rho_J with prominence >= "
       "{min_prominence} of the largest B0/N; present for Hertz, absent for linear")
def b0_ridge(system: SystemData, tolerances: ClaimTolerances) -> Judgement:
    expected = _expected_for_law(system, nonlinear=True)
    found = _ridge(system)
    peak, threshold = found if found else (None, None)
    return _peak_verdict(peak, "B0/N", system, tolerances, expected, threshold)


def _ridge(system: SystemData) -> tuple[Peak, float] | None:
    b0 = system.mean("betti", homology_dim=0)
    small = system.thresholds[system.thresholds < P1_SMALL_THRESHOLD]
    if small.size == 0 or system.data.sizes["rho"] < 3:
        raise NotEvaluated("no F_th < 0.5 or fewer than 3 rho")
    return _strongest_peak(b0, system, small, _nanmax(b0.values))


@claim("p1-5.1-b0-interior-maximum", "5.1",
       "beyond jamming B0/N first grows with F_th, then falls as F_th -> max (arrows of Fig. 6)",
       "median over rho > rho_J + tol of the F_th maximising mean B0/N lies strictly inside the F_th grid")
def b0_interior_maximum(system: SystemData, tolerances: ClaimTolerances) -> Judgement:
    beyond = _require(system.beyond, "rho beyond rho_J")
    b0 = system.mean("betti", homology_dim=0).transpose("rho", "threshold").values[beyond]
    rows = [row for row in b0 if np.isfinite(row).any() and np.nanmax(row) > 0]
    if not rows:
        raise NotEvaluated("no clusters beyond rho_J")
    best = np.array([system.thresholds[int(np.nanargmax(row))] for row in rows])
    median = float(np.median(best))
    holds = system.thresholds.min() < median < system.thresholds.max()
    evidence = (f"F_th of the largest B0/N at each rho beyond rho_J: {_fmt(best)}; grid "
                f"[{system.thresholds.min():.3g}, {system.thresholds.max():.3g}] ({system.label()})")
    return Judgement(median, evidence, bool(holds))


@claim("p1-5.1-b1-zero-below", "5.1", "no loops below jamming: B1 = 0 for rho < rho_J (Fig. 7)",
       "max over rho < rho_J - tol of the mean (over realizations) of max over F_th of B1/N <= "
       "{negligible_fraction} x its maximum")
def b1_zero_below(system: SystemData, tolerances: ClaimTolerances) -> Judgement:
    return _zero_below(_betti_curve(system, 1), system, tolerances, "B1/N")


@claim("p1-5.1-b1-rises", "5.1", "beyond jamming B1/N starts to rise (Fig. 7)",
       "max of B1/N (max over F_th) over rho > rho_J + tol minus its value at the last rho <= rho_J > "
       "{negligible_fraction} x its maximum")
def b1_rises(system: SystemData, tolerances: ClaimTolerances) -> Judgement:
    curve = np.asarray(_betti_curve(system, 1).values, dtype=float)
    beyond = _require(system.beyond, "rho beyond rho_J")
    before = _require(system.rho <= system.rho_j + 1e-12, "rho at or below rho_J")
    start = float(curve[np.flatnonzero(before)[-1]])
    rise = _nanmax(curve[beyond]) - start
    holds = rise > tolerances.negligible_fraction * _nanmax(curve)
    evidence = f"B1/N {_fmt(curve)} at rho {_fmt(system.rho)} ({system.label()}); rise {rise:.3g}"
    return Judgement(rise, evidence, bool(holds))


@claim("p1-5.1-b1-plateau", "5.1", "B1/N plateaus for rho close to rho_max (Fig. 7)",
       "B1/N (max over F_th) changes over [rho_max - window, rho_max] by <= {plateau_fraction} of its rise from "
       "its minimum to rho_max; the window must lie beyond rho_J + tol")
def b1_plateau(system: SystemData, tolerances: ClaimTolerances) -> Judgement:
    if not np.isfinite(system.rho_max):
        raise NotEvaluated("rho_max undefined")
    start = system.rho_max - system.window
    if start < system.rho_j + system.tolerance - 1e-12:
        raise NotEvaluated(f"rho_max={system.rho_max:.3f} is within tol + window of {system.label()}")
    curve = _betti_curve(system, 1, full=True)
    shown = curve.isel(rho=np.flatnonzero(rho_values(curve) <= system.rho_max + 1e-12))
    top = _interp(shown, system.rho_max)
    change, rise = top - _interp(shown, start), top - _nanmin(shown.values)
    if not np.isfinite(rise) or rise <= 0:
        return Judgement(math.nan, f"B1/N does not rise up to rho_max ({_fmt(shown.values)})", False)
    relative = change / rise
    evidence = (f"B1/N {top:.3g} at rho_max={system.rho_max:.3f}, {top - change:.3g} at {start:.3f}; rise {rise:.3g}"
                f" ({system.label()})")
    return Judgement(relative, evidence, abs(relative) <= tolerances.plateau_fraction)


@claim("p1-5.1-b1-larger-in-3d", "5.1", "the only visible difference in B1/N: larger magnitude in 3D (Fig. 7)",
       "max over rho of B1/N (max over F_th): 3D > each 2D system", per_system=False)
def b1_larger_in_3d(context: ClaimContext) -> Judgement:
    three = _nanmax(_betti_curve(context.role(HERTZ_3D), 1).values)
    two = {context.role(r).name: _nanmax(_betti_curve(context.role(r), 1).values) for r in ALL_2D}
    largest = max(two.values())
    evidence = f"max B1/N: 3D {three:.3g}; " + ", ".join(f"{n} {v:.3g}" for n, v in two.items())
    return Judgement(three / largest if largest > 0 else math.inf, evidence, three > largest)


@claim("p1-5.1-b2-zero-below", "5.1", "in 3D B2 vanishes for rho < rho_J",
       "max over rho < rho_J - tol of the mean of max over F_th of B2/N <= {negligible_fraction} x its maximum",
       roles=(HERTZ_3D,))
def b2_zero_below(system: SystemData, tolerances: ClaimTolerances) -> Judgement:
    return _zero_below(_betti_curve(system, 2), system, tolerances, "B2/N")


@claim("p1-5.1-b2-grows", "5.1", "in 3D B2 grows monotonically as rho increases beyond rho_J",
       "B2/N (max over F_th) over rho >= rho_J - tol rises by > {negligible_fraction} of its maximum and never "
       "drops between consecutive rho by more than {monotone_tolerance} of it", roles=(HERTZ_3D,))
def b2_grows(system: SystemData, tolerances: ClaimTolerances) -> Judgement:
    return _grows_beyond(_betti_curve(system, 2), system, tolerances, "B2/N")


# --- §5.2 Shape of the clusters ----------------------------------------------------------------------------------
def _shape(system: SystemData, rho_mask: np.ndarray, threshold_mask: np.ndarray, what: str) -> np.ndarray:
    """The nonzero S_p (P1's averaging rule) in the selected (ρ, F_th) cells."""
    shape, _ = shape_parameter_average(system.data["shape_parameter"])
    values = shape.transpose("rho", "threshold").values[np.ix_(rho_mask, threshold_mask)]
    values = values[np.isfinite(values) & (values != 0)]
    if values.size == 0:
        raise NotEvaluated(f"no clusters ({what}) in {system.name}")
    return values


def _small_thresholds(system: SystemData) -> np.ndarray:
    return system.thresholds < P1_LARGE_THRESHOLD - 1e-12


def _large_thresholds(system: SystemData) -> np.ndarray:
    return system.thresholds > P1_LARGE_THRESHOLD + 1e-12


@claim("p1-5.2-shape-open-paths-below-jamming", "5.2",
       "in 2D below jamming S_p ~ 1 for both laws: the clusters are open paths (Figs. 8, 9)",
       "|median of the nonzero S_p over rho < rho_J - tol, all F_th - 1| <= {unity_tolerance}", roles=ALL_2D)
def shape_open_paths_below(system: SystemData, tolerances: ClaimTolerances) -> Judgement:
    values = _shape(system, _require(system.below, "rho below rho_J"), np.ones(system.thresholds.size, bool),
                    "below rho_J")
    median = float(np.median(values))
    evidence = f"S_p below rho_J over {values.size} cells: median {median:.3g}, range [{values.min():.3g}, " \
               f"{values.max():.3g}] ({system.label()})"
    return Judgement(median, evidence, abs(median - 1) <= tolerances.unity_tolerance)


def _mean_shape(system: SystemData, rho_mask: np.ndarray, what: str) -> float:
    return float(np.mean(_shape(system, rho_mask, _small_thresholds(system), what)))


@claim("p1-5.2-shape-linear-above-hertz-below-jamming", "5.2",
       "below jamming S_p is consistently larger for the linear law than for the non-linear one, in particular "
       "at smaller F_th (Fig. 9a, b)",
       "mean nonzero S_p over rho < rho_J - tol and F_th < 2: 2D linear > 2D Hertz", per_system=False)
def shape_linear_above_hertz_below(context: ClaimContext) -> Judgement:
    linear, hertz = context.role(LINEAR_2D), context.role(HERTZ_2D)
    a = _mean_shape(linear, _require(linear.below, "rho below rho_J (2D linear)"), "below rho_J, F_th < 2")
    b = _mean_shape(hertz, _require(hertz.below, "rho below rho_J (2D Hertz)"), "below rho_J, F_th < 2")
    return Judgement(a - b, f"mean S_p below rho_J, F_th < 2: 2D linear {a:.3g}, 2D Hertz {b:.3g}", a > b)


@claim("p1-5.2-shape-open-paths-large-threshold", "5.2",
       "beyond jamming, for large F_th (> 2) S_p ~ 1 in every system: open paths (also 3D and §5.2 summary)",
       "|median of the nonzero S_p over rho > rho_J + tol and F_th > 2 - 1| <= {unity_tolerance}")
def shape_open_paths_large_threshold(system: SystemData, tolerances: ClaimTolerances) -> Judgement:
    values = _shape(system, _require(system.beyond, "rho beyond rho_J"), _large_thresholds(system),
                    "beyond rho_J, F_th > 2")
    median = float(np.median(values))
    evidence = f"S_p beyond rho_J at F_th > 2 over {values.size} cells: median {median:.3g}, range " \
               f"[{values.min():.3g}, {values.max():.3g}] ({system.label()})"
    return Judgement(median, evidence, abs(median - 1) <= tolerances.unity_tolerance)


def _jammed_shapes(context: ClaimContext, *roles) -> dict[str, float]:
    means = {}
    for role in roles:
        system = context.role(role)
        means[system.name] = _mean_shape(system, _require(system.beyond, f"rho beyond rho_J ({system.name})"),
                                         "beyond rho_J, F_th < 2")
    return means


@claim("p1-5.2-shape-linear-above-hertz", "5.2",
       "beyond jamming, for F_th around the mean force, S_p is significantly larger for the linear law than the "
       "non-linear one in 2D: more complex clusters",
       "mean nonzero S_p over rho > rho_J + tol and F_th < 2: 2D linear - 2D Hertz >= {shape_difference}",
       per_system=False)
def shape_linear_above_hertz(context: ClaimContext) -> Judgement:
    means = _jammed_shapes(context, LINEAR_2D, HERTZ_2D)
    (linear, a), (hertz, b) = means.items()
    return Judgement(a - b, f"mean S_p beyond rho_J, F_th < 2: {linear} {a:.3g}, {hertz} {b:.3g}",
                     a - b >= context.tolerances.shape_difference)


@claim("p1-5.2-shape-3d-above-2d-hertz", "5.2",
       "3D clusters are more complex than 2D non-linear ones, but less than geometry suggests (S_p bounds 7 vs 4)",
       "mean nonzero S_p over rho > rho_J + tol and F_th < 2: 3D > 2D Hertz, and 3D / 2D Hertz < 7/4",
       per_system=False)
def shape_3d_above_2d_hertz(context: ClaimContext) -> Judgement:
    means = _jammed_shapes(context, HERTZ_3D, HERTZ_2D)
    (three, a), (two, b) = means.items()
    bound = P1_SHAPE_BOUNDS[3] / P1_SHAPE_BOUNDS[2]
    return Judgement(a - b, f"mean S_p beyond rho_J, F_th < 2: {three} {a:.3g}, {two} {b:.3g}; ratio {a / b:.3g} "
                            f"(geometric {bound:.3g})", bool(b < a < bound * b))


@claim("p1-5.2-shape-linear-above-3d", "5.2",
       "for F_th below twice the mean force the non-linear systems, whatever the dimension, hold less complex "
       "clusters than the linear one (§5.2 summary)",
       "mean nonzero S_p over rho > rho_J + tol and F_th < 2: 2D linear > 3D", per_system=False)
def shape_linear_above_3d(context: ClaimContext) -> Judgement:
    means = _jammed_shapes(context, LINEAR_2D, HERTZ_3D)
    (linear, a), (three, b) = means.items()
    return Judgement(a - b, f"mean S_p beyond rho_J, F_th < 2: {linear} {a:.3g}, {three} {b:.3g}", a > b)


def _relative_shape_spread(system: SystemData) -> float:
    shape, spread = shape_parameter_average(system.data["shape_parameter"])
    beyond = _require(system.beyond, f"rho beyond rho_J ({system.name})")
    small = system.thresholds < 1.0
    s = shape.transpose("rho", "threshold").values[np.ix_(beyond, small)]
    d = spread.transpose("rho", "threshold").values[np.ix_(beyond, small)]
    ok = np.isfinite(s) & (s != 0)
    if not ok.any():
        raise NotEvaluated(f"no clusters at F_th < 1 beyond rho_J in {system.name}")
    return float(np.mean(d[ok] / s[ok]))


@claim("p1-5.2-shape-noisier-in-3d", "5.2", "S_p is noisier in 3D, particularly for small F_th",
       "mean over rho > rho_J + tol and F_th < 1 of (spread over realizations / S_p): 3D > 2D Hertz",
       per_system=False)
def shape_noisier_in_3d(context: ClaimContext) -> Judgement:
    if min(s.data.sizes.get("realization", 1) for s in context.systems.values()) < 2:
        raise NotEvaluated("needs at least 2 realizations")
    three, two = _relative_shape_spread(context.role(HERTZ_3D)), _relative_shape_spread(context.role(HERTZ_2D))
    return Judgement(three / two if two > 0 else math.inf,
                     f"relative spread of S_p at F_th < 1 beyond rho_J: 3D {three:.3g}, 2D Hertz {two:.3g}",
                     three > two)


@claim("p1-5.2-shape-bounds", "5.2",
       "S_p lies in [0.5, 4] in 2D and [0.5, 7] in 3D (open paths >= 0.5, bound from the largest contact number)",
       "every nonzero S_p (P1's averaging rule) within those bounds", needs_rho_j=False)
def shape_bounds(system: SystemData, tolerances: ClaimTolerances) -> Judgement:
    every = np.ones(system.rho.size, bool), np.ones(system.thresholds.size, bool)
    values = _shape(system, *every, "any rho")
    upper = P1_SHAPE_BOUNDS.get(system.dimension, math.nan)
    holds = values.min() >= P1_OPEN_PATH_MIN - 1e-12 and values.max() <= upper + 1e-12
    return Judgement(float(values.max()), f"S_p in [{values.min():.3g}, {values.max():.3g}] over {values.size} "
                                          f"cells; bounds [{P1_OPEN_PATH_MIN}, {upper:g}] ({system.name})", bool(holds))


# --- §5.3 Persistence diagrams and total persistence ----------------------------------------------------------
@claim("p1-5.3-rough-similar-near-jamming", "5.3",
       "near jamming the roughness (rough-bin N0/N) is very similar for all systems (Fig. 11a, b)",
       "mean rough-bin N0/N at rho_J (interpolated): largest / smallest over the systems <= {similar_ratio}",
       per_system=False)
def rough_similar_near_jamming(context: ClaimContext) -> Judgement:
    values = {name: _interp(_bin_curve(system, "rough"), system.rho_j) for name, system in context.systems.items()
              if np.isfinite(system.rho_j)}
    values = {name: value for name, value in values.items() if np.isfinite(value)}
    if len(values) < 2:
        raise NotEvaluated("fewer than 2 systems with rho_J and rough-bin counts")
    ratio = max(values.values()) / min(values.values()) if min(values.values()) > 0 else math.inf
    evidence = "rough N0/N at rho_J: " + ", ".join(f"{n} {v:.3g}" for n, v in values.items())
    return Judgement(ratio, evidence, ratio <= context.tolerances.similar_ratio)


def _fewer_for_nonlinear(context: ClaimContext, bin_name: str) -> Judgement:
    def jammed_mean(system: SystemData) -> float:
        beyond = _require(system.beyond, f"rho beyond rho_J ({system.name})")
        return float(np.nanmean(_finite(_bin_curve(system, bin_name).values[beyond], f"{bin_name} N0/N")))

    linear = jammed_mean(context.role(LINEAR_2D))
    others = {system.name: jammed_mean(system) for system in context.nonlinear()}
    evidence = (f"mean {bin_name} N0/N beyond rho_J: 2D linear {linear:.3g}; "
                + ", ".join(f"{n} {v:.3g}" for n, v in others.items()))
    return Judgement(max(others.values()) / linear if linear > 0 else math.inf, evidence,
                     max(others.values()) < linear)


@claim("p1-5.3-rough-fewer-nonlinear", "5.3", "the non-linear systems have fewer rough-bin points (Fig. 11a, b)",
       "mean rough-bin N0/N over rho > rho_J + tol: every non-linear system < 2D linear", per_system=False)
def rough_fewer_nonlinear(context: ClaimContext) -> Judgement:
    return _fewer_for_nonlinear(context, "rough")


@claim("p1-5.3-medium-fewer-nonlinear", "5.3", "the non-linear systems have fewer medium-bin points (Fig. 11e, f)",
       "mean medium-bin N0/N over rho > rho_J + tol: every non-linear system < 2D linear", per_system=False)
def medium_fewer_nonlinear(context: ClaimContext) -> Judgement:
    return _fewer_for_nonlinear(context, "medium")


@claim("p1-5.3-medium-jump", "5.3", "the medium-bin N0/N increases suddenly beyond jamming (Fig. 11e, f)",
       "medium N0/N at the first rho > rho_J + tol >= {jump_factor} x its value at the last rho < rho_J - tol, "
       "and > 0")
def medium_jump(system: SystemData, tolerances: ClaimTolerances) -> Judgement:
    curve = _bin_curve(system, "medium").values
    before = curve[np.flatnonzero(_require(system.below, "rho below rho_J"))[-1]]
    after = curve[np.flatnonzero(_require(system.beyond, "rho beyond rho_J"))[0]]
    if not (np.isfinite(before) and np.isfinite(after)):
        raise NotEvaluated("medium-bin count NaN next to rho_J")
    ratio = after / before if before > 0 else (math.inf if after > 0 else math.nan)
    evidence = f"medium N0/N {_fmt(curve)} at rho {_fmt(system.rho)} ({system.label()}): {before:.3g} -> {after:.3g}"
    return Judgement(ratio, evidence, bool(after > 0 and after >= tolerances.jump_factor * before))


def _bin_peak(system: SystemData, tolerances: ClaimTolerances, bin_name: str, nonlinear: bool) -> Judgement:
    expected = _expected_for_law(system, nonlinear)
    curve = _bin_curve(system, bin_name).values
    return _peak_verdict(_peak(curve, system.rho, system.rho_j, system.tolerance, _nanmax(curve)),
                         f"{bin_name}-bin N0/N", system, tolerances, expected)


@claim("p1-5.3-strong-peak-linear-only", "5.3",
       "the strong-bin N0/N peaks during jamming for the 2D linear law only; the non-linear systems stay high "
       "beyond jamming (Fig. 11g, h)",
       "the maximum of strong-bin N0/N(rho) lies within tol of rho_J with prominence >= {min_prominence} of it; "
       "present for linear, absent for Hertz")
def strong_peak_linear_only(system: SystemData, tolerances: ClaimTolerances) -> Judgement:
    return _bin_peak(system, tolerances, "strong", nonlinear=False)


@claim("p1-5.3-weak-peak-nonlinear-only", "5.3",
       "the weak-bin N0/N shows a pronounced peak around jamming for the non-linear laws, not for the linear one "
       "(Fig. 11c, d)",
       "the maximum of weak-bin N0/N(rho) lies within tol of rho_J with prominence >= {min_prominence} of it; "
       "present for Hertz, absent for linear")
def weak_peak_nonlinear_only(system: SystemData, tolerances: ClaimTolerances) -> Judgement:
    return _bin_peak(system, tolerances, "weak", nonlinear=True)


@claim("p1-5.3-linear-medium-over-strong", "5.3",
       "for the linear law beyond jamming most clusters remain in the medium bin (Fig. 11e)",
       "mean over rho > rho_J + tol: medium-bin N0/N > strong-bin N0/N", roles=(LINEAR_2D,))
def linear_medium_over_strong(system: SystemData, tolerances: ClaimTolerances) -> Judgement:
    beyond = _require(system.beyond, "rho beyond rho_J")
    medium = float(np.nanmean(_finite(_bin_curve(system, "medium").values[beyond], "medium N0/N")))
    strong = float(np.nanmean(_finite(_bin_curve(system, "strong").values[beyond], "strong N0/N")))
    return Judgement(medium / strong if strong > 0 else math.inf,
                     f"mean N0/N beyond rho_J: medium {medium:.3g}, strong {strong:.3g} ({system.label()})",
                     medium > strong)


@claim("p1-5.3-weak-peak-at-ridge", "5.3",
       "(conjecture) the B0/N ridge is formed by weak interactions: the weak-bin peak sits at the ridge",
       "|rho of the weak-bin N0/N maximum - rho of the B0/N ridge peak (F_th < 0.5)| <= tol; judged where both "
       "peaks are found near rho_J", roles=(HERTZ_2D, HERTZ_3D))
def weak_peak_at_ridge(system: SystemData, tolerances: ClaimTolerances) -> Judgement:
    curve = _bin_curve(system, "weak").values
    weak = _peak(curve, system.rho, system.rho_j, system.tolerance, _nanmax(curve))
    ridge = _ridge(system)
    found = [p for p in (weak, ridge[0] if ridge else None)
             if p is not None and p.near and p.relative_prominence >= tolerances.min_prominence]
    if len(found) < 2:
        raise NotEvaluated("the weak-bin peak or the B0/N ridge is not found near rho_J")
    distance = abs(found[0].rho - found[1].rho)
    return Judgement(distance, f"weak-bin peak at rho={found[0].rho:.3f}, B0/N ridge at rho={found[1].rho:.3f} "
                               f"(tolerance {system.tolerance:.3g})", distance <= system.tolerance + 1e-12)


def _persistence_rise(system: SystemData, k: int) -> float:
    """Rise of the mean TP_k/N over ρ_J ± window (interpolated, clipped to the sampled ρ)."""
    curve = _persistence_curve(system, k)
    return _interp(curve, system.rho_j + system.window) - _interp(curve, system.rho_j - system.window)


def _steeper_in_3d(context: ClaimContext, k: int) -> Judgement:
    three = _persistence_rise(context.role(HERTZ_3D), k)
    two = {context.role(r).name: _persistence_rise(context.role(r), k) for r in ALL_2D}
    largest = max(two.values())
    ratio = three / largest if largest > 0 else math.inf
    evidence = (f"rise of TP{k}/N over rho_J +- window: 3D {three:.3g}; "
                + ", ".join(f"{n} {v:.3g}" for n, v in two.items()))
    return Judgement(ratio, evidence, bool(three > 0 and three >= context.tolerances.steeper_factor * largest))


@claim("p1-5.3-tp0-steeper-in-3d", "5.3", "TP0 increases much more prominently close to rho_J in 3D than in 2D "
       "(Fig. 12)", "rise of mean TP0/N over rho_J +- window: 3D >= {steeper_factor} x the larger 2D rise",
       per_system=False)
def tp0_steeper_in_3d(context: ClaimContext) -> Judgement:
    return _steeper_in_3d(context, 0)


@claim("p1-5.3-tp1-steeper-in-3d", "5.3", "TP1 increases much more prominently close to rho_J in 3D than in 2D "
       "(Fig. 12)", "rise of mean TP1/N over rho_J +- window: 3D >= {steeper_factor} x the larger 2D rise",
       per_system=False)
def tp1_steeper_in_3d(context: ClaimContext) -> Judgement:
    return _steeper_in_3d(context, 1)


@claim("p1-5.3-tp2-zero-below", "5.3", "in 3D TP2 ~ 0 for rho < rho_J",
       "max over rho < rho_J - tol of mean TP2/N <= {negligible_fraction} x its maximum", roles=(HERTZ_3D,))
def tp2_zero_below(system: SystemData, tolerances: ClaimTolerances) -> Judgement:
    return _zero_below(_persistence_curve(system, 2), system, tolerances, "TP2/N")


@claim("p1-5.3-tp2-grows", "5.3", "in 3D TP2 increases monotonically for rho > rho_J",
       "mean TP2/N over rho >= rho_J - tol rises by > {negligible_fraction} of its maximum and never drops between "
       "consecutive rho by more than {monotone_tolerance} of it", roles=(HERTZ_3D,))
def tp2_grows(system: SystemData, tolerances: ClaimTolerances) -> Judgement:
    return _grows_beyond(_persistence_curve(system, 2), system, tolerances, "TP2/N")


# =============================================================================================================
# Validation table
# =============================================================================================================
def p1_validation(measures: Mapping[str, xr.Dataset], *, force_unit: str = DEFAULT_P1_FORCE_UNIT,
                  judge_up_to_rho_max: bool = False, **tolerances) -> pd.DataFrame:
    """P1's numbers and claims beside what `measures` (system → network_measures dataset) shows.

    Rows of kind ``"value"``: F_max and per system ρ_max under each unit of `P1_FORCE_UNITS` (the one the figures
    use, `force_unit` = ``analysis.p1_force_unit``, is marked "[figures]"), ρ_J (inflection of mean Z), Z at ρ_J
    (all particles, and rattlers excluded), φ_c = 1/(Z(ρ_J) − 1) of P1 Eq. 6, ρ where Z = d + 1; with P1's value
    and measured − paper. Rows of kind ``"claim"``: one per claim of `CLAIMS` and system it is about (or one
    for a claim comparing systems), with P1's section, statement, the criterion, the key number (``measured``),
    the evidence and a verdict: ``holds`` / ``does not hold`` / ``not evaluated`` (a system, a quantity or a ρ
    range is missing; the evidence says which).

    Claims are judged over every simulated ρ, or over ρ ≤ ρ_max (P1's shown range) with `judge_up_to_rho_max`;
    those P1 states at ρ_max (PDF order, B1 plateau) use ρ_max either way. `tolerances`: the fields of
    `ClaimTolerances` (documented there), e.g. ``rho_tolerance=0.03``.
    """
    tolerances_ = ClaimTolerances(**tolerances)
    present = {name: ds for name, ds in measures.items() if ds is not None}
    cuts = _cuts(present)
    if force_unit not in P1_FORCE_UNITS:
        raise ValueError(f"unknown P1 force unit {force_unit!r}; known: {', '.join(P1_FORCE_UNITS)}")
    cut = cuts.get(force_unit)
    systems = {name: _system_data(name, ds, cut if isinstance(cut, FMaxCut) else None, tolerances_,
                                  judge_up_to_rho_max) for name, ds in present.items()}
    rows = _force_rows(cuts, force_unit)
    for name in system_order(set(P1_SYSTEMS) | set(present)):
        rows.extend(_value_rows(name, systems.get(name), cuts, force_unit))
    context = ClaimContext(systems, tolerances_)
    for claim_ in sorted(CLAIMS, key=lambda c: tuple(int(part) for part in c.section.split("."))):
        rows.extend(_claim_rows(claim_, context, set(P1_SYSTEMS) | set(present)))
    return pd.DataFrame(rows, columns=list(COLUMNS))


def _cuts(present: Mapping[str, xr.Dataset]) -> dict[str, FMaxCut | str]:
    """The F_max cut under every unit, or the reason it cannot be made."""
    cuts: dict[str, FMaxCut | str] = {}
    for unit in P1_FORCE_UNITS:
        try:
            cuts[unit] = f_max_cut(present, unit) if present else "no system in the results"
        except ValueError as error:
            cuts[unit] = str(error)
    return cuts


def _system_data(name: str, ds: xr.Dataset, cut: FMaxCut | None, tolerances: ClaimTolerances,
                 up_to_rho_max: bool) -> SystemData:
    full = select_total(ds)
    rho = rho_values(full)
    step = float(np.median(np.diff(rho))) if rho.size > 1 else 0.0
    tolerance = tolerances.rho_tolerance if tolerances.rho_tolerance is not None else max(P1_RHO_STEP, step)
    window = tolerances.rho_window if tolerances.rho_window is not None else 2.0 * tolerance
    rho_max = cut.rho_max.get(name, math.nan) if cut else math.nan
    return SystemData(name=name, dimension=system_dimension(ds, name), force_law=system_force_law(ds, name),
                      data=cut_at_rho_max(full, rho_max) if up_to_rho_max else full, full=full,
                      rho_j=jamming_point(ds), rho_max=rho_max, tolerance=tolerance, window=window)


def _claim_rows(claim_: Claim, context: ClaimContext, names: set[str]) -> list[dict]:
    criterion = claim_.criterion_text(context.tolerances)
    if not claim_.per_system:
        return [_claim_row(claim_, "all", None, criterion, lambda: claim_.judge(context))]
    rows = []
    for name in system_order(names):
        system = context.systems.get(name)
        role = system.role if system else P1_ROLES.get(name)
        if claim_.roles is not None and role not in claim_.roles:
            continue

        def judge(system=system):
            if system is None:
                raise NotEvaluated("system not in the results")
            if claim_.needs_rho_j and not np.isfinite(system.rho_j):
                raise NotEvaluated("rho_J could not be located")
            return claim_.judge(system, context.tolerances)

        rows.append(_claim_row(claim_, name, role, criterion, judge))
    return rows


def _claim_row(claim_: Claim, system: str, role, criterion: str, judge: Callable[[], Judgement]) -> dict:
    try:
        judgement = judge()
        measured, evidence, verdict = judgement.measured, judgement.evidence, HOLDS if judgement.holds else FAILS
    except NotEvaluated as reason:
        measured, evidence, verdict = math.nan, str(reason), NOT_EVALUATED
    row = _row("claim", claim_.statement, system, measured, claim_.paper_value(role), evidence, verdict)
    row.update(id=claim_.id, section=claim_.section, criterion=criterion)
    return row


def _force_rows(cuts: Mapping[str, FMaxCut | str], force_unit: str) -> list[dict]:
    rows = []
    for unit, cut in cuts.items():
        item = f"F_max (min over systems of max_rho <F>, <F> in {unit})" + (" [figures]" if unit == force_unit else "")
        if isinstance(cut, FMaxCut):
            evidence = ("F'_max: " + ", ".join(f"{n} {v:.4g}" for n, v in cut.f_prime_max.items())
                        + f" [{cut.force_units}]")
            rows.append(_row("value", item, "all", cut.f_max, math.nan, evidence, "", id=f"f_max.{unit}",
                             section="3"))
        else:
            rows.append(_row("value", item, "all", math.nan, math.nan, cut, NOT_EVALUATED, id=f"f_max.{unit}",
                             section="3"))
    return rows


def _value_rows(name: str, system: SystemData | None, cuts: Mapping[str, FMaxCut | str],
                force_unit: str) -> list[dict]:
    dimension = system.dimension if system else P1_ROLES.get(name, (2, ""))[0]
    paper_z, paper_phi = PAPER_Z_AT_JAMMING.get(dimension, math.nan), PAPER_PHI_C.get(dimension, math.nan)
    rho_max_items = [(unit, f"rho_max (F_max rule, <F> in {unit})" + (" [figures]" if unit == force_unit else ""))
                     for unit in P1_FORCE_UNITS]
    if system is None:
        items = [("rho_J", "rho_J (inflection of Z)", PAPER_RHO_J.get(name, math.nan), "4")]
        items += [(f"rho_max.{unit}", item, PAPER_RHO_MAX.get(name, math.nan), "3") for unit, item in rho_max_items]
        items += [("Z_at_rho_J", "Z at rho_J", paper_z, "4.3"), ("phi_c", "phi_c = 1/(Z(rho_J) - 1)", paper_phi, "4.3")]
        return [_row("value", item, name, math.nan, paper, "system not in the results", NOT_EVALUATED, id=id_,
                     section=section) for id_, item, paper, section in items]
    ds, rho_j = system.full, system.rho_j
    realizations = ds.sizes.get("realization", 1)
    rows = [_value_row("rho_J", "4", "rho_J (inflection of Z)", name, rho_j, PAPER_RHO_J.get(name, math.nan),
                       f"inflection of the mean Z(rho) over {realizations} realizations")]
    for unit, item in rho_max_items:
        cut = cuts[unit]
        if isinstance(cut, FMaxCut):
            evidence = (f"every rho has mean <F> > F_max: rho_max lies below the grid (<F> in {cut.force_units})"
                        if cut.below_grid(name) else f"largest rho with mean <F> <= F_max, <F> in {cut.force_units}")
            rows.append(_value_row(f"rho_max.{unit}", "3", item, name, cut.rho_max.get(name, math.nan),
                                   PAPER_RHO_MAX.get(name, math.nan), evidence))
        else:
            rows.append(_row("value", item, name, math.nan, PAPER_RHO_MAX.get(name, math.nan), cut, NOT_EVALUATED,
                             id=f"rho_max.{unit}", section="3"))
    z_j = value_at(ds, "Z", rho_j)
    rows.append(_value_row("Z_at_rho_J", "4.3", "Z at rho_J", name, z_j, paper_z, "mean Z (all particles) at rho_J"))
    if "Z_no_rattlers" in ds:
        rows.append(_value_row("Z_no_rattlers_at_rho_J", "4.3", "Z at rho_J (rattlers excluded)", name,
                               value_at(ds, "Z_no_rattlers", rho_j), paper_z, "mean Z without rattlers at rho_J"))
    phi_c = 1.0 / (z_j - 1.0) if np.isfinite(z_j) and z_j > 1 else math.nan  # P1 Eq. 6 with <k^2> = <k>^2
    rows.append(_value_row("phi_c", "4.3", "phi_c = 1/(Z(rho_J) - 1)", name, phi_c, paper_phi,
                           "P1 Eq. 6 with <k^2> = <k>^2, <k> = mean Z at rho_J"))
    rows.append(_value_row("rho_at_Z_d+1", "4", "rho at Z = d+1", name, isostatic_crossing(ds), math.nan,
                           f"first rho where the mean Z reaches {system.dimension + 1} (P2's definition)"))
    return rows


def _value_row(id_: str, section: str, item: str, system: str, measured: float, paper: float, evidence: str) -> dict:
    verdict = "" if np.isfinite(measured) else NOT_EVALUATED
    return _row("value", item, system, measured, paper, evidence, verdict, id=id_, section=section)


def _row(kind: str, item: str, system: str, measured: float, paper: float, evidence: str, verdict: str,
         **extra) -> dict:
    measured, paper = float(measured), float(paper)
    difference = measured - paper if np.isfinite(measured) and np.isfinite(paper) else math.nan
    row = dict.fromkeys(COLUMNS, "")
    row.update(kind=kind, item=item, system=system, measured=measured, paper=paper, difference=difference,
               evidence=evidence, verdict=verdict, **extra)
    return row


def verdict_counts(table: pd.DataFrame) -> dict[str, int]:
    """How many claim rows hold, do not hold, are not evaluated."""
    claims = table[table["kind"] == "claim"]
    return {verdict: int((claims["verdict"] == verdict).sum()) for verdict in (HOLDS, FAILS, NOT_EVALUATED)}


def p1_validation_markdown(table: pd.DataFrame, force_unit: str = DEFAULT_P1_FORCE_UNIT) -> str:
    """The validation table as Markdown: one table of values, one of claims, with the verdict counts."""
    counts = verdict_counts(table)
    lines = ["# P1 validation", "",
             "Measured from the aggregated network measures; paper values from P1 "
             "(compressed 2D/3D interaction networks). difference = measured − paper.", "",
             f"The figures mark rho_max of the F_max rule with <F> compared in {force_unit} "
             f"({P1_FORCE_UNITS.get(force_unit, '?')}; config key analysis.p1_force_unit); the rows marked "
             "[figures] are that unit.", "",
             "## Values", ""]
    values = table[table["kind"] == "value"]
    lines += _markdown_table(values, ["item", "system", "measured", "paper", "difference", "evidence", "verdict"])
    lines += ["", "## Claims", "",
              f"{len(table[table['kind'] == 'claim'])} rows: {counts[HOLDS]} hold, {counts[FAILS]} do not hold, "
              f"{counts[NOT_EVALUATED]} not evaluated.", ""]
    claims = table[table["kind"] == "claim"]
    lines += _markdown_table(claims, ["id", "section", "item", "system", "measured", "paper", "criterion",
                                      "evidence", "verdict"])
    return "\n".join(lines) + "\n"


def write_p1_validation(table: pd.DataFrame, csv_path: str | os.PathLike, md_path: str | os.PathLike,
                        force_unit: str = DEFAULT_P1_FORCE_UNIT) -> None:
    """Write the validation table as CSV and Markdown."""
    for path in (csv_path, md_path):
        Path(path).parent.mkdir(parents=True, exist_ok=True)
    table.to_csv(csv_path, index=False)
    Path(md_path).write_text(p1_validation_markdown(table, force_unit))


# --- helpers ---------------------------------------------------------------------------------------------------
def _nanmax(values) -> float:
    values = np.asarray(values, dtype=float)
    return float(np.nanmax(values)) if np.isfinite(values).any() else math.nan


def _nanmin(values) -> float:
    values = np.asarray(values, dtype=float)
    return float(np.nanmin(values)) if np.isfinite(values).any() else math.nan


def _format(value) -> str:
    if isinstance(value, (float, np.floating)):
        return "–" if not np.isfinite(value) else f"{value:.4g}"
    return str(value).replace("|", "\\|")


def _markdown_table(frame: pd.DataFrame, columns: list[str]) -> list[str]:
    lines = ["| " + " | ".join(columns) + " |", "|" + "|".join("---" for _ in columns) + "|"]
    for _, row in frame.iterrows():
        lines.append("| " + " | ".join(_format(row[c]) for c in columns) + " |")
    return lines
