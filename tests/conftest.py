"""Shared fixtures: repository paths and config loading."""
from __future__ import annotations

import copy
import os
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


def snakemake(workdir: Path, *args: str, config: Path = REPO / "config/smoke.yaml") -> subprocess.CompletedProcess:
    """Run Snakemake on `config` in `workdir` (targets go before --configfile, which takes several values), with the
    umask 022 a shared machine typically has."""
    command = [sys.executable, "-m", "snakemake", *args, "--snakefile", str(REPO / "Snakefile"), "--directory",
               str(workdir), "--cores", "2", "--configfile", str(config)]
    return subprocess.run(command, capture_output=True, text=True, timeout=900, preexec_fn=lambda: os.umask(0o022))


@pytest.fixture(scope="session")
def smoke_run(tmp_path_factory) -> Path:
    """A scratch directory holding a complete smoke build (results/), made once per test session."""
    workdir = tmp_path_factory.mktemp("smoke")
    result = snakemake(workdir)
    assert result.returncode == 0, result.stderr[-6000:]
    return workdir
