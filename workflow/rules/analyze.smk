# Analyses: one file per snapshot, computed by one job per (system, realization) that loops over that run's
# snapshots. A per-snapshot job would spend ~20x its kernel time starting Python and importing numba, xarray and
# dionysus (bench/workflow_overhead.py); a run's snapshots are produced together by one simulate job anyway, so
# they change together. Any single analysis file is still a target: it builds its realization's batch. A recorded
# run of a P2 system has only the states its record keeps (simulate.smk): rule analyze_{system}_recorded analyses
# those.
for _name, _spec in SYSTEMS.items():
    _kept = p2_kept_labels(config, _name) if p2_system(config, _name) else None

    rule:
        name:
            f"analyze_{_name}"
        input:
            [snapshot_path(_name, "{realization}", rho) for rho in _spec.rho_labels],
        output:
            [analysis_path(_name, "{realization}", rho) for rho in _spec.rho_labels],
        wildcard_constraints:
            realization=realizations_except(recorded_runs(_name) if _kept is not None else []),
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

    if _kept and recorded_runs(_name):

        rule:
            name:
                f"analyze_{_name}_recorded"
            input:
                [snapshot_path(_name, "{realization}", rho) for rho in _kept],
            output:
                [analysis_path(_name, "{realization}", rho) for rho in _kept],
            wildcard_constraints:
                realization="|".join(recorded_runs(_name)),
            log:
                paths.run_log(RESULTS, "analyze", _name, "{realization}"),
            params:
                analysis=snapshot_analysis_params(config, _name),
                system=_name,
            group:
                "analysis"
            threads: 1
            resources:
                runtime=lambda wildcards, attempt, spec=_spec: analysis_runtime_minutes(spec) * attempt,
                mem_mb=2000,
            script:
                "../scripts/analyze.py"


# The tetrahedra reading beside (common.smk): P1's 3D systems analysed again with the other fill_tetrahedra, a few
# seconds per run; 2D complexes have no tetrahedra, so the reading leaves them alone.
P1_SOLIDS = [s for s in P1_SYSTEMS if SYSTEMS[s].dimension == 3]
TETRAHEDRA_RESULTS = READING_RESULTS["tetrahedra"]

for _name in P1_SOLIDS:
    _spec = SYSTEMS[_name]

    rule:
        name:
            f"analyze_{_name}_{READINGS['tetrahedra'].folder.replace('-', '_')}"
        input:
            [snapshot_path(_name, "{realization}", rho) for rho in _spec.rho_labels],
        output:
            [paths.analysis(TETRAHEDRA_RESULTS, _name, "{realization}", rho) for rho in _spec.rho_labels],
        log:
            paths.run_log(TETRAHEDRA_RESULTS, "analyze", _name, "{realization}"),
        params:
            analysis={**snapshot_analysis_params(config, _name), "fill_tetrahedra": READINGS["tetrahedra"].value},
            system=_name,
        group:
            "analysis"
        threads: 1
        resources:
            runtime=lambda wildcards, attempt, spec=_spec: analysis_runtime_minutes(spec) * attempt,
            mem_mb=2000,
        script:
            "../scripts/analyze.py"


def stacked_realizations(wildcards):
    """The realization of each analysis that aggregate stacks (realization-major)."""
    return [r for r in realization_numbers(wildcards) for _ in SYSTEMS[wildcards.system].rho_grid]


def stacked_rhos(wildcards):
    """The grid ρ of each analysis that aggregate stacks (realization-major)."""
    return [rho for _ in realizations(wildcards.system) for rho in SYSTEMS[wildcards.system].rho_grid]


for _results, _suffix in ((RESULTS, ""), *(((TETRAHEDRA_RESULTS, "_tetrahedra_reading"),) if P1_SOLIDS else ())):

    rule:
        """Stack one system's analyses over (realization, ρ)."""
        name:
            f"aggregate_system{_suffix}"
        localrule: True
        input:
            lambda wildcards, results=_results: system_analyses(wildcards, results),
        output:
            measures=paths.network_measures(_results, "{system}"),
            diagrams=paths.diagrams(_results, "{system}"),
        log:
            paths.log(_results, "aggregate", "{system}"),
        params:
            realizations=stacked_realizations,
            rhos=stacked_rhos,
        resources:
            runtime=30,
            mem_mb=4000,
        script:
            "../scripts/aggregate.py"
