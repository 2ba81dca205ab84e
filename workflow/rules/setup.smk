rule resolved_config:
    localrule: True
    """The config as the workflow understands it: every system in reduced units with its ρ grid."""
    output:
        f"{RESULTS}/config/resolved.yaml",
    log:
        f"{LOGS}/resolved_config.log",
    params:
        config=config,
    script:
        "../scripts/resolved_config.py"
