# P2: distances between persistence diagrams of consecutive states, Tables I–III, figures 1, 3, 6–10 and the
# validation of P2's claims. P2_SYSTEMS[0] is the frictional system (μ = 0.5), P2_SYSTEMS[1] the frictionless one.
from forcenet.systems import study_rattler_rule

P2_FRICTIONAL = P2_SYSTEMS[0] if P2_SYSTEMS else None
P2_FRICTIONLESS = P2_SYSTEMS[1] if len(P2_SYSTEMS) > 1 else None


def p2_table_labels():
    """ρ labels of the three nearby snapshots a, b, c around studies.p2.table_rho (P2 Tables I–III)."""
    from forcenet.systems import select_table_snapshots  # pure numpy: no xarray at parse time

    spec = SYSTEMS[P2_FRICTIONAL]
    indices = select_table_snapshots(spec.rho_grid, config["studies"]["p2"].get("table_rho", 0.79))
    return [spec.rho_labels[i] for i in indices]


def p2_table_candidates(path=snapshot_path, states="abc"):
    """Files of the states a, b, c (or those named by `states`) of every realization, realization-major: the
    candidates among which p2_table_states picks one realization (forcenet.report.p2_tables.TABLE_STATE_CRITERION); none
    when the config has no P2 study."""
    if not P2_FRICTIONAL:
        return []
    labels = [label for letter, label in zip("abc", p2_table_labels()) if letter in states]
    return [path(P2_FRICTIONAL, r, rho) for r in REALIZATIONS for rho in labels]


P2_TABLE_STATES = f"{RESULTS}/tables/p2_table_states.csv"
# the P2 products read networks made by the P2 study's rattler rule (P2 §III C keeps rattlers)
P2_RATTLER_RULE = study_rattler_rule(config, P2_FRICTIONAL) if P2_FRICTIONAL else None


P2_FIGURE_INPUTS = {
    "p2_fig01_snapshots_differences": ("snapshots", None),
    "p2_fig03_diagrams": ("analysis", None),
    "p2_fig06_distances_normal_mu05": ("distances", P2_FRICTIONAL),
    "p2_fig07_ratios_mu05": ("distances", P2_FRICTIONAL),
    "p2_fig08_distances_tangential_mu05": ("distances", P2_FRICTIONAL),
    "p2_fig09_distances_normal_mu0": ("distances", P2_FRICTIONLESS),
    "p2_fig10_ratios_mu0": ("distances", P2_FRICTIONLESS),
}
P2_CAPTIONS = {
    "p2_fig01_snapshots_differences": "Three nearby snapshots a, b, c (normal forces) and maps of the force change ΔF between them (P2 Fig. 1).",
    "p2_fig03_diagrams": "PD0 and PD1 of the normal-force network of snapshot a (P2 Fig. 3).",
    "p2_fig06_distances_normal_mu05": "d_B, d_W1, d_W2 between consecutive PDs vs ρ for β0 and β1 with Z(ρ); μ = 0.5, normal forces (P2 Fig. 6).",
    "p2_fig07_ratios_mu05": "Ratios d_B/d_W1 and d_B/d_W2; μ = 0.5, normal forces (P2 Fig. 7).",
    "p2_fig08_distances_tangential_mu05": "As Fig. 6 for tangential forces (P2 Fig. 8).",
    "p2_fig09_distances_normal_mu0": "As Fig. 6 for the frictionless system μ = 0 (P2 Fig. 9).",
    "p2_fig10_ratios_mu0": "As Fig. 7 for μ = 0 (P2 Fig. 10).",
}
# figures of a system that the config does not list are not built
P2_FIGURES = {name: (kind, system) for name, (kind, system) in P2_FIGURE_INPUTS.items()
              if P2_FRICTIONAL and (kind != "distances" or system is not None)}


rule p2_distances:
    """d_B, d_W1, d_W2 between consecutive snapshots, normal and tangential networks, β0 and β1."""
    input:
        system_analyses,
    output:
        f"{RESULTS}/{{system}}/distances.nc",
    log:
        f"{LOGS}/distances/{{system}}.log",
    params:
        realizations=[realization_index(r) for r in REALIZATIONS],
        essential_convention=config["analysis"]["essential_convention"],
    resources:
        runtime=60,
        mem_mb=4000,
    script:
        "../scripts/p2_distances.py"


rule p2_table_states:
    """Which realization's states a, b, c make Tables I–III and Figs 1, 3 (P2 Fig. 1: Z and <F> almost identical)."""
    localrule: True
    input:
        p2_table_candidates(analysis_path),
    output:
        P2_TABLE_STATES,
    log:
        f"{LOGS}/tables/p2_table_states.log",
    script:
        "../scripts/p2_table_states.py"


rule p2_tables:
    localrule: True
    input:
        snapshots=p2_table_candidates(),
        states=P2_TABLE_STATES,
    output:
        csv=[f"{RESULTS}/tables/p2_table{i}.csv" for i in (1, 2, 3)],
        md=[report(f"{RESULTS}/tables/p2_table{i}.md", caption="../report/p2_tables.rst", category="P2",
                   subcategory=REPORT_TABLES) for i in (1, 2, 3)],
    log:
        f"{LOGS}/tables/p2_tables.log",
    params:
        rattler_rule=P2_RATTLER_RULE,
        essential_convention=config["analysis"]["essential_convention"],
    script:
        "../scripts/p2_tables.py"


for _figure, (_kind, _system) in P2_FIGURES.items():

    rule:
        name:
            f"figure_{_figure}"
        localrule: True
        input:
            snapshots=p2_table_candidates() if _kind == "snapshots" else [],
            analysis=p2_table_candidates(analysis_path, states="a") if _kind == "analysis" else [],
            states=[P2_TABLE_STATES] if _kind in ("snapshots", "analysis") else [],
            distances=[f"{RESULTS}/{_system}/distances.nc"] if _kind == "distances" else [],
        output:
            **figure_outputs(_figure, "P2"),
        log:
            f"{LOGS}/figures/{_figure}.log",
        params:
            figure=_figure,
            caption=P2_CAPTIONS[_figure],
            systems=[_system or P2_FRICTIONAL],
            rattler_rule=P2_RATTLER_RULE,
        script:
            "../scripts/p2_figure.py"


rule p2_validation:
    localrule: True
    input:
        distances=[f"{RESULTS}/{s}/distances.nc" for s in P2_SYSTEMS],
        tables=rules.p2_tables.output.csv,
        measures=[f"{RESULTS}/{s}/network_measures.nc" for s in P2_SYSTEMS],
        states=P2_TABLE_STATES,
        paper_size=paper_size_input("p2"),
    output:
        md=report(f"{RESULTS}/tables/p2_validation.md", caption="../report/table.rst", category="P2",
                  subcategory=REPORT_TABLES),
        csv=f"{RESULTS}/tables/p2_validation.csv",
    log:
        f"{LOGS}/tables/p2_validation.log",
    params:
        frictional=P2_FRICTIONAL,
        frictionless=P2_FRICTIONLESS,
        paper_size=paper_size_table("p2"),
    script:
        "../scripts/p2_validation.py"
