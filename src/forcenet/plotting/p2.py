"""P2 figures (evolution of force networks): one function per figure, each returns a matplotlib Figure.

Inputs are forcenet datasets: snapshots (Fig. 1), one snapshot's analysis (Fig. 3) and the stacked
``results/{system}/distances.nc`` (Figs 6–10, `forcenet.report.p2.stack_distances`). The reductions (realization
means, ratios, ρ_J) are the ones `forcenet.report.p2` uses for the validation, so figures and verdicts agree.

Curves are means over realizations with the 16–84 % band of the realizations as spread; distances and ratios
are drawn on log axes (P2 discusses them in orders of magnitude, §IV A). Z(ρ) is on a twin axis, with ρ_J
(mean Z reaching d + 1) marked.
"""
from __future__ import annotations

from typing import Callable, Sequence

import matplotlib.pyplot as plt
import numpy as np
import xarray as xr
from matplotlib.collections import LineCollection
from matplotlib.figure import Figure
from matplotlib.patches import Rectangle

from forcenet.plotting.style import FALLBACK_COLORS, LABELS, apply_style, system_color, system_label
from forcenet.report import p2 as report

METRIC_COLORS = {metric: FALLBACK_COLORS[i] for i, metric in enumerate(report.METRICS)}
METRIC_MARKERS = {"bottleneck": "o", "wasserstein_1": "s", "wasserstein_2": "^"}
METRIC_TEX = {"bottleneck": r"$d_B$", "wasserstein_1": r"$d_{W1}$", "wasserstein_2": r"$d_{W2}$"}
KIND_WORDS = {"normal": "normal forces", "tangential": "tangential forces"}
DISTANCE_LABEL = r"distance $d$ between consecutive PDs $[\langle F\rangle]$"
RATIO_LABEL = r"ratio of distances $d_B/d_{Wq}$"


# --- Fig. 1: three nearby snapshots and |ΔF| between them ------------------------------------------------------
def p2_fig01_snapshots_differences(snapshots: Sequence[xr.Dataset], *, kind: str = "normal",
                                   system: str = report.FRICTIONAL, remove_rattlers: bool | str = False) -> Figure:
    """P2 Fig. 1: (a–c) the force network of three nearby snapshots, colour = F/⟨F⟩ of that snapshot;
    (d) |F_b − F_a| and (e) |F_c − F_a| on the contacts of either snapshot (a contact missing in one has F = 0
    there), drawn at snapshot a's particle positions."""
    if len(snapshots) != 3:
        raise ValueError(f"Fig. 1 needs three snapshots a, b, c; got {len(snapshots)}")
    apply_style()
    fig, axes = plt.subplots(2, 3, figsize=(13, 8.6), constrained_layout=True)
    # each network is built once: panels (a–c) draw it, (d–e) take differences of the same edge values
    networks = [report.contact_forces(s, kind, remove_rattlers=remove_rattlers) for s in snapshots]
    vmax = max(float(np.max(n.force)) if n.force.size else 1.0 for n in networks)
    for ax, snap, net, letter in zip(axes[0], snapshots, networks, "abc"):
        lines = _draw_edges(ax, snap["position"].values, net.i, net.j, net.force, "viridis", 0.0, vmax)
        _frame(ax, snap, f"({letter}) ρ = {float(snap['rho']):.4f}")
    fig.colorbar(lines, ax=axes[0].tolist(), shrink=0.8, label=rf"{kind} force $F/\langle F\rangle$")
    n_particles = max(int(s.sizes["particle"]) for s in snapshots)
    diffs = [report.edge_differences(networks[0], networks[k], n_particles) for k in (1, 2)]
    dmax = max([float(np.max(d.force)) for d in diffs if d.force.size] + [1e-12])
    for ax, diff, letter, pair in zip(axes[1], diffs, "de", ("b", "c")):
        lines = _draw_edges(ax, snapshots[0]["position"].values, diff.i, diff.j, diff.force, "inferno_r", 0.0, dmax)
        _frame(ax, snapshots[0], rf"({letter}) $|F_{pair} - F_a|$")
    side = axes[1, 2]
    side.axis("off")
    fig.colorbar(lines, cax=side.inset_axes([0.0, 0.1, 0.06, 0.8]),
                 label=r"$|\Delta F|/\langle F\rangle$ (each snapshot normalised by its own mean)")
    side.text(0.45, 0.5, f"{system_label(system)}, realization {snapshots[0].attrs.get('realization', '?')}\n"
              f"{KIND_WORDS.get(kind, kind)}\n"
              + "\n".join(f"{letter}: ρ = {float(s['rho']):.4f}, Z = {float(s['Z']):.2f}"
                          for letter, s in zip("abc", snapshots)),
              transform=side.transAxes, va="center")
    fig.suptitle("Force networks of three nearby states and their differences (P2 Fig. 1)")
    return fig


def _draw_edges(ax, position, i, j, values, cmap, vmin, vmax):
    segments = np.stack([position[i, :2], position[j, :2]], axis=1) if len(i) else np.zeros((0, 2, 2))
    order = np.argsort(values)  # strongest on top
    lines = LineCollection(segments[order], cmap=cmap, linewidths=1.4)
    lines.set_array(np.asarray(values)[order])
    lines.set_clim(vmin, vmax if vmax > vmin else vmin + 1.0)
    ax.add_collection(lines)
    return lines


def _frame(ax, snapshot: xr.Dataset, title: str) -> None:
    lo, hi = snapshot["box_lo"].values[:2], snapshot["box_hi"].values[:2]
    ax.add_patch(Rectangle(lo, *(hi - lo), fill=False, color="0.4", lw=0.8))
    pad = 0.03 * float(np.max(hi - lo))
    ax.set_xlim(lo[0] - pad, hi[0] + pad)
    ax.set_ylim(lo[1] - pad, hi[1] + pad)
    ax.set_aspect("equal")
    ax.set_xlabel(r"$x$ $[d_{ave}]$")
    ax.set_ylabel(r"$y$ $[d_{ave}]$")
    ax.set_title(title)


# --- Fig. 3: PD0 and PD1 of one snapshot --------------------------------------------------------------------------
def p2_fig03_diagrams(analysis: xr.Dataset, *, kind: str = "normal", system: str = report.FRICTIONAL,
                      essential_death: float = -1.0) -> Figure:
    """P2 Fig. 3: PD0 and PD1 of one snapshot (birth ≥ death, super-level filtration); never-dying classes are
    drawn at death = `essential_death` (P2's −1) with their own marker."""
    apply_style()
    fig, axes = plt.subplots(1, 2, figsize=(10, 4.6), constrained_layout=True)
    color = system_color(system)
    for ax, h in zip(axes, report.P2_HOMOLOGY_DIMS):
        birth, death, essential = report.diagram_points(analysis, kind, h)
        finite = ~essential
        ax.scatter(birth[finite], death[finite], s=10, color=color, alpha=0.6, lw=0, label="finite classes")
        ax.scatter(birth[essential], np.full(essential.sum(), essential_death), s=40, marker="x", color="k",
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
                 f"ρ = {float(analysis['rho']):.4f} (P2 Fig. 3)")
    return fig


# --- Figs 6, 8, 9: distances vs ρ with Z(ρ) ------------------------------------------------------------------------
def p2_fig06_distances_normal_mu05(distances: xr.Dataset, *, system: str = report.FRICTIONAL) -> Figure:
    """P2 Fig. 6: d_B, d_W1, d_W2 between consecutive PDs vs ρ, β0 and β1, normal forces, μ = 0.5; Z(ρ)."""
    return _distance_figure(distances, "normal", system, 6)


def p2_fig08_distances_tangential_mu05(distances: xr.Dataset, *, system: str = report.FRICTIONAL) -> Figure:
    """P2 Fig. 8: as Fig. 6 for the tangential forces (each network normalised by its mean tangential force)."""
    return _distance_figure(distances, "tangential", system, 8)


def p2_fig09_distances_normal_mu0(distances: xr.Dataset, *, system: str = report.FRICTIONLESS) -> Figure:
    """P2 Fig. 9: as Fig. 6 for the frictionless system (μ = 0)."""
    return _distance_figure(distances, "normal", system, 9)


def _distance_figure(distances: xr.Dataset, kind: str, system: str, p2_figure: int) -> Figure:
    apply_style()
    fig, axes = plt.subplots(1, 2, figsize=(11.5, 4.6), constrained_layout=True)
    dimension, rho_j = _jamming(distances)
    for ax, h in zip(axes, report.P2_HOMOLOGY_DIMS):
        for metric in report.METRICS:
            da = distances["distance"].sel(force_kind=kind, homology_dim=h, metric=metric)
            _mean_band(ax, report.realization_mean(da), da, METRIC_COLORS[metric], METRIC_MARKERS[metric],
                       METRIC_TEX[metric])
        _log_panel_vs_rho(ax, h, DISTANCE_LABEL, rho_j, dimension)
        _mark_quoted_levels(ax, p2_figure, h, distances["rho"].values, rho_j)
        twin = _z_twin(ax, distances, system, dimension)
    _figure_legend(fig, [axes[0], twin])
    fig.suptitle(f"{system_label(system)}, {KIND_WORDS.get(kind, kind)}: distances between consecutive states "
                 f"({_realizations_text(distances)}; P2 Fig. {p2_figure})")
    return fig


def _mark_quoted_levels(ax, p2_figure: int, h: int, rho: np.ndarray, rho_j: float) -> None:
    """P2's quoted levels for this panel (`report.P2_QUOTED_LEVELS`) as grey dashed segments over their ρ range."""
    for level in report.quoted_levels(p2_figure, h):
        high = rho_j if level.rho_below == "rho_J" else float(level.rho_below)
        if np.isfinite(high) and high > float(np.min(rho)):
            ax.hlines(level.value, float(np.min(rho)), min(high, float(np.max(rho))), colors=METRIC_COLORS[level.metric],
                      linestyles=(0, (5, 3)), lw=1.6, alpha=0.8, label=level.text)


def _jamming(distances: xr.Dataset) -> tuple[int, float]:
    """(d, ρ_J) of a distances dataset: its spatial dimension and where the mean Z(ρ) reaches d + 1."""
    dimension = int(distances.attrs.get("dimension", 2))
    return dimension, report.jamming_density(distances, dimension)


def _mean_band(ax, mean: xr.DataArray, band_source: xr.DataArray, color, marker: str, label: str) -> None:
    """The curve `mean` (vs ρ) and the 16–84 % band of `band_source` over its realizations."""
    low, high = report.realization_band(band_source)
    rho = mean["rho"].values
    ax.plot(rho, mean.values, color=color, marker=marker, ms=3.5, lw=1.3, label=label)
    ax.fill_between(rho, low.values, high.values, color=color, alpha=0.2, lw=0)


def _log_panel_vs_rho(ax, h: int, ylabel: str, rho_j: float, dimension: int) -> None:
    """Panel set-up shared by Figs 6–10: ρ_J marked (if Z reaches d + 1), log y axis, labels, β_h title."""
    if np.isfinite(rho_j):
        ax.axvline(rho_j, color="0.3", ls=":", lw=1.0, label=rf"$\rho_J$ = {rho_j:.3f} ($Z = {dimension + 1}$)")
    ax.set_yscale("log", nonpositive="mask")
    ax.set_xlabel(LABELS["rho"])
    ax.set_ylabel(ylabel)
    ax.set_title(rf"({'ab'[h]}) $\beta_{h}$")


def _z_twin(ax, distances: xr.Dataset, system: str, dimension: int):
    twin = ax.twinx()
    z = report.realization_mean(distances["Z"])
    twin.plot(z["rho"].values, z.values, color=system_color(system), ls="--", lw=1.5, label=r"$Z$")
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
def p2_fig07_ratios_mu05(distances: xr.Dataset, *, kind: str = "normal", system: str = report.FRICTIONAL) -> Figure:
    """P2 Fig. 7: d_B/d_W1 and d_B/d_W2 vs ρ, β0 and β1, μ = 0.5 (normal forces)."""
    return _ratio_figure(distances, kind, system, 7)


def p2_fig10_ratios_mu0(distances: xr.Dataset, *, kind: str = "normal", system: str = report.FRICTIONLESS) -> Figure:
    """P2 Fig. 10: as Fig. 7 for the frictionless system (μ = 0)."""
    return _ratio_figure(distances, kind, system, 10)


def _ratio_figure(distances: xr.Dataset, kind: str, system: str, p2_figure: int) -> Figure:
    apply_style()
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.4), constrained_layout=True)
    dimension, rho_j = _jamming(distances)
    for ax, h in zip(axes, report.P2_HOMOLOGY_DIMS):
        for den in ("wasserstein_1", "wasserstein_2"):
            panel = {"force_kind": kind, "homology_dim": h}
            _mean_band(ax, report.mean_distance_ratio(distances, den).sel(panel),
                       report.distance_ratio(distances, den).sel(panel),
                       METRIC_COLORS[den], METRIC_MARKERS[den], rf"$d_B/${METRIC_TEX[den]}")
        _log_panel_vs_rho(ax, h, RATIO_LABEL, rho_j, dimension)
        _mark_quoted_levels(ax, p2_figure, h, distances["rho"].values, rho_j)
    _figure_legend(fig, [axes[0]])
    fig.suptitle(f"{system_label(system)}, {KIND_WORDS.get(kind, kind)}: ratios of the rates of change "
                 f"({_realizations_text(distances)}; P2 Fig. {p2_figure})")
    return fig


def _realizations_text(ds: xr.Dataset) -> str:
    n = int(ds.sizes.get("realization", 1))
    return f"mean of {n} realization{'s' if n != 1 else ''}" + (", 16–84 % band" if n > 1 else "")


P2_FIGURES: dict[str, Callable[..., Figure]] = {
    "p2_fig01_snapshots_differences": p2_fig01_snapshots_differences,
    "p2_fig03_diagrams": p2_fig03_diagrams,
    "p2_fig06_distances_normal_mu05": p2_fig06_distances_normal_mu05,
    "p2_fig07_ratios_mu05": p2_fig07_ratios_mu05,
    "p2_fig08_distances_tangential_mu05": p2_fig08_distances_tangential_mu05,
    "p2_fig09_distances_normal_mu0": p2_fig09_distances_normal_mu0,
    "p2_fig10_ratios_mu0": p2_fig10_ratios_mu0,
}
"""Figure name (the output file stem, ``results/figures/{name}.pdf``) → function."""
