"""One study's committed validation tables: thin wrapper around forcenet.report.validation."""
from forcenet.datasets.io import git_commit
from forcenet.report.validation import provenance, read_run_costs, write_validation_report

info = provenance(study=snakemake.params.study, config=snakemake.config,  # noqa: F821 — injected by Snakemake
                  systems=snakemake.params.systems, costs=read_run_costs(snakemake.input.costs),  # noqa: F821
                  commit=git_commit())
write_validation_report(info=info, title=snakemake.params.title,  # noqa: F821
                        sections=list(zip(snakemake.params.headings, snakemake.input.md, snakemake.input.csv)),  # noqa: F821
                        md_path=snakemake.output.md, csv_path=snakemake.output.csv)  # noqa: F821
