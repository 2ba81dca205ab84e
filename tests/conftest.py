"""Shared fixtures: repository paths and config loading."""
from __future__ import annotations

import copy
import subprocess
import sys
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


def snakemake(workdir: Path, *args: str) -> subprocess.CompletedProcess:
    """Run the workflow on config/smoke.yaml in `workdir` (2 cores)."""
    command = [sys.executable, "-m", "snakemake", "--snakefile", str(REPO / "Snakefile"), "--directory",
               str(workdir), "--configfile", str(REPO / "config/smoke.yaml"), "--cores", "2", *args]
    return subprocess.run(command, capture_output=True, text=True, timeout=900)


@pytest.fixture(scope="session")
def smoke_run(tmp_path_factory) -> Path:
    """A scratch directory holding a complete smoke build (results/), made once per test session."""
    workdir = tmp_path_factory.mktemp("smoke")
    result = snakemake(workdir)
    assert result.returncode == 0, result.stderr[-6000:]
    return workdir
