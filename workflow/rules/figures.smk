# Every figure of P1 and P2: one rule per entry of forcenet.plotting.registry.FIGURES (nothing to edit here to add a
# figure), the P1 validation table and the compression movies. Included after p2.smk, whose states a, b, c and
# system roles the P2 figures read.
from forcenet.plotting.registry import FIGURES  # pure data: nothing heavy is imported at parse time
from forcenet.systems import study_rattler_rule

FORCE_UNIT = config["analysis"]["p1_force_unit"]  # P1's F_max rule: ρ_max marked on the ρ axes


def p1_measures(wildcards=None):
    return [paths.network_measures(RESULTS, s) for s in P1_SYSTEMS]


def figure_systems(entry):
    """The systems a figure reads (forcenet.plotting.registry.SYSTEM_CHOICES): every system of its study, or P2's
    frictional or frictionless one; none when the config lacks them (the figure is then not built)."""
    study = P1_SYSTEMS if entry.study == "p1" else P2_SYSTEMS
    chosen = {"all": study, "frictional": [P2_FRICTIONAL], "frictionless": [P2_FRICTIONLESS]}[entry.systems]
    return [s for s in chosen if s]


def figure_input_files(kind, systems, results=RESULTS):
    """The files of one input kind (forcenet.plotting.registry.INPUT_KINDS) of a figure reading `systems` (the
    distances of a reading beside from its own results folder, `results`)."""
    if kind == "measures":
        return [paths.network_measures(RESULTS, s) for s in systems]
    if kind == "diagrams":
        return [paths.diagrams(RESULTS, s) for s in systems]
    if kind == "example_snapshots":
        return [snapshot_path(s, realizations(s)[0], SYSTEMS[s].rho_labels[-1]) for s in systems]
    if kind == "state_snapshots":
        return p2_table_candidates()
    if kind == "state_analysis":
        return p2_table_candidates(analysis_path, states="a")
    if kind == "distances":
        return [paths.distances(results, systems[0])]
    raise WorkflowError(f"figure input kind {kind!r} has no files in workflow/rules/figures.smk")


def figure_inputs(entry, systems):
    files = {kind: figure_input_files(kind, systems) for kind in entry.inputs}
    if {"state_snapshots", "state_analysis"} & set(entry.inputs):
        files["states"] = [P2_TABLE_STATES]  # which realization's states a, b, c
    return files


def figure_params(figure, caption, systems, file_stem=None):
    """What workflow/scripts/figure.py needs besides its files: the figure's id, its report caption, its systems,
    P1's force unit, the study's rattler rule (the networks the analysis measured) and the systems' labels; and the
    name of its files (`file_stem`, the id unless drawn again under a reading beside), which the caption links."""
    return dict(figure=figure, file_stem=file_stem or figure, caption=caption, systems=systems, force_unit=FORCE_UNIT,
                rattler_rule=study_rattler_rule(config, systems[0]),
                system_info={name: config["system_info"][name] for name in systems if name in config["system_info"]})


# the figures this config builds (every one of a study it lists), each with the systems it fits
# (forcenet.plotting.registry.figure_fit: one state, or a sequence where states a, b, c of a compression are read,
# leaves a system out, with a note in SKIPPED): all_targets builds them all
from forcenet.plotting.registry import figure_fit

STATE_COUNTS = {name: len(spec.rho_grid) for name, spec in SYSTEMS.items()}
BUILT_FIGURES = {}
for _entry in FIGURES:
    _kept, _notes = figure_fit(_entry, figure_systems(_entry), STATE_COUNTS, SEQUENCES)
    SKIPPED.extend(_notes)
    if _kept:
        BUILT_FIGURES[_entry.id] = (_entry, _kept)

for _figure, (_entry, _systems) in BUILT_FIGURES.items():

    rule:
        name:
            f"figure_{_figure}"
        localrule: True
        input:
            **figure_inputs(_entry, _systems),
        output:
            **figure_outputs(_figure, _entry.study.upper()),
        log:
            paths.log(RESULTS, "figures", _figure),
        params:
            **figure_params(_figure, _entry.report_caption, _systems),
        script:
            "../scripts/figure.py"


# P2's distance figures (Figs 6-10) again under the never-dying reading beside that leaves those classes out
# (docs/validation/controls.md §3), in that reading's results folder; the figures draw nothing else a reading changes.
# Their files are named apart (<figure>_essential_drop.pdf): the HTML report links a figure's PDF by its file name.
DROP_FIGURES = {f"{name}_essential_drop": (name, entry, systems) for name, (entry, systems) in BUILT_FIGURES.items()
                if "essential_drop" in READINGS and entry.study == "p2" and entry.inputs == ("distances",)}
DROP_RESULTS = READING_RESULTS.get("essential_drop")

for _drawn, (_figure, _entry, _systems) in DROP_FIGURES.items():

    rule:
        name:
            f"figure_{_drawn}"
        localrule: True
        input:
            distances=figure_input_files("distances", _systems, DROP_RESULTS),
        output:
            **figure_outputs(_drawn, _entry.study.upper(), DROP_RESULTS, READINGS["essential_drop"].label),
        log:
            paths.log(DROP_RESULTS, "figures", _drawn),
        params:
            **figure_params(_figure, f"{_entry.report_caption} Reading beside: {READINGS['essential_drop'].label}.",
                            _systems, file_stem=_drawn),
        script:
            "../scripts/figure.py"


def drop_figure_files(study="p2"):
    """The PDF, PNG and CSV of every figure drawn again under the `drop` reading (none for P1)."""
    return [paths.figure(DROP_RESULTS, drawn, fmt) for drawn in DROP_FIGURES if study == "p2"
            for fmt in paths.FIGURE_FORMATS]


# P1's claims are judged on its compressions: a sequence (SEQUENCES) is left out, and a study of sequences alone gets a
# table that says why it lists no claim
P1_CLAIMED = [s for s in P1_SYSTEMS if s not in SEQUENCES]
SKIPPED.extend(f"p1_validation: {s} left out: it is an imported sequence, and P1's claims are about compressions"
               for s in P1_SYSTEMS if s in SEQUENCES and P1_CLAIMED)
if P1_CLAIMED or not P1_SYSTEMS:

    rule p1_validation_table:
        localrule: True
        input:
            measures=[paths.network_measures(RESULTS, s) for s in P1_CLAIMED + P1_COUNTERPARTS],
            paper_size=paper_size_input("p1"),
            # P1 §3: the overlaps of every state and realization, judged at P1's depth above jamming
            snapshots=[snapshot_path(s, r, rho) for s in P1_CLAIMED for r in realizations(s)
                       for rho in SYSTEMS[s].rho_labels],
            # never-dying classes at death -1 in TP, bins
            diagrams=[paths.diagrams(RESULTS, s) for s in P1_CLAIMED + P1_COUNTERPARTS],
            # the tetrahedra reading beside (analyze.smk): the 3D systems with the other complex
            tetrahedra_measures=[paths.network_measures(TETRAHEDRA_RESULTS, s) for s in P1_SOLIDS],
            tetrahedra_diagrams=[paths.diagrams(TETRAHEDRA_RESULTS, s) for s in P1_SOLIDS],
        output:
            csv=paths.p1_validation_table(RESULTS, "csv"),
            md=report(paths.p1_validation_table(RESULTS, "md"), caption="../report/table.rst", category="P1",
                      subcategory=REPORT_TABLES),
        log:
            paths.log(RESULTS, "tables", "p1_validation"),
        params:
            systems=P1_CLAIMED,
            force_unit=FORCE_UNIT,
            paper_size=paper_size_table("p1"),
            tetrahedra_reading=READINGS["tetrahedra"].label,
            counterparts=P1_COUNTERPARTS,
            judges=JUDGES_DIGEST,  # common.smk: a changed judge reruns the table
        script:
            "../scripts/p1_validation.py"

else:
    from forcenet.pipeline import sequence_claims_note

    rule p1_validation_table:
        localrule: True
        output:
            csv=paths.p1_validation_table(RESULTS, "csv"),
            md=report(paths.p1_validation_table(RESULTS, "md"), caption="../report/table.rst", category="P1",
                      subcategory=REPORT_TABLES),
        log:
            paths.log(RESULTS, "tables", "p1_validation"),
        params:
            paper="P1",
            note=sequence_claims_note("P1", P1_SYSTEMS, [SYSTEMS[s].coordinate for s in P1_SYSTEMS]),
        script:
            "../scripts/no_claims_table.py"


# Compression movies (MP4, ffmpeg from the imageio-ffmpeg wheel): per P1 system, its force network through the ρ
# grid (realization 0, rattlers removed by P1's rule as in the analysis) and one turn around its B0/N surface (the
# data of Fig. 2). Part of the default build; `snakemake --cores 2 movies` builds only them.
# Imported systems have movies only where their entry sets `movies: true`, and a system with one state none.
def makes_movies(system):
    spec = SYSTEMS[system]
    if len(spec.rho_grid) < 2:
        SKIPPED.append(f"movies of {system}: not made: it has one state (a movie needs several)")
        return False
    if isinstance(spec, ImportedSystem) and not spec.movies:
        SKIPPED.append(f"movies of {system}: not made: an imported system's movies are opt-in "
                       f"(systems.{system}.movies: true)")
        return False
    return True


P1_MOVIES = {paths.movie_name(kind, system): (kind, system) for system in P1_SYSTEMS if makes_movies(system)
             for kind in ("network", "b0_surface")}


def movie_inputs(kind, system):
    if kind == "network":
        return [snapshot_path(system, realizations(system)[0], rho) for rho in SYSTEMS[system].rho_labels]
    return p1_measures()


for _movie, (_kind, _system) in P1_MOVIES.items():

    rule:
        name:
            f"movie_{_movie}"
        localrule: True
        input:
            movie_inputs(_kind, _system),
        output:
            paths.movie(RESULTS, _movie),
        log:
            paths.log(RESULTS, "movies", _movie),
        params:
            kind=_kind,
            system=_system,
            rattler_rule=study_rattler_rule(config, _system),
            force_unit=FORCE_UNIT,  # the b0_surface movie's ρ_max, as the figures
            system_info={name: info for name, info in config["system_info"].items() if name in P1_SYSTEMS + [_system]},
        script:
            "../scripts/movie.py"


rule movies:
    """Every compression movie (and what they need)."""
    localrule: True
    input:
        [paths.movie(RESULTS, name) for name in P1_MOVIES],


rule figures:
    """Every figure of the config's studies and their CSVs (and what they need; with config/validation.yaml, drawn
    at the papers' sizes from the campaign records, data/validation/README.md)."""
    localrule: True
    input:
        [paths.figure(RESULTS, name, fmt) for name in BUILT_FIGURES for fmt in paths.FIGURE_FORMATS]
        + drop_figure_files(),


for _study in ("p1", "p2"):

    rule:
        """Every figure of one study and their CSVs (figures_p1, figures_p2): one study's figures at the papers'
        sizes from the records while the other study's runs are still being made."""
        name: f"figures_{_study}"
        localrule: True
        input:
            [paths.figure(RESULTS, name, fmt) for name, (entry, _) in BUILT_FIGURES.items() if entry.study == _study
             for fmt in paths.FIGURE_FORMATS] + drop_figure_files(_study),


rule skipped_products:
    """The products this config does not make, or makes for fewer systems, and why (SKIPPED, common.smk)."""
    localrule: True
    output:
        report(paths.skipped_products(RESULTS), caption="../report/skipped.rst", category="Notes",
               subcategory=REPORT_TABLES),
    params:
        notes=SKIPPED,
    run:
        Path(output[0]).parent.mkdir(parents=True, exist_ok=True)
        Path(output[0]).write_text("# Products left out of this build\n\n"
                                   + "".join(f"- {note}\n" for note in params.notes), encoding="utf-8")


for _note in SKIPPED:
    print(f"forcenet: note: {_note}", file=sys.stderr)
