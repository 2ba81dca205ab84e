"""Importers: states from other codes and from experiments → contract snapshots (`forcenet.datasets.snapshot`).

A config system with a ``source:`` entry (instead of the DEM settings) names a format and its files; its snapshots
are written by `import_run` (rule ``import_{system}``) and then analysed, aggregated and drawn like any other. Two
formats (`FORMATS`):

- ``table`` (`forcenet.importers.table`): a plain CSV pair per state, particles (id, x, y[, z], radius) and contacts
  (i, j, normal and tangential force as vectors or magnitudes), for experiments and codes without a dump reader;
- ``lammps`` (`forcenet.importers.lammps`): LAMMPS text dumps, a ``dump custom`` of atoms and a ``dump local`` of
  pair forces, one or many timesteps.

A malformed source stops with `SourceError`: one line naming the file and the line or column, and nothing is
written. This package reads with the standard library and numpy only. When the workflow parses its config it needs
an imported system's states: `imported_system` (`forcenet.importers.system`) builds its
`forcenet.systems.ImportedSystem` from the config entry (a compression's declared ρ, a sequence's coordinate), for
which `forcenet.importers.scan` checks the source files' paths and sizes and keeps a record of each, never reading
their contents; the import job reads and checks every file in full (`source_states`, `checked_run`).
"""
from __future__ import annotations

from forcenet._lazy import lazy_exports

#: the formats a config's ``source.format`` may name
FORMATS = ("table", "lammps")

#: public name → the submodule that defines it, imported on first use (PEP 562): the configuration builds an imported
#: system through `system` without loading `run`, which writes snapshots through `forcenet.datasets`
_EXPORTS = {"SourceError": "common", "SourceState": "common", "file_sha256": "common", "import_run": "run",
            "run_files": "sources", "source_states": "sources",
            "imported_system": "system", "imported_system_from_config": "system", "read_all_sources": "system"}

__all__ = ["FORMATS", *sorted(_EXPORTS)]


__getattr__, __dir__ = lazy_exports(__name__, _EXPORTS, globals())
