# Analyses: one file per snapshot, computed by one job per (system, realization) that loops over that run's
# snapshots. A per-snapshot job would spend ~20x its kernel time starting Python and importing numba, xarray and
# dionysus (bench/workflow_overhead.py); a run's snapshots are produced together by one simulate job anyway, so
# they change together. Any single analysis file is still a target: it builds its realization's batch.
for _name, _spec in SYSTEMS.items():

    rule:
        name:
            f"analyze_{_name}"
        input:
            [snapshot_path(_name, "{realization}", rho) for rho in _spec.rho_labels],
        output:
            [analysis_path(_name, "{realization}", rho) for rho in _spec.rho_labels],
        log:
            paths.run_log(RESULTS, "analyze", _name, "{realization}"),
        params:
            # only the keys the snapshot analysis reads, with the rattler rule of the system's study: changing
            # another `analysis:` key (P2's distance settings) must not rerun every snapshot analysis
            analysis=snapshot_analysis_params(config, _name),
        group:
            "analysis"
        threads: 1
        resources:
            runtime=lambda wildcards, attempt, spec=_spec: analysis_runtime_minutes(spec) * attempt,
            mem_mb=2000,
        script:
            "../scripts/analyze.py"


rule aggregate_system:
    """Stack one system's analyses over (realization, ρ)."""
    localrule: True
    input:
        system_analyses,
    output:
        measures=paths.network_measures(RESULTS, "{system}"),
        diagrams=paths.diagrams(RESULTS, "{system}"),
    log:
        paths.log(RESULTS, "aggregate", "{system}"),
    params:
        realizations=lambda wildcards: [realization_index(r) for r in realizations(wildcards.system)
                                        for _ in SYSTEMS[wildcards.system].rho_grid],
        rhos=lambda wildcards: [rho for _ in realizations(wildcards.system) for rho in SYSTEMS[wildcards.system].rho_grid],
    resources:
        runtime=30,
        mem_mb=4000,
    script:
        "../scripts/aggregate.py"
