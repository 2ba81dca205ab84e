"""P2 Tables I-III: thin wrapper around forcenet.pipeline_p2.p2_tables."""
from forcenet.pipeline_p2 import p2_tables

p2_tables(  # noqa: F821 — `snakemake` is injected by Snakemake
    snapshots=list(snakemake.input.snapshots), states=snakemake.input.states, csv=list(snakemake.output.csv),
    md=list(snakemake.output.md), rattler_rule=snakemake.params.rattler_rule,
    essential_convention=snakemake.params.essential_convention, log_path=snakemake.log[0],
)
