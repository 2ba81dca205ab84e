"""`forcenet-campaign`: the validation campaign's runs, recorded one by one (`forcenet.campaign`).

    forcenet-campaign status                          every run: recorded / finished / running / stopped / missing
    forcenet-campaign record SYSTEM REALIZATION       a finished run's record (--commit: and its git commit)
    forcenet-campaign record --finished               every finished run without a record
    forcenet-campaign run --jobs 2 --hours 2.5        the missing runs, one core each, niced, each recorded as it lands
                      [--first SYSTEM …] [--only SYSTEM[:rNN] …] [--commit]
    forcenet-campaign verify                          every record against the manifest and the config
    forcenet-campaign sizes [--write]                 the records' size per system [written into its README]
    forcenet-campaign drop SYSTEM REALIZATION         remove a record (the run is simulated again)
    forcenet-campaign recode [--commit]               rewrite records of an earlier layout in this one (same values)

`run` stops its runs when it is stopped (Ctrl-C or SIGTERM; a run started with `nohup … &` from a script ignores
Ctrl-C, so stop it with `kill PID`): each run is left resumable from its checkpoint, none half-recorded.

Every command reads config/validation.yaml unless given --configfile, from the repository root.
"""
from __future__ import annotations

import argparse
import signal
import subprocess
import sys
import time
from pathlib import Path
from typing import Any, Callable, Mapping, Sequence

from forcenet.campaign import (DEFAULT_CAMPAIGN_CONFIG, RunStatus, campaign_status, drop_record, p2_system,
                               recode_records, record_run, recorded_row, records_folder, size_table, status_table,
                               verify_records, write_size_table)
from forcenet.datasets import paths
from forcenet.errors import ForcenetError

#: how much longer than its estimate a run may take before `run_missing` counts it as not finishing in time: the
#: estimates come from the machine that made the committed tables or the records, and a run shares its machine
DEFAULT_MARGIN = 1.5
#: seconds between two looks at the runs in progress
POLL_SECONDS = 30.0
#: seconds a stopped run has to end before it is killed
STOP_GRACE_SECONDS = 60.0


def commit_records(records: str, rows: Sequence[Mapping[str, str]], message: str | None = None) -> None:
    """git-commit the records of `rows`, the manifest and the folder's README (its size table), and nothing else
    that is staged (a path-limited commit); `message` replaces the default one, which names the runs."""
    files = [str(Path(records) / row["file"]) for row in rows] + [paths.record_manifest(records)]
    readme = Path(records) / "README.md"
    files += [str(readme)] if readme.exists() else []
    runs = ", ".join(f"{row['system']} {row['realization']}" for row in rows)
    hours = sum(float(row["cpu_hours"]) for row in rows)
    message = message or f"data/validation: campaign record of {runs} ({hours:.2f} CPU-hours)"
    for attempt in range(10):  # another git process (a developer's commit) may hold the index for a moment
        added = subprocess.run(["git", "add", "--", *files], capture_output=True, text=True)
        if added.returncode == 0:
            done = subprocess.run(["git", "commit", "-q", "-m", message, "--", *files], capture_output=True, text=True)
            if done.returncode == 0:
                return
            added = done
        if "index.lock" not in added.stderr:
            raise ForcenetError(f"git could not commit the records of {runs}: {added.stderr.strip()}")
        time.sleep(2.0 * (attempt + 1))
    raise ForcenetError(f"git could not commit the records of {runs}: the index stayed locked")


def simulation_command(configfile: str, results: str, status: RunStatus, p2: bool = False) -> list[str]:
    """The niced one-core Snakemake call that makes one run (its cost record is the target, or with `p2` the run's
    summary, which its P2 run record holds: the run and its analyses; --nolock, since the runs of one campaign run
    side by side in one folder and each holds its own stage lock)."""
    target = (paths.p2_run if p2 else paths.run_cost)(results, status.system, status.realization)
    return ["nice", "-n", "10", sys.executable, "-m", "snakemake", target, "--configfile", configfile, "--cores", "1",
            "--nolock"]


def run_missing(config: Mapping[str, Any], *, configfile: str, results: str, jobs: int = 2,
                hours: float | None = None, margin: float = DEFAULT_MARGIN, systems: Sequence[str] = (),
                only: Sequence[str] = (), commit: bool = False, say: Callable[[str], None] = print,
                start: Callable[[list[str], Path], subprocess.Popen] | None = None) -> list[dict[str, str]]:
    """Make the missing (and resume the stopped) runs of `config`, `jobs` at a time, each recorded (and committed
    with `commit`) as soon as it finishes; the records' rows, in the order they landed.

    Order: the runs of `systems` first, in that order, then the config's. With `only` (SYSTEM or SYSTEM:rNN
    items) no other run is recorded or started: another process may be making the others. A run is started only if its estimate
    (`RunStatus.cpu_hours_to_go`) times `margin` fits in the `hours` left of the budget, so no run is begun that
    cannot finish; one that is not started is named with its estimate. A finished run without a record is recorded
    first. A run that fails is named with its log and the others go on. A P2 system's run is made with its
    analyses and summary, what its record holds (`forcenet.campaign.p2_system`)."""
    start = start or (lambda command, log: subprocess.Popen(command, stdout=open(log, "a"), stderr=subprocess.STDOUT))
    deadline = None if hours is None else time.time() + 3600.0 * hours
    statuses = [s for s in campaign_status(config, results=results)
                if not only or s.system in only or f"{s.system}:{s.realization}" in only]
    rows = []

    def land(system: str, realization: str) -> None:
        if recorded_row(config, records_folder(config), system, realization) is not None:
            say(f"already recorded: {system} {realization} (its record kept)")
            return
        row = record_run(config, system, realization, results=results)
        write_size_table(config)
        if commit:
            commit_records(records_folder(config), [row])
        rows.append(row)
        say(f"recorded {system} {realization}: {row['file']} ({int(row['bytes']) / 1e6:.2f} MB, "
            f"{float(row['cpu_hours']):.2f} CPU-hours){' and committed' if commit else ''}")

    for status in statuses:
        if status.state == "finished":
            land(status.system, status.realization)
    rank = {name: index for index, name in enumerate(systems)}
    queue = sorted((s for s in statuses if s.state in ("missing", "stopped")),
                   key=lambda s: rank.get(s.system, len(rank)))
    running: dict[subprocess.Popen, RunStatus] = {}
    try:
        _make_runs(config, results, configfile, queue, running, jobs, deadline, margin, rows, land, say, start)
    finally:  # stopped (Ctrl-C, SIGTERM): stop the runs too, each left resumable from its checkpoint
        _stop_runs(running, say)
    return rows


def _make_runs(config, results, configfile, queue, running, jobs, deadline, margin, rows, land, say, start) -> None:
    """The loop of `run_missing`: start runs while cores are free and time is left, land each that finishes."""
    while queue or running:
        if rows:  # the estimates follow the runs recorded meanwhile (the mean of a system's recorded runs)
            fresh = {(s.system, s.realization): s for s in campaign_status(config, results=results)}
            queue = [fresh.get((s.system, s.realization), s) for s in queue]
        while queue and len(running) < jobs:
            status = queue.pop(0)
            status = next((s for s in campaign_status(config, results=results)
                           if (s.system, s.realization) == (status.system, status.realization)), status)
            if status.state not in ("missing", "stopped"):  # another runner took it meanwhile
                say(f"skipped: {status.system} {status.realization} is {status.state} (another process)")
                continue
            needed = status.cpu_hours_to_go * margin
            left = None if deadline is None else (deadline - time.time()) / 3600.0
            if left is not None and needed > left:
                say(f"not started: {status.system} {status.realization} needs about {needed:.2f} h "
                    f"({status.cpu_hours_to_go:.2f} × {margin}), {left:.2f} h left")
                continue
            log = Path(paths.run_log(results, "campaign", status.system, status.realization))
            log.parent.mkdir(parents=True, exist_ok=True)
            running[start(simulation_command(configfile, results, status, p2_system(config, status.system)),
                           log)] = status
            say(f"started {status.system} {status.realization} ({status.state}; about {status.cpu_hours_to_go:.2f} "
                f"CPU-hours; log {log})")
        if not running:
            break
        time.sleep(POLL_SECONDS if all(p.poll() is None for p in running) else 0)
        for process in [p for p in running if p.poll() is not None]:
            status = running.pop(process)
            if process.returncode == 0:
                land(status.system, status.realization)
            else:
                say(f"failed: {status.system} {status.realization} (exit {process.returncode}; its job log: "
                    f"{paths.run_log(results, 'simulate', status.system, status.realization)})")


def _stop_runs(running: Mapping[subprocess.Popen, RunStatus], say: Callable[[str], None],
               grace: float = STOP_GRACE_SECONDS) -> None:
    """Stop the runs still in progress (SIGTERM: Snakemake stops its job, which keeps its checkpoint), then kill any
    that outlives `grace` seconds; each is named."""
    live = [process for process in running if process.poll() is None]
    for process in live:
        process.terminate()
    for process in live:
        try:
            process.wait(timeout=grace)
        except subprocess.TimeoutExpired:
            process.kill()
            process.wait()
        status = running[process]
        say(f"stopped {status.system} {status.realization} (resumes from its checkpoint)")


def _terminate(signum: int, frame: Any) -> None:
    raise SystemExit(128 + signum)


def load_config(path: str) -> dict[str, Any]:
    """A campaign config, checked as the workflow checks it (schema, systems, physics)."""
    import forcenet
    from forcenet.workflow_io import CONFIG_SCHEMA, checked_config, read_config_file

    config = read_config_file(path)
    checked_config(config, Path(forcenet.__file__).resolve().parents[2] / CONFIG_SCHEMA)
    return config


def main(argv: Sequence[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="forcenet-campaign", description=__doc__.split("\n\n")[0],
                                     formatter_class=argparse.RawDescriptionHelpFormatter, epilog=__doc__)
    parser.add_argument("--configfile", default=DEFAULT_CAMPAIGN_CONFIG, help="the campaign config (%(default)s)")
    parser.add_argument("--results", help="the results folder the runs were made in (default: the config's "
                                          "results_dir; another checkout's, e.g. a worktree running the campaign)")
    commands = parser.add_subparsers(dest="command", required=True)
    commands.add_parser("status", help="every run of the config: recorded / finished / running / stopped / missing")
    record = commands.add_parser("record", help="record finished runs in the config's records_dir")
    record.add_argument("run", nargs="*", help="SYSTEM REALIZATION (e.g. 2d_linear r00)")
    record.add_argument("--finished", action="store_true", help="every finished run without a record")
    record.add_argument("--commit", action="store_true", help="git-commit the records and the manifest")
    record.add_argument("--replace", action="store_true",
                        help="record a run again that already has an intact record of the same settings")
    run = commands.add_parser("run", help="make the missing runs, each recorded as it finishes")
    run.add_argument("--jobs", type=int, default=2, help="runs side by side, one core each (%(default)s)")
    run.add_argument("--hours", type=float, help="time budget: start no run that would not finish within it")
    run.add_argument("--margin", type=float, default=DEFAULT_MARGIN,
                     help="a run may take this times its estimate (%(default)s)")
    run.add_argument("--first", nargs="*", default=[], metavar="SYSTEM", help="these systems' runs first, in order")
    run.add_argument("--only", nargs="*", default=[], metavar="SYSTEM[:rNN]",
                     help="these systems or runs alone (another process makes the others)")
    run.add_argument("--commit", action="store_true", help="git-commit each record as it lands")
    commands.add_parser("verify", help="every record against the manifest and the config")
    sizes = commands.add_parser("sizes", help="the records' size per system (the table of the records folder's README)")
    sizes.add_argument("--write", action="store_true", help="also write it into the records folder's README")
    drop = commands.add_parser("drop", help="remove a run's record (it is simulated again)")
    drop.add_argument("system")
    drop.add_argument("realization")
    recode = commands.add_parser("recode", help="rewrite the records of an earlier layout in this forcenet's "
                                                "(every value kept bit for bit)")
    recode.add_argument("--commit", action="store_true", help="git-commit the rewritten records")
    args = parser.parse_args(argv)
    try:
        config = load_config(args.configfile)
        from forcenet.workflow_io import resolve_results_dir

        results = args.results or resolve_results_dir(config.get("results_dir"), Path.cwd())[0]
        if args.command == "status":
            print(status_table(campaign_status(config, results=results)))
        elif args.command == "verify":
            problems = verify_records(config)
            print("\n".join(problems) or f"every record of {records_folder(config)} can be restored")
            return 1 if problems else 0
        elif args.command == "sizes":
            print(size_table(config))
            if args.write and write_size_table(config) is None:
                raise ForcenetError(f"{records_folder(config)}/README.md has no size table to write")
        elif args.command == "drop":
            print(f"removed {drop_record(config, args.system, args.realization)}")
        elif args.command == "recode":
            rows = recode_records(config)
            if rows:
                write_size_table(config)
            if args.commit and rows:
                commit_records(records_folder(config), rows, f"data/validation: {len(rows)} records rewritten "
                                                             "in the current layout (same values)")
            print(f"{len(rows)} records rewritten")
        elif args.command == "run":
            signal.signal(signal.SIGTERM, _terminate)  # `kill PID` stops the runs as Ctrl-C does
            run_missing(config, configfile=args.configfile, results=results, jobs=args.jobs, hours=args.hours,
                        margin=args.margin, systems=args.first, only=args.only, commit=args.commit,
                        say=lambda line: print(f"{time.strftime('%H:%M:%S')} {line}", flush=True))
        else:
            if args.finished == bool(args.run) or (args.run and len(args.run) != 2):
                parser.error("record takes SYSTEM REALIZATION or --finished")
            runs = ([(s.system, s.realization) for s in campaign_status(config, results=results)
                     if s.state == "finished"] if args.finished else [tuple(args.run)])
            rows = []
            for system, realization in runs:
                if not args.replace and recorded_row(config, records_folder(config), system, realization):
                    print(f"already recorded: {system} {realization} (--replace records it again)")
                    continue
                row = record_run(config, system, realization, results=results, replace=args.replace)
                print(f"recorded {system} {realization}: {row['file']} ({int(row['bytes']) / 1e6:.2f} MB, "
                      f"{row['cpu_hours']} CPU-hours)")
                rows.append(row)
            if rows:
                write_size_table(config)
            if args.commit and rows:
                commit_records(records_folder(config), rows)
    except ForcenetError as error:
        print(f"forcenet-campaign: {error}", file=sys.stderr)
        return 2
    return 0


if __name__ == "__main__":
    sys.exit(main())
