# Config loading and validation, paths and input functions. Runs at parse time, before any job: a bad config stops
# here with one line naming the file and line (YAML, a key given twice) or the key (NaN or infinity, JSON schema,
# then forcenet.checks: what a schema cannot see and the physical checks). Kept light (no numba/xarray imports) so a
# dry-run of thousands of jobs stays fast.
import sys
from pathlib import Path

from snakemake.exceptions import WorkflowError

sys.path.insert(0, str(Path(workflow.basedir) / "src"))  # works before `pip install -e .` too

from forcenet._digest import PACKAGE, sources_digest
from forcenet.datasets import paths  # every file name of the build (standard library only)
from forcenet.datasets.paths import realization_index
from forcenet.datasets.runs import simulation_params
from forcenet.errors import ForcenetError
from forcenet.pipeline import readings_beside, snapshot_analysis_params
from forcenet.systems import realization_indices
from forcenet.workflow_io import CONFIG_SCHEMA, DEFAULT_CONFIG, checked_config, read_config_file, resolve_results_dir

# The claim tables follow their judges: every rule that judges claims or makes P2's Tables I-III takes this digest of
# `src/forcenet/report/` as a param, so a changed judge reruns them (seconds to minutes). A change to the analysis
# code does not rerun the analyses (hours at the papers' sizes); each output records the commit that made it.
JUDGES_DIGEST = sources_digest(PACKAGE, ("report/*.py",))

# A config given with --configfile stands alone: the default is read only when none is given (Snakemake's
# `configfile:` directive would merge the given file onto the default, so a config could never drop a system, and a
# ρ grid given as {start, stop, count} would inherit the default's `step`).
if not workflow.overwrite_configfiles:
    _default_config = Path(workflow.basedir) / DEFAULT_CONFIG
    try:
        read_config_file(_default_config)  # names the file and line of a YAML error
    except ForcenetError as error:
        raise WorkflowError(str(error)) from None
    workflow.configfile(str(_default_config))
else:
    # Snakemake has read them already, keeping the last value of a key given twice: refuse that, naming file and line
    for _configfile in workflow.overwrite_configfiles:
        try:
            read_config_file(_configfile)
        except ForcenetError as error:
            raise WorkflowError(str(error)) from None
try:
    SYSTEMS = checked_config(config, Path(workflow.basedir) / CONFIG_SCHEMA)
    # resolved once, against the working directory (the repository root, or --directory); the recorded config
    # (every output's `config` attribute) holds the folder as the rules write it
    RESULTS, RESULTS_ABSOLUTE = resolve_results_dir(config.get("results_dir"), Path.cwd())
except ForcenetError as error:
    raise WorkflowError(f"Invalid config: {error}") from None
if "results_dir" in config:
    config["results_dir"] = RESULTS
print(f"forcenet: results_dir = {RESULTS_ABSOLUTE} (every output is written there)", file=sys.stderr)
# The committed tables of the validation campaign (docs/validation/, written by validation_report): their values
# stand beside the papers' in this build's validation tables. A config at the papers' sizes (validation.yaml,
# paper.yaml) sets null: its tables are the paper-size values and get no such column.
PAPER_SIZE_TABLES = config.get("paper_size_tables", paths.VALIDATION_DIR)
P1_SYSTEMS = list(config["studies"].get("p1", {}).get("systems", []))
P2_SYSTEMS = list(config["studies"].get("p2", {}).get("systems", []))
# P1's counterparts (the mu = 0 and box-size runs): only the friction and system-size claims judge them
P1_COUNTERPARTS = list(config["studies"].get("p1", {}).get("counterparts", []))
# imported sequences (source.sequence: states ordered by strain, time, frame or timestep at any rho,
# forcenet.importers.sequence): their measures are drawn against the coordinate; the products that compare states of
# a compression (P2's states a, b, c, P1's and P2's validation claims) are not made for them
SEQUENCES = [name for name, spec in SYSTEMS.items() if getattr(spec, "is_sequence", False)]
# the products this config does not make, or makes for fewer systems, each as one line: printed below once the rules
# are read and listed in tables/skipped.md (rule skipped_products)
SKIPPED = []


def realizations(system):
    """The realization names of `system` (r00, r01, …): `realizations` is one count for all or one per system."""
    return [paths.realization_name(r) for r in realization_indices(config, system)]


wildcard_constraints:
    system="|".join(SYSTEMS) or "NONE",
    realization=r"r\d\d+",
    rho=r"\d\.\d\d\d",


def paper_size_table(study):
    """The campaign table (docs/validation/{study}.csv) whose values the study's validation table sets beside the
    paper's, or None in a paper-size config."""
    return None if PAPER_SIZE_TABLES is None else paths.campaign_table(study, "csv", PAPER_SIZE_TABLES)


def paper_size_input(study):
    """Input function: the campaign table of `study` where it exists, so that a regenerated table rebuilds the
    validation table; nothing where it does not (its column then says "not yet run")."""
    def campaign_table(wildcards):
        path = paper_size_table(study)
        return [path] if path is not None and Path(path).exists() else []
    return campaign_table


def snapshot_path(system, realization, rho_label):
    return paths.snapshot(RESULTS, system, realization, rho_label)


def analysis_path(system, realization, rho_label):
    return paths.analysis(RESULTS, system, realization, rho_label)


def system_analyses(wildcards, results=None):
    """Every analysis file of one system (in `results`, a reading's folder, else RESULTS), realization-major (the
    order aggregate expects)."""
    spec = SYSTEMS[wildcards.system]
    return [paths.analysis(results or RESULTS, wildcards.system, r, rho)
            for r in realizations(wildcards.system) for rho in spec.rho_labels]


def realization_numbers(wildcards):
    """The realization indices (0, 1, …) of one system."""
    return [realization_index(r) for r in realizations(wildcards.system)]


# The readings beside (issue 25; forcenet.pipeline.readings_beside): the other value of three conventions, built
# from the same runs into {results}/readings/{folder}/ (paths.reading) and judged beside the config's own in the
# validation tables, a row for each claim it changes. tetrahedra: P1's 3D systems analysed again with the other
# analysis.fill_tetrahedra (analyze.smk); essential: P2's distances and Tables I-III with never-dying classes
# matched only with each other; table_states: P2's Tables I-III from the literal states (beside the jammed rule
# only; p2.smk).
READINGS = readings_beside(config)
READING_RESULTS = {key: paths.reading(RESULTS, reading.folder) for key, reading in READINGS.items()}


def system_params(system):
    """What a simulation depends on: its own entry, the material and the seed (not other systems)."""
    return simulation_params(config, system)


def simulation_runtime_minutes(spec):
    from forcenet.cost import simulation_cost

    return max(10, int(2 * simulation_cost(spec).core_hours * 60) + 5)  # 2x the estimate, for slow nodes


def analysis_runtime_minutes(spec):
    from forcenet.cost import analysis_cost_seconds

    return max(5, int(2 * analysis_cost_seconds(spec) / 60) + 2)


def simulation_memory_mb(spec):
    from forcenet.cost import simulation_cost

    return simulation_cost(spec).memory_mb


def figure_outputs(name, category, results=RESULTS, reading=None):
    """The PDF, PNG and source-data CSV of one figure, both in the HTML report (`snakemake --report`): the PNG is what the report shows
    inline (every browser draws it; a PDF is blank without a PDF viewer), and its caption links the PDF. A figure of a
    reading beside (its label `reading`) lies in that reading's `results` folder, under its own report heading."""
    beside = f", {reading}" if reading else ""
    return dict(
        pdf=report(paths.figure(results, name, "pdf"), caption="../report/figure_pdf.rst", category=category,
                   subcategory=REPORT_PDFS + beside, labels={"figure": name, "format": "PDF"}),
        png=report(paths.figure(results, name, "png"), caption="../report/figure.rst", category=category,
                   subcategory=REPORT_FIGURES + beside, labels={"figure": name, "format": "PNG"}),
        csv=paths.figure(results, name, "csv"),  # the values the figure draws (forcenet.plotting.figure_data)
    )


REPORT_FIGURES, REPORT_PDFS, REPORT_TABLES = "Figures", "Figures as PDF (vector, for print)", "Tables"


def all_targets():
    """Everything `snakemake` builds by default: figures and tables of the studies in the config."""
    targets = [paths.resolved_config(RESULTS)]
    # every system's stacked measures, also of a system in no study (analysed, not drawn); not of a P2 system with a
    # campaign record (simulate.smk: the record keeps the run's summary, not the analyses of every state)
    targets += [paths.network_measures(RESULTS, s) for s in dict.fromkeys(P1_SYSTEMS + P2_SYSTEMS + list(SYSTEMS))
                if not (s in P2_SYSTEMS and recorded_runs(s))]
    targets += [paths.figure(RESULTS, name, "pdf") for name in BUILT_FIGURES]  # figures.smk, from the registry
    targets += [path for path in drop_figure_files() if path.endswith(".pdf")]  # figures.smk: P2's under `drop`
    if SKIPPED:
        targets += [paths.skipped_products(RESULTS)]
    if P1_SYSTEMS:
        targets += [paths.p1_validation_table(RESULTS, "md")]
        targets += [paths.movie(RESULTS, name) for name in P1_MOVIES]
    if P2_SYSTEMS:
        targets += [paths.distances(RESULTS, s) for s in P2_SYSTEMS]
        if not P2_SEQUENCES:  # p2.smk: no Tables I-III of a sequence
            targets += [paths.p2_table(RESULTS, i, "md") for i in paths.P2_TABLE_NUMBERS]
        targets += [paths.p2_validation_table(RESULTS, "md")]
    return targets
