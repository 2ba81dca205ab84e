"""P2 validation of the paper's claims: thin wrapper around forcenet.pipeline_p2.p2_validation_table."""
from forcenet.pipeline_p2 import p2_validation_table

p2_validation_table(  # noqa: F821 — `snakemake` is injected by Snakemake
    distances=list(snakemake.input.distances), tables=list(snakemake.input.tables),
    runs=list(snakemake.input.runs), states=snakemake.input.states,
    frictional=snakemake.params.frictional, frictionless=snakemake.params.frictionless,
    md=snakemake.output.md, csv=snakemake.output.csv, paper_size=snakemake.params.paper_size,
    beside={snakemake.params.essential_reading: {"distances": list(snakemake.input.essential_distances),
                                                 "tables": list(snakemake.input.essential_tables)},
            **({snakemake.params.essential_drop_reading: {"distances": list(snakemake.input.essential_drop_distances),
                                                          "tables": list(snakemake.input.essential_drop_tables)}}
               if snakemake.params.essential_drop_reading else {}),
            **({snakemake.params.table_states_reading: {"tables": list(snakemake.input.table_states_tables)}}
               if snakemake.params.table_states_reading else {})},
    log_path=snakemake.log[0],
)
