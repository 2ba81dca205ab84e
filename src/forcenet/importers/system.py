"""An imported system of a config (an entry with ``source:``) → its `forcenet.systems.ImportedSystem`, from the config
alone when the workflow parses it (`imported_system`: a compression's states by the ρ the config declares under
``systems.<name>.rho``, a sequence's by its coordinate and the states or timesteps its run lists; the source files'
paths and sizes checked, `forcenet.importers.scan`, never their contents), and the full read of a run checked against
it (`checked_run`): by the import job, and by `forcenet-check-config` for every run (`read_all_sources`)."""
from __future__ import annotations

from typing import Any, Mapping

from forcenet.datasets.paths import RHO_DECIMALS, format_rho
from forcenet.importers.common import SourceError, SourceState
from forcenet.importers.scan import file_record, first_state_particles, run_paths
from forcenet.importers.sequence import COORDINATES, SequenceError, coordinate, coordinate_values
from forcenet.importers.sources import source_states
from forcenet.systems import ConfigError, ImportedSystem, realization_indices, rho_grid

#: how `forcenet-check-config` is named in the messages that send a user to it
CHECK_CONFIG = "forcenet-check-config CONFIG"


class UndeclaredStates(ConfigError):
    """An imported compression without ``systems.<name>.rho``: the workflow reads no source file when it parses a
    config, so the states' ρ (their snapshots' names) must be declared; `forcenet-check-config` reads the files and
    says them (`measured_labels`)."""

    def __init__(self, system: str):
        super().__init__(f"systems.{system}.rho", "not given: an imported compression declares the ρ of each state of "
                                                  f"its runs, in order, at {RHO_DECIMALS} decimals (its snapshots' "
                                                  "names; the import job checks them against the files); the workflow "
                                                  f"reads no source file when it parses a config: {CHECK_CONFIG} "
                                                  "reads them and prints the list")
        self.system = system


def imported_system_from_config(name: str, config: Mapping[str, Any]) -> ImportedSystem:
    """The `ImportedSystem` of ``config["systems"][name]`` (schema-validated, with ``source:``): one source run per
    realization (`ConfigError` naming ``systems.<name>.source.runs`` otherwise), then `imported_system`."""
    entry = config["systems"][name]
    runs = len(entry["source"]["runs"])
    if runs != config["realizations"]:
        raise ConfigError(f"systems.{name}.source.runs", f"lists {runs} run(s), but realizations is "
                                                         f"{config['realizations']}: one run per realization")
    return imported_system(name, entry)


def imported_system(name: str, entry: Mapping[str, Any]) -> ImportedSystem:
    """The `ImportedSystem` of a ``source:`` entry from the config alone: a compression's ρ grid as declared
    (``systems.<name>.rho``, `UndeclaredStates` when absent), a sequence's coordinate of each state
    (`declared_timesteps`, `coordinate_values`). Every source file is checked to exist and not be empty
    (`forcenet.importers.scan.file_record`), and run 0's first header gives the particles (the cost model); nothing
    else is read: the import job checks the files against these states (`checked_run`). Raises `ConfigError` naming
    the key, or `SourceError` naming a missing or empty file."""
    key = f"systems.{name}.source"
    source = entry["source"]
    for run in range(len(source["runs"])):
        for path in run_paths(entry, run):
            file_record(path)
    listed = None
    if source["format"] == "table":
        counts = [len(run) for run in source["runs"]]
        if len(set(counts)) != 1:
            raise ConfigError(f"{key}.runs", f"every run needs the same number of states, got {counts}")
        listed = counts[0]
    common = dict(name=name, dimension=int(entry["dimension"]), source=dict(source),
                  particles=first_state_particles(entry), units=dict(entry.get("units") or {}),
                  movies=bool(entry.get("movies", False)))
    name_of = coordinate(entry)
    if name_of not in COORDINATES:
        raise ConfigError(f"{key}.sequence.coordinate", f"{name_of!r} is not one of {', '.join(COORDINATES)}")
    if name_of != "rho":
        if "rho" in entry:
            raise ConfigError(f"systems.{name}.rho", "a sequence's states are keyed by its coordinate "
                                                     f"({name_of}), their ρ measured by the import job: leave rho out")
        try:
            values = coordinate_values(entry, declared_timesteps(entry, key), key)
        except SequenceError as error:
            raise ConfigError(error.key, error.problem) from None
        return ImportedSystem(rho_grid=values, coordinate=name_of, **common)
    if "rho" not in entry:
        raise UndeclaredStates(name)
    grid = rho_grid(entry["rho"], f"systems.{name}.rho")
    if listed is None and "timesteps" in source:
        listed = len(source["timesteps"])
    if listed is not None and listed != len(grid):
        raise ConfigError(f"systems.{name}.rho", f"declares {len(grid)} state(s), but source."
                                                 f"{'runs[0] lists' if source['format'] == 'table' else 'timesteps picks'}"
                                                 f" {listed}: one ρ per state, in order")
    return ImportedSystem(rho_grid=grid, **common)


def declared_timesteps(entry: Mapping[str, Any], key: str) -> list[int]:
    """The timestep of each state of a sequence's run as the config gives them (`coordinate_values` reads them): a
    table run's positions; a LAMMPS run's ``source.timesteps``, else, with ``sequence.values``, positions. A LAMMPS
    sequence with neither raises `ConfigError` naming ``source.timesteps``: its number of states is not read from
    the dump when the config is parsed."""
    source = entry["source"]
    if source["format"] == "table":
        return list(range(len(source["runs"][0])))
    if "timesteps" in source:
        return [int(step) for step in source["timesteps"]]
    values = (source.get("sequence") or {}).get("values")
    if values is not None:
        return list(range(len(values)))
    raise ConfigError(f"{key}.timesteps", "not given: a LAMMPS sequence lists its states, as the workflow reads no "
                                          "source file when it parses a config: source.timesteps (the dump's "
                                          "timesteps it takes, in order) or sequence.values (one per state)")


def checked_run(name: str, entry: Mapping[str, Any], spec: ImportedSystem,
                realization: int) -> tuple[list[SourceState], tuple[float, ...] | None]:
    """Every state of run `realization` read in full (`source_states`) and checked against the states the config
    declares (`spec`, from `imported_system`): their number, each state's ρ below 1, and a compression's ρ at
    `RHO_DECIMALS` decimals (a sequence's coordinate) equal to the declared one. Returns the states and a sequence's
    coordinate values (None for a compression); raises `SourceError` naming the file and the state."""
    key = f"systems.{name}.source"
    states = source_states(entry, realization, where=key)
    lammps = entry["source"]["format"] == "lammps"
    first = run_paths(entry, realization)[0]
    declared = spec.rho_grid
    if len(states) != len(declared):
        given = (f"systems.{name}.rho declares" if not spec.is_sequence else
                 "source.timesteps picks" if "timesteps" in entry["source"] else "source.sequence.values gives")
        raise SourceError(first, "", f"{len(states)} state(s) in run {realization}, but {given} {len(declared)}: "
                                     "every run of a system has the states the config declares")
    if not spec.is_sequence:
        same_rho_problem(states, first, f"{key}.runs[{realization}]")
    for k, state in enumerate(states):
        where = f"timestep {state.timestep}" if lammps else f"state {k}"
        rho = state.rho
        if not 0.0 < rho < 1.0:
            raise SourceError(state.files[0], where, f"ρ = {rho:.4g}: the particles' "
                                                     f"{'area' if spec.dimension == 2 else 'volume'} is not below the "
                                                     "box's (radii and box in different units? diameters given as "
                                                     "radii?)")
        if not spec.is_sequence and format_rho(rho) != format_rho(declared[k]):
            raise SourceError(state.files[0], where, f"ρ = {rho:.5f} ({format_rho(rho)} at {RHO_DECIMALS} decimals), "
                                                     f"but systems.{name}.rho declares {format_rho(declared[k])} for "
                                                     f"state {k}: declare the ρ the files give ({CHECK_CONFIG} "
                                                     "prints them)")
    if not spec.is_sequence:
        return states, None
    values = coordinate_values(entry, [state.timestep for state in states], key)
    for k, (value, given) in enumerate(zip(values, declared)):
        if value != given:
            state = states[k]
            raise SourceError(state.files[0], f"timestep {state.timestep}" if lammps else f"state {k}",
                              f"its {spec.coordinate} is {value:g} in the file's order, but the config gives "
                              f"{given:g} for state {k}: list source.timesteps in the dump's order")
    return states, values


def same_rho_problem(states: list[SourceState], path: str, key: str) -> None:
    """Raise `SourceError` naming `path` when two consecutive states of a compression share one ρ at `RHO_DECIMALS`
    decimals: such a run (a shear at constant volume) is a sequence."""
    labels = [format_rho(state.rho) for state in states]
    if any(a == b for a, b in zip(labels, labels[1:])):
        raise SourceError(path, key, f"states with the same ρ at {RHO_DECIMALS} decimals ({', '.join(labels)}): a "
                                     "compression's states are keyed by ρ; a sequence at constant ρ (a shear, a time "
                                     "series) is one run with source.sequence: {coordinate: strain, time, frame or "
                                     "timestep}")


def measured_labels(name: str, entry: Mapping[str, Any]) -> list[str]:
    """The ρ of each state of run 0 at `RHO_DECIMALS` decimals, read from its files in full: what
    ``systems.<name>.rho`` declares (`forcenet-check-config` prints them for a compression that declares none)."""
    key = f"systems.{name}.source"
    states = source_states(entry, 0, where=key)
    if coordinate(entry) == "rho":
        same_rho_problem(states, run_paths(entry, 0)[0], f"{key}.runs[0]")
    return [format_rho(state.rho) for state in states]


def read_all_sources(config: Mapping[str, Any], systems: Mapping[str, Any]) -> None:
    """Read every run of every imported system in `systems` in full and check it against its declared states
    (`checked_run`), as its import job will: `forcenet-check-config` finds a bad source file before any job.
    Raises the first `forcenet.importers.SourceError`."""
    for name, spec in systems.items():
        if isinstance(spec, ImportedSystem):
            for realization in realization_indices(config, name):
                checked_run(name, config["systems"][name], spec, realization)
