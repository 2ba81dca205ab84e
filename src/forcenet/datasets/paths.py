"""Every file name a build reads or writes, defined once: the layout of a results folder and of the campaign tables.

Each function takes the results folder (the config's ``results_dir``, "results" by default, or a Path) and the
file's wildcards, and returns its path as a string. A wildcard passed as a Snakemake pattern comes back as that pattern
(``snapshot("results", "2d_hertz", "{realization}", "0.840")`` is ``results/sim/2d_hertz/{realization}/rho0.840.nc``),
so the rules of ``workflow/rules/*.smk`` declare their inputs, outputs and logs with these same functions that the
scripts, tests and tutorial use to find a file. Imported when the workflow is parsed: standard library only.

``{results}/`` holds (netCDF kinds are those of `forcenet.datasets.schema`)::

    config/resolved.yaml                     every system in reduced units with its ρ grid (rule resolved_config)
    sim/{system}/{realization}/rho{ρ}.nc     snapshot (DEM or imported), kind "snapshot": positions, radii, contacts, forces
    sim/{system}/{realization}/run_cost.json what the compression run cost (CPU seconds, particles, snapshots)
    sim/{system}/{realization}/.partial/     a run in progress: its snapshots so far and checkpoint.npz
    analysis/{system}/{realization}/rho{ρ}.nc  analysis of one snapshot, kind "analysis"
    {system}/network_measures.nc             the analyses stacked over (realization, ρ), kind "network_measures"
    {system}/diagrams.nc                     every persistence point of the system, kind "diagrams"
    {system}/distances.nc                    P2's d_B, d_W1, d_W2 between consecutive states, kind "distances"
    {system}/p2_runs/{realization}.nc        what P2's products read from one run, its diagrams apart, kind "p2_run"
    figures/{figure}.{pdf,png,csv}           one figure of `forcenet.plotting.registry` and the values it draws
    tables/p1_validation.{csv,md}            P1's numbers and claims beside ours
    tables/p2_table{1,2,3}.{csv,md}          P2 Tables I–III
    tables/p2_table_states.csv               which realization's states a, b, c make Tables I–III and Figs 1, 3
    tables/p2_validation.{csv,md}            every P2 claim with its evidence and verdict
    tables/skipped.md                        the figures, movies and tables a build leaves out, and why
    movies/{kind}_{system}.mp4               compression movies of the P1 systems (kind: network, b0_surface)
    logs/{step}/{name}.log                   one log per job: simulate and analyze {system}/{realization}, …
    readings/{reading}                       a reading beside (another value of one convention), laid out as above

and ``docs/validation/{p1,p2}.{md,csv}`` (in the repository, not under a results folder) are the validation
campaign's committed tables. A config with ``records_dir`` (config/validation.yaml: ``data/validation``) keeps the
campaign's finished runs there, in the repository (`forcenet.campaign`)::

    manifest.csv                             one row per recorded run: fingerprint, commit, CPU-hours, sha256
    {system}/{realization}/states.nc         the run's snapshots, kind "run_record" (`forcenet.datasets.records`)
    {system}/{realization}/p2_run.nc         a P2 run's summary and the states Tables I-III read, kind "p2_run_record"

A state of an imported sequence (`forcenet.importers.sequence`) is ``state{k}.nc`` (k = 000, 001, …,
`state_labels`) where a compression's is ``rho{ρ}.nc`` (`rho_file`). A realization is named ``r{NN}``
(`realization_name`, `realization_index`); a ρ label has `RHO_DECIMALS` decimals (`format_rho`).
"""
from __future__ import annotations

import os
from pathlib import Path

#: a results folder: "results", or a Path
Folder = str | os.PathLike

#: ρ values are written into file names with this many decimals (results/sim/…/rho0.842.nc)
RHO_DECIMALS = 3

#: the folder (below the results folder) that holds the DEM runs
SIM_DIR = "sim"
#: the folder of a run in progress (beside its outputs): Snakemake deletes the declared outputs of an interrupted
#: job, not this folder, so a rerun resumes from the checkpoint in it
STAGING_DIR = ".partial"
#: the DEM state a run in progress resumes from (in its staging folder)
CHECKPOINT = "checkpoint.npz"
#: the lock a run in progress holds (beside its staging folder, holding its pid; `forcenet.pipeline.exclusive_stage`)
STAGE_LOCK = STAGING_DIR + ".lock"
#: a campaign record's file name (one per run) and the manifest of all (below a config's ``records_dir``)
RECORD_FILE = "states.nc"
#: a P2 run's campaign record (`forcenet.datasets.records.p2_record_dataset`)
P2_RECORD_FILE = "p2_run.nc"
RECORD_MANIFEST = "manifest.csv"
EXCLUDED_RUNS = "excluded.csv"
#: the validation campaign's committed tables (in the repository): validation_report writes them, every other
#: config reads them (config key ``paper_size_tables``)
VALIDATION_DIR = "docs/validation"
#: the formats each figure is written in: vector PDF, PNG (shown in the HTML report) and the CSV of its values
FIGURE_FORMATS = ("pdf", "png", "csv")
#: the folder (below the results folder) that holds the readings beside, each laid out as a results folder
READINGS_DIR = "readings"
#: the numbers of P2's Tables I–III
P2_TABLE_NUMBERS = (1, 2, 3)


def realization_name(index: int) -> str:
    """The name of realization `index` in paths and wildcards: ``r00``, ``r01``, …"""
    return f"r{index:02d}"


def realization_index(name: str) -> int:
    """The index of a realization from its name: ``r03`` → 3."""
    return int(str(name).lstrip("r"))


def format_rho(rho: float) -> str:
    """The label of the state at packing fraction `rho` [-] in file names: `RHO_DECIMALS` decimals (``"0.842"``)."""
    return f"{rho:.{RHO_DECIMALS}f}"


def state_labels(count: int) -> list[str]:
    """The labels of a sequence's `count` states in file names: ``state000``, ``state001``, … (at least three
    digits)."""
    width = max(3, len(str(max(count - 1, 0))))
    return [f"state{k:0{width}d}" for k in range(count)]


def rho_file(rho_label: str) -> str:
    """The file name of one state of a run (snapshot or analysis): ``rho{ρ}.nc`` for the state at one ρ of a
    compression (`format_rho`), ``{label}.nc`` for a state of an imported sequence (its label ``state000``,
    ``state001``, …: `state_labels`)."""
    return f"{rho_label}.nc" if rho_label[:1].isalpha() else f"rho{rho_label}.nc"


def run_dir(results: Folder, system: str, realization: str) -> str:
    """The folder of one compression run: its snapshots and cost record."""
    return f"{results}/{SIM_DIR}/{system}/{realization}"


def snapshot(results: Folder, system: str, realization: str, rho_label: str) -> str:
    """One DEM snapshot (kind "snapshot")."""
    return f"{run_dir(results, system, realization)}/{rho_file(rho_label)}"


def record_file(records: Folder, system: str, realization: str) -> str:
    """The campaign record of one compression run (kind "run_record"), below a config's ``records_dir``."""
    return f"{records}/{system}/{realization}/{RECORD_FILE}"


def p2_record_file(records: Folder, system: str, realization: str) -> str:
    """The campaign record of one P2 compression run (kind "p2_run_record"), below a config's ``records_dir``."""
    return f"{records}/{system}/{realization}/{P2_RECORD_FILE}"


def excluded_runs(records: Folder) -> str:
    """The runs of a campaign that are not made on a workstation, each with its reason (`forcenet.campaign`)."""
    return f"{records}/{EXCLUDED_RUNS}"


def record_manifest(records: Folder) -> str:
    """The manifest of a campaign's records: one CSV row per recorded run (`forcenet.campaign.MANIFEST_COLUMNS`)."""
    return f"{records}/{RECORD_MANIFEST}"


def run_cost(results: Folder, system: str, realization: str) -> str:
    """CPU time and size of one compression run (JSON, written when the run completes)."""
    return f"{run_dir(results, system, realization)}/run_cost.json"


def staging_dir(output: str | os.PathLike) -> Path:
    """Where a run keeps its snapshots and checkpoint until it completes: the `STAGING_DIR` beside `output` (one of
    its snapshots)."""
    return Path(output).parent / STAGING_DIR


def analysis(results: Folder, system: str, realization: str, rho_label: str) -> str:
    """The analysis of one snapshot (kind "analysis")."""
    return f"{results}/analysis/{system}/{realization}/{rho_file(rho_label)}"


def network_measures(results: Folder, system: str) -> str:
    """One system's analyses stacked over (realization, ρ) (kind "network_measures")."""
    return f"{results}/{system}/network_measures.nc"


def diagrams(results: Folder, system: str) -> str:
    """Every persistence point of one system (kind "diagrams")."""
    return f"{results}/{system}/diagrams.nc"


def distances(results: Folder, system: str) -> str:
    """P2's distances between the diagrams of consecutive states of one system (kind "distances")."""
    return f"{results}/{system}/distances.nc"


def p2_run(results: Folder, system: str, realization: str) -> str:
    """What P2's products read from one run of a P2 system, its diagrams apart (kind "p2_run")."""
    return f"{results}/{system}/p2_runs/{realization}.nc"


def reading(results: Folder, name: str) -> str:
    """The results folder of one reading beside (`forcenet.pipeline.ReadingBeside.folder`): its analyses, measures,
    distances and tables have below it the names they have below `results`."""
    return f"{results}/{READINGS_DIR}/{name}"


def figure(results: Folder, figure_id: str, fmt: str) -> str:
    """One figure in one of `FIGURE_FORMATS`; `figure_id` is its id in `forcenet.plotting.registry`."""
    return f"{results}/figures/{figure_id}.{fmt}"


def table(results: Folder, name: str, fmt: str) -> str:
    """A table of the build: ``name`` is p1_validation, p2_table1 … p2_table3, p2_table_states or p2_validation;
    `fmt` csv or md (p2_table_states: csv only)."""
    return f"{results}/tables/{name}.{fmt}"


def p1_validation_table(results: Folder, fmt: str) -> str:
    """P1's numbers and claims beside ours (csv or md)."""
    return table(results, "p1_validation", fmt)


def p2_table(results: Folder, number: int, fmt: str) -> str:
    """P2 Table I, II or III (`number` 1, 2 or 3; csv or md)."""
    return table(results, f"p2_table{number}", fmt)


def p2_table_states(results: str) -> str:
    """Which realization's states a, b, c make P2 Tables I–III and Figs 1, 3, with every realization's score (CSV)."""
    return table(results, "p2_table_states", "csv")


def p2_validation_table(results: Folder, fmt: str) -> str:
    """Every P2 claim with its evidence and verdict (csv or md)."""
    return table(results, "p2_validation", fmt)


def skipped_products(results: Folder) -> str:
    """The products a build does not make, or makes for fewer systems, one line each (Markdown, in the report)."""
    return table(results, "skipped", "md")


def movie_name(kind: str, system: str) -> str:
    """The name of a compression movie (and of its rule, ``movie_{name}``): `kind` network or b0_surface."""
    return f"{kind}_{system}"


def movie(results: Folder, name: str) -> str:
    """One compression movie (MP4); `name` from `movie_name`."""
    return f"{results}/movies/{name}.mp4"


def resolved_config(results: str) -> str:
    """The config as the workflow understands it (YAML)."""
    return f"{results}/config/resolved.yaml"


def log(results: Folder, step: str, name: str) -> str:
    """The log of one job: `step` is the kind of job (simulate, import, analyze, aggregate, distances, figures,
    tables, movies) and `name` what it made (``{system}/{realization}`` for simulate, import and analyze, the system, the figure,
    table or movie name); ``log(results, "", "resolved_config")`` is the resolved config's."""
    return f"{results}/logs/{step + '/' if step else ''}{name}.log"


def run_log(results: Folder, step: str, system: str, realization: str) -> str:
    """The log of the job that simulates, imports or analyses (`step`) one run."""
    return log(results, step, f"{system}/{realization}")


def campaign_table(study: str, fmt: str, folder: Folder = VALIDATION_DIR) -> str:
    """A committed table of the validation campaign: `study` p1 or p2, `fmt` md or csv."""
    return f"{str(folder).rstrip('/')}/{study}.{fmt}"
