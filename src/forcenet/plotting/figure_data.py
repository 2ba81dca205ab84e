"""What a figure draws, as data: every figure is prepared (datasets → `FigureData`) and then drawn
(`FigureData` → matplotlib Figure), and the same `FigureData.table` is written beside the figure as its source
data (``results/figures/<figure>.csv``).

The table is tidy: one row per plotted value, columns named with symbol and unit (the names below), so a reader
can re-plot or compare without netCDF. Curves carry ``realization_mean`` with their band ``spread_low`` and
``spread_high``; a quantity drawn on the y axis or as colour is named in ``quantity``. What is not a data value
(panel titles, axis limits, the box of a snapshot) goes in `FigureData.layout`.

To add something to a figure (a marker, a reference level), add its values to the table in the preparation
step (a column on the rows it belongs to, or rows of their own with a distinct ``quantity``) and draw them from
there: the CSV then carries them too.
"""
from __future__ import annotations

import os
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd

# --- column names (symbol [unit]); forces are in units of the network's mean force ⟨F⟩ ---------------------------
SYSTEM = "system"
PANEL = "panel"  # index of the panel (axes) the row is drawn in, row-major from the top left
QUANTITY = "quantity"  # what `realization_mean` (or `value`) holds, e.g. "B0/N"
RHO = "rho"
THRESHOLD = "F_th [<F>]"
FORCE = "F/<F>"
MEAN = "realization_mean"
LOW = "spread_low"
HIGH = "spread_high"
VALUE = "value"
RHO_J = "rho_J"
BIRTH = "birth [<F>]"
DEATH = "death [<F>]"


@dataclass
class FigureData:
    """The plotted values of one figure.

    table: one row per plotted value (the CSV); layout: drawing context that is not a data value.
    """

    table: pd.DataFrame
    layout: dict[str, Any] = field(default_factory=dict)

    def panel(self, index: int) -> pd.DataFrame:
        """The rows drawn in panel `index`."""
        return self.table[self.table[PANEL] == index]


def curve_rows(x_name: str, x, mean, spread_low, spread_high, **columns) -> pd.DataFrame:
    """Rows of one curve with its band: the x column, realization_mean, spread_low/high, plus constant columns."""
    x, mean, low, high = (np.asarray(v, dtype=float) for v in (x, mean, spread_low, spread_high))
    frame = pd.DataFrame({x_name: x, MEAN: mean, LOW: low, HIGH: high})
    for key, value in reversed(list(columns.items())):
        frame.insert(0, key, value)
    return frame


def concat(frames) -> pd.DataFrame:
    """Stack row blocks. Every block's columns are kept, an empty block's too (a network without loaded contacts
    still has the contact columns), in the order they first appear; empty blocks add no rows."""
    frames = list(frames)
    if not frames:
        return pd.DataFrame()
    columns = list(dict.fromkeys(column for frame in frames for column in frame.columns))
    filled = [f for f in frames if len(f)]
    if not filled:
        return frames[0].iloc[0:0].reindex(columns=columns)
    return pd.concat(filled, ignore_index=True).reindex(columns=columns)


def write_csv(data: FigureData, path: str | os.PathLike) -> None:
    """Write the table (full float precision, no index) atomically: a partial file never looks complete."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    partial = path.with_name(path.name + ".partial")
    data.table.to_csv(partial, index=False, float_format="%.10g")
    os.replace(partial, path)
