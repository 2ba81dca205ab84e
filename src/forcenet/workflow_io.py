"""Small helpers the workflow calls: reading and checking the config at parse time (before any job), the resolved
config. Kept light (no numba or xarray imports) so that a dry run stays fast."""
from __future__ import annotations

import dataclasses
import os
import sys
from pathlib import Path
from typing import Any, Mapping

import yaml

from forcenet.catalog import ConfigFileError, expanded, read_config_file  # noqa: F401 (the readers' home)
from forcenet.errors import ForcenetError
from forcenet.datasets.runs import config_sha256
from forcenet.systems import ConfigError, non_finite_number


def write_resolved_config(config: Mapping[str, Any], path: str | Path, results_dir: str | Path) -> None:
    """Every system in reduced units (k_n, k_t, ρ grid …) plus the config hash and the absolute folder that received
    the outputs (`results_dir`, from `resolve_results_dir`), as YAML."""
    from forcenet.checks import validate_config

    systems = validate_config(config)
    resolved = {
        "config_sha256": config_sha256(config),
        "results_dir": str(results_dir),
        "units": {"length": "d_ave", "mass": "m_mean", "time": "tau_c"},
        "systems": {name: _plain(dataclasses.asdict(spec)) for name, spec in systems.items()},
    }
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(yaml.safe_dump(resolved, sort_keys=False))


def _plain(value: Any) -> Any:
    if isinstance(value, dict):
        return {k: _plain(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_plain(v) for v in value]
    return value


#: the config `snakemake` reads when no --configfile is given (relative to the repository root)
DEFAULT_CONFIG = "config/config.yaml"
#: the JSON schema of every config (relative to the repository root)
CONFIG_SCHEMA = "workflow/schemas/config.schema.yaml"


#: where outputs go when a config sets no results_dir (relative to the working directory)
DEFAULT_RESULTS_DIR = "results"


def resolve_results_dir(value: str | None, working_dir: str | Path) -> tuple[str, Path]:
    """The config's `results_dir` resolved once: (the folder as the rules write it, its absolute path).

    A relative path stays relative (so that targets such as ``results/sim/…`` on the command line match the rules'
    outputs), with ``.`` and ``..`` removed; it must stay inside `working_dir` (the repository root, or Snakemake's
    ``--directory``): ``results/../../escape`` is refused, an absolute path says where outside. An absolute path
    (a cluster's scratch space) is taken as given, normalised; ``~`` is expanded. Environment variables are not
    expanded, and braces would be read as Snakemake wildcards: both are refused. Raises `ConfigError` naming
    ``results_dir``."""
    raw = DEFAULT_RESULTS_DIR if value is None else value
    if not raw.strip():
        raise ConfigError("results_dir", f"is empty: name the folder that receives the outputs (default: {DEFAULT_RESULTS_DIR})")
    for character, why in (("$", "environment variables are not expanded"), ("{", "braces are Snakemake wildcards"),
                           ("}", "braces are Snakemake wildcards"),
                           ("\n", "a newline cannot be part of a folder name")):
        if character in raw:
            raise ConfigError("results_dir", f"{raw!r} contains {character!r} ({why}): write the folder's path itself")
    expanded = os.path.expanduser(raw)
    normalised = os.path.normpath(expanded)
    working_dir = Path(os.path.abspath(working_dir))
    if os.path.isabs(normalised):
        return normalised, Path(normalised)
    if normalised == "." or normalised == ".." or normalised.startswith(".." + os.sep):
        where = os.path.normpath(working_dir / normalised)
        raise ConfigError("results_dir", f"{raw!r} resolves to {where}, which is not a folder inside the working "
                                         f"directory {working_dir}: give a relative path below it, or an absolute "
                                         "path to write elsewhere")
    return normalised, working_dir / normalised


def _forbidden_key(error, schema: Mapping[str, Any], config: Mapping[str, Any]) -> str | None:
    """The key a schema error is about when the schema forbids that key here (``key: false``, e.g. a table's
    setting under ``format: lammps``): jsonschema reports it at the enclosing entry, without the key; else None."""
    if error.validator is not None or not error.schema_path or error.schema_path[-1] != "properties":
        return None
    properties: Any = schema
    for part in error.schema_path:  # the path does not show the (local) $refs it went through: follow them
        while isinstance(properties, dict) and part not in properties and "$ref" in properties:
            target: Any = schema
            for name in properties["$ref"].lstrip("#/").split("/"):
                target = target[name]
            properties = target
        properties = properties[part]
    entry: Any = config
    for part in error.absolute_path:
        entry = entry[part]
    return next((name for name, rule in properties.items() if rule is False and name in entry), None)


def schema_problem(config: Mapping[str, Any], schema_path: str | Path) -> ConfigError | None:
    """The most relevant way `config` breaks the JSON schema (jsonschema's best match), as a `ConfigError` naming the
    key, with the number of further problems; None when it validates."""
    import jsonschema
    from jsonschema.exceptions import best_match

    schema = yaml.safe_load(Path(schema_path).read_text(encoding="utf-8"))
    errors = list(jsonschema.Draft202012Validator(schema).iter_errors(config))
    if not errors:
        return None
    error = best_match(errors)
    path, message = list(error.absolute_path), error.message
    forbidden = _forbidden_key(error, schema, config)
    if forbidden:
        path, message = path + [forbidden], "not allowed in this entry (its other settings exclude it)"
    key = ".".join(str(part) for part in path) or "(top level)"
    message = message if len(message) <= 300 else message[:300] + " …"
    if len(errors) > 1:
        message += f" (and {len(errors) - 1} more schema problem{'s' if len(errors) > 2 else ''})"
    return ConfigError(key, message)


def checked_config(config: Mapping[str, Any], schema_path: str | Path) -> dict:
    """Expand a run config with its catalog in place (`forcenet.catalog.expanded`), validate it (JSON schema, then
    `forcenet.checks.validate_config` with the physical checks of each system) and return its systems by
    name; raises the first `ConfigError` (or `CatalogError`), whose one-line message names the key. A NaN or infinity is named before the schema runs (the schema's bounds cannot see NaN)."""
    from forcenet.checks import validate_config

    expanded(config)  # a run config names catalog systems (forcenet.catalog): in place, as the rules read it
    problem = non_finite_number(config) or schema_problem(config, schema_path)
    if problem is not None:
        raise problem
    systems = validate_config(config)
    problem = table_rho_problem(config, systems)
    if problem is not None:
        raise problem
    for note in config_notes(systems):
        print(f"forcenet: note: {note}", file=sys.stderr)
    return systems


def config_notes(systems: Mapping[str, Any]) -> list[str]:
    """The lines a valid config should hear before it runs, each naming its keys: one for the ρ grids that end past
    random close packing (`forcenet.checks.past_random_close_packing`; the papers' grids all do, so one line says it
    for all of them)."""
    from forcenet.checks import MAX_OVERLAP_FRACTION, RANDOM_CLOSE_PACKING, past_random_close_packing
    from forcenet.systems import SystemSpec

    past = [f"systems.{name}.rho ({spec.rho_grid[-1]:g})" for name, spec in systems.items()
            if isinstance(spec, SystemSpec) and past_random_close_packing(spec)]
    if not past:
        return []
    named = ", ".join(past[:3]) + (f" and {len(past) - 3} more" if len(past) > 3 else "")
    return [f"{named} end past random close packing (disks ≈ {RANDOM_CLOSE_PACKING[2]}, spheres ≈ "
            f"{RANDOM_CLOSE_PACKING[3]}): expect the largest overlaps above P1's 10 % of a diameter there, and a "
            f"3D grid near the densest packing to stop at the engine's {MAX_OVERLAP_FRACTION:.0%} blow-up limit"]


def table_rho_problem(config: Mapping[str, Any], systems: Mapping[str, Any]) -> ConfigError | None:
    """``studies.p2.table_rho`` against each P2 system's grid, as a `ConfigError` naming the key (None when it fits):
    the jammed rule (the default) takes its states a, b, c among the samples at or above table_rho, so at least three
    must be; the literal rule takes the three nearest, so table_rho must lie within the grid. Issue 57: a table_rho
    above the grid passed every check and failed at job time naming no key."""
    from forcenet.systems import TABLE_STATES

    p2 = config["studies"].get("p2", {})
    table_rho = float(p2.get("table_rho", 0.79))
    rule = p2.get("table_states", "jammed")
    for name in p2.get("systems", []):
        if getattr(systems[name], "is_sequence", False):  # no states a, b, c of a sequence (workflow/rules/p2.smk)
            continue
        grid = systems[name].rho_grid
        if rule == "jammed" and sum(rho >= table_rho - 1e-9 for rho in grid) < TABLE_STATES:
            return ConfigError("studies.p2.table_rho", f"is {table_rho:g}, but system '{name}' has "
                                                       f"{sum(rho >= table_rho - 1e-9 for rho in grid)} grid point(s) "
                                                       f"at or above it (its grid ends at {grid[-1]}), and the jammed "
                                                       f"states a, b, c need {TABLE_STATES}: lower table_rho or extend "
                                                       "the grid")
        if rule == "literal" and not grid[0] <= table_rho <= grid[-1]:
            return ConfigError("studies.p2.table_rho", f"is {table_rho:g}, outside system '{name}''s grid "
                                                       f"({grid[0]} … {grid[-1]}): the literal states a, b, c are the "
                                                       "three nearest it")
    return None


CHECK_CONFIG_HELP = """usage: forcenet-check-config CONFIG.yaml [...]

Every check the workflow runs on a config before any job (YAML, keys given twice, schema, physical checks,
results_dir), one line per file. Unlike the workflow, which checks only the paths and sizes of an imported system's
source files when it parses a config, this also reads every source file in full and checks it against the states
the config declares, as the import jobs will: its time and memory grow with the files. An imported compression that
declares no rho gets the values its files give."""


def check_config_main(argv: list[str] | None = None) -> int:
    """`forcenet-check-config FILE …`: every check the workflow runs on a config before any job, one line per file,
    and a full read of every source file of its imported systems, which the workflow itself never reads.

    Snakemake reads a --configfile before the workflow does and reports a YAML syntax error without the file or line,
    and a key given twice not at all; this names both (and runs the schema and physical checks as the workflow
    would, and resolves `results_dir` against the current directory, as a run from it would). Unlike the workflow,
    which checks only the source files' paths and sizes when it parses a config, it then reads every source file in
    full and checks it against the states the config declares, as the import jobs will
    (`forcenet.importers.system.read_all_sources`), so a bad source is named before any job; its time and memory grow
    with the files. An imported compression that declares no ``rho`` gets the values its files give."""
    from forcenet.importers.system import UndeclaredStates, measured_labels, read_all_sources

    paths = sys.argv[1:] if argv is None else argv
    if not paths or paths[0] in ("-h", "--help"):
        print(CHECK_CONFIG_HELP, file=sys.stderr if not paths else sys.stdout)
        return 2 if not paths else 0
    schema = Path(__file__).resolve().parents[2] / CONFIG_SCHEMA
    status = 0
    for path in paths:
        try:
            config = read_config_file(path)
            systems = checked_config(config, schema)
            _, results = resolve_results_dir(config.get("results_dir"), Path.cwd())
            read_all_sources(config, systems)
        except UndeclaredStates as error:
            print(f"{path}: invalid: {error}", file=sys.stderr)
            try:
                labels = measured_labels(error.system, config["systems"][error.system])
            except ForcenetError as unread:
                print(f"{path}: {unread}", file=sys.stderr)
            else:
                print(f"{path}: its files give systems.{error.system}.rho: [{', '.join(labels)}]", file=sys.stderr)
            status = 1
        except ForcenetError as error:
            print(f"{path}: invalid: {error}", file=sys.stderr)
            status = 1
        else:
            print(f"{path}: valid ({len(systems)} systems: {', '.join(systems)}; results_dir {results})")
    return status


if __name__ == "__main__":
    raise SystemExit(check_config_main())
