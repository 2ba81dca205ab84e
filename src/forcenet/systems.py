"""Systems and configuration: frozen dataclasses built from the validated workflow config.

The JSON schema (`workflow/schemas/config.schema.yaml`) checks types and shapes. This module turns the
``systems.<name>`` entry of a simulated system into a `SystemSpec` in reduced units (length d_ave, mass m̄, time τ_c;
see `forcenet.units`), checking what the entry alone can get wrong that a schema cannot (a ρ grid that is empty or
out of order, settings that exclude each other), and defines the `ImportedSystem` that `forcenet.importers` builds
from a ``source:`` entry's files. It reads no data file and runs no physical check: `forcenet.checks` validates a
whole config (`validate_config`) and builds each system checked (`checked_system`).
"""
from __future__ import annotations

import math
import zlib
from dataclasses import dataclass, field
from typing import Any, Mapping

import numpy as np

from forcenet import units
from forcenet.datasets.paths import RHO_DECIMALS, format_rho, state_labels
from forcenet.errors import ForcenetError


class ConfigError(ForcenetError, ValueError):
    """An invalid configuration; the message starts with the offending key (e.g. `systems.2d_hertz.rho`)."""

    def __init__(self, key: str, message: str):
        super().__init__(f"config key '{key}': {message}")
        self.key = key


#: rattler rules of the force networks (`study_rattler_rule`; `forcenet.network` applies them)
RATTLER_RULES = ("once", "iterative", "none")
#: `Relaxation.criterion`: P1 §3's kinetic-energy fluctuation (the default) and its contact-number protocol
RELAXATION_CRITERIA = ("kinetic_energy_fluctuation", "contact_number")
KINETIC_ENERGY_FLUCTUATION, CONTACT_NUMBER = RELAXATION_CRITERIA

#: P2's states a, b, c (Tables I–III, Figs 1, 3) are this many consecutive snapshots of one run
TABLE_STATES = 3


@dataclass(frozen=True)
class Relaxation:
    """P1 §3 relaxation, with the walls fixed, in windows of `window_steps` until the window meets `criterion`:

    ``"kinetic_energy_fluctuation"`` (P1's own): std(E_kin)/mean(E_kin) over the window < `tolerance`;
    ``"contact_number"`` (P1 §3's protocol "tracking the average contact number change"): the number of touching
    particle pairs is the same at every chunk end (`forcenet.dem.protocol.CHUNK_STEPS` steps apart) of the window;
    `tolerance` is not used. Either way at most `max_steps` per grid point (hitting it is logged).
    """

    window_steps: int
    tolerance: float
    max_steps: int
    # not in the repr, which the checkpoint fingerprint hashes: runs with the default keep their fingerprints
    # (`forcenet.dem.protocol._fingerprint` adds a criterion other than the default)
    criterion: str = field(default=KINETIC_ENERGY_FLUCTUATION, repr=False)


@dataclass(frozen=True)
class InitialState:
    """How a run starts (`systems.<name>.initial_state`).

    lattice : ``"gapped"`` (spacing = largest diameter + a gap: no overlaps, as many sites as fit) or ``"box"``
        (P1 §3: `sites_per_axis` sites per axis spread evenly over the whole box)
    sites_per_axis : sites per axis of the ``"box"`` lattice (N = sites_per_axis^d)
    relax_first : relax at the initial ρ with the system's relaxation rule before the first compression (P1 §3:
        a relaxation after every compression step from the start; resolves the ``"box"`` lattice's overlaps)
    """

    lattice: str = "gapped"
    sites_per_axis: int | None = None
    relax_first: bool = False


@dataclass(frozen=True)
class SystemSpec:
    """One simulated system in reduced units (d_ave, m̄, τ_c).

    Attributes
    ----------
    name : config name, e.g. ``"2d_hertz"``
    dimension : 2 (disks) or 3 (spheres)
    beta : force-law exponent β, F_n = k_n x^(1+β) (P1 Eq. 1)
    normal_stiffness : k_n [m̄ d_ave^(−β) τ_c^(−2)]
    tangential_stiffness : k_t [same units as k_n] (P1: 6/7 k_n, P2: 0.8 k_n)
    box_length : initial side of the square/cubic box between the walls [d_ave]
    size_distribution : ``"bidisperse"`` (P1) or ``"polydisperse"`` (P2)
    diameter_ratio : large/small diameter (bidisperse) [-]
    small_to_large : number ratio of small to large particles (bidisperse) [-]
    polydispersity : r_p, diameters uniform in [1 − r_p/2, 1 + r_p/2] (polydisperse) [-]
    friction : Coulomb coefficient μ [-]
    restitution : normal restitution e_n [-]
    damping_model : how γ_n follows from e_n (`forcenet.dem.calibration`): ``"linear_law"``, γ_n = −2 ln(e_n)/τ_c
        in the system's own τ_c units (P1 ref. [47]), or ``"head_on"``, a head-on collision of two mean particles
        (at `wall_speed` for Hertz) has restitution e_n, or ``"explicit"``, γ_n = `normal_damping`
    normal_damping : γ_n [d_ave^(−β) τ_c^(−1)] of ``damping_model: explicit``, None otherwise
    initial_state : the start (`InitialState`), None for the default gapped lattice without a first relaxation
        (left out of the repr, so the checkpoint fingerprints of runs without it are unchanged; the fingerprint
        adds it when set)
    walls : ``"flat"`` (P1) or ``"rough"`` (P2, monodisperse wall particles)
    wall_stiffness_factor : k_n and k_t of a particle–flat-wall contact over a pair's [-]: 1 when the walls have the
        particles' material, else `forcenet.units.wall_stiffness_factor` of the entry's ``wall_material`` (P1 §2:
        plexiglass walls); left out of the repr as `initial_state` is (the fingerprint adds it when not 1)
    time_step : Δt [τ_c]
    protocol : ``"quasistatic"`` (P1) or ``"continuous"`` (P2)
    wall_speed : inward speed of every wall [d_ave/τ_c]
    initial_speed : scale of the random initial velocities [d_ave/τ_c]
    rho_grid : packing fractions at which snapshots are written, increasing
    relaxation : quasi-static relaxation rule, None for the continuous protocol
    """

    name: str
    dimension: int
    force_law: str
    beta: float
    normal_stiffness: float
    tangential_stiffness: float
    box_length: float
    size_distribution: str
    diameter_ratio: float
    small_to_large: float
    polydispersity: float
    friction: float
    restitution: float
    damping_model: str
    walls: str
    time_step: float
    protocol: str
    wall_speed: float
    initial_speed: float
    rho_grid: tuple[float, ...]
    relaxation: Relaxation | None
    paper: str = field(default="P1")
    normal_damping: float | None = None
    initial_state: InitialState | None = field(default=None, repr=False)
    wall_stiffness_factor: float = field(default=1.0, repr=False)

    @property
    def rho_labels(self) -> list[str]:
        """ρ values as they appear in file names, e.g. ``"0.842"``."""
        return [format_rho(rho) for rho in self.rho_grid]


#: the `force_law` an imported system records (its stacked files' global attribute): the law is the source's own
IMPORTED_FORCE_LAW = "imported"


@dataclass(frozen=True)
class ImportedSystem:
    """A system whose states are imported (`forcenet.importers`) instead of simulated: a config entry with
    ``source:`` (a format and its files) in place of the DEM settings.

    Attributes
    ----------
    name : config name
    dimension : 2 or 3
    rho_grid : the run's state axis, increasing: the packing fractions of its states as the config declares them
        (``systems.<name>.rho``, at `RHO_DECIMALS`; the import job checks them against the files) for a compression
        (`coordinate` "rho"); the coordinate of each state
        for a sequence (``source.sequence``, `forcenet.importers.sequence`), whose stacked files name that axis after
        the coordinate (`forcenet.datasets.schema.STATE_COORDINATE_ATTR`)
    source : the config's ``source:`` entry
    particles : particles in run 0's first state from a bounded read of its file's head (the cost model's job sizes;
        `forcenet.importers.scan.first_state_particles`)
    force_law : ``"imported"`` (the law is the source's own; every network is analysed in units of its mean force)
    coordinate : "rho" (a compression), or a sequence's coordinate: strain, time, frame or timestep
    units : the config's ``units:`` entry (length, force, time), empty for the source's own unnamed units
    movies : whether the P1 movies of this system are made (``movies:``, default false: opt-in for imports)
    """

    name: str
    dimension: int
    rho_grid: tuple[float, ...]
    source: Mapping[str, Any] = field(compare=False)
    particles: int = 0
    force_law: str = IMPORTED_FORCE_LAW
    paper: str = "imported"
    normal_stiffness: float = float("nan")
    coordinate: str = "rho"
    units: Mapping[str, str] = field(default_factory=dict, compare=False)
    movies: bool = False

    @property
    def is_sequence(self) -> bool:
        return self.coordinate != "rho"

    @property
    def rho_labels(self) -> list[str]:
        """The states' labels in file names: ρ at `RHO_DECIMALS` (a compression), ``state000``, … (a sequence)."""
        if self.is_sequence:
            return state_labels(len(self.rho_grid))
        return [format_rho(rho) for rho in self.rho_grid]


def rho_grid(spec: Any, key: str) -> tuple[float, ...]:
    """Expand a ρ grid: ``{start, stop, step}`` (stop included when on the grid), ``{start, stop, count}``
    (both ends included) or an explicit list. Values are rounded to `RHO_DECIMALS` and must increase."""
    if isinstance(spec, Mapping):
        start, stop = float(spec["start"]), float(spec["stop"])
        if stop < start:
            raise ConfigError(key, f"stop {stop} is below start {start}: the ρ grid is empty")
        if "step" in spec:
            n = int(math.floor((stop - start) / float(spec["step"]) + 1e-9)) + 1
            values = start + float(spec["step"]) * np.arange(n)
        else:
            values = np.linspace(start, stop, int(spec["count"]))
    else:
        values = np.asarray(list(spec), dtype=float)
    values = np.round(values, RHO_DECIMALS)
    if values.size == 0:
        raise ConfigError(key, "the ρ grid is empty")
    if np.any(np.diff(values) <= 0):
        raise ConfigError(key, f"ρ values must increase and differ at {RHO_DECIMALS} decimals: {values.tolist()}")
    if values[0] <= 0 or values[-1] >= 1:
        raise ConfigError(key, f"ρ values must lie in (0, 1): {values.tolist()}")
    return tuple(float(v) for v in values)


def material_from_config(config: Mapping[str, Any]) -> units.Material:
    return units.Material(**config["material"])


def system_from_config(name: str, config: Mapping[str, Any]) -> SystemSpec:
    """Build the `SystemSpec` of the simulated system ``config["systems"][name]`` (config already schema-validated),
    without the physical checks (`forcenet.checks.check_system`). An imported system (an entry with ``source:``) is
    built from its config entry by `forcenet.importers.imported_system_from_config`; `forcenet.checks.checked_system` builds
    either kind, checked."""
    key = f"systems.{name}"
    if name not in config["systems"]:
        raise ConfigError(key, "no such system")
    entry = config["systems"][name]
    if "source" in entry:
        raise ConfigError(f"{key}.source", "an imported system has no simulation settings: "
                                           "forcenet.checks.checked_system builds it from its files")
    if entry["stiffness"] == "material" and "material" not in config:
        raise ConfigError("material", f"missing: system '{name}' takes its stiffness from the material")
    beta = units.FORCE_LAW_BETA[entry["force_law"]]
    if entry["stiffness"] == "material":  # P1: Y, σ, d_ave, m̄, v0 → k_n in τ_c units
        k_n = units.reduced_normal_stiffness(material_from_config(config), beta)
        paper = "P1"
    else:  # P2: τ_c is the collision time of two mean particles under a linear spring
        if beta != 0.0:
            raise ConfigError(f"{key}.stiffness", "'collision_time' (P2 units) needs force_law: linear")
        k_n = units.P2_REDUCED_NORMAL_STIFFNESS
        paper = "P2"
    if "normal_damping" in entry and entry["damping_model"] != "explicit":
        raise ConfigError(f"{key}.normal_damping", f"is used only with damping_model: explicit (this system's "
                                                   f"damping_model is {entry['damping_model']}): remove one")
    wall_factor = 1.0
    if "wall_material" in entry:  # P1 §2: the walls have the material properties of plexiglass
        if entry["walls"] != "flat" or entry["stiffness"] != "material":
            raise ConfigError(f"{key}.wall_material", "needs walls: flat and stiffness: material (the particles' "
                                                      "Young's modulus and Poisson ratio come from the material block)")
        wall = entry["wall_material"]
        wall_factor = units.wall_stiffness_factor(material_from_config(config), float(wall["young_modulus"]),
                                                  float(wall["poisson_ratio"]))
    relaxation = None
    if entry["protocol"] == "quasistatic":
        criterion = entry["relaxation"].get("criterion", KINETIC_ENERGY_FLUCTUATION)
        if criterion not in RELAXATION_CRITERIA:
            raise ConfigError(f"{key}.relaxation.criterion",
                              f"is {criterion!r}, not one of {list(RELAXATION_CRITERIA)}")
        relaxation = Relaxation(**entry["relaxation"])
    return SystemSpec(
        name=name,
        dimension=int(entry["dimension"]),
        force_law=entry["force_law"],
        beta=beta,
        normal_stiffness=k_n,
        tangential_stiffness=k_n * float(entry["tangential_stiffness_ratio"]),
        box_length=float(entry["box_length"]),
        size_distribution=entry["size_distribution"],
        diameter_ratio=float(entry.get("diameter_ratio", 1.0)),
        small_to_large=float(entry.get("small_to_large", 1.0)),
        polydispersity=float(entry.get("polydispersity", 0.0)),
        friction=float(entry["friction"]),
        restitution=float(entry["restitution"]),
        damping_model=entry["damping_model"],
        normal_damping=float(entry["normal_damping"]) if "normal_damping" in entry else None,
        initial_state=InitialState(**entry["initial_state"]) if "initial_state" in entry else None,
        walls=entry["walls"],
        wall_stiffness_factor=wall_factor,
        time_step=float(entry["time_step"]),
        protocol=entry["protocol"],
        wall_speed=float(entry["wall_speed"]),
        initial_speed=float(entry["initial_speed"]),
        rho_grid=rho_grid(entry["rho"], f"{key}.rho"),
        relaxation=relaxation,
        paper=paper,
    )


def resolve_rattler_rule(remove_rattlers: bool | str) -> str:
    """``True`` → "once" (P1 §3), ``False`` → "none" (P2 §III C: rattlers kept), or a rule name itself
    (`RATTLER_RULES`; what each does: `forcenet.network.RATTLER_RULE_DESCRIPTIONS`)."""
    if remove_rattlers is True:
        return "once"
    if remove_rattlers is False:
        return "none"
    if remove_rattlers not in RATTLER_RULES:
        raise ValueError(f"remove_rattlers must be a bool or one of {RATTLER_RULES}, got {remove_rattlers!r}")
    return remove_rattlers


def study_rattler_rule(config: Mapping[str, Any], system: str) -> str:
    """The rattler rule that makes `system`'s force networks (its analysis files and its study's products).

    Each study may choose its own (``studies.<study>.remove_rattlers``: P1 removes rattlers, P2 keeps them);
    a study without one, or a system in no study, uses ``analysis.remove_rattlers``. A system listed by two
    studies with different rules is a `ConfigError` (its snapshots are analysed once).
    """
    default = config["analysis"]["remove_rattlers"]
    rules = {}
    for study, entry in config["studies"].items():
        if system in entry["systems"] or system in entry.get("counterparts", ()):
            key = f"studies.{study}.remove_rattlers" if "remove_rattlers" in entry else "analysis.remove_rattlers"
            try:
                rules[key] = resolve_rattler_rule(entry.get("remove_rattlers", default))
            except ValueError as error:
                raise ConfigError(key, str(error)) from None
    if len(set(rules.values())) > 1:
        raise ConfigError(next(iter(rules)), f"system '{system}' is analysed once but its studies ask for different "
                                             f"rattler rules: {rules}")
    if rules:
        return next(iter(rules.values()))
    try:
        return resolve_rattler_rule(default)
    except ValueError as error:
        raise ConfigError("analysis.remove_rattlers", str(error)) from None


def non_finite_number(config: Any, key: str = "") -> ConfigError | None:
    """The first NaN or ±inf anywhere in `config` (YAML's ``.nan``, ``.inf``, ``-.inf``; nested mappings and lists
    walked in order), as a `ConfigError` naming its key (``systems.2d_hertz.rho[1]``); None when every number is
    finite. A JSON schema cannot say this: every comparison with NaN is false, so NaN passes any bound."""
    if isinstance(config, float) and not math.isfinite(config):
        return ConfigError(key or "(top level)", f"is {config}, not a finite number: every number in a config must "
                                                 "be finite")
    if isinstance(config, Mapping):
        items = ((f"{key}.{name}" if key else str(name), value) for name, value in config.items())
    elif isinstance(config, (list, tuple)):
        items = ((f"{key}[{index}]", value) for index, value in enumerate(config))
    else:
        return None
    for item_key, value in items:
        problem = non_finite_number(value, item_key)
        if problem is not None:
            return problem
    return None


def realization_count(config: Mapping[str, Any], system: str) -> int:
    """How many realizations (compression runs with their own seeds) `system` gets: ``realizations`` is one integer
    for every system or a mapping {system: integer} (e.g. more for the cheap 2D systems than for 3D)."""
    realizations = config["realizations"]
    return int(realizations[system] if isinstance(realizations, Mapping) else realizations)


def realization_indices(config: Mapping[str, Any], system: str) -> list[int]:
    """The realization indices of `system`: 0 … count − 1. Realization k keeps its name (``r{k:02d}``), its seed
    (`realization_seed`) and so its files whatever the count, so raising a count adds runs and restarts none."""
    return list(range(realization_count(config, system)))


def realization_seed(base_seed: int, system_name: str, realization: int) -> int:
    """Seed of one compression run: independent of the order systems appear in the config."""
    return (int(base_seed) * 1_000_003 + zlib.crc32(system_name.encode()) * 101 + int(realization)) % (2 ** 32)


def run_seed(config: Mapping[str, Any], system: str, realization: int) -> int:
    """The seed of realization `realization` of `system`: `realization_seed` of its own name, or of the system its
    entry names under ``seeds_of`` (a control or a series point that starts from the same initial states as the
    system it is compared with: paired runs)."""
    return realization_seed(config["seed"], config["systems"][system].get("seeds_of", system), realization)


def select_table_snapshots(rhos, table_rho: float) -> tuple[int, int, int]:
    """Indices (a, b, c) of three consecutive grid points around `table_rho` (P2 Fig. 1: three values of ρ close
    to 0.79): b is the grid point nearest `table_rho`, a and c its neighbours below and above (shifted inwards at
    the ends of the grid). Indices refer to `rhos` as given (it need not be sorted)."""
    rhos = np.asarray(rhos, dtype=float)
    if rhos.ndim != 1 or rhos.size < TABLE_STATES:
        raise ValueError(f"need at least {TABLE_STATES} snapshots, got {rhos.size}")
    if not np.all(np.isfinite(rhos)) or len(np.unique(rhos)) != rhos.size:
        raise ValueError("rho values must be finite and distinct")
    order = np.argsort(rhos)
    nearest = int(np.argmin(np.abs(rhos[order] - table_rho)))
    middle = min(max(nearest, 1), rhos.size - 2)
    a, b, c = (int(order[i]) for i in (middle - 1, middle, middle + 1))
    return a, b, c
