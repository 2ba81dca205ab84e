"""P2 figures (evolution of force networks) that read diagrams and distances: per figure, a preparation (inputs →
`FigureData`, whose table of plotted values is written beside the figure as CSV) and a drawing (`FigureData` →
matplotlib Figure). Fig. 1, the networks, is in `forcenet.plotting.networks`; `forcenet.plotting.registry` lists
every figure with its inputs, options and caption (Figs 6, 8, 9 share `prepare_distances`/`draw_distances`, Figs 7,
10 `prepare_ratios`/`draw_ratios`, with the force kind as the entry's option and P2's figure number as `source`).

Inputs are forcenet datasets: one snapshot's analysis (Fig. 3) and the stacked ``results/{system}/distances.nc``
(Figs 6–10, `forcenet.report.p2_distances.stack_distances`). The reductions (realization means, ratios, ρ_J) are
the ones `forcenet.report.p2` uses for the validation, so figures and verdicts agree.

Curves are means over realizations with the band mean ± the standard deviation over the realizations
(`forcenet.report.realizations`; the part below 0 is not drawn on the log axes); distances and ratios are drawn on log axes (P2 discusses them in orders of magnitude, §IV A). Z(ρ) is on a twin axis, with ρ_J
(mean Z reaching d + 1) marked.
"""
from __future__ import annotations

import matplotlib.pyplot as plt
import numpy as np
import pandas as pd
import xarray as xr
from matplotlib.figure import Figure

from forcenet.plotting import figure_data as cols
from forcenet.plotting.figure_data import FigureData, concat, curve_rows
from forcenet.plotting.style import (FALLBACK_COLORS, FORCE_KIND_WORDS, LABELS, apply_style, is_sequence,
                                     state_axis_label, system_color, system_label)
from forcenet.report import p2 as report
from forcenet.report.p1 import system_dimension
from forcenet.datasets import diagram_points
from forcenet.report.p2_distances import ESSENTIAL_CONVENTIONS_DOC
from forcenet.report.realizations import realization_mean, realization_spread

METRIC_COLORS = {metric: FALLBACK_COLORS[i] for i, metric in enumerate(report.METRICS)}
METRIC_MARKERS = {"bottleneck": "o", "wasserstein_1": "s", "wasserstein_2": "^"}
METRIC_TEX = {"bottleneck": r"$d_B$", "wasserstein_1": r"$d_{W1}$", "wasserstein_2": r"$d_{W2}$"}
DISTANCE_LABEL = r"distance $d$ between consecutive PDs $[\langle F\rangle]$"
RATIO_LABEL = r"ratio of distances $d_B/d_{Wq}$"


#: plain-text symbol [unit] of each distance metric and ratio (the CSV's `quantity` column)
METRIC_QUANTITY = {"bottleneck": "d_B [<F>]", "wasserstein_1": "d_W1 [<F>]", "wasserstein_2": "d_W2 [<F>]"}
RATIO_QUANTITY = {"wasserstein_1": "d_B/d_W1", "wasserstein_2": "d_B/d_W2"}


# --- Fig. 3: PD0 and PD1 of one snapshot --------------------------------------------------------------------------
def prepare_p2_fig03_diagrams(analysis: xr.Dataset, *, kind: str = "normal", system: str = report.FRICTIONAL,
                              essential_death: float = -1.0) -> FigureData:
    """P2 Fig. 3: points of PD0 (panel 0) and PD1 (panel 1) of one snapshot; never-dying classes (death −inf) are
    drawn at death = `essential_death` (P2's −1), given in the column "death drawn [<F>]"."""
    blocks = []
    for h in report.P2_HOMOLOGY_DIMS:
        points = diagram_points(analysis, kind, h)
        birth, death, essential = points.birth, points.death, points.essential
        blocks.append(pd.DataFrame({cols.PANEL: h, cols.SYSTEM: system, "force_kind": kind,
                                    cols.RHO: float(analysis["rho"]), "homology_dim": h, cols.BIRTH: birth,
                                    cols.DEATH: np.where(essential, -np.inf, death), "essential": essential,
                                    "death drawn [<F>]": np.where(essential, essential_death, death)}))
    return FigureData(concat(blocks), {"kind": kind, "system": system, "rho": float(analysis["rho"]),
                                       "essential_death": essential_death})


def draw_p2_fig03_diagrams(data: FigureData) -> Figure:
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
    fig.suptitle(f"Persistence diagrams, {system_label(system)}, {FORCE_KIND_WORDS.get(kind, kind)}, "
                 f"ρ = {data.layout['rho']:.4f} (P2 Fig. 3)")
    return fig


# --- Figs 6, 8, 9: distances vs ρ with Z(ρ) ------------------------------------------------------------------------
def prepare_distances(distances: xr.Dataset, *, kind: str, system: str, source: str) -> FigureData:
    """d_B, d_W1, d_W2 between consecutive PDs vs ρ (realization mean ± standard deviation), panel h = β_h, and the
    realization-mean Z(ρ) (quantity "Z", no band) drawn on a twin axis of each panel; ρ_J on every row."""
    dimension, rho_j = _jamming(distances)
    if is_sequence(system):  # Z reaching d + 1 along a sequence's coordinate is no jamming point
        rho_j = float("nan")
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
                      **common, **{cols.QUANTITY: quantity, cols.RHO_J: rho_j})


def _layout(distances: xr.Dataset, kind: str, system: str, source: str, dimension: int, rho_j: float) -> dict:
    return {"kind": kind, "system": system, "source": source, "dimension": dimension, "rho_J": rho_j,
            "realizations": _realizations_text(distances),
            "never_dying": _never_dying_words(distances)}


def _never_dying_words(distances: xr.Dataset) -> str:
    """How the never-dying classes entered the distances, for the title: nothing under P2's own death −1."""
    convention = distances.attrs.get("essential_convention", "minus_one")
    return "" if convention == "minus_one" else ESSENTIAL_CONVENTIONS_DOC.get(convention, convention)


def draw_distances(data: FigureData) -> Figure:
    """P2 Figs 6, 8, 9: d_B, d_W1, d_W2 vs ρ in panels β0 and β1, Z(ρ) on a twin axis of each."""
    fig, axes = _draw_beta_panels(data, (11.5, 4.6), {METRIC_QUANTITY[m]: (m, METRIC_TEX[m]) for m in report.METRICS},
                                  DISTANCE_LABEL, "distances between consecutive states")
    for ax, h in zip(axes, report.P2_HOMOLOGY_DIMS):
        rows = data.panel(h)
        twin = _z_twin(ax, rows[rows[cols.QUANTITY] == "Z"], data.layout["system"], data.layout["dimension"])
    _figure_legend(fig, [axes[0], twin])
    return fig


def _draw_beta_panels(data: FigureData, size: tuple[float, float], curves: dict[str, tuple[str, str]], ylabel: str,
                      what: str):
    """The two panels of Figs 6–10, (a) β0 and (b) β1 vs ρ on a log y axis: one banded curve per `curves` entry
    (quantity → (metric giving its colour and marker, legend label)), ρ_J and P2's quoted levels marked, and a
    title saying `what`. Returns (figure, axes)."""
    apply_style()
    layout = data.layout
    fig, axes = plt.subplots(1, 2, figsize=size, constrained_layout=True)
    for ax, h in zip(axes, report.P2_HOMOLOGY_DIMS):
        rows = data.panel(h)
        for quantity, (metric, label) in curves.items():
            _draw_band(ax, rows[rows[cols.QUANTITY] == quantity], METRIC_COLORS[metric], METRIC_MARKERS[metric], label)
        _say_when_nothing_is_drawn(ax, rows[rows[cols.QUANTITY].isin(list(curves))][cols.MEAN].to_numpy(float))
        _log_panel_vs_rho(ax, h, ylabel, layout["rho_J"], layout["dimension"])
        ax.set_xlabel(state_axis_label(layout["system"]))
        if not is_sequence(layout["system"]):  # P2 quotes its levels over ρ
            _mark_quoted_levels(ax, layout["source"], h, rows[cols.RHO].values, layout["rho_J"])
    never_dying = f"; {layout['never_dying']}" if layout.get("never_dying") else ""
    fig.suptitle(f"{system_label(layout['system'])}, {FORCE_KIND_WORDS.get(layout['kind'], layout['kind'])}: {what} "
                 f"({layout['realizations']}; {layout['source']}{never_dying})")
    return fig, axes


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
    dimension = system_dimension(distances)
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


def _say_when_nothing_is_drawn(ax, values: np.ndarray) -> None:
    """A log panel with no positive finite value (a diagram pair with nothing finite to match, e.g. under the `drop`
    convention, gives 0 and 0/0) says so on the panel instead of failing to find a log axis range."""
    if not np.any(np.isfinite(values) & (values > 0)):
        ax.set_ylim(0.1, 10.0)
        ax.text(0.5, 0.5, "no positive value to draw on a log axis\n(every distance 0, every ratio undefined)",
                transform=ax.transAxes, ha="center", va="center", color="0.35")


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
    if is_sequence(system):  # Z reaching d + 1 along a sequence's coordinate is no jamming point
        rho_j = float("nan")
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
    """P2 Figs 7, 10: d_B/d_W1 and d_B/d_W2 vs ρ in panels β0 and β1."""
    fig, axes = _draw_beta_panels(data, (11, 4.4), {RATIO_QUANTITY[den]: (den, rf"$d_B/${METRIC_TEX[den]}")
                                                    for den in ("wasserstein_1", "wasserstein_2")},
                                  RATIO_LABEL, "ratios of the rates of change")
    _figure_legend(fig, [axes[0]])
    return fig


def _realizations_text(ds: xr.Dataset) -> str:
    n = int(ds.sizes.get("realization", 1))
    return f"mean of {n} realization{'s' if n != 1 else ''}" + (", band ± 1 standard deviation" if n > 1 else "")
