"""Write one compression movie: thin wrapper around forcenet.pipeline_figures.movie."""
from forcenet.pipeline_figures import movie

movie(  # noqa: F821 — `snakemake` is injected by Snakemake
    kind=snakemake.params.kind, system=snakemake.params.system, inputs=list(snakemake.input),
    output=snakemake.output[0], rattler_rule=snakemake.params.rattler_rule, log_path=snakemake.log[0],
    force_unit=snakemake.params.force_unit, system_info=snakemake.params.system_info,
)
