"""Draw one figure of forcenet.plotting.registry: thin wrapper around forcenet.pipeline_figures.figure."""
from forcenet.pipeline_figures import figure

figure(  # noqa: F821 — `snakemake` is injected by Snakemake
    name=snakemake.params.figure, systems=snakemake.params.systems, inputs=dict(snakemake.input.items()),
    pdf=snakemake.output.pdf, png=snakemake.output.png, csv=snakemake.output.csv,
    force_unit=snakemake.params.force_unit, rattler_rule=snakemake.params.rattler_rule,
    system_info=snakemake.params.system_info,
    log_path=snakemake.log[0],
)
