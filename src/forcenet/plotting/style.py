"""One look for every figure: a colour per system (the same in every figure), labels with symbols and units."""
from __future__ import annotations

import zlib
from typing import Sequence

import matplotlib

matplotlib.use("Agg")  # figures are files; no display on compute nodes

import matplotlib.pyplot as plt  # noqa: E402
import seaborn as sns  # noqa: E402

SYSTEM_COLORS = {
    "2d_hertz": "#1b9e77",
    "2d_linear": "#d95f02",
    "3d_hertz": "#7570b3",
    "2d_poly_mu05": "#e7298a",
    "2d_poly_mu0": "#66a61e",
}
SYSTEM_LABELS = {
    "2d_hertz": "2D Hertzian",
    "2d_linear": "2D linear",
    "3d_hertz": "3D Hertzian",
    "2d_poly_mu05": "2D polydisperse, μ = 0.5",
    "2d_poly_mu0": "2D polydisperse, μ = 0",
}
FALLBACK_COLORS = sns.color_palette("colorblind", 10)

LABELS = {
    "rho": r"packing fraction $\rho$",
    "threshold": r"force threshold $F_{th}/\langle F\rangle$",
    "force": r"$F/\langle F\rangle$",
    "pdf": r"PDF$(F/\langle F\rangle)$",
    "Z": r"coordination number $Z$",
    "birth": r"birth $b/\langle F\rangle$",
    "death": r"death $d/\langle F\rangle$",
}
#: a force kind in words (figure titles)
FORCE_KIND_WORDS = {"total": "total forces", "normal": "normal forces", "tangential": "tangential forces"}


def system_color(name: str):
    if name in SYSTEM_COLORS:
        return SYSTEM_COLORS[name]
    return FALLBACK_COLORS[zlib.crc32(name.encode()) % len(FALLBACK_COLORS)]  # stable across runs


def system_label(name: str) -> str:
    return SYSTEM_LABELS.get(name, name)


def panel_figure(n_panels: int, ncols: int = 3, size=(4.2, 3.3), projections: Sequence[str | None] | None = None):
    """A figure of `n_panels` axes, `ncols` a row, each `size` inches (width, height); `projections` per panel
    (None, or "3d"). Returns (figure, [axes, …])."""
    import numpy as np

    apply_style()
    ncols = max(1, min(ncols, n_panels))
    nrows = int(np.ceil(n_panels / ncols))
    fig = plt.figure(figsize=(size[0] * ncols, size[1] * nrows), layout="constrained")
    projections = projections or [None] * n_panels
    axes = [fig.add_subplot(nrows, ncols, k + 1, projection=projections[k]) for k in range(n_panels)]
    return fig, axes


def system_title(ax, name: str, extra: str = "") -> None:
    """The panel title: the system's label in its colour, then `extra`."""
    ax.set_title(system_label(name) + extra, color=system_color(name))


def apply_style() -> None:
    sns.set_theme(context="paper", style="ticks", font_scale=1.1)
    plt.rcParams.update({"figure.dpi": 110, "savefig.dpi": 200, "savefig.bbox": "tight"})


def save_figure(figure, pdf_path, png_path) -> None:
    """Write a figure as PDF and PNG and close it."""
    from pathlib import Path

    for path in (pdf_path, png_path):
        Path(path).parent.mkdir(parents=True, exist_ok=True)
        figure.savefig(path)
    plt.close(figure)
