"""Shared fixtures: repository paths and config loading."""
from __future__ import annotations

import copy
from pathlib import Path

import pytest
import yaml

REPO = Path(__file__).resolve().parents[1]
CONFIG_DIR = REPO / "config"


def load_config(name: str = "config.yaml") -> dict:
    return yaml.safe_load((CONFIG_DIR / name).read_text())


@pytest.fixture
def default_config() -> dict:
    return copy.deepcopy(load_config())
