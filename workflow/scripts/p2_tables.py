"""P2 Tables I-III: thin wrapper around forcenet.pipeline.p2_tables."""
from forcenet.pipeline import p2_tables

p2_tables(  # noqa: F821 — `snakemake` is injected by Snakemake
    snapshots=list(snakemake.input), csv=list(snakemake.output.csv), md=list(snakemake.output.md),
    analysis=snakemake.params.analysis, log_path=snakemake.log[0],
)
