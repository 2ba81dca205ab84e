"""The validation campaign as committed records: every finished paper-size run kept in the repository, made once.

A config with ``records_dir`` (config/validation.yaml: ``data/validation``) keeps there, for each finished
compression run, its snapshots in one compact file (`forcenet.datasets.records`) and a row of ``manifest.csv``
(`MANIFEST_COLUMNS`). The workflow restores the snapshots of a recorded run instead of simulating it
(workflow/rules/simulate.smk, `restore_run`) and simulates only the runs without a record, so the campaign grows
run by run across working copies and its tables are regenerated from the records with no DEM step.

A record is the run of one system's settings: the manifest keeps the run's simulation fingerprint
(`forcenet.datasets.runs.simulation_sha256`: the system's own config entry, the seed and the material), and a record
whose fingerprint is not the config's is refused by name (`recorded_realizations`), never reused.

The command `forcenet-campaign` (`forcenet.campaign_cli`) lists the runs, records finished ones and works through
the missing ones.

Parse-time functions (`records_folder`, `recorded_realizations`) import nothing heavy: the workflow calls them when
it is parsed, a dry run included.
"""
from __future__ import annotations

import contextlib
import csv
import datetime as _dt
import fcntl
import hashlib
import json
import os
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Callable, Mapping, Sequence

from forcenet.datasets import paths
from forcenet.datasets.runs import simulation_sha256
from forcenet.errors import ForcenetError
from forcenet.systems import ImportedSystem, realization_indices

#: the columns of manifest.csv, one row per recorded run
MANIFEST_COLUMNS = ("system", "realization", "simulation_sha256", "git_commit", "cpu_hours", "particles", "states",
                    "file", "bytes", "sha256", "recorded")
#: the config every command reads unless told otherwise
DEFAULT_CAMPAIGN_CONFIG = "config/validation.yaml"


class CampaignError(ForcenetError):
    """A record that cannot be used (another system's settings, a changed file) or a run that cannot be recorded."""


def records_folder(config: Mapping[str, Any]) -> str | None:
    """The config's ``records_dir`` (relative to the repository root), or None: every run is simulated."""
    value = config.get("records_dir")
    return None if value is None else str(value).rstrip("/")


def read_manifest(records: str | os.PathLike) -> list[dict[str, str]]:
    """The rows of a records folder's manifest.csv (none when it has no manifest yet)."""
    path = Path(paths.record_manifest(records))
    if not path.exists():
        return []
    with open(path, newline="") as handle:
        rows = list(csv.DictReader(handle))
    if rows and set(rows[0]) != set(MANIFEST_COLUMNS):
        raise CampaignError(f"{path}: columns {sorted(rows[0])}, expected {list(MANIFEST_COLUMNS)}")
    return rows


def excluded_runs(records: str | os.PathLike | None) -> dict[tuple[str, str], str]:
    """{(system, realization): why} of the runs that `records`' excluded.csv says are not made here (a run that
    cannot integrate, a run for a cluster)."""
    path = Path(paths.excluded_runs(records)) if records else None
    if path is None or not path.exists():
        return {}
    with open(path, newline="") as handle:
        rows = list(csv.DictReader(handle))
    if rows and set(rows[0]) != {"system", "realization", "reason"}:
        raise CampaignError(f"{path}: columns {sorted(rows[0])}, expected ['realization', 'reason', 'system']")
    return {(row["system"], row["realization"]): row["reason"] for row in rows}


def write_manifest(records: str | os.PathLike, rows: Sequence[Mapping[str, Any]]) -> Path:
    """Write manifest.csv sorted by system and realization (atomically: a temporary name renamed over it)."""
    path = Path(paths.record_manifest(records))
    path.parent.mkdir(parents=True, exist_ok=True)
    temporary = path.with_name(f".{path.name}.tmp{os.getpid()}")
    with open(temporary, "w", newline="") as handle:
        writer = csv.DictWriter(handle, fieldnames=MANIFEST_COLUMNS, lineterminator="\n")
        writer.writeheader()
        writer.writerows(sorted(rows, key=lambda row: (row["system"], row["realization"])))
    os.replace(temporary, path)
    return path


def file_sha256(path: str | os.PathLike) -> str:
    digest = hashlib.sha256()
    with open(path, "rb") as handle:
        for block in iter(lambda: handle.read(1 << 20), b""):
            digest.update(block)
    return digest.hexdigest()


def recorded_realizations(config: Mapping[str, Any], system: str) -> list[str]:
    """The realizations of `system` (r00, …) that the config restores from its records: those of its realization
    count with a manifest row. A row recorded under other settings of the system is refused (`CampaignError` naming
    the record, both fingerprints and what to do): the run must be made again."""
    records = records_folder(config)
    if records is None:
        return []
    wanted = {paths.realization_name(index) for index in realization_indices(config, system)}
    rows = [row for row in read_manifest(records) if row["system"] == system and row["realization"] in wanted]
    if rows:
        expected = simulation_sha256(config, system)
        for row in rows:
            if row["simulation_sha256"] != expected:
                raise CampaignError(
                    f"campaign record {records}/{row['file']} was made under other settings of system '{system}' "
                    f"(simulation fingerprint {row['simulation_sha256'][:12]}, this config's {expected[:12]}): the run "
                    f"must be made again — remove its record (forcenet-campaign drop {system} {row['realization']}) "
                    f"or give the changed system a new name")
    return sorted(row["realization"] for row in rows)


def realizations_except(names: Sequence[str]) -> str:
    """A Snakemake wildcard constraint (regular expression) matching every realization name (r00, r01, …, r100)
    but `names`: the simulate rule of a system takes the realizations its restore rule does not."""
    return rf"(?!(?:{'|'.join(names)})(?!\d))r\d\d+" if names else r"r\d\d+"


def recorded_row(config: Mapping[str, Any], records: str | os.PathLike, system: str,
                 realization: str) -> dict[str, str] | None:
    """The manifest row of a run recorded under the config's settings of its system whose file is intact (its
    sha256 the manifest's), else None."""
    rows = [row for row in read_manifest(records) if (row["system"], row["realization"]) == (system, realization)]
    if not rows or rows[0]["simulation_sha256"] != simulation_sha256(config, system):
        return None
    path = Path(records) / rows[0]["file"]
    return rows[0] if path.exists() and file_sha256(path) == rows[0]["sha256"] else None


def manifest_row(records: str, system: str, realization: str) -> dict[str, str]:
    rows = [row for row in read_manifest(records) if row["system"] == system and row["realization"] == realization]
    if not rows:
        raise CampaignError(f"{paths.record_manifest(records)}: no record of {system} {realization}")
    return rows[0]


def p2_system(config: Mapping[str, Any], system: str) -> bool:
    """Whether `system` is one of the config's P2 systems, whose runs are recorded as P2 run records (their
    summary and the states Tables I-III read, `forcenet.datasets.records.p2_record_dataset`)."""
    return system in config.get("studies", {}).get("p2", {}).get("systems", [])


def p2_kept_labels(config: Mapping[str, Any], system: str) -> list[str]:
    """The grid labels of the states a P2 run record of `system` keeps: those P2's Tables I-III and their state
    choice can read (`forcenet.pipeline_p2.p2_read_state_indices`) for the frictional system (its catalog role,
    `forcenet.catalog.p2_roles`), none for the frictionless one."""
    from forcenet.catalog import p2_roles
    from forcenet.checks import checked_system
    from forcenet.pipeline_p2 import p2_read_state_indices

    p2 = config["studies"]["p2"]
    if system != p2_roles(config, p2["systems"])[0]:
        return []
    spec = checked_system(system, config)
    return [spec.rho_labels[i] for i in p2_read_state_indices(spec.rho_grid, p2.get("table_rho", 0.79),
                                                               p2.get("table_states", "jammed"))]


def record_path(config: Mapping[str, Any], records: str | os.PathLike, system: str, realization: str) -> str:
    """The record file of a run: a P2 run record for a P2 system, a run record otherwise."""
    if p2_system(config, system):
        return paths.p2_record_file(records, system, realization)
    return paths.record_file(records, system, realization)


def restore_run(*, config: Mapping[str, Any], system: str, realization: str, outputs: Sequence[str],
                cost_path: str | None = None, summary_path: str | None = None) -> None:
    """Write a recorded run's snapshots (`outputs`, in grid order) and cost record from its campaign record: the
    record's sha256 is the manifest's, its fingerprint the config's, every state on its ρ (zero DEM steps). A P2
    run's record writes its summary (`summary_path`) and the states it keeps (`outputs`), and is refused, by name,
    when it lacks a never-dying convention the config's P2 products read."""
    from forcenet.datasets import read_dataset
    from forcenet.datasets.records import (P2_RECORD_FORMAT, RECORD_FORMAT, record_global_problems, restore_p2_run,
                                           restore_snapshots)

    records = records_folder(config)
    if records is None:
        raise CampaignError(f"{system} {realization}: the config has no records_dir")
    row = manifest_row(records, system, realization)
    path = Path(records) / row["file"]
    digest = file_sha256(path) if path.exists() else "missing"
    if digest != row["sha256"]:
        raise CampaignError(f"{path}: sha256 {digest[:12]}, the manifest's {row['sha256'][:12]}: the record was "
                            "changed or not fetched (a Git LFS pointer?); restore it from git or make the run again")
    p2 = p2_system(config, system)
    if p2 and Path(row["file"]).name != paths.P2_RECORD_FILE:
        raise CampaignError(f"{path}: {system} is a P2 system, whose runs are recorded as {paths.P2_RECORD_FILE} "
                            "(make the record again: forcenet-campaign drop, then record)")
    record = read_dataset(path, "p2_run_record" if p2 else "run_record")
    problems = record_global_problems(record, P2_RECORD_FORMAT if p2 else RECORD_FORMAT)
    expected = simulation_sha256(config, system)
    if not problems and record.attrs["simulation_sha256"] != expected:
        problems.append(f"its simulation fingerprint is not this config's ({expected[:12]})")
    if problems:
        raise CampaignError(f"{path}: " + "; ".join(problems))
    if p2:
        from forcenet.pipeline_p2 import p2_conventions

        if summary_path is None:
            raise CampaignError(f"{path}: a P2 run's record restores its summary, but no summary path was given")
        try:
            restore_p2_run(path, summary_path, outputs, p2_conventions(config))
        except ForcenetError as error:
            raise CampaignError(str(error)) from None
    else:
        restore_snapshots(path, outputs)
    if cost_path is not None:  # a P2 record keeps some states: the run's particles and states are the manifest's
        cost = {"system": system, "realization": paths.realization_index(realization),
                "cpu_seconds": round(float(record.attrs["cpu_seconds"]), 1),
                "particles": int(row["particles"]) if p2 else int(record.sizes["particle"]),
                "snapshots": int(row["states"]) if p2 else int(record.sizes["state"])}
        temporary = Path(f"{cost_path}.tmp{os.getpid()}")
        temporary.write_text(json.dumps(cost, indent=1) + "\n")
        os.replace(temporary, cost_path)


def record_run(config: Mapping[str, Any], system: str, realization: str, *, results: str | os.PathLike,
               records: str | None = None, replace: bool = False) -> dict[str, str]:
    """Record one finished run of `results` (its published snapshots and run_cost.json) in `records` (default: the
    config's ``records_dir``): the record file, checked to give back every kept value of every snapshot, and its
    manifest row (returned). Refuses a run that has not finished or whose snapshots are of other settings. A run
    already recorded under the same settings, its file intact, keeps its record (its row is returned) unless
    `replace`: the same run recorded again would only rewrite the file with another date."""
    from forcenet.checks import checked_system
    from forcenet.datasets import read_snapshot, run_expectation, write_netcdf
    from forcenet.datasets.records import record_dataset, record_differences, record_encoding
    from forcenet.datasets.runs import state_expectation

    records = records or records_folder(config)
    if records is None:
        raise CampaignError("the config has no records_dir: name the folder with --records")
    spec = checked_system(system, config)
    if isinstance(spec, ImportedSystem):
        raise CampaignError(f"{system} is imported, not simulated: its sources are its record")
    kept = recorded_row(config, records, system, realization)
    if kept is not None and not replace:
        return kept
    outputs = [Path(paths.snapshot(results, system, realization, label)) for label in spec.rho_labels]
    cost_path = Path(paths.run_cost(results, system, realization))
    missing = [str(p) for p in [*outputs, cost_path] if not p.exists()]
    if missing:
        raise CampaignError(f"{system} {realization} has not finished in {results}: {len(missing)} of its files are "
                            f"missing (first: {missing[0]})")
    expect = run_expectation(spec, config)
    snapshots = [read_snapshot(path, expect=state_expectation(expect, path)) for path in outputs]
    if spec.protocol == "quasistatic":
        out_of_balance(snapshots, spec.rho_labels, system, realization)
    cost = json.loads(cost_path.read_text())
    title = f"forcenet campaign record, {system} {realization}"
    if p2_system(config, system):
        record, kind = _p2_record(config, system, realization, results, snapshots, expect, cost, title)
        target = Path(paths.p2_record_file(records, system, realization))
    else:
        record = record_dataset(snapshots, spec.rho_labels, simulation_sha256=expect["simulation_sha256"],
                                cpu_seconds=float(cost["cpu_seconds"]), title=title)
        kind, target = "run_record", Path(paths.record_file(records, system, realization))
    if kind == "run_record":
        kept = snapshots
    else:  # a P2 record gives back the states it keeps
        kept = [snapshots[spec.rho_labels.index(label)] for label in p2_kept_labels(config, system)]
    differences = record_differences(record, kept) if kept else []
    if differences:
        raise CampaignError(f"{system} {realization}: the record would not give back the run: {differences[0]}")
    write_netcdf(record, target, kind=kind, encoding=record_encoding(record))
    commits = sorted({str(s.attrs["git_commit"]) for s in snapshots})  # a contract attribute of every snapshot
    row = {"system": system, "realization": realization, "simulation_sha256": expect["simulation_sha256"],
           "git_commit": " ".join(commits), "cpu_hours": f"{float(cost['cpu_seconds']) / 3600:.3f}",
           "particles": str(snapshots[0].sizes["particle"]), "states": str(len(snapshots)),
           "file": target.relative_to(records).as_posix(), "bytes": str(target.stat().st_size),
           "sha256": file_sha256(target),
           "recorded": _dt.datetime.now(_dt.timezone.utc).strftime("%Y-%m-%d %H:%M UTC")}
    with _manifest_lock(records):  # two campaign runners may record into one folder at the same moment
        kept = [r for r in read_manifest(records) if (r["system"], r["realization"]) != (system, realization)]
        write_manifest(records, [*kept, row])
    return row


def out_of_balance(snapshots: Sequence[Any], labels: Sequence[str], system: str, realization: str) -> None:
    """Refuse a quasi-static run one of whose jammed states (Z ≥ d + 1) is not in mechanical equilibrium: a particle
    whose recorded contact and wall forces sum to more than `FORCE_BALANCE_TOLERANCE` × the mean normal force
    (`forcenet.measures.forces.force_imbalance`). Such a run did not move under the forces it recorded."""
    from forcenet.measures.forces import FORCE_BALANCE_TOLERANCE, force_imbalance

    for label, snapshot in zip(labels, snapshots):
        if float(snapshot["Z"]) < snapshot.sizes["spatial"] + 1:
            continue
        imbalance, particle = force_imbalance(snapshot)
        if imbalance > FORCE_BALANCE_TOLERANCE:
            raise CampaignError(f"{system} {realization}: the state at rho = {label} is not at rest under its recorded "
                                f"forces (particle {particle} feels {imbalance:.3g} x the mean normal force, at most "
                                f"{FORCE_BALANCE_TOLERANCE:g}); not recorded: simulate it again")


def _p2_record(config: Mapping[str, Any], system: str, realization: str, results: str | os.PathLike,
               snapshots: Sequence[Any], expect: Mapping[str, Any], cost: Mapping[str, Any], title: str):
    """(the P2 run record, its kind) of a finished P2 run: the run's summary (results/{system}/p2_runs/, made by the
    workflow from its analyses) and the states `p2_kept_labels` names; refused when the summary is missing, of other
    settings, or lacks a never-dying convention the config's P2 products read."""
    from forcenet.checks import checked_system
    from forcenet.datasets import read_dataset
    from forcenet.datasets.records import p2_record_dataset
    from forcenet.pipeline_p2 import p2_conventions

    spec = checked_system(system, config)
    summary_path = Path(paths.p2_run(results, system, realization))
    if not summary_path.exists():
        raise CampaignError(f"{system} {realization}: its summary {summary_path} is missing (make it: snakemake "
                            f"{summary_path} --configfile CONFIG)")
    summary = read_dataset(summary_path, "p2_run")
    if summary.attrs["simulation_sha256"] != expect["simulation_sha256"]:
        raise CampaignError(f"{summary_path}: made from a run of other settings of '{system}' than the config's")
    held = [str(c) for c in summary["essential_convention"].values]
    missing = [c for c in p2_conventions(config) if c not in held]
    if missing:
        raise CampaignError(f"{summary_path}: no distances under the never-dying conventions {missing} (it holds "
                            f"{held}); make it again from the run's analyses")
    kept = [spec.rho_labels.index(label) for label in p2_kept_labels(config, system)]
    record = p2_record_dataset(summary, snapshots, spec.rho_labels, kept, simulation_sha256=expect["simulation_sha256"],
                               cpu_seconds=float(cost["cpu_seconds"]), title=title)
    return record, "p2_run_record"


@contextlib.contextmanager
def _manifest_lock(records: str | os.PathLike):
    """Hold an exclusive lock on the records folder's manifest for one read-modify-write."""
    path = Path(paths.record_manifest(records))
    path.parent.mkdir(parents=True, exist_ok=True)
    with open(path.with_name(f".{path.name}.lock"), "w") as handle:
        fcntl.flock(handle, fcntl.LOCK_EX)
        try:
            yield
        finally:
            fcntl.flock(handle, fcntl.LOCK_UN)


@dataclass(frozen=True)
class RunStatus:
    """One run of a campaign config: `state` recorded / finished (published, no record yet) / running (a process
    holds its stage) / stopped (a stage to resume, nobody running it) / missing / excluded (not made here, its
    reason in the records' excluded.csv: nothing to go); CPU-hours done (recorded or
    finished) and to go (an estimate: the mean of the system's recorded runs, else of its runs in the committed
    tables' provenance, else of the recorded runs of the system it is a variant of when both have one size and
    grid, else the cost model)."""

    system: str
    realization: str
    state: str
    cpu_hours_done: float
    cpu_hours_to_go: float
    detail: str = ""


def _stage_is_held(results: str | os.PathLike, system: str, realization: str) -> bool:
    """Whether a process holds the lock of the run's stage (`forcenet.pipeline.exclusive_stage`)."""
    lock = Path(paths.run_dir(results, system, realization)) / paths.STAGE_LOCK
    if not lock.exists():
        return False
    with open(lock) as handle:
        try:
            fcntl.flock(handle, fcntl.LOCK_SH | fcntl.LOCK_NB)
        except BlockingIOError:
            return True
        fcntl.flock(handle, fcntl.LOCK_UN)
    return False


def tabled_cpu_hours(folder: str | os.PathLike = paths.VALIDATION_DIR) -> dict[str, float]:
    """CPU-hours per run of each system in the provenance of the committed validation tables (``# system NAME:
    N=… realizations=R cpu_hours=H`` lines of docs/validation/{p1,p2}.csv): H / R, the estimate of a system with no
    record yet."""
    per_run = {}
    for study in ("p1", "p2"):
        path = Path(paths.campaign_table(study, "csv", folder))
        if not path.exists():
            continue
        for line in path.read_text().splitlines():
            if not line.startswith("#"):
                break
            if line.startswith("# system "):
                name, _, fields = line[len("# system "):].partition(":")
                values = dict(field.split("=", 1) for field in fields.split() if "=" in field)
                if int(values.get("realizations", 0)) > 0:
                    per_run[name] = float(values["cpu_hours"]) / int(values["realizations"])
    return per_run


def campaign_status(config: Mapping[str, Any], *, results: str | os.PathLike) -> list[RunStatus]:
    """Every compression run of `config`, in config order, with its `RunStatus`."""
    from forcenet.checks import checked_system
    from forcenet.cost import simulation_cost

    records = records_folder(config)
    manifest = read_manifest(records) if records else []
    excluded = excluded_runs(records)
    tabled = tabled_cpu_hours()
    statuses = []
    for system in config["systems"]:
        spec = checked_system(system, config)
        if isinstance(spec, ImportedSystem):
            continue
        fingerprint = simulation_sha256(config, system)
        recorded = {row["realization"]: row for row in manifest if row["system"] == system}
        measured = [float(row["cpu_hours"]) for row in recorded.values() if row["simulation_sha256"] == fingerprint]
        base = _same_size_base(config, system)
        based = [float(row["cpu_hours"]) for row in manifest if base and row["system"] == base]
        if measured:
            estimate, basis = sum(measured) / len(measured), "mean of recorded runs"
        elif system in tabled:
            estimate, basis = tabled[system], "mean in the committed tables' provenance"
        elif based:
            estimate, basis = sum(based) / len(based), f"mean of the recorded runs of {base} (same size and grid)"
        else:
            estimate, basis = simulation_cost(spec).core_hours, "cost model (errs long)"
        for index in realization_indices(config, system):
            name = paths.realization_name(index)
            row = recorded.get(name)
            if row is not None and row["simulation_sha256"] == fingerprint:
                statuses.append(RunStatus(system, name, "recorded", float(row["cpu_hours"]), 0.0))
                continue
            stale = "" if row is None else "its record has other settings (remake it)"
            why = excluded.get((system, name))
            cost_path = Path(paths.run_cost(results, system, name))
            stage = Path(paths.run_dir(results, system, name)) / paths.STAGING_DIR
            if cost_path.exists():
                done = float(json.loads(cost_path.read_text())["cpu_seconds"]) / 3600
                statuses.append(RunStatus(system, name, "finished", done, 0.0,
                                          stale or "not recorded: forcenet-campaign record " + f"{system} {name}"))
            elif why and not (stage.exists() and _stage_is_held(results, system, name)):  # made elsewhere, if at all
                statuses.append(RunStatus(system, name, "excluded", 0.0, 0.0, f"{why} (estimate {estimate:.2f} h)"))
            elif stage.exists():
                staged = len(list(stage.glob("rho*.nc")))
                held = _stage_is_held(results, system, name)
                left = estimate * (1 - staged / len(spec.rho_grid))
                statuses.append(RunStatus(system, name, "running" if held else "stopped", 0.0, left,
                                          f"{staged} of {len(spec.rho_grid)} states; {stale}".rstrip("; ")))
            else:
                detail = stale or f"estimate: {basis}"
                statuses.append(RunStatus(system, name, "missing", 0.0, estimate, detail))
    return statuses


def _same_size_base(config: Mapping[str, Any], system: str) -> str | None:
    """The catalog system `system` is a variant of (``system_info.<name>.like``) when the two share their size,
    start and ρ grid (so a run of one costs about what a run of the other does), else None."""
    base = config.get("system_info", {}).get(system, {}).get("like")
    entries = config["systems"]
    if base is None:
        return None
    if base not in entries:  # the base is not run by this config: its entry from the catalog's files
        from forcenet.catalog import catalog_files, read_catalog, resolve_entry

        base_entry = resolve_entry(base, read_catalog(catalog_files(config))[1])
    else:
        base_entry = entries[base]
    same = all(base_entry.get(key) == entries[system].get(key) for key in ("box_length", "initial_state", "rho"))
    return base if same else None


def status_table(statuses: Sequence[RunStatus]) -> str:
    """The status as text: one line per run, then the totals."""
    lines = [f"{'system':<20} {'run':<4} {'state':<9} {'CPU-h done':>10} {'CPU-h to go':>11}  detail"]
    for s in statuses:
        lines.append(f"{s.system:<20} {s.realization:<4} {s.state:<9} {s.cpu_hours_done:>10.2f} "
                     f"{s.cpu_hours_to_go:>11.2f}  {s.detail}")
    counts = {state: sum(s.state == state for s in statuses)
              for state in ("recorded", "finished", "running", "stopped", "missing", "excluded")}
    lines.append(", ".join(f"{n} {state}" for state, n in counts.items())
                 + f"; CPU-hours done {sum(s.cpu_hours_done for s in statuses):.2f}, "
                 f"to go {sum(s.cpu_hours_to_go for s in statuses):.2f}")
    return "\n".join(lines)


def verify_records(config: Mapping[str, Any]) -> list[str]:
    """Problems of the config's records: a manifest row whose file is missing or has another sha256, a record of a
    system the config does not have or of other settings. Empty: every record can be restored."""
    records = records_folder(config)
    if records is None:
        return ["the config has no records_dir"]
    problems = []
    for row in read_manifest(records):
        path = Path(records) / row["file"]
        if not path.exists():
            problems.append(f"{path}: missing")
        elif file_sha256(path) != row["sha256"]:
            problems.append(f"{path}: sha256 differs from the manifest's")
        if row["system"] not in config["systems"]:
            problems.append(f"{path}: system '{row['system']}' is not in the config")
        elif row["simulation_sha256"] != simulation_sha256(config, row["system"]):
            problems.append(f"{path}: made under other settings of '{row['system']}' than the config's")
    return problems


def recode_records(config: Mapping[str, Any], say: Callable[[str], None] = print) -> list[dict[str, str]]:
    """Rewrite every record of an earlier layout in this forcenet's (`forcenet.datasets.records.recoded_record`: the
    same values, bit for bit, checked) and update its manifest row (bytes, sha256); the rows rewritten. A record's
    fingerprint, commit and CPU time stay: it is the same run."""
    import xarray as xr

    from forcenet.datasets import write_netcdf
    from forcenet.datasets.records import record_encoding, recoded_record

    records = records_folder(config)
    if records is None:
        raise CampaignError("the config has no records_dir")
    rewritten = []
    with _manifest_lock(records):
        rows = read_manifest(records)
        for row in rows:
            path = Path(records) / row["file"]
            if file_sha256(path) != row["sha256"]:
                raise CampaignError(f"{path}: sha256 differs from the manifest's; restore it from git first")
            with xr.open_dataset(path) as opened:
                record = opened.load()
            recoded = recoded_record(record)
            if recoded is record:
                continue
            kind = "p2_run_record" if path.name == paths.P2_RECORD_FILE else "run_record"
            write_netcdf(recoded, path, kind=kind, encoding=record_encoding(recoded))
            say(f"{row['file']}: {record.attrs['record_format']} -> {recoded.attrs['record_format']}, "
                f"{int(row['bytes']) / 1e6:.2f} -> {path.stat().st_size / 1e6:.2f} MB")
            row.update(bytes=str(path.stat().st_size), sha256=file_sha256(path))
            rewritten.append(row)
        write_manifest(records, rows)
    return rewritten


def drop_record(config: Mapping[str, Any], system: str, realization: str) -> Path:
    """Remove a run's record and manifest row (the run is then simulated again)."""
    records = records_folder(config)
    if records is None:
        raise CampaignError("the config has no records_dir")
    with _manifest_lock(records):
        row = manifest_row(records, system, realization)
        (Path(records) / row["file"]).unlink(missing_ok=True)
        write_manifest(records, [r for r in read_manifest(records)
                                 if (r["system"], r["realization"]) != (system, realization)])
    return Path(records) / row["file"]


#: the lines of the records folder's README.md between which `write_size_table` keeps the table of sizes
SIZE_TABLE_START, SIZE_TABLE_END = "<!-- size table: forcenet-campaign record writes it -->", "<!-- end of size table -->"


def size_table(config: Mapping[str, Any]) -> str:
    """Markdown: per system of the config, its recorded runs of all, their bytes and the bytes all its runs would
    take at the mean of those recorded; then the totals."""
    from forcenet.checks import checked_system

    records = records_folder(config)
    manifest = read_manifest(records) if records else []
    lines = ["| system | runs recorded | MB recorded | MB per run | MB when all are recorded |", "|---|---|---|---|---|"]
    total = projected_total = 0.0
    for system in config["systems"]:
        if isinstance(checked_system(system, config), ImportedSystem):
            continue
        rows = [row for row in manifest if row["system"] == system]
        count = len(realization_indices(config, system))
        size = sum(int(row["bytes"]) for row in rows) / 1e6
        per_run = size / len(rows) if rows else float("nan")
        projected = per_run * count
        total += size
        projected_total += projected if rows else 0.0
        lines.append(f"| {system} | {len(rows)} of {count} | {size:.1f} | "
                     + (f"{per_run:.2f} | {projected:.1f} |" if rows else "– | – |"))
    lines.append(f"| all | {len(manifest)} | {total:.1f} | | {projected_total:.1f} (systems with a record) |")
    return "\n".join(lines)


def write_size_table(config: Mapping[str, Any]) -> Path | None:
    """Replace the size table in the records folder's README.md (between `SIZE_TABLE_START` and `SIZE_TABLE_END`);
    None when the README has no such table."""
    readme = Path(records_folder(config) or ".") / "README.md"
    if not readme.exists():
        return None
    text = readme.read_text()
    head, start, rest = text.partition(SIZE_TABLE_START)
    _, end, tail = rest.partition(SIZE_TABLE_END)
    if not start or not end:
        return None
    readme.write_text(f"{head}{start}\n{size_table(config)}\n{end}{tail}")
    return readme
