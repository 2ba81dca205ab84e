"""The figures of P1 (compressed 2D/3D interaction networks), one function per figure.

Every function takes the aggregated datasets keyed by system name — ``measures`` (network_measures.nc),
``diagrams`` (diagrams.nc), ``snapshots`` (one snapshot file per system) — and returns a matplotlib Figure. They
only select and average: the reductions P1 defines (F_max rule → ρ_max, S_p averaging rule, ≥ 50 % percolation
rule, jamming point) live in `forcenet.report.p1` and are shared with the validation table. Curves are
realization means with ± one standard deviation over the realizations as a band; each system keeps its colour
(`forcenet.plotting.style.system_color`), a family of curves within a panel (F_th, ρ) uses shades of it.
Every simulated ρ is drawn; ρ_max of P1's F_max rule (§3), with ⟨F⟩ compared in `force_unit`
(``analysis.p1_force_unit``), is a dashed line on every ρ axis with the range beyond it shaded, where P1 shows
nothing.

The workflow calls one figure by name: ``make_p1_figure(name, measures, diagrams, snapshots)``; `P1_FIGURES`
lists the names, which inputs each figure needs and its caption.
"""
from __future__ import annotations

import inspect
from dataclasses import dataclass
from typing import Callable, Mapping, Sequence

import numpy as np
import xarray as xr

from forcenet.measures.persistence_stats import MEDIUM_BIRTH, ROUGH_LIFESPAN, STRONG_BIRTH, WEAK_BIRTH
from forcenet.plotting.style import LABELS, apply_style, system_color, system_label
from forcenet.report.p1 import (DEFAULT_P1_FORCE_UNIT, P1_SMALL_THRESHOLD, f_max_cut, jamming_point,
                                mean_and_spread, per_particle, percolating_size_mean, rho_values, select_total,
                                shape_parameter_average, system_dimension, system_order)

import matplotlib.pyplot as plt  # noqa: E402  (style sets the Agg backend first)
import seaborn as sns  # noqa: E402
from matplotlib.collections import EllipseCollection, LineCollection  # noqa: E402
from matplotlib.colors import Normalize  # noqa: E402
from matplotlib.figure import Figure  # noqa: E402

#: F_th cross-sections drawn in the line figures (the nearest values of the threshold grid are used)
DEFAULT_THRESHOLDS = (0.0, 0.5, 1.0, 1.5, 2.0, 2.5)
PD_BINS = ("rough", "weak", "medium", "strong")  # P1 §5.3 bins drawn in Figs. 10-11 (essential points apart)

MEAN_GID = "mean"  # gid of every realization-mean curve, so that tests (and readers) can find them
RHO_J_GID = "rho_J"
RHO_MAX_GID = "rho_max"  # the dashed ρ_max line; the shading beyond it is "beyond_rho_max"
FORCE_CMAP = "viridis"

LABEL_B0 = r"$B_0/N$"
LABEL_B1 = r"$B_1/N$"
LABEL_B2 = r"$B_2/N$"
LABEL_S = r"$\langle S\rangle/N$"
LABEL_NPER = r"$N_{per}/N$"
LABEL_SP = r"shape parameter $S_p$"
LABEL_N0 = r"$N_0/N$"
LABEL_TP = r"$TP_k/N$ [$\langle F\rangle$]"
POSITION_LABELS = (r"$x$ [$d_{ave}$]", r"$y$ [$d_{ave}$]", r"$z$ [$d_{ave}$]")


# =============================================================================================================
# helpers: selection, panels, curves
# =============================================================================================================
@dataclass(frozen=True)
class _System:
    name: str
    data: xr.Dataset  # total force, every simulated ρ
    rho_j: float
    dimension: int
    rho_max: float  # P1 §3 F_max rule
    rho_max_below_grid: bool = False  # every ρ has ⟨F⟩ > F_max


def _systems(measures: Mapping[str, xr.Dataset], force_unit: str = DEFAULT_P1_FORCE_UNIT) -> list[_System]:
    """The systems in P1's order, each with its ρ_J and its ρ_max (P1 §3 F_max rule, ⟨F⟩ in `force_unit`)."""
    if not measures:
        raise ValueError("no system to plot")
    cut = f_max_cut(measures, force_unit)
    return [_System(name, select_total(measures[name]), jamming_point(measures[name]),
                    system_dimension(measures[name], name), cut.rho_max[name], cut.below_grid(name))
            for name in system_order(measures)]


def _figure(n_panels: int, ncols: int = 3, size=(4.2, 3.3), projections: Sequence[str | None] | None = None):
    apply_style()
    ncols = max(1, min(ncols, n_panels))
    nrows = int(np.ceil(n_panels / ncols))
    fig = plt.figure(figsize=(size[0] * ncols, size[1] * nrows), layout="constrained")
    projections = projections or [None] * n_panels
    axes = [fig.add_subplot(nrows, ncols, k + 1, projection=projections[k]) for k in range(n_panels)]
    return fig, axes


def _shades(name: str, n: int) -> list:
    """n shades of the system's colour, light to dark (a family of curves: increasing F_th or ρ)."""
    if n <= 1:
        return [system_color(name)] * n
    return sns.light_palette(system_color(name), n_colors=n + 2)[2:]


def _nearest(values: np.ndarray, wanted: Sequence[float]) -> list[float]:
    """The grid values nearest to `wanted`, each once, in increasing order."""
    values = np.asarray(values, dtype=float)
    picked = {float(values[np.argmin(np.abs(values - w))]) for w in wanted}
    return sorted(picked)


def _curve(ax, x, mean, spread, color, label=None, **line):
    x, mean, spread = (np.asarray(v, dtype=float) for v in (x, mean, spread))
    ax.plot(x, mean, color=color, label=label, gid=MEAN_GID, **line)
    ax.fill_between(x, mean - spread, mean + spread, color=color, alpha=0.2, linewidth=0)


def _mark_jamming(ax, rho_j: float, name: str) -> None:
    """ρ_J of system `name` as a dotted vertical line in its colour."""
    if np.isfinite(rho_j):
        ax.axvline(rho_j, color=system_color(name), linestyle=":", linewidth=1, gid=RHO_J_GID)


def _mark_rho_max(ax, system: _System, color=None, label: bool = True) -> None:
    """ρ_max of `system` as a dashed vertical line, the ρ beyond it (not shown in P1) lightly shaded; every ρ
    shaded when ρ_max lies below the grid."""
    color = system_color(system.name) if color is None else color
    if system.rho_max_below_grid:
        rho = rho_values(system.data)
        ax.axvspan(rho.min(), rho.max(), color=color, alpha=0.08, linewidth=0, gid="beyond_rho_max",
                   label=r"every $\rho$ > $\rho_{max}$ (P1 §3)" if label else None)
    if not np.isfinite(system.rho_max):
        return
    ax.axvline(system.rho_max, color=color, linestyle="--", linewidth=1, gid=RHO_MAX_GID,
               label=r"$\rho_{max}$ (P1 §3)" if label else None)
    top = float(rho_values(system.data).max())
    if top > system.rho_max:
        ax.axvspan(system.rho_max, top, color=color, alpha=0.08, linewidth=0, gid="beyond_rho_max")


def _title(ax, name: str, extra: str = "") -> None:
    ax.set_title(system_label(name) + extra, color=system_color(name))


def _threshold_family(ax, system: _System, values: xr.DataArray | tuple, thresholds: Sequence[float],
                      ylabel: str) -> None:
    """Curves versus ρ, one per F_th: `values` is (realization, rho, threshold) or a (mean, spread) pair."""
    if isinstance(values, tuple):
        mean, spread = values
    else:
        mean, spread = mean_and_spread(values)
    rho = rho_values(system.data)
    chosen = _nearest(mean["threshold"].values, thresholds)
    for color, threshold in zip(_shades(system.name, len(chosen)), chosen):
        _curve(ax, rho, mean.sel(threshold=threshold).transpose("rho").values,
               spread.sel(threshold=threshold).transpose("rho").values, color, label=rf"$F_{{th}}$ = {threshold:g}")
    _mark_jamming(ax, system.rho_j, system.name)
    _mark_rho_max(ax, system)
    ax.set_xlabel(LABELS["rho"])
    ax.set_ylabel(ylabel)
    _title(ax, system.name)


def _heat_map(fig, ax, system: _System, values: xr.DataArray, label: str) -> None:
    """A (ρ, F_th) map of a realization-averaged quantity, ρ on x."""
    values = values.transpose("threshold", "rho")
    mesh = ax.pcolormesh(rho_values(system.data), values["threshold"].values, values.values, shading="nearest",
                         cmap="magma")
    fig.colorbar(mesh, ax=ax, label=label)
    _mark_jamming(ax, system.rho_j, system.name)
    _mark_rho_max(ax, system, color="white", label=False)
    ax.set_xlabel(LABELS["rho"])
    ax.set_ylabel(LABELS["threshold"])
    _title(ax, system.name)


def _first_legend(axes, **kwargs) -> None:
    if axes:
        axes[0].legend(fontsize="x-small", frameon=False, **kwargs)


# =============================================================================================================
# the figures
# =============================================================================================================
def fig01_networks(snapshots: Mapping[str, xr.Dataset], *, max_line_width: float = 3.0) -> Figure:
    """F1: force networks of one snapshot per system, edges coloured (and thickened) by F/⟨F⟩, with F the
    total contact force |F_n + F_t|; 2D as lines over the disks, 3D as lines in a 3D box."""
    names = system_order(snapshots)
    dims = [int(snapshots[name].sizes["spatial"]) for name in names]
    fig, axes = _figure(len(names), size=(4.6, 4.2), projections=["3d" if d == 3 else None for d in dims])
    networks = {}
    for name in names:
        ds = snapshots[name]
        force = np.linalg.norm(ds["force_normal"].values + ds["force_tangential"].values, axis=-1)
        keep = force > 0
        relative = force[keep] / force[keep].mean() if keep.any() else force[keep]
        networks[name] = (ds["contact_i"].values[keep], ds["contact_j"].values[keep], relative)
    everything = np.concatenate([n[2] for n in networks.values()]) if networks else np.zeros(0)
    norm = Normalize(0.0, float(np.quantile(everything, 0.99)) if everything.size else 1.0)
    for ax, name, dim in zip(axes, names, dims):
        ds = snapshots[name]
        i, j, relative = networks[name]
        position = ds["position"].values
        segments = np.stack([position[i], position[j]], axis=1)
        widths = 0.3 + max_line_width * np.clip(relative / max(norm.vmax, 1e-12), 0, 1)
        lo, hi = ds["box_lo"].values, ds["box_hi"].values
        if dim == 3:
            from mpl_toolkits.mplot3d.art3d import Line3DCollection

            lines = Line3DCollection(segments, cmap=FORCE_CMAP, norm=norm, linewidths=widths)
            lines.set_array(relative)
            ax.add_collection3d(lines)
            ax.set_zlim(lo[2], hi[2])
            ax.set_zlabel(POSITION_LABELS[2])
        else:
            disks = EllipseCollection(2 * ds["radius"].values, 2 * ds["radius"].values, 0, units="xy",
                                      offsets=position, offset_transform=ax.transData, facecolors="none",
                                      edgecolors="0.75", linewidths=0.4)
            ax.add_collection(disks)
            lines = LineCollection(segments, cmap=FORCE_CMAP, norm=norm, linewidths=widths)
            lines.set_array(relative)
            ax.add_collection(lines)
            ax.set_aspect("equal")
        ax.set_xlim(lo[0], hi[0])
        ax.set_ylim(lo[1], hi[1])
        ax.set_xlabel(POSITION_LABELS[0])
        ax.set_ylabel(POSITION_LABELS[1])
        rho = float(ds["rho"]) if "rho" in ds else float("nan")
        _title(ax, name, rf", $\rho$ = {rho:.3f}")
    mappable = plt.cm.ScalarMappable(norm=norm, cmap=FORCE_CMAP)
    fig.colorbar(mappable, ax=axes, label=LABELS["force"], shrink=0.8)
    return fig


def fig02_betti0_surface(measures: Mapping[str, xr.Dataset], *, force_unit: str = DEFAULT_P1_FORCE_UNIT) -> Figure:
    """F2: B0/N over (ρ, F_th), realization mean, one map per system."""
    systems = _systems(measures, force_unit)
    fig, axes = _figure(len(systems))
    for ax, system in zip(axes, systems):
        b0 = per_particle(system.data, "betti").sel(homology_dim=0).mean("realization", skipna=True)
        _heat_map(fig, ax, system, b0, LABEL_B0)
    return fig


def fig03_force_pdf(measures: Mapping[str, xr.Dataset], *, n_rho: int = 6,
                    force_unit: str = DEFAULT_P1_FORCE_UNIT) -> Figure:
    """F3: PDF of F/⟨F⟩ (total force) at `n_rho` packing fractions spread over the grid, darker for larger ρ;
    those beyond ρ_max (not shown in P1) dashed."""
    systems = _systems(measures, force_unit)
    fig, axes = _figure(len(systems))
    for ax, system in zip(axes, systems):
        pdf = system.data["force_pdf"]
        mean, spread = mean_and_spread(pdf)
        rho = rho_values(system.data)
        picks = np.unique(np.round(np.linspace(0, rho.size - 1, min(n_rho, rho.size))).astype(int))
        centres = pdf["force_bin"].values
        for color, index in zip(_shades(system.name, picks.size), picks):
            beyond = rho[index] > system.rho_max + 1e-12  # False when ρ_max is NaN
            _curve(ax, centres, mean.isel(rho=index).values, spread.isel(rho=index).values, color,
                   label=rf"$\rho$ = {rho[index]:.3f}" + (r" > $\rho_{max}$" if beyond else ""),
                   linestyle="--" if beyond else "-")
        ax.set_xlabel(LABELS["force"])
        ax.set_ylabel(LABELS["pdf"] + r" [$\langle F\rangle^{-1}$]")
        _title(ax, system.name)
        ax.legend(fontsize="x-small", frameon=False)
    return fig


def fig04_cluster_size(measures: Mapping[str, xr.Dataset], *, thresholds: Sequence[float] = DEFAULT_THRESHOLDS,
                       force_unit: str = DEFAULT_P1_FORCE_UNIT) -> Figure:
    """F4: mean size ⟨S⟩/N of the non-percolating clusters versus ρ, one curve per F_th."""
    systems = _systems(measures, force_unit)
    fig, axes = _figure(len(systems))
    for ax, system in zip(axes, systems):
        _threshold_family(ax, system, per_particle(system.data, "cluster_mean_size"), thresholds, LABEL_S)
    _first_legend(axes)
    return fig


def fig05_percolating_size(measures: Mapping[str, xr.Dataset], *,
                           thresholds: Sequence[float] = DEFAULT_THRESHOLDS,
                           force_unit: str = DEFAULT_P1_FORCE_UNIT) -> Figure:
    """F5: N_per/N versus ρ per F_th, averaged over the percolating realizations and shown only where at
    least 50 % of the realizations percolate (P1 §4.3)."""
    systems = _systems(measures, force_unit)
    fig, axes = _figure(len(systems))
    for ax, system in zip(axes, systems):
        _threshold_family(ax, system, percolating_size_mean(system.data), thresholds, LABEL_NPER)
    _first_legend(axes)
    return fig


def fig06_betti0(measures: Mapping[str, xr.Dataset], *, thresholds: Sequence[float] = DEFAULT_THRESHOLDS,
                 zoom_curves: int = 4, force_unit: str = DEFAULT_P1_FORCE_UNIT) -> Figure:
    """F6: B0/N versus ρ per F_th; for each 3D system an extra close-up of the F_th < 0.5 curves around ρ_J
    (P1 Fig. 6d)."""
    systems = _systems(measures, force_unit)
    zooms = [s for s in systems if s.dimension == 3]
    fig, axes = _figure(len(systems) + len(zooms), ncols=4 if zooms else 3)
    for ax, system in zip(axes, systems):
        _threshold_family(ax, system, per_particle(system.data, "betti").sel(homology_dim=0), thresholds, LABEL_B0)
    for ax, system in zip(axes[len(systems):], zooms):
        grid = system.data["threshold"].values
        small = grid[grid < P1_SMALL_THRESHOLD]
        chosen = small[np.unique(np.round(np.linspace(0, small.size - 1, min(zoom_curves, small.size))).astype(int))] \
            if small.size else grid[:1]
        _threshold_family(ax, system, per_particle(system.data, "betti").sel(homology_dim=0), chosen, LABEL_B0)
        rho = rho_values(system.data)
        if np.isfinite(system.rho_j) and rho.size > 1:
            half_width = 4 * float(np.median(np.diff(rho)))
            ax.set_xlim(max(rho[0], system.rho_j - half_width), min(rho[-1], system.rho_j + half_width))
        _title(ax, system.name, rf", $F_{{th}}$ < {P1_SMALL_THRESHOLD:g} (close-up)")
        ax.legend(fontsize="x-small", frameon=False)
    _first_legend(axes)
    return fig


def fig07_loops(measures: Mapping[str, xr.Dataset], *, thresholds: Sequence[float] = DEFAULT_THRESHOLDS,
                force_unit: str = DEFAULT_P1_FORCE_UNIT) -> Figure:
    """F7: B1/N versus ρ per F_th for every system, and B2/N for the 3D ones."""
    systems = _systems(measures, force_unit)
    panels = [(s, 1) for s in systems] + [(s, 2) for s in systems if s.dimension == 3]
    fig, axes = _figure(len(panels))
    for ax, (system, k) in zip(axes, panels):
        _threshold_family(ax, system, per_particle(system.data, "betti").sel(homology_dim=k), thresholds,
                          LABEL_B1 if k == 1 else LABEL_B2)
    _first_legend(axes)
    return fig


def fig08_shape_surface(measures: Mapping[str, xr.Dataset], *, force_unit: str = DEFAULT_P1_FORCE_UNIT) -> Figure:
    """F8: shape parameter S_p over (ρ, F_th) with P1's averaging rule (§5.2)."""
    systems = _systems(measures, force_unit)
    fig, axes = _figure(len(systems))
    for ax, system in zip(axes, systems):
        shape, _ = shape_parameter_average(system.data["shape_parameter"])
        _heat_map(fig, ax, system, shape, LABEL_SP)
    return fig


def fig09_shape_sections(measures: Mapping[str, xr.Dataset], *,
                         thresholds: Sequence[float] = DEFAULT_THRESHOLDS,
                         force_unit: str = DEFAULT_P1_FORCE_UNIT) -> Figure:
    """F9: S_p versus ρ for chosen F_th (P1's averaging rule; band: spread over the nonzero realizations)."""
    systems = _systems(measures, force_unit)
    fig, axes = _figure(len(systems))
    for ax, system in zip(axes, systems):
        _threshold_family(ax, system, shape_parameter_average(system.data["shape_parameter"]), thresholds,
                          LABEL_SP)
    _first_legend(axes)
    return fig


def fig10_persistence_diagram(measures: Mapping[str, xr.Dataset], diagrams: Mapping[str, xr.Dataset], *,
                              system: str | None = None, rho: float | None = None,
                              realization: int | None = None) -> Figure:
    """F10: one PD0 (total force) with P1's bins shaded: rough (lifespan ≤ 0.1), weak (0.1 ≤ birth < 1),
    medium (1 ≤ birth < 2.5), strong (birth ≥ 2.5). Defaults: the 2D Hertzian system (as P1), the first
    realization, the packing fraction nearest to its ρ_J."""
    names = system_order(diagrams)
    system = system or next((n for n in names if n == "2d_hertz"), names[0])
    points = diagrams[system]
    realization = int(np.min(points["point_realization"].values)) if realization is None else realization
    if rho is None:
        grid = np.unique(points["point_rho"].values)
        rho_j = jamming_point(measures[system]) if system in measures else float("nan")
        rho = float(grid[np.argmin(np.abs(grid - rho_j))]) if np.isfinite(rho_j) else float(grid[len(grid) // 2])
    from forcenet.datasets.schema import FORCE_KINDS

    mask = ((points["diagram_force_kind"].values == FORCE_KINDS.index("total"))
            & (points["diagram_homology_dim"].values == 0)
            & (points["point_realization"].values == realization)
            & np.isclose(points["point_rho"].values, rho))
    birth, death = points["birth"].values[mask], points["death"].values[mask]
    essential = ~np.isfinite(death)
    fig, (ax,) = _figure(1, size=(4.8, 4.4))
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
    _title(ax, system, rf", $\rho$ = {rho:.3f}, realization {realization}")
    ax.legend(fontsize="x-small", frameon=False, loc="upper left")
    return fig


def fig11_persistence_bins(measures: Mapping[str, xr.Dataset], *, force_unit: str = DEFAULT_P1_FORCE_UNIT) -> Figure:
    """F11: PD0 points per bin N0/N versus ρ; rows rough/weak/medium/strong, columns 2D and 3D (P1 Fig. 11),
    one curve per system."""
    systems = _systems(measures, force_unit)
    dimensions = sorted({s.dimension for s in systems})
    fig, axes = _figure(len(PD_BINS) * len(dimensions), ncols=len(dimensions), size=(4.4, 2.8))
    for row, bin_name in enumerate(PD_BINS):
        for col, dimension in enumerate(dimensions):
            ax = axes[row * len(dimensions) + col]
            for system in (s for s in systems if s.dimension == dimension):
                counts = per_particle(system.data, "persistence_bin_count").sel(persistence_bin=bin_name)
                mean, spread = mean_and_spread(counts)
                _curve(ax, rho_values(system.data), mean.values, spread.values, system_color(system.name),
                       label=system_label(system.name))
                _mark_jamming(ax, system.rho_j, system.name)
                _mark_rho_max(ax, system, label=system is next(s for s in systems if s.dimension == dimension))
            ax.set_xlabel(LABELS["rho"])
            ax.set_ylabel(LABEL_N0)
            ax.set_title(f"{bin_name}, {dimension}D")
            ax.legend(fontsize="x-small", frameon=False)
    return fig


def fig12_total_persistence(measures: Mapping[str, xr.Dataset], *,
                            force_unit: str = DEFAULT_P1_FORCE_UNIT) -> Figure:
    """F12: total persistence TP0/N (solid) and TP1/N (dashed) of the total-force network versus ρ."""
    systems = _systems(measures, force_unit)
    fig, axes = _figure(len(systems))
    for ax, system in zip(axes, systems):
        tp = per_particle(system.data, "total_persistence")
        for k, style in ((0, "-"), (1, "--")):
            mean, spread = mean_and_spread(tp.sel(homology_dim=k))
            _curve(ax, rho_values(system.data), mean.values, spread.values, system_color(system.name),
                   label=rf"$TP_{k}/N$", linestyle=style)
        _mark_jamming(ax, system.rho_j, system.name)
        _mark_rho_max(ax, system)
        ax.set_xlabel(LABELS["rho"])
        ax.set_ylabel(LABEL_TP)
        _title(ax, system.name)
        ax.legend(fontsize="x-small", frameon=False)
    return fig


def z_jamming(measures: Mapping[str, xr.Dataset], *, force_unit: str = DEFAULT_P1_FORCE_UNIT) -> Figure:
    """Z(ρ) of every system over its whole ρ grid, with ρ_J (inflection, P1 §4) and ρ_max marked and Z = d + 1
    dotted."""
    fig, (ax,) = _figure(1, size=(5.2, 3.8))
    for index, system in enumerate(_systems(measures, force_unit)):
        name, ds = system.name, measures[system.name]
        mean, spread = mean_and_spread(ds["Z"])
        color = system_color(name)
        _curve(ax, rho_values(ds), mean.values, spread.values, color, label=system_label(name))
        rho_j = jamming_point(ds)
        if np.isfinite(rho_j):
            z_j = np.interp(rho_j, rho_values(ds), mean.values)
            ax.plot([rho_j], [z_j], marker="o", markersize=7, markerfacecolor="white", color=color,
                    gid=RHO_J_GID, label=rf"$\rho_J$ = {rho_j:.3f}")
        _mark_rho_max(ax, system, label=index == 0)
    for dimension in sorted({system_dimension(measures[name], name) for name in measures}):
        ax.axhline(dimension + 1, color="0.5", linestyle=":", linewidth=0.8, gid="isostatic")
        ax.annotate(f"Z = d + 1 = {dimension + 1} ({dimension}D)", (0.01, dimension + 1),
                    xycoords=("axes fraction", "data"), va="bottom", fontsize="x-small", color="0.4")
    ax.set_xlabel(LABELS["rho"])
    ax.set_ylabel(LABELS["Z"])
    ax.legend(fontsize="x-small", frameon=False)
    return fig


# =============================================================================================================
# registry
# =============================================================================================================
@dataclass(frozen=True)
class P1Figure:
    """A P1 figure: the function drawing it, the inputs it needs ("measures", "diagrams", "snapshots") and the
    caption for the report."""

    function: Callable[..., Figure]
    needs: tuple[str, ...]
    caption: str


_CUT = (" Every simulated ρ; ρ_max of P1's F_max rule (§3, ⟨F⟩ compared in the unit analysis.p1_force_unit) "
        "dashed, the range beyond it (not shown in P1) shaded; mean over realizations, band ± 1 s.d.")
P1_FIGURES: dict[str, P1Figure] = {
    "p1_fig01_networks": P1Figure(fig01_networks, ("snapshots",),
                                  "Fig. 1: force networks in 2D and 3D, contacts coloured by F/⟨F⟩."),
    "p1_fig02_betti0_surface": P1Figure(fig02_betti0_surface, ("measures",),
                                        "Fig. 2: number of clusters B0/N over (ρ, F_th)." + _CUT),
    "p1_fig03_force_pdf": P1Figure(fig03_force_pdf, ("measures",),
                                   "Fig. 3: PDF of F/⟨F⟩ for several ρ, darker for larger ρ." + _CUT),
    "p1_fig04_cluster_size": P1Figure(fig04_cluster_size, ("measures",),
                                      "Fig. 4: mean non-percolating cluster size ⟨S⟩/N versus ρ per F_th." + _CUT),
    "p1_fig05_percolating_cluster": P1Figure(fig05_percolating_size, ("measures",),
                                          "Fig. 5: percolating-cluster size N_per/N versus ρ per F_th, where "
                                          "≥ 50 % of the realizations percolate." + _CUT),
    "p1_fig06_betti0": P1Figure(fig06_betti0, ("measures",),
                                "Fig. 6: B0/N versus ρ per F_th, with a close-up of small F_th in 3D." + _CUT),
    "p1_fig07_betti1": P1Figure(fig07_loops, ("measures",),
                                "Fig. 7: loops B1/N (and cavities B2/N in 3D) versus ρ per F_th." + _CUT),
    "p1_fig08_shape_heatmap": P1Figure(fig08_shape_surface, ("measures",),
                                       "Fig. 8: shape parameter S_p over (ρ, F_th), P1's averaging rule." + _CUT),
    "p1_fig09_shape_sections": P1Figure(fig09_shape_sections, ("measures",),
                                        "Fig. 9: shape parameter S_p versus ρ for chosen F_th." + _CUT),
    "p1_fig10_persistence_diagram": P1Figure(fig10_persistence_diagram, ("measures", "diagrams"),
                                             "Fig. 10: an example PD0 with the rough, weak, medium and strong "
                                             "bins."),
    "p1_fig11_persistence_bins": P1Figure(fig11_persistence_bins, ("measures",),
                                          "Fig. 11: PD0 points per bin N0/N versus ρ, 2D and 3D." + _CUT),
    "p1_fig12_total_persistence": P1Figure(fig12_total_persistence, ("measures",),
                                           "Fig. 12: total persistence TP0/N and TP1/N versus ρ." + _CUT),
    "p1_z_jamming": P1Figure(z_jamming, ("measures",),
                             "Coordination number Z(ρ) with the jamming point ρ_J (inflection) and ρ_max marked."),
}


def make_p1_figure(name: str, measures: Mapping[str, xr.Dataset] | None = None,
                   diagrams: Mapping[str, xr.Dataset] | None = None,
                   snapshots: Mapping[str, xr.Dataset] | None = None, *, force_unit: str | None = None,
                   **options) -> Figure:
    """Draw the P1 figure `name` (a key of `P1_FIGURES`) from datasets keyed by system name; `force_unit`
    (``analysis.p1_force_unit``) goes to the figures that mark ρ_max."""
    if name not in P1_FIGURES:
        raise KeyError(f"unknown P1 figure {name!r}; known: {', '.join(P1_FIGURES)}")
    spec = P1_FIGURES[name]
    given = {"measures": measures, "diagrams": diagrams, "snapshots": snapshots}
    missing = [need for need in spec.needs if not given[need]]
    if missing:
        raise ValueError(f"{name} needs {', '.join(missing)}")
    if force_unit is not None and "force_unit" in inspect.signature(spec.function).parameters:
        options["force_unit"] = force_unit
    return spec.function(**{need: given[need] for need in spec.needs}, **options)
