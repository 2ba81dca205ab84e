"""Analyse one compression run's snapshots: thin wrapper around forcenet.pipeline.analyze_run."""
from forcenet.checks import checked_system
from forcenet.datasets.runs import run_expectation
from forcenet.pipeline import analyze_run

# the rule is analyze_{system} (workflow/rules/analyze.smk; a reading's analysis names its system in a param); the
# run's expectation is computed here from its checked system, not passed as a param: the rules' params stay the
# analysis keys (a param change reruns every analysis)
system = snakemake.params.get("system") or snakemake.rule.removeprefix("analyze_")  # noqa: F821 — injected
spec = checked_system(system, snakemake.config)  # noqa: F821
analyze_run(  # noqa: F821
    snapshots=list(snakemake.input), outputs=list(snakemake.output), analysis=snakemake.params.analysis,
    log_path=snakemake.log[0], expect=run_expectation(spec, snakemake.config),
)
