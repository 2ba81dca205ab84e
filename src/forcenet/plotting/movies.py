"""Compression movies (MP4, H.264): a system's force network through its ρ grid, and a rotating view of its B0/N
surface over (ρ, F_th).

Frames are drawn by the P1 figure code from the same prepared data as Figs. 1 and 2 (`forcenet.plotting.networks`,
`forcenet.plotting.p1`), so a frame has that figure's axes, colour bar and ρ label, and its edges are those of the
analysed network (the study's rattler rule). The encoder is the ffmpeg binary shipped in the
``imageio-ffmpeg`` wheel (pinned in environment.txt): no system package is needed.
"""
from __future__ import annotations

import os
from pathlib import Path
from typing import Mapping, Sequence

import numpy as np
import xarray as xr

from forcenet.plotting import figure_data as cols
from forcenet.plotting import networks, p1
from forcenet.plotting.figure_data import concat
from forcenet.plotting.style import LABELS, apply_style, is_sequence, state_axis_label, system_color, system_label

import matplotlib.pyplot as plt  # noqa: E402  (style sets the Agg backend first)
from matplotlib.animation import FFMpegWriter  # noqa: E402

NETWORK_FPS = 2  # frames (ρ values) per second of the compression movie
SURFACE_FRAMES = 36  # one turn of the B0/N surface, 10° a frame ...
SURFACE_FPS = 12  # ... in 3 s
DPI = 100


def _writer(fps: int) -> FFMpegWriter:
    import imageio_ffmpeg

    plt.rcParams["animation.ffmpeg_path"] = imageio_ffmpeg.get_ffmpeg_exe()
    # yuv420p and even frame sizes (pad) so that every player shows the H.264 stream
    return FFMpegWriter(fps=fps, codec="libx264",
                        extra_args=["-pix_fmt", "yuv420p", "-vf", "pad=ceil(iw/2)*2:ceil(ih/2)*2"])


def _publish(partial: Path, output: Path) -> None:
    os.replace(partial, output)  # a movie only gets its name once it is complete


def network_movie(snapshots: Sequence[xr.Dataset], output: str | os.PathLike, *, rattler_rule: bool | str,
                  fps: int = NETWORK_FPS) -> int:
    """The force network of one compression run, one frame per snapshot (in the given order, increasing ρ),
    edges coloured by F/⟨F⟩ on one colour scale for the whole movie; rattlers removed by `rattler_rule` (the
    study's, as in the analysis). Returns the number of frames."""
    if not snapshots:
        raise ValueError("a network movie needs at least one snapshot")
    frames = [networks.prepare_p1_fig01_networks({str(s.attrs["system"]): s}, rattler_rule=rattler_rule)
              for s in snapshots]
    norm = networks.network_color_scale(concat([f.table for f in frames]))
    dimension = int(snapshots[0].sizes["spatial"])
    output = Path(output)
    output.parent.mkdir(parents=True, exist_ok=True)
    partial = output.with_name(output.stem + ".partial" + output.suffix)
    apply_style()
    fig = plt.figure(figsize=(5.6, 4.8))
    writer = _writer(fps)
    with writer.saving(fig, str(partial), DPI):
        for frame in frames:
            fig.clear()
            ax = fig.add_subplot(projection="3d" if dimension == 3 else None)
            networks.draw_network_panel(ax, frame.panel(0), frame.layout["box"][0], norm)
            fig.colorbar(plt.cm.ScalarMappable(norm=norm, cmap=networks.FORCE_CMAP), ax=ax, label=LABELS["force"],
                         shrink=0.8, pad=0.12 if dimension == 3 else 0.05)
            writer.grab_frame()
    plt.close(fig)
    _publish(partial, output)
    return len(frames)


def b0_surface_movie(measures: Mapping[str, xr.Dataset], system: str, output: str | os.PathLike, *,
                     frames: int = SURFACE_FRAMES, fps: int = SURFACE_FPS, force_unit: str | None = None) -> int:
    """One turn around the realization-mean B0/N surface of `system` over (ρ, F_th), the data of P1 Fig. 2 (ρ up
    to ρ_max). `measures` holds every P1 system (the F_max cut compares them, ⟨F⟩ in `force_unit`,
    ``analysis.p1_force_unit``; default P1's dyn). Returns the number of frames."""
    unit = {} if force_unit is None else {"force_unit": force_unit}
    table = p1.prepare_p1_fig02_betti0_surface(measures, **unit).table
    rows = table[table[cols.SYSTEM] == system]
    if rows.empty:
        raise ValueError(f"no B0/N data for system {system!r}")
    grid = rows.pivot(index=cols.THRESHOLD, columns=cols.RHO, values=cols.MEAN)
    rho, threshold = np.meshgrid(grid.columns.to_numpy(float), grid.index.to_numpy(float))
    values = grid.to_numpy(float)
    output = Path(output)
    output.parent.mkdir(parents=True, exist_ok=True)
    partial = output.with_name(output.stem + ".partial" + output.suffix)
    apply_style()
    fig = plt.figure(figsize=(6.4, 5.0))
    ax = fig.add_subplot(projection="3d")
    surface = ax.plot_surface(rho, threshold, values, cmap="magma", linewidth=0, antialiased=False)
    fig.colorbar(surface, ax=ax, label=p1.LABEL_B0, shrink=0.7, pad=0.1)
    ax.set_xlabel(state_axis_label(system))
    ax.set_ylabel(LABELS["threshold"])
    ax.set_zlabel(p1.LABEL_B0)
    ax.set_title(system_label(system) + (", realization mean" if is_sequence(system) else
                                         r", realization mean, $\rho \leq \rho_{max}$"), color=system_color(system))
    writer = _writer(fps)
    with writer.saving(fig, str(partial), DPI):
        for azimuth in np.linspace(-60.0, 300.0, frames, endpoint=False):
            ax.view_init(elev=28.0, azim=float(azimuth))
            writer.grab_frame()
    plt.close(fig)
    _publish(partial, output)
    return frames
