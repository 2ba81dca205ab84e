"""What the workflow's scripts call: one function per rule, taking plain paths and the config.

Workflow scripts (`workflow/scripts/*.py`) are one call into this module, so every step can also be run and
tested without Snakemake. Heavy modules (numba engine, dionysus, matplotlib) are imported inside the functions
that need them, keeping the per-job start-up of light rules small.
"""
from __future__ import annotations

import errno
import fcntl
import json
import logging
import os
import shutil
import sys
from contextlib import contextmanager
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Iterator, Mapping, Sequence

from forcenet.datasets.paths import CHECKPOINT, STAGE_LOCK, realization_index, staging_dir
from forcenet.errors import ForcenetError
from forcenet.systems import material_from_config, run_seed


#: an error while the outputs' filesystem has fewer free bytes than this is reported as a full disk [bytes] (a failed
#: write's temporary file is removed before the check, so this must exceed the largest file a job writes)
FULL_DISK_BYTES = 64 << 20
_FULL_DISK_ERRNOS = (errno.ENOSPC, errno.EDQUOT)


def full_disk_message(error: BaseException, folder: str | os.PathLike) -> str | None:
    """One line for an error that a full disk caused, None for any other: an OSError ENOSPC or EDQUOT, or any error
    while `folder`'s filesystem has under `FULL_DISK_BYTES` free (netCDF/HDF5 reports a failed write as
    ``RuntimeError: NetCDF: HDF error`` or a PermissionError). The line keeps the original error's type and text."""
    try:
        free = shutil.disk_usage(folder).free
    except OSError:
        free = None
    if getattr(error, "errno", None) not in _FULL_DISK_ERRNOS and (free is None or free >= FULL_DISK_BYTES):
        return None
    left = "" if free is None else f", {free} bytes free"
    return (f"no space left on the disk holding {os.path.abspath(folder)}{left} ({type(error).__name__}: {error}): "
            "free space there (or set results_dir to a larger filesystem), then run the same command again")


class _JobLogFile(logging.FileHandler):
    """The job's log file; what a full disk cannot take is dropped quietly (stderr still shows every line), not
    reported with logging's own traceback."""

    def handleError(self, record: logging.LogRecord) -> None:
        error = sys.exc_info()[1]
        if isinstance(error, OSError) and error.errno in _FULL_DISK_ERRNOS:
            return
        super().handleError(record)

    def close(self) -> None:
        try:
            super().close()
        except OSError as error:
            if error.errno not in _FULL_DISK_ERRNOS:
                raise


@contextmanager
def job_logger(log_path: str | os.PathLike | None, name: str) -> Iterator[logging.Logger]:
    """A logger writing to the job's log file (and stderr), closed afterwards.

    An expected error (`forcenet.errors.ForcenetError`: an invalid file or config, a simulation blow-up) is logged
    as its one-line message and ends the process with exit status 1, no traceback: the message names the file or
    the setting. So is an error that a full disk caused (`full_disk_message`). Any other exception is a bug and is
    logged and re-raised with its traceback."""
    logger = logging.getLogger(f"forcenet.{name}")
    logger.setLevel(logging.INFO)
    logger.propagate = False
    handlers: list[logging.Handler] = [logging.StreamHandler()]
    if log_path:
        Path(log_path).parent.mkdir(parents=True, exist_ok=True)
        handlers.append(_JobLogFile(log_path, mode="a"))
    formatter = logging.Formatter("%(asctime)s %(levelname)s %(message)s", "%Y-%m-%d %H:%M:%S")
    for handler in handlers:
        handler.setFormatter(formatter)
        logger.addHandler(handler)
    try:
        yield logger
    except ForcenetError as error:
        logger.error("%s", error)
        raise SystemExit(1) from None
    except Exception as error:
        message = full_disk_message(error, Path(log_path).parent if log_path else Path.cwd())
        if message is None:
            logger.exception("job failed")
            raise
        logger.error("%s", message)
        raise SystemExit(1) from None
    except BaseException:
        logger.exception("job failed")  # the traceback belongs in the job's log, not only on the console
        raise
    finally:
        for handler in handlers:
            logger.removeHandler(handler)
            handler.close()


def run_attrs(config: Mapping[str, Any], system: str, realization: int, title: str) -> dict[str, Any]:
    from forcenet.datasets import provenance_attrs

    from forcenet.datasets.schema import ENGINE_SOURCE_FORMAT, SOURCE_FORMAT_ATTR

    seed = run_seed(config, system, realization)
    return {**provenance_attrs(system=system, realization=realization, seed=seed, config=config, title=title),
            SOURCE_FORMAT_ATTR: ENGINE_SOURCE_FORMAT}


def stacked_seed(config: Mapping[str, Any], spec) -> int:
    """The `seed` of a file stacked over a system's runs: the config's base seed of a simulated system (each run's own
    is `realization_seed` of it), −1 for an imported one, as its snapshots say (its states have no seed)."""
    from forcenet.systems import ImportedSystem

    return -1 if isinstance(spec, ImportedSystem) else int(config["seed"])


def sequence_attrs(spec) -> dict[str, str]:
    """The global attributes of the stacked files of a sequence (an imported run ordered by strain, time, frame or
    timestep, `forcenet.importers.sequence`): its coordinate and the coordinate's unit, under which
    `forcenet.datasets.io` names the state axis on disk; none for a compression (every DEM system)."""
    from forcenet.datasets.schema import STATE_COORDINATE_ATTR, STATE_UNITS_ATTR
    from forcenet.systems import ImportedSystem

    if not isinstance(spec, ImportedSystem) or not spec.is_sequence:
        return {}
    from forcenet.importers.sequence import coordinate_units

    return {STATE_COORDINATE_ATTR: spec.coordinate,
            STATE_UNITS_ATTR: coordinate_units({"source": spec.source, "units": spec.units})}


def prepare_stage(stage: Path, config: Mapping[str, Any], system: str) -> Path:
    """Create (or keep) the staging folder of a run. A stage written under other simulation settings is
    discarded (its checkpoint must not be resumed); one whose config differs only in what the run does not depend
    on (`forcenet.datasets.runs.simulation_params`: analysis keys, other systems, studies) is kept, so long runs survive
    such edits."""
    from forcenet.datasets.runs import simulation_sha256

    marker, fingerprint = stage / "simulation_sha256", simulation_sha256(config, system)
    if stage.exists() and (not marker.exists() or marker.read_text() != fingerprint):
        shutil.rmtree(stage)
    stage.mkdir(parents=True, exist_ok=True)
    marker.write_text(fingerprint)
    return stage


class RunInProgress(ForcenetError):
    """Another process is running the same compression run (it holds the lock of its stage)."""


@contextmanager
def exclusive_stage(stage: Path, log: logging.Logger | None = None) -> Iterator[Path]:
    """Hold an exclusive lock (flock) on a run's stage for as long as the run works in it, so that a second
    process on the same run stops at once instead of writing the same checkpoint and snapshots: a job script that
    outlived its killed Snakemake (kill Snakemake's whole process group, `kill -- -PGID`), or two Snakemake
    instances building one target. Yields the lock file (`STAGE_LOCK` beside the stage, holding the pid), which a
    published run removes while it still holds it; the kernel releases the lock when its holder dies, so a killed
    run never blocks its resumption. On a file system without locks the run goes on unlocked, with a warning."""
    lock_path = stage.parent / STAGE_LOCK
    lock_path.parent.mkdir(parents=True, exist_ok=True)
    with open(lock_path, "a+") as handle:
        try:
            fcntl.flock(handle, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            handle.seek(0)
            holder = handle.read().strip() or "unknown"
            raise RunInProgress(f"{stage.parent} is being run by another process (pid {holder}): stop it or let "
                                "it finish; two processes must not write one run") from None
        except OSError as error:  # e.g. ENOLCK, EOPNOTSUPP on some cluster file systems
            (log or logging.getLogger("forcenet")).warning(
                "cannot lock %s (%s): running without the guard against a second process on this run",
                lock_path, error)
        else:
            handle.seek(0)
            handle.truncate()
            handle.write(f"{os.getpid()}\n")
            handle.flush()
        yield lock_path


def simulate(*, config: Mapping[str, Any], system: str, realization: str, outputs: Sequence[str],
             cost_path: str | None = None, log_path: str | None = None) -> None:
    """One compression run of `system`: snapshots at every ρ of its grid, published only when all exist.

    Snapshots and the checkpoint live in the run's staging folder (`forcenet.datasets.paths.staging_dir`) while the
    run is in progress (Snakemake deletes declared outputs of an interrupted job; the staged ones survive, so a rerun
    resumes from the checkpoint).
    cost_path: a JSON record of what the run cost (CPU seconds over every job that resumed it, particles,
    snapshots), written last; the validation report sums it into its provenance.
    """
    from forcenet.checks import checked_system
    from forcenet.dem.protocol import run_compression

    spec = checked_system(system, config)
    index = realization_index(realization)
    attrs = run_attrs(config, system, index, title=f"forcenet DEM snapshot, {system}")
    stage = staging_dir(outputs[0])
    with job_logger(log_path, f"simulate.{system}.{realization}") as log, exclusive_stage(stage, log) as lock:
        stage = prepare_stage(stage, config, system)
        staged = [stage / Path(path).name for path in outputs]
        log.info("system %s realization %s seed %d: %d snapshots, staging in %s", system, realization,
                 attrs["seed"], len(outputs), stage)
        cpu_seconds = run_compression(spec, seed=attrs["seed"], snapshot_paths=staged,
                                      checkpoint_path=stage / CHECKPOINT, attrs=attrs, log=log)
        for source, target in zip(staged, outputs):
            os.replace(source, target)
        shutil.rmtree(stage, ignore_errors=True)
        lock.unlink(missing_ok=True)  # still held: no other process waits on it
        log.info("published %d snapshots (%.2f CPU-hours, every job of the run)", len(outputs), cpu_seconds / 3600)
        if cost_path is not None:
            from forcenet.datasets import read_snapshot

            with read_snapshot(outputs[0]) as snapshot:
                particles = int(snapshot.sizes["particle"])
            record = {"system": system, "realization": index, "cpu_seconds": round(cpu_seconds, 1),
                      "particles": particles, "snapshots": len(outputs)}
            temporary = Path(f"{cost_path}.tmp{os.getpid()}")
            temporary.write_text(json.dumps(record, indent=1) + "\n")
            os.replace(temporary, cost_path)


def import_states(*, config: Mapping[str, Any], system: str, realization: str, outputs: Sequence[str],
                  log_path: str | None = None) -> None:
    """The snapshots of one run of an imported system (``source:`` in its config entry): every state of the run's
    source files, checked against the snapshot contract, written in ρ order (`forcenet.importers.import_run`). A
    malformed source stops the job with one line naming the file and line or column, and nothing is written."""
    from forcenet.importers import import_run

    with job_logger(log_path, f"import.{system}.{realization}") as log:
        import_run(config=config, system=system, realization=realization_index(realization), outputs=outputs, log=log)


def force_constants(config: Mapping[str, Any], system: str) -> dict[str, float]:
    """The per-system constants in which P1's F_max rule (§3) compares ⟨F⟩ across systems
    (`analysis.p1_force_unit`), stored as global attributes of network_measures.nc (`forcenet.datasets.aggregate` lists them with units).

    force_unit_dyn : one reduced force unit m̄ d_ave/τ_c² in dyn (NaN for a system without `material`)
    stiffness_scale_reduced : k_n d_ave^(1+β) in the system's reduced force units (= its reduced k_n, d_ave = 1)
    normal_stiffness_cgs : k_n in dyn/cm^(1+β), P1 Eq. 1 (NaN for a system without `material`)
    """
    from forcenet import units
    from forcenet.checks import checked_system

    spec = checked_system(system, config)
    constants = {"force_unit_dyn": float("nan"), "stiffness_scale_reduced": float(spec.normal_stiffness),
                 "normal_stiffness_cgs": float("nan")}
    if config["systems"][system].get("stiffness") == "material":
        material = material_from_config(config)
        constants["force_unit_dyn"] = units.force_unit_dyn(material, spec.beta)
        constants["normal_stiffness_cgs"] = units.normal_stiffness_cgs(material, spec.beta)
    return constants


def aggregate(*, analyses: Sequence[str], realizations: Sequence[int], rhos: Sequence[float], measures_path: str,
              diagrams_path: str, config: Mapping[str, Any], system: str, log_path: str | None = None) -> None:
    """Stack one system's per-snapshot analyses over (realization, ρ) into network_measures.nc and diagrams.nc; an
    analysis recorded for another run (system, dimension, simulation settings) is refused, naming the file."""
    from forcenet.checks import checked_system
    from forcenet.datasets import provenance_attrs, read_dataset, run_expectation, write_netcdf
    from forcenet.datasets.aggregate import stack_diagrams, stack_network_measures

    spec = checked_system(system, config)
    with job_logger(log_path, f"aggregate.{system}") as log:
        expect = run_expectation(spec, config)
        datasets = [read_dataset(path, "analysis", expect=expect) for path in analyses]
        attrs = provenance_attrs(system=system, realization=-1, seed=stacked_seed(config, spec), config=config,
                                 title=f"forcenet network measures, {system}, stacked over realization and rho")
        attrs.update(dimension=spec.dimension, force_law=spec.force_law, **force_constants(config, system))
        attrs.update(common_analysis_attrs(datasets))
        attrs.update(sequence_attrs(spec))  # a sequence's state axis is its coordinate
        write_netcdf(stack_network_measures(datasets, realizations, rhos, attrs), measures_path,
                     kind="network_measures")
        attrs["title"] = f"forcenet persistence diagrams, {system}, all realizations and rho"
        write_netcdf(stack_diagrams(datasets, realizations, rhos, attrs), diagrams_path, kind="diagrams")
        log.info("stacked %d analyses of %s", len(datasets), system)


#: the `analysis:` config keys that the per-snapshot analysis reads (`snapshot_measures`, `analysis_attrs`); the
#: workflow passes only these to the analysis jobs, so that other keys do not rerun every snapshot analysis
SNAPSHOT_ANALYSIS_KEYS = ("thresholds", "remove_rattlers", "force_pdf", "fill_tetrahedra")


def snapshot_analysis_params(config: Mapping[str, Any], system: str) -> dict[str, Any]:
    """What the analysis jobs of `system` read: the `SNAPSHOT_ANALYSIS_KEYS` of ``analysis:``, with
    ``remove_rattlers`` replaced by the rule of the system's study (`forcenet.systems.study_rattler_rule`:
    P1 removes rattlers, P2 keeps them), so that changing one study's rule reruns only its systems' analyses, and
    ``fill_tetrahedra`` fixed at True for a 2D system (its complex has no tetrahedra either way,
    `forcenet.topology.flag_complex_name`), so that changing it reruns only the 3D analyses."""
    from forcenet.systems import study_rattler_rule

    params = {key: config["analysis"][key] for key in SNAPSHOT_ANALYSIS_KEYS}
    params["remove_rattlers"] = study_rattler_rule(config, system)
    if config["systems"][system]["dimension"] != 3:
        params["fill_tetrahedra"] = True
    return params


@dataclass(frozen=True)
class ReadingBeside:
    """Another value of one convention, built from the same runs and judged beside the config's own in the
    validation tables (issue 25, docs/decisions.md): `key` is the config key (dotted), `value` its other value,
    `label` the tables' ``reading`` text."""

    key: str
    value: Any
    label: str

    @property
    def folder(self) -> str:
        """The name of its results folder below ``{results}/readings/`` (`forcenet.datasets.paths.reading`)."""
        return f"{self.key.rsplit('.', 1)[-1]}-{str(self.value).lower()}"


_TETRAHEDRA_READINGS = {True: "filled tetrahedra", False: "hollow tetrahedra (each 4-clique a void)"}
_ESSENTIAL_READINGS = {"apart": "never-dying classes matched only with each other",
                       "minus_one": "never-dying classes at death -1",
                       "drop": "never-dying classes left out of the distances"}


def readings_beside(config: Mapping[str, Any]) -> dict[str, ReadingBeside]:
    """The readings a build judges beside its own conventions, each from a second build of the same runs:
    ``tetrahedra``, P1's 3D systems analysed with the other ``analysis.fill_tetrahedra``; ``essential``, P2's
    distances and Tables I–III with never-dying classes matched only with each other (``apart``; at death −1 when
    the config's convention is ``apart``); ``essential_drop``, the same with them left out (``drop``, the control of
    docs/validation/controls.md §3; none when the config's convention is ``drop``); ``table_states``, P2's Tables I–III from the literal states around
    ``table_rho`` when the config's ``studies.p2.table_states`` is ``jammed`` (none when it is ``literal``: a build
    on states that never jam, such as imported ones, has no jammed states a, b, c to set beside)."""
    fill = not bool(config["analysis"]["fill_tetrahedra"])
    convention = "minus_one" if config["analysis"]["essential_convention"] == "apart" else "apart"
    p2 = config["studies"].get("p2", {})
    table_rho = float(p2.get("table_rho", 0.79))
    readings = {"tetrahedra": ReadingBeside("analysis.fill_tetrahedra", fill, _TETRAHEDRA_READINGS[fill]),
                "essential": ReadingBeside("analysis.essential_convention", convention, _ESSENTIAL_READINGS[convention])}
    if config["analysis"]["essential_convention"] != "drop":
        readings["essential_drop"] = ReadingBeside("analysis.essential_convention", "drop", _ESSENTIAL_READINGS["drop"])
    if p2.get("table_states", "jammed") == "jammed":
        readings["table_states"] = ReadingBeside("studies.p2.table_states", "literal",
                                                 f"states a, b, c nearest rho = {table_rho:g} (literal)")
    return readings


def analyze_run(*, snapshots: Sequence[str], outputs: Sequence[str], analysis: Mapping[str, Any],
                log_path: str | None = None, expect: Mapping[str, Any] | None = None) -> None:
    """Analyse every snapshot of one compression run (one process: imports and JIT paid once). Every snapshot is
    read and checked before the first analysis is written, so a bad one stops the job with nothing written.
    `expect` (`forcenet.datasets.runs.run_expectation` of the run): a snapshot recorded for another system,
    dimension, simulation settings, realization or state (its file name's, `state_expectation`) is refused, naming
    the file and the attribute."""
    from forcenet.datasets import read_snapshot
    from forcenet.datasets.runs import state_expectation

    with job_logger(log_path, "analyze") as log:
        snaps = [read_snapshot(snapshot, expect=None if expect is None else state_expectation(expect, snapshot))
                 for snapshot in snapshots]
        for snapshot, snap, output in zip(snapshots, snaps, outputs, strict=True):
            analyze_snapshot(snapshot, output, analysis, log, snap=snap)


def analyze_snapshot(snapshot: str, output: str, analysis: Mapping[str, Any], log: logging.Logger,
                     snap=None) -> None:
    """Analyse one snapshot file (`snap`: its dataset, if already read) and write its analysis file (see
    `snapshot_measures`)."""
    import time

    from forcenet.datasets import read_snapshot, write_netcdf
    from forcenet.datasets.analysis import analysis_dataset

    start = time.perf_counter()
    snap = read_snapshot(snapshot) if snap is None else snap
    ds = analysis_dataset(snapshot_measures(snap, analysis), rho=float(snap.rho),
                          attrs=analysis_attrs(snap, snapshot, analysis), force_units=imported_force_units(snap))
    write_netcdf(ds, output, kind="analysis")
    log.info("%s: rho %.3f, Z %.3f, %d diagram points, %.2f s", snapshot, float(snap.rho), float(snap.Z),
             ds.sizes["point"], time.perf_counter() - start)


def imported_force_units(snap) -> str | None:
    """The force unit of an imported snapshot (its forces' `units`: the source's, ``systems.<name>.units.force``),
    which its analysis' ⟨F⟩ keeps; None for our engine's (the schema's reduced unit, files unchanged)."""
    from forcenet.datasets.io import optional_attr
    from forcenet.datasets.schema import ENGINE_SOURCE_FORMAT, SOURCE_FORMAT_ATTR

    if optional_attr(snap, SOURCE_FORMAT_ATTR) == ENGINE_SOURCE_FORMAT:
        return None
    return str(snap["force_normal"].attrs["units"])


def snapshot_measures(snap, analysis: Mapping[str, Any]) -> dict[str, Any]:
    """Every single-snapshot measure of the total (P1), normal and tangential (P2) force networks of a snapshot
    dataset, each network normalised by its own mean: {kind: SnapshotMeasures}."""
    from forcenet.datasets.schema import FORCE_KINDS
    from forcenet.measures.forces import default_force_bin_edges
    from forcenet.measures.snapshot import compute_snapshot_measures
    from forcenet.network import snapshot_network
    from forcenet.topology.betti import default_thresholds

    thresholds = default_thresholds(**analysis["thresholds"])
    edges = default_force_bin_edges(analysis["force_pdf"]["max"], analysis["force_pdf"]["bins"])
    measures = {}
    for kind in FORCE_KINDS:
        # wall contacts kept for percolation, not counted by the rattler rule (forcenet.network.snapshot)
        network = snapshot_network(snap, kind, rattler_rule=analysis["remove_rattlers"], wall_contacts="kept")
        measures[kind] = compute_snapshot_measures(network, thresholds=thresholds, force_bin_edges=edges,
                                                   fill_tetrahedra=analysis["fill_tetrahedra"])
    return measures


def analysis_attrs(snap, source: str, analysis: Mapping[str, Any]) -> dict[str, Any]:
    """Global attributes of an analysis file: the snapshot's provenance plus what the analysis used."""
    from forcenet.topology import flag_complex_name

    attrs = {key: snap.attrs[key] for key in ("system", "realization", "seed", "forcenet_version", "git_commit",
                                               "config_sha256", "config", "Conventions", "dimension")}
    from forcenet.datasets.schema import BOX_TILT_ATTR, PERIODIC_AXES_ATTR, SNAPSHOT_SOURCE_ATTRS, SOURCE_FORMAT_ATTR

    # where the snapshot came from (our engine, or an import's files and their sha256) travels with its analysis, and
    # so does its box: the periodic axes, along which percolation means winding around the box, and a tilt
    attrs.update({key: snap.attrs[key] for key in (SOURCE_FORMAT_ATTR, *SNAPSHOT_SOURCE_ATTRS, PERIODIC_AXES_ATTR,
                                                   BOX_TILT_ATTR) if key in snap.attrs})
    attrs["title"] = f"forcenet analysis of one snapshot, {attrs['system']}"
    attrs["source"] = str(source)
    attrs.update(rattler_attrs(analysis["remove_rattlers"]))
    attrs.update(flag_complex_attrs(flag_complex_name(int(snap.attrs["dimension"]), analysis["fill_tetrahedra"])))
    return attrs


def rattler_attrs(remove_rattlers: bool | str) -> dict[str, str]:
    """Global attributes naming the rattler rule that made a file's force networks (analysis, stacked and
    distance files, P2 tables)."""
    from forcenet.network import RATTLER_RULE_DESCRIPTIONS, resolve_rattler_rule

    rule = resolve_rattler_rule(remove_rattlers)
    return {"rattler_rule": rule, "rattler_rule_description": RATTLER_RULE_DESCRIPTIONS[rule]}


def flag_complex_attrs(name: str) -> dict[str, str]:
    """Global attributes naming the flag complex whose diagrams a file holds (analysis, stacked and distance
    files): ``flag_complex``, the highest filled simplex (`forcenet.topology.flag_complex_name`: "tetrahedra" or
    "triangles"), and its description."""
    from forcenet.topology import FLAG_COMPLEX_DESCRIPTIONS

    return {"flag_complex": name, "flag_complex_description": FLAG_COMPLEX_DESCRIPTIONS[name]}


def common_attribute(datasets: Sequence[Any], name: str, what: str) -> str:
    """The global attribute `name` shared by every dataset (analysis files or P2 run summaries, whose validated read
    refused one without it); ValueError when they differ (a product must not mix diagrams made under different
    `what`)."""
    values = {ds.attrs[name] for ds in datasets}
    if len(values) != 1:
        raise ValueError(f"analyses were made with different {what}: {sorted(values)}")
    return values.pop()


def common_analysis_attrs(datasets: Sequence[Any]) -> dict[str, str]:
    """The rattler rule and flag complex shared by every analysis file that a product stacks or compares, as
    its global attributes (`common_attribute`: ValueError when they differ or one lacks them)."""
    return {**rattler_attrs(common_attribute(datasets, "rattler_rule", "rattler rules")),
            **flag_complex_attrs(common_attribute(datasets, "flag_complex", "flag complexes"))}


def open_by_system(paths: Sequence[str], kind: str) -> dict[str, Any]:
    """{system: dataset} of files of one kind (`forcenet.datasets.schema.FILE_KINDS`), each checked on reading."""
    from forcenet.datasets import read_dataset

    datasets = [read_dataset(path, kind) for path in paths]
    return {ds.attrs["system"]: ds for ds in datasets}


def p1_validation_table(*, measures: Sequence[str], systems: Sequence[str], csv: str, md: str, force_unit: str,
                        paper_size: str | None = None, snapshots: Sequence[str] = (), diagrams: Sequence[str] = (),
                        beside: Mapping[str, Mapping[str, Sequence[str]]] | None = None,
                        counterparts: Sequence[str] = (), log_path: str | None = None) -> None:
    """P1's numbers and claims next to ours (results/tables/p1_validation.{csv,md}); `force_unit`
    (``analysis.p1_force_unit``) is the unit of the F_max rule the figures use; `paper_size` (the campaign's
    ``docs/validation/p1.csv``, or None in a paper-size config) adds our paper-size values beside P1's;
    `snapshots` (each system's snapshots, every state and realization) give the overlaps P1 §3 bounds, judged at
    P1's depth above jamming (`forcenet.report.p1_validation.overlaps_by_state`);
    `diagrams` (diagrams.nc) the never-dying classes that enter TP and the bins at death −1; `beside` ({reading
    label: {"measures": […], "diagrams": […]}}, `readings_beside`) the systems a reading changes, judged beside;
    `counterparts` (``studies.p1.counterparts``) the systems among `measures` that only the friction and
    system-size claims judge."""
    from forcenet.datasets import read_snapshot
    from forcenet.report.claims import verdict_counts
    from forcenet.report.p1_validation import overlaps_by_state, p1_validation, write_p1_validation
    from forcenet.report.realizations import ROBUSTNESS_RESAMPLES

    def opened(paths: Sequence[str]):
        """Each snapshot open only while it is measured."""
        for path in paths:
            with read_snapshot(path) as snapshot:
                yield snapshot

    with job_logger(log_path, "p1_validation") as log:
        overlaps = overlaps_by_state(opened(snapshots))
        # a reading without measures of its own (no 3D system for the tetrahedra) would only repeat the primary
        readings = {label: files for label, files in (beside or {}).items() if files.get("measures")}
        table = p1_validation(open_by_system(measures, "network_measures"), force_unit=force_unit,
                              resamples=ROBUSTNESS_RESAMPLES, overlaps=overlaps,
                              diagrams=open_by_system(diagrams, "diagrams"),
                              beside={label: open_by_system(files.get("measures", ()), "network_measures")
                                      for label, files in readings.items()},
                              beside_diagrams={label: open_by_system(files.get("diagrams", ()), "diagrams")
                                               for label, files in readings.items()},
                              counterparts=counterparts)
        write_p1_validation(table, csv, md, paper_size=paper_size)
        log.info("P1 validation: %d rows, claim verdicts %s", len(table), verdict_counts(table))


def sequence_claims_note(paper: str, systems: Sequence[str], coordinates: Sequence[str]) -> str:
    """Why a validation table of `paper` (P1 or P2) lists no claim: its study's `systems` are all sequences (imported
    runs at any ρ, ordered by `coordinates`)."""
    return (f"no claim applies: the study's systems ({', '.join(systems)}) are imported sequences ordered by "
            f"{', '.join(sorted(set(coordinates)))}, not compressions, and every claim of {paper} is about how a "
            "packing's force networks change as it is compressed (over ρ, around ρ_J, between nearby ρ)")


def no_claims_table(*, csv: str, md: str, paper: str, note: str, log_path: str | None = None) -> None:
    """A validation table that lists no claim (`csv`: one column `note`, one row; `md`: a title and the line `note`
    saying why), for a study whose every system is a sequence (`sequence_claims_note`)."""
    import pandas as pd

    with job_logger(log_path, f"{paper.lower()}_validation") as log:
        Path(csv).parent.mkdir(parents=True, exist_ok=True)
        pd.DataFrame({"note": [note]}).to_csv(csv, index=False)
        Path(md).write_text(f"# {paper} validation\n\n{note[0].upper()}{note[1:]}.\n", encoding="utf-8")
        log.info("%s validation: %s", paper, note)


def chosen_datasets(paths: Sequence[str], states_csv: str, reader) -> list:
    """The datasets among `paths` (read with `reader`) of the realization `states_csv` chose, in increasing ρ."""
    import pandas as pd

    from forcenet.report.p2_tables import chosen_states

    return chosen_states([reader(p) for p in paths], pd.read_csv(states_csv))
