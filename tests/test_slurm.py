"""config/smoke.yaml through the Slurm profile on a real one-node cluster gives the same data as a local run.

Needs a Slurm cluster whose configuration is at /etc/slurm/slurm.conf (the executor plugin unsets SLURM_CONF).
If `scripts/slurm_cluster.sh status` says this machine's node takes jobs, that cluster is used as it is. Otherwise, with
FORCENET_SLURM_TESTS=1 or CI=true, root and apt-get (or Slurm already installed), the test brings one up with
scripts/slurm_cluster.sh and stops what it started afterwards; anywhere else it is skipped, with the reason.

Target: every snapshot, every analysis and the aggregated datasets of the smoke config (5 simulations, the
snapshot analyses in grouped cluster jobs, 5 aggregations). Figures and tables are left out: they read only
the aggregated datasets compared here, and twenty more one-figure cluster jobs would triple the runtime.
"""
from __future__ import annotations

import os
import shutil
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest
import xarray as xr
import yaml

from conftest import REAL_PATH, REPO, SCONTROL_STUB_PREFIX, load_config
from forcenet.datasets import open_dataset, paths
from forcenet.checks import validate_config

pytestmark = [pytest.mark.slurm, pytest.mark.workflow, pytest.mark.slow]

SCRIPT = REPO / "scripts/slurm_cluster.sh"
PROFILE = REPO / "workflow/profiles/slurm"
SMOKE = REPO / "config/smoke.yaml"
# Global attributes that may differ between two runs of the same code: the commit (+dirty) of a tree being edited.
VOLATILE_ATTRS = {"git_commit"}
# the real Slurm commands: conftest puts an scontrol that fails at once first on the suite's PATH
SLURM_ENV = {**os.environ, "PATH": REAL_PATH}


def test_slurm_runs_see_the_real_scontrol():
    """No folder of the suite's scontrol stub (conftest) on the Slurm runs' PATH, in one process or under xdist.

    With the stub, the executor plugin reads no MinJobAge, polls `sacct` instead of `squeue`, and the one-node
    cluster (no accounting database) never reports a job finished: the run waits until its timeout."""
    def is_stub(folder: str) -> bool:
        return Path(folder).name.startswith(SCONTROL_STUB_PREFIX)

    assert [folder for folder in SLURM_ENV["PATH"].split(os.pathsep) if is_stub(folder)] == []
    # and it is this run's PATH without the stubs, not one an earlier run left in the environment
    assert SLURM_ENV["PATH"].split(os.pathsep) == [f for f in os.environ["PATH"].split(os.pathsep) if not is_stub(f)]


def _node_takes_jobs() -> bool:
    """`scripts/slurm_cluster.sh status` exits 0 when this node takes jobs (the one definition of that)."""
    try:
        return subprocess.run([str(SCRIPT), "status"], capture_output=True, timeout=60, env=SLURM_ENV).returncode == 0
    except (OSError, subprocess.SubprocessError):
        return False


def _why_cluster_cannot_start() -> str | None:
    """None if scripts/slurm_cluster.sh can be tried here, else the reason it cannot."""
    if not (os.environ.get("FORCENET_SLURM_TESTS") == "1" or os.environ.get("CI", "").lower() == "true"):
        return ("no Slurm cluster is up; set FORCENET_SLURM_TESTS=1 (root, Debian/Ubuntu) to let the test start one "
                "with scripts/slurm_cluster.sh, or run `scripts/slurm_cluster.sh up` first")
    if sys.platform != "linux":
        return f"a local Slurm cluster needs Linux, not {sys.platform}"
    if os.geteuid() != 0:
        return "bringing up Slurm needs root (scripts/slurm_cluster.sh installs packages and starts daemons)"
    installed = all(shutil.which(p) for p in ("munged", "slurmctld", "slurmd", "sinfo", "sbatch", "squeue"))
    if not installed and shutil.which("apt-get") is None:
        return "Slurm is not installed and there is no apt-get to install slurm-wlm and munge"
    return None


@pytest.fixture(scope="module")
def slurm_cluster():
    if _node_takes_jobs():
        yield "existing"
        return
    reason = _why_cluster_cannot_start()
    if reason:
        pytest.skip(reason)
    up = subprocess.run(["bash", str(SCRIPT), "up"], capture_output=True, text=True, timeout=900, env=SLURM_ENV)
    if up.returncode != 0:
        subprocess.run(["bash", str(SCRIPT), "down"], capture_output=True, text=True, timeout=120, env=SLURM_ENV)
        pytest.fail(f"scripts/slurm_cluster.sh up failed:\n{up.stdout[-3000:]}\n{up.stderr[-3000:]}")
    try:
        yield "started"
    finally:
        subprocess.run(["bash", str(SCRIPT), "down"], capture_output=True, text=True, timeout=120, env=SLURM_ENV)


def _targets() -> list[str]:
    config = load_config("smoke.yaml")
    return [path("results", system) for system in config["systems"] for path in (paths.network_measures, paths.diagrams)]


def _snakemake(workdir: Path, *args: str) -> list[str]:
    return [sys.executable, "-m", "snakemake", "--snakefile", str(REPO / "Snakefile"), "--directory", str(workdir),
            "--configfile", str(SMOKE), *args, *_targets()]


@pytest.fixture(scope="module")
def runs(slurm_cluster, tmp_path_factory):
    """The same targets built locally and through Slurm (the local run goes alongside the Slurm one)."""
    local_dir, slurm_dir = tmp_path_factory.mktemp("local"), tmp_path_factory.mktemp("slurm")
    started = time.perf_counter()
    local = subprocess.Popen(_snakemake(local_dir, "--cores", "1"), stdout=subprocess.PIPE,
                             stderr=subprocess.STDOUT, text=True)
    slurm = subprocess.run(_snakemake(slurm_dir, "--workflow-profile", str(PROFILE), "--jobs", "4",
                                      "--slurm-keep-successful-logs"),
                           capture_output=True, text=True, timeout=1500, env=SLURM_ENV)
    local_output, _ = local.communicate(timeout=1500)
    print(f"local + Slurm runs: {time.perf_counter() - started:.0f} s")
    if slurm.returncode != 0:
        logs = "\n".join(p.read_text()[-1500:] for p in sorted(slurm_dir.glob(".snakemake/slurm_logs/**/*.log"))[-3:])
        pytest.fail(f"Slurm run failed:\n{slurm.stderr[-5000:]}\nlast Slurm job logs:\n{logs}")
    assert local.returncode == 0, local_output[-5000:]
    return local_dir, slurm_dir, slurm.stderr


def _netcdf_files(root: Path) -> list[Path]:
    return sorted(p.relative_to(root) for p in (root / "results").rglob("*.nc") if paths.STAGING_DIR not in p.parts)


def test_slurm_submitted_jobs(runs):
    _, slurm_dir, log = runs
    # analyses went as grouped cluster jobs, not one allocation per snapshot
    assert (slurm_dir / ".snakemake/slurm_logs").is_dir()
    assert list((slurm_dir / ".snakemake/slurm_logs").glob("group_analysis*")), \
        sorted(p.name for p in (slurm_dir / ".snakemake/slurm_logs").iterdir())


def test_same_files(runs):
    local_dir, slurm_dir, _ = runs
    local_files, slurm_files = _netcdf_files(local_dir), _netcdf_files(slurm_dir)
    assert slurm_files == local_files
    smoke = load_config("smoke.yaml")
    expected = smoke["realizations"] * sum(len(spec.rho_grid) for spec in validate_config(smoke).values())
    assert sum(1 for p in local_files if p.parts[1] == "sim") == expected
    assert sum(1 for p in local_files if p.parts[1] == "analysis") == expected


def test_outputs_identical_to_local_run(runs):
    local_dir, slurm_dir, _ = runs
    files = _netcdf_files(local_dir)
    assert files
    for relative in files:
        local, slurm = open_dataset(local_dir / relative), open_dataset(slurm_dir / relative)
        # exact: same dims, coords, values (NaN where NaN), dtypes and variable attributes
        xr.testing.assert_identical(local.drop_attrs(deep=False), slurm.drop_attrs(deep=False))
        for name in local.variables:
            assert local[name].dtype == slurm[name].dtype, (relative, name)
            if local[name].dtype.kind == "f":
                np.testing.assert_array_equal(local[name].values, slurm[name].values, err_msg=f"{relative}:{name}")
        assert set(local.attrs) == set(slurm.attrs), relative
        for key in set(local.attrs) - VOLATILE_ATTRS:
            a, b = np.asarray(local.attrs[key]), np.asarray(slurm.attrs[key])
            assert np.array_equal(a, b, equal_nan=a.dtype.kind in "fc"), (relative, key)
