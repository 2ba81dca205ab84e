"""Stack a system's analyses over (realization, ρ): thin wrapper around forcenet.pipeline.aggregate."""
from forcenet.pipeline import aggregate

aggregate(  # noqa: F821 — `snakemake` is injected by Snakemake
    analyses=list(snakemake.input), realizations=snakemake.params.realizations, rhos=snakemake.params.rhos,
    measures_path=snakemake.output.measures, diagrams_path=snakemake.output.diagrams,
    config=snakemake.config, system=snakemake.wildcards.system, log_path=snakemake.log[0],
)
