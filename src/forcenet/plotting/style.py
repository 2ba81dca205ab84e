"""One look for every figure: a colour per system (the same in every figure), labels with symbols and units."""
from __future__ import annotations

import colorsys
import zlib
from typing import Mapping, Sequence

import matplotlib

matplotlib.use("Agg")  # figures are files; no display on compute nodes

import matplotlib.pyplot as plt  # noqa: E402
import seaborn as sns  # noqa: E402

#: label and colour of each system a figure draws ({name: {"label": …, "colour": …}}), from the system catalog
#: (`config/systems.yaml`, the config's ``system_info``): `use_system_styles` fills it before a figure is drawn
SYSTEM_STYLES: dict[str, dict[str, str]] = {}
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


def use_system_styles(system_info: Mapping[str, Mapping[str, str]]) -> None:
    """Take the label and colour of each system from the config's ``system_info`` (the catalog's entries); a system
    without one (an imported system) is drawn under its name in a colour of its own."""
    SYSTEM_STYLES.update({name: {"label": info["label"], "colour": info["colour"]}
                          for name, info in system_info.items() if "label" in info and "colour" in info})


#: the state axis of each system a figure draws that is a sequence (an imported run ordered by strain, time, frame or
#: timestep at any ρ): {name: (coordinate, unit)}, filled by `use_state_axes` before a figure is drawn; a system not
#: in it is a compression, drawn against ρ
STATE_AXES: dict[str, tuple[str, str]] = {}
#: each sequence coordinate's axis label (its unit is added where it has one)
COORDINATE_LABELS = {"strain": r"strain $\gamma$", "time": r"time $t$", "frame": "frame", "timestep": "timestep"}


def use_state_axes(datasets) -> None:
    """Record the state axis of every sequence among `datasets` (stacked files, snapshots or analyses, whose global
    attributes name their system and coordinate, `forcenet.datasets.schema.STATE_COORDINATE_ATTR`)."""
    from forcenet.datasets import optional_attr
    from forcenet.datasets.schema import STATE_COORDINATE_ATTR, STATE_UNITS_ATTR

    for ds in datasets:
        coordinate = optional_attr(ds, STATE_COORDINATE_ATTR)  # absent: a compression
        if coordinate != "rho":
            STATE_AXES[str(ds.attrs["system"])] = (str(coordinate), str(optional_attr(ds, STATE_UNITS_ATTR)))


def is_sequence(name: str) -> bool:
    """Whether system `name` is drawn against a sequence's coordinate (`STATE_AXES`), not against ρ: no ρ_J, ρ_max
    or P2 levels quoted over ρ are marked on its axes."""
    return name in STATE_AXES


def state_axis_label(name: str | None = None) -> str:
    """The label of the axis of system `name`'s states: ρ, or its sequence coordinate with its unit."""
    if name not in STATE_AXES:
        return LABELS["rho"]
    coordinate, unit = STATE_AXES[name]
    label = COORDINATE_LABELS.get(coordinate, coordinate)
    return label if unit in ("1", "") else f"{label} [{unit}]"


def state_column(name: str | None = None) -> str:
    """The CSV column of system `name`'s state axis: ``rho``, or its coordinate's symbol with its unit."""
    from forcenet.importers.sequence import COORDINATE_SYMBOLS

    if name not in STATE_AXES:
        return "rho"
    coordinate, unit = STATE_AXES[name]
    symbol = COORDINATE_SYMBOLS.get(coordinate, coordinate)
    return symbol if unit in ("1", "") else f"{symbol} [{unit}]"


def system_color(name: str):
    if name in SYSTEM_STYLES:
        return SYSTEM_STYLES[name]["colour"]
    return FALLBACK_COLORS[zlib.crc32(name.encode()) % len(FALLBACK_COLORS)]  # stable across runs


def system_label(name: str) -> str:
    return SYSTEM_STYLES[name]["label"] if name in SYSTEM_STYLES else name


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


#: the lightness (HLS) of the lightest and darkest of a family of curves in one system's hue (`system_shades`), and
#: the most a title's text may have: a light colour (the fallback palette's yellow) stays readable on white
SHADE_LIGHTNESS = (0.78, 0.22)
TEXT_LIGHTNESS = 0.45


def _with_lightness(color, lightness: float) -> tuple[float, float, float]:
    hue, _, saturation = colorsys.rgb_to_hls(*matplotlib.colors.to_rgb(color))
    return colorsys.hls_to_rgb(hue, lightness, saturation)


def system_shades(name: str, n: int) -> list:
    """n shades of the system's hue, light to dark, for a family of curves (increasing F_th or ρ): the same span of
    lightness whatever the system's own colour, so a light colour gives curves as distinct as a dark one."""
    if n <= 1:
        return [system_color(name)] * n
    light, dark = SHADE_LIGHTNESS
    return [_with_lightness(system_color(name), light + (dark - light) * k / (n - 1)) for k in range(n)]


def system_title(ax, name: str, extra: str = "") -> None:
    """The panel title: the system's label in its colour (darkened where too light to read), then `extra`."""
    color = system_color(name)
    _, lightness, _ = colorsys.rgb_to_hls(*matplotlib.colors.to_rgb(color))
    ax.set_title(system_label(name) + extra,
                 color=_with_lightness(color, TEXT_LIGHTNESS) if lightness > TEXT_LIGHTNESS else color)


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
