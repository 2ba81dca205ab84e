"""P2 Tables I–III (§III D): distances between three nearby states a, b, c, whole box and per quadrant.

- `table_state_candidates`, `chosen_states` — the states a, b, c of Tables I–III and Figs 1, 3 (`TABLE_STATE_RULES`):
  the first three consecutive samples at or above ``table_rho`` whose mean Z ≥ d + 1 (`jammed_table_states`; P2's
  states near ρ = 0.79 are jammed), or the three around it (P2: ρ ≈ 0.79; `forcenet.systems.select_table_snapshots`),
  of the realization whose Z and ⟨F_n⟩ change least over them (P2 Fig. 1: "almost identical";
  `TABLE_STATE_CRITERION`).
- `p2_tables` — the distances (a,b) and (a,c) of the normal-force diagrams over the whole box (Table I) and per
  quadrant of the box (Tables II, III), β0 and β1 × d_B, d_W1, d_W2, as P2 prints them.
- `write_table`, `write_p2_tables`, `read_table` — ``results/tables/p2_table{1,2,3}.{csv,md}`` with P2's printed
  values (`P2_TABLE_VALUES`) and ours / P2's beside them.
"""
from __future__ import annotations

import math
import os
from pathlib import Path
from typing import Mapping, Sequence

import numpy as np
import pandas as pd
import xarray as xr

from forcenet.datasets.schema import FORCE_KINDS
from forcenet.report.p2 import (METRICS, P2_HOMOLOGY_DIMS, QUADRANTS, TABLE_PAIRS, TABLE_RHO_KEYS, format_number,
                                pretty_column, table_column)
from forcenet.report.claims_table import table_attribute
from forcenet.report.p2_distances import network_diagrams, pair_distances, p2_network, quadrant_diagrams


def p2_tables(snapshots: Sequence[xr.Dataset], *, kind: str = "normal", remove_rattlers: bool | str = True,
              essential_convention: str = "minus_one") -> dict[str, pd.DataFrame]:
    """P2 Tables I–III from three nearby snapshots (a, b, c) of one realization, in increasing ρ.

    Table I: distances (PD^a, PD^b) and (PD^a, PD^c) over the whole box. Tables II and III: the same for each
    quarter of the box (bottom left, bottom right, top right, top left, as P2), the quarters taken at each
    snapshot's own walls. Columns: β0 and β1 × d_B, d_W1, d_W2 (``beta0_d_B`` …), normal forces as P2.

    Returns ``{"table1": …, "table2": …, "table3": …}``; each DataFrame's ``attrs`` holds the caption and ρ_a,
    ρ_b, ρ_c.
    """
    if len(snapshots) != 3:
        raise ValueError(f"Tables I-III need three snapshots a, b, c; got {len(snapshots)}")
    rho = [float(s["rho"]) for s in snapshots]
    if not rho[0] < rho[1] < rho[2]:
        raise ValueError(f"snapshots a, b, c must be in increasing rho, got {rho}")
    networks = [p2_network(s, kind, remove_rattlers) for s in snapshots]
    whole = [network_diagrams(n) for n in networks]
    parts = [quadrant_diagrams(n, s) for n, s in zip(networks, snapshots)]

    def row(pd_x, pd_y) -> dict[str, float]:
        """One table row: every `table_column` between the diagrams pd_x and pd_y [⟨F⟩]."""
        out = {}
        for h in P2_HOMOLOGY_DIMS:
            d = pair_distances(pd_x, pd_y, h, essential_convention)
            out.update({table_column(h, m): d[m] for m in METRICS})
        return out

    table1 = pd.DataFrame([row(whole[0], whole[1]), row(whole[0], whole[2])],
                          index=pd.Index(TABLE_PAIRS, name="pair"))
    quadrants = pd.Index(QUADRANTS, name="quadrant")
    table2 = pd.DataFrame([row(parts[0][q], parts[1][q]) for q in QUADRANTS], index=quadrants)
    table3 = pd.DataFrame([row(parts[0][q], parts[2][q]) for q in QUADRANTS], index=quadrants)
    meta = {**dict(zip(TABLE_RHO_KEYS, rho)), "force_kind": kind, "essential_convention": essential_convention,
            "rattler_rule": networks[0].rattler_rule, "realization": int(snapshots[0].attrs["realization"])}
    captions = {
        "table1": "Table I: distances between the persistence diagrams of the force networks of snapshots a, b, c",
        "table2": "Table II: distances (PD^a, PD^b) between corresponding quarters of the box",
        "table3": "Table III: distances (PD^a, PD^c) between corresponding quarters of the box",
    }
    tables = {"table1": table1, "table2": table2, "table3": table3}
    for name, table in tables.items():
        table.attrs.update(meta, caption=captions[name])
    return tables


# --- which realization gives the states a, b, c ---------------------------------------------------------------
TABLE_STATE_CRITERION = (
    "P2 Fig. 1: the three states look alike and 'both the average contact number Z and the average force are almost "
    "identical'. Among the realizations, the one whose states a, b, c (consecutive samples around table_rho) change "
    "Z and the mean normal force <F_n> least: score = the larger of max(|Z_x - Z_a|)/Z_a and "
    "max(|<F_n>_x - <F_n>_a|)/<F_n>_a over x = b, c; the lowest score is chosen, the lowest index on ties")
TABLE_STATES = ("a", "b", "c")


def mean_force_column(state: str, unit: str) -> str:
    """The column of state `state`'s (a, b or c) mean normal force ⟨F_n⟩ in `unit`, named with it as the project's
    CSV columns are (``mean_normal_force_a [m_mean d_ave tau_c-2]`` for a DEM run, ``… [N]`` for an import whose
    ``units:`` block says newtons)."""
    return f"mean_normal_force_{state} [{unit}]"


def table_state_columns(force_unit: str) -> tuple[str, ...]:
    """The columns of `table_state_candidates`' table whose mean forces are in `force_unit`."""
    return ("realization", *TABLE_RHO_KEYS, *(f"Z_{x}" for x in TABLE_STATES),
            *(mean_force_column(x, force_unit) for x in TABLE_STATES), "Z_change", "force_change", "score", "chosen")


def state_mean_force(row: Mapping[str, float] | pd.Series, state: str) -> float:
    """State `state`'s mean normal force in a row of the table-state candidates (the p2_table_states CSV), in the
    unit its column names."""
    (column,) = [c for c in (row.index if isinstance(row, pd.Series) else row)
                 if str(c).startswith(f"mean_normal_force_{state} [")]
    return float(row[column])


def mean_force_unit(analyses: Sequence[xr.Dataset]) -> str:
    """The one unit of the analyses' mean forces ⟨F⟩ (their `units`: the schema's reduced unit for a DEM run, the
    source's force unit for an import)."""
    units = sorted({str(ds["mean_force"].attrs["units"]) for ds in analyses})
    if len(units) != 1:
        raise ValueError(f"the analyses' mean forces are in {len(units)} units ({', '.join(units)}), need one")
    return units[0]


#: which states a, b, c Tables I–III and Figs 1, 3 use (config key ``studies.p2.table_states``, issue 25):
#: "jammed" — the first three consecutive samples at or above table_rho whose mean Z ≥ d + 1 (P2's states near
#: ρ = 0.79 are jammed: Z and ⟨F⟩ "almost identical" between them; ours at 0.79 are not), the table's own;
#: "literal" — the three consecutive samples around table_rho (`forcenet.systems.select_table_snapshots`).
TABLE_STATE_RULES = ("jammed", "literal")


def jammed_table_states(rho: Sequence[float], z: Sequence[float], table_rho: float,
                        dimension: int = 2) -> tuple[int, int, int] | None:
    """Indices (into `rho`, sorted ascending) of the first three consecutive samples at or above `table_rho` whose
    mean contact number Z is ≥ d + 1; None when no such three exist."""
    rho, z = np.asarray(rho, dtype=float), np.asarray(z, dtype=float)
    if np.any(np.diff(rho) <= 0):
        raise ValueError("rho must be strictly increasing")
    for first in np.flatnonzero(rho >= table_rho - 1e-9):
        if first + 3 <= rho.size and np.mean(z[first:first + 3]) >= dimension + 1:
            return int(first), int(first) + 1, int(first) + 2
    return None


def table_state_candidates(analyses: Sequence[xr.Dataset], rule: str = "literal", table_rho: float = 0.79,
                           dimension: int = 2) -> pd.DataFrame:
    """The candidate states a, b, c of Tables I–III and Figs 1, 3: one row per realization (`TABLE_STATE_COLUMNS`).

    Parameters
    ----------
    analyses : per-snapshot analysis files of every realization (told apart by their ``realization``
        attribute): Z and the mean normal force ⟨F_n⟩ (in its `units`) are read. With `rule` "literal" the three
        states a, b, c of each realization; with "jammed" its states at and above `table_rho`, among which
        `jammed_table_states` picks a, b, c (a realization with no such three is no candidate).

    Returns
    -------
    DataFrame (`table_state_columns`) with ρ, Z, ⟨F_n⟩ of a, b, c (its columns name the analyses' force unit,
    `mean_force_column`), the relative changes, the score and ``chosen`` (one True row) by
    `TABLE_STATE_CRITERION`; ``attrs["rule"]`` the rule.
    """
    if rule not in TABLE_STATE_RULES:
        raise ValueError(f"rule must be one of {TABLE_STATE_RULES}, got {rule!r}")
    by_realization: dict[int, list[xr.Dataset]] = {}
    for ds in analyses:
        by_realization.setdefault(int(ds.attrs["realization"]), []).append(ds)
    normal = FORCE_KINDS.index("normal")
    unit = mean_force_unit(analyses)
    rows = []
    for realization, states in sorted(by_realization.items()):
        states = sorted(states, key=lambda ds: float(ds["rho"]))
        if rule == "jammed":
            picked = jammed_table_states([float(ds["rho"]) for ds in states], [float(ds["Z"]) for ds in states],
                                         table_rho, dimension)
            if picked is None:
                continue
            states = [states[i] for i in picked]
        elif len(states) != 3:
            raise ValueError(f"realization {realization}: {len(states)} states, need a, b, c")
        z = [float(ds["Z"]) for ds in states]
        force = [float(ds["mean_force"].values[normal]) for ds in states]
        z_change = max(abs(z[1] - z[0]), abs(z[2] - z[0])) / z[0] if z[0] > 0 else math.inf
        force_change = max(abs(force[1] - force[0]), abs(force[2] - force[0])) / force[0] if force[0] > 0 else math.inf
        rows.append({"realization": realization, **{k: float(ds["rho"]) for k, ds in zip(TABLE_RHO_KEYS, states)},
                     **{f"Z_{x}": v for x, v in zip(TABLE_STATES, z)},
                     **{mean_force_column(x, unit): v for x, v in zip(TABLE_STATES, force)}, "Z_change": z_change,
                     "force_change": force_change, "score": max(z_change, force_change)})
    if not rows:
        raise ValueError(f"no candidate states a, b, c ({rule} rule"
                         + (f": no three consecutive samples at rho >= {table_rho} with mean Z >= {dimension + 1}"
                            if rule == "jammed" else "") + ")")
    table = pd.DataFrame(rows, columns=list(table_state_columns(unit)[:-1]))
    table["chosen"] = False
    table.loc[table["score"].idxmin(), "chosen"] = True  # idxmin: first (lowest realization) on ties
    table.attrs["criterion"] = TABLE_STATE_CRITERION
    table.attrs["rule"] = rule
    return table


def chosen_states(datasets: Sequence[xr.Dataset], candidates: pd.DataFrame) -> list[xr.Dataset]:
    """The datasets (snapshots or analyses) of the chosen realization of `candidates`, in increasing ρ."""
    chosen = candidates[candidates["chosen"].astype(bool)]
    if len(chosen) != 1:
        raise ValueError(f"{len(chosen)} chosen realizations in the table-state candidates, need one")
    realization = int(chosen["realization"].iloc[0])
    expected = chosen[list(TABLE_RHO_KEYS)].to_numpy(dtype=float)[0]
    picked = sorted((ds for ds in datasets if int(ds.attrs["realization"]) == realization),
                    key=lambda ds: float(ds["rho"]))
    if len(picked) > len(expected):  # candidates beyond a, b, c (the jammed rule reads every state >= table_rho)
        picked = [ds for ds in picked if np.isclose(float(ds["rho"]), expected, atol=1e-9).any()]
    if not picked:
        raise ValueError(f"no dataset of the chosen realization {realization}")
    expected = expected[:len(picked)]
    if not np.allclose([float(ds["rho"]) for ds in picked], expected, atol=1e-9):
        raise ValueError(f"realization {realization}: states at rho {[float(ds['rho']) for ds in picked]}, "
                         f"expected {expected.tolist()}")
    return picked


# P2's printed Tables I–III (μ = 0.5, normal forces, three nearby states at ρ ≈ 0.79), columns β0 then β1 ×
# d_B, d_W1, d_W2 as `table_column` orders them: printed beside ours, and the reference of the III.D claims
P2_TABLE_VALUES = {
    "table1": {"(a,b)": (0.089, 4.18, 0.50, 0.081, 3.8, 0.57),
               "(a,c)": (0.12, 14.0, 0.89, 0.15, 19.2, 0.99)},
    "table2": {"bottom left": (0.12, 3.6, 0.50, 0.16, 3.66, 0.95),
               "bottom right": (0.014, 0.40, 0.070, 0.014, 0.43, 0.037),
               "top right": (0.0046, 0.58, 0.35, 0.0055, 0.29, 0.024),
               "top left": (0.0076, 0.56, 0.31, 0.0045, 0.23, 0.019)},
    "table3": {"bottom left": (0.16, 4.1, 0.53, 0.13, 5.8, 0.59),
               "bottom right": (0.18, 5.2, 0.67, 0.14, 5.6, 0.50),
               "top right": (0.10, 5.1, 0.69, 0.12, 5.5, 0.51),
               "top left": (0.11, 4.3, 0.53, 0.087, 5.1, 0.87)},
}
P2_PREFIX, RATIO_PREFIX = "p2_", "ratio_"  # CSV columns of P2's value and of ours / P2's


def p2_reference_table(name: str) -> pd.DataFrame:
    """P2's printed Table I, II or III (``"table1"`` …) with our row labels and `table_column` columns."""
    rows = P2_TABLE_VALUES[name]
    columns = [table_column(h, m) for h in P2_HOMOLOGY_DIMS for m in METRICS]
    index = pd.Index(list(rows), name="pair" if name == "table1" else "quadrant")
    return pd.DataFrame([rows[label] for label in index], index=index, columns=columns)


def table_markdown(table: pd.DataFrame, digits: int = 3, reference: pd.DataFrame | None = None) -> str:
    """One table as Markdown, with P2's header (β0/β1 × d_B, d_W1, d_W2) and a caption with ρ_a, ρ_b, ρ_c.

    With `reference` (P2's printed table, `p2_reference_table`), each row of ours is followed by P2's row and
    the row of ratios ours / P2's."""
    header = [table.index.name or ""] + [pretty_column(c) for c in table.columns]
    lines = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    for label, values in table.iterrows():
        lines.append("| " + " | ".join([str(label)] + [format_number(v, digits) for v in values]) + " |")
        if reference is not None and label in reference.index:
            paper = reference.loc[label, table.columns]
            lines.append("| " + " | ".join([f"{label}, P2"] + [format_number(float(v), digits) for v in paper]) + " |")
            lines.append("| " + " | ".join([f"{label}, ours / P2"] + [format_number(float(v), 2) for v in
                                                                      values / paper]) + " |")
    caption, kind, realization, rule = (table_attribute(table, key, "p2_tables")
                                        for key in ("caption", "force_kind", "realization", "rattler_rule"))
    rhos = ", ".join(f"{key} = {table_attribute(table, key, 'p2_tables'):.4f}" for key in TABLE_RHO_KEYS)
    note = "; ".join(x for x in (rhos, f"realization {realization}" if realization >= 0 else "",
                                 f"{kind} forces" if kind else "", f"rattler rule '{rule}'" if rule else "",
                                 "distances in units of <F>") if x)
    return "\n".join(([f"{caption} ({note}).", ""] if caption else []) + lines) + "\n"


def write_table(table: pd.DataFrame, csv_path: str | os.PathLike, md_path: str | os.PathLike,
                reference: pd.DataFrame | None = None) -> None:
    """Write one of Tables I–III as CSV (machine-readable, flat columns: ours, then with `reference` P2's values
    ``p2_*`` and ours / P2's ``ratio_*``) and Markdown (P2's layout, P2's rows beside ours)."""
    for path in (csv_path, md_path):
        Path(path).parent.mkdir(parents=True, exist_ok=True)
    frame = table.copy()
    if reference is not None:
        paper = reference.loc[table.index, table.columns]
        frame = frame.join(paper.add_prefix(P2_PREFIX)).join((table / paper).add_prefix(RATIO_PREFIX))
    for key in TABLE_RHO_KEYS:
        if key in table.attrs:
            frame[key] = table.attrs[key]
    frame.to_csv(csv_path)
    Path(md_path).write_text(table_markdown(table, reference=reference))


def write_p2_tables(tables: Mapping[str, pd.DataFrame], directory: str | os.PathLike,
                    prefix: str = "p2_") -> list[Path]:
    """Write every table of `p2_tables` as ``{directory}/{prefix}{name}.csv`` and ``.md``
    (``results/tables/p2_table1.csv`` …); returns the paths written."""
    written = []
    for name, table in tables.items():
        csv_path, md_path = Path(directory) / f"{prefix}{name}.csv", Path(directory) / f"{prefix}{name}.md"
        write_table(table, csv_path, md_path, p2_reference_table(name) if name in P2_TABLE_VALUES else None)
        written += [csv_path, md_path]
    return written


def read_table(csv_path: str | os.PathLike) -> pd.DataFrame:
    """Read a table written by `write_table`: our values (ρ_a, ρ_b, ρ_c go back into ``attrs``; P2's values and
    the ratios are left out)."""
    frame = pd.read_csv(csv_path, index_col=0)
    frame = frame.drop(columns=[c for c in frame.columns if c.startswith((P2_PREFIX, RATIO_PREFIX))])
    for key in TABLE_RHO_KEYS:
        if key in frame:
            frame.attrs[key] = float(frame[key].iloc[0])
            frame = frame.drop(columns=key)
    return frame
