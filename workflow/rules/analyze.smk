# One job per snapshot: force networks (total, normal, tangential), persistence, Betti curves, clusters,
# percolation, shape, PDF, bins. Grouped for cluster execution so one allocation does minutes of work.
rule analyze_snapshot:
    input:
        snapshot_path("{system}", "{realization}", "{rho}"),
    output:
        analysis_path("{system}", "{realization}", "{rho}"),
    log:
        f"{LOGS}/analyze/{{system}}/{{realization}}/rho{{rho}}.log",
    params:
        analysis=config["analysis"],
    group:
        "analysis"
    threads: 1
    resources:
        runtime=10,
        mem_mb=1000,
    script:
        "../scripts/analyze.py"


rule aggregate_system:
    """Stack one system's analyses over (realization, ρ)."""
    input:
        system_analyses,
    output:
        measures=f"{RESULTS}/{{system}}/network_measures.nc",
        diagrams=f"{RESULTS}/{{system}}/diagrams.nc",
    log:
        f"{LOGS}/aggregate/{{system}}.log",
    params:
        realizations=lambda wildcards: [realization_index(r) for r in REALIZATIONS for _ in SYSTEMS[wildcards.system].rho_grid],
        rhos=lambda wildcards: [rho for _ in REALIZATIONS for rho in SYSTEMS[wildcards.system].rho_grid],
    resources:
        runtime=30,
        mem_mb=4000,
    script:
        "../scripts/aggregate.py"
