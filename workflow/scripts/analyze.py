"""Analyse one compression run's snapshots: thin wrapper around forcenet.pipeline.analyze_run."""
from forcenet.datasets.runs import run_expectation
from forcenet.pipeline import analyze_run
from forcenet.systems import system_from_config

# the rule is analyze_{system} (workflow/rules/analyze.smk; a reading's analysis names its system in a param); the
# run's expectation is computed here, not passed as a param, so that adding the check did not change the rules'
# params (a param change reruns every analysis)
system = snakemake.params.get("system") or snakemake.rule.removeprefix("analyze_")  # noqa: F821 — injected
analyze_run(  # noqa: F821
    snapshots=list(snakemake.input), outputs=list(snakemake.output), analysis=snakemake.params.analysis,
    log_path=snakemake.log[0], expect=run_expectation(system_from_config(system, snakemake.config), snakemake.config),
)
