# Config validation and input functions. Runs at parse time, before any job: a bad config stops here
# with a message naming the key (JSON schema first, then forcenet.systems for what a schema cannot say).
import sys
from pathlib import Path

from snakemake.exceptions import WorkflowError
from snakemake.utils import validate

sys.path.insert(0, str(Path(workflow.basedir) / "src"))  # works before `pip install -e .` too

from forcenet.systems import ConfigError, format_rho, validate_config

validate(config, str(Path(workflow.basedir) / "workflow/schemas/config.schema.yaml"))
try:
    SYSTEMS = validate_config(config)
except ConfigError as error:
    raise WorkflowError(f"Invalid config: {error}") from None

RESULTS = "results"
LOGS = "results/logs"


def realization_labels():
    return [f"r{r:02d}" for r in range(config["realizations"])]


def all_targets():
    return [f"{RESULTS}/config/resolved.yaml"]
