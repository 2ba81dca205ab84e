"""A validation table that lists no claim, with the line saying why: thin wrapper around
forcenet.pipeline.no_claims_table."""
from forcenet.pipeline import no_claims_table

no_claims_table(  # noqa: F821 — `snakemake` is injected by Snakemake
    csv=snakemake.output.csv, md=snakemake.output.md, paper=snakemake.params.paper, note=snakemake.params.note,
    log_path=snakemake.log[0],
)
