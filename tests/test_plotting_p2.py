"""P2 figures: every registered P2 figure gives a Figure whose axes are labelled; the data reach the plot."""
from __future__ import annotations

import io

import matplotlib.pyplot as plt
import numpy as np
import pytest
from matplotlib.figure import Figure

from forcenet.plotting import registry
from forcenet.report import p2 as report
from forcenet.report.p2_distances import force_differences
from forcenet.report.realizations import realization_mean

from test_report_p2 import (NEVER, analysis_factory, lattice_contacts, lattice_forces_and_quadrants,
                            lattice_snapshot, p2_shaped, permuted)


@pytest.fixture(scope="module")
def snapshots():
    forces, quadrant = lattice_forces_and_quadrants()
    return [lattice_snapshot(forces, 0.78), lattice_snapshot(permuted(forces, quadrant, ["bottom left"]), 0.79),
            lattice_snapshot(permuted(forces, quadrant, report.QUADRANTS), 0.80)]


DIAGRAMS = {("normal", 0): [(3.0, NEVER), (0.0, NEVER), (2.5, 1.0), (1.8, 0.9)],
            ("normal", 1): [(1.2, NEVER), (0.9, 0.4)]}


@pytest.fixture(scope="module")
def analysis():
    return analysis_factory(0.79, 3.1, DIAGRAMS)


P2_IDS = sorted(entry.id for entry in registry.FIGURES if entry.study == "p2")
SYSTEM_NAMES = {"frictional": report.FRICTIONAL, "frictionless": report.FRICTIONLESS}


def make_p2_figure(name: str, *inputs, **options):
    """Prepare and draw P2 figure `name` through the registry for its system, networks made by P2's rattler rule
    ("none": P2 §III C keeps rattlers)."""
    options.setdefault("system", SYSTEM_NAMES[registry.figure_entry(name).systems])
    options.setdefault("rattler_rule", "none")
    return registry.make_figure(name, *inputs, **options)


def inputs(name, snapshots, analysis):
    if name == "p2_fig01_snapshots_differences":
        return (snapshots,)
    if name == "p2_fig03_diagrams":
        return (analysis,)
    return (p2_shaped(frictionless=name.endswith("mu0")),)


def labelled(fig: Figure) -> None:
    """Every axis (and colour bar) is labelled, and every label names its quantity's symbol ($…$)."""
    drawn = [ax for ax in fig.axes if ax.axison and (ax.lines or ax.collections)]
    assert drawn, "nothing drawn"
    for ax in fig.axes:
        if not ax.axison:
            continue
        if ax.get_label() == "<colorbar>":
            label = ax.get_ylabel() or ax.get_xlabel()
            assert "$" in label, f"colour bar without a symbol: {label!r}"
            continue
        twin = ax.get_shared_x_axes().get_siblings(ax)
        xlabel = ax.get_xlabel() or next((t.get_xlabel() for t in twin if t.get_xlabel()), "")
        assert "$" in ax.get_ylabel(), f"y axis without a symbol in {ax.get_title()!r}: {ax.get_ylabel()!r}"
        assert "$" in xlabel, f"x axis without a symbol in {ax.get_title()!r}: {xlabel!r}"


@pytest.mark.parametrize("name", P2_IDS)
def test_every_figure_returns_a_labelled_figure(name, snapshots, analysis):
    fig = make_p2_figure(name, *inputs(name, snapshots, analysis))
    try:
        assert isinstance(fig, Figure)
        labelled(fig)
    finally:
        plt.close(fig)


def test_distance_figure_draws_realization_means_on_log_axes():
    ds = p2_shaped()
    fig = make_p2_figure("p2_fig06_distances_normal_mu05", ds)
    try:
        ax = fig.axes[0]
        assert ax.get_yscale() == "log"
        expected = realization_mean(ds["distance"].sel(force_kind="normal", homology_dim=0, metric="bottleneck"))
        np.testing.assert_allclose(ax.lines[0].get_ydata(), expected.values)
        assert any("Z" in t.get_ylabel() for t in fig.axes)  # the twin axis carries Z(rho)
    finally:
        plt.close(fig)


@pytest.mark.parametrize("convention, named", [("minus_one", False), ("drop", True)])
def test_a_distance_figure_names_a_never_dying_convention_other_than_p2s(convention, named):
    # the figures of the `drop` reading beside (docs/validation/controls.md §3) must not pass for P2's own
    ds = p2_shaped()
    ds.attrs["essential_convention"] = convention
    for name in ("p2_fig06_distances_normal_mu05", "p2_fig07_ratios_mu05"):
        fig = make_p2_figure(name, ds)
        try:
            assert ("left out of the matching" in fig._suptitle.get_text()) is named
        finally:
            plt.close(fig)


@pytest.mark.parametrize("name", ["p2_fig06_distances_normal_mu05", "p2_fig07_ratios_mu05"])
def test_a_panel_with_nothing_positive_says_so_instead_of_failing(name):
    # under `drop` a sequence can have no finite beta1 class at all: every distance 0, every ratio 0/0
    ds = p2_shaped()
    ds["distance"].loc[{"homology_dim": 1}] = 0.0
    fig = make_p2_figure(name, ds)
    try:
        fig.savefig(io.BytesIO(), format="png")  # a log axis without a positive value cannot find its range
        notes = [[t.get_text() for t in ax.texts] for ax in fig.axes[:2]]
        assert not any("no positive value" in t for t in notes[0])  # beta0 has values
        assert any("no positive value" in t for t in notes[1])
    finally:
        plt.close(fig)


def test_tangential_figure_plots_tangential_distances():
    ds = p2_shaped()
    fig = make_p2_figure("p2_fig08_distances_tangential_mu05", ds)
    try:
        expected = realization_mean(ds["distance"].sel(force_kind="tangential", homology_dim=1,
                                                              metric="wasserstein_1"))
        np.testing.assert_allclose(fig.axes[1].lines[1].get_ydata(), expected.values)
    finally:
        plt.close(fig)


@pytest.mark.parametrize("name, system", [("p2_fig07_ratios_mu05", report.FRICTIONAL),
                                          ("p2_fig10_ratios_mu0", report.FRICTIONLESS)])
def test_ratio_figure_draws_the_ratio_of_mean_distances(name, system):
    ds = p2_shaped(frictionless=system == report.FRICTIONLESS)
    fig = make_p2_figure(name, ds)
    try:
        for h, ax in zip(report.P2_HOMOLOGY_DIMS, fig.axes):
            assert ax.get_yscale() == "log"
            for line, den in zip(ax.lines, ("wasserstein_1", "wasserstein_2")):
                expected = report.mean_distance_ratio(ds, den).sel(force_kind="normal", homology_dim=h)
                np.testing.assert_allclose(line.get_xdata(), expected["rho"].values)
                np.testing.assert_allclose(line.get_ydata(), expected.values)
            rho_j = report.jamming_density(ds, int(ds.attrs.get("dimension", 2)))
            assert [float(line.get_xdata()[0]) for line in ax.lines[2:]] == [pytest.approx(rho_j)]  # ρ_J marked
    finally:
        plt.close(fig)


def test_diagram_figure_plots_each_point_once(analysis):
    fig = make_p2_figure("p2_fig03_diagrams", analysis, essential_death=-1.0)
    try:
        for h, ax in zip(report.P2_HOMOLOGY_DIMS, fig.axes):
            points = DIAGRAMS["normal", h]
            finite, essential = ax.collections[:2]
            assert sorted(map(tuple, finite.get_offsets().tolist())) == sorted(p for p in points if p[1] is not NEVER)
            assert sorted(map(tuple, essential.get_offsets().tolist())) == sorted(
                (b, -1.0) for b, d in points if d is NEVER)
            assert f"{len(points)} points" in ax.get_title()
    finally:
        plt.close(fig)


def edge_rows(collection) -> np.ndarray:
    """(x0, y0, x1, y1, value) per drawn edge, in a canonical order."""
    segments = np.array([path.vertices[:2].ravel() for path in collection.get_paths()]).reshape(-1, 4)
    rows = np.column_stack([segments, np.asarray(collection.get_array(), dtype=float)])
    return rows[np.lexsort(rows.T[::-1])]


def test_fig01_builds_each_network_once_and_draws_the_reported_differences(snapshots, monkeypatch):
    import forcenet.network.snapshot

    built = []
    original = forcenet.network.snapshot.build_force_network
    monkeypatch.setattr(forcenet.network.snapshot, "build_force_network",
                        lambda *args, **kwargs: built.append(1) or original(*args, **kwargs))
    fig = make_p2_figure("p2_fig01_snapshots_differences", snapshots)
    monkeypatch.undo()
    try:
        assert len(built) == len(snapshots)  # a, b, c: the difference panels reuse them
        position = snapshots[0]["position"].values
        for ax, k in zip(fig.axes[3:5], (1, 2)):
            diff = force_differences(snapshots[0], snapshots[k])
            expected = np.column_stack([position[diff.i, :2], position[diff.j, :2], diff.force])
            np.testing.assert_allclose(edge_rows(ax.collections[0]), expected[np.lexsort(expected.T[::-1])])
    finally:
        plt.close(fig)


def test_difference_maps_are_zero_where_nothing_changed(snapshots):
    diff = force_differences(snapshots[0], snapshots[1])
    ci, cj = lattice_contacts()
    assert set(zip(diff.i.tolist(), diff.j.tolist())) == set(zip(ci.tolist(), cj.tolist()))
    _, quadrant = lattice_forces_and_quadrants()
    key = {(i, j): q for i, j, q in zip(ci.tolist(), cj.tolist(), quadrant)}
    changed = np.array([key[i, j] == "bottom left" for i, j in zip(diff.i.tolist(), diff.j.tolist())])
    assert np.all(diff.force[~changed] == 0) and np.any(diff.force[changed] > 0)


def quoted_segments(ax) -> list[tuple[float, float, float, str]]:
    """(level, ρ from, ρ to, label) of the P2 levels drawn on a panel (horizontal LineCollections)."""
    out = []
    for collection in ax.collections:
        if collection.get_label().startswith("P2"):
            (x0, y0), (x1, y1) = collection.get_segments()[0]
            assert y0 == y1
            out.append((y0, x0, x1, collection.get_label()))
    return out


def test_ratio_and_distance_figures_mark_p2_quoted_levels():
    ds = p2_shaped()  # rho 0.63 .. 0.90, rho_J = 0.78
    fig = make_p2_figure("p2_fig07_ratios_mu05", ds)
    try:
        beta0, beta1 = (quoted_segments(ax) for ax in fig.axes[:2])
        assert sorted(level for level, *_ in beta0) == [0.2, 0.75]  # P2 §IV A, rho < 0.75
        assert all(lo == pytest.approx(0.63) and hi == pytest.approx(0.75) for _, lo, hi, _ in beta0)
        assert beta1 == []  # P2 quotes no level for loops
    finally:
        plt.close(fig)
    fig = make_p2_figure("p2_fig06_distances_normal_mu05", ds)
    try:
        [(level, lo, hi, label)] = quoted_segments(fig.axes[0])
        rho_j = report.jamming_density(ds)
        assert level == 10.0 and hi == pytest.approx(rho_j) and r"\rho_J" in label
    finally:
        plt.close(fig)
    fig = make_p2_figure("p2_fig10_ratios_mu0", p2_shaped(frictionless=True))
    try:
        assert all(quoted_segments(ax) == [] for ax in fig.axes)  # P2 gives no level for Fig. 10
    finally:
        plt.close(fig)
