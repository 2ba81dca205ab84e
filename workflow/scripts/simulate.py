"""Run one compression (system, realization): thin wrapper around forcenet.pipeline.simulate."""
from forcenet.pipeline import simulate

simulate(  # noqa: F821 — `snakemake` is injected by Snakemake
    config=snakemake.config, system=snakemake.params.system, realization=snakemake.wildcards.realization,
    outputs=list(snakemake.output.snapshots), cost_path=snakemake.output.cost, log_path=snakemake.log[0],
)
