"""Every figure of P1 and P2, once: its id (the on-disk name), the functions that prepare and draw it, the data
products it reads, its caption and the paper figure it reproduces.

The workflow makes one rule per entry (``workflow/rules/figures.smk`` loops over `FIGURES`): rule
``figure_<id>`` writes ``results/figures/<id>.{pdf,png,csv}``, reads the files of the entry's `inputs`, and puts the
figure in the HTML report under `FigureEntry.report_caption`; every built figure is a target of the default build.
Adding a figure is one entry here plus its functions (docs/architecture.md, "A new figure").

Names: the preparation of figure ``<id>`` is ``prepare_<id>`` and its drawing ``draw_<id>``; a preparation or a
drawing shared by several figures is named for what it does (``draw_threshold_families``, ``prepare_distances``)
and the entry gives the options that make it this figure (`FigureEntry.options`). Functions are named as
``"<module of forcenet.plotting>:<function>"`` and imported only when a figure is made, so that this module, read
when the workflow is parsed, imports nothing heavy (no matplotlib, xarray or numba).

How a figure is made (`figure_data`, then `draw_figure`): the preparation is called with one argument per input kind,
in the entry's order, the entry's `options`, and those of the run's options it takes by name — ``system`` (the one
system of a figure whose `FigureEntry.systems` is not "all"), ``force_unit`` (``analysis.p1_force_unit``: the unit
of P1's F_max rule whose ρ_max the ρ-axis figures mark), ``rattler_rule`` (the study's rule: a figure that builds
networks from snapshots draws the edges the analysis measured) and ``source`` (the entry's `paper`); it returns a
`FigureData` (its table is the CSV). The drawing takes that `FigureData` and returns a matplotlib Figure.
"""
from __future__ import annotations

import importlib
import inspect
from dataclasses import dataclass, field
from typing import Any, Callable, Mapping

#: the data products a figure can read → what the preparation receives for each (the workflow finds the files)
INPUT_KINDS = {
    "measures": "results/{system}/network_measures.nc of each of the figure's systems: {system: dataset}",
    "diagrams": "results/{system}/diagrams.nc of each of the figure's systems: {system: dataset}",
    "example_snapshots": "the last snapshot (largest ρ) of realization 0 of each of the figure's systems: "
                         "{system: dataset}",
    "state_snapshots": "the snapshots of the consecutive states a, b, c (P2 Tables I–III) of the realization that "
                       "rule p2_table_states chose: [a, b, c]",
    "state_analysis": "the analysis file of state a of that realization: one dataset",
    "distances": "results/{system}/distances.nc of the figure's one system: one dataset",
}
#: which systems of its study a figure reads: every one, or P2's first (frictional) or second (frictionless) system
SYSTEM_CHOICES = ("all", "frictional", "frictionless")
#: the run's options a preparation may take by name (module docstring)
RUN_OPTIONS = ("system", "force_unit", "rattler_rule", "source")


@dataclass(frozen=True)
class FigureEntry:
    """One figure.

    id : the on-disk name, ``results/figures/<id>.{pdf,png,csv}``, and the rule ``figure_<id>``; it starts with its
        study (``p1_``, ``p2_``), whose systems it reads.
    paper : the figure of the paper it reproduces ("P1 Fig. 4"), or the section that defines what it shows.
    prepare, draw : ``"<module of forcenet.plotting>:<function>"`` (module docstring).
    inputs : the data products it reads, keys of `INPUT_KINDS`, in the order the preparation takes them.
    caption : what the figure shows (the HTML report adds `paper`).
    systems : one of `SYSTEM_CHOICES`.
    options : fixed keyword arguments of a shared preparation (e.g. ``{"kind": "normal"}``).
    """

    id: str
    paper: str
    prepare: str
    draw: str
    inputs: tuple[str, ...]
    caption: str
    systems: str = "all"
    options: Mapping[str, Any] = field(default_factory=dict)

    @property
    def study(self) -> str:
        """"p1" or "p2": the study whose systems the figure reads."""
        return self.id.split("_", 1)[0]

    @property
    def report_caption(self) -> str:
        return f"{self.caption} ({self.paper})."


_CUT = (" Every simulated ρ; ρ_max of P1's F_max rule (§3) dashed, the range beyond it (not shown in P1) shaded;"
        " mean over realizations, band ± 1 s.d.")
_P2_BAND = " Mean over realizations, band ± 1 standard deviation."

FIGURES: tuple[FigureEntry, ...] = (
    # --- P1: the stacked measures (and diagrams, example snapshots) of every P1 system ---------------------------
    FigureEntry("p1_fig01_networks", "P1 Fig. 1", "networks:prepare_p1_fig01_networks",
                "networks:draw_p1_fig01_networks", ("example_snapshots",),
                "Force networks of a 2D and a 3D snapshot at the largest ρ, edges coloured by F/⟨F⟩, rattlers "
                "removed by P1's rule as in the analysis"),
    FigureEntry("p1_fig02_betti0_surface", "P1 Fig. 2", "p1:prepare_p1_fig02_betti0_surface", "p1:draw_heat_maps",
                ("measures",), "Number of clusters B0/N over packing fraction ρ and force threshold F_th for each "
                "system." + _CUT),
    FigureEntry("p1_fig03_force_pdf", "P1 Fig. 3", "p1:prepare_p1_fig03_force_pdf", "p1:draw_p1_fig03_force_pdf",
                ("measures",), "PDF of F/⟨F⟩ at several ρ for each system, darker for larger ρ." + _CUT),
    FigureEntry("p1_fig04_cluster_size", "P1 Fig. 4", "p1:prepare_p1_fig04_cluster_size",
                "p1:draw_threshold_families", ("measures",),
                "Mean size of the non-percolating clusters ⟨S⟩/N versus ρ per F_th." + _CUT),
    FigureEntry("p1_fig05_percolating_cluster", "P1 Fig. 5", "p1:prepare_p1_fig05_percolating_cluster",
                "p1:draw_threshold_families", ("measures",),
                "Size of the percolating cluster N_per/N versus ρ per F_th, where ≥ 50 % of the realizations "
                "percolate." + _CUT),
    FigureEntry("p1_fig06_betti0", "P1 Fig. 6", "p1:prepare_p1_fig06_betti0", "p1:draw_p1_fig06_betti0",
                ("measures",), "B0/N versus ρ per F_th, with a close-up of small F_th in 3D." + _CUT),
    FigureEntry("p1_fig07_betti1", "P1 Fig. 7", "p1:prepare_p1_fig07_betti1", "p1:draw_threshold_families",
                ("measures",), "Loops B1/N (and cavities B2/N in 3D) versus ρ per F_th." + _CUT),
    FigureEntry("p1_fig08_shape_heatmap", "P1 Fig. 8", "p1:prepare_p1_fig08_shape_heatmap", "p1:draw_heat_maps",
                ("measures",), "Shape parameter S_p over (ρ, F_th) with P1's averaging rule (§5.2)." + _CUT),
    FigureEntry("p1_fig09_shape_sections", "P1 Fig. 9", "p1:prepare_p1_fig09_shape_sections",
                "p1:draw_threshold_families", ("measures",), "Shape parameter S_p versus ρ for chosen F_th." + _CUT),
    FigureEntry("p1_fig10_persistence_diagram", "P1 Fig. 10", "p1:prepare_p1_fig10_persistence_diagram",
                "p1:draw_p1_fig10_persistence_diagram", ("measures", "diagrams"),
                "An example PD0 with the rough, weak, medium and strong persistence bins"),
    FigureEntry("p1_fig11_persistence_bins", "P1 Fig. 11", "p1:prepare_p1_fig11_persistence_bins",
                "p1:draw_p1_fig11_persistence_bins", ("measures", "diagrams"),
                "PD0 points per bin N0/N versus ρ, 2D and 3D; a never-dying class in the bin of its birth (death −1)."
                + _CUT),
    FigureEntry("p1_fig12_total_persistence", "P1 Fig. 12", "p1:prepare_p1_fig12_total_persistence",
                "p1:draw_p1_fig12_total_persistence", ("measures", "diagrams"),
                "Total persistence TP0/N and TP1/N versus ρ, never-dying classes at death −1." + _CUT),
    FigureEntry("p1_z_jamming", "P1 §4, the jamming point", "p1:prepare_p1_z_jamming", "p1:draw_p1_z_jamming",
                ("measures",), "Coordination number Z(ρ) with the jamming point ρ_J (inflection) marked"),
    # --- P2: one realization's consecutive states, or one system's distances.nc ---------------------------------
    FigureEntry("p2_fig01_snapshots_differences", "P2 Fig. 1", "networks:prepare_p2_fig01_snapshots_differences",
                "networks:draw_p2_fig01_snapshots_differences", ("state_snapshots",),
                "Three nearby snapshots a, b, c (normal forces) and maps of the force change ΔF between them",
                systems="frictional"),
    FigureEntry("p2_fig03_diagrams", "P2 Fig. 3", "p2:prepare_p2_fig03_diagrams", "p2:draw_p2_fig03_diagrams",
                ("state_analysis",), "PD0 and PD1 of the normal-force network of snapshot a", systems="frictional"),
    FigureEntry("p2_fig06_distances_normal_mu05", "P2 Fig. 6", "p2:prepare_distances", "p2:draw_distances",
                ("distances",), "d_B, d_W1, d_W2 between consecutive PDs vs ρ for β0 and β1 with Z(ρ); μ = 0.5, "
                "normal forces." + _P2_BAND, systems="frictional", options={"kind": "normal"}),
    FigureEntry("p2_fig07_ratios_mu05", "P2 Fig. 7", "p2:prepare_ratios", "p2:draw_ratios", ("distances",),
                "Ratios d_B/d_W1 and d_B/d_W2; μ = 0.5, normal forces." + _P2_BAND, systems="frictional",
                options={"kind": "normal"}),
    FigureEntry("p2_fig08_distances_tangential_mu05", "P2 Fig. 8", "p2:prepare_distances", "p2:draw_distances",
                ("distances",), "As Fig. 6 for tangential forces." + _P2_BAND, systems="frictional",
                options={"kind": "tangential"}),
    FigureEntry("p2_fig09_distances_normal_mu0", "P2 Fig. 9", "p2:prepare_distances", "p2:draw_distances",
                ("distances",), "As Fig. 6 for the frictionless system μ = 0." + _P2_BAND, systems="frictionless",
                options={"kind": "normal"}),
    FigureEntry("p2_fig10_ratios_mu0", "P2 Fig. 10", "p2:prepare_ratios", "p2:draw_ratios", ("distances",),
                "As Fig. 7 for μ = 0." + _P2_BAND, systems="frictionless", options={"kind": "normal"}),
)
FIGURES_BY_ID: dict[str, FigureEntry] = {entry.id: entry for entry in FIGURES}

#: the figures that draw a measure over the states of a run (curves or surfaces along ρ, or along a sequence's
#: coordinate): a system with one state has nothing to draw there and is left out of them (`figure_fit`)
SEVERAL_STATE_FIGURES = frozenset({
    "p1_fig02_betti0_surface", "p1_fig04_cluster_size", "p1_fig05_percolating_cluster", "p1_fig06_betti0",
    "p1_fig07_betti1", "p1_fig08_shape_heatmap", "p1_fig09_shape_sections", "p1_fig11_persistence_bins",
    "p1_fig12_total_persistence", "p1_z_jamming"})
#: the figures that compare three nearby states a, b, c of a compression (P2 Tables I–III's): not made for a
#: sequence, whose states share one ρ
COMPRESSION_STATE_FIGURES = frozenset(entry.id for entry in FIGURES
                                      if {"state_snapshots", "state_analysis"} & set(entry.inputs))


def figure_fit(entry: FigureEntry, systems, state_counts: Mapping[str, int],
               sequences=()) -> tuple[list[str], list[str]]:
    """(the systems figure `entry` is drawn for, one-line notes on those it leaves out) among `systems`:
    a figure of `SEVERAL_STATE_FIGURES` leaves out a system with fewer than two states (`state_counts`), and one of
    `COMPRESSION_STATE_FIGURES` a sequence (`sequences`). A figure left with no system is not made: its notes say
    why (the workflow prints them and lists them in ``tables/skipped.md``)."""
    kept, notes = [], []
    for name in systems:
        if entry.id in SEVERAL_STATE_FIGURES and state_counts.get(name, 0) < 2:
            notes.append(f"{entry.id}: {name} left out: it has {state_counts.get(name, 0)} state, and the figure "
                         "draws a measure over the states of a run")
        elif entry.id in COMPRESSION_STATE_FIGURES and name in sequences:
            notes.append(f"{entry.id}: {name} left out: it is a sequence at constant ρ, and the figure compares three "
                         "nearby states of a compression (P2 Tables I–III's a, b, c)")
        else:
            kept.append(name)
    if systems and not kept:  # one line: the figure is not made
        notes = [f"{entry.id}: not made: " + "; ".join(note.split(": ", 1)[1] for note in notes)]
    return kept, notes


def figure_entry(figure_id: str) -> FigureEntry:
    """The entry of `figure_id`; KeyError naming the known ids otherwise."""
    if figure_id not in FIGURES_BY_ID:
        raise KeyError(f"unknown figure {figure_id!r}; known: {', '.join(FIGURES_BY_ID)}")
    return FIGURES_BY_ID[figure_id]


def resolve(name: str) -> Callable:
    """The function named ``"<module of forcenet.plotting>:<function>"`` (imported now)."""
    module, function = name.split(":")
    return getattr(importlib.import_module(f"forcenet.plotting.{module}"), function)


def registry_problems(entries=FIGURES) -> list[str]:
    """What is wrong with `entries` (none for `FIGURES`): a repeated id, an id without its study prefix, an unknown
    input kind or system choice, a function that does not exist, a preparation that does not take one argument per
    input, the entry's options or a system, or a function named neither after its figure (``prepare_<id>``,
    ``draw_<id>``) nor shared by several entries. Imports every plotting module (call it from tests)."""
    problems, seen = [], set()
    uses = {}
    for entry in entries:
        for name in (entry.prepare, entry.draw):
            uses[name] = uses.get(name, 0) + 1
    for entry in entries:
        where = f"{entry.id}:"
        if entry.id in seen:
            problems.append(f"{where} id used twice")
        seen.add(entry.id)
        if entry.study not in ("p1", "p2"):
            problems.append(f"{where} id must start with its study, p1_ or p2_")
        problems += [f"{where} unknown input kind {kind!r}" for kind in entry.inputs if kind not in INPUT_KINDS]
        if entry.systems not in SYSTEM_CHOICES:
            problems.append(f"{where} systems must be one of {SYSTEM_CHOICES}, got {entry.systems!r}")
        for role, name in (("prepare", entry.prepare), ("draw", entry.draw)):
            try:
                function = resolve(name)
            except (AttributeError, ImportError, ValueError) as error:
                problems.append(f"{where} {role} function {name!r} not found ({error})")
                continue
            if not callable(function):
                problems.append(f"{where} {name!r} is not a function")
                continue
            if name.split(":")[1] != f"{role}_{entry.id}" and uses[name] < 2:
                problems.append(f"{where} {role} function {name!r} is neither {role}_{entry.id} nor shared")
            if role == "prepare":
                problems += [f"{where} {problem}" for problem in _signature_problems(function, entry)]
    return problems


def _signature_problems(prepare: Callable, entry: FigureEntry) -> list[str]:
    parameters = list(inspect.signature(prepare).parameters.values())
    positional = [p for p in parameters if p.kind in (p.POSITIONAL_ONLY, p.POSITIONAL_OR_KEYWORD)]
    names = {p.name for p in parameters}
    problems = []
    if len(positional) != len(entry.inputs):
        problems.append(f"the preparation takes {len(positional)} inputs, the entry names {len(entry.inputs)}")
    problems += [f"the preparation takes no option {key!r}" for key in entry.options if key not in names]
    if entry.systems != "all" and "system" not in names:
        problems.append("the preparation of a figure of one system must take `system`")
    if entry.systems == "all" and "system" in names:
        problems.append("a figure of every system of its study is given no `system`: name the option otherwise")
    return problems


def figure_data(figure_id: str, *inputs, **run_options):
    """The `FigureData` of figure `figure_id` from its inputs (one per `FigureEntry.inputs`, in that order).

    `run_options` (names in `RUN_OPTIONS`, or options of its preparation such as ``thresholds``) go to the
    preparation when it takes them by name; None means "not given". ValueError when an input is missing.
    """
    entry = figure_entry(figure_id)
    if len(inputs) != len(entry.inputs) or any(value is None or (isinstance(value, (dict, list, tuple)) and not value)
                                               for value in inputs):
        raise ValueError(f"{figure_id} needs {', '.join(entry.inputs)}")
    prepare = resolve(entry.prepare)
    accepted = inspect.signature(prepare).parameters
    options = {key: value for key, value in run_options.items() if value is not None
               and (key in accepted or key not in RUN_OPTIONS)}
    if "source" in accepted:
        options.setdefault("source", entry.paper)
    return prepare(*inputs, **entry.options, **options)


def draw_figure(figure_id: str, data):
    """The matplotlib Figure of figure `figure_id` drawn from its prepared data."""
    return resolve(figure_entry(figure_id).draw)(data)


def make_figure(figure_id: str, *inputs, **run_options):
    """Prepare and draw figure `figure_id` (`figure_data`, then `draw_figure`)."""
    return draw_figure(figure_id, figure_data(figure_id, *inputs, **run_options))
