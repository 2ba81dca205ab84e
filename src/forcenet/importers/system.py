"""An imported system of a config (an entry with ``source:``) → its `forcenet.systems.ImportedSystem`: the state axis
of its runs from the particles files (`scan.run_scan`, read once per content when the workflow parses the config),
and the full read of every source file that `forcenet-check-config` makes before any job (`read_all_sources`)."""
from __future__ import annotations

from typing import Any, Mapping

import numpy as np

from forcenet.datasets.paths import RHO_DECIMALS
from forcenet.importers.scan import run_scan
from forcenet.importers.sequence import COORDINATES, SequenceError, coordinate, coordinate_values
from forcenet.importers.sources import source_states
from forcenet.systems import ConfigError, ImportedSystem, realization_indices, rho_grid


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
    """The `ImportedSystem` of a ``source:`` entry: the ρ grid of run 0 from each state's particles and box
    (`forcenet.importers.scan.run_scan`: the particles files read once per content, which stops at a malformed
    one with its name and line; the other files are checked to exist here and read by the import job), or for a
    sequence (``source.sequence``) the coordinate of each state, the same in every run."""
    key = f"systems.{name}.source"
    runs = [run_scan(entry, run) for run in range(len(entry["source"]["runs"]))]
    grids = [[rho for rho, _, _ in states] for states in runs]
    if len({len(grid) for grid in grids}) != 1:
        raise ConfigError(f"{key}.runs", f"every run needs the same number of states, got {[len(g) for g in grids]}")
    common = dict(name=name, dimension=int(entry["dimension"]), source=dict(entry["source"]),
                  particles=runs[0][0][1] if runs[0] else 0, units=dict(entry.get("units") or {}),
                  movies=bool(entry.get("movies", False)), measured_rho=tuple(grids[0]))
    name_of = coordinate(entry)
    if name_of not in COORDINATES:
        raise ConfigError(f"{key}.sequence.coordinate", f"{name_of!r} is not one of {', '.join(COORDINATES)}")
    if name_of != "rho":
        try:
            values = [coordinate_values(entry, [step for _, _, step in states], key) for states in runs]
        except SequenceError as error:
            raise ConfigError(error.key, error.problem) from None
        for run, other in enumerate(values[1:], start=1):
            if other != values[0]:
                raise ConfigError(f"{key}.runs[{run}]", f"its states' {name_of} differ from run 0's: every run of a "
                                                        "sequence is stacked on run 0's coordinate")
        return ImportedSystem(rho_grid=values[0], coordinate=name_of, **common)
    rounded = np.round(grids[0], RHO_DECIMALS)
    if np.any(np.diff(rounded) == 0):  # a shear at constant volume: its states share one ρ
        raise ConfigError(f"{key}.runs[0]", f"states with the same ρ at {RHO_DECIMALS} decimals ({rounded.tolist()}): a "
                                            "compression's states are keyed by ρ; a sequence at constant ρ (a shear, "
                                            "a time series) is one run with source.sequence: {coordinate: strain, "
                                            "time, frame or timestep}")
    return ImportedSystem(rho_grid=rho_grid(grids[0], f"{key}.runs[0] (the states' packing fractions, in order)"),
                          **common)


def read_all_sources(config: Mapping[str, Any], systems: Mapping[str, Any]) -> None:
    """Read every run of every imported system in `systems` in full, as its import job will (`source_states`;
    parsing a config reads the particles files only): `forcenet-check-config` finds a bad pairs or contacts file
    before any job. Raises the first `forcenet.importers.SourceError`."""
    for name, spec in systems.items():
        if isinstance(spec, ImportedSystem):
            for realization in realization_indices(config, name):
                source_states(config["systems"][name], realization, where=f"systems.{name}.source")
