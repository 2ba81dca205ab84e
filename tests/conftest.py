"""Shared fixtures: repository paths and config loading."""
from __future__ import annotations

import atexit
import copy
import fcntl
import os
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

import pytest
import yaml

REPO = Path(__file__).resolve().parents[1]
CONFIG_DIR = REPO / "config"


SCONTROL_STUB_PREFIX = "forcenet-tests-no-scontrol-"


def _without_slurm_controller_query() -> str:
    """Put an `scontrol` that fails at once first on this process's PATH (inherited by every Snakemake it starts);
    the folder holding it.

    Snakemake's Slurm executor plugin asks `scontrol show config` each time Snakemake starts, whichever executor runs
    (snakemake-executor-plugin-slurm 2.x, for a help text; 10 s timeout). Where Slurm is installed and no controller
    answers, as after tests/test_slurm.py stopped the cluster it started (it installs Slurm on a fresh CI machine),
    every later Snakemake process of the suite waited those 10 s. Where no scontrol exists the plugin gets the same
    answer, none. tests/test_slurm.py runs with `REAL_PATH`."""
    folder = tempfile.mkdtemp(prefix=SCONTROL_STUB_PREFIX)
    stub = Path(folder) / "scontrol"
    stub.write_text("#!/bin/sh\necho 'scontrol is off for the tests that do not use Slurm' >&2\nexit 1\n")
    stub.chmod(0o755)
    atexit.register(shutil.rmtree, folder, ignore_errors=True)
    os.environ["PATH"] = folder + os.pathsep + os.environ.get("PATH", "")
    return folder


def _path_before_the_stub() -> str:
    """The PATH before any stub. pytest-xdist's workers inherit the controller's PATH, stub included, and import
    this file again, so a worker takes the PATH its controller recorded; the controller (or a run without xdist)
    records its own, whatever an earlier run left in the environment. (A stub on tests/test_slurm.py's PATH makes
    the Slurm plugin find no MinJobAge and poll an accounting database the test cluster does not have: its jobs
    never finish.)"""
    if "PYTEST_XDIST_WORKER" in os.environ and REAL_PATH_VARIABLE in os.environ:
        return os.environ[REAL_PATH_VARIABLE]
    os.environ[REAL_PATH_VARIABLE] = os.environ.get("PATH", "")
    return os.environ[REAL_PATH_VARIABLE]


REAL_PATH_VARIABLE = "FORCENET_TESTS_REAL_PATH"
REAL_PATH = _path_before_the_stub()
SCONTROL_STUB_DIR = _without_slurm_controller_query()


def load_config(name: str = "config.yaml") -> dict:
    """A shipped run config expanded with the system catalog (`forcenet.catalog`), as the workflow reads it."""
    from forcenet.catalog import load_run_config

    return load_run_config(CONFIG_DIR / name)


@pytest.fixture
def default_config() -> dict:
    return copy.deepcopy(load_config())


def snakemake(workdir: Path, *args: str, config: Path = REPO / "config/smoke.yaml") -> subprocess.CompletedProcess:
    """Run Snakemake on `config` in `workdir` (targets go before --configfile, which takes several values), with the
    umask 022 a shared machine typically has."""
    command = [sys.executable, "-m", "snakemake", *args, "--snakefile", str(REPO / "Snakefile"), "--directory",
               str(workdir), "--cores", "2", "--configfile", str(config)]
    return subprocess.run(command, capture_output=True, text=True, timeout=900, preexec_fn=lambda: os.umask(0o022))


def _build_smoke(workdir: Path) -> Path:
    result = snakemake(workdir)
    assert result.returncode == 0, result.stderr[-6000:]
    return workdir


@pytest.fixture(scope="session")
def smoke_run(tmp_path_factory) -> Path:
    """A scratch directory holding a complete smoke build (results/), made once per test session.

    Under pytest-xdist each worker is its own session; the workers of one run share the folder above their own
    base temporary folders (unique to the run), so the first worker to ask builds the smoke there under a lock and
    the others wait for it and read it, instead of each building its own."""
    if "PYTEST_XDIST_WORKER" not in os.environ:
        return _build_smoke(tmp_path_factory.mktemp("smoke"))
    shared = tmp_path_factory.getbasetemp().parent
    workdir, built = shared / "smoke", shared / "smoke.built"
    with open(shared / "smoke.lock", "w") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)  # released when the file closes
        if not built.exists():
            if workdir.exists():  # a build that failed in another worker: start again, not on top of it
                shutil.rmtree(workdir)
            workdir.mkdir()
            _build_smoke(workdir)
            built.touch()
    return workdir


# The two modules that build a whole pipeline before their first test (the smoke build, about two minutes; the
# import example, about one): collected first, so that pytest-xdist's per-file distribution (`--dist loadfile` in
# pyproject.toml) starts each at once on a worker of its own instead of leaving the longest file to run last alone.
_BUILDING_MODULES = ("test_workflow.py", "test_workflow_import.py")


# Test tiers. Plain `pytest` runs the unit tier: every test that needs nothing beyond the package (no pipeline
# build, no LAMMPS, no Slurm). `pytest --all` runs every tier, as the README's test command and .ci/run do. A test's
# tier follows from what it uses: a fixture below marks every test that needs it (directly or through another
# fixture), so a test cannot slip into the unit tier by forgetting a marker; a module or test may also carry a tier's
# marker itself (pyproject.toml lists them).
#: fixture → the tier of the tests that use it
TIER_OF_FIXTURE = {"smoke_run": "workflow", "example_run": "workflow", "lmp": "lammps", "slurm_cluster": "slurm"}
#: the tiers beyond the unit tier, run only with --all
OUTER_TIERS = ("workflow", "lammps", "slurm")


def pytest_addoption(parser):
    parser.addoption("--all", action="store_true", dest="all_tiers",
                     help="run every tier: unit, workflow (Snakemake builds), lammps, slurm (plain pytest: the unit "
                          "tier only)")


def tiers_of(item) -> set[str]:
    """The outer tiers `item` belongs to: its markers' and those of the fixtures it uses."""
    tiers = {marker.name for marker in item.iter_markers() if marker.name in OUTER_TIERS}
    return tiers | {TIER_OF_FIXTURE[name] for name in getattr(item, "fixturenames", ()) if name in TIER_OF_FIXTURE}


def pytest_collection_modifyitems(config, items):
    """Mark each test with the tiers of the fixtures it uses; without --all, deselect every test of an outer tier.
    Then a stable reorder: the tests of `_BUILDING_MODULES` first, in that order; every other test keeps its place."""
    deselected = []
    for item in list(items):
        tiers = tiers_of(item)
        for tier in tiers:
            item.add_marker(tier)
        if tiers and not config.getoption("all_tiers"):
            deselected.append(item)
    if deselected:
        config.hook.pytest_deselected(items=deselected)
        left_out = set(deselected)
        items[:] = [item for item in items if item not in left_out]

    def rank(item) -> int:
        name = item.path.name
        return _BUILDING_MODULES.index(name) if name in _BUILDING_MODULES else len(_BUILDING_MODULES)
    items.sort(key=rank)
