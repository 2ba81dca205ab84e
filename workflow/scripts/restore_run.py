"""Restore one recorded compression run (system, realization) from its campaign record: thin wrapper around
forcenet.campaign.restore_run."""
from forcenet.campaign import restore_run
from forcenet.pipeline import job_logger

with job_logger(snakemake.log[0], f"restore.{snakemake.params.system}.{snakemake.wildcards.realization}") as log:  # noqa: F821
    restore_run(config=snakemake.config, system=snakemake.params.system,  # noqa: F821 — injected by Snakemake
                realization=snakemake.wildcards.realization, outputs=list(snakemake.output.snapshots),  # noqa: F821
                cost_path=snakemake.output.cost,  # noqa: F821
                summary_path=dict(snakemake.output.items()).get("summary"))  # noqa: F821 — a P2 run's summary
    log.info("restored %d snapshots of %s %s from its campaign record (no DEM step)"
             + (" and its P2 run summary" if "summary" in dict(snakemake.output.items()) else ""),  # noqa: F821
             len(snakemake.output.snapshots), snakemake.params.system, snakemake.wildcards.realization)  # noqa: F821
