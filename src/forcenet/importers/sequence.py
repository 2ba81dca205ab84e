"""The coordinate along which an imported run's states are ordered (``source.sequence``), and the source's units
(``units:`` beside ``source:``).

An imported run is an ordered sequence of states. By default (``sequence`` absent, or ``coordinate: rho``) it is a
compression: its states are keyed by their packing fraction ρ, which must increase along the run, and they are
labelled by ρ in their file names (``rho0.842.nc``), as a DEM run's. Any other coordinate makes the run a sequence
whose ρ is one measured variable of each state, equal or not from state to state (a shear at constant volume, a
cyclic or a time series), the states labelled by their position (``state000.nc``, ``state001.nc``, …:
`forcenet.datasets.paths.state_labels`) and every per-state measure stored and drawn against the coordinate:

- ``frame``: the states' order, 0, 1, 2, … (a table run's file order, a dump's timesteps in their order);
- ``timestep``: the LAMMPS timestep of each state (a table run: its index, as ``frame``);
- ``time`` and ``strain``: ``values`` (one per state, in order), or for LAMMPS ``per_timestep`` times the timestep
  (the time step Δt for time; the strain rate times Δt for a shear at a constant rate).

``values`` may be given for any coordinate but ``rho``; it must increase strictly along the run, as the coordinate
always must. Standard library only: the workflow reads this when it parses the config.
"""
from __future__ import annotations

from typing import Any, Mapping, Sequence

from forcenet.datasets.schema import STATE_COORDINATE_LONG_NAMES as COORDINATE_LONG_NAMES  # noqa: F401
from forcenet.errors import ForcenetError

#: the coordinates ``source.sequence.coordinate`` may name; "rho" is a compression (the default)
COORDINATES = ("rho", "strain", "time", "frame", "timestep")
DEFAULT_COORDINATE = "rho"
#: the plain-text symbol of each coordinate (figure axes and CSV columns)
COORDINATE_SYMBOLS = {"rho": "rho", "strain": "strain", "time": "t", "frame": "frame", "timestep": "timestep"}
#: the units of an imported system: ``units: {length, force[, time]}``; absent, the source's own, unnamed
UNIT_KEYS = ("length", "force", "time")
#: what a variable's `units` attribute says when the config names no unit for it
UNNAMED_UNITS = {"length": "source length unit", "force": "source force unit", "time": "source time unit"}


class SequenceError(ForcenetError, ValueError):
    """A ``source.sequence`` that does not fit the run: one line naming the config key."""

    def __init__(self, key: str, problem: str):
        super().__init__(f"config key '{key}': {problem}")
        self.key, self.problem = key, problem


def coordinate(entry: Mapping[str, Any]) -> str:
    """The coordinate of an imported system's runs (`COORDINATES`): ``source.sequence.coordinate``, "rho" when
    absent."""
    return str((entry.get("source", {}).get("sequence") or {}).get("coordinate", DEFAULT_COORDINATE))


def is_sequence(entry: Mapping[str, Any]) -> bool:
    """Whether an imported system's runs are sequences keyed by a coordinate other than ρ."""
    return "source" in entry and coordinate(entry) != DEFAULT_COORDINATE


def unit(entry: Mapping[str, Any], quantity: str) -> str:
    """The unit of `quantity` (length, force or time) of an imported system: its ``units:`` entry, else the source's
    own unnamed unit (`UNNAMED_UNITS`)."""
    return str((entry.get("units") or {}).get(quantity, UNNAMED_UNITS[quantity]))


def coordinate_units(entry: Mapping[str, Any]) -> str:
    """The unit of a sequence's coordinate: ``units.time`` for time, "1" for the others."""
    return unit(entry, "time") if coordinate(entry) == "time" else "1"


def coordinate_values(entry: Mapping[str, Any], timesteps: Sequence[int], key: str) -> tuple[float, ...]:
    """The coordinate of each state of one run (`timesteps`: the LAMMPS timestep of each state, or its index in a
    table run), in the run's order. Raises `SequenceError` naming the key when the coordinate cannot be had or does
    not increase strictly along the run."""
    source = entry["source"]
    sequence = source.get("sequence") or {}
    name = coordinate(entry)
    where = f"{key}.sequence"
    if name not in COORDINATES:
        raise SequenceError(f"{where}.coordinate", f"{name!r} is not one of {', '.join(COORDINATES)}")
    if name == DEFAULT_COORDINATE:
        raise SequenceError(f"{where}.coordinate", "rho: the states are keyed by their packing fraction")
    n = len(timesteps)
    if "values" in sequence:
        values = [float(v) for v in sequence["values"]]
        if len(values) != n:
            raise SequenceError(f"{where}.values", f"{len(values)} values for {n} states: give one per state, in order")
    elif name == "frame" or (name == "timestep" and source["format"] == "table"):
        values = [float(k) for k in range(n)]
    elif name == "timestep":
        values = [float(t) for t in timesteps]
    elif source["format"] == "lammps" and "per_timestep" in sequence:
        values = [float(sequence["per_timestep"]) * float(t) for t in timesteps]
    else:
        accepted = ("values (one per state) or per_timestep (the coordinate per LAMMPS timestep)"
                    if source["format"] == "lammps" else "values (one per state, in order)")
        raise SequenceError(where, f"coordinate {name} needs {accepted}; coordinate frame takes the states' order")
    for k in range(1, n):
        if not values[k] > values[k - 1]:
            raise SequenceError(where, f"the {name} of state {k} ({values[k]:g}) does not exceed that of state {k - 1} "
                                       f"({values[k - 1]:g}): a run's states are ordered by its coordinate, which must "
                                       "increase along it")
    return tuple(values)
