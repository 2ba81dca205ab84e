"""What P2's products read from one run, its diagrams apart: thin wrapper around forcenet.pipeline_p2.p2_run_summary."""
from forcenet.pipeline_p2 import p2_run_summary

p2_run_summary(  # noqa: F821 — `snakemake` is injected by Snakemake
    analyses=list(snakemake.input), output=snakemake.output[0], config=snakemake.config,
    system=snakemake.params.system, realization=snakemake.wildcards.realization,
    conventions=list(snakemake.params.conventions), log_path=snakemake.log[0],
)
