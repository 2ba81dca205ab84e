rule resolved_config:
    localrule: True
    """The config as the workflow understands it: every system in reduced units with its ρ grid."""
    output:
        paths.resolved_config(RESULTS),
    log:
        paths.log(RESULTS, "", "resolved_config"),
    params:
        config=config,
        results_dir=str(RESULTS_ABSOLUTE),
    script:
        "../scripts/resolved_config.py"
