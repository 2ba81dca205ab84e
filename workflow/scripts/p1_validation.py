"""P1 validation table: thin wrapper around forcenet.pipeline.p1_validation_table."""
from forcenet.pipeline import p1_validation_table

p1_validation_table(  # noqa: F821 — `snakemake` is injected by Snakemake
    measures=list(snakemake.input.measures), systems=snakemake.params.systems,
    csv=snakemake.output.csv, md=snakemake.output.md, force_unit=snakemake.params.force_unit,
    paper_size=snakemake.params.paper_size, snapshots=list(snakemake.input.snapshots),
    diagrams=list(snakemake.input.diagrams), counterparts=snakemake.params.counterparts,
    beside={snakemake.params.tetrahedra_reading: {"measures": list(snakemake.input.tetrahedra_measures),
                                                  "diagrams": list(snakemake.input.tetrahedra_diagrams)}},
    log_path=snakemake.log[0],
)
