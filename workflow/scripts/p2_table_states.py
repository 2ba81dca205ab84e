"""Which realization's states a, b, c make P2 Tables I-III and Figs 1, 3: thin wrapper around
forcenet.pipeline_p2.p2_table_states."""
from forcenet.pipeline_p2 import p2_table_states

p2_table_states(  # noqa: F821 — `snakemake` is injected by Snakemake
    analyses=list(snakemake.input), csv=snakemake.output[0], rule=snakemake.params.rule,
    table_rho=snakemake.params.table_rho, dimension=snakemake.params.dimension, log_path=snakemake.log[0],
)
