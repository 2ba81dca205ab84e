"""P2 reproduction logic: consecutive distances, stacking, Tables I–III, validation verdicts."""
from __future__ import annotations

import math

import numpy as np
import pandas as pd
import pytest
import xarray as xr

from forcenet.datasets import provenance_attrs, validate_dataset, write_netcdf, open_dataset
from forcenet.datasets.schema import FORCE_KINDS
from forcenet.datasets.snapshot import snapshot_dataset
from forcenet.report import p2

NEVER = None  # a class that never dies


# --- factories -------------------------------------------------------------------------------------------------------
def analysis_factory(rho: float, z: float, diagrams: dict) -> xr.Dataset:
    """A per-snapshot analysis with only what the distances read: {(kind, dim): [(birth, death | NEVER)]}."""
    kind, dim, birth, death = [], [], [], []
    for (k, h), points in diagrams.items():
        for b, d in points:
            kind.append(FORCE_KINDS.index(k))
            dim.append(h)
            birth.append(b)
            death.append(-np.inf if d is NEVER else d)
    death = np.asarray(death, dtype=float)
    return xr.Dataset({
        "diagram_force_kind": ("point", np.asarray(kind, dtype=np.int32)),
        "diagram_homology_dim": ("point", np.asarray(dim, dtype=np.int32)),
        "birth": ("point", np.asarray(birth, dtype=float)),
        "death": ("point", death),
        "essential": ("point", (~np.isfinite(death)).astype(np.int8)),
        "rho": ((), rho), "Z": ((), z),
    })


# P2 §III D worked example (Fig. 5): PD0(f) = {(5, -1)}, PD0(g) = {(3, -1)} + 7 x (1, 0)
PD0_F = [(5.0, NEVER)]
PD0_G = [(3.0, NEVER)] + [(1.0, 0.0)] * 7
WORKED = {"bottleneck": 2.0, "wasserstein_1": 5.5, "wasserstein_2": math.sqrt(4 + 7 * 0.25)}


def worked_example_analyses(z0=2.5, rhos=(0.70, 0.71, 0.72)):
    first = analysis_factory(rhos[0], z0, {("normal", 0): PD0_F, ("normal", 1): [(2.0, 1.0)],
                                           ("tangential", 0): PD0_G})
    second = analysis_factory(rhos[1], z0 + 0.1, {("normal", 0): PD0_G, ("tangential", 0): PD0_G})
    third = analysis_factory(rhos[2], z0 + 0.2, {("normal", 0): PD0_G, ("tangential", 0): PD0_F})
    return [first, second, third]


# --- consecutive distances -------------------------------------------------------------------------------------------
def test_consecutive_distances_reproduce_the_worked_example():
    ds = p2.consecutive_distances(worked_example_analyses())
    assert ds["distance"].dims == ("rho", "force_kind", "homology_dim", "metric")
    np.testing.assert_allclose(ds["rho"], [0.71, 0.72])
    np.testing.assert_allclose(ds["rho_previous"], [0.70, 0.71])
    np.testing.assert_allclose(ds["Z"], [2.6, 2.7])
    for metric, value in WORKED.items():
        pair1 = ds["distance"].sel(rho=0.71, metric=metric)
        pair2 = ds["distance"].sel(rho=0.72, metric=metric)
        assert float(pair1.sel(force_kind="normal", homology_dim=0)) == pytest.approx(value, rel=1e-6)
        assert float(pair1.sel(force_kind="tangential", homology_dim=0)) == pytest.approx(0.0, abs=1e-9)
        assert float(pair2.sel(force_kind="normal", homology_dim=0)) == pytest.approx(0.0, abs=1e-9)
        assert float(pair2.sel(force_kind="tangential", homology_dim=0)) == pytest.approx(value, rel=1e-6)
        # PD1 {(2, 1)} against an empty diagram: the point goes to the diagonal, (2 - 1)/2 = 0.5 in L-infinity
        assert float(pair1.sel(force_kind="normal", homology_dim=1)) == pytest.approx(0.5, rel=1e-6)
        assert float(pair2.sel(force_kind="normal", homology_dim=1)) == pytest.approx(0.0, abs=1e-9)
    assert ds.attrs["essential_convention"] == "minus_one"
    assert "-1" in ds.attrs["essential_convention_description"]


def test_bottleneck_below_wasserstein_and_ratio_reductions():
    ds = p2.consecutive_distances(worked_example_analyses())
    d = ds["distance"].sel(force_kind="normal", homology_dim=0, rho=0.71)
    assert float(d.sel(metric="bottleneck")) <= float(d.sel(metric="wasserstein_2")) <= float(
        d.sel(metric="wasserstein_1"))
    ratio = p2.distance_ratio(ds, "wasserstein_1").sel(force_kind="normal", homology_dim=0, rho=0.71)
    assert float(ratio) == pytest.approx(2 / 5.5, rel=1e-6)


def test_consecutive_distances_reject_unordered_or_single_snapshots():
    analyses = worked_example_analyses()
    with pytest.raises(ValueError, match="increasing"):
        p2.consecutive_distances([analyses[1], analyses[0]])
    with pytest.raises(ValueError, match="two snapshots"):
        p2.consecutive_distances(analyses[:1])


# --- stacking --------------------------------------------------------------------------------------------------------
def stacked_worked_example(n_realizations=2):
    per = [p2.consecutive_distances(worked_example_analyses(z0=2.5 + 0.01 * r,
                                                            rhos=(0.70, 0.71 + 1e-4 * r, 0.72)))
           for r in range(n_realizations)]
    attrs = provenance_attrs(system="2d_poly_mu05", realization=-1, seed=1, config={}, title="P2 distances")
    return p2.stack_distances(per, list(range(n_realizations)), attrs)


def test_stack_distances_dims_attrs_and_round_trip(tmp_path):
    ds = stacked_worked_example()
    assert ds["distance"].dims == ("realization", "rho", "force_kind", "homology_dim", "metric")
    assert ds["Z"].dims == ("realization", "rho")
    assert list(ds["force_kind"].values) == ["normal", "tangential"]
    assert list(ds["homology_dim"].values) == [0, 1]
    assert list(ds["metric"].values) == list(p2.METRICS)
    assert list(ds["realization"].values) == [0, 1]
    np.testing.assert_allclose(ds["rho_measured"].sel(realization=1), [0.7101, 0.72])
    assert ds.attrs["essential_convention"] == "minus_one" and ds.attrs["system"] == "2d_poly_mu05"
    for name, var in ds.variables.items():
        assert var.attrs.get("units") and var.attrs.get("long_name"), name
    validate_dataset(ds)
    back = open_dataset(write_netcdf(ds, tmp_path / "distances.nc"))
    xr.testing.assert_allclose(back["distance"], ds["distance"])
    assert back.attrs["essential_convention"] == "minus_one"


def test_stack_distances_refuses_mismatched_grids():
    a = p2.consecutive_distances(worked_example_analyses())
    shifted = p2.consecutive_distances(worked_example_analyses(rhos=(0.70, 0.75, 0.80)))
    with pytest.raises(ValueError, match="differ"):
        p2.stack_distances([a, shifted], [0, 1], {})
    with pytest.raises(ValueError, match="numbers of snapshot pairs"):
        p2.stack_distances([a, p2.consecutive_distances(worked_example_analyses()[:2])], [0, 1], {})
    with pytest.raises(ValueError, match="duplicate"):
        p2.stack_distances([a, a], [3, 3], {})


# --- table snapshots -------------------------------------------------------------------------------------------------
GRID = np.round(np.linspace(0.63, 0.90, 28), 4)


@pytest.mark.parametrize("table_rho, expected", [(0.79, (0.78, 0.79, 0.80)), (0.7912, (0.78, 0.79, 0.80)),
                                                 (0.60, (0.63, 0.64, 0.65)), (0.95, (0.88, 0.89, 0.90))])
def test_select_table_snapshots(table_rho, expected):
    a, b, c = p2.select_table_snapshots(GRID, table_rho)
    np.testing.assert_allclose(GRID[[a, b, c]], expected)
    shuffled = np.random.default_rng(3).permutation(GRID)
    a, b, c = p2.select_table_snapshots(shuffled, table_rho)
    np.testing.assert_allclose(shuffled[[a, b, c]], expected)


def test_select_table_snapshots_needs_three_distinct():
    with pytest.raises(ValueError):
        p2.select_table_snapshots([0.7, 0.8], 0.79)
    with pytest.raises(ValueError):
        p2.select_table_snapshots([0.7, 0.8, 0.8], 0.79)


# --- Tables I–III on a constructed network ---------------------------------------------------------------------------
SIDE = 12  # particles per side of a square lattice; quadrants are 6 x 6


def lattice_snapshot(forces: np.ndarray, rho: float, offset=(0.0, 0.0)) -> xr.Dataset:
    """Square lattice of touching unit disks in [0, SIDE]^2 with nearest-neighbour contacts."""
    ix, iy = np.meshgrid(np.arange(SIDE), np.arange(SIDE), indexing="ij")
    position = np.stack([ix.ravel() + 0.5, iy.ravel() + 0.5], axis=1) + np.asarray(offset)
    ci, cj = lattice_contacts()
    direction = position[cj] - position[ci]
    direction /= np.linalg.norm(direction, axis=1, keepdims=True)
    n = len(position)
    zeros2 = np.zeros((0, 2))
    return snapshot_dataset(
        attrs={"system": "test"}, position=position, radius=np.full(n, 0.5), velocity=np.zeros((n, 2)),
        angular_velocity=np.zeros(n), contact_i=ci, contact_j=cj, force_normal=-forces[:, None] * direction,
        force_tangential=0.1 * forces[:, None] * direction[:, ::-1] * [1, -1],
        wall_contact_particle=np.zeros(0), wall_contact_wall=np.zeros(0), wall_contact_force=zeros2,
        box_lo=np.asarray(offset, float), box_hi=np.asarray(offset, float) + SIDE, rho=rho, Z=4.0,
        kinetic_energy=0.0, pressure=1.0, time=0.0, step=0, relaxation_steps=-1)


def lattice_contacts():
    index = np.arange(SIDE * SIDE).reshape(SIDE, SIDE)
    ci = np.concatenate([index[:-1, :].ravel(), index[:, :-1].ravel()])
    cj = np.concatenate([index[1:, :].ravel(), index[:, 1:].ravel()])
    return ci, cj


def lattice_forces_and_quadrants():
    """Forces periodic with the quadrant (each quadrant holds the same landscape) and, per contact, the quadrant
    holding both its ends (None for contacts across a dividing line)."""
    ci, cj = lattice_contacts()
    half = SIDE // 2
    x, y = np.divmod(np.arange(SIDE * SIDE), SIDE)
    table = np.random.default_rng(11).uniform(0.2, 3.0, size=(half, half, 2))
    orientation = (y[cj] != y[ci]).astype(int)
    forces = table[x[ci] % half, y[ci] % half, orientation]
    names = {(0, 0): "bottom left", (1, 0): "bottom right", (1, 1): "top right", (0, 1): "top left"}
    qi = list(zip(x[ci] // half, y[ci] // half))
    qj = list(zip(x[cj] // half, y[cj] // half))
    quadrant = np.array([names[a] if a == b else None for a, b in zip(qi, qj)], dtype=object)
    return forces, quadrant


def permuted(forces, quadrant, where):
    """The same permutation of the interior contacts' forces in each quadrant of `where` (means unchanged)."""
    out = forces.copy()
    for name in where:
        idx = np.flatnonzero(quadrant == name)
        out[idx] = forces[idx][np.random.default_rng(5).permutation(len(idx))]
    return out


@pytest.fixture(scope="module")
def quadrant_tables():
    forces, quadrant = lattice_forces_and_quadrants()
    result = {}
    for changed in ("bottom left", "top right"):
        snaps = [lattice_snapshot(forces, 0.78),
                 lattice_snapshot(permuted(forces, quadrant, [changed]), 0.79, offset=(3.0, -2.0)),
                 lattice_snapshot(permuted(forces, quadrant, p2.QUADRANTS), 0.80)]
        result[changed] = p2.p2_tables(snaps, remove_rattlers=False)
    return result


@pytest.mark.parametrize("changed", ["bottom left", "top right"])
def test_quadrant_tables_localise_a_change_in_one_quadrant(quadrant_tables, changed):
    tables = quadrant_tables[changed]
    assert list(tables["table1"].index) == list(p2.TABLE_PAIRS)
    assert list(tables["table2"].index) == list(p2.QUADRANTS)
    assert list(tables["table1"].columns) == [p2.table_column(h, m) for h in (0, 1) for m in p2.METRICS]
    table2, table3 = tables["table2"], tables["table3"]
    assert (table2.loc[changed] > 0).all()
    others = table2.drop(index=changed)
    np.testing.assert_allclose(others.to_numpy(), 0.0, atol=1e-9)  # translated box: quadrants follow the walls
    # every quadrant holds the same landscape and the same change: identical rows
    np.testing.assert_allclose(table3.to_numpy(), np.repeat(table3.to_numpy()[:1], 4, axis=0), rtol=1e-6)
    # (a, c) changes all four quadrants, (a, b) only one: larger over the whole box
    assert (tables["table1"].loc["(a,c)"] >= tables["table1"].loc["(a,b)"] - 1e-9).all()
    verdicts = p2.p2_validation({}, tables).set_index("claim_id")["verdict"]
    assert verdicts["III.D-3"] == p2.HOLDS and verdicts["III.D-4"] == p2.HOLDS


def test_table_writer_csv_and_markdown(quadrant_tables, tmp_path):
    tables = quadrant_tables["bottom left"]
    p2.write_table(tables["table2"], tmp_path / "t2.csv", tmp_path / "t2.md")
    back = p2.read_table(tmp_path / "t2.csv")
    pd.testing.assert_frame_equal(back, tables["table2"], check_names=False)
    assert back.attrs["rho_b"] == pytest.approx(0.79)
    md = (tmp_path / "t2.md").read_text()
    assert "β0 d_B" in md and "β1 d_W2" in md and "bottom left" in md and "rho_a = 0.7800" in md
    written = p2.write_p2_tables(tables, tmp_path / "tables")
    assert sorted(p.name for p in written) == sorted(f"p2_table{k}.{e}" for k in (1, 2, 3) for e in ("csv", "md"))
    assert list(p2.read_table(tmp_path / "tables" / "p2_table1.csv").index) == list(p2.TABLE_PAIRS)


# --- validation: P2's own tables and synthetic curves ----------------------------------------------------------------
def paper_tables() -> dict[str, pd.DataFrame]:
    """P2's printed Tables I–III (test data: the criteria must accept the paper's own numbers)."""
    cols = [p2.table_column(h, m) for h in (0, 1) for m in p2.METRICS]
    t1 = pd.DataFrame([[0.089, 4.18, 0.50, 0.081, 3.8, 0.57], [0.12, 14.0, 0.89, 0.15, 19.2, 0.99]],
                      index=list(p2.TABLE_PAIRS), columns=cols)
    t2 = pd.DataFrame([[0.12, 3.6, 0.50, 0.16, 3.66, 0.95], [0.014, 0.40, 0.070, 0.014, 0.43, 0.037],
                       [0.0046, 0.58, 0.35, 0.0055, 0.29, 0.024], [0.0076, 0.56, 0.31, 0.0045, 0.23, 0.019]],
                      index=list(p2.QUADRANTS), columns=cols)
    t3 = pd.DataFrame([[0.16, 4.1, 0.53, 0.13, 5.8, 0.59], [0.18, 5.2, 0.67, 0.14, 5.6, 0.50],
                       [0.10, 5.1, 0.69, 0.12, 5.5, 0.51], [0.11, 4.3, 0.53, 0.087, 5.1, 0.87]],
                      index=list(p2.QUADRANTS), columns=cols)
    return {"table1": t1, "table2": t2, "table3": t3}


def verdicts(distances=None, tables=None, **kw) -> pd.Series:
    return p2.p2_validation(distances or {}, tables, **kw).set_index("claim_id")["verdict"]


def test_table_claims_hold_on_p2_numbers_and_flip_when_swapped():
    v = verdicts(tables=paper_tables())
    assert [v[c] for c in ("III.D-1", "III.D-2", "III.D-3", "III.D-4")] == [p2.HOLDS] * 4
    t = paper_tables()
    swapped = verdicts(tables={"table1": t["table1"].iloc[::-1].set_axis(list(p2.TABLE_PAIRS)),
                               "table2": t["table3"], "table3": t["table2"]})
    assert swapped["III.D-3"] == p2.FAILS and swapped["III.D-4"] == p2.FAILS and swapped["III.D-2"] == p2.FAILS


RHO = np.round(np.arange(0.63, 0.9001, 0.005), 4)
J = 0.78  # rho_J of the frictional shapes below (P2 Fig. 6: Z ≈ 3 near 0.78)


def frictional_shapes(x, *, peak=0.70, loop_peak=0.77, ratio_w1=0.2, ratio_w2=0.75, after=1.0):
    """{(dim, metric): curve} over x (rho of the frictional system) shaped as P2 §IV A describes."""
    pre, late, jammed = x < 0.75, (x >= 0.75) & (x < J), x >= J
    d_b0 = np.where(x < peak, 16 + 9 * (x - 0.63) / (peak - 0.63), 25 - 10 * (x - peak) / (0.75 - peak))
    d_b0 = np.where(late, 4.0, np.where(jammed, 1e-3 * after, d_b0))
    r2_0 = np.where(x < J - 0.02, ratio_w2, np.where(jammed, 0.1 * ratio_w2, 0.2))
    r1_0 = np.where(pre, ratio_w1, np.where(late, ratio_w1 * np.exp(-(x - 0.75) / 0.01), 1e-3 * ratio_w1))
    d_b1 = np.where(x <= loop_peak, 1 + 10 * np.clip(x - 0.63, 0, None) / (loop_peak - 0.63),
                    11 - 5 * (x - loop_peak) / (J - loop_peak))
    d_b1 = np.where(jammed, 1e-4 * after, d_b1)
    decay = np.exp(-np.clip(x - 0.76, 0, None) / 0.01)
    r2_1 = np.where(jammed, 0.05, 0.5 * decay)
    r1_1 = np.where(jammed, 1e-4, 0.1 * decay)
    return {(0, "bottleneck"): d_b0, (0, "wasserstein_1"): d_b0 / r1_0, (0, "wasserstein_2"): d_b0 / r2_0,
            (1, "bottleneck"): d_b1, (1, "wasserstein_1"): d_b1 / r1_1, (1, "wasserstein_2"): d_b1 / r2_1}


def p2_shaped(*, frictionless=False, rho_j=None, tangential="track", n_realizations=3, seed=0, **shape):
    """A distances dataset whose curves follow P2's description: frictional (mu = 0.5, rho_J = 0.78) or, with
    `frictionless`, the mu = 0 system (rho_J = 0.80, curves shifted by 0.02 and rescaled as P2 §IV C says)."""
    rho_j = rho_j if rho_j is not None else (0.80 if frictionless else J)
    x = RHO - (rho_j - J)  # the frictional-equivalent density
    if frictionless:
        curves = frictional_shapes(x, peak=0.72, **shape)
        before = x < J
        s = np.where(x < 0.65, 1.0, 1 / 1.3)  # component peaks 30 % lower without friction (§V)
        curves[0, "bottleneck"] = np.where(before, curves[0, "bottleneck"] * s, curves[0, "bottleneck"])
        curves[0, "wasserstein_2"] = np.where(before, curves[0, "wasserstein_2"] * s, curves[0, "wasserstein_2"])
        curves[0, "wasserstein_1"] = curves[0, "wasserstein_1"] * 0.6 * np.where(before, 1.0, 1.17)
        g = np.where(x < 0.75, 0.4, np.where(before, 4.0, 2.0))  # loops: slower, then much faster, then 2x
        for m in p2.METRICS:
            curves[1, m] = curves[1, m] * g
    else:
        curves = frictional_shapes(x, **shape)
    rng = np.random.default_rng(seed)
    values = np.empty((n_realizations, RHO.size, 2, 2, 3))
    near = np.abs(RHO - rho_j) <= 0.02
    for r in range(n_realizations):
        for h in (0, 1):
            for k, m in enumerate(p2.METRICS):
                noise = np.exp(0.05 * rng.standard_normal((2, RHO.size)))
                base = curves[h, m]
                values[r, :, 0, h, k] = base * noise[0]
                other = base[::-1] if tangential == "reversed" else base
                if not frictionless and m != "bottleneck":
                    other = np.where(near, 0.2 * other, other)  # §IV B: smaller d_W near rho_J
                values[r, :, 1, h, k] = other * noise[1]
    z = 3.0 + 1.5 * np.tanh((RHO - rho_j) / 0.02)
    return xr.Dataset(
        {"distance": (("realization", "rho", "force_kind", "homology_dim", "metric"), values),
         "Z": (("realization", "rho"), np.tile(z, (n_realizations, 1)))},
        coords={"realization": np.arange(n_realizations), "rho": RHO, "force_kind": ["normal", "tangential"],
                "homology_dim": [0, 1], "metric": list(p2.METRICS)},
        attrs={"essential_convention": "minus_one", "dimension": 2})


def both_systems(**frictional_options):
    return {p2.FRICTIONAL: p2_shaped(**frictional_options), p2.FRICTIONLESS: p2_shaped(frictionless=True)}


def test_data_shaped_as_p2_describes_satisfy_every_claim():
    table = p2.p2_validation(both_systems(), paper_tables())
    failing = table[table["verdict"] != p2.HOLDS]
    assert failing.empty, failing[["claim_id", "measured", "verdict"]].to_string()


@pytest.mark.parametrize("claim_id, options", [
    ("IV.A-3", {"ratio_w2": 0.3}),
    ("IV.A-4", {"ratio_w1": 0.05}),
    ("IV.A-8", {"loop_peak": 0.66}),
    ("IV.A-9", {"loop_peak": 0.72}),
    ("IV.A-11a", {"after": 3000.0}),
    ("IV.B-1", {"tangential": "reversed"}),
    ("IV.C-1", {"rho_j": 0.83}),
    ("V-1", {"ratio_w1": 0.02}),
])
def test_verdicts_flip_when_the_data_violate_a_claim(claim_id, options):
    good = verdicts(both_systems())
    assert good[claim_id] == p2.HOLDS
    bad = verdicts(both_systems(**options))
    assert bad[claim_id] == p2.FAILS


def test_missing_system_is_not_evaluated():
    alone = p2.p2_validation({p2.FRICTIONAL: p2_shaped()}).set_index("claim_id")
    assert alone.loc["IV.C-1", "verdict"] == p2.NOT_EVALUATED
    assert "not in the results" in alone.loc["IV.C-1", "measured"]
    assert alone.loc["IV.A-3", "verdict"] == p2.HOLDS
    assert alone.loc["III.D-1", "verdict"] == p2.NOT_EVALUATED


def test_jamming_density_from_z_crossing():
    assert p2.jamming_density(p2_shaped(rho_j=0.81)) == pytest.approx(0.81, abs=0.005)


def test_validation_markdown_lists_every_claim(tmp_path):
    table = p2.p2_validation(both_systems(), paper_tables())
    assert set(table["verdict"]) <= {p2.HOLDS, p2.FAILS, p2.NOT_EVALUATED}
    assert table["claim_id"].is_unique and len(table) == len(p2.CLAIMS)
    p2.write_p2_validation(table, tmp_path / "p2_validation.md", tmp_path / "p2_validation.csv")
    md = (tmp_path / "p2_validation.md").read_text()
    for claim_id in table["claim_id"]:
        assert f"| {claim_id} |" in md
    assert "value_factor = 1.5" in md and "2d_poly_mu0 " in md
