# Config validation, paths and input functions. Runs at parse time, before any job: a bad config stops here
# with a message naming the key (JSON schema first, then forcenet.systems for what a schema cannot say).
# Kept light (no numba/xarray imports) so a dry-run of thousands of jobs stays fast.
import sys
from pathlib import Path

from snakemake.exceptions import WorkflowError
from snakemake.utils import validate

sys.path.insert(0, str(Path(workflow.basedir) / "src"))  # works before `pip install -e .` too

from forcenet.pipeline import realization_index, snapshot_analysis_params
from forcenet.systems import ConfigError, validate_config

validate(config, str(Path(workflow.basedir) / "workflow/schemas/config.schema.yaml"))
try:
    SYSTEMS = validate_config(config)
except ConfigError as error:
    raise WorkflowError(f"Invalid config: {error}") from None

RESULTS = "results"
LOGS = f"{RESULTS}/logs"
P1_SYSTEMS = list(config["studies"].get("p1", {}).get("systems", []))
P2_SYSTEMS = list(config["studies"].get("p2", {}).get("systems", []))
REALIZATIONS = [f"r{r:02d}" for r in range(config["realizations"])]

wildcard_constraints:
    system="|".join(SYSTEMS) or "NONE",
    realization=r"r\d\d+",
    rho=r"\d\.\d\d\d",


def snapshot_path(system, realization, rho_label):
    return f"{RESULTS}/sim/{system}/{realization}/rho{rho_label}.nc"


def analysis_path(system, realization, rho_label):
    return f"{RESULTS}/analysis/{system}/{realization}/rho{rho_label}.nc"


def system_analyses(wildcards):
    """Every analysis file of one system, realization-major (the order aggregate expects)."""
    spec = SYSTEMS[wildcards.system]
    return [analysis_path(wildcards.system, r, rho) for r in REALIZATIONS for rho in spec.rho_labels]


def system_params(system):
    """What a simulation depends on: its own entry, the material and the seed (not other systems)."""
    entry = config["systems"][system]
    params = {"system": entry, "seed": config["seed"]}
    if entry["stiffness"] == "material":
        params["material"] = config["material"]
    return params


def simulation_runtime_minutes(spec):
    from forcenet.cost import simulation_cost

    return max(10, int(2 * simulation_cost(spec).core_hours * 60) + 5)  # 2x the estimate, for slow nodes


def analysis_runtime_minutes(spec):
    from forcenet.cost import analysis_cost_seconds

    return max(5, int(2 * analysis_cost_seconds(spec) / 60) + 2)


def simulation_memory_mb(spec):
    from forcenet.cost import simulation_cost

    return simulation_cost(spec).memory_mb


def all_targets():
    """Everything `snakemake` builds by default: figures and tables of the studies in the config."""
    targets = [f"{RESULTS}/config/resolved.yaml"]
    targets += [f"{RESULTS}/{s}/network_measures.nc" for s in dict.fromkeys(P1_SYSTEMS + P2_SYSTEMS)]
    if P1_SYSTEMS:
        targets += [f"{RESULTS}/figures/{name}.pdf" for name in P1_FIGURES]
        targets += [f"{RESULTS}/tables/p1_validation.md"]
    if P2_SYSTEMS:
        targets += [f"{RESULTS}/{s}/distances.nc" for s in P2_SYSTEMS]
        targets += [f"{RESULTS}/figures/{name}.pdf" for name in P2_FIGURES]
        targets += [f"{RESULTS}/tables/p2_table{i}.md" for i in (1, 2, 3)] + [f"{RESULTS}/tables/p2_validation.md"]
    return targets
