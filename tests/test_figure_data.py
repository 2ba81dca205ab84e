"""Source data of the figures: for one figure of each kind, the CSV written beside it holds exactly the values the
figure draws (read back from the matplotlib artists), and a figure whose drawing departs from its table fails."""
from __future__ import annotations

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pandas as pd  # noqa: E402
import pytest  # noqa: E402
from matplotlib.collections import LineCollection, PathCollection, QuadMesh  # noqa: E402

from forcenet.plotting import figure_data as cols  # noqa: E402
from forcenet.plotting import networks, p1, p2  # noqa: E402
from forcenet.plotting.registry import draw_figure, figure_data  # noqa: E402
from forcenet.plotting.figure_data import FigureData, write_csv  # noqa: E402
from forcenet.report import p2 as report  # noqa: E402
from forcenet.report.p2_distances import force_differences  # noqa: E402
from forcenet.report.realizations import realization_mean  # noqa: E402
from test_plotting_p1 import make_diagrams, make_p1_figure, make_snapshot, p1_figure_data  # noqa: E402
from test_plotting_p2 import DIAGRAMS, analysis_factory  # noqa: E402
from test_report_p1 import make_p1_measures  # noqa: E402
from test_report_p2 import lattice_forces_and_quadrants, lattice_snapshot, p2_shaped, permuted  # noqa: E402


@pytest.fixture(scope="module")
def measures():
    return make_p1_measures()


@pytest.fixture(autouse=True)
def close_figures():
    yield
    plt.close("all")


def round_trip(data: FigureData, tmp_path) -> pd.DataFrame:
    """The CSV as a reader gets it."""
    path = tmp_path / "figure.csv"
    write_csv(data, path)
    assert not list(tmp_path.glob("*.partial"))
    return pd.read_csv(path)


def data_axes(fig) -> list:
    return [ax for ax in fig.axes if ax.get_label() != "<colorbar>"]


def band_limits(ax) -> list[tuple[float, float]]:
    """(lowest, highest) y of every fill_between band of a panel, in drawing order."""
    polys = [c for c in ax.collections if type(c).__name__ in ("PolyCollection", "FillBetweenPolyCollection")]
    out = []
    for poly in polys:
        y = np.concatenate([path.vertices[:, 1] for path in poly.get_paths()]) if poly.get_paths() else np.array([])
        out.append((float(np.min(y)), float(np.max(y))) if y.size else (np.nan, np.nan))
    return out


def assert_curves_match(fig, table: pd.DataFrame, x: str, family: str) -> None:
    """Every realization-mean curve of every panel is a CSV curve (x, realization_mean), and its band spans the
    CSV's spread_low … spread_high."""
    for panel, ax in enumerate(data_axes(fig)):
        rows = table[table[cols.PANEL] == panel]
        lines = [line for line in ax.get_lines() if line.get_gid() == p1.MEAN_GID]
        values = sorted(rows[family].unique())
        assert len(lines) == len(values) > 0
        for line, value, band in zip(lines, values, band_limits(ax)):
            curve = rows[rows[family] == value]
            np.testing.assert_allclose(np.asarray(line.get_xdata(), float), curve[x].to_numpy())
            np.testing.assert_allclose(np.asarray(line.get_ydata(), float), curve[cols.MEAN].to_numpy(), equal_nan=True)
            finite = np.isfinite(curve[cols.LOW])
            if finite.any():
                assert band == pytest.approx((curve[cols.LOW][finite].min(), curve[cols.HIGH][finite].max()))


def test_line_family_csv_holds_the_plotted_curves(measures, tmp_path):
    data = p1_figure_data("p1_fig04_cluster_size", measures)
    table = round_trip(data, tmp_path)
    assert {cols.SYSTEM, cols.RHO, cols.THRESHOLD, cols.QUANTITY, cols.MEAN, cols.LOW, cols.HIGH} <= set(table)
    assert set(table[cols.QUANTITY]) == {"<S>/N"}
    fig = make_p1_figure("p1_fig04_cluster_size", measures)
    assert_curves_match(fig, table, cols.RHO, cols.THRESHOLD)
    # the ρ_J line of each panel is the CSV's
    for panel, ax in enumerate(data_axes(fig)):
        marks = [line for line in ax.get_lines() if line.get_gid() == p1.RHO_J_GID]
        rho_j = table.loc[table[cols.PANEL] == panel, cols.RHO_J].unique()
        assert len(marks) == 1 and marks[0].get_xdata()[0] == pytest.approx(rho_j[0])


def test_a_changed_table_is_what_gets_drawn_and_a_mismatch_is_caught(measures, tmp_path):
    """The drawing reads only the table: alter one value and the figure shows it, and the comparison above fails
    against the unaltered CSV (so it can fail)."""
    diagrams = {name: make_diagrams(ds) for name, ds in measures.items()}
    data = p1_figure_data("p1_fig12_total_persistence", measures, diagrams)
    original = round_trip(data, tmp_path)
    changed = FigureData(data.table.copy(), data.layout)
    changed.table.loc[0, cols.MEAN] += 1.0
    fig = draw_figure("p1_fig12_total_persistence", changed)
    assert_curves_match(fig, changed.table, cols.RHO, p1.HOMOLOGY_K)
    with pytest.raises(AssertionError):
        assert_curves_match(fig, original, cols.RHO, p1.HOMOLOGY_K)


def test_force_pdf_csv_holds_one_curve_per_rho(measures, tmp_path):
    table = round_trip(p1_figure_data("p1_fig03_force_pdf", measures), tmp_path)
    assert_curves_match(make_p1_figure("p1_fig03_force_pdf", measures), table, cols.FORCE, cols.RHO)


def test_heat_map_csv_holds_the_map(measures, tmp_path):
    table = round_trip(p1_figure_data("p1_fig02_betti0_surface", measures), tmp_path)
    fig = make_p1_figure("p1_fig02_betti0_surface", measures)
    for panel, ax in enumerate(data_axes(fig)):
        (mesh,) = [c for c in ax.collections if isinstance(c, QuadMesh)]
        rows = table[table[cols.PANEL] == panel]
        grid = rows.pivot(index=cols.THRESHOLD, columns=cols.RHO, values=cols.MEAN)
        np.testing.assert_allclose(np.asarray(mesh.get_array()).reshape(grid.shape), grid.to_numpy())
        system = rows[cols.SYSTEM].iloc[0]
        b0 = (measures[system]["betti"].sel(force_kind="total", homology_dim=0) / measures[system]["n_particles"])
        expected = b0.mean("realization").sel(rho=grid.columns.values, threshold=grid.index.values)
        np.testing.assert_allclose(grid.to_numpy(), expected.transpose("threshold", "rho").values)


def test_network_csv_holds_every_drawn_contact(tmp_path):
    snapshots = {"2d_hertz": make_snapshot(2), "3d_hertz": make_snapshot(3)}
    table = round_trip(p1_figure_data("p1_fig01_networks", snapshots=snapshots), tmp_path)
    fig = make_p1_figure("p1_fig01_networks", snapshots=snapshots)
    ax2d = data_axes(fig)[0]
    (lines,) = [c for c in ax2d.collections if isinstance(c, LineCollection)]
    contacts = table[(table[cols.PANEL] == 0) & (table["element"] == "contact")]
    np.testing.assert_allclose(lines.get_array(), contacts[cols.FORCE].to_numpy())
    ends = np.array([seg for seg in lines.get_segments()]).reshape(len(contacts), 4)
    end_columns = [networks.END_I[0], networks.END_I[1], networks.END_J[0], networks.END_J[1]]
    np.testing.assert_allclose(ends, contacts[end_columns].to_numpy())
    particles = table[(table[cols.PANEL] == 0) & (table["element"] == "particle")]
    assert len(particles) == snapshots["2d_hertz"].sizes["particle"]
    three = table[(table[cols.PANEL] == 1) & (table["element"] == "contact")]
    assert three[list(networks.END_J)].notna().all().all()  # 3D rows carry z


def test_persistence_diagram_csv_holds_the_points(measures, tmp_path):
    diagrams = {name: make_diagrams(ds) for name, ds in measures.items()}
    data = p1_figure_data("p1_fig10_persistence_diagram", measures, diagrams, rho=0.85, realization=1)
    table = round_trip(data, tmp_path)
    (ax,) = data_axes(draw_figure("p1_fig10_persistence_diagram", data))
    drawn = {c.get_gid(): c for c in ax.collections if isinstance(c, PathCollection)}
    finite = table[~table["essential"]]
    np.testing.assert_allclose(drawn["points"].get_offsets(), finite[[cols.BIRTH, cols.DEATH]].to_numpy())
    assert np.isneginf(table.loc[table["essential"], cols.DEATH]).all()
    assert len(drawn["essential"].get_offsets()) == table["essential"].sum() == 1


def test_p2_distance_csv_holds_the_curves_and_z(tmp_path):
    ds = p2_shaped()
    data = figure_data("p2_fig08_distances_tangential_mu05", ds, system=report.FRICTIONAL)
    table = round_trip(data, tmp_path)
    fig = draw_figure("p2_fig08_distances_tangential_mu05", data)
    assert set(table["force_kind"]) == {"tangential"}
    panels, twins = fig.axes[:2], fig.axes[2:4]  # the two panels, then the Z twin of each
    for h, ax, twin in zip(report.P2_HOMOLOGY_DIMS, panels, twins):
        rows = table[table[cols.PANEL] == h]
        for line, metric in zip(ax.lines, report.METRICS):
            curve = rows[rows[cols.QUANTITY] == p2.METRIC_QUANTITY[metric]]
            np.testing.assert_allclose(line.get_xdata(), curve[cols.RHO])
            np.testing.assert_allclose(line.get_ydata(), curve[cols.MEAN])
            expected = realization_mean(ds["distance"].sel(force_kind="tangential", homology_dim=h,
                                                                  metric=metric))
            np.testing.assert_allclose(curve[cols.MEAN], expected.values)
        z = rows[rows[cols.QUANTITY] == "Z"]
        np.testing.assert_allclose(twin.lines[0].get_ydata(), z[cols.MEAN])


def test_p2_bands_are_the_realization_mean_plus_minus_the_sample_std():
    """The one convention of forcenet.report.realizations: distances mean ± std over realizations, ratios the ratio
    of the means ± the std of the per-realization ratios."""
    ds = p2_shaped()  # 3 realizations
    table = figure_data("p2_fig06_distances_normal_mu05", ds, system=report.FRICTIONAL).table
    da = ds["distance"].sel(force_kind="normal", homology_dim=1, metric="wasserstein_2")
    rows = table[(table[cols.PANEL] == 1) & (table[cols.QUANTITY] == p2.METRIC_QUANTITY["wasserstein_2"])]
    std = np.std(da.transpose("realization", "rho").values, axis=0, ddof=1)
    np.testing.assert_allclose(rows[cols.LOW], da.mean("realization") - std)
    np.testing.assert_allclose(rows[cols.HIGH], da.mean("realization") + std)
    table = figure_data("p2_fig07_ratios_mu05", ds, system=report.FRICTIONAL).table
    rows = table[(table[cols.PANEL] == 0) & (table[cols.QUANTITY] == p2.RATIO_QUANTITY["wasserstein_1"])]
    ratios = report.distance_ratio(ds, "wasserstein_1").sel(force_kind="normal", homology_dim=0)
    spread = np.nanstd(ratios.transpose("realization", "rho").values, axis=0, ddof=1)
    np.testing.assert_allclose(rows[cols.HIGH] - rows[cols.MEAN], spread, equal_nan=True)
    np.testing.assert_allclose(rows[cols.MEAN] - rows[cols.LOW], spread, equal_nan=True)
    one = figure_data("p2_fig06_distances_normal_mu05", ds.isel(realization=[0]), system=report.FRICTIONAL)
    np.testing.assert_array_equal(one.table[cols.LOW].dropna(), one.table[cols.MEAN][one.table[cols.LOW].notna()])


def test_p2_ratio_csv_holds_the_ratio_curves(tmp_path):
    ds = p2_shaped(frictionless=True)
    data = figure_data("p2_fig10_ratios_mu0", ds, system=report.FRICTIONLESS)
    table = round_trip(data, tmp_path)
    fig = draw_figure("p2_fig10_ratios_mu0", data)
    for h, ax in zip(report.P2_HOMOLOGY_DIMS, fig.axes):
        for line, den in zip(ax.lines, ("wasserstein_1", "wasserstein_2")):
            curve = table[(table[cols.PANEL] == h) & (table[cols.QUANTITY] == p2.RATIO_QUANTITY[den])]
            np.testing.assert_allclose(line.get_ydata(), curve[cols.MEAN], equal_nan=True)


def test_p2_network_and_diagram_csvs_hold_the_drawn_edges_and_points(tmp_path):
    forces, quadrant = lattice_forces_and_quadrants()
    snapshots = [lattice_snapshot(forces, 0.78), lattice_snapshot(permuted(forces, quadrant, ["bottom left"]), 0.79),
                 lattice_snapshot(permuted(forces, quadrant, report.QUADRANTS), 0.80)]
    data = figure_data("p2_fig01_snapshots_differences", snapshots, system=report.FRICTIONAL,
                       rattler_rule="none")
    table = round_trip(data, tmp_path)
    fig = draw_figure("p2_fig01_snapshots_differences", data)
    for panel, ax in enumerate(fig.axes[:5]):
        rows = table[table[cols.PANEL] == panel]
        drawn = np.sort(np.asarray(ax.collections[0].get_array(), float))
        np.testing.assert_allclose(drawn, np.sort(rows[cols.VALUE].to_numpy()))
    diff = force_differences(snapshots[0], snapshots[2])
    np.testing.assert_allclose(np.sort(table.loc[table[cols.PANEL] == 4, cols.VALUE]), np.sort(diff.force))

    analysis = analysis_factory(0.79, 3.1, DIAGRAMS)
    data = figure_data("p2_fig03_diagrams", analysis, system=report.FRICTIONAL)
    table = round_trip(data, tmp_path)
    fig = draw_figure("p2_fig03_diagrams", data)
    for h, ax in zip(report.P2_HOMOLOGY_DIMS, fig.axes):
        rows = table[table[cols.PANEL] == h]
        finite, essential = ax.collections[:2]
        np.testing.assert_allclose(np.asarray(finite.get_offsets()),
                                   rows.loc[~rows["essential"], [cols.BIRTH, "death drawn [<F>]"]].to_numpy())
        assert len(rows) == len(DIAGRAMS["normal", h])
        assert (rows.loc[rows["essential"], "death drawn [<F>]"] == -1.0).all()


def test_concat_keeps_the_columns_of_an_empty_block():
    """A block without rows (a network with no loaded contact) still brings its columns; it adds no rows."""
    from forcenet.plotting.figure_data import concat

    contacts = pd.DataFrame({"element": [], "F/<F>": []})
    particles = pd.DataFrame({"element": ["particle", "particle"], "radius [d_ave]": [0.5, 0.7]})
    table = concat([contacts, particles])
    assert list(table.columns) == ["element", "F/<F>", "radius [d_ave]"] and len(table) == 2
    assert table["F/<F>"].isna().all()
    assert list(concat([contacts]).columns) == ["element", "F/<F>"] and concat([]).empty
