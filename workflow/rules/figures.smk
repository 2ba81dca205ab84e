# P1 figures and validation table: one rule per figure, each reading the aggregated datasets.
P1_FIGURES = {
    "p1_fig01_networks": "Force networks of a 2D and a 3D snapshot near the largest ρ, edges coloured by F/⟨F⟩ (P1 Fig. 1).",
    "p1_fig02_betti0_surface": "B0/N over packing fraction ρ and force threshold F_th for each system (P1 Fig. 2).",
    "p1_fig03_force_pdf": "PDF of F/⟨F⟩ at several ρ for each system (P1 Fig. 3).",
    "p1_fig04_cluster_size": "Mean size of non-percolating clusters ⟨S⟩/N vs ρ per F_th (P1 Fig. 4).",
    "p1_fig05_percolating_cluster": "N_per/N vs ρ per F_th, where ≥ 50 % of realizations percolate (P1 Fig. 5).",
    "p1_fig06_betti0": "B0/N vs ρ per F_th, with the 3D zoom (P1 Fig. 6).",
    "p1_fig07_betti1": "B1/N (and B2/N in 3D) vs ρ per F_th (P1 Fig. 7).",
    "p1_fig08_shape_heatmap": "Shape parameter S_p over (ρ, F_th) with P1's averaging rule (P1 Fig. 8).",
    "p1_fig09_shape_sections": "S_p vs ρ for selected F_th (P1 Fig. 9).",
    "p1_fig10_persistence_diagram": "An example PD0 with the persistence-bin regions (P1 Fig. 10).",
    "p1_fig11_persistence_bins": "PD0 points per bin N0/N vs ρ (P1 Fig. 11).",
    "p1_fig12_total_persistence": "Total persistence TP0/N and TP1/N vs ρ (P1 Fig. 12).",
    "p1_z_jamming": "Coordination Z(ρ) with the jamming point ρ_J (inflection) marked.",
}


def p1_measures(wildcards=None):
    return [f"{RESULTS}/{s}/network_measures.nc" for s in P1_SYSTEMS]


def p1_diagrams(wildcards=None):
    return [f"{RESULTS}/{s}/diagrams.nc" for s in P1_SYSTEMS]


def p1_example_snapshots(wildcards=None):
    """The last grid point of realization 0 of each P1 system (figure 1)."""
    return [snapshot_path(s, REALIZATIONS[0], SYSTEMS[s].rho_labels[-1]) for s in P1_SYSTEMS]


for _figure, _caption in P1_FIGURES.items():

    rule:
        name:
            f"figure_{_figure}"
        localrule: True
        input:
            measures=p1_measures(),
            diagrams=p1_diagrams(),
            snapshots=p1_example_snapshots() if _figure == "p1_fig01_networks" else [],
        output:
            **figure_outputs(_figure, "P1"),
        log:
            f"{LOGS}/figures/{_figure}.log",
        params:
            figure=_figure,
            caption=_caption,
            systems=P1_SYSTEMS,
            force_unit=config["analysis"]["p1_force_unit"],  # the F_max rule's unit: ρ_max marked on the figures
        script:
            "../scripts/figure.py"


rule p1_validation_table:
    localrule: True
    input:
        measures=p1_measures(),
        paper_size=paper_size_input("p1"),
    output:
        csv=f"{RESULTS}/tables/p1_validation.csv",
        md=report(f"{RESULTS}/tables/p1_validation.md", caption="../report/table.rst", category="P1",
                  subcategory=REPORT_TABLES),
    log:
        f"{LOGS}/tables/p1_validation.log",
    params:
        systems=P1_SYSTEMS,
        force_unit=config["analysis"]["p1_force_unit"],
        paper_size=paper_size_table("p1"),
    script:
        "../scripts/p1_validation.py"


# Compression movies (MP4, ffmpeg from the imageio-ffmpeg wheel): per P1 system, its force network through the ρ
# grid (realization 0) and one turn around its B0/N surface (the data of Fig. 2). Part of the default build;
# `snakemake --cores 2 movies` builds only them.
P1_MOVIES = {f"{kind}_{system}": (kind, system) for system in P1_SYSTEMS for kind in ("network", "b0_surface")}


def movie_inputs(kind, system):
    if kind == "network":
        return [snapshot_path(system, REALIZATIONS[0], rho) for rho in SYSTEMS[system].rho_labels]
    return p1_measures()


for _movie, (_kind, _system) in P1_MOVIES.items():

    rule:
        name:
            f"movie_{_movie}"
        localrule: True
        input:
            movie_inputs(_kind, _system),
        output:
            f"{RESULTS}/movies/{_movie}.mp4",
        log:
            f"{LOGS}/movies/{_movie}.log",
        params:
            kind=_kind,
            system=_system,
        script:
            "../scripts/movie.py"


rule movies:
    """Every compression movie (and what they need)."""
    localrule: True
    input:
        [f"{RESULTS}/movies/{name}.mp4" for name in P1_MOVIES],
