"""Distances between consecutive persistence diagrams: thin wrapper around forcenet.pipeline_p2.p2_distances."""
from forcenet.pipeline_p2 import p2_distances

p2_distances(  # noqa: F821 — `snakemake` is injected by Snakemake
    runs=list(snakemake.input), realizations=snakemake.params.realizations, output=snakemake.output[0],
    essential_convention=snakemake.params.essential_convention,
    config=snakemake.config, system=snakemake.wildcards.system, log_path=snakemake.log[0],
)
