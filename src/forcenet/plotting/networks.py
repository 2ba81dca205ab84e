"""Figures that draw force networks edge by edge: P1 Fig. 1 (one snapshot per system), P2 Fig. 1 (three nearby
states and the force changes between them) and the frames of the compression movies (`forcenet.plotting.movies`).

Each network is the analysis' own (`forcenet.network.snapshot_network`, with the study's rattler rule), so a drawn
edge is one whose topology the other figures measure. Preparations return a `FigureData` whose table has one row
per edge (end points [d_ave], or an imported snapshot's length unit; F/⟨F⟩) and, for P1 Fig. 1, one per
particle; the drawings read nothing else.
"""
from __future__ import annotations

from typing import Mapping, Sequence

import numpy as np
import pandas as pd
import xarray as xr

from forcenet.boxes import box_corners, image_shifts
from forcenet.datasets.io import optional_attr
from forcenet.datasets.schema import STATE_VALUE_ATTR
from forcenet.datasets.snapshot import box_tilt, periodic_vectors
from forcenet.network import snapshot_network
from forcenet.plotting import figure_data as cols
from forcenet.plotting.figure_data import FigureData, concat
from forcenet.plotting.style import (FORCE_KIND_WORDS, LABELS, apply_style, is_sequence, panel_figure,
                                     state_axis_label, system_label, system_title)
from forcenet.report import p2 as report
from forcenet.report.p1 import system_order
from forcenet.report.p2_distances import contact_forces, edge_differences

import matplotlib.pyplot as plt  # noqa: E402  (style sets the Agg backend first)
from matplotlib.collections import EllipseCollection, LineCollection  # noqa: E402
from matplotlib.colors import Normalize  # noqa: E402
from matplotlib.figure import Figure  # noqa: E402
from matplotlib.patches import Polygon  # noqa: E402

FORCE_CMAP = "viridis"
POSITION_LABELS = (r"$x$ [$d_{ave}$]", r"$y$ [$d_{ave}$]", r"$z$ [$d_{ave}$]")
NETWORK_MAX_LINE_WIDTH = 3.0  # P1 Fig. 1: line width of the strongest contacts (0.3 + this at the colour-scale top)
#: P1 Fig. 1 columns: contact end points and particle centres [d_ave]
END_I = tuple(f"{a}_i [d_ave]" for a in "xyz")
END_J = tuple(f"{a}_j [d_ave]" for a in "xyz")
CENTRE = tuple(f"{a} [d_ave]" for a in "xyz")
RADIUS = "radius [d_ave]"
#: P2 Fig. 1 edge columns: end points [d_ave]
EDGE_ENDS = ("x_i [d_ave]", "y_i [d_ave]", "x_j [d_ave]", "y_j [d_ave]")
#: the engine's length unit; an imported snapshot's positions carry the source's (``systems.<name>.units.length``)
REDUCED_LENGTH = "d_ave"
#: the column naming each row's length unit where a figure draws snapshots of different units (its position
#: columns then say "[length_unit]")
LENGTH_UNIT_COLUMN = "length_unit"


def length_unit(ds: xr.Dataset) -> str:
    """The length unit of a snapshot: its positions' `units` (d_ave for our engine's, the source's for an import)."""
    return str(ds["position"].attrs.get("units", REDUCED_LENGTH))


def length_columns(unit: str) -> dict[str, tuple[str, ...]]:
    """The position columns of a network table whose lengths are in `unit`: end points, centres, radius and P2 Fig.
    1's edge ends (`END_I`, `END_J`, `CENTRE`, `RADIUS`, `EDGE_ENDS` for d_ave)."""
    return {"end_i": tuple(f"{a}_i [{unit}]" for a in "xyz"), "end_j": tuple(f"{a}_j [{unit}]" for a in "xyz"),
            "centre": tuple(f"{a} [{unit}]" for a in "xyz"), "radius": (f"radius [{unit}]",),
            "edge_ends": (f"x_i [{unit}]", f"y_i [{unit}]", f"x_j [{unit}]", f"y_j [{unit}]")}


def position_labels(unit: str) -> tuple[str, str, str]:
    """Axis labels of positions in `unit` (`POSITION_LABELS` for d_ave)."""
    if unit == REDUCED_LENGTH:
        return POSITION_LABELS
    return tuple(rf"${a}$ [{unit}]" for a in "xyz")


def _rows_unit(rows: pd.DataFrame) -> tuple[str, str]:
    """(the unit in `rows`' column names, the unit of its lengths) of a network table: the column names' unit is the
    rows' own, or "length_unit" where the rows name theirs in `LENGTH_UNIT_COLUMN`."""
    radius = next((c for c in rows.columns if c.startswith(("radius [", "x_i ["))), RADIUS)
    column_unit = radius[radius.index("[") + 1:-1]
    if column_unit == LENGTH_UNIT_COLUMN and LENGTH_UNIT_COLUMN in rows and len(rows):
        return column_unit, str(rows[LENGTH_UNIT_COLUMN].iloc[0])
    return column_unit, column_unit


# --- P1 Fig. 1: one snapshot per system ---------------------------------------------------------------------------
def prepare_p1_fig01_networks(snapshots: Mapping[str, xr.Dataset], *, rattler_rule: bool | str) -> FigureData:
    """P1 Fig. 1: the edges of the total-force network of one snapshot per system with F/⟨F⟩ and their end points,
    and every particle (drawn as disks in 2D, rattlers included).

    The network is the analysis' (`forcenet.network.snapshot_network`): contacts that carry no force are no edges,
    and the rattlers removed by `rattler_rule` (the P1 study's, ``studies.p1.remove_rattlers``) take their edges
    with them, so the figure draws the edges whose topology the other figures measure."""
    blocks, boxes = [], {}
    units = {name: length_unit(ds) for name, ds in snapshots.items()}
    # one unit in the column names where every snapshot has it (d_ave for our engine's); else each row names its own
    shared = len(set(units.values())) == 1
    names = length_columns(next(iter(units.values())) if shared else LENGTH_UNIT_COLUMN)
    end_i_, end_j_, centre_, radius_ = names["end_i"], names["end_j"], names["centre"], names["radius"][0]
    for panel, name in enumerate(system_order(snapshots)):
        ds = snapshots[name]
        # walls are not drawn, and the analysis does not count their contacts: its edges either way
        network = snapshot_network(ds, "total", rattler_rule=rattler_rule, wall_contacts="ignored")
        dim = network.dim
        i, j = network.edge_i, network.edge_j
        position = network.position
        end_j = position[j] + image_shifts(position, i, j, periodic_vectors(ds))  # across a periodic face: out of it
        # the state on the run's axis: ρ, or a sequence state's coordinate (the CSV names that column after it)
        value = optional_attr(ds, STATE_VALUE_ATTR)
        state = float(value) if value is not None else float(ds["rho"]) if "rho" in ds else float("nan")
        common = {cols.PANEL: panel, cols.SYSTEM: name, "dimension": dim, cols.RHO: state,
                  **({} if shared else {LENGTH_UNIT_COLUMN: units[name]})}
        contacts = pd.DataFrame({**common, "element": "contact", "i": i, "j": j, cols.FORCE: network.force})
        particles = pd.DataFrame({**common, "element": "particle", "i": np.arange(len(position)),
                                  radius_: ds["radius"].values})
        for k in range(dim):
            contacts[end_i_[k]] = position[i, k]
            contacts[end_j_[k]] = end_j[:, k]
            particles[centre_[k]] = position[:, k]
        blocks += [contacts, particles]
        boxes[panel] = (ds["box_lo"].values, ds["box_hi"].values, box_tilt(ds))
    return FigureData(concat(blocks), {"box": boxes})


def draw_p1_fig01_networks(data: FigureData) -> Figure:
    """Edges coloured (and thickened) by F/⟨F⟩; 2D as lines over the disks, 3D as lines in a 3D box; one colour
    scale for all panels, up to the 99 % quantile of F/⟨F⟩."""
    panels = sorted(data.table[cols.PANEL].unique())
    dims = [int(data.panel(p)["dimension"].iloc[0]) for p in panels]
    fig, axes = panel_figure(len(panels), size=(4.6, 4.2), projections=["3d" if d == 3 else None for d in dims])
    norm = network_color_scale(data.table)
    for ax, panel in zip(axes, panels):
        draw_network_panel(ax, data.panel(panel), data.layout["box"][panel], norm)
    fig.colorbar(plt.cm.ScalarMappable(norm=norm, cmap=FORCE_CMAP), ax=axes, label=LABELS["force"], shrink=0.8)
    return fig


def network_color_scale(table: pd.DataFrame) -> Normalize:
    """F/⟨F⟩ colour scale of network drawings: 0 to the 99 % quantile of the table's contacts."""
    everything = table.loc[table["element"] == "contact", cols.FORCE].to_numpy()
    return Normalize(0.0, float(np.quantile(everything, 0.99)) if everything.size else 1.0)


def draw_network_panel(ax, rows: pd.DataFrame, box, norm: Normalize) -> None:
    """One snapshot's network (rows of `prepare_p1_fig01_networks`) in `ax` (a 3D axes for a 3D snapshot)."""
    dim = int(rows["dimension"].iloc[0])
    column_unit, unit = _rows_unit(rows)
    names, labels = length_columns(column_unit), position_labels(unit)
    contacts, particles = rows[rows["element"] == "contact"], rows[rows["element"] == "particle"]
    relative = contacts[cols.FORCE].to_numpy(float)
    segments = np.stack([contacts[list(names["end_i"][:dim])].to_numpy(float),
                         contacts[list(names["end_j"][:dim])].to_numpy(float)],
                        axis=1).reshape(-1, 2, dim)
    widths = 0.3 + NETWORK_MAX_LINE_WIDTH * np.clip(relative / max(norm.vmax, 1e-12), 0, 1)
    corners = box_corners(*box)  # a triclinic box's parallelogram (parallelepiped) within the axes' limits
    lo, hi = corners.min(axis=0), corners.max(axis=0)
    if dim == 3:
        from mpl_toolkits.mplot3d.art3d import Line3DCollection

        if len(segments):  # mplot3d cannot draw an empty collection
            lines = Line3DCollection(segments, cmap=FORCE_CMAP, norm=norm, linewidths=widths)
            lines.set_array(relative)
            ax.add_collection3d(lines)
        ax.set_zlim(lo[2], hi[2])
        ax.set_zlabel(labels[2])
    else:
        diameter = 2 * particles[names["radius"][0]].to_numpy()
        disks = EllipseCollection(diameter, diameter, 0, units="xy",
                                  offsets=particles[list(names["centre"][:2])].to_numpy(),
                                  offset_transform=ax.transData, facecolors="none", edgecolors="0.75", linewidths=0.4)
        ax.add_collection(disks)
        lines = LineCollection(segments, cmap=FORCE_CMAP, norm=norm, linewidths=widths)
        lines.set_array(relative)
        ax.add_collection(lines)
        if box[2] is not None:  # a triclinic box: its periodic cell, which the axes' rectangle does not show
            ax.add_patch(Polygon(corners[[0, 2, 3, 1]], closed=True, fill=False, color="0.4", lw=0.8))
        ax.set_aspect("equal")
    ax.set_xlim(lo[0], hi[0])
    ax.set_ylim(lo[1], hi[1])
    ax.set_xlabel(labels[0])
    ax.set_ylabel(labels[1])
    name = rows[cols.SYSTEM].iloc[0]
    state = float(rows[cols.RHO].iloc[0])
    system_title(ax, name, f", {state_axis_label(name)} = {state:.4g}" if is_sequence(name) else
                 rf", $\rho$ = {state:.3f}")


# --- P2 Fig. 1: three nearby snapshots and |ΔF| between them ------------------------------------------------------
def prepare_p2_fig01_snapshots_differences(snapshots: Sequence[xr.Dataset], *, rattler_rule: bool | str,
                                           kind: str = "normal", system: str = report.FRICTIONAL) -> FigureData:
    """Edges of panels (a–c): the force network of three nearby snapshots, F/⟨F⟩ of that snapshot; (d–e):
    |F_b − F_a| and |F_c − F_a| on the contacts of either snapshot (a contact missing in one has F = 0 there),
    at snapshot a's particle positions. Panels 0–4 are a–e."""
    if len(snapshots) != 3:
        raise ValueError(f"Fig. 1 needs three snapshots a, b, c; got {len(snapshots)}")
    # each network is built once: panels (a–c) draw it, (d–e) take differences of the same edge values
    networks = [contact_forces(s, kind, remove_rattlers=rattler_rule) for s in snapshots]
    n_particles = max(int(s.sizes["particle"]) for s in snapshots)
    diffs = [edge_differences(networks[0], networks[k], n_particles) for k in (1, 2)]
    unit = length_unit(snapshots[0])  # three states of one run: one unit
    ends = length_columns(unit)["edge_ends"]
    blocks = []
    for panel, (snap, edges) in enumerate(zip([*snapshots, snapshots[0], snapshots[0]], [*networks, *diffs])):
        position = snap["position"].values
        end_j = position[edges.j] + image_shifts(position, edges.i, edges.j, periodic_vectors(snap))
        quantity = "F/<F>" if panel < 3 else "|F_%s - F_a|/<F>" % "bc"[panel - 3]
        blocks.append(pd.DataFrame({cols.PANEL: panel, cols.SYSTEM: system, "force_kind": kind,
                                    cols.RHO: float(snap["rho"]), cols.QUANTITY: quantity, "i": edges.i, "j": edges.j,
                                    ends[0]: position[edges.i, 0], ends[1]: position[edges.i, 1],
                                    ends[2]: end_j[:, 0], ends[3]: end_j[:, 1],
                                    cols.VALUE: edges.force}))
    return FigureData(concat(blocks), {
        "box": [(s["box_lo"].values[:2], s["box_hi"].values[:2], box_tilt(s)) for s in snapshots],
        "states": [(float(s["rho"]), float(s["Z"])) for s in snapshots], "kind": kind, "system": system,
        "realization": snapshots[0].attrs["realization"], "length_unit": unit})


def draw_p2_fig01_snapshots_differences(data: FigureData) -> Figure:
    apply_style()
    kind, system = data.layout["kind"], data.layout["system"]
    fig, axes = plt.subplots(2, 3, figsize=(13, 8.6), constrained_layout=True)
    networks = [data.panel(p) for p in range(5)]
    vmax = max(float(n[cols.VALUE].max()) if len(n) else 1.0 for n in networks[:3])
    boxes = data.layout["box"]
    for ax, rows, box, (rho, _), letter in zip(axes[0], networks[:3], boxes, data.layout["states"], "abc"):
        lines = _draw_edges(ax, rows, "viridis", 0.0, vmax)
        _frame(ax, box, f"({letter}) ρ = {rho:.4f}", data.layout.get("length_unit", REDUCED_LENGTH))
    fig.colorbar(lines, ax=axes[0].tolist(), shrink=0.8, label=rf"{kind} force $F/\langle F\rangle$")
    dmax = max([float(n[cols.VALUE].max()) for n in networks[3:] if len(n)] + [1e-12])
    for ax, rows, letter, pair in zip(axes[1], networks[3:], "de", ("b", "c")):
        lines = _draw_edges(ax, rows, "inferno_r", 0.0, dmax)
        _frame(ax, boxes[0], rf"({letter}) $|F_{pair} - F_a|$", data.layout.get("length_unit", REDUCED_LENGTH))
    side = axes[1, 2]
    side.axis("off")
    fig.colorbar(lines, cax=side.inset_axes([0.0, 0.1, 0.06, 0.8]),
                 label=r"$|\Delta F|/\langle F\rangle$ (each snapshot normalised by its own mean)")
    side.text(0.45, 0.5, f"{system_label(system)}, realization {data.layout.get('realization', '?')}\n"
              f"{FORCE_KIND_WORDS.get(kind, kind)}\n"
              + "\n".join(f"{letter}: ρ = {rho:.4f}, Z = {z:.2f}"
                          for letter, (rho, z) in zip("abc", data.layout["states"])),
              transform=side.transAxes, va="center")
    fig.suptitle("Force networks of three nearby states and their differences (P2 Fig. 1)")
    return fig


def _draw_edges(ax, rows: pd.DataFrame, cmap, vmin, vmax):
    values = rows[cols.VALUE].to_numpy(float)
    ends = rows[list(length_columns(_rows_unit(rows)[0])["edge_ends"])].to_numpy(float)
    segments = ends.reshape(-1, 2, 2)
    order = np.argsort(values)  # strongest on top
    lines = LineCollection(segments[order], cmap=cmap, linewidths=1.4)
    lines.set_array(values[order])
    lines.set_clim(vmin, vmax if vmax > vmin else vmin + 1.0)
    ax.add_collection(lines)
    return lines


def _frame(ax, box, title: str, unit: str = REDUCED_LENGTH) -> None:
    corners = box_corners(*box)
    ax.add_patch(Polygon(corners[[0, 2, 3, 1]], closed=True, fill=False, color="0.4", lw=0.8))  # round the box
    lo, hi = corners.min(axis=0), corners.max(axis=0)
    pad = 0.03 * float(np.max(hi - lo))
    ax.set_xlim(lo[0] - pad, hi[0] + pad)
    ax.set_ylim(lo[1] - pad, hi[1] + pad)
    ax.set_aspect("equal")
    ax.set_xlabel(r"$x$ $[d_{ave}]$" if unit == REDUCED_LENGTH else rf"$x$ [{unit}]")
    ax.set_ylabel(r"$y$ $[d_{ave}]$" if unit == REDUCED_LENGTH else rf"$y$ [{unit}]")
    ax.set_title(title)
