"""The system catalog: every simulated system described once, and the run configs that name the systems they run.

`config/systems.yaml` describes each system: its physics and protocol (force law, sizes, friction, damping, walls,
time step …), the papers' sizes as the defaults of its scale keys, its role in the studies, its label and colour.
A variant names its base with ``like:`` and gives only what it changes. A run config (`config/config.yaml`,
`paper.yaml`, `smoke.yaml`, `validation.yaml`, or a user's own) names the systems it runs under ``systems:`` and
may change only their scale keys (`SCALE_KEYS`: box, start, ρ grid, relaxation windows, speeds); an imported
system (``source:``) is described in the run config itself, since its source files are its description.

`expand_config` turns a run config into the config every other module reads: ``systems.<name>`` the full entry
(physics, protocol and scale, exactly the keys a simulation depends on: `forcenet.datasets.runs.simulation_params`),
``system_info.<name>`` its role, label and colour (and the system it is a variant of, ``like``), and
``systems_from`` the catalog files it came from. A config
with ``systems_from`` is full already (the config every output records): it is read as it is, so an output's
recorded config runs the same systems again.
"""
from __future__ import annotations

import copy
from pathlib import Path
from typing import Any, Mapping, Sequence

import yaml

from forcenet.errors import ForcenetError

#: the shipped catalog, relative to the repository root
DEFAULT_CATALOG = "config/systems.yaml"
#: the keys a run config may change: the size, the start, the grid, the relaxation windows and the speeds
SCALE_KEYS = ("box_length", "initial_state", "rho", "relaxation", "wall_speed", "initial_speed")
#: the relaxation's own scale keys (its `criterion` is the protocol, the catalog's)
RELAXATION_SCALE_KEYS = ("window_steps", "tolerance", "max_steps")
#: what a catalog entry says about a system besides its physics (kept out of the simulation fingerprint)
INFO_KEYS = ("role", "label", "colour")
#: the roles a system plays in the studies: P1's three systems (and their counterparts and controls, which share
#: their base's role) and P2's two
ROLES = ("p1_linear_2d", "p1_hertz_2d", "p1_hertz_3d", "p2_frictional", "p2_frictionless")


class ConfigFileError(ForcenetError):
    """A config file that cannot be read as YAML: the message names the file and the line."""


def duplicate_keys(node: yaml.Node, key: str = "") -> list[tuple[str, int, int]]:
    """(key, line, line of its first occurrence) of every key given twice in one mapping of a composed YAML
    document, keys written ``systems.2d_hertz.friction`` and lines counted from 1 (YAML itself keeps the last value
    silently)."""
    found = []
    if isinstance(node, yaml.MappingNode):
        first_lines: dict[str, int] = {}
        for key_node, value_node in node.value:
            name = str(key_node.value)
            path = f"{key}.{name}" if key else name
            line = key_node.start_mark.line + 1
            if name in first_lines:
                found.append((path, line, first_lines[name]))
            first_lines.setdefault(name, line)
            found += duplicate_keys(value_node, path)
    elif isinstance(node, yaml.SequenceNode):
        for index, item in enumerate(node.value):
            found += duplicate_keys(item, f"{key}[{index}]")
    return found


def read_config_file(path: str | Path) -> dict:
    """The mapping in a YAML config file; `ConfigFileError` naming the file (and line) when it is missing, not YAML,
    not a mapping, or gives one key twice in a mapping."""
    path = Path(path)
    try:
        text = path.read_text(encoding="utf-8")
    except OSError as error:
        raise ConfigFileError(f"config file {path}: cannot be read ({error.strerror or error})") from None
    try:
        config = yaml.safe_load(text)
    except yaml.YAMLError as error:
        mark = getattr(error, "problem_mark", None)
        where = f", line {mark.line + 1}, column {mark.column + 1}" if mark is not None else ""
        problem = getattr(error, "problem", None) or str(error).splitlines()[0]
        raise ConfigFileError(f"config file {path}{where}: not valid YAML ({problem})") from None
    if not isinstance(config, dict):
        raise ConfigFileError(f"config file {path}: must be a mapping of keys (seed, systems, …) at the top level")
    repeated = duplicate_keys(yaml.compose(text, Loader=yaml.SafeLoader))
    if repeated:
        key, line, first = repeated[0]
        raise ConfigFileError(f"config file {path}, line {line}: key '{key}' is given twice (first at line {first}); "
                              "YAML would keep the last value silently: remove one")
    return config


class CatalogError(ForcenetError, ValueError):
    """A catalog or run config that cannot be expanded; the message names the file and the key."""


def repository_root() -> Path:
    """The folder holding `config/`, `workflow/` and `src/` (forcenet is installed from it, editable)."""
    return Path(__file__).resolve().parents[2]


def recorded_catalog_path(path: str | Path) -> str:
    """A catalog file as an expanded config records it (``systems_from``): relative to the repository root when it
    lies inside it, so that the config, and the config sha256 every output records, are the same in every clone;
    absolute otherwise."""
    path = Path(path).resolve()
    try:
        return path.relative_to(repository_root()).as_posix()
    except ValueError:
        return str(path)


def catalog_files(config: Mapping[str, Any]) -> list[Path]:
    """The catalog files an expanded config's systems come from (``systems_from``), as paths to read."""
    return [Path(p) if Path(p).is_absolute() else repository_root() / p for p in config.get("systems_from", [])]


def read_catalog(paths: Sequence[str | Path]) -> tuple[dict[str, Any], dict[str, dict[str, Any]]]:
    """(material, {name: raw entry}) of the catalog files; a name described twice is refused naming both files."""
    material: dict[str, Any] | None = None
    entries: dict[str, dict[str, Any]] = {}
    origin: dict[str, Path] = {}
    for path in map(Path, paths):
        document = read_config_file(path)
        unknown = sorted(set(document) - {"material", "systems"})
        if unknown:
            raise CatalogError(f"catalog {path}: key '{unknown[0]}' is not a catalog key (material, systems)")
        if "material" in document:
            if material is not None and document["material"] != material:
                raise CatalogError(f"catalog {path}: key 'material' differs from the one of another catalog file")
            material = document["material"]
        for name, entry in (document.get("systems") or {}).items():
            if name in entries:
                raise CatalogError(f"catalog {path}: system '{name}' is described in {origin[name]} already")
            if not isinstance(entry, Mapping):
                raise CatalogError(f"catalog {path}: key 'systems.{name}' must be a mapping of its settings")
            entries[name], origin[name] = dict(entry), path
    return material or {}, entries


def resolve_entry(name: str, entries: Mapping[str, Mapping[str, Any]], catalog: str = "the catalog") -> dict:
    """The full catalog entry of `name` (its ``like:`` chain applied, base first), info keys included."""
    chain, current = [], name
    while True:
        if current not in entries:
            known = ", ".join(sorted(entries))
            where = f"system '{name}'" if current == name else f"'like: {current}' of system '{chain[-1]}'"
            raise CatalogError(f"{catalog}: {where} is not described there (described: {known})")
        if current in chain:
            raise CatalogError(f"{catalog}: systems.{name}: 'like:' goes round in a circle ({' → '.join(chain)})")
        chain.append(current)
        base = entries[current].get("like")
        if base is None:
            break
        current = base
    resolved: dict[str, Any] = {}
    for link in reversed(chain):
        for key, value in entries[link].items():
            if key == "like":
                continue
            if value is None:
                resolved.pop(key, None)  # a variant removes a key of its base
            else:
                resolved[key] = copy.deepcopy(value)
    return resolved


def _apply_scale(name: str, entry: dict, overrides: Mapping[str, Any], source: str) -> dict:
    """`entry` with the run config's scale keys applied; any other key is refused naming it."""
    for key, value in overrides.items():
        where = f"{source}: config key 'systems.{name}.{key}"
        if key not in SCALE_KEYS:
            raise CatalogError(f"{where}': a run config changes only the scale keys {list(SCALE_KEYS)}; physics, "
                               f"protocol, role, label and colour are the catalog's: describe another system there "
                               f"(a variant: 'like: {name}' and the keys it changes)")
        if value is None:
            entry.pop(key, None)
        elif key == "relaxation" and isinstance(value, Mapping):
            other = sorted(set(value) - set(RELAXATION_SCALE_KEYS))
            if other:
                raise CatalogError(f"{where}.{other[0]}': the relaxation's scale keys are {list(RELAXATION_SCALE_KEYS)}"
                                   f"; its criterion is the catalog's")
            entry[key] = {**entry.get(key, {}), **copy.deepcopy(dict(value))}
        else:
            entry[key] = copy.deepcopy(value)
    return entry


def expand_config(run_config: Mapping[str, Any], *, source: str = "the config",
                  root: str | Path | None = None) -> dict[str, Any]:
    """The full config of a run config (see the module docstring). `source` names the run config in messages;
    `root` is where relative catalog paths start (default: the repository root for the shipped catalog, the working
    directory for those a config names under ``catalog:``)."""
    if "systems_from" in run_config:  # already full: the config an output records, read back to run it again
        return copy.deepcopy(dict(run_config))
    named = run_config.get("catalog")
    if named is None:
        paths = [(Path(root) if root is not None else repository_root()) / DEFAULT_CATALOG]
    else:
        named = [named] if isinstance(named, str) else list(named)
        paths = [Path(p) if Path(p).is_absolute() or root is None else Path(root) / p for p in named]
    material, entries = read_catalog(paths)
    catalog = " + ".join(str(p) for p in paths)
    config = {key: copy.deepcopy(value) for key, value in run_config.items() if key != "catalog"}
    systems = run_config.get("systems")
    if isinstance(systems, list) and all(isinstance(name, str) for name in systems):
        systems = dict.fromkeys(systems)  # a list of names: each system at the catalog's sizes
    if not isinstance(systems, Mapping):
        raise CatalogError(f"{source}: config key 'systems' must list the systems it runs, or map each to its scale "
                           "keys (or to nothing)")
    if "material" in run_config and any(not (o or {}).get("source") for o in systems.values()):
        raise CatalogError(f"{source}: config key 'material': the particles' material is the catalog's ({catalog}): "
                           "remove it here, or describe systems of another material in a catalog of your own")
    config["systems"], config["system_info"] = {}, {}
    for name, overrides in systems.items():
        overrides = overrides or {}
        if not isinstance(overrides, Mapping):
            raise CatalogError(f"{source}: config key 'systems.{name}' must be a mapping of scale keys (or empty)")
        if "source" in overrides:  # an imported system: its sources describe it
            config["systems"][name] = copy.deepcopy(dict(overrides))
            continue
        resolved = resolve_entry(name, entries, catalog)
        info = {key: resolved.pop(key) for key in INFO_KEYS if key in resolved}
        base = entries[name].get("like")
        missing = [key for key in INFO_KEYS if key not in info]
        if missing:
            raise CatalogError(f"{catalog}: system '{name}' has no {missing[0]} (every system names its role, label "
                               "and colour)")
        if info["role"] not in ROLES:
            raise CatalogError(f"{catalog}: systems.{name}.role is '{info['role']}', not one of {list(ROLES)}")
        config["systems"][name] = _apply_scale(name, resolved, overrides, source)
        config["system_info"][name] = {**info, "like": base} if base else info
    if config["system_info"] and "material" not in config and material:
        config["material"] = copy.deepcopy(material)
    config["systems_from"] = [recorded_catalog_path(p) for p in paths]
    return config


def load_run_config(path: str | Path, *, root: str | Path | None = None) -> dict[str, Any]:
    """Read a run config file and expand it (`expand_config`)."""
    return expand_config(read_config_file(path), source=str(path), root=root)


def expanded(config: dict[str, Any], *, source: str = "the config") -> dict[str, Any]:
    """`config` expanded in place (Snakemake's own `config` object, which the rules read) unless it already is."""
    if "systems_from" not in config:
        full = expand_config(config, source=source)
        config.clear()
        config.update(full)
    return config


def system_role(config: Mapping[str, Any], name: str) -> str | None:
    """The catalog role of a system of an expanded config (None for an imported system: it plays its study's
    role by the study that names it)."""
    return config.get("system_info", {}).get(name, {}).get("role")


def systems_with_role(config: Mapping[str, Any], names: Sequence[str], role: str) -> list[str]:
    """The systems among `names` whose catalog role is `role`, in the order given."""
    return [name for name in names if system_role(config, name) == role]


def p2_roles(config: Mapping[str, Any], names: Sequence[str]) -> tuple[str | None, str | None]:
    """(frictional, frictionless) among P2's systems `names`: by their catalog roles; an imported system, which has
    none, takes the first role left in the order of `names`."""
    chosen = {role: next(iter(systems_with_role(config, names, role)), None)
              for role in ("p2_frictional", "p2_frictionless")}
    unplaced = [name for name in names if system_role(config, name) is None]
    for role in chosen:
        if chosen[role] is None and unplaced:
            chosen[role] = unplaced.pop(0)
    return chosen["p2_frictional"], chosen["p2_frictionless"]

