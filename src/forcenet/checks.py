"""The checks of a config before any job, each naming its key: what a JSON schema cannot see, and the physical
checks of one system that need nothing but its config.

`validate_config` checks a whole config and builds every system with `checked_system`: a simulated system's
`forcenet.systems.SystemSpec` must pass `check_system` (`system_problems`), when the workflow reads its config (before
any job, a dry run included) and again when a run starts (`forcenet.pipeline.simulate`); an imported system's
`ImportedSystem` is built from its config entry, its source files' paths and sizes checked, never their contents
(`forcenet.importers.imported_system_from_config`). The margins:

* **ρ grid against the initial packing.** The first grid value must lie above the packing fraction of the initial
  lattice (`forcenet.dem.packing`): exact for bidisperse sizes (the counts are fixed); for polydisperse sizes,
  whose lattice ρ varies with the seed, the expectation plus `INITIAL_RHO_SIGMAS` standard deviations.
* **ρ grid against the densest packing.** Disks: the last grid value must stay at or below the densest packing of
  equal disks, π/(2√3) = 0.9069, compressed to a uniform overlap of `RHO_OVERLAP_MARGIN` of a diameter: ρ_max =
  ρ_densest / (1 − margin)² = 0.9105. (Hard disks of two sizes cannot be packed much denser: Florian's bound is
  0.9091 for diameter ratio 1.4, 0.9101 for 1.5.) The margin is small on purpose: a disordered packing is never
  compressed uniformly, so its largest overlap is far above the mean (14–15 % of a diameter at ρ = 0.91 in 2D,
  growing ≈ 0.7 % per 0.01 in ρ); it admits the end of P1's 2D grid (0.91, which P1 ran: a simulation then warns of
  every snapshot past P1's 10 % overlap, `forcenet.dem.protocol.warn_of_overlaps`) and refuses the next grid point
  (0.92). Spheres: the last grid value must stay below the densest packing of equal spheres, π/(3√2) = 0.7405,
  at the grid's `RHO_DECIMALS` decimals (ρ ≤ 0.739): a disordered packing of spheres of two sizes never reaches
  the fcc density (random close packing is ≈ 0.64; the largest overlap is 13.5 % at P1's 0.71 already), and a grid
  to 0.74 passed the engine's 20 % blow-up limit at job time. P1's 3D grid (to 0.71) passes. The walls must also be
  able to reach it: the final box must stay wider than two of the largest particles.
* **Δt against the collision time of the lightest pair.** The undamped head-on collision of two of the lightest
  particles at twice the fastest imposed speed (initial or wall speed; P1 Eq. 4 generalised,
  `forcenet.units.undamped_collision_time`) must span at least `MIN_STEPS_PER_COLLISION` steps.
* **Damping against the Gear corrector's bound** (`forcenet.dem.stability.GEAR_DAMPING_BOUND`), where it can
  be estimated from the config: for the linear force law the damping rate of a contact does not depend on its
  overlap, and a single contact between two of the lightest particles damps its slip at 3 γ (disks) or 3.5 γ
  (spheres) (P1 Eq. 1–2; the exact mode of `stability.fastest_damping_rate`). A packing, with several contacts
  per particle, damps faster still, so rate · Δt above the bound for one contact means the run cannot be stable.
  γ_n is the damping model's value, for ``head_on`` its closed form, which lies below the calibrated root (the
  check errs towards passing). For the Hertz law the rate grows with overlap^½, which the config does not give:
  every snapshot is checked instead (`forcenet.dem.protocol.check_damping_is_integrable`).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from typing import Any, Mapping

from forcenet import units
from forcenet.dem import packing, stability
from forcenet.datasets.paths import RHO_DECIMALS
from forcenet.dem._kernels.contacts import MAX_OVERLAP_FRACTION
from forcenet.importers.system import imported_system_from_config
from forcenet.systems import (TABLE_STATES, ConfigError, ImportedSystem, SystemSpec, non_finite_number,
                              study_rattler_rule, system_from_config)

#: random close packing of disks (bidisperse or polydisperse, ≈ P1's 2D jamming point) and of spheres: past it a
#: disordered packing is held up by overlaps alone, which grow ≈ 0.7 % of a diameter per 0.01 in ρ (module docstring)
RANDOM_CLOSE_PACKING = {2: 0.84, 3: 0.64}
#: Δt ≤ (shortest collision) / MIN_STEPS_PER_COLLISION
MIN_STEPS_PER_COLLISION = 10
#: densest packing of equal disks (hexagonal) and spheres (fcc/hcp)
DENSEST_PACKING = {2: math.pi / (2.0 * math.sqrt(3.0)), 3: math.pi / (3.0 * math.sqrt(2.0))}
#: a 2D grid may exceed the densest packing by a uniform overlap of this fraction of a diameter (admits P1's grid
#: end 0.91, refuses 0.92: module docstring); a 3D grid stays below the densest packing
RHO_OVERLAP_MARGIN = 0.002
#: polydisperse initial lattices: the first ρ must exceed the expected lattice ρ by this many standard deviations
INITIAL_RHO_SIGMAS = 5.0
#: the walls cannot close the box below this many of the largest diameters
SMALLEST_BOX_IN_DIAMETERS = 2.0


@dataclass(frozen=True)
class Problem:
    """A check that failed: `key` below ``systems.<name>`` (e.g. ``"time_step"``) and a one-line message."""

    key: str
    message: str


def max_packing_fraction(dimension: int) -> float:
    """The highest last grid value a system may ask for: ρ_densest / (1 − RHO_OVERLAP_MARGIN)² for disks (0.9105),
    for spheres the last grid value below ρ_densest at `RHO_DECIMALS` decimals (0.739)."""
    if dimension == 2:
        return DENSEST_PACKING[2] / (1.0 - RHO_OVERLAP_MARGIN) ** 2
    return round(round(DENSEST_PACKING[3], RHO_DECIMALS) - 10.0 ** -RHO_DECIMALS, RHO_DECIMALS)


def _uniform_moment(low: float, high: float, power: int) -> float:
    """E[d^power] for d uniform on [low, high]."""
    if high - low < 1e-12:
        return low ** power
    return (high ** (power + 1) - low ** (power + 1)) / ((power + 1) * (high - low))


def initial_packing_fraction_bound(system) -> float:
    """The largest packing fraction the initial lattice can have [-]: exact (bidisperse) or expectation +
    INITIAL_RHO_SIGMAS standard deviations over the random diameters (polydisperse)."""
    dim = system.dimension
    n = packing.sites_per_axis(system) ** dim
    box = system.box_length ** dim
    shape = float(packing.particle_volume(1.0, dim))  # volume = shape · d^dim
    if system.size_distribution == "bidisperse":
        s, ratio = system.small_to_large, system.diameter_ratio
        small = packing.smallest_diameter(system)
        n_small = int(round(n * s / (1.0 + s)))
        return shape * (n_small * small ** dim + (n - n_small) * (ratio * small) ** dim) / box
    low, high = packing.smallest_diameter(system), packing.largest_diameter(system)
    mean = _uniform_moment(low, high, dim)
    std = math.sqrt(max(_uniform_moment(low, high, 2 * dim) - mean ** 2, 0.0))
    return shape * (n * mean + INITIAL_RHO_SIGMAS * math.sqrt(n) * std) / box


def lightest_mass(system) -> float:
    """Mass of the lightest particle the size distribution gives [m̄] (masses ∝ d^dim, mean 1)."""
    dim = system.dimension
    small = packing.smallest_diameter(system)
    if system.size_distribution == "bidisperse":
        s, ratio = system.small_to_large, system.diameter_ratio
        mean = (s * small ** dim + (ratio * small) ** dim) / (s + 1.0)
    else:
        mean = _uniform_moment(small, packing.largest_diameter(system), dim)
    return small ** dim / mean


def shortest_collision_time(system) -> tuple[float, float, float]:
    """(duration [τ_c], mass [m̄], relative speed [d_ave/τ_c]) of the undamped head-on collision of two of the lightest
    particles at twice the fastest imposed speed (P1 Eq. 4 generalised). A flat wall's collision is never shorter: its
    reduced mass is m_i, twice the pair's, and even a rigid wall only doubles k_n (`units.wall_stiffness_factor` ≤ 2)."""
    mass = lightest_mass(system)
    speed = 2.0 * max(system.initial_speed, system.wall_speed)
    duration = units.undamped_collision_time(system.normal_stiffness, system.beta, 0.5 * mass, max(speed, 1e-12))
    return duration, mass, speed


def normal_damping_estimate(system) -> float | None:
    """γ_n of a linear-law system from its damping model [τ_c⁻¹] (``head_on``: the closed form, a lower bound of the
    calibrated value); None for the Hertz law, whose damping rate depends on the overlap."""
    if system.beta != 0.0:
        return None
    if system.damping_model != "head_on":  # linear_law and explicit: the engine's own value, no calibration to run
        from forcenet.dem.calibration import normal_damping_for_system

        return normal_damping_for_system(system)
    return units.linear_damping_for_restitution(system.normal_stiffness, system.restitution,
                                                0.5)  # two mean particles, as the calibration


def single_contact_damping_rate(system, gamma: float) -> float:
    """Fastest damping rate [τ_c⁻¹] of one contact between two of the lightest particles (zero overlap, γ_t = γ_n =
    `gamma`), from the engine's damping operator (`forcenet.dem.stability`)."""
    dim = system.dimension
    diameter = packing.smallest_diameter(system)
    mass = np.full(2, lightest_mass(system))
    inertia = mass * (0.5 if dim == 2 else 0.4) * (0.5 * diameter) ** 2  # disk m r²/2, sphere 2 m r²/5
    coefficient = gamma * 0.5 * mass[0]  # g = γ x^0 m_eff
    contact = stability.DampingContacts(
        i=np.array([0]), j=np.array([1]), normal=np.eye(dim)[:1], normal_coefficient=np.array([coefficient]),
        tangential_coefficient=np.array([coefficient]), lever_i=np.array([0.5 * diameter]),
        lever_j=np.array([0.5 * diameter]))
    return stability.fastest_damping_rate(contact, mass, inertia).rate


def system_problems(system) -> list[Problem]:
    """Every check above (and positivity of what the engine divides by) on a `forcenet.systems.SystemSpec`."""
    problems = []
    positive = {"box_length": system.box_length, "time_step": system.time_step, "wall_speed": system.wall_speed,
                "normal_stiffness": system.normal_stiffness}
    if system.size_distribution == "bidisperse":
        positive.update(diameter_ratio=system.diameter_ratio, small_to_large=system.small_to_large)
    problems += [Problem(name, f"must be positive, got {value}") for name, value in positive.items()
                 if not (math.isfinite(value) and value > 0)]
    problems += [Problem(name, f"must be non-negative, got {value}") for name, value in
                 {"initial_speed": system.initial_speed, "friction": system.friction,
                  "tangential_stiffness": system.tangential_stiffness,
                  "polydispersity": system.polydispersity}.items() if not (math.isfinite(value) and value >= 0)]
    if not 0.0 < system.restitution <= 1.0:
        problems.append(Problem("restitution", f"must lie in (0, 1], got {system.restitution}"))
    if system.protocol == "quasistatic" and system.relaxation is None:
        problems.append(Problem("relaxation", "the quasi-static protocol needs a relaxation rule"))
    if system.size_distribution == "polydisperse" and system.polydispersity >= 1.0:
        problems.append(Problem("polydispersity", "r_p must be < 1 so that every diameter 1 ± r_p/2 is positive"))
    if problems:  # the physics below needs sane numbers
        return problems
    n_axis = packing.sites_per_axis(system)
    if n_axis ** system.dimension < 2:
        return [Problem("box_length", f"a box of {system.box_length} d_ave holds {n_axis ** system.dimension} "
                                      "particle(s) on the initial lattice; need ≥ 2")]
    overlap = packing.initial_overlap(system)
    if overlap >= MAX_OVERLAP_FRACTION:
        return [Problem("initial_state.sites_per_axis",
                        f"{n_axis} sites per axis in a box of {system.box_length} d_ave are "
                        f"{packing.lattice_spacing(system):.4f} d_ave apart, so two large particles overlap by "
                        f"{overlap:.0%} of their diameter at t = 0, at or above the engine's blow-up limit "
                        f"{MAX_OVERLAP_FRACTION:.0%}: use fewer sites or a larger box")]
    problems += _rho_problems(system)
    problems += _time_step_problems(system)
    return problems


def past_random_close_packing(system) -> bool:
    """Whether a valid system's ρ grid ends past random close packing (`RANDOM_CLOSE_PACKING`): the papers' grids
    do, on purpose; there the largest overlaps pass P1's stated 10 % of a diameter (13 % at 2D 0.91, issue 57) and a
    3D run near the densest packing may stop at the engine's blow-up limit (0.74 did). A note, not a refusal."""
    return system.rho_grid[-1] > RANDOM_CLOSE_PACKING[system.dimension]


def _rho_problems(system) -> list[Problem]:
    dim = system.dimension
    rho0 = initial_packing_fraction_bound(system)
    first, last = system.rho_grid[0], system.rho_grid[-1]
    if first <= rho0:
        exact = "" if system.size_distribution == "bidisperse" else f" + {INITIAL_RHO_SIGMAS:g} σ over seeds"
        return [Problem("rho", f"the first ρ = {first} is not above the packing fraction of the initial lattice, "
                               f"{rho0:.4f}{exact} (box {system.box_length} d_ave, {packing.sites_per_axis(system)}"
                               f"^{dim} sites): start the grid higher")]
    highest = max_packing_fraction(dim)
    if last > highest and dim == 2:
        return [Problem("rho", f"the last ρ = {last} is above {highest:.4f}, the densest packing of equal disks "
                               f"({DENSEST_PACKING[dim]:.4f}) compressed to a uniform overlap of "
                               f"{RHO_OVERLAP_MARGIN:.1%} of a diameter: lower the grid's stop")]
    if last > highest + 1e-12:
        return [Problem("rho", f"the last ρ = {last} is at or above the densest packing of equal spheres, π/(3√2) = "
                               f"{DENSEST_PACKING[dim]:.4f} ({DENSEST_PACKING[dim]:.{RHO_DECIMALS}f} at the grid's "
                               f"{RHO_DECIMALS} decimals), which a disordered packing never reaches (the engine stops at its {MAX_OVERLAP_FRACTION:.0%} overlap "
                               f"limit): end the grid at {highest:.{RHO_DECIMALS}f} or below")]
    final_length = system.box_length * (rho0 / last) ** (1.0 / dim)
    smallest_box = SMALLEST_BOX_IN_DIAMETERS * packing.largest_diameter(system)
    if final_length < smallest_box:
        return [Problem("rho", f"ρ = {last} needs a box of {final_length:.3f} d_ave, narrower than "
                               f"{SMALLEST_BOX_IN_DIAMETERS:g} of the largest particles ({smallest_box:.3f} d_ave): "
                               "enlarge box_length or lower the grid's stop")]
    return []


def _time_step_problems(system) -> list[Problem]:
    dt = system.time_step
    shortest, mass, speed = shortest_collision_time(system)
    limit = shortest / MIN_STEPS_PER_COLLISION
    if dt > limit:
        return [Problem("time_step", f"Δt = {dt} τ_c is too large: the shortest collision (two particles of mass "
                                     f"{mass:.3f} m̄ at relative speed {speed:g} d_ave/τ_c) lasts {shortest:.4g} τ_c "
                                     f"and must span {MIN_STEPS_PER_COLLISION} steps: Δt ≤ {limit:.4g} τ_c")]
    gamma = normal_damping_estimate(system)
    if gamma is None:
        return []
    rate = single_contact_damping_rate(system, gamma)
    if rate * dt > stability.GEAR_DAMPING_BOUND:
        return [Problem("time_step", f"Δt = {dt} τ_c is too large for the contact damping: one contact alone damps "
                                     f"its slip at {rate:.4g} τ_c⁻¹ (γ_n ≥ {gamma:.4g} τ_c⁻¹ from restitution "
                                     f"{system.restitution}, damping_model {system.damping_model}), and rate · Δt = "
                                     f"{rate * dt:.3g} exceeds the Gear corrector's bound "
                                     f"{stability.GEAR_DAMPING_BOUND}: Δt ≤ {stability.stable_time_step(rate):.4g} τ_c "
                                     "(a packing needs less still) or a larger restitution")]
    return []


def check_system(system: SystemSpec, key: str) -> None:
    """Every check that needs only the config (`system_problems`: positivity, the ρ grid against the initial and the
    densest packing, Δt against the shortest collision and the contact damping); raise `ConfigError` naming the
    key (``{key}.<setting>``) of the first that fails."""
    problems = system_problems(system)
    if problems:
        raise ConfigError(f"{key}.{problems[0].key}", problems[0].message)


def checked_system(name: str, config: Mapping[str, Any]) -> SystemSpec | ImportedSystem:
    """The system ``config["systems"][name]`` of a schema-validated config: a simulated system's `SystemSpec`
    (`forcenet.systems.system_from_config`) that passed `check_system`, or an imported system's `ImportedSystem`
    (an entry with ``source:``, `forcenet.importers.imported_system_from_config`: its files' paths and sizes checked,
    not read). Raises
    `ConfigError` naming the key."""
    key = f"systems.{name}"
    if name not in config["systems"]:
        raise ConfigError(key, "no such system")
    if "source" in config["systems"][name]:
        return imported_system_from_config(name, config)
    system = system_from_config(name, config)
    check_system(system, key)
    return system


def validate_config(config: Mapping[str, Any]) -> dict[str, SystemSpec | ImportedSystem]:
    """Semantic validation after the JSON schema; returns every system by name (`checked_system`). Raises
    `ConfigError`."""
    problem = non_finite_number(config)
    if problem is not None:
        raise problem
    for study, entry in config["studies"].items():
        if "counterparts" in entry and study != "p1":
            raise ConfigError(f"studies.{study}.counterparts", "only P1's friction and system-size claims judge "
                                                               "counterpart runs; this study has none")
        for key in ("systems", "counterparts"):
            for i, name in enumerate(entry.get(key, ())):
                if name not in config["systems"]:
                    raise ConfigError(f"studies.{study}.{key}[{i}]", f"unknown system '{name}' "
                                                                      f"(defined: {sorted(config['systems'])})")
                if key == "counterparts" and name in entry["systems"]:
                    raise ConfigError(f"studies.{study}.{key}[{i}]", f"'{name}' is one of the study's own systems; "
                                                                      "a counterpart stands beside them")
    thresholds = config["analysis"]["thresholds"]
    if thresholds["stop"] <= thresholds["start"]:
        raise ConfigError("analysis.thresholds", "stop must exceed start")
    for name in config["systems"]:
        study_rattler_rule(config, name)
    realizations = config["realizations"]
    if isinstance(realizations, Mapping):
        for name in realizations:
            if name not in config["systems"]:
                raise ConfigError(f"realizations.{name}",
                                  f"unknown system '{name}' (defined: {sorted(config['systems'])})")
        missing = [name for name in config["systems"] if name not in realizations]
        if missing:
            raise ConfigError("realizations", f"no count for system(s) {missing}: a per-system mapping names every "
                                              "system (or give one integer for all)")
    systems = {name: checked_system(name, config) for name in config["systems"]}
    for name in config["studies"].get("p2", {}).get("systems", []):
        if len(systems[name].rho_grid) < TABLE_STATES:
            raise ConfigError(f"systems.{name}.rho", f"has {len(systems[name].rho_grid)} snapshot(s), but a system of "
                                                     f"study p2 needs at least {TABLE_STATES} (the consecutive states "
                                                     "a, b, c of Tables I–III): extend the ρ grid")
    return systems
