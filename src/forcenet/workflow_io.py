"""Small helpers the workflow scripts call (kept here so the scripts stay thin)."""
from __future__ import annotations

import dataclasses
from pathlib import Path
from typing import Any, Mapping

import yaml

from forcenet.systems import config_sha256, validate_config


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
