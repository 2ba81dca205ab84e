"""Draw one P2 figure: thin wrapper around forcenet.pipeline.p2_figure."""
from forcenet.pipeline import p2_figure

p2_figure(  # noqa: F821 — `snakemake` is injected by Snakemake
    name=snakemake.params.figure, system=snakemake.params.systems[0], inputs=dict(snakemake.input.items()),
    pdf=snakemake.output.pdf, png=snakemake.output.png, csv=snakemake.output.csv,
    rattler_rule=snakemake.params.rattler_rule,
    log_path=snakemake.log[0],
)
