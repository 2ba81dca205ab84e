"""Import one run of a system with `source:`: thin wrapper around forcenet.pipeline.import_states."""
from forcenet.pipeline import import_states

import_states(  # noqa: F821 — `snakemake` is injected by Snakemake
    config=snakemake.config, system=snakemake.params.system, realization=snakemake.wildcards.realization,
    outputs=list(snakemake.output.snapshots), log_path=snakemake.log[0],
)
