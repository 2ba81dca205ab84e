"""The figure and movie jobs of the workflow (rules in workflow/rules/figures.smk): each opens its input files with
the validated readers, prepares the data with `forcenet.plotting.registry`, draws it and writes the values it draws."""
from __future__ import annotations

from typing import Mapping, Sequence

from forcenet.pipeline import chosen_datasets, job_logger, open_by_system


def figure(*, name: str, systems: Sequence[str], inputs: Mapping[str, Sequence[str]], pdf: str, png: str, csv: str,
           force_unit: str | None = None, rattler_rule: bool | str | None = None,
           system_info: Mapping[str, Mapping[str, str]] | None = None, log_path: str | None = None) -> None:
    """Draw the figure `name` (an id of `forcenet.plotting.registry.FIGURES`) from its input files, and write the
    values it draws to `csv` (one preparation feeds both).

    `inputs` maps each input kind of the figure's entry to its files (and ``states`` to the table of chosen states
    for the state kinds); `systems` are the figure's systems (one for a figure that reads one, given to its
    preparation as `system`);
    `force_unit` (``analysis.p1_force_unit``) is the unit of P1's F_max rule whose ρ_max the ρ-axis figures mark;
    `rattler_rule` is the study's (figures that build networks from snapshots); `system_info` the catalog's label
    and colour of each system (the config's ``system_info``)."""
    from forcenet.plotting.figure_data import write_csv
    from forcenet.plotting.registry import draw_figure, figure_data, figure_entry
    from forcenet.plotting.style import apply_style, save_figure, use_state_axes, use_system_styles

    with job_logger(log_path, f"figure.{name}") as log:
        apply_style()
        use_system_styles(system_info or {})
        entry = figure_entry(name)
        opened = [FIGURE_INPUT_READERS[kind](inputs[kind], inputs) for kind in entry.inputs]
        use_state_axes([ds for value in opened for ds in ([value] if hasattr(value, "attrs") else  # a dataset
                                                          value.values() if isinstance(value, Mapping) else value)])
        one_system = systems[0] if entry.systems != "all" else None  # a P1 preparation's `system` is a choice
        data = figure_data(name, *opened, system=one_system, force_unit=force_unit, rattler_rule=rattler_rule)
        save_figure(draw_figure(name, data), pdf, png)
        write_csv(with_state_columns(data), csv)
        log.info("%s drawn for %s (%d rows of source data)", name, ", ".join(systems), len(data.table))


def with_state_columns(data):
    """`data` (a `FigureData`) as its CSV gives it: the ``rho`` column of a figure whose every system is a sequence of
    one coordinate named after that coordinate and its unit (``strain``, ``t [s]``, `forcenet.plotting.style.
    state_column`); of a figure that draws sequences beside compressions, a ``state_axis`` column naming each row's."""
    from forcenet.plotting import figure_data as cols
    from forcenet.plotting.figure_data import FigureData
    from forcenet.plotting.style import is_sequence, state_column

    table = data.table
    if cols.RHO not in table or cols.SYSTEM not in table or not any(map(is_sequence, table[cols.SYSTEM].unique())):
        return data
    columns = {state_column(name) for name in table[cols.SYSTEM].unique()}
    if len(columns) == 1:
        return FigureData(table.rename(columns={cols.RHO: columns.pop()}), data.layout)
    table = table.copy()
    table.insert(list(table.columns).index(cols.RHO), "state_axis", table[cols.SYSTEM].map(state_column))
    return FigureData(table, data.layout)


def _chosen_states(paths: Sequence[str], inputs: Mapping[str, Sequence[str]], reader) -> list:
    """The files of the realization that ``inputs["states"]`` (rule p2_table_states) chose, opened by `reader`."""
    return chosen_datasets(paths, inputs["states"][0], reader)


def _read_state_snapshots(paths, inputs):
    from forcenet.datasets import read_snapshot

    return _chosen_states(paths, inputs, read_snapshot)


def _read_state_analysis(paths, inputs):
    from forcenet.datasets import read_dataset

    return _chosen_states(paths, inputs, lambda path: read_dataset(path, "analysis"))[0]


def _read_distances(paths, inputs):
    from forcenet.datasets import read_dataset

    return read_dataset(paths[0], "distances")


#: input kind of a figure (`forcenet.plotting.registry.INPUT_KINDS`) → how its files are opened:
#: reader(files of that kind, every input of the rule)
FIGURE_INPUT_READERS = {
    "measures": lambda paths, inputs: open_by_system(paths, "network_measures"),
    "diagrams": lambda paths, inputs: open_by_system(paths, "diagrams"),
    "example_snapshots": lambda paths, inputs: open_by_system(paths, "snapshot"),
    "state_snapshots": _read_state_snapshots,
    "state_analysis": _read_state_analysis,
    "distances": _read_distances,
}


def movie(*, kind: str, system: str, inputs: Sequence[str], output: str, rattler_rule: bool | str,
          log_path: str | None = None, force_unit: str | None = None,
          system_info: Mapping[str, Mapping[str, str]] | None = None) -> None:
    """One compression movie of `system` (`forcenet.plotting.movies`): kind "network" from the snapshots of one
    run in ρ order (`inputs`), networks made by the study's `rattler_rule`; kind "b0_surface" from the
    network_measures.nc of every P1 system, its ρ_max from ⟨F⟩ in `force_unit` (``analysis.p1_force_unit``)."""
    from forcenet.datasets import read_snapshot
    from forcenet.plotting import movies
    from forcenet.plotting.style import use_state_axes, use_system_styles

    with job_logger(log_path, f"movie.{kind}.{system}") as log:
        use_system_styles(system_info or {})
        if kind == "network":
            frames = movies.network_movie([read_snapshot(p) for p in inputs], output, rattler_rule=rattler_rule)
        elif kind == "b0_surface":
            measures = open_by_system(inputs, "network_measures")
            use_state_axes(measures.values())
            frames = movies.b0_surface_movie(measures, system, output,
                                             force_unit=force_unit)
        else:
            raise ValueError(f"unknown movie kind {kind!r}; known: network, b0_surface")
        log.info("%s movie of %s: %d frames", kind, system, frames)
