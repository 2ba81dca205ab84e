"""Analyse one compression run's snapshots: thin wrapper around forcenet.pipeline.analyze_run."""
from forcenet.pipeline import analyze_run

analyze_run(  # noqa: F821 — `snakemake` is injected by Snakemake
    snapshots=list(snakemake.input), outputs=list(snakemake.output), analysis=snakemake.params.analysis,
    log_path=snakemake.log[0],
)
