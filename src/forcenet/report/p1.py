"""P1 (compressed 2D/3D interaction networks): its reference values and the reductions its figures and claims share.

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

Means and spreads over realizations follow the one convention of `forcenet.report.realizations` (mean ± sample
standard deviation). The only typed-in numbers are P1's own: its reference values (``PAPER_*``) and the definitions
it states (Δρ = 0.02, "small F_th < 0.5", "twice the average force", the 50 % percolation rule, the S_p bounds 4
and 7).

P1's validation is cut by job: `forcenet.report.p1_judging` (tolerances and the data a judge sees),
`forcenet.report.p1_claims` (the claims of §3–4 and §6) and `forcenet.report.p1_claims_topology` (§5: Betti
numbers, cluster shape, persistence), `forcenet.report.p1_validation` (the table).
"""
from __future__ import annotations

import json
import math
from dataclasses import dataclass, field
from typing import Mapping

import numpy as np
import xarray as xr

from forcenet.boxes import relative_overlaps as relative_overlaps_of
from forcenet.datasets.snapshot import periodic_vectors
from forcenet.report.realizations import mean_and_spread, realization_mean
from forcenet.systems import KINETIC_ENERGY_FLUCTUATION

# --- P1's reference values (the only results typed in) --------------------------------------------------------
HERTZ_2D, LINEAR_2D, HERTZ_3D = (2, "hertz"), (2, "linear"), (3, "hertz")  # roles: (dimension, force law)
P1_ROLE_ORDER = (HERTZ_2D, LINEAR_2D, HERTZ_3D)  # P1's panel order a, b, c
#: the catalog's P1 roles (config/systems.yaml, forcenet.catalog.ROLES) as (dimension, force law)
CATALOG_ROLES = {"p1_hertz_2d": HERTZ_2D, "p1_linear_2d": LINEAR_2D, "p1_hertz_3d": HERTZ_3D}
#: the shipped systems that play P1's roles: the names of the rows of a role no system of the results plays
P1_SYSTEMS = ("2d_hertz", "2d_linear", "3d_hertz")
P1_ROLES = dict(zip(P1_SYSTEMS, P1_ROLE_ORDER))
PAPER_RHO_J_BY_ROLE = {HERTZ_2D: 0.842, LINEAR_2D: 0.834, HERTZ_3D: 0.57}  # P1 §4 (inflection of Z)
PAPER_RHO_MAX_BY_ROLE = {HERTZ_2D: 0.906, LINEAR_2D: 0.890, HERTZ_3D: 0.710}  # P1 §3 (F_max rule)
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


def system_order(systems) -> list[str]:
    """P1's panel order (2D Hertzian, 2D linear, 3D Hertzian) first, any other system after, alphabetically.

    `systems`: {name: its file (a dataset recording its dimension and force law), its `SystemData` (which has a
    role), or None}; or names alone. A system whose role none of these tells takes that of its shipped name
    (`P1_ROLES`). Two systems of one role keep their alphabetical order."""
    files = systems if isinstance(systems, Mapping) else dict.fromkeys(systems)

    def role_of(name, value):
        role = getattr(value, "role", None) or (file_role(value) if isinstance(value, xr.Dataset) else None)
        return role or P1_ROLES.get(name)

    roles = {name: role_of(name, value) for name, value in files.items()}
    rank = {role: index for index, role in enumerate(P1_ROLE_ORDER)}
    return sorted(files, key=lambda name: (rank.get(roles[name], len(rank)), name))


def file_role(ds: xr.Dataset) -> tuple[int, str] | None:
    """(dimension, force law) a system's stacked file records (None when it records neither)."""
    if "dimension" not in ds.attrs or "force_law" not in ds.attrs:
        return None
    return (int(ds.attrs["dimension"]), str(ds.attrs["force_law"]).lower())


def system_dimension(ds: xr.Dataset, name: str = "") -> int:
    """Spatial dimension of a system's file: its global attribute ``dimension`` (required of every stacked kind,
    `forcenet.datasets.schema.KIND_GLOBAL_ATTRS`; nothing is guessed from the system's name). `name` is unused: the
    validated read names the file that lacks it."""
    return int(ds.attrs["dimension"])


def system_force_law(ds: xr.Dataset, name: str = "") -> str:
    """The force law a system's file records (global attribute ``force_law``, required of every stacked kind:
    ``"linear"``, ``"hertz"``, or ``"imported"`` for states imported from another code or an experiment)."""
    return str(ds.attrs["force_law"]).lower()


def _system_setting(ds: xr.Dataset, name: str, *config_keys: str, default=None):
    """A setting of the system's runs: its entry's value at the path `config_keys` in the config the file records
    (global attribute ``config``, required of every kind), `default` where the entry does not set it."""
    value = _config_system(ds, name)
    for key in config_keys:
        value = value.get(key) if isinstance(value, dict) else None
    return default if value is None else value


def _system_number(ds: xr.Dataset, name: str, *config_keys: str) -> float:
    """A number of the system's recorded config (`_system_setting`); NaN when it does not say (or it is not a
    number)."""
    try:
        return float(_system_setting(ds, name, *config_keys, default=math.nan))
    except (TypeError, ValueError):
        return math.nan


def system_friction(ds: xr.Dataset, name: str = "") -> float:
    """The friction coefficient μ of the system's runs (the recorded config's ``friction``; NaN where it has none:
    an imported system)."""
    return _system_number(ds, name, "friction")


def system_relaxation_tolerance(ds: xr.Dataset, name: str = "") -> float:
    """The kinetic-energy fluctuation tolerance the system's runs relaxed to (P1 §3's 0.1; the recorded config's
    ``relaxation.tolerance``; NaN where it has none)."""
    return _system_number(ds, name, "relaxation", "tolerance")


def system_relaxation_criterion(ds: xr.Dataset, name: str = "") -> str:
    """The criterion the system's runs relaxed by (`forcenet.systems.RELAXATION_CRITERIA`; the recorded config's
    ``relaxation.criterion``, else P1's kinetic-energy fluctuation, the config's default)."""
    return str(_system_setting(ds, name, "relaxation", "criterion", default=KINETIC_ENERGY_FLUCTUATION))


def system_particles(ds: xr.Dataset) -> int:
    """The number of particles N of the system's runs (largest ``n_particles``; 0 when the dataset has none)."""
    return int(np.nanmax(ds["n_particles"].values)) if "n_particles" in ds else 0


def relative_overlaps(snapshot: xr.Dataset) -> tuple[np.ndarray, np.ndarray]:
    """Per particle contact of one snapshot: the overlap relative to the sum of the radii, (r_i + r_j − |x_i −
    x_j|) / (r_i + r_j), x_j the image of j nearest to i in a periodic box (shape (n_contacts,), dimensionless),
    and whether either particle also touches a wall
    (bool, same shape; from ``wall_contact_particle``, all False in a snapshot without walls)."""
    i, j = snapshot["contact_i"].values, snapshot["contact_j"].values
    # across a periodic face (an imported box) to the nearest image
    overlaps = relative_overlaps_of(snapshot["position"].values, snapshot["radius"].values, i, j,
                                    periodic_vectors(snapshot))
    touching = snapshot["wall_contact_particle"].values if "wall_contact_particle" in snapshot else np.empty(0, int)
    return overlaps, np.isin(i, touching) | np.isin(j, touching)


def relative_wall_overlaps(snapshot) -> tuple[np.ndarray, np.ndarray]:
    """Per wall contact of one snapshot of a flat-walled box: (its overlap relative to the particle's diameter,
    (r_i − gap) / d_i, and the magnitude of the wall's normal force [force unit]), shapes (n_wall_contacts,). Wall id
    w is the lower (even w) or upper (odd w) wall of axis w // 2 (``wall_contact_wall``), at box_lo / box_hi of
    that axis. `snapshot`: a snapshot's arrays (an xarray Dataset or a mapping of arrays)."""
    particle = np.asarray(snapshot["wall_contact_particle"], dtype=int)
    wall = np.asarray(snapshot["wall_contact_wall"], dtype=int)
    axis, upper = wall // 2, wall % 2 == 1
    coordinate = np.asarray(snapshot["position"])[particle, axis]
    gap = np.where(upper, np.asarray(snapshot["box_hi"])[axis] - coordinate,
                   coordinate - np.asarray(snapshot["box_lo"])[axis])
    radius = np.asarray(snapshot["radius"])[particle]
    normal = np.abs(np.asarray(snapshot["wall_contact_force"]).reshape(len(wall), -1)[np.arange(len(wall)), axis])
    return (radius - gap) / (2.0 * radius), normal


def largest_relative_overlap(snapshot: xr.Dataset) -> float:
    """The largest overlap of two particles in contact relative to the sum of their radii (`relative_overlaps`) in
    one snapshot (P1 §3: "up to 10 %" at the largest ρ); 0 without contacts."""
    overlaps, _ = relative_overlaps(snapshot)
    return float(np.max(overlaps)) if overlaps.size else 0.0


def _config_system(ds: xr.Dataset, name: str) -> dict:
    """The system's entry ({} where it has none) of the config recorded in the dataset's ``config`` attribute
    (required of every kind, `forcenet.datasets.schema.REQUIRED_GLOBAL_ATTRS`)."""
    try:
        config = json.loads(ds.attrs["config"])
        return dict(config.get("systems", {}).get(name or ds.attrs["system"], {}))
    except (TypeError, ValueError, AttributeError):
        return {}


def rho_values(ds: xr.Dataset) -> np.ndarray:
    """The packing fractions ρ of a dataset or curve, as float array (n_rho,)."""
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

    Raises ValueError when the attribute is NaN (a system without a material has no dyn), naming the system and the
    attribute; a file without it (required of network measures, `schema.FORCE_CONSTANT_ATTRS`) is refused by its
    validated read."""
    if unit not in P1_FORCE_UNITS:
        raise ValueError(f"unknown P1 force unit {unit!r}; known: {', '.join(P1_FORCE_UNITS)}")
    attr = _UNIT_ATTRS[unit]
    if attr is None:
        return 1.0
    value = float(ds.attrs[attr])
    if not np.isfinite(value) or value <= 0:
        raise ValueError(f"{name or ds.attrs['system']}: attribute {attr} is NaN in its network measures: <F> cannot "
                         f"be compared in {unit!r} (analysis.p1_force_unit)")
    return value if unit == "dyn" else 1.0 / value


def mean_force(ds: xr.Dataset, scale: float = 1.0) -> xr.DataArray:
    """Realization-mean ⟨F⟩ of the total-force network versus ρ, times `scale` (e.g. dyn per reduced unit)."""
    return realization_mean(select_total(ds)["mean_force"]) * scale


def f_max_cut(measures: Mapping[str, xr.Dataset], unit: str = DEFAULT_P1_FORCE_UNIT,
              f_max: float | None = None) -> FMaxCut:
    """P1 §3 F_max rule over the systems in `measures`, ⟨F⟩ compared in `unit` (see `FMaxCut`, `force_scale`);
    with `f_max` given (the F_max of other systems, e.g. P1's own beside their counterparts) each system's ρ_max
    under that F_max.

    Raises ValueError if a system lacks the constant the unit needs."""
    if not measures:
        raise ValueError("f_max_cut needs at least one system")
    curves = {name: mean_force(ds, force_scale(ds, unit, name)) for name, ds in measures.items()}
    f_prime = {name: finite_max(curve.values) for name, curve in curves.items()}
    finite = [value for value in f_prime.values() if np.isfinite(value)]
    if f_max is None:
        f_max = min(finite) if finite else math.nan
    rho_max = {}
    for name, curve in curves.items():
        rho = rho_values(curve)
        below = np.asarray(curve.values <= f_max)  # NaN (no contacts) compares False
        rho_max[name] = float(rho[below].max()) if below.any() else math.nan
    return FMaxCut(f_max=f_max, f_prime_max=f_prime, rho_max=rho_max, unit=unit,
                   force_units=force_units_label(measures, unit), mean_force=curves)


def force_units_label(measures: Mapping[str, xr.Dataset], unit: str) -> str:
    """The label of ⟨F⟩ compared in `unit` (`P1_FORCE_UNITS`); under "reduced" (⟨F⟩ as stored) the systems' own unit
    where they share one other than the engine's (imported systems' source unit, ``units.force``: their
    ``mean_force`` says it), the engine's reduced label otherwise."""
    from forcenet.datasets.schema import FORCE_UNITS

    stored = {str(ds["mean_force"].attrs.get("units", FORCE_UNITS)) for ds in measures.values()}
    if unit == "reduced" and len(stored) == 1 and FORCE_UNITS not in stored:
        return stored.pop()
    return P1_FORCE_UNITS[unit]


def up_to_rho_max(rho: np.ndarray, rho_max: float) -> np.ndarray:
    """Mask of the packing fractions `rho` ≤ ρ_max (all of them when ρ_max is NaN or None)."""
    if rho_max is None or not np.isfinite(rho_max):
        return np.ones(np.shape(rho), dtype=bool)
    return np.asarray(rho) <= rho_max + 1e-12


def cut_at_rho_max(ds: xr.Dataset, rho_max: float) -> xr.Dataset:
    """The packing fractions ρ ≤ ρ_max (all of them when ρ_max is NaN)."""
    if rho_max is None or not np.isfinite(rho_max):
        return ds
    return ds.isel(rho=np.flatnonzero(up_to_rho_max(rho_values(ds), rho_max)))


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
    curve = realization_mean(ds[variable]).values
    grid = rho_values(ds)
    ok = np.isfinite(curve)
    if not ok.any() or rho < grid[ok].min() or rho > grid[ok].max():
        return math.nan
    return float(np.interp(rho, grid[ok], curve[ok]))


def percolation_fraction(ds: xr.Dataset) -> xr.DataArray:
    """Fraction of realizations with a percolating total-force cluster, per (ρ, F_th)."""
    return realization_mean(select_total(ds)["percolates"] > 0)


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
# P1 §5.3: never-dying classes at death −1 (the papers' group's convention, P2 §III C; P1 takes total persistence
# from its ref. [7])
# =============================================================================================================
NEVER_DYING_DEATH = -1.0  # [⟨F⟩] the death P2 §III C gives a class that never dies


def never_dying_at_minus_one(measures: xr.Dataset, diagrams: xr.Dataset) -> xr.Dataset:
    """`measures` (network_measures.nc) with the never-dying classes of `diagrams` (the same system's diagrams.nc)
    given death −1 ⟨F⟩: each adds birth + 1 to TP_k (``total_persistence``), and in PD0 it leaves the
    ``essential`` bin of ``persistence_bin_count`` for the bin of its birth (lifespan b + 1 > 0.1: never rough;
    weak below 1, a birth under 0.1 counted there too, medium [1, 2.5), strong ≥ 2.5; P1 §5.3's bins). The
    measures as stored leave them out (their reading, judged beside)."""
    import pandas as pd

    from forcenet.measures.persistence_stats import MEDIUM_BIRTH, STRONG_BIRTH

    essential = np.asarray(diagrams["essential"].values, dtype=bool)
    kinds = np.asarray([str(k) for k in diagrams["force_kind"].values])
    grid = rho_values(measures)
    point_rho = np.asarray(diagrams["point_rho"].values, dtype=float)[essential]
    points = pd.DataFrame({
        "realization": np.asarray(diagrams["point_realization"].values, dtype=int)[essential],
        "rho": grid[np.abs(point_rho[:, None] - grid[None, :]).argmin(axis=1)] if grid.size else point_rho,
        "force_kind": kinds[np.asarray(diagrams["diagram_force_kind"].values, dtype=int)[essential]],
        "homology_dim": np.asarray(diagrams["diagram_homology_dim"].values, dtype=int)[essential],
        "birth": np.asarray(diagrams["birth"].values, dtype=float)[essential]})
    out = measures.copy(deep=True)
    keys = ["realization", "rho", "force_kind"]
    added = (points["birth"] - NEVER_DYING_DEATH).groupby([points[k] for k in (*keys, "homology_dim")]).sum()
    if len(added):
        extra = added.to_xarray().reindex_like(out["total_persistence"]).fillna(0.0)
        out["total_persistence"] = out["total_persistence"] + extra
    pd0 = points[points["homology_dim"] == 0]
    if len(pd0):
        target = np.where(pd0["birth"] < MEDIUM_BIRTH, "weak", np.where(pd0["birth"] < STRONG_BIRTH, "medium",
                                                                         "strong"))
        moved = pd0.groupby([pd0[k] for k in keys] + [pd.Series(target, index=pd0.index,
                                                                name="persistence_bin")]).size()
        counts = moved.to_xarray().reindex_like(out["persistence_bin_count"]).fillna(0)
        leaving = counts.sum("persistence_bin")
        out["persistence_bin_count"] = (out["persistence_bin_count"] + counts
                                        - leaving.where(out["persistence_bin"] == "essential", 0))
    out.attrs["never_dying_death"] = NEVER_DYING_DEATH
    return out


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



# --- helpers ---------------------------------------------------------------------------------------------------
def finite_max(values) -> float:
    """Largest finite value of an array (any shape), NaN when none is finite."""
    values = np.asarray(values, dtype=float)
    return float(np.nanmax(values)) if np.isfinite(values).any() else math.nan


# relative difference under which two values are the same maximum (`first_max_index`)
TIE_RTOL = 1e-9


def first_max_index(values) -> int:
    """Index of the largest finite value of a 1-D array, the first of those within `TIE_RTOL` of it.

    The curves P1's claims read are mostly counts (B0, persistence points) averaged over realizations: two equal
    counts can differ in their last bit, and `np.nanargmax` would then pick by rounding. Needs a finite value."""
    values = np.asarray(values, dtype=float)
    top = np.nanmax(values)
    return int(np.flatnonzero(values >= top - TIE_RTOL * abs(top))[0])


def finite_min(values) -> float:
    """Smallest finite value of an array (any shape), NaN when none is finite."""
    values = np.asarray(values, dtype=float)
    return float(np.nanmin(values)) if np.isfinite(values).any() else math.nan
