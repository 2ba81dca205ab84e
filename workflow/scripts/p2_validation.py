"""P2 validation of the paper's claims: thin wrapper around forcenet.pipeline.p2_validation_table."""
from forcenet.pipeline import p2_validation_table

p2_validation_table(  # noqa: F821 — `snakemake` is injected by Snakemake
    distances=list(snakemake.input.distances), tables=list(snakemake.input.tables),
    measures=list(snakemake.input.measures), states=snakemake.input.states, diagrams=list(snakemake.input.diagrams),
    frictional=snakemake.params.frictional, frictionless=snakemake.params.frictionless,
    md=snakemake.output.md, csv=snakemake.output.csv, paper_size=snakemake.params.paper_size,
    log_path=snakemake.log[0],
)
