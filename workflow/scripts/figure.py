"""Draw one paper figure: thin wrapper around forcenet.pipeline.figure."""
from forcenet.pipeline import figure

figure(  # noqa: F821 — `snakemake` is injected by Snakemake
    name=snakemake.params.figure, systems=snakemake.params.systems, inputs=dict(snakemake.input.items()),
    pdf=snakemake.output.pdf, png=snakemake.output.png, csv=snakemake.output.csv,
    force_unit=snakemake.params.force_unit,
    log_path=snakemake.log[0],
)
