"""The figures of P1 (compressed 2D/3D interaction networks) that read the stacked measures and diagrams: per
figure, one function that prepares its data and one that draws it (Fig. 1, the networks, is in
`forcenet.plotting.networks`; `forcenet.plotting.registry` lists every figure with its inputs and caption).

The preparation (``prepare_<figure id>``) takes the aggregated datasets keyed by system name — ``measures``
(network_measures.nc), ``diagrams`` (diagrams.nc) — and returns a `FigureData` whose table holds every plotted
value (the figure's CSV); the drawing (``draw_<figure id>``, or the shared `draw_threshold_families` and
`draw_heat_maps`) turns that into a matplotlib Figure and reads nothing else. The preparations only select and
average: the reductions P1 defines (F_max rule → ρ_max, S_p averaging rule, ≥ 50 % percolation rule, jamming
point) live in `forcenet.report.p1` and are shared with the validation table. Every simulated ρ is drawn; ρ_max,
with ⟨F⟩ compared in `force_unit` (``analysis.p1_force_unit``), is a dashed line on every ρ axis with the range
beyond it shaded. Curves are realization means with ± one standard deviation over the realizations as a band; each
system keeps its colour (`forcenet.plotting.style.system_color`), a family of curves within a panel (F_th, ρ) uses
shades of it.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Callable, Mapping, Sequence

import numpy as np
import pandas as pd
import xarray as xr

from forcenet.measures.persistence_stats import MEDIUM_BIRTH, ROUGH_LIFESPAN, STRONG_BIRTH, WEAK_BIRTH
from forcenet.plotting import figure_data as cols
from forcenet.plotting.figure_data import FigureData, concat, curve_rows
from forcenet.plotting.style import (LABELS, is_sequence, panel_figure, state_axis_label, system_color, system_label,
                                     system_shades, system_title)
from forcenet.report.p1 import (DEFAULT_P1_FORCE_UNIT, P1_SMALL_THRESHOLD, f_max_cut, jamming_point,
                                never_dying_at_minus_one, per_particle, percolating_size_mean, rho_values, select_total,
                                shape_parameter_average, system_dimension, system_order)
from forcenet.report.realizations import mean_and_spread, realization_mean

import matplotlib.pyplot as plt  # noqa: E402  (style sets the Agg backend first)
import seaborn as sns  # noqa: E402
from matplotlib.figure import Figure  # noqa: E402

#: F_th cross-sections drawn in the line figures (the nearest values of the threshold grid are used)
DEFAULT_THRESHOLDS = (0.0, 0.5, 1.0, 1.5, 2.0, 2.5)
PD_BINS = ("rough", "weak", "medium", "strong")  # P1 §5.3 bins drawn in Figs. 10-11 (essential points apart)

MEAN_GID = "mean"  # gid of every realization-mean curve, so that tests (and readers) can find them
RHO_J_GID = "rho_J"
RHO_MAX_GID = "rho_max"  # the dashed ρ_max line; the shading beyond it is BEYOND_RHO_MAX_GID
BEYOND_RHO_MAX_GID = "beyond_rho_max"
RHO_MAX_COLUMN = "rho_max"  # CSV column: ρ_max of P1's F_max rule for the row's system

LABEL_B0 = r"$B_0/N$"
LABEL_B1 = r"$B_1/N$"
LABEL_B2 = r"$B_2/N$"
LABEL_S = r"$\langle S\rangle/N$"
LABEL_NPER = r"$N_{per}/N$"
LABEL_SP = r"shape parameter $S_p$"
LABEL_N0 = r"$N_0/N$"
LABEL_TP = r"$TP_k/N$ [$\langle F\rangle$]"


#: plain-text symbol [unit] of each drawn quantity (the CSV's `quantity` column) → its axis label
QUANTITY_LABELS = {
    "B0/N": LABEL_B0, "B1/N": LABEL_B1, "B2/N": LABEL_B2, "<S>/N": LABEL_S, "N_per/N": LABEL_NPER,
    "S_p": LABEL_SP, "N0/N": LABEL_N0, "TP_k/N [<F>]": LABEL_TP, "Z": LABELS["Z"],
    "PDF [<F>^-1]": LABELS["pdf"] + r" [$\langle F\rangle^{-1}$]",
}
HOMOLOGY_K = "k"  # family column of Fig. 12: TP_k, k = 0 (solid), 1 (dashed)


# =============================================================================================================
# helpers: selection, panels, curves
# =============================================================================================================
@dataclass(frozen=True)
class _System:
    name: str
    data: xr.Dataset  # total force, every simulated ρ
    rho_j: float
    dimension: int
    rho_max: float  # P1 §3 F_max rule; NaN when every ρ has ⟨F⟩ > F_max (`rho_max_below_grid`)
    rho_max_below_grid: bool = False


def _systems(measures: Mapping[str, xr.Dataset], force_unit: str = DEFAULT_P1_FORCE_UNIT) -> list[_System]:
    """The systems in P1's order, each with its ρ_J and its ρ_max (P1 §3 F_max rule, ⟨F⟩ in `force_unit`)."""
    if not measures:
        raise ValueError("no system to plot")
    # a sequence (drawn against its coordinate, `style.is_sequence`) has neither ρ_J nor ρ_max, and no place in the cut
    compressions = {name: ds for name, ds in measures.items() if not is_sequence(name)}
    cut = f_max_cut(compressions, force_unit) if compressions else None
    return [_System(name, select_total(measures[name]), jamming_point(measures[name]),
                    system_dimension(measures[name], name), cut.rho_max[name], cut.below_grid(name))
            if name in compressions else
            _System(name, select_total(measures[name]), float("nan"), system_dimension(measures[name], name),
                    float("nan"))
            for name in system_order(measures)]


def _marks(system: _System) -> dict:
    """The ρ_J and ρ_max columns every ρ-curve row carries (the CSV says where P1 would stop showing data)."""
    return {cols.RHO_J: system.rho_j, RHO_MAX_COLUMN: system.rho_max}


def _nearest(values: np.ndarray, wanted: Sequence[float]) -> list[float]:
    """The grid values nearest to `wanted`, each once, in increasing order."""
    values = np.asarray(values, dtype=float)
    picked = {float(values[np.argmin(np.abs(values - w))]) for w in wanted}
    return sorted(picked)


def _mean_rows(values: xr.DataArray | tuple, system: _System, family: str, family_values: Sequence[float],
               quantity: str, panel: int) -> pd.DataFrame:
    """Rows of curves versus ρ, one per value of `family` (a dimension of `values`, here F_th): `values` is
    (realization, rho, family) or a (mean, spread) pair; the band is mean ± spread."""
    mean, spread = values if isinstance(values, tuple) else mean_and_spread(values)
    rho = rho_values(system.data)
    blocks = []
    for value in family_values:
        blocks.append(_spread_rows(cols.RHO, rho, mean.sel(threshold=value).transpose("rho"),
                                   spread.sel(threshold=value).transpose("rho"), **{
            cols.PANEL: panel, cols.SYSTEM: system.name, cols.QUANTITY: quantity, family: value,
            **_marks(system)}))
    return concat(blocks)


def _spread_rows(x_name: str, x, mean, spread, **columns) -> pd.DataFrame:
    """Rows of one curve whose band is mean ± spread."""
    mean, spread = np.asarray(mean, dtype=float), np.asarray(spread, dtype=float)
    return curve_rows(x_name, x, mean, mean - spread, mean + spread, **columns)


def _panels(data: FigureData, **figure_options):
    """A figure with one panel per `panel` value of the table: (figure, [(axes, rows of that panel), …])."""
    panels = sorted(data.table[cols.PANEL].unique())
    fig, axes = panel_figure(len(panels), **figure_options)
    return fig, [(ax, data.panel(panel)) for ax, panel in zip(axes, panels)]


def _threshold_rows(system: _System, values, thresholds: Sequence[float], quantity: str, panel: int) -> pd.DataFrame:
    """Curves versus ρ at the grid's F_th nearest to `thresholds`."""
    grid = (values[0] if isinstance(values, tuple) else values)["threshold"].values
    return _mean_rows(values, system, cols.THRESHOLD, _nearest(grid, thresholds), quantity, panel)


def _curve(ax, x, mean, low, high, color, label=None, **line):
    x, mean, low, high = (np.asarray(v, dtype=float) for v in (x, mean, low, high))
    ax.plot(x, mean, color=color, label=label, gid=MEAN_GID, **line)
    ax.fill_between(x, low, high, color=color, alpha=0.2, linewidth=0)


def _draw_rows(ax, rows: pd.DataFrame, x: str, color, label=None, **line) -> None:
    """One curve and its band from table rows."""
    _curve(ax, rows[x], rows[cols.MEAN], rows[cols.LOW], rows[cols.HIGH], color, label, **line)


def _mark_jamming(ax, rho_j: float, name: str) -> None:
    """ρ_J of system `name` as a dotted vertical line in its colour."""
    if np.isfinite(rho_j):
        ax.axvline(rho_j, color=system_color(name), linestyle=":", linewidth=1, gid=RHO_J_GID)


def _mark_rho_max(ax, rows: pd.DataFrame, name: str, color=None, label: bool = True) -> None:
    """ρ_max of P1's F_max rule (§3) as a dashed vertical line, the ρ beyond it (where P1 shows nothing) lightly
    shaded; every ρ shaded when ρ_max lies below the grid (NaN)."""
    if RHO_MAX_COLUMN not in rows or cols.RHO not in rows or is_sequence(name):
        return
    color = system_color(name) if color is None else color
    rho_max = float(rows[RHO_MAX_COLUMN].iloc[0])
    low, high = float(rows[cols.RHO].min()), float(rows[cols.RHO].max())
    if not np.isfinite(rho_max):
        ax.axvspan(low, high, color=color, alpha=0.08, linewidth=0, gid=BEYOND_RHO_MAX_GID,
                   label=r"every $\rho$ > $\rho_{max}$ (P1 §3)" if label else None)
        return
    ax.axvline(rho_max, color=color, linestyle="--", linewidth=1, gid=RHO_MAX_GID,
               label=r"$\rho_{max}$ (P1 §3)" if label else None)
    if high > rho_max:
        ax.axvspan(rho_max, high, color=color, alpha=0.08, linewidth=0, gid=BEYOND_RHO_MAX_GID)


def _draw_family(ax, rows: pd.DataFrame, family: str, label: Callable[[float], str]) -> None:
    """A panel of curves versus ρ, one per value of `family`, in shades of the system's colour; ρ_J marked."""
    name = rows[cols.SYSTEM].iloc[0]
    values = sorted(rows[family].unique())
    for color, value in zip(system_shades(name, len(values)), values):
        _draw_rows(ax, rows[rows[family] == value], cols.RHO, color, label=label(value))
    _mark_jamming(ax, float(rows[cols.RHO_J].iloc[0]), name)
    _mark_rho_max(ax, rows, name)
    ax.set_xlabel(state_axis_label(name))
    ax.set_ylabel(QUANTITY_LABELS[rows[cols.QUANTITY].iloc[0]])
    system_title(ax, name)


def _threshold_label(threshold: float) -> str:
    return rf"$F_{{th}}$ = {threshold:g}"


def draw_threshold_families(data: FigureData, ncols: int = 3) -> Figure:
    """One panel per `panel` value, each a family of F_th curves (Figs. 4, 5, 7, 9)."""
    fig, panels = _panels(data, ncols=ncols)
    for ax, rows in panels:
        _draw_family(ax, rows, cols.THRESHOLD, _threshold_label)
    _first_legend([ax for ax, _ in panels])
    return fig


def _heat_rows(system: _System, values: xr.DataArray, quantity: str, panel: int) -> pd.DataFrame:
    """A realization-averaged (threshold, rho) map as rows (ρ, F_th, value)."""
    values = values.transpose("rho", "threshold")
    rho = np.repeat(rho_values(system.data), values.sizes["threshold"])
    threshold = np.tile(values["threshold"].values, values.sizes["rho"])
    return pd.DataFrame({cols.PANEL: panel, cols.SYSTEM: system.name, cols.QUANTITY: quantity, **_marks(system),
                         cols.RHO: rho, cols.THRESHOLD: threshold, cols.MEAN: values.values.ravel()})


def draw_heat_maps(data: FigureData) -> Figure:
    """One (ρ, F_th) map per panel, ρ on x."""
    fig, panels = _panels(data)
    for ax, rows in panels:
        grid = rows.pivot(index=cols.THRESHOLD, columns=cols.RHO, values=cols.MEAN)
        mesh = ax.pcolormesh(grid.columns.values, grid.index.values, grid.values, shading="nearest", cmap="magma")
        name = rows[cols.SYSTEM].iloc[0]
        fig.colorbar(mesh, ax=ax, label=QUANTITY_LABELS[rows[cols.QUANTITY].iloc[0]])
        _mark_jamming(ax, float(rows[cols.RHO_J].iloc[0]), name)
        _mark_rho_max(ax, rows, name, color="white", label=False)
        ax.set_xlabel(state_axis_label(name))
        ax.set_ylabel(LABELS["threshold"])
        system_title(ax, name)
    return fig


def _first_legend(axes, **kwargs) -> None:
    if axes:
        axes[0].legend(fontsize="x-small", frameon=False, **kwargs)


def prepare_p1_fig02_betti0_surface(measures: Mapping[str, xr.Dataset], *,
                                    force_unit: str = DEFAULT_P1_FORCE_UNIT) -> FigureData:
    """F2: B0/N over (ρ, F_th), realization mean, one map per system."""
    return FigureData(concat(
        _heat_rows(system, realization_mean(per_particle(system.data, "betti").sel(homology_dim=0)),
                   "B0/N", panel)
        for panel, system in enumerate(_systems(measures, force_unit))))


def prepare_p1_fig03_force_pdf(measures: Mapping[str, xr.Dataset], *, n_rho: int = 6,
                               force_unit: str = DEFAULT_P1_FORCE_UNIT) -> FigureData:
    """F3: PDF of F/⟨F⟩ (total force) at `n_rho` packing fractions spread over the grid; those beyond ρ_max (not
    shown in P1) are drawn dashed."""
    blocks = []
    for panel, system in enumerate(_systems(measures, force_unit)):
        pdf = system.data["force_pdf"]
        mean, spread = mean_and_spread(pdf)
        rho = rho_values(system.data)
        picks = np.unique(np.round(np.linspace(0, rho.size - 1, min(n_rho, rho.size))).astype(int))
        for index in picks:
            blocks.append(_spread_rows(cols.FORCE, pdf["force_bin"].values, mean.isel(rho=index),
                                       spread.isel(rho=index), **{
                cols.PANEL: panel, cols.SYSTEM: system.name, cols.QUANTITY: "PDF [<F>^-1]", cols.RHO: rho[index],
                RHO_MAX_COLUMN: system.rho_max}))
    return FigureData(concat(blocks))


def draw_p1_fig03_force_pdf(data: FigureData) -> Figure:
    """One panel per system, one curve per ρ, darker for larger ρ."""
    fig, panels = _panels(data)
    for ax, rows in panels:
        name = rows[cols.SYSTEM].iloc[0]
        values = sorted(rows[cols.RHO].unique())
        rho_max = float(rows[RHO_MAX_COLUMN].iloc[0])
        for color, rho in zip(system_shades(name, len(values)), values):
            beyond = rho > rho_max + 1e-12  # beyond P1's range (False when ρ_max is NaN)
            _draw_rows(ax, rows[rows[cols.RHO] == rho], cols.FORCE, color,
                       label=rf"$\rho$ = {rho:.3f}" + (r" > $\rho_{max}$" if beyond else ""),
                       linestyle="--" if beyond else "-")
        ax.set_xlabel(LABELS["force"])
        ax.set_ylabel(QUANTITY_LABELS["PDF [<F>^-1]"])
        system_title(ax, name)
        ax.legend(fontsize="x-small", frameon=False)
    return fig


def prepare_p1_fig04_cluster_size(measures: Mapping[str, xr.Dataset], *,
                                  thresholds: Sequence[float] = DEFAULT_THRESHOLDS,
                                  force_unit: str = DEFAULT_P1_FORCE_UNIT) -> FigureData:
    """F4: mean size ⟨S⟩/N of the non-percolating clusters versus ρ, one curve per F_th."""
    return FigureData(concat(_threshold_rows(system, per_particle(system.data, "cluster_mean_size"), thresholds,
                                             "<S>/N", panel)
                             for panel, system in enumerate(_systems(measures, force_unit))))


def prepare_p1_fig05_percolating_cluster(measures: Mapping[str, xr.Dataset], *,
                                         thresholds: Sequence[float] = DEFAULT_THRESHOLDS,
                                         force_unit: str = DEFAULT_P1_FORCE_UNIT) -> FigureData:
    """F5: N_per/N versus ρ per F_th, averaged over the percolating realizations and shown only where at
    least 50 % of the realizations percolate (P1 §4.3)."""
    return FigureData(concat(_threshold_rows(system, percolating_size_mean(system.data), thresholds, "N_per/N", panel)
                             for panel, system in enumerate(_systems(measures, force_unit))))


def prepare_p1_fig06_betti0(measures: Mapping[str, xr.Dataset], *, thresholds: Sequence[float] = DEFAULT_THRESHOLDS,
                            zoom_curves: int = 4, force_unit: str = DEFAULT_P1_FORCE_UNIT) -> FigureData:
    """F6: B0/N versus ρ per F_th; for each 3D system an extra close-up of the F_th < 0.5 curves around ρ_J
    (P1 Fig. 6d). layout["close_up"] maps each close-up panel to its ρ range (None: the whole range)."""
    systems = _systems(measures, force_unit)
    blocks = [_threshold_rows(system, per_particle(system.data, "betti").sel(homology_dim=0), thresholds, "B0/N", panel)
              for panel, system in enumerate(systems)]
    close_up = {}
    for panel, system in enumerate((s for s in systems if s.dimension == 3), start=len(systems)):
        grid = system.data["threshold"].values
        small = grid[grid < P1_SMALL_THRESHOLD]
        chosen = small[np.unique(np.round(np.linspace(0, small.size - 1, min(zoom_curves, small.size))).astype(int))] \
            if small.size else grid[:1]
        blocks.append(_mean_rows(per_particle(system.data, "betti").sel(homology_dim=0), system, cols.THRESHOLD,
                                 [float(t) for t in chosen], "B0/N", panel))
        rho = rho_values(system.data)
        close_up[panel] = None  # the whole ρ range
        if np.isfinite(system.rho_j) and rho.size > 1:
            half_width = 4 * float(np.median(np.diff(rho)))
            close_up[panel] = (max(rho[0], system.rho_j - half_width), min(rho[-1], system.rho_j + half_width))
    return FigureData(concat(blocks), {"close_up": close_up})


def draw_p1_fig06_betti0(data: FigureData) -> Figure:
    close_up = data.layout.get("close_up", {})
    panels = sorted(data.table[cols.PANEL].unique())
    fig, axes = panel_figure(len(panels), ncols=4 if close_up else 3)
    for ax, panel in zip(axes, panels):
        rows = data.panel(panel)
        _draw_family(ax, rows, cols.THRESHOLD, _threshold_label)
        if panel in close_up:
            if close_up[panel] is not None:
                ax.set_xlim(*close_up[panel])
            system_title(ax, rows[cols.SYSTEM].iloc[0], rf", $F_{{th}}$ < {P1_SMALL_THRESHOLD:g} (close-up)")
            ax.legend(fontsize="x-small", frameon=False)
    _first_legend(axes)
    return fig


def prepare_p1_fig07_betti1(measures: Mapping[str, xr.Dataset], *,
                            thresholds: Sequence[float] = DEFAULT_THRESHOLDS,
                            force_unit: str = DEFAULT_P1_FORCE_UNIT) -> FigureData:
    """F7: B1/N versus ρ per F_th for every system, and B2/N for the 3D ones."""
    systems = _systems(measures, force_unit)
    panels = [(s, 1) for s in systems] + [(s, 2) for s in systems if s.dimension == 3]
    return FigureData(concat(_threshold_rows(system, per_particle(system.data, "betti").sel(homology_dim=k),
                                             thresholds, f"B{k}/N", panel)
                             for panel, (system, k) in enumerate(panels)))


def prepare_p1_fig08_shape_heatmap(measures: Mapping[str, xr.Dataset], *,
                                   force_unit: str = DEFAULT_P1_FORCE_UNIT) -> FigureData:
    """F8: shape parameter S_p over (ρ, F_th) with P1's averaging rule (§5.2)."""
    return FigureData(concat(_heat_rows(system, shape_parameter_average(system.data["shape_parameter"])[0], "S_p", panel)
                             for panel, system in enumerate(_systems(measures, force_unit))))


def prepare_p1_fig09_shape_sections(measures: Mapping[str, xr.Dataset], *,
                                    thresholds: Sequence[float] = DEFAULT_THRESHOLDS,
                                    force_unit: str = DEFAULT_P1_FORCE_UNIT) -> FigureData:
    """F9: S_p versus ρ for chosen F_th (P1's averaging rule; band: spread over the nonzero realizations)."""
    return FigureData(concat(_threshold_rows(system, shape_parameter_average(system.data["shape_parameter"]),
                                             thresholds, "S_p", panel)
                             for panel, system in enumerate(_systems(measures, force_unit))))


def prepare_p1_fig10_persistence_diagram(measures: Mapping[str, xr.Dataset], diagrams: Mapping[str, xr.Dataset], *,
                                         example_system: str | None = None, rho: float | None = None,
                                         realization: int | None = None) -> FigureData:
    """F10: the points of one PD0 (total force). Defaults: the 2D Hertzian system (as P1), the first
    realization, the packing fraction nearest to its ρ_J. Never-dying points have death −inf (drawn at 0)."""
    from forcenet.datasets.schema import FORCE_KINDS

    names = system_order(diagrams)
    system = example_system or next((n for n in names if n == "2d_hertz"), names[0])
    points = diagrams[system]
    realization = int(np.min(points["point_realization"].values)) if realization is None else realization
    if rho is None:
        grid = np.unique(points["point_rho"].values)
        rho_j = jamming_point(measures[system]) if system in measures else float("nan")
        rho = float(grid[np.argmin(np.abs(grid - rho_j))]) if np.isfinite(rho_j) else float(grid[len(grid) // 2])
    mask = ((points["diagram_force_kind"].values == FORCE_KINDS.index("total"))
            & (points["diagram_homology_dim"].values == 0)
            & (points["point_realization"].values == realization)
            & np.isclose(points["point_rho"].values, rho))
    death = points["death"].values[mask]
    chosen = {cols.SYSTEM: system, "realization": realization, cols.RHO: rho}
    return FigureData(pd.DataFrame({cols.PANEL: 0, **chosen, "homology_dim": 0, cols.BIRTH: points["birth"].values[mask],
                                    cols.DEATH: death, "essential": ~np.isfinite(death)}), chosen)


def draw_p1_fig10_persistence_diagram(data: FigureData) -> Figure:
    """The PD0 with P1's bins shaded: rough (lifespan ≤ 0.1), weak (0.1 ≤ birth < 1), medium (1 ≤ birth < 2.5),
    strong (birth ≥ 2.5)."""
    rows = data.table
    system, rho, realization = (data.layout[k] for k in (cols.SYSTEM, cols.RHO, "realization"))
    birth, death = rows[cols.BIRTH].to_numpy(float), rows[cols.DEATH].to_numpy(float)
    essential = rows["essential"].to_numpy(bool)
    fig, (ax,) = panel_figure(1, size=(4.8, 4.4))
    top = max(float(np.nanmax(birth)) if birth.size else 0.0, STRONG_BIRTH) * 1.05

    def below_rough(lo, hi):  # births in [lo, hi), lifespan > ROUGH_LIFESPAN, death ≥ 0
        return [(lo, 0), (hi, 0), (hi, hi - ROUGH_LIFESPAN), (lo, max(lo - ROUGH_LIFESPAN, 0))]

    regions = {
        "rough": [(0, 0), (ROUGH_LIFESPAN, 0), (top, top - ROUGH_LIFESPAN), (top, top)],
        "weak": below_rough(WEAK_BIRTH, MEDIUM_BIRTH),
        "medium": below_rough(MEDIUM_BIRTH, STRONG_BIRTH),
        "strong": below_rough(STRONG_BIRTH, top),
    }
    for color, (label, corners) in zip(sns.color_palette("pastel", 4), regions.items()):
        ax.add_patch(plt.Polygon(corners, closed=True, facecolor=color, edgecolor="none", alpha=0.6,
                                 label=label, gid=f"bin_{label}"))
    ax.scatter(birth[~essential], death[~essential], s=10, color=system_color(system), label="finite",
               gid="points", zorder=3)
    ax.scatter(birth[essential], np.zeros(essential.sum()), s=30, marker="v", color="k", gid="essential",
               label="never dies (at 0)", zorder=3)
    ax.plot([0, top], [0, top], color="0.3", linewidth=0.8)
    ax.set_xlim(0, top)
    ax.set_ylim(0, top)
    ax.set_aspect("equal")
    ax.set_xlabel(LABELS["birth"])
    ax.set_ylabel(LABELS["death"])
    system_title(ax, system, rf", $\rho$ = {rho:.3f}, realization {realization}")
    ax.legend(fontsize="x-small", frameon=False, loc="upper left")
    return fig


def _never_dying_at_minus_one(measures: Mapping[str, xr.Dataset],
                              diagrams: Mapping[str, xr.Dataset]) -> dict[str, xr.Dataset]:
    """The measures with each system's never-dying classes at death −1 (`never_dying_at_minus_one`: the papers'
    convention, docs/decisions.md), as the P1 table judges them."""
    return {name: never_dying_at_minus_one(ds, diagrams[name]) if name in diagrams else ds
            for name, ds in measures.items()}


def prepare_p1_fig11_persistence_bins(measures: Mapping[str, xr.Dataset], diagrams: Mapping[str, xr.Dataset], *,
                                      force_unit: str = DEFAULT_P1_FORCE_UNIT) -> FigureData:
    """F11: PD0 points per bin N0/N versus ρ; rows rough/weak/medium/strong, columns 2D and 3D (P1 Fig. 11),
    one curve per system; a never-dying class counts in the bin of its birth (death −1, `diagrams`).
    layout["columns"]: the number of panel columns (one per dimension)."""
    systems = _systems(_never_dying_at_minus_one(measures, diagrams), force_unit)
    dimensions = sorted({s.dimension for s in systems})
    blocks = []
    for row, bin_name in enumerate(PD_BINS):
        for col, dimension in enumerate(dimensions):
            for system in (s for s in systems if s.dimension == dimension):
                mean, spread = mean_and_spread(
                    per_particle(system.data, "persistence_bin_count").sel(persistence_bin=bin_name))
                blocks.append(_spread_rows(cols.RHO, rho_values(system.data), mean, spread, **{
                                             cols.PANEL: row * len(dimensions) + col, cols.SYSTEM: system.name,
                                             "persistence_bin": bin_name, "dimension": dimension,
                                             cols.QUANTITY: "N0/N", **_marks(system)}))
    return FigureData(concat(blocks), {"columns": len(dimensions)})


def draw_p1_fig11_persistence_bins(data: FigureData) -> Figure:
    ncols = data.layout["columns"]
    fig, axes = panel_figure(len(PD_BINS) * ncols, ncols=ncols, size=(4.4, 2.8))
    for ax, panel in zip(axes, sorted(data.table[cols.PANEL].unique())):
        rows = data.panel(panel)
        for name, curve in rows.groupby(cols.SYSTEM, sort=False):
            _draw_rows(ax, curve, cols.RHO, system_color(name), label=system_label(name))
            _mark_jamming(ax, float(curve[cols.RHO_J].iloc[0]), name)
            _mark_rho_max(ax, curve, name, label=False)
        ax.set_xlabel(state_axis_label(name))
        ax.set_ylabel(LABEL_N0)
        ax.set_title(f"{rows['persistence_bin'].iloc[0]}, {rows['dimension'].iloc[0]}D")
        ax.legend(fontsize="x-small", frameon=False)
    return fig


def prepare_p1_fig12_total_persistence(measures: Mapping[str, xr.Dataset], diagrams: Mapping[str, xr.Dataset], *,
                                       force_unit: str = DEFAULT_P1_FORCE_UNIT) -> FigureData:
    """F12: total persistence TP0/N and TP1/N of the total-force network versus ρ, each never-dying class of
    `diagrams` adding birth + 1 (death −1)."""
    blocks = []
    for panel, system in enumerate(_systems(_never_dying_at_minus_one(measures, diagrams), force_unit)):
        tp = per_particle(system.data, "total_persistence")
        for k in (0, 1):
            mean, spread = mean_and_spread(tp.sel(homology_dim=k))
            blocks.append(_spread_rows(cols.RHO, rho_values(system.data), mean, spread, **{
                                         cols.PANEL: panel, cols.SYSTEM: system.name, cols.QUANTITY: "TP_k/N [<F>]",
                                         HOMOLOGY_K: k, **_marks(system)}))
    return FigureData(concat(blocks))


def draw_p1_fig12_total_persistence(data: FigureData) -> Figure:
    """TP0/N solid, TP1/N dashed, in the system's colour."""
    fig, panels = _panels(data)
    for ax, rows in panels:
        name = rows[cols.SYSTEM].iloc[0]
        for k, style in ((0, "-"), (1, "--")):
            _draw_rows(ax, rows[rows[HOMOLOGY_K] == k], cols.RHO, system_color(name), label=rf"$TP_{k}/N$",
                       linestyle=style)
        _mark_jamming(ax, float(rows[cols.RHO_J].iloc[0]), name)
        _mark_rho_max(ax, rows, name)
        ax.set_xlabel(state_axis_label(name))
        ax.set_ylabel(LABEL_TP)
        system_title(ax, name)
        ax.legend(fontsize="x-small", frameon=False)
    return fig


def prepare_p1_z_jamming(measures: Mapping[str, xr.Dataset], *, force_unit: str = DEFAULT_P1_FORCE_UNIT) -> FigureData:
    """Z(ρ) of every system over its whole ρ grid, with ρ_J (inflection, P1 §4), Z(ρ_J) and ρ_max on every row."""
    blocks = []
    rho_max = {system.name: system.rho_max for system in _systems(measures, force_unit)}
    for name in system_order(measures):
        ds = measures[name]
        mean, spread = mean_and_spread(ds["Z"])
        rho = rho_values(ds)
        rho_j = float("nan") if is_sequence(name) else jamming_point(ds)
        z_j = float(np.interp(rho_j, rho, mean.values)) if np.isfinite(rho_j) else float("nan")
        blocks.append(_spread_rows(cols.RHO, rho, mean, spread, **{
            cols.PANEL: 0, cols.SYSTEM: name, "dimension": system_dimension(ds, name), cols.QUANTITY: "Z",
            cols.RHO_J: rho_j, "Z(rho_J)": z_j, RHO_MAX_COLUMN: rho_max[name]}))
    return FigureData(concat(blocks))


def draw_p1_z_jamming(data: FigureData) -> Figure:
    """The curves, ρ_J as an open circle on each, and Z = d + 1 dotted."""
    fig, (ax,) = panel_figure(1, size=(5.2, 3.8))
    for name, rows in data.table.groupby(cols.SYSTEM, sort=False):
        color = system_color(name)
        _draw_rows(ax, rows, cols.RHO, color, label=system_label(name))
        rho_j = float(rows[cols.RHO_J].iloc[0])
        if np.isfinite(rho_j):
            ax.plot([rho_j], [float(rows["Z(rho_J)"].iloc[0])], marker="o", markersize=7, markerfacecolor="white",
                    color=color, gid=RHO_J_GID, label=rf"$\rho_J$ = {rho_j:.3f}")
        _mark_rho_max(ax, rows, name, label=False)
    for dimension in sorted(data.table["dimension"].unique()):
        ax.axhline(dimension + 1, color="0.5", linestyle=":", linewidth=0.8, gid="isostatic")
        ax.annotate(f"Z = d + 1 = {dimension + 1} ({dimension}D)", (0.01, dimension + 1),
                    xycoords=("axes fraction", "data"), va="bottom", fontsize="x-small", color="0.4")
    ax.set_xlabel(state_axis_label(name))
    ax.set_ylabel(LABELS["Z"])
    ax.legend(fontsize="x-small", frameon=False)
    return fig
