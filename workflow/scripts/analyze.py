"""Analyse one snapshot: thin wrapper around forcenet.pipeline.analyze."""
from forcenet.pipeline import analyze

analyze(  # noqa: F821 — `snakemake` is injected by Snakemake
    snapshot=snakemake.input[0], output=snakemake.output[0], analysis=snakemake.params.analysis,
    config=snakemake.config, log_path=snakemake.log[0],
)
