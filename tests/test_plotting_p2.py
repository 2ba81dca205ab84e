"""P2 figures: every figure function returns a Figure whose axes are labelled; the data reach the plot."""
from __future__ import annotations

import matplotlib.pyplot as plt
import numpy as np
import pytest
from matplotlib.figure import Figure

from forcenet.plotting import p2 as figures
from forcenet.report import p2 as report

from test_report_p2 import (NEVER, analysis_factory, lattice_contacts, lattice_forces_and_quadrants,
                            lattice_snapshot, p2_shaped, permuted)


@pytest.fixture(scope="module")
def snapshots():
    forces, quadrant = lattice_forces_and_quadrants()
    return [lattice_snapshot(forces, 0.78), lattice_snapshot(permuted(forces, quadrant, ["bottom left"]), 0.79),
            lattice_snapshot(permuted(forces, quadrant, report.QUADRANTS), 0.80)]


@pytest.fixture(scope="module")
def analysis():
    return analysis_factory(0.79, 3.1, {("normal", 0): [(3.0, NEVER), (0.0, NEVER), (2.5, 1.0), (1.8, 0.9)],
                                        ("normal", 1): [(1.2, NEVER), (0.9, 0.4)]})


def inputs(name, snapshots, analysis):
    if name == "p2_fig01_snapshots_differences":
        return (snapshots,)
    if name == "p2_fig03_diagrams":
        return (analysis,)
    return (p2_shaped(frictionless=name.endswith("mu0")),)


def labelled(fig: Figure) -> None:
    drawn = [ax for ax in fig.axes if ax.axison and (ax.lines or ax.collections)]
    assert drawn, "nothing drawn"
    for ax in fig.axes:
        if not ax.axison or ax.get_label() == "<colorbar>":
            continue
        twin = ax.get_shared_x_axes().get_siblings(ax)
        assert ax.get_ylabel(), f"unlabelled y axis in {ax.get_title()!r}"
        assert ax.get_xlabel() or any(t.get_xlabel() for t in twin), f"unlabelled x axis in {ax.get_title()!r}"


@pytest.mark.parametrize("name", sorted(figures.P2_FIGURES))
def test_every_figure_returns_a_labelled_figure(name, snapshots, analysis):
    fig = figures.P2_FIGURES[name](*inputs(name, snapshots, analysis))
    try:
        assert isinstance(fig, Figure)
        labelled(fig)
    finally:
        plt.close(fig)


def test_registry_names_the_issue_figures():
    assert set(figures.P2_FIGURES) == {
        "p2_fig01_snapshots_differences", "p2_fig03_diagrams", "p2_fig06_distances_normal_mu05",
        "p2_fig07_ratios_mu05", "p2_fig08_distances_tangential_mu05", "p2_fig09_distances_normal_mu0",
        "p2_fig10_ratios_mu0"}


def test_distance_figure_draws_realization_means_on_log_axes():
    ds = p2_shaped()
    fig = figures.p2_fig06_distances_normal_mu05(ds)
    try:
        ax = fig.axes[0]
        assert ax.get_yscale() == "log"
        expected = report.realization_mean(ds["distance"].sel(force_kind="normal", homology_dim=0, metric="bottleneck"))
        np.testing.assert_allclose(ax.lines[0].get_ydata(), expected.values)
        assert any("Z" in t.get_ylabel() for t in fig.axes)  # the twin axis carries Z(rho)
    finally:
        plt.close(fig)


def test_tangential_figure_plots_tangential_distances():
    ds = p2_shaped()
    fig = figures.p2_fig08_distances_tangential_mu05(ds)
    try:
        expected = report.realization_mean(ds["distance"].sel(force_kind="tangential", homology_dim=1,
                                                              metric="wasserstein_1"))
        np.testing.assert_allclose(fig.axes[1].lines[1].get_ydata(), expected.values)
    finally:
        plt.close(fig)


def test_difference_maps_are_zero_where_nothing_changed(snapshots):
    diff = report.force_differences(snapshots[0], snapshots[1])
    ci, cj = lattice_contacts()
    assert set(zip(diff.i.tolist(), diff.j.tolist())) == set(zip(ci.tolist(), cj.tolist()))
    _, quadrant = lattice_forces_and_quadrants()
    key = {(i, j): q for i, j, q in zip(ci.tolist(), cj.tolist(), quadrant)}
    changed = np.array([key[i, j] == "bottom left" for i, j in zip(diff.i.tolist(), diff.j.tolist())])
    assert np.all(diff.force[~changed] == 0) and np.any(diff.force[changed] > 0)
