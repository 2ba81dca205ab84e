"""Small helpers the workflow calls: reading and checking the config at parse time (before any job), the resolved
config. Kept light (no numba or xarray imports) so that a dry run stays fast."""
from __future__ import annotations

import dataclasses
from pathlib import Path
from typing import Any, Mapping

import yaml

from forcenet.errors import ForcenetError
from forcenet.systems import ConfigError, config_sha256, validate_config


def write_resolved_config(config: Mapping[str, Any], path: str | Path) -> None:
    """Every system in reduced units (k_n, k_t, ρ grid …) plus the config hash, as YAML."""
    systems = validate_config(config)
    resolved = {
        "config_sha256": config_sha256(config),
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


class ConfigFileError(ForcenetError):
    """A config file that cannot be read as YAML: the message names the file and the line."""


def read_config_file(path: str | Path) -> dict:
    """The mapping in a YAML config file; `ConfigFileError` naming the file (and line) when it is missing, not YAML
    or not a mapping."""
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
    return config


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
    key = ".".join(str(part) for part in error.absolute_path) or "(top level)"
    message = error.message if len(error.message) <= 300 else error.message[:300] + " …"
    if len(errors) > 1:
        message += f" (and {len(errors) - 1} more schema problem{'s' if len(errors) > 2 else ''})"
    return ConfigError(key, message)


def checked_config(config: Mapping[str, Any], schema_path: str | Path) -> dict:
    """Validate a workflow config (JSON schema, then `forcenet.systems.validate_config` with the physical checks of
    `forcenet.checks`) and return its systems by name; raises the first `ConfigError`, whose one-line message names
    the key."""
    problem = schema_problem(config, schema_path)
    if problem is not None:
        raise problem
    return validate_config(config)


def check_config_main(argv: list[str] | None = None) -> int:
    """`forcenet-check-config FILE …`: every check the workflow runs on a config before any job, one line per file.

    Snakemake reads a --configfile before the workflow does and reports a YAML syntax error without the file or line;
    this names both (and runs the schema and physical checks as the workflow would)."""
    import sys

    paths = sys.argv[1:] if argv is None else argv
    if not paths:
        print("usage: forcenet-check-config CONFIG.yaml [...]", file=sys.stderr)
        return 2
    schema = Path(__file__).resolve().parents[2] / CONFIG_SCHEMA
    status = 0
    for path in paths:
        try:
            systems = checked_config(read_config_file(path), schema)
        except ForcenetError as error:
            print(f"{path}: invalid: {error}", file=sys.stderr)
            status = 1
        else:
            print(f"{path}: valid ({len(systems)} systems: {', '.join(systems)})")
    return status


if __name__ == "__main__":
    raise SystemExit(check_config_main())
