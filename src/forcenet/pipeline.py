"""What the workflow's scripts call: one function per rule, taking plain paths and the config.

Workflow scripts (`workflow/scripts/*.py`) are one call into this module, so every step can also be run and
tested without Snakemake. Heavy modules (numba engine, dionysus, matplotlib) are imported inside the functions
that need them, keeping the per-job start-up of light rules small.
"""
from __future__ import annotations

import logging
import os
import shutil
from contextlib import contextmanager
from pathlib import Path
from typing import Any, Iterator, Mapping, Sequence

from forcenet.systems import realization_seed, system_from_config


@contextmanager
def job_logger(log_path: str | os.PathLike | None, name: str) -> Iterator[logging.Logger]:
    """A logger writing to the job's log file (and stderr), closed afterwards."""
    logger = logging.getLogger(f"forcenet.{name}")
    logger.setLevel(logging.INFO)
    logger.propagate = False
    handlers: list[logging.Handler] = [logging.StreamHandler()]
    if log_path:
        Path(log_path).parent.mkdir(parents=True, exist_ok=True)
        handlers.append(logging.FileHandler(log_path, mode="a"))
    formatter = logging.Formatter("%(asctime)s %(levelname)s %(message)s", "%Y-%m-%d %H:%M:%S")
    for handler in handlers:
        handler.setFormatter(formatter)
        logger.addHandler(handler)
    try:
        yield logger
    finally:
        for handler in handlers:
            logger.removeHandler(handler)
            handler.close()


def realization_index(label: str) -> int:
    """'r03' → 3."""
    return int(str(label).lstrip("r"))


def run_attrs(config: Mapping[str, Any], system: str, realization: int, title: str) -> dict[str, Any]:
    from forcenet.datasets import provenance_attrs

    seed = realization_seed(config["seed"], system, realization)
    return provenance_attrs(system=system, realization=realization, seed=seed, config=config, title=title)


def staging_dir(output: str | os.PathLike) -> Path:
    """Where a run keeps its snapshots and checkpoint until it completes: {run dir}/.partial/."""
    return Path(output).parent / ".partial"


def simulate(*, config: Mapping[str, Any], system: str, realization: str, outputs: Sequence[str],
             log_path: str | None = None) -> None:
    """One compression run of `system`: snapshots at every ρ of its grid, published only when all exist.

    Snapshots and the checkpoint live in `.partial/` while the run is in progress (Snakemake deletes declared
    outputs of an interrupted job; the staged ones survive, so a rerun resumes from the checkpoint).
    """
    from forcenet.dem.protocol import run_compression

    spec = system_from_config(system, config)
    index = realization_index(realization)
    attrs = run_attrs(config, system, index, title=f"forcenet DEM snapshot, {system}")
    stage = staging_dir(outputs[0])
    marker = stage / "config_sha256"
    if stage.exists() and (not marker.exists() or marker.read_text() != attrs["config_sha256"]):
        shutil.rmtree(stage)  # a checkpoint from another config must not be resumed
    stage.mkdir(parents=True, exist_ok=True)
    marker.write_text(attrs["config_sha256"])
    staged = [stage / Path(path).name for path in outputs]
    with job_logger(log_path, f"simulate.{system}.{realization}") as log:
        log.info("system %s realization %s seed %d: %d snapshots, staging in %s", system, realization,
                 attrs["seed"], len(outputs), stage)
        run_compression(spec, seed=attrs["seed"], snapshot_paths=staged, checkpoint_path=stage / "checkpoint.npz",
                        attrs=attrs, log=log)
        for source, target in zip(staged, outputs):
            os.replace(source, target)
        shutil.rmtree(stage, ignore_errors=True)
        log.info("published %d snapshots", len(outputs))
