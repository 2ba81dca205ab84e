"""P1 figures: every registered figure draws from synthetic datasets, with labelled axes, the expected panels
and curves, realization spread, every simulated ρ and ρ_max marked."""
from __future__ import annotations

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pytest  # noqa: E402
import xarray as xr  # noqa: E402
from matplotlib.collections import LineCollection, PathCollection, QuadMesh  # noqa: E402
from matplotlib.figure import Figure  # noqa: E402

from contract import contract_attrs  # noqa: E402
from forcenet.datasets.schema import FORCE_KINDS  # noqa: E402
from forcenet.network import snapshot_network  # noqa: E402
from forcenet.plotting import figure_data as cols  # noqa: E402
from forcenet.plotting import registry  # noqa: E402
from forcenet.plotting import p1 as figures  # noqa: E402
from forcenet.plotting.style import save_figure, system_color  # noqa: E402
from forcenet.report import p1 as report_p1  # noqa: E402
from forcenet.report.p1_validation import p1_validation  # noqa: E402
from forcenet.report.p1 import f_max_cut  # noqa: E402
from test_network import rattler_snapshot  # noqa: E402  (one rattler, one wall contact)
from test_report_p1 import make_p1_measures  # noqa: E402  (synthetic aggregated datasets)


# --- synthetic diagrams and snapshots -----------------------------------------------------------------------
def p1_inputs(name: str, measures=None, diagrams=None, snapshots=None) -> list:
    """The inputs of P1 figure `name` in its registry entry's order."""
    given = {"measures": measures, "diagrams": diagrams, "example_snapshots": snapshots}
    return [given[kind] for kind in registry.figure_entry(name).inputs]


def make_p1_figure(name: str, measures=None, diagrams=None, snapshots=None, **options):
    """Prepare and draw P1 figure `name` through the registry, networks made by P1's rattler rule ("once")."""
    options.setdefault("rattler_rule", "once")
    return registry.make_figure(name, *p1_inputs(name, measures, diagrams, snapshots), **options)


def p1_figure_data(name: str, measures=None, diagrams=None, snapshots=None, **options):
    options.setdefault("rattler_rule", "once")
    return registry.figure_data(name, *p1_inputs(name, measures, diagrams, snapshots), **options)


def make_diagrams(measures: xr.Dataset, points_per_diagram: int = 12, seed: int = 0) -> xr.Dataset:
    """Ragged persistence points for every (realization, ρ, force kind, homology dim); one essential PD0 point."""
    rng = np.random.default_rng(seed)
    columns = {k: [] for k in ("diagram_force_kind", "diagram_homology_dim", "birth", "death", "essential",
                               "point_realization", "point_rho")}
    for realization in measures["realization"].values:
        for rho in measures["rho"].values:
            for kind in range(len(FORCE_KINDS)):
                for dim in measures["homology_dim"].values:
                    birth = rng.uniform(0.05, 4.0, points_per_diagram)
                    death = birth - rng.uniform(0.0, 1.0, points_per_diagram) * birth
                    essential = np.zeros(points_per_diagram, dtype=np.int8)
                    if dim == 0:
                        essential[0], death[0] = 1, -np.inf
                    for key, values in (("diagram_force_kind", np.full(points_per_diagram, kind)),
                                        ("diagram_homology_dim", np.full(points_per_diagram, dim)),
                                        ("birth", birth), ("death", death), ("essential", essential),
                                        ("point_realization", np.full(points_per_diagram, realization)),
                                        ("point_rho", np.full(points_per_diagram, rho))):
                        columns[key].append(values)
    return xr.Dataset({key: ("point", np.concatenate(values)) for key, values in columns.items()},
                      coords={"force_kind": list(FORCE_KINDS)}, attrs=dict(measures.attrs))


def make_snapshot(dimension: int, n_side: int = 6, seed: int = 1) -> xr.Dataset:
    """Particles on a square/cubic lattice, contacts between lattice neighbours, random forces (a few zero)."""
    rng = np.random.default_rng(seed)
    grid = np.stack(np.meshgrid(*[np.arange(n_side)] * dimension, indexing="ij"), axis=-1).reshape(-1, dimension)
    index = {tuple(p): k for k, p in enumerate(grid)}
    pairs = [(k, index[tuple(p + step)]) for k, p in enumerate(grid) for step in np.eye(dimension, dtype=int)
             if tuple(p + step) in index]
    i, j = np.array(pairs).T
    normal = (grid[j] - grid[i]) * rng.exponential(1.0, len(i))[:, None]
    normal[:3] = 0.0  # contacts that carry no force are not drawn
    tangential = 0.1 * rng.normal(size=normal.shape) * (np.abs(normal).sum(axis=1) > 0)[:, None]
    return xr.Dataset({
        "position": (("particle", "spatial"), grid + 0.5),
        "radius": ("particle", np.full(len(grid), 0.5)),
        "contact_i": ("contact", i), "contact_j": ("contact", j),
        "force_normal": (("contact", "spatial"), normal), "force_tangential": (("contact", "spatial"), tangential),
        "box_lo": ("spatial", np.zeros(dimension)), "box_hi": ("spatial", np.full(dimension, float(n_side))),
        "rho": 0.85 if dimension == 2 else 0.6,
    }, attrs=contract_attrs("snapshot", dimension=dimension))


@pytest.fixture(scope="module")
def measures():
    return make_p1_measures()


@pytest.fixture(scope="module")
def diagrams(measures):
    return {name: make_diagrams(ds) for name, ds in measures.items()}


@pytest.fixture(scope="module")
def snapshots():
    return {"2d_hertz": make_snapshot(2), "3d_hertz": make_snapshot(3)}


@pytest.fixture(autouse=True)
def close_figures():
    yield
    plt.close("all")


# --- helpers --------------------------------------------------------------------------------------------------
def data_axes(fig: Figure) -> list:
    return [ax for ax in fig.axes if ax.get_label() != "<colorbar>"]


def mean_lines(ax) -> list:
    return [line for line in ax.get_lines() if line.get_gid() == figures.MEAN_GID]


def bands(ax) -> list:
    return [c for c in ax.collections if type(c).__name__ in ("PolyCollection", "FillBetweenPolyCollection")]


# expected data panels and mean curves per panel for the three synthetic systems (2D Hertz, 2D linear, 3D)
N_THRESHOLD_CURVES = len(figures.DEFAULT_THRESHOLDS)  # all are on the synthetic 0.25 grid
EXPECTED = {
    "p1_fig01_networks": (2, None),
    "p1_fig02_betti0_surface": (3, 0),
    "p1_fig03_force_pdf": (3, 6),
    "p1_fig04_cluster_size": (3, N_THRESHOLD_CURVES),
    "p1_fig05_percolating_cluster": (3, N_THRESHOLD_CURVES),
    "p1_fig06_betti0": (4, None),  # 3 systems + the 3D close-up
    "p1_fig07_betti1": (4, N_THRESHOLD_CURVES),  # B1 for 3 systems + B2 for 3D
    "p1_fig08_shape_heatmap": (3, 0),
    "p1_fig09_shape_sections": (3, N_THRESHOLD_CURVES),
    "p1_fig10_persistence_diagram": (1, 0),
    "p1_fig11_persistence_bins": (8, None),  # 4 bins × (2D, 3D)
    "p1_fig12_total_persistence": (3, 2),  # TP0, TP1
    "p1_z_jamming": (1, 3),
}


def test_the_registry_covers_every_p1_figure():
    assert {entry.id for entry in registry.FIGURES if entry.study == "p1"} == set(EXPECTED)


@pytest.mark.parametrize("name", sorted(EXPECTED))
def test_figure_draws_labelled_panels(name, measures, diagrams, snapshots):
    fig = make_p1_figure(name, measures, diagrams, snapshots)
    assert isinstance(fig, Figure)
    axes = data_axes(fig)
    n_panels, n_curves = EXPECTED[name]
    assert len(axes) == n_panels
    for ax in axes:
        assert ax.get_xlabel().strip() and ax.get_ylabel().strip(), (name, ax.get_title())
        if n_curves is not None:
            assert len(mean_lines(ax)) == n_curves, (name, ax.get_title())
            assert len(bands(ax)) == n_curves  # every mean curve carries its spread band


def test_line_figures_use_the_system_colour(measures, diagrams):
    fig = make_p1_figure("p1_fig12_total_persistence", measures, diagrams)
    for ax, name in zip(data_axes(fig), ["2d_hertz", "2d_linear", "3d_hertz"]):  # P1's panel order
        assert {line.get_color() for line in mean_lines(ax)} == {system_color(name)}


def rho_max_marks(ax) -> list[float]:
    return [float(line.get_xdata()[0]) for line in ax.get_lines() if line.get_gid() == figures.RHO_MAX_GID]


def test_curves_span_every_rho_and_mark_rho_max(measures):
    rho_max = f_max_cut(measures).rho_max  # dyn: 2D Hertz 0.94, 2D linear 0.95 (its top), 3D 0.67
    fig = make_p1_figure("p1_fig04_cluster_size", measures)
    for ax, name in zip(data_axes(fig), ["2d_hertz", "2d_linear", "3d_hertz"]):
        for line in mean_lines(ax):
            np.testing.assert_allclose(line.get_xdata(), measures[name]["rho"].values)  # nothing cut
        assert rho_max_marks(ax) == pytest.approx([rho_max[name]])
        shaded = [p for p in ax.patches if p.get_gid() == "beyond_rho_max"]
        assert len(shaded) == (1 if rho_max[name] < measures[name]["rho"].max() else 0)
    assert "rho_{max}" in data_axes(fig)[0].get_legend_handles_labels()[1][-1]
    fig = make_p1_figure("p1_fig02_betti0_surface", measures)
    mesh = [c for c in data_axes(fig)[2].collections if isinstance(c, QuadMesh)]
    assert len(mesh) == 1 and mesh[0].get_array().shape[1] == measures["3d_hertz"].sizes["rho"]
    assert rho_max_marks(data_axes(fig)[2]) == pytest.approx([rho_max["3d_hertz"]])
    # the unit of the F_max rule moves the mark: in reduced units 2D Hertz is cut at 0.88
    fig = make_p1_figure("p1_fig04_cluster_size", measures, force_unit="reduced")
    assert rho_max_marks(data_axes(fig)[0]) == pytest.approx([0.88])


def test_rho_max_below_the_grid_shades_every_rho():
    measures = make_p1_measures(**{"2d_linear": {"mean_force": np.full(18, 10.0)}})  # 40 dyn > F_max = 1.38
    assert report_p1.f_max_cut(measures).below_grid("2d_linear")
    ax = data_axes(make_p1_figure("p1_fig04_cluster_size", measures))[1]
    shaded = [p for p in ax.patches if p.get_gid() == "beyond_rho_max"]
    assert not rho_max_marks(ax) and len(shaded) == 1
    np.testing.assert_allclose(shaded[0].get_x(), 0.78)  # the whole grid, 0.78 … 0.95
    np.testing.assert_allclose(shaded[0].get_width(), 0.17)
    table = p1_validation(measures)
    row = table[(table["id"] == "rho_max.dyn") & (table["system"] == "2d_linear")].iloc[0]
    assert "below the grid" in row["evidence"]


RHO_AXIS_FIGURES = sorted(set(EXPECTED) - {"p1_fig01_networks", "p1_fig03_force_pdf", "p1_fig10_persistence_diagram"})


@pytest.mark.parametrize("name", RHO_AXIS_FIGURES)
def test_every_rho_panel_is_populated_and_marks_rho_max(name, measures, diagrams):
    fig = make_p1_figure(name, measures, diagrams)
    for ax in data_axes(fig):
        assert rho_max_marks(ax), (name, ax.get_title())
        if mean_lines(ax):  # line panels: some curve has at least two points (heat maps: a full mesh)
            assert max(np.isfinite(np.asarray(line.get_ydata(), float)).sum() for line in mean_lines(ax)) >= 2


def test_force_pdfs_beyond_rho_max_are_dashed(measures):
    fig = make_p1_figure("p1_fig03_force_pdf", measures)
    ax = data_axes(fig)[0]  # 2D Hertz, ρ_max 0.94: the largest ρ drawn (0.95) lies beyond it
    last = mean_lines(ax)[-1]
    assert last.get_linestyle() == "--" and "rho_{max}" in last.get_label()
    assert mean_lines(ax)[0].get_linestyle() == "-"


def test_percolating_size_is_hidden_where_most_realizations_do_not_percolate(measures):
    fig = make_p1_figure("p1_fig05_percolating_cluster", measures)
    ax = data_axes(fig)[0]  # 2D Hertzian, percolation from ρ_J = 0.845
    rho, value = (np.asarray(v, dtype=float) for v in mean_lines(ax)[0].get_data())  # F_th = 0
    assert np.isnan(value[rho < 0.845]).all() and np.isfinite(value[rho >= 0.85]).all()  # 1 of 3 at 0.84
    assert mean_lines(ax)[-1].get_label() == r"$F_{th}$ = 2.5"
    assert np.isnan(np.asarray(mean_lines(ax)[-1].get_ydata(), dtype=float)).all()  # never percolates at F_th ≥ 2


def test_z_figure_marks_the_jamming_points(measures):
    fig = make_p1_figure("p1_z_jamming", measures)
    (ax,) = data_axes(fig)
    markers = [line for line in ax.get_lines() if line.get_gid() == figures.RHO_J_GID]
    assert sorted(float(m.get_xdata()[0]) for m in markers) == pytest.approx([0.575, 0.83, 0.845], abs=0.004)


@pytest.mark.parametrize("rule", ["none", "once"])
def test_network_figure_draws_every_edge_of_the_analysed_network(snapshots, rule):
    fig = make_p1_figure("p1_fig01_networks", snapshots=snapshots, rattler_rule=rule)
    ax2d, ax3d = data_axes(fig)
    assert ax3d.name == "3d" and ax3d.get_zlabel()
    lines = [c for c in ax2d.collections if isinstance(c, LineCollection)]
    ds = snapshots["2d_hertz"]
    loaded = np.linalg.norm(ds["force_normal"].values + ds["force_tangential"].values, axis=1) > 0
    # particle 1 keeps one loaded contact (its others are two of the three unloaded ones): a rattler under "once"
    expected = loaded.sum() - (1 if rule == "once" else 0)
    assert len(lines) == 1 and len(lines[0].get_segments()) == expected
    network = snapshot_network(ds, "total", rattler_rule=rule, wall_contacts="ignored")
    np.testing.assert_allclose(np.sort(lines[0].get_array()), np.sort(network.force))  # coloured by F/⟨F⟩
    assert len(fig.axes) == 3  # two panels and one colour bar


def test_network_figure_holds_no_edge_of_a_removed_rattler():
    """Fig. 1 draws the analysis' network: with P1's rule the rattler (disk 4) and its one edge are gone from the
    figure data (its disk stays drawn); with rattlers kept its edge is there."""
    snapshots = {"2d_hertz": rattler_snapshot()}
    table = p1_figure_data("p1_fig01_networks", snapshots=snapshots, rattler_rule="once").table
    contacts = table[table["element"] == "contact"]
    assert sorted(zip(contacts["i"], contacts["j"])) == [(0, 1), (0, 3), (1, 2), (2, 3)]
    assert len(table[table["element"] == "particle"]) == 5
    np.testing.assert_allclose(contacts[cols.FORCE], np.array([1.0, 2.0, 4.0, 5.0]) / 3.0)  # F/⟨F⟩, ⟨F⟩ = 3
    kept = p1_figure_data("p1_fig01_networks", snapshots=snapshots, rattler_rule="none").table
    assert (0, 4) in set(zip(kept["i"], kept["j"]))


def test_persistence_diagram_shows_the_chosen_points(measures, diagrams):
    fig = make_p1_figure("p1_fig10_persistence_diagram", measures, diagrams, rho=0.85, realization=1)
    (ax,) = data_axes(fig)
    points = diagrams["2d_hertz"]
    chosen = ((points["diagram_force_kind"] == 0) & (points["diagram_homology_dim"] == 0)
              & (points["point_realization"] == 1) & np.isclose(points["point_rho"], 0.85)).values
    finite = chosen & np.isfinite(points["death"].values)
    drawn = {c.get_gid(): c for c in ax.collections if isinstance(c, PathCollection)}
    assert len(drawn["points"].get_offsets()) == finite.sum() > 0
    assert len(drawn["essential"].get_offsets()) == (chosen & ~np.isfinite(points["death"].values)).sum() == 1
    assert {p.get_gid() for p in ax.patches} == {f"bin_{b}" for b in figures.PD_BINS}


def test_figures_cope_with_a_missing_system(measures, diagrams):
    two = {name: ds for name, ds in measures.items() if name != "3d_hertz"}
    assert len(data_axes(make_p1_figure("p1_fig06_betti0", two))) == 2  # no 3D close-up
    assert len(data_axes(make_p1_figure("p1_fig07_betti1", two))) == 2  # no B2 panel
    assert len(data_axes(make_p1_figure("p1_fig11_persistence_bins", two, diagrams))) == 4  # 2D column only


@pytest.fixture(scope="module")
def smoke_like():
    """One realization and three ρ per system (config/smoke.yaml)."""
    grid2, grid3 = [0.80, 0.84, 0.88], [0.55, 0.60, 0.65]
    measures = make_p1_measures(**{name: dict(rho=grid3 if name.startswith("3d") else grid2, n_realizations=1)
                                   for name in ("2d_hertz", "2d_linear", "3d_hertz")})
    return measures, {name: make_diagrams(ds) for name, ds in measures.items()}


@pytest.mark.parametrize("name", sorted(EXPECTED))
def test_figures_draw_from_a_smoke_sized_run(name, smoke_like, snapshots):
    measures, diagrams = smoke_like
    fig = make_p1_figure(name, measures, diagrams, snapshots)
    assert len(data_axes(fig)) == EXPECTED[name][0]


def test_registry_errors(measures):
    with pytest.raises(KeyError, match="unknown figure"):
        registry.make_figure("p1_fig99", measures)
    with pytest.raises(ValueError, match="diagrams"):
        make_p1_figure("p1_fig10_persistence_diagram", measures)


def test_saved_as_pdf_and_png(tmp_path, measures):
    fig = make_p1_figure("p1_z_jamming", measures)
    save_figure(fig, tmp_path / "f.pdf", tmp_path / "f.png")
    assert (tmp_path / "f.pdf").stat().st_size > 1000 and (tmp_path / "f.png").stat().st_size > 1000


def test_total_persistence_and_bins_are_drawn_with_never_dying_classes_at_minus_one(measures, diagrams):
    # the papers' convention (docs/decisions.md), as the P1 table judges: each never-dying class adds birth + 1 to
    # TP_k and counts in the PD0 bin of its birth; with no never-dying class the stored measures are drawn
    from forcenet.report.p1 import never_dying_at_minus_one, per_particle

    name = "2d_hertz"
    data = p1_figure_data("p1_fig12_total_persistence", measures, diagrams).table
    tp0 = data[(data[cols.SYSTEM] == name) & (data[figures.HOMOLOGY_K] == 0)][cols.MEAN].to_numpy()
    expected = per_particle(never_dying_at_minus_one(measures[name], diagrams[name]), "total_persistence")
    total = dict(homology_dim=0, force_kind="total")
    assert tp0 == pytest.approx(expected.sel(**total).mean("realization").values)
    stored = per_particle(measures[name], "total_persistence").sel(**total).mean("realization").values
    assert np.all(tp0 > stored)  # make_diagrams has one never-dying PD0 point per diagram, born at >= 0.05
    none = {n: d.isel(point=np.flatnonzero(~d["essential"].values.astype(bool))) for n, d in diagrams.items()}
    data = p1_figure_data("p1_fig12_total_persistence", measures, none).table
    tp0 = data[(data[cols.SYSTEM] == name) & (data[figures.HOMOLOGY_K] == 0)][cols.MEAN].to_numpy()
    assert tp0 == pytest.approx(stored)
    bins = p1_figure_data("p1_fig11_persistence_bins", measures, diagrams).table
    assert set(bins["persistence_bin"]) == set(figures.PD_BINS)


def test_a_family_of_curves_spans_the_same_lightness_in_any_hue_and_titles_stay_readable():
    import colorsys

    import matplotlib.colors as mcolors
    from forcenet.plotting import style

    for colour in ("#ece133", "#1b9e77"):  # the fallback palette's yellow, a catalog colour
        style.SYSTEM_STYLES["s"] = {"label": "s", "colour": colour}
        shades = style.system_shades("s", 6)
        lightness = [colorsys.rgb_to_hls(*mcolors.to_rgb(c))[1] for c in shades]
        assert lightness[0] == pytest.approx(style.SHADE_LIGHTNESS[0]) and lightness[-1] == pytest.approx(
            style.SHADE_LIGHTNESS[1])
        assert all(a > b for a, b in zip(lightness, lightness[1:]))  # light to dark, every curve its own shade
    fig, ax = style.panel_figure(1)
    style.system_title(ax[0], "s")  # #1b9e77: dark enough, kept
    assert mcolors.to_hex(ax[0].title.get_color()) == "#1b9e77"
    style.SYSTEM_STYLES["s"]["colour"] = "#ece133"
    style.system_title(ax[0], "s")
    assert colorsys.rgb_to_hls(*mcolors.to_rgb(ax[0].title.get_color()))[1] == pytest.approx(style.TEXT_LIGHTNESS)
    del style.SYSTEM_STYLES["s"]
