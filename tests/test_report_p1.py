"""P1 validation table and the reductions shared with the P1 figures, on synthetic aggregated datasets.

The factories below (also used by test_plotting_p1.py) build `network_measures.nc`-shaped datasets whose
answers are known by construction: a sigmoid Z(ρ) around a chosen ρ_J, a chosen ⟨F⟩(ρ), a B0 ridge near ρ_J
(or not), loops only above ρ_J (or not), force PDFs of a chosen width, percolation from a chosen ρ.
"""
from __future__ import annotations

import math

import numpy as np
import pandas as pd
import pytest
import xarray as xr

from forcenet.datasets.schema import FORCE_KINDS, PERSISTENCE_BINS
from forcenet.report import p1 as report

N_PARTICLES = 400
THRESHOLDS = np.round(np.arange(0.0, 3.0 + 1e-9, 0.25), 2)
FORCE_BINS = np.arange(0.05, 6.0, 0.1)  # bin centres of F/<F>
B1, B2 = "B1 = 0 below rho_J", "B2 = 0 below rho_J"  # claim items of the table
REALIZATION_OFFSETS = np.array([-1.0, 0.0, 1.0])  # symmetric: realization means equal the noiseless curves


def sigmoid(x):
    return 1.0 / (1.0 + np.exp(-x))


def make_measures(name: str, *, dimension: int = 2, force_law: str = "hertz", rho=None, rho_j: float = 0.845,
                  force_slope: float = 20.0, force_unit_dyn: float | None = 1.0, mean_force=None,
                  ridge: bool | None = None, loops_below: float = 0.0, pdf_std: float = 0.6,
                  percolation_onset: float | None = None, n_realizations: int = 3) -> xr.Dataset:
    """A synthetic aggregated network_measures dataset (dims realization × rho × ...).

    Z(ρ) is a sigmoid centred on `rho_j`; the realization-mean ⟨F⟩ [reduced units] is `mean_force` if given,
    else force_slope·(ρ − ρ_J + 0.01)₊ / force_unit_dyn (so in dyn it is force_slope·(ρ − ρ_J + 0.01)₊);
    `ridge` (default: Hertzian) adds a B0/N bump at ρ_J for F_th < 0.5; B1 (and B2 in 3D) vanish below ρ_J
    unless `loops_below` > 0; the PDF of F/⟨F⟩ is a gamma law of mean 1 and std `pdf_std`; percolation at
    small F_th starts at `percolation_onset` (default ρ_J) ± 0.01 across realizations.
    """
    rho = np.round(np.asarray(rho if rho is not None else np.arange(0.78, 0.92 + 1e-9, 0.01)), 3)
    ridge = (force_law == "hertz") if ridge is None else ridge
    onset = rho_j if percolation_onset is None else percolation_onset
    offsets = REALIZATION_OFFSETS[:n_realizations] if n_realizations <= 3 else np.linspace(-1, 1, n_realizations)
    offsets = offsets - offsets.mean()
    R, M, K, T = len(offsets), len(rho), len(FORCE_KINDS), len(THRESHOLDS)
    homology = np.arange(dimension)  # 0, 1 (, 2)
    jam = sigmoid((rho - rho_j) / 0.006)  # (M,)
    above = np.clip((rho - rho_j) / 0.03, 0.0, 1.0)  # 0 below ρ_J, 1 well above
    theta = THRESHOLDS

    z = (0.5 + (dimension + 2 - 0.5) * jam)[None, :] + 0.02 * offsets[:, None]
    if mean_force is None:
        scale = 1.0 if force_unit_dyn is None else force_unit_dyn
        mean_force = force_slope * np.clip(rho - rho_j + 0.01, 0.0, None) / scale
    mean_force = np.asarray(mean_force, dtype=float)
    force = (mean_force[None, :] * (1 + 0.05 * offsets[:, None]))[:, :, None].repeat(K, axis=2)

    # B0/N: a bump around F_th ≈ 1.2 growing with jamming, few clusters at small F_th before jamming
    b0 = (0.05 * jam[:, None] * np.exp(-(theta[None, :] - 1.2) ** 2 / 0.3)
          + 0.01 * (1 - jam[:, None]) * np.exp(-theta[None, :]))
    if ridge:
        b0 = b0 + 0.04 * np.exp(-((rho[:, None] - rho_j) / 0.012) ** 2) * (theta[None, :] < 0.5)
    betti = np.zeros((R, M, K, dimension, T))
    betti[..., 0, :] = (N_PARTICLES * b0)[None, :, None, :]
    for k in homology[1:]:
        loops = 0.2 / k * above[:, None] * np.exp(-theta[None, :]) + loops_below * (rho < rho_j)[:, None]
        betti[..., k, :] = (N_PARTICLES * loops)[None, :, None, :]
    betti = betti * (1 + 0.02 * offsets[:, None, None, None, None])

    starts = onset + 0.01 * offsets  # per realization: some ρ have a minority percolating
    percolates = ((rho[None, :] >= starts[:, None])[:, :, None] & (theta[None, None, :] < 2.0)).astype(np.int8)
    percolates = np.broadcast_to(percolates[:, :, None, :], (R, M, K, T)).copy()
    perc_size = percolates.astype(float) * N_PARTICLES * 0.8 * np.exp(-theta / 2.0)
    cluster_size = N_PARTICLES * 0.01 * (1 + jam[:, None] * np.exp(-(theta[None, :] - 1.5) ** 2))
    cluster_size = np.broadcast_to(cluster_size[None, :, None, :], (R, M, K, T)).copy()
    shape = np.broadcast_to((1.0 + 0.6 * jam[:, None] * np.exp(-theta[None, :]))[None, :, None, :],
                            (R, M, K, T)).copy()
    shape[0, :, :, -1] = 0.0  # one realization without clusters at the largest F_th

    k_shape = 1.0 / pdf_std ** 2  # gamma law with mean 1, std pdf_std
    from math import lgamma
    pdf1 = np.exp((k_shape - 1) * np.log(FORCE_BINS) - FORCE_BINS * k_shape + k_shape * np.log(k_shape)
                  - lgamma(k_shape))
    pdf = np.broadcast_to(pdf1, (R, M, K, len(FORCE_BINS))).copy()

    bins = np.zeros((R, M, K, len(PERSISTENCE_BINS)))
    for b, amplitude in enumerate((0.05, 0.02, 0.01, 0.005, 0.0)):
        bins[..., b] = N_PARTICLES * amplitude * (0.5 + jam)[None, :, None]
    tp = np.zeros((R, M, K, dimension))
    for k in homology:
        tp[..., k] = N_PARTICLES * 0.1 / (k + 1) * (0.2 + above)[None, :, None]

    d_rkt = ("realization", "rho", "force_kind", "threshold")
    data = {
        "betti": (("realization", "rho", "force_kind", "homology_dim", "threshold"), betti),
        "cluster_count": (d_rkt, np.round(betti[..., 0, :])),
        "cluster_mean_size": (d_rkt, cluster_size),
        "percolating_size": (d_rkt, perc_size),
        "percolates": (d_rkt, percolates),
        "edge_count": (d_rkt, shape * 10),
        "cluster_particle_count": (d_rkt, np.full((R, M, K, T), 10.0)),
        "shape_parameter": (d_rkt, shape),
        "force_pdf": (("realization", "rho", "force_kind", "force_bin"), pdf),
        "mean_force": (("realization", "rho", "force_kind"), force),
        "persistence_bin_count": (("realization", "rho", "force_kind", "persistence_bin"), bins),
        "total_persistence": (("realization", "rho", "force_kind", "homology_dim"), tp),
        "essential_count": (("realization", "rho", "force_kind", "homology_dim"), np.ones((R, M, K, dimension))),
        "Z": (("realization", "rho"), z),
        "Z_no_rattlers": (("realization", "rho"), z + 0.2),
        "n_particles": (("realization", "rho"), np.full((R, M), N_PARTICLES)),
    }
    coords = {"realization": np.arange(R), "rho": rho, "force_kind": list(FORCE_KINDS), "homology_dim": homology,
              "threshold": THRESHOLDS, "force_bin": FORCE_BINS, "persistence_bin": list(PERSISTENCE_BINS)}
    attrs = {"system": name, "dimension": dimension, "force_law": force_law}
    if force_unit_dyn is not None:
        attrs["force_unit_dyn"] = force_unit_dyn
    return xr.Dataset(data, coords=coords, attrs=attrs)


def make_p1_measures(**overrides) -> dict[str, xr.Dataset]:
    """The three P1 systems as P1 describes them; `overrides` = {system: {keyword: value}} breaks them."""
    base = {
        "2d_hertz": dict(dimension=2, force_law="hertz", rho_j=0.845, force_slope=20.0, pdf_std=0.7,
                         force_unit_dyn=2.0),
        "2d_linear": dict(dimension=2, force_law="linear", rho_j=0.83, force_slope=10.0, pdf_std=0.5,
                          force_unit_dyn=4.0),
        "3d_hertz": dict(dimension=3, force_law="hertz", rho_j=0.575, force_slope=25.0, pdf_std=0.9,
                         force_unit_dyn=0.5, rho=np.arange(0.50, 0.66 + 1e-9, 0.01)),
    }
    return {name: make_measures(name, **{**kwargs, **overrides.get(name, {})}) for name, kwargs in base.items()}


def rows(table: pd.DataFrame, item: str, system: str | None = None) -> pd.DataFrame:
    selected = table[table["item"] == item]
    return selected if system is None else selected[selected["system"] == system]


def verdict(table: pd.DataFrame, item: str, system: str) -> str:
    selected = rows(table, item, system)
    assert len(selected) == 1, (item, system, selected)
    return selected["verdict"].iloc[0]


# --- F_max rule ---------------------------------------------------------------------------------------------
def test_f_max_rule_by_hand():
    rho2, rho3 = [0.80, 0.82, 0.84, 0.86, 0.88], [0.50, 0.52, 0.54, 0.56, 0.58]
    measures = {
        # dyn: [0.2, 0.6, 1.2, 2.0, 3.0] → F'_max 3.0
        "a": make_measures("a", rho=rho2, mean_force=[0.1, 0.3, 0.6, 1.0, 1.5], force_unit_dyn=2.0),
        # dyn: [0.05, 0.2, 0.9, 0.7, 0.4] → F'_max 0.9 (not at the largest ρ) = F_max
        "b": make_measures("b", rho=rho2, mean_force=[0.05, 0.2, 0.9, 0.7, 0.4], force_unit_dyn=1.0),
        # dyn: [0.1, 0.4, 0.8, 1.5, 2.5] → F'_max 2.5
        "c": make_measures("c", dimension=3, rho=rho3, mean_force=[0.2, 0.8, 1.6, 3.0, 5.0], force_unit_dyn=0.5),
    }
    cut = report.f_max_cut(measures)
    assert cut.force_units == "dyn"
    assert cut.f_prime_max == pytest.approx({"a": 3.0, "b": 0.9, "c": 2.5})
    assert cut.f_max == pytest.approx(0.9)
    assert cut.rho_max == pytest.approx({"a": 0.82, "b": 0.88, "c": 0.54})
    kept = report.cut_at_rho_max(measures["c"], cut.rho_max["c"])
    np.testing.assert_allclose(kept["rho"].values, [0.50, 0.52, 0.54])


def test_f_max_rule_needs_comparable_units():
    measures = make_p1_measures()
    measures["2d_linear"].attrs.pop("force_unit_dyn")
    with pytest.raises(ValueError, match="force_unit_dyn"):
        report.f_max_cut(measures)


def test_f_max_rule_on_the_p1_like_systems():
    # in dyn: ⟨F⟩ = slope·(ρ − ρ_J + 0.01); the linear system's max 10·0.10 = 1.0 is the smallest F'_max
    cut = report.f_max_cut(make_p1_measures())
    assert cut.f_max == pytest.approx(1.0)
    assert cut.rho_max == pytest.approx({"2d_linear": 0.92, "2d_hertz": 0.88, "3d_hertz": 0.60})


# --- other reductions ---------------------------------------------------------------------------------------
def test_shape_parameter_rule():
    values = xr.DataArray([[0.0, 0.0, 2.0],      # zero in 2 of 3 realizations → 0
                           [0.0, 1.5, 2.5],      # zero in 1 of 3 → mean of the nonzero ones
                           [np.nan, 0.0, 1.0],   # NaN (no clusters) counts as zero → 0
                           [1.0, 2.0, 3.0]], dims=("threshold", "realization"))
    shape, spread = report.shape_parameter_average(values)
    np.testing.assert_allclose(shape.values, [0.0, 2.0, 0.0, 2.0])
    np.testing.assert_allclose(spread.values, [0.0, np.std([1.5, 2.5], ddof=1), 0.0, 1.0])
    half = xr.DataArray([0.0, 0.0, 1.0, 3.0], dims="realization")  # exactly half zero → 0
    assert float(report.shape_parameter_average(half)[0]) == 0.0


def test_percolating_size_shown_only_where_most_realizations_percolate():
    ds = make_measures("x", rho_j=0.845)
    mean, _ = report.percolating_size_mean(ds)
    fraction = report.percolation_fraction(ds)
    assert bool(mean.where(fraction < 0.5).isnull().all())
    # at ρ = 0.84 one realization of three percolates (onsets 0.835, 0.845, 0.855): hidden although it has a value
    assert float(fraction.sel(threshold=0.0, rho=0.84)) == pytest.approx(1 / 3)
    assert np.isnan(float(mean.sel(threshold=0.0, rho=0.84)))
    shown = mean.sel(threshold=0.0).dropna("rho")
    assert shown["rho"].min() >= 0.845 - 0.005 and shown.size > 0
    # averaged over the percolating realizations only: N_per/N = 0.8 at F_th = 0 wherever shown
    np.testing.assert_allclose(shown.values, 0.8)


def test_force_pdf_width_recovers_the_std():
    for std in (0.4, 0.8):
        width = report.force_pdf_width(make_measures("x", pdf_std=std))
        np.testing.assert_allclose(width.values, std, rtol=0.03)


def test_jamming_point_of_a_sigmoid():
    rho = np.round(np.arange(0.78, 0.92 + 1e-9, 0.01), 3)
    for rho_j in (0.835, 0.8431, 0.862):
        ds = make_measures("x", rho=rho, rho_j=rho_j)
        assert report.jamming_point(ds) == pytest.approx(rho_j, abs=0.004)


# --- validation table ---------------------------------------------------------------------------------------
@pytest.fixture(scope="module")
def p1_table() -> pd.DataFrame:
    return report.p1_validation(make_p1_measures())


def test_values_against_the_paper(p1_table):
    assert list(p1_table.columns) == list(report.COLUMNS)
    truth = {"2d_hertz": 0.845, "2d_linear": 0.83, "3d_hertz": 0.575}
    for system, rho_j in truth.items():
        row = rows(p1_table, "rho_J (inflection of Z)", system).iloc[0]
        assert row["measured"] == pytest.approx(rho_j, abs=0.004)
        assert row["paper"] == report.PAPER_RHO_J[system]
        assert row["difference"] == pytest.approx(row["measured"] - row["paper"])
        row = rows(p1_table, "rho_max (F_max rule)", system).iloc[0]
        assert row["paper"] == report.PAPER_RHO_MAX[system]
    cut = report.f_max_cut(make_p1_measures())
    for system, rho_max in cut.rho_max.items():
        assert rows(p1_table, "rho_max (F_max rule)", system)["measured"].iloc[0] == pytest.approx(rho_max)
    z = rows(p1_table, "Z at rho_J", "2d_hertz").iloc[0]
    # Z = 0.5 + 3.5 sigmoid: 2.25 at the true ρ_J; paper value 3 in 2D
    assert z["measured"] == pytest.approx(2.25, abs=0.3) and z["paper"] == 3.0
    assert np.isnan(rows(p1_table, "Z at rho_J", "3d_hertz")["paper"].iloc[0])


def test_every_claim_holds_when_the_data_behaves_as_p1(p1_table):
    claims = p1_table[p1_table["kind"] == "claim"]
    assert set(claims["verdict"]) == {report.HOLDS}, claims[["item", "system", "evidence", "verdict"]]
    assert len(rows(claims, B2)) == 1  # B2 only for the 3D system
    assert len(claims) == 3 + 3 + 1 + 1 + 3  # ridge, B1, B2, PDF width, percolation


@pytest.mark.parametrize("overrides, failing", [
    ({"2d_linear": {"ridge": True}}, [(report.RIDGE_ITEM, "2d_linear")]),
    ({"2d_hertz": {"ridge": False}}, [(report.RIDGE_ITEM, "2d_hertz")]),
    ({"3d_hertz": {"ridge": False}}, [(report.RIDGE_ITEM, "3d_hertz")]),
    ({"2d_hertz": {"loops_below": 0.05}}, [(B1, "2d_hertz")]),
    ({"3d_hertz": {"loops_below": 0.05}}, [(B1, "3d_hertz"), (B2, "3d_hertz")]),
    ({"2d_linear": {"pdf_std": 0.8}}, [(report.PDF_ITEM, "all")]),
    ({"3d_hertz": {"pdf_std": 0.6}}, [(report.PDF_ITEM, "all")]),
    ({"2d_linear": {"percolation_onset": 0.79}}, [(report.PERCOLATION_ITEM, "2d_linear")]),
    ({"3d_hertz": {"percolation_onset": 0.99}}, [(report.PERCOLATION_ITEM, "3d_hertz")]),  # never percolates
])
def test_a_violated_claim_does_not_hold(overrides, failing):
    table = report.p1_validation(make_p1_measures(**overrides))
    for item, system in failing:
        assert verdict(table, item, system) == report.FAILS, rows(table, item, system)["evidence"].iloc[0]
    claims = table[table["kind"] == "claim"]
    others = claims[[(i, s) not in failing for i, s in zip(claims["item"], claims["system"])]]
    assert set(others["verdict"]) == {report.HOLDS}  # the violation is pinned on the right claim


def test_a_missing_system_is_not_evaluated():
    measures = make_p1_measures()
    del measures["3d_hertz"]
    table = report.p1_validation(measures)
    assert verdict(table, report.RIDGE_ITEM, "3d_hertz") == report.NOT_EVALUATED
    assert verdict(table, report.PERCOLATION_ITEM, "3d_hertz") == report.NOT_EVALUATED
    assert verdict(table, report.PDF_ITEM, "all") == report.NOT_EVALUATED
    assert verdict(table, "rho_J (inflection of Z)", "3d_hertz") == report.NOT_EVALUATED
    assert rows(table, "rho_J (inflection of Z)", "3d_hertz")["paper"].iloc[0] == 0.57
    assert verdict(table, report.RIDGE_ITEM, "2d_hertz") == report.HOLDS
    # with 2 systems the F_max rule is taken over those two
    assert rows(table, "rho_max (F_max rule)", "2d_hertz")["measured"].iloc[0] == pytest.approx(0.88)


def test_writer_round_trip(tmp_path, p1_table):
    csv, md = tmp_path / "tables" / "p1_validation.csv", tmp_path / "tables" / "p1_validation.md"
    report.write_p1_validation(p1_table, csv, md)
    back = pd.read_csv(csv, keep_default_na=False, na_values=[""])
    assert len(back) == len(p1_table)
    np.testing.assert_allclose(back["measured"].astype(float), p1_table["measured"], equal_nan=True)
    text = md.read_text()
    assert "## Values" in text and "## Claims" in text
    table_lines = [line for line in text.splitlines() if line.startswith("| ") and "---" not in line]
    assert len(table_lines) == len(p1_table) + 2  # one header per table
    assert text.count(report.HOLDS) >= (p1_table["verdict"] == report.HOLDS).sum()
    assert "0.842" in text and "0.71" in text  # paper values


def test_all_nan_force_does_not_crash():
    measures = make_p1_measures()
    measures["2d_linear"]["mean_force"][:] = math.nan
    cut = report.f_max_cut(measures)
    assert math.isnan(cut.rho_max["2d_linear"]) and np.isfinite(cut.f_max)
    table = report.p1_validation(measures)
    assert len(table) > 0
