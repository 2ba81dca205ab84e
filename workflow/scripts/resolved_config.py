"""Write the resolved config (systems in reduced units, expanded ρ grids)."""
from forcenet.workflow_io import write_resolved_config

write_resolved_config(snakemake.params.config, snakemake.output[0])  # noqa: F821 (snakemake injects it)
