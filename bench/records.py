"""The record a benchmark run leaves: `bench/results/<benchmark>[-<variant>].json`, the latest run only.

A record holds what was measured and where: the machine (CPU model, cores, the cores the run was pinned to, OS,
python, numpy and numba versions, the load average before and after the run), the git commit and whether the
tree had uncommitted changes, the UTC date, the command line, the settings, the measured figures and the peer's
figures from the same run (LAMMPS, where a benchmark has a peer). A benchmark that cannot run here (LAMMPS cannot be
installed, no build's results to read) leaves a record with ``"status": "not measured"`` and the reason, so the
performance page says so instead of quoting an older figure. `bench/report.py` builds the tables of
docs/performance.md from these records.

Use (from a script in bench/, which has bench/ on sys.path)::

    run = records.Run("dem_scaling", variant="2d", settings=vars(args))   # at the start: load, date
    ...
    run.write(measured={...}, peer={"name": "LAMMPS ...", "figures": {...}})   # or run.not_measured(reason)

The file is replaced atomically. A run with ``--no-record`` (every benchmark has it), or a benchmark's
``main(argv)`` called from Python with explicit arguments (tests), writes nothing (`wanted`).
"""
from __future__ import annotations

import json
import os
import platform
import subprocess
import sys
import tempfile
from datetime import datetime, timezone
from pathlib import Path

HERE = Path(__file__).resolve().parent
REPO = HERE.parent
RESULTS = HERE / "results"
SCHEMA = 1
REQUIRED_KEYS = ("schema", "benchmark", "variant", "status", "reason", "date", "commit", "dirty", "dirty_files",
                 "command", "machine", "settings", "measured", "peer")
MACHINE_KEYS = ("cpu", "cores", "affinity", "memory_gib", "os", "python", "numpy", "numba", "load_before",
                "load_after")


def record_name(benchmark: str, variant: str | None = None) -> str:
    """File stem of a benchmark's record: ``dem_scaling-2d``, ``analysis``."""
    return f"{benchmark}-{variant}" if variant else benchmark


def cpu_model() -> str:
    """The CPU's model name from /proc/cpuinfo (platform.processor() elsewhere)."""
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or platform.machine()


def memory_gib() -> float | None:
    try:
        for line in Path("/proc/meminfo").read_text().splitlines():
            if line.startswith("MemTotal:"):
                return round(int(line.split()[1]) / 2**20, 1)
    except (OSError, ValueError, IndexError):
        pass
    return None


def _version(module: str) -> str | None:
    try:
        from importlib.metadata import version
        return version(module)
    except Exception:  # noqa: BLE001  (not installed)
        return None


def load_average() -> list[float] | None:
    try:
        return [round(x, 2) for x in os.getloadavg()]
    except OSError:
        return None


def machine(load_before: list[float] | None = None) -> dict:
    """The machine as a record describes it (the load average now is `load_after`)."""
    try:
        affinity = sorted(os.sched_getaffinity(0))
    except AttributeError:
        affinity = None
    return dict(cpu=cpu_model(), cores=os.cpu_count(), affinity=affinity, memory_gib=memory_gib(),
                os=platform.platform(), python=platform.python_version(), numpy=_version("numpy"),
                numba=_version("numba"), load_before=load_before, load_after=load_average())


def git_state(repo: Path = REPO) -> tuple[str | None, bool | None, list[str]]:
    """(commit, whether tracked files differ from it, those files) of the checkout; (None, None, []) outside git."""
    def git(*args: str) -> str:
        return subprocess.run(["git", "-C", str(repo), *args], capture_output=True, text=True, check=True).stdout
    try:
        commit = git("rev-parse", "HEAD").strip()
        changed = [line[3:] for line in git("status", "--porcelain", "--untracked-files=no").splitlines()]
    except (OSError, subprocess.CalledProcessError):
        return None, None, []
    return commit, bool(changed), sorted(changed)


def command_line(argv: list[str] | None = None) -> str:
    """The command as run from the repository root: ``bench/dem_scaling.py --dim 2 …``."""
    argv = list(sys.argv if argv is None else argv)
    script = Path(argv[0]).resolve() if argv else None
    if script is not None and script.is_relative_to(REPO):
        argv[0] = str(script.relative_to(REPO))
    return " ".join(argv)


def _plain(value):
    """JSON-ready copy (Paths and tuples to str and lists, numpy scalars to Python numbers)."""
    if isinstance(value, dict):
        return {str(k): _plain(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_plain(v) for v in value]
    if isinstance(value, Path):
        return str(value)
    if hasattr(value, "item") and callable(value.item):  # numpy scalar
        return value.item()
    return value


def make_record(benchmark: str, *, variant: str | None = None, measured: dict | None = None,
                peer: dict | None = None, settings: dict | None = None, status: str = "measured",
                reason: str | None = None, load_before: list[float] | None = None, date: str | None = None,
                command: str | None = None, git: tuple | None = None) -> dict:
    """The record of one run; `date`, `command` and `git` (commit, dirty, dirty files) default to now's."""
    commit, dirty, dirty_files = git or git_state()
    return _plain(dict(
        schema=SCHEMA, benchmark=benchmark, variant=variant, status=status, reason=reason,
        date=date or datetime.now(timezone.utc).strftime("%Y-%m-%dT%H:%M:%SZ"),
        commit=commit, dirty=dirty, dirty_files=dirty_files, command=command or command_line(),
        machine=machine(load_before), settings=settings or {}, measured=measured or {}, peer=peer))


def write_record(record: dict, results: Path | None = None) -> Path:
    """Write `record` as results/<benchmark>[-<variant>].json (results: bench/results/), atomically (temporary
    file, then rename)."""
    results = RESULTS if results is None else results
    results.mkdir(parents=True, exist_ok=True)
    path = results / f"{record_name(record['benchmark'], record['variant'])}.json"
    with tempfile.NamedTemporaryFile("w", dir=results, prefix=f".{path.stem}.", suffix=".tmp", delete=False,
                                     encoding="utf-8") as handle:
        json.dump(record, handle, indent=1, ensure_ascii=False)
        handle.write("\n")
    os.replace(handle.name, path)
    return path


def read_records(results: Path | None = None) -> dict[str, dict]:
    """{file stem: record} of every record under `results` (bench/results/)."""
    results = RESULTS if results is None else results
    return {path.stem: json.loads(path.read_text(encoding="utf-8")) for path in sorted(results.glob("*.json"))}


class Run:
    """One benchmark run: notes the load, date and commit at the start (the code the run measures);
    `write` or `not_measured` leaves its record."""

    def __init__(self, benchmark: str, *, variant: str | None = None, settings: dict | None = None,
                 enabled: bool = True, results: Path | None = None):
        self.benchmark, self.variant, self.settings = benchmark, variant, settings or {}
        self.enabled, self.results = enabled, results
        self.load_before = load_average()
        self.date = datetime.now(timezone.utc).strftime("%Y-%m-%dT%H:%M:%SZ")
        self.command = command_line()
        self.git = git_state()

    def _write(self, **fields) -> Path | None:
        if not self.enabled:
            return None
        record = make_record(self.benchmark, variant=self.variant, settings=self.settings,
                             load_before=self.load_before, date=self.date, command=self.command, git=self.git,
                             **fields)
        path = write_record(record, self.results)
        print(f"record: {path.relative_to(REPO) if path.is_relative_to(REPO) else path}", file=sys.stderr)
        return path

    def write(self, measured: dict, peer: dict | None = None) -> Path | None:
        return self._write(measured=measured, peer=peer)

    def not_measured(self, reason: str, peer: dict | None = None) -> Path | None:
        return self._write(status="not measured", reason=reason, peer=peer)


def wanted(args, argv) -> bool:
    """Whether a benchmark's `main(argv)` writes its record: run from the command line (argv None) without
    ``--no-record``. A call with explicit arguments from Python (a test) leaves the committed records alone."""
    return argv is None and not getattr(args, "no_record", False)


def add_no_record(parser) -> None:
    """The `--no-record` option every benchmark has."""
    parser.add_argument("--no-record", action="store_true",
                        help="do not write the run's record under bench/results/")
