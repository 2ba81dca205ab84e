"""P2 figures (evolution of force networks): per figure, a preparation (inputs → `FigureData`, whose table of
plotted values is written beside the figure as CSV) and a drawing (`FigureData` → matplotlib Figure); the
public function of each figure (`P2_FIGURES`) does both.

Inputs are forcenet datasets: snapshots (Fig. 1), one snapshot's analysis (Fig. 3) and the stacked
``results/{system}/distances.nc`` (Figs 6–10, `forcenet.report.p2_distances.stack_distances`). The reductions
(realization means, ratios, ρ_J) are the ones `forcenet.report.p2` uses for the validation, so figures and verdicts
agree.

Curves are means over realizations with the band mean ± the standard deviation over the realizations
(`forcenet.report.realizations`; the part below 0 is not drawn on the log axes); distances and ratios
are drawn on log axes (P2 discusses them in orders of magnitude, §IV A). Z(ρ) is on a twin axis, with ρ_J
(mean Z reaching d + 1) marked.
"""
from __future__ import annotations

from functools import partial
from typing import Callable, Sequence

import matplotlib.pyplot as plt
import numpy as np
import pandas as pd
import xarray as xr
from matplotlib.collections import LineCollection
from matplotlib.figure import Figure
from matplotlib.patches import Rectangle

from forcenet.plotting import figure_data as cols
from forcenet.plotting.figure_data import FigureData, concat, curve_rows
from forcenet.plotting.style import FALLBACK_COLORS, LABELS, apply_style, system_color, system_label
from forcenet.report import p2 as report
from forcenet.report.p2_distances import contact_forces, diagram_points, edge_differences
from forcenet.report.realizations import realization_mean, realization_spread

METRIC_COLORS = {metric: FALLBACK_COLORS[i] for i, metric in enumerate(report.METRICS)}
METRIC_MARKERS = {"bottleneck": "o", "wasserstein_1": "s", "wasserstein_2": "^"}
METRIC_TEX = {"bottleneck": r"$d_B$", "wasserstein_1": r"$d_{W1}$", "wasserstein_2": r"$d_{W2}$"}
KIND_WORDS = {"normal": "normal forces", "tangential": "tangential forces"}
DISTANCE_LABEL = r"distance $d$ between consecutive PDs $[\langle F\rangle]$"
RATIO_LABEL = r"ratio of distances $d_B/d_{Wq}$"


#: plain-text symbol [unit] of each distance metric and ratio (the CSV's `quantity` column)
METRIC_QUANTITY = {"bottleneck": "d_B [<F>]", "wasserstein_1": "d_W1 [<F>]", "wasserstein_2": "d_W2 [<F>]"}
RATIO_QUANTITY = {"wasserstein_1": "d_B/d_W1", "wasserstein_2": "d_B/d_W2"}
#: P2 Fig. 1 edge columns: end points [d_ave]
EDGE_ENDS = ("x_i [d_ave]", "y_i [d_ave]", "x_j [d_ave]", "y_j [d_ave]")


# --- Fig. 1: three nearby snapshots and |ΔF| between them ------------------------------------------------------
def prepare_p2_fig01(snapshots: Sequence[xr.Dataset], *, kind: str = "normal", system: str = report.FRICTIONAL,
                     remove_rattlers: bool | str = False) -> FigureData:
    """Edges of panels (a–c): the force network of three nearby snapshots, F/⟨F⟩ of that snapshot; (d–e):
    |F_b − F_a| and |F_c − F_a| on the contacts of either snapshot (a contact missing in one has F = 0 there),
    at snapshot a's particle positions. Panels 0–4 are a–e."""
    if len(snapshots) != 3:
        raise ValueError(f"Fig. 1 needs three snapshots a, b, c; got {len(snapshots)}")
    # each network is built once: panels (a–c) draw it, (d–e) take differences of the same edge values
    networks = [contact_forces(s, kind, remove_rattlers=remove_rattlers) for s in snapshots]
    n_particles = max(int(s.sizes["particle"]) for s in snapshots)
    diffs = [edge_differences(networks[0], networks[k], n_particles) for k in (1, 2)]
    blocks = []
    for panel, (snap, edges) in enumerate(zip([*snapshots, snapshots[0], snapshots[0]], [*networks, *diffs])):
        position = snap["position"].values
        quantity = "F/<F>" if panel < 3 else "|F_%s - F_a|/<F>" % "bc"[panel - 3]
        blocks.append(pd.DataFrame({cols.PANEL: panel, cols.SYSTEM: system, "force_kind": kind,
                                    cols.RHO: float(snap["rho"]), cols.QUANTITY: quantity, "i": edges.i, "j": edges.j,
                                    EDGE_ENDS[0]: position[edges.i, 0], EDGE_ENDS[1]: position[edges.i, 1],
                                    EDGE_ENDS[2]: position[edges.j, 0], EDGE_ENDS[3]: position[edges.j, 1],
                                    cols.VALUE: edges.force}))
    return FigureData(concat(blocks), {
        "box": [(s["box_lo"].values[:2], s["box_hi"].values[:2]) for s in snapshots],
        "states": [(float(s["rho"]), float(s["Z"])) for s in snapshots], "kind": kind, "system": system,
        "realization": snapshots[0].attrs.get("realization", "?")})


def draw_p2_fig01(data: FigureData) -> Figure:
    apply_style()
    kind, system = data.layout["kind"], data.layout["system"]
    fig, axes = plt.subplots(2, 3, figsize=(13, 8.6), constrained_layout=True)
    networks = [data.panel(p) for p in range(5)]
    vmax = max(float(n[cols.VALUE].max()) if len(n) else 1.0 for n in networks[:3])
    boxes = data.layout["box"]
    for ax, rows, box, (rho, _), letter in zip(axes[0], networks[:3], boxes, data.layout["states"], "abc"):
        lines = _draw_edges(ax, rows, "viridis", 0.0, vmax)
        _frame(ax, box, f"({letter}) ρ = {rho:.4f}")
    fig.colorbar(lines, ax=axes[0].tolist(), shrink=0.8, label=rf"{kind} force $F/\langle F\rangle$")
    dmax = max([float(n[cols.VALUE].max()) for n in networks[3:] if len(n)] + [1e-12])
    for ax, rows, letter, pair in zip(axes[1], networks[3:], "de", ("b", "c")):
        lines = _draw_edges(ax, rows, "inferno_r", 0.0, dmax)
        _frame(ax, boxes[0], rf"({letter}) $|F_{pair} - F_a|$")
    side = axes[1, 2]
    side.axis("off")
    fig.colorbar(lines, cax=side.inset_axes([0.0, 0.1, 0.06, 0.8]),
                 label=r"$|\Delta F|/\langle F\rangle$ (each snapshot normalised by its own mean)")
    side.text(0.45, 0.5, f"{system_label(system)}, realization {data.layout.get('realization', '?')}\n"
              f"{KIND_WORDS.get(kind, kind)}\n"
              + "\n".join(f"{letter}: ρ = {rho:.4f}, Z = {z:.2f}"
                          for letter, (rho, z) in zip("abc", data.layout["states"])),
              transform=side.transAxes, va="center")
    fig.suptitle("Force networks of three nearby states and their differences (P2 Fig. 1)")
    return fig


def p2_fig01_snapshots_differences(snapshots: Sequence[xr.Dataset], *, kind: str = "normal",
                                   system: str = report.FRICTIONAL, remove_rattlers: bool | str = False) -> Figure:
    """P2 Fig. 1: (a–c) the force network of three nearby snapshots, colour = F/⟨F⟩ of that snapshot;
    (d) |F_b − F_a| and (e) |F_c − F_a| on the contacts of either snapshot (see `prepare_p2_fig01`)."""
    return draw_p2_fig01(prepare_p2_fig01(snapshots, kind=kind, system=system, remove_rattlers=remove_rattlers))


def _draw_edges(ax, rows: pd.DataFrame, cmap, vmin, vmax):
    values = rows[cols.VALUE].to_numpy(float)
    ends = rows[list(EDGE_ENDS)].to_numpy(float)
    segments = ends.reshape(-1, 2, 2)
    order = np.argsort(values)  # strongest on top
    lines = LineCollection(segments[order], cmap=cmap, linewidths=1.4)
    lines.set_array(values[order])
    lines.set_clim(vmin, vmax if vmax > vmin else vmin + 1.0)
    ax.add_collection(lines)
    return lines


def _frame(ax, box, title: str) -> None:
    lo, hi = box
    ax.add_patch(Rectangle(lo, *(hi - lo), fill=False, color="0.4", lw=0.8))
    pad = 0.03 * float(np.max(hi - lo))
    ax.set_xlim(lo[0] - pad, hi[0] + pad)
    ax.set_ylim(lo[1] - pad, hi[1] + pad)
    ax.set_aspect("equal")
    ax.set_xlabel(r"$x$ $[d_{ave}]$")
    ax.set_ylabel(r"$y$ $[d_{ave}]$")
    ax.set_title(title)


# --- Fig. 3: PD0 and PD1 of one snapshot --------------------------------------------------------------------------
def prepare_p2_fig03(analysis: xr.Dataset, *, kind: str = "normal", system: str = report.FRICTIONAL,
                     essential_death: float = -1.0) -> FigureData:
    """Points of PD0 (panel 0) and PD1 (panel 1) of one snapshot; never-dying classes (death −inf) are drawn at
    death = `essential_death` (P2's −1), given in the column "death drawn [<F>]"."""
    blocks = []
    for h in report.P2_HOMOLOGY_DIMS:
        birth, death, essential = diagram_points(analysis, kind, h)
        blocks.append(pd.DataFrame({cols.PANEL: h, cols.SYSTEM: system, "force_kind": kind,
                                    cols.RHO: float(analysis["rho"]), "homology_dim": h, cols.BIRTH: birth,
                                    cols.DEATH: np.where(essential, -np.inf, death), "essential": essential,
                                    "death drawn [<F>]": np.where(essential, essential_death, death)}))
    return FigureData(concat(blocks), {"kind": kind, "system": system, "rho": float(analysis["rho"]),
                                       "essential_death": essential_death})


def draw_p2_fig03(data: FigureData) -> Figure:
    apply_style()
    kind, system, essential_death = (data.layout[k] for k in ("kind", "system", "essential_death"))
    fig, axes = plt.subplots(1, 2, figsize=(10, 4.6), constrained_layout=True)
    color = system_color(system)
    for ax, h in zip(axes, report.P2_HOMOLOGY_DIMS):
        rows = data.panel(h)
        birth, drawn = rows[cols.BIRTH].to_numpy(float), rows["death drawn [<F>]"].to_numpy(float)
        essential = rows["essential"].to_numpy(bool)
        ax.scatter(birth[~essential], drawn[~essential], s=10, color=color, alpha=0.6, lw=0, label="finite classes")
        ax.scatter(birth[essential], drawn[essential], s=40, marker="x", color="k",
                   label=f"never dies (death := {essential_death:g})")
        top = 1.05 * max(1.0, float(np.max(birth)) if birth.size else 1.0)
        ax.plot([essential_death, top], [essential_death, top], color="0.5", lw=0.8, ls="--", label="diagonal")
        ax.set_xlim(min([0.0] + ([float(np.min(birth))] if birth.size else [])) - 0.05 * top, top)
        ax.set_ylim(essential_death - 0.05 * top, top)
        ax.set_xlabel(LABELS["birth"])
        ax.set_ylabel(LABELS["death"])
        ax.set_title(rf"({'ab'[h]}) PD$_{h}$: {birth.size} points")
        ax.legend(loc="upper left", fontsize="small")
    fig.suptitle(f"Persistence diagrams, {system_label(system)}, {KIND_WORDS.get(kind, kind)}, "
                 f"ρ = {data.layout['rho']:.4f} (P2 Fig. 3)")
    return fig


def p2_fig03_diagrams(analysis: xr.Dataset, *, kind: str = "normal", system: str = report.FRICTIONAL,
                      essential_death: float = -1.0) -> Figure:
    """P2 Fig. 3: PD0 and PD1 of one snapshot (birth ≥ death, super-level filtration); never-dying classes are
    drawn at death = `essential_death` (P2's −1) with their own marker."""
    return draw_p2_fig03(prepare_p2_fig03(analysis, kind=kind, system=system, essential_death=essential_death))


# --- Figs 6, 8, 9: distances vs ρ with Z(ρ) ------------------------------------------------------------------------
def prepare_distances(distances: xr.Dataset, *, kind: str, system: str, source: str) -> FigureData:
    """d_B, d_W1, d_W2 between consecutive PDs vs ρ (realization mean ± standard deviation), panel h = β_h, and the
    realization-mean Z(ρ) (quantity "Z", no band) drawn on a twin axis of each panel; ρ_J on every row."""
    dimension, rho_j = _jamming(distances)
    blocks = []
    for h in report.P2_HOMOLOGY_DIMS:
        common = {cols.PANEL: h, cols.SYSTEM: system, "force_kind": kind, "homology_dim": h}
        for metric in report.METRICS:
            da = distances["distance"].sel(force_kind=kind, homology_dim=h, metric=metric)
            blocks.append(_band_rows(realization_mean(da), da, common, METRIC_QUANTITY[metric], rho_j))
        z = realization_mean(distances["Z"])
        blocks.append(curve_rows(cols.RHO, z["rho"].values, z.values, np.nan, np.nan, **common,
                                 **{cols.QUANTITY: "Z", cols.RHO_J: rho_j}))
    return FigureData(concat(blocks), _layout(distances, kind, system, source, dimension, rho_j))


def _band_rows(mean: xr.DataArray, band_source: xr.DataArray, common: dict, quantity: str, rho_j: float):
    """Rows of the curve `mean` (vs ρ) with the band mean ± the standard deviation of `band_source` over its
    realizations (`forcenet.report.realizations`)."""
    spread = realization_spread(band_source)
    return curve_rows(cols.RHO, mean["rho"].values, mean.values, (mean - spread).values, (mean + spread).values,
                      **common,
                      **{cols.QUANTITY: quantity, cols.RHO_J: rho_j})


def _layout(distances: xr.Dataset, kind: str, system: str, source: str, dimension: int, rho_j: float) -> dict:
    return {"kind": kind, "system": system, "source": source, "dimension": dimension, "rho_J": rho_j,
            "realizations": _realizations_text(distances)}


def draw_distances(data: FigureData) -> Figure:
    apply_style()
    layout = data.layout
    fig, axes = plt.subplots(1, 2, figsize=(11.5, 4.6), constrained_layout=True)
    for ax, h in zip(axes, report.P2_HOMOLOGY_DIMS):
        rows = data.panel(h)
        for metric in report.METRICS:
            _draw_band(ax, rows[rows[cols.QUANTITY] == METRIC_QUANTITY[metric]], METRIC_COLORS[metric],
                       METRIC_MARKERS[metric], METRIC_TEX[metric])
        _log_panel_vs_rho(ax, h, DISTANCE_LABEL, layout["rho_J"], layout["dimension"])
        _mark_quoted_levels(ax, layout["source"], h, rows[cols.RHO].values, layout["rho_J"])
        twin = _z_twin(ax, rows[rows[cols.QUANTITY] == "Z"], layout["system"], layout["dimension"])
    _figure_legend(fig, [axes[0], twin])
    fig.suptitle(f"{system_label(layout['system'])}, {KIND_WORDS.get(layout['kind'], layout['kind'])}: distances "
                 f"between consecutive states ({layout['realizations']}; {layout['source']})")
    return fig


def p2_fig06_distances_normal_mu05(distances: xr.Dataset, *, system: str = report.FRICTIONAL) -> Figure:
    """P2 Fig. 6: d_B, d_W1, d_W2 between consecutive PDs vs ρ, β0 and β1, normal forces, μ = 0.5; Z(ρ)."""
    return _from_parts("p2_fig06_distances_normal_mu05", distances, system)


def p2_fig08_distances_tangential_mu05(distances: xr.Dataset, *, system: str = report.FRICTIONAL) -> Figure:
    """P2 Fig. 8: as Fig. 6 for the tangential forces (each network normalised by its mean tangential force)."""
    return _from_parts("p2_fig08_distances_tangential_mu05", distances, system)


def p2_fig09_distances_normal_mu0(distances: xr.Dataset, *, system: str = report.FRICTIONLESS) -> Figure:
    """P2 Fig. 9: as Fig. 6 for the frictionless system (μ = 0)."""
    return _from_parts("p2_fig09_distances_normal_mu0", distances, system)


def _mark_quoted_levels(ax, source: str, h: int, rho: np.ndarray, rho_j: float) -> None:
    """P2's quoted levels for this panel (`report.quoted_levels`; `source` is "P2 Fig. N") as dashed segments over
    the ρ range P2 quotes them for."""
    rho = np.asarray(rho, dtype=float)
    if rho.size == 0:
        return
    for level in report.quoted_levels(int(source.split()[-1]), h):
        high = rho_j if level.rho_below == "rho_J" else float(level.rho_below)
        if np.isfinite(high) and high > float(np.min(rho)):
            ax.hlines(level.value, float(np.min(rho)), min(high, float(np.max(rho))),
                      colors=METRIC_COLORS[level.metric], linestyles=(0, (5, 3)), lw=1.6, alpha=0.8, label=level.text)


def _jamming(distances: xr.Dataset) -> tuple[int, float]:
    """(d, ρ_J) of a distances dataset: its spatial dimension and where the mean Z(ρ) reaches d + 1."""
    dimension = int(distances.attrs.get("dimension", 2))
    return dimension, report.jamming_density(distances, dimension)


def _draw_band(ax, rows: pd.DataFrame, color, marker: str, label: str) -> None:
    """A curve (vs ρ) with its band, from table rows."""
    rho = rows[cols.RHO].to_numpy(float)
    ax.plot(rho, rows[cols.MEAN].to_numpy(float), color=color, marker=marker, ms=3.5, lw=1.3, label=label)
    ax.fill_between(rho, rows[cols.LOW].to_numpy(float), rows[cols.HIGH].to_numpy(float), color=color, alpha=0.2, lw=0)


def _log_panel_vs_rho(ax, h: int, ylabel: str, rho_j: float, dimension: int) -> None:
    """Panel set-up shared by Figs 6–10: ρ_J marked (if Z reaches d + 1), log y axis, labels, β_h title."""
    if np.isfinite(rho_j):
        ax.axvline(rho_j, color="0.3", ls=":", lw=1.0, label=rf"$\rho_J$ = {rho_j:.3f} ($Z = {dimension + 1}$)")
    ax.set_yscale("log", nonpositive="mask")
    ax.set_xlabel(LABELS["rho"])
    ax.set_ylabel(ylabel)
    ax.set_title(rf"({'ab'[h]}) $\beta_{h}$")


def _z_twin(ax, rows: pd.DataFrame, system: str, dimension: int):
    twin = ax.twinx()
    twin.plot(rows[cols.RHO].to_numpy(float), rows[cols.MEAN].to_numpy(float), color=system_color(system), ls="--",
              lw=1.5, label=r"$Z$")
    twin.axhline(dimension + 1, color="0.6", ls=":", lw=0.8)
    twin.set_ylabel(LABELS["Z"])
    return twin


def _figure_legend(fig, axes) -> None:
    """One legend under the panels (the panels share their curves), so no curve is hidden behind it."""
    handles, labels = [], []
    for ax in axes:
        for handle, label in zip(*ax.get_legend_handles_labels()):
            if label not in labels:
                handles.append(handle)
                labels.append(label)
    fig.legend(handles, labels, loc="outside lower center", ncol=min(len(labels), 4), frameon=False)


# --- Figs 7, 10: ratios d_B/d_W1 and d_B/d_W2 ---------------------------------------------------------------------
def prepare_ratios(distances: xr.Dataset, *, kind: str, system: str, source: str) -> FigureData:
    """d_B/d_W1 and d_B/d_W2 vs ρ, panel h = β_h: the ratio of the realization-mean distances, ± the standard
    deviation of the per-realization ratios."""
    dimension, rho_j = _jamming(distances)
    blocks = []
    for h in report.P2_HOMOLOGY_DIMS:
        panel = {"force_kind": kind, "homology_dim": h}
        common = {cols.PANEL: h, cols.SYSTEM: system, **panel}
        for den in ("wasserstein_1", "wasserstein_2"):
            blocks.append(_band_rows(report.mean_distance_ratio(distances, den).sel(panel),
                                     report.distance_ratio(distances, den).sel(panel), common, RATIO_QUANTITY[den],
                                     rho_j))
    return FigureData(concat(blocks), _layout(distances, kind, system, source, dimension, rho_j))


def draw_ratios(data: FigureData) -> Figure:
    apply_style()
    layout = data.layout
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.4), constrained_layout=True)
    for ax, h in zip(axes, report.P2_HOMOLOGY_DIMS):
        rows = data.panel(h)
        for den in ("wasserstein_1", "wasserstein_2"):
            _draw_band(ax, rows[rows[cols.QUANTITY] == RATIO_QUANTITY[den]], METRIC_COLORS[den], METRIC_MARKERS[den],
                       rf"$d_B/${METRIC_TEX[den]}")
        _log_panel_vs_rho(ax, h, RATIO_LABEL, layout["rho_J"], layout["dimension"])
        _mark_quoted_levels(ax, layout["source"], h, rows[cols.RHO].values, layout["rho_J"])
    _figure_legend(fig, [axes[0]])
    fig.suptitle(f"{system_label(layout['system'])}, {KIND_WORDS.get(layout['kind'], layout['kind'])}: ratios of the "
                 f"rates of change ({layout['realizations']}; {layout['source']})")
    return fig


def p2_fig07_ratios_mu05(distances: xr.Dataset, *, kind: str = "normal", system: str = report.FRICTIONAL) -> Figure:
    """P2 Fig. 7: d_B/d_W1 and d_B/d_W2 vs ρ, β0 and β1, μ = 0.5 (normal forces)."""
    return draw_ratios(prepare_ratios(distances, kind=kind, system=system, source=_source("p2_fig07_ratios_mu05")))


def p2_fig10_ratios_mu0(distances: xr.Dataset, *, kind: str = "normal", system: str = report.FRICTIONLESS) -> Figure:
    """P2 Fig. 10: as Fig. 7 for the frictionless system (μ = 0)."""
    return draw_ratios(prepare_ratios(distances, kind=kind, system=system, source=_source("p2_fig10_ratios_mu0")))


def _realizations_text(ds: xr.Dataset) -> str:
    n = int(ds.sizes.get("realization", 1))
    return f"mean of {n} realization{'s' if n != 1 else ''}" + (", band ± 1 standard deviation" if n > 1 else "")


P2_FIGURES: dict[str, Callable[..., Figure]] = {
    "p2_fig01_snapshots_differences": p2_fig01_snapshots_differences,
    "p2_fig03_diagrams": p2_fig03_diagrams,
    "p2_fig06_distances_normal_mu05": p2_fig06_distances_normal_mu05,
    "p2_fig07_ratios_mu05": p2_fig07_ratios_mu05,
    "p2_fig08_distances_tangential_mu05": p2_fig08_distances_tangential_mu05,
    "p2_fig09_distances_normal_mu0": p2_fig09_distances_normal_mu0,
    "p2_fig10_ratios_mu0": p2_fig10_ratios_mu0,
}
"""Figure name (the output file stem, ``results/figures/{name}.pdf``) → function drawing it from its input."""

#: figure name → (preparation with its fixed options, drawing); the functions of `P2_FIGURES` are these composed
P2_FIGURE_PARTS: dict[str, tuple[Callable[..., FigureData], Callable[[FigureData], Figure]]] = {
    "p2_fig01_snapshots_differences": (prepare_p2_fig01, draw_p2_fig01),
    "p2_fig03_diagrams": (prepare_p2_fig03, draw_p2_fig03),
    "p2_fig06_distances_normal_mu05": (partial(prepare_distances, kind="normal", source="P2 Fig. 6"), draw_distances),
    "p2_fig07_ratios_mu05": (partial(prepare_ratios, kind="normal", source="P2 Fig. 7"), draw_ratios),
    "p2_fig08_distances_tangential_mu05": (partial(prepare_distances, kind="tangential", source="P2 Fig. 8"),
                                           draw_distances),
    "p2_fig09_distances_normal_mu0": (partial(prepare_distances, kind="normal", source="P2 Fig. 9"), draw_distances),
    "p2_fig10_ratios_mu0": (partial(prepare_ratios, kind="normal", source="P2 Fig. 10"), draw_ratios),
}


def _source(name: str) -> str:
    return P2_FIGURE_PARTS[name][0].keywords["source"]


def _from_parts(name: str, data, system: str) -> Figure:
    return draw_p2_figure(name, p2_figure_data(name, data, system=system))


def p2_figure_data(name: str, data, *, system: str, **options) -> FigureData:
    """The plotted values of the P2 figure `name` from its input (three snapshots, one analysis or a distances
    dataset, as `P2_FIGURES[name]` takes); `options` go to its preparation (Fig. 1: ``remove_rattlers``)."""
    return P2_FIGURE_PARTS[name][0](data, system=system, **options)


def draw_p2_figure(name: str, data: FigureData) -> Figure:
    return P2_FIGURE_PARTS[name][1](data)
