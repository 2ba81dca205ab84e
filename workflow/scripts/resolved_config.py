"""Write the resolved config (systems in reduced units, expanded ρ grids, the absolute results folder)."""
from forcenet.workflow_io import write_resolved_config

write_resolved_config(snakemake.params.config, snakemake.output[0],  # noqa: F821 (snakemake injects it)
                      snakemake.params.results_dir)  # noqa: F821
