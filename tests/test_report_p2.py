"""P2 reproduction logic: consecutive distances, stacking, Tables I–III, validation verdicts."""
from __future__ import annotations

import math
import re

import numpy as np
import pandas as pd
import pytest
import xarray as xr

from contract import contract_attrs
from forcenet.datasets import provenance_attrs, validate_dataset, write_netcdf, open_dataset
from forcenet.datasets.schema import FORCE_KINDS, FORCE_UNITS
from forcenet.datasets.snapshot import snapshot_dataset
from forcenet.report import claims, p2, p2_claims, p2_distances, p2_explanations, p2_judging, p2_tables, p2_validation
from forcenet import systems

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
    }, coords={"force_kind": list(FORCE_KINDS)})  # what diagram_force_kind indexes, as in an analysis file


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
    ds = p2_distances.consecutive_distances(worked_example_analyses())
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


def test_consecutive_distances_pass_the_never_dying_convention_on():
    # "drop": PD0(f) = {} and PD0(g) = 7 x (1, 0) (the never-dying classes left out): each point to the diagonal
    ds = p2_distances.consecutive_distances(worked_example_analyses(), "drop")
    d = ds["distance"].sel(force_kind="normal", homology_dim=0, rho=0.71)
    np.testing.assert_allclose(d.sel(metric=list(WORKED)), [0.5, 3.5, math.sqrt(7 * 0.25)], rtol=1e-6)
    assert ds.attrs["essential_convention"] == "drop"


def test_ratio_reductions():
    ds = stacked_worked_example()
    ratio = p2.distance_ratio(ds, "wasserstein_1").sel(force_kind="normal", homology_dim=0)
    np.testing.assert_allclose(ratio.isel(rho=0), 2 / 5.5, rtol=1e-6)
    assert np.isnan(ratio.isel(rho=1)).all()  # identical diagrams: 0 / 0
    w2 = p2.distance_ratio(ds, "wasserstein_2").sel(force_kind="normal", homology_dim=0).isel(rho=0)
    np.testing.assert_allclose(w2, 2 / WORKED["wasserstein_2"], rtol=1e-6)
    # mean_distance_ratio: the ratio of the realization means (the curves of Figs 6, 8), not the mean of the ratios.
    # PD1 {(2, 1)} against {}: every distance 0.5; realization 1 scaled to d_B 1.5, d_W1 1.0
    distance = ds["distance"].copy()
    distance.loc[dict(realization=1, metric="bottleneck")] *= 3
    distance.loc[dict(realization=1, metric="wasserstein_1")] *= 2
    mean = p2.mean_distance_ratio(ds.assign(distance=distance), "wasserstein_1")
    assert float(mean.sel(force_kind="normal", homology_dim=1).isel(rho=0)) == pytest.approx(1.0 / 0.75)


def test_consecutive_distances_reject_unordered_or_single_snapshots():
    analyses = worked_example_analyses()
    with pytest.raises(ValueError, match="increasing"):
        p2_distances.consecutive_distances([analyses[1], analyses[0]])
    with pytest.raises(ValueError, match="two snapshots"):
        p2_distances.consecutive_distances(analyses[:1])


# --- stacking --------------------------------------------------------------------------------------------------------
def stacked_worked_example(n_realizations=2):
    per = [p2_distances.consecutive_distances(worked_example_analyses(z0=2.5 + 0.01 * r,
                                                            rhos=(0.70, 0.71 + 1e-4 * r, 0.72)))
           for r in range(n_realizations)]
    attrs = provenance_attrs(system="2d_poly_mu05", realization=-1, seed=1, config={}, title="P2 distances")
    return p2_distances.stack_distances(per, list(range(n_realizations)), attrs)


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
    a = p2_distances.consecutive_distances(worked_example_analyses())
    shifted = p2_distances.consecutive_distances(worked_example_analyses(rhos=(0.70, 0.75, 0.80)))
    with pytest.raises(ValueError, match="differ"):
        p2_distances.stack_distances([a, shifted], [0, 1], {})
    with pytest.raises(ValueError, match="numbers of snapshot pairs"):
        p2_distances.stack_distances([a, p2_distances.consecutive_distances(worked_example_analyses()[:2])], [0, 1], {})
    with pytest.raises(ValueError, match="duplicate"):
        p2_distances.stack_distances([a, a], [3, 3], {})


# --- table snapshots -------------------------------------------------------------------------------------------------
GRID = np.round(np.linspace(0.63, 0.90, 28), 4)


@pytest.mark.parametrize("table_rho, expected", [(0.79, (0.78, 0.79, 0.80)), (0.7912, (0.78, 0.79, 0.80)),
                                                 (0.60, (0.63, 0.64, 0.65)), (0.95, (0.88, 0.89, 0.90))])
def test_select_table_snapshots(table_rho, expected):
    a, b, c = systems.select_table_snapshots(GRID, table_rho)
    np.testing.assert_allclose(GRID[[a, b, c]], expected)
    shuffled = np.random.default_rng(3).permutation(GRID)
    a, b, c = systems.select_table_snapshots(shuffled, table_rho)
    np.testing.assert_allclose(shuffled[[a, b, c]], expected)


def test_select_table_snapshots_needs_three_distinct():
    with pytest.raises(ValueError):
        systems.select_table_snapshots([0.7, 0.8], 0.79)
    with pytest.raises(ValueError):
        systems.select_table_snapshots([0.7, 0.8, 0.8], 0.79)


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
        attrs=contract_attrs("snapshot"), position=position, radius=np.full(n, 0.5), velocity=np.zeros((n, 2)),
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
        result[changed] = p2_tables.p2_tables(snaps, remove_rattlers=False)
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
    verdicts = p2_validation.p2_validation({}, tables).set_index("claim_id")["verdict"]
    assert verdicts["III.D-3"] == claims.HOLDS and verdicts["III.D-4"] == claims.HOLDS


def test_table_writer_csv_and_markdown(quadrant_tables, tmp_path):
    tables = quadrant_tables["bottom left"]
    p2_tables.write_table(tables["table2"], tmp_path / "t2.csv", tmp_path / "t2.md")
    back = p2_tables.read_table(tmp_path / "t2.csv")
    pd.testing.assert_frame_equal(back, tables["table2"], check_names=False)
    assert back.attrs["rho_b"] == pytest.approx(0.79)
    md = (tmp_path / "t2.md").read_text()
    assert "β0 d_B" in md and "β1 d_W2" in md and "bottom left" in md and "rho_a = 0.7800" in md
    written = p2_tables.write_p2_tables(tables, tmp_path / "tables")
    assert sorted(p.name for p in written) == sorted(f"p2_table{k}.{e}" for k in (1, 2, 3) for e in ("csv", "md"))
    assert list(p2_tables.read_table(tmp_path / "tables" / "p2_table1.csv").index) == list(p2.TABLE_PAIRS)


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
    return p2_validation.p2_validation(distances or {}, tables, **kw).set_index("claim_id")["verdict"]


def test_table_claims_hold_on_p2_numbers():
    v = verdicts(tables=paper_tables())
    assert [v[c] for c in ("III.D-1", "III.D-2", "III.D-3", "III.D-4")] == [claims.HOLDS] * 4


RHO = np.round(np.arange(0.63, 0.9001, 0.005), 4)
J = 0.78  # rho_J of the frictional shapes below (P2 Fig. 6: Z ≈ 3 near 0.78)
B, W1, W2 = "bottleneck", "wasserstein_1", "wasserstein_2"


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
    return {(0, B): d_b0, (0, W1): d_b0 / r1_0, (0, W2): d_b0 / r2_0,
            (1, B): d_b1, (1, W1): d_b1 / r1_1, (1, W2): d_b1 / r2_1}


def p2_shaped(*, frictionless=False, rho_j=None, tangential="track", n_realizations=3, seed=0, modify=None,
              tangential_w_near=0.2, tangential_w_away=1.0, tangential_b=1.0, w1_factor=0.6,
              loop_factors=(0.4, 4.0, 2.0), **shape):
    """A distances dataset whose curves follow P2's description: frictional (mu = 0.5, rho_J = 0.78) or, with
    `frictionless`, the mu = 0 system (rho_J = 0.80, curves shifted by 0.02 and rescaled as P2 §IV C says).

    The factors are P2's numbers where it gives one (0.6, 1.3, 2) and otherwise values that fit its words
    ("much less" …). The keywords exist so that a test can violate one claim:
    - `modify(x, curves)`: changes the frictional-shaped curves {(dim, metric): values over x} in place (before
      the frictionless rescaling), x the frictional-equivalent density.
    - tangential (frictional system, P2 §IV B): `tangential="reversed"` mirrors the curves in rho; the tangential
      d_W1, d_W2 are `tangential_w_near` × the normal ones within 0.02 of rho_J ("significantly smaller") and
      `tangential_w_away` × elsewhere; the tangential d_B is `tangential_b` × the normal one ("similar").
    - frictionless (P2 §IV C): `w1_factor` = d_W1(mu=0) / d_W1(mu=0.5) for beta0, 0.6 ("≈ 40 % smaller", stated
      for rho < 0.65; P2 gives no other value, so it is used at every rho); `loop_factors` = beta1 rates mu=0 /
      mu=0.5 for rho < 0.75, [0.75, rho_J), after rho_J ("much less", "much more dramatically", "about twice").
    """
    rho_j = rho_j if rho_j is not None else (0.80 if frictionless else J)
    x = RHO - (rho_j - J)  # the frictional-equivalent density
    curves = frictional_shapes(x, **({"peak": 0.72, **shape} if frictionless else shape))
    if modify is not None:
        modify(x, curves)
    if frictionless:
        before = x < J
        s = np.where(x < 0.65, 1.0, 1 / 1.3)  # component peaks 30 % lower without friction (§V: 20-40 % higher with)
        curves[0, B] = np.where(before, curves[0, B] * s, curves[0, B])
        curves[0, W2] = np.where(before, curves[0, W2] * s, curves[0, W2])
        curves[0, W1] = curves[0, W1] * w1_factor
        below, close, after = loop_factors
        g = np.where(x < 0.75, below, np.where(before, close, after))
        for m in p2.METRICS:
            curves[1, m] = curves[1, m] * g
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
                if not frictionless:
                    factor = (np.full(RHO.size, tangential_b) if m == B
                              else np.where(near, tangential_w_near, tangential_w_away))
                    other = factor * other
                values[r, :, 1, h, k] = other * noise[1]
    z = 3.0 + 1.5 * np.tanh((RHO - rho_j) / 0.02)
    return xr.Dataset(
        {"distance": (("realization", "rho", "force_kind", "homology_dim", "metric"), values),
         "Z": (("realization", "rho"), np.tile(z, (n_realizations, 1)))},
        coords={"realization": np.arange(n_realizations), "rho": RHO, "force_kind": ["normal", "tangential"],
                "homology_dim": [0, 1], "metric": list(p2.METRICS)},
        attrs=contract_attrs("distances", system="2d_poly_mu0" if frictionless else "2d_poly_mu05"))


def pd1_diagrams(points_per_state, n_realizations: int = 3) -> xr.Dataset:
    """A diagrams.nc-shaped dataset with `points_per_state` normal-force PD1 points (and one PD0 point) in every
    state of `RHO` and realization (a function of rho: that many at each state)."""
    kind, dim, realization, rho = [], [], [], []
    count = points_per_state if callable(points_per_state) else (lambda x: points_per_state)
    for r in range(n_realizations):
        for x in RHO:
            points_per_state = int(count(x))
            kind += [FORCE_KINDS.index("normal")] * (points_per_state + 1)
            dim += [0] + [1] * points_per_state
            realization += [r] * (points_per_state + 1)
            rho += [x] * (points_per_state + 1)
    return xr.Dataset({"diagram_force_kind": ("point", np.array(kind)),
                       "diagram_homology_dim": ("point", np.array(dim)),
                       "point_realization": ("point", np.array(realization)), "point_rho": ("point", np.array(rho))},
                      coords={"force_kind": list(FORCE_KINDS)})


#: P2 §IV C: more PD1 points without friction than with it
DIAGRAMS = {p2.FRICTIONAL: pd1_diagrams(20), p2.FRICTIONLESS: pd1_diagrams(30)}


def both_systems(frictional=None, frictionless=None):
    return {p2.FRICTIONAL: p2_shaped(**(frictional or {})),
            p2.FRICTIONLESS: p2_shaped(frictionless=True, **(frictionless or {}))}


# --- modifications of the shaped curves (`p2_shaped(modify=...)`) --------------------------------------------------
def late(x):  # 0.75 <= rho < rho_J
    return (x >= 0.75) & (x < J)


def scaled(dim, metrics, factor, where):
    """Multiply the PD_dim curves of `metrics` by `factor` where `where(x)`."""
    def modify(x, curves):
        for m in metrics:
            curves[dim, m] = np.where(where(x), factor * curves[dim, m], curves[dim, m])
    return modify


def with_ratio(dim, denominator, ratio, where):
    """Set d_B / `denominator` of PD_dim to `ratio(x)` where `where(x)` (the Wasserstein curve follows d_B)."""
    def modify(x, curves):
        curves[dim, denominator] = np.where(where(x), curves[dim, B] / ratio(x), curves[dim, denominator])
    return modify


# The synthetic data contain the one number P2 gives for d_W1 with and without friction (mu=0 / mu=0.5 = 0.6,
# §IV C) at every rho. After jamming that contradicts V-2 ("the component rates become quite similar"; criterion:
# within value_factor = 1.5 of 1 for every metric), so V-2 is the one claim these data do not satisfy. (A factor
# near 0.7 would satisfy V-2 and IV.C-3 both, but P2 states no such number.)
SHAPED_DATA_FAIL = {"V-2"}


def test_data_shaped_as_p2_describes_satisfy_every_claim_but_v2():
    table = p2_validation.p2_validation(both_systems(), paper_tables(), diagrams=DIAGRAMS).set_index("claim_id")
    not_holding = table[table["verdict"] != claims.HOLDS]
    assert set(not_holding.index) == SHAPED_DATA_FAIL, not_holding[["evidence", "verdict"]].to_string()
    assert (not_holding["verdict"] == claims.FAILS).all()
    assert "d_W1 0.6" in table.loc["V-2", "evidence"]


def test_equal_w1_rates_satisfy_v2_but_not_iv_c3():
    # d_W1 equal with and without friction: the component rates after jamming are similar (V-2), but d_B/d_W1 is
    # no longer consistently larger for mu = 0 (IV.C-3)
    v = verdicts(both_systems(frictionless={"w1_factor": 1.0}), paper_tables())
    assert v["V-2"] == claims.HOLDS and v["IV.C-3"] == claims.FAILS


def table_variation(change):
    def tables():
        t = paper_tables()
        change(t)
        return t
    return tables


def swap_rows(t):
    t["table1"] = t["table1"].iloc[::-1].set_axis(list(p2.TABLE_PAIRS))


def larger_bottleneck(t):
    t["table1"][[p2.table_column(h, B) for h in (0, 1)]] *= 3


def even_table2(t):
    t["table2"] = t["table3"].copy()


def localised_table3(t):
    t["table3"] = t["table2"].copy()


def fails(*claim_ids: str) -> dict[str, str]:
    return dict.fromkeys(claim_ids, claims.FAILS)


def holds(*claim_ids: str) -> dict[str, str]:
    return dict.fromkeys(claim_ids, claims.HOLDS)


# One variation of the data per claim under which it does not hold: (claim, {"frictional": p2_shaped options,
# "frictionless": p2_shaped(frictionless=True) options, "tables": () -> Tables I-III, "diagrams": diagrams.nc},
# every other verdict it turns). A variation reaches the claims that read the same curve: a d_W1 peak ten times
# larger also moves V-1's peak quotient and IV.C-2's mu = 0 / mu = 0.5 quotient; no other verdict may move.
VIOLATIONS = [
    ("III.D-1", {"tables": table_variation(larger_bottleneck)}, {}),  # d_B(a,c) 0.36-0.45 > 0.15·1.5
    ("III.D-2", {"tables": table_variation(swap_rows)}, {}),  # d_W1 grows less than d_W2 from (a,b) to (a,c)
    ("III.D-3", {"tables": table_variation(even_table2)}, {}),  # (a,b) differences spread over all quadrants
    ("III.D-4", {"tables": table_variation(localised_table3)}, {}),  # (a,c) differences in one quadrant
    ("IV.A-1", {"frictional": {"modify": scaled(0, [W1], 10.0, lambda x: x < 0.70)}},  # d_W1 peaks at 0.70
     fails("IV.A-4", "IV.A-12a", "IV.C-2", "V-1")),
    ("IV.A-2", {"frictional": {"modify": scaled(0, p2.METRICS, 0.1, lambda x: x < J)}},  # d_B ≈ 2 before rho_J
     fails("IV.A-11a", "IV.C-2", "V-1")),
    ("IV.A-3", {"frictional": {"ratio_w2": 0.3}}, fails("IV.C-2", "IV.C-3", "V-1")),
    ("IV.A-4", {"frictional": {"ratio_w1": 0.05}}, fails("IV.C-2", "V-1")),
    ("IV.A-5", {"frictional": {"modify": scaled(0, p2.METRICS, 5.0, late)}},  # no drop of d_B at 0.75
     fails("IV.C-4", "V-1")),
    ("IV.A-6", {"frictional": {"modify": with_ratio(0, W1, lambda x: 0.2 * np.exp((x - 0.75) / 0.01), late)}},
     fails("IV.A-1", "IV.A-11a", "V-1")),
    ("IV.A-7", {"frictional": {"modify": with_ratio(0, W2, lambda x: 0.75, lambda x: x >= J - 0.02)}},  # no plunge
     fails("IV.A-12a")),
    ("IV.A-8", {"frictional": {"loop_peak": 0.66}}, fails("IV.A-9")),
    ("IV.A-9", {"frictional": {"loop_peak": 0.72}}, {}),
    ("IV.A-10", {"frictional": {"modify": with_ratio(1, W1, lambda x: 0.1 * np.exp((x - 0.76) / 0.01),
                                                     lambda x: (x >= 0.76) & (x < J))}}, {}),  # loop d_B/d_W1 rises
    ("IV.A-11a", {"frictional": {"after": 3000.0}}, fails("IV.A-1", "IV.C-4", "IV.C-6", "IV.C-7", "IV.C-9", "V-1")),
    ("IV.A-11b", {"frictionless": {"after": 3000.0}}, fails("IV.C-7", "V-1")),
    ("IV.A-12a", {"frictional": {"modify": with_ratio(0, W2, lambda x: 0.75, lambda x: x >= J)}}, {}),  # no drop
    ("IV.A-12b", {"frictional": {"modify": with_ratio(1, W1, lambda x: 0.1, lambda x: x >= J)}},  # no drop
     fails("IV.A-10", "IV.C-7")),
    ("IV.B-1", {"frictional": {"tangential": "reversed"}}, fails("IV.B-2", "IV.B-3", "IV.B-4")),
    ("IV.B-2", {"frictional": {"tangential_w_near": 1.0, "tangential_w_away": 0.2}},  # deviation away from rho_J
     fails("IV.B-3")),
    ("IV.B-3", {"frictional": {"tangential_w_near": 1.0}}, {}),  # tangential d_W as large as normal near rho_J
    ("IV.B-4", {"frictional": {"tangential_b": 3.0}}, {}),  # tangential d_B three times the normal one
    ("IV.C-1", {"frictional": {"rho_j": 0.83}}, fails("IV.A-5", "IV.A-6", "IV.A-9", "IV.C-5")),
    ("IV.C-2", {"frictionless": {"w1_factor": 1.5}},  # d_W1 larger without friction
     fails("IV.C-3", "V-1") | holds("V-2")),
    ("IV.C-3", {"frictionless": {"w1_factor": 1.0}}, holds("V-2")),  # d_B/d_W1 no longer larger for mu = 0
    ("IV.C-4", {"frictionless": {"peak": 0.68}}, {}),  # mu = 0 slows down earlier relative to its rho_J
    ("IV.C-5", {"frictionless": {"loop_factors": (2.0, 4.0, 2.0)}}, {}),  # loops change faster for mu = 0 early on
    ("IV.C-6", {"frictionless": {"loop_factors": (0.4, 1.0, 2.0)}}, {}),  # no stronger change near jamming
    ("IV.C-7", {"frictionless": {"loop_factors": (0.4, 4.0, 1.0)}}, fails("IV.C-9")),  # same loop rates after jamming
    # fewer PD1 points without friction below both rho_J (0.78, 0.80), more above: IV.C-8a fails, IV.C-8b holds
    ("IV.C-8a", {"diagrams": {p2.FRICTIONAL: pd1_diagrams(20),
                              p2.FRICTIONLESS: pd1_diagrams(lambda x: 10 if x < 0.78 else 30)}}, {}),
    # and the other way round: the regime above both rho_J alone fails
    ("IV.C-8b", {"diagrams": {p2.FRICTIONAL: pd1_diagrams(20),
                              p2.FRICTIONLESS: pd1_diagrams(lambda x: 30 if x < 0.80 else 10)}}, {}),
    # friction sets the components apart after jamming (4x, 0.6 decades) more than the loops (2x)
    ("IV.C-9", {"frictionless": {"modify": scaled(0, p2.METRICS, 0.25, lambda x: x >= J)}}, {}),
    ("V-1", {"frictional": {"ratio_w1": 0.02}}, fails("IV.A-4", "IV.C-2")),  # frictional d_W1 peak 10x larger
    ("V-2", {}, {}),  # the shaped data themselves (SHAPED_DATA_FAIL)
]


def test_every_claim_has_a_violating_variation():
    assert [claim_id for claim_id, _, _ in VIOLATIONS] == [c.id for c in p2_validation.CLAIMS]


@pytest.fixture(scope="module")
def shaped_verdicts():
    table = p2_validation.p2_validation(both_systems(), paper_tables(), diagrams=DIAGRAMS)
    return dict(zip(table["claim_id"], table["verdict"]))


@pytest.mark.parametrize("claim_id, variation, also_turned", VIOLATIONS, ids=[c for c, _, _ in VIOLATIONS])
def test_verdict_is_does_not_hold_when_the_data_violate_the_claim(claim_id, variation, also_turned,
                                                                   shaped_verdicts):
    tables = variation.get("tables", paper_tables)()
    data = both_systems(variation.get("frictional"), variation.get("frictionless"))
    table = p2_validation.p2_validation(data, tables, diagrams=variation.get("diagrams", DIAGRAMS))
    table = table.set_index("claim_id")
    assert table.loc[claim_id, "verdict"] == claims.FAILS, table.loc[claim_id, "evidence"]
    turned = {c: v for c, v in table["verdict"].items() if v != shaped_verdicts[c]}
    expected = {c: v for c, v in {claim_id: claims.FAILS, **also_turned}.items() if v != shaped_verdicts[c]}
    assert turned == expected, table.loc[list(set(turned) ^ set(expected)), ["verdict", "evidence"]].to_string()


def test_missing_system_is_not_evaluated():
    alone = p2_validation.p2_validation({p2.FRICTIONAL: p2_shaped()}).set_index("claim_id")
    assert alone.loc["IV.C-1", "verdict"] == claims.NOT_EVALUATED
    assert "not in the results" in alone.loc["IV.C-1", "evidence"]
    assert alone.loc["IV.A-3", "verdict"] == claims.HOLDS
    assert alone.loc["III.D-1", "verdict"] == claims.NOT_EVALUATED


# claims that read one normal-force curve: its argmax (IV.A-1, IV.A-9, IV.C-4), a ratio (IV.A-3, IV.C-3), a median
ALL_NAN_NOT_EVALUATED = {
    (p2.FRICTIONAL, 0, B): ["IV.A-2", "IV.A-3", "IV.C-3", "IV.C-4"],
    (p2.FRICTIONAL, 0, W1): ["IV.A-1", "IV.A-4", "IV.C-3"],
    (p2.FRICTIONAL, 1, B): ["IV.A-9", "IV.A-10"],
    (p2.FRICTIONLESS, 0, B): ["IV.C-2", "IV.C-3", "IV.C-4", "V-2"],
    (p2.FRICTIONLESS, 1, W2): ["IV.A-11b", "IV.C-5", "IV.C-7"],
}


@pytest.mark.parametrize("system, dim, metric", list(ALL_NAN_NOT_EVALUATED))
def test_all_nan_curve_is_not_evaluated(system, dim, metric):
    data = both_systems()
    data[system]["distance"].loc[dict(force_kind="normal", homology_dim=dim, metric=metric)] = np.nan
    table = p2_validation.p2_validation(data, paper_tables()).set_index("claim_id")
    for claim_id in ALL_NAN_NOT_EVALUATED[system, dim, metric]:
        assert table.loc[claim_id, "verdict"] == claims.NOT_EVALUATED, claim_id
        assert "0 finite rho value(s)" in table.loc[claim_id, "evidence"], claim_id


def test_after_jamming_windows_leave_out_rho_j():
    curves = p2_judging.Curves(p2.FRICTIONAL, p2_shaped(), 2, claims.ClaimTolerances(min_points=1))
    s = curves.mean("normal", 0, B)
    assert curves.window(s, lo=J).index.min() == pytest.approx(J)
    assert curves.window(s, lo=J, closed_lo=False).index.min() == pytest.approx(J + 0.005)
    assert curves.window(s, hi=J, closed_hi=True).index.max() == pytest.approx(J)
    with pytest.raises(claims.NotEvaluated, match=r"0 finite rho value\(s\) in \(0.900, inf\)"):
        curves.window(s, lo=0.9, closed_lo=False)


def test_a_window_of_infinite_distances_says_why_it_cannot_be_judged():
    # the 'apart' convention: consecutive diagrams with different numbers of never-dying classes are infinitely far
    curves = p2_judging.Curves(p2.FRICTIONAL, p2_shaped(), 2, claims.ClaimTolerances(min_points=2))
    s = curves.mean("normal", 0, B)
    s[s.index > J] = np.inf
    with pytest.raises(claims.NotEvaluated, match=r"0 finite rho value\(s\) .*; \d+ infinite there \(different "
                       r"numbers of never-dying classes\)"):
        curves.window(s, lo=J, closed_lo=False)
    with pytest.raises(claims.NotEvaluated) as finite_only:
        curves.window(s, lo=0.9, closed_lo=False)
    assert "infinite" not in str(finite_only.value)  # no state there at all: nothing infinite to name


def test_jamming_density_from_z_crossing():
    assert p2.jamming_density(p2_shaped(rho_j=0.81)) == pytest.approx(0.81, abs=0.005)


def test_validation_markdown_lists_every_claim(tmp_path):
    table = p2_validation.p2_validation(both_systems(), paper_tables(), diagrams=DIAGRAMS)
    p2_validation.write_p2_validation(table, tmp_path / "p2_validation.csv", tmp_path / "p2_validation.md")
    md = (tmp_path / "p2_validation.md").read_text()
    n = len(p2_validation.CLAIMS)
    assert f"{n} rows: {n - len(SHAPED_DATA_FAIL)} hold, {len(SHAPED_DATA_FAIL)} do not hold, 0 not evaluated" in md
    rows = {line.split(" | ")[0].removeprefix("| "): line for line in md.splitlines() if line.startswith("| ")}
    for claim_id, verdict, why, basis, changed in zip(table["claim_id"], table["verdict"], table["explanation"],
                                                      table["explanation_basis"], table["judge_changed_after_reading"]):
        assert f"| {verdict} |" in rows[claim_id], rows[claim_id]
        assert rows[claim_id].endswith(f"| {why} | {basis} | {changed} |"), rows[claim_id]
    assert f"| {p2.FRICTIONAL} | 3 | {RHO.size} | 0.630–0.900 | 0.78 | minus_one |" in md
    assert "value_factor = 1.5" in md and "2d_poly_mu0 " in md
    back = pd.read_csv(tmp_path / "p2_validation.csv")
    assert list(back.columns) == list(p2_validation.VALIDATION_COLUMNS) and list(back["verdict"]) == list(table["verdict"])
    assert back["measured"].dtype == float  # a number, as in P1's table; the evidence text has its own column


# --- rattlers (P2 §III C) ----------------------------------------------------------------------------------------
def small_snapshot(rattler_forces=(), realization=0, rho=0.79, z=2.0, scale=1.0):
    """Particles 0-1-2 a triangle (forces 3, 2, 1), particle 3 touches 0 only (one contact: a rattler by P1's
    rule) with force `rattler_forces[0]` if given, particle 4 touches nothing."""
    position = np.array([[0.0, 0.0], [1.0, 0.0], [0.5, 0.87], [-1.0, 0.0], [3.0, 3.0]])
    ci, cj, f = [0, 1, 0], [1, 2, 2], [3.0, 2.0, 1.0]
    for force in rattler_forces:
        ci, cj, f = ci + [0], cj + [3], f + [force]
    ci, cj, f = np.array(ci), np.array(cj), scale * np.array(f)
    direction = position[cj] - position[ci]
    direction /= np.linalg.norm(direction, axis=1, keepdims=True)
    n = len(position)
    return snapshot_dataset(
        attrs=contract_attrs("snapshot", realization=realization), position=position, radius=np.full(n, 0.5),
        velocity=np.zeros((n, 2)), angular_velocity=np.zeros(n), contact_i=ci, contact_j=cj,
        force_normal=-f[:, None] * direction, force_tangential=np.zeros((len(f), 2)),
        wall_contact_particle=np.zeros(0), wall_contact_wall=np.zeros(0), wall_contact_force=np.zeros((0, 2)),
        box_lo=np.zeros(2), box_hi=np.full(2, 4.0), rho=rho, Z=z, kinetic_energy=0.0, pressure=1.0, time=0.0,
        step=0, relaxation_steps=-1)


def test_kept_rattlers_are_components_born_at_the_zero_level():
    snap = small_snapshot()  # forces 3, 2, 1 have mean 2: the triangle's births are 1.5, 1, 0.5 in <F>
    kept = p2_distances.snapshot_diagrams(snap, "normal", "none")
    pd0 = kept.points(0)
    # the triangle (born at its largest force 3/2) and the isolated particles 3 and 4, born at zero; all never die
    assert sorted(map(tuple, pd0.tolist())) == [(0.0, -np.inf), (0.0, -np.inf), (1.5, -np.inf)]
    removed = p2_distances.snapshot_diagrams(snap, "normal", "once")
    assert removed.points(0).tolist() == [[1.5, -np.inf]]
    # P2's convention: a zero-level component that joins the network costs d_B = 1/2 (its (0, -1) point goes to
    # the diagonal), and nothing when rattlers are removed (force 2 keeps <F> = 2: the triangle is unchanged)
    joined = small_snapshot(rattler_forces=(2.0,))
    for rule, expected in (("none", 0.5), ("once", 0.0)):
        d = p2_distances.pair_distances(p2_distances.snapshot_diagrams(snap, "normal", rule), p2_distances.snapshot_diagrams(joined, "normal", rule),
                          0, "minus_one")
        assert d["bottleneck"] == pytest.approx(expected, abs=1e-6), rule


def test_tables_record_the_rattler_rule_and_realization():
    snaps = [small_snapshot(rho=r, realization=2) for r in (0.78, 0.79, 0.80)]
    tables = p2_tables.p2_tables(snaps, remove_rattlers=False)
    assert tables["table1"].attrs["rattler_rule"] == "none" and tables["table1"].attrs["realization"] == 2
    md = p2_tables.table_markdown(tables["table1"])
    assert "realization 2" in md and "rattler rule 'none'" in md


# --- P2's printed tables beside ours ------------------------------------------------------------------------------
def test_tables_print_p2_values_beside_ours_with_the_ratio(quadrant_tables, tmp_path):
    tables = quadrant_tables["bottom left"]
    written = p2_tables.write_p2_tables(tables, tmp_path)
    md = (tmp_path / "p2_table1.md").read_text()
    rows = {line.split(" | ")[0].removeprefix("| "): line.split(" | ")[1:] for line in md.splitlines()
            if line.startswith("| (a")}
    assert rows["(a,b), P2"][0] == "0.089" and rows["(a,c), P2"][1] == "14"  # P2 Table I, β0 d_B and d_W1
    ours = tables["table1"].loc["(a,b)", "beta0_d_B"]
    assert float(rows["(a,b), ours / P2"][0]) == pytest.approx(ours / 0.089, rel=0.01)
    csv = pd.read_csv(tmp_path / "p2_table3.csv", index_col=0)
    assert csv.loc["top left", "p2_beta1_d_W2"] == pytest.approx(0.87)  # P2 Table III
    np.testing.assert_allclose(csv["ratio_beta0_d_W1"], csv["beta0_d_W1"] / csv["p2_beta0_d_W1"])
    back = p2_tables.read_table(tmp_path / "p2_table3.csv")  # our values only
    pd.testing.assert_frame_equal(back, tables["table3"], check_names=False)
    assert len(written) == 6


def test_p2_reference_tables_have_our_layout():
    for name in ("table1", "table2", "table3"):
        ref = p2_tables.p2_reference_table(name)
        assert list(ref.columns) == [p2.table_column(h, m) for h in (0, 1) for m in p2.METRICS]
        assert list(ref.index) == list(p2.TABLE_PAIRS if name == "table1" else p2.QUADRANTS)


# --- which realization gives a, b, c ------------------------------------------------------------------------------
def state_analysis(realization, rho, z, mean_normal_force, units=FORCE_UNITS):
    ds = analysis_factory(rho, z, {})
    ds["mean_force"] = ("force_kind", np.array([2.0, mean_normal_force, 0.5]), {"units": units})
    ds.attrs["realization"] = realization
    return ds


def test_the_table_states_name_the_unit_of_their_mean_forces(tmp_path):
    """The mean normal forces of a, b, c carry their analyses' unit in their column names: the reduced unit of a DEM
    run, the source's (its `units:` block) for an import; the CSV read back gives the same ratios."""
    rhos = (0.788, 0.791, 0.794)
    dem = p2_tables.table_state_candidates([state_analysis(0, r, 3.0, f) for r, f in zip(rhos, (1.0, 1.5, 2.0))])
    assert list(dem.columns) == ["realization", "rho_a", "rho_b", "rho_c", "Z_a", "Z_b", "Z_c",
                                 "mean_normal_force_a [m_mean d_ave tau_c-2]",
                                 "mean_normal_force_b [m_mean d_ave tau_c-2]",
                                 "mean_normal_force_c [m_mean d_ave tau_c-2]", "Z_change", "force_change", "score",
                                 "chosen"]
    imported = p2_tables.table_state_candidates([state_analysis(0, r, 3.0, f, units="N")
                                                 for r, f in zip(rhos, (1.0, 1.5, 2.0))])
    assert [c for c in imported.columns if c.startswith("mean_normal")] == [
        "mean_normal_force_a [N]", "mean_normal_force_b [N]", "mean_normal_force_c [N]"]
    imported.to_csv(tmp_path / "states.csv", index=False)
    row = pd.read_csv(tmp_path / "states.csv").iloc[0]
    assert [p2_tables.state_mean_force(row, x) for x in "abc"] == [1.0, 1.5, 2.0]
    with pytest.raises(ValueError, match=r"mean forces are in 2 units \(N, m_mean d_ave tau_c-2\), need one"):
        p2_tables.table_state_candidates([state_analysis(0, r, 3.0, 1.0, units=u)
                                          for r, u in zip(rhos, ("N", "N", FORCE_UNITS))])


def test_table_states_pick_the_realization_whose_z_and_force_change_least():
    rhos = (0.788, 0.791, 0.794)
    analyses = [state_analysis(0, r, z, f) for r, z, f in zip(rhos, (2.8, 2.9, 3.0), (1.0, 1.5, 2.0))]  # ⟨F⟩ +100 %
    analyses += [state_analysis(1, r, z, f) for r, z, f in zip(rhos, (3.2, 3.21, 3.22), (1.0, 1.01, 1.03))]  # quiet
    analyses += [state_analysis(2, r, z, f) for r, z, f in zip(rhos, (3.2, 3.5, 3.6), (1.0, 1.0, 1.0))]  # Z +12 %
    table = p2_tables.table_state_candidates(analyses[::-1])  # any order
    assert list(table["realization"]) == [0, 1, 2] and list(table["chosen"]) == [False, True, False]
    assert table.loc[0, "force_change"] == pytest.approx(1.0) and table.loc[2, "Z_change"] == pytest.approx(0.125)
    assert table.loc[1, "score"] == pytest.approx(0.03)
    picked = p2_tables.chosen_states(analyses, table)
    assert [int(ds.attrs["realization"]) for ds in picked] == [1, 1, 1]
    assert [float(ds["rho"]) for ds in picked] == list(rhos)
    # equal scores: the lowest realization
    twins = [state_analysis(r, rho, 3.0, 1.0) for r in (4, 3) for rho in rhos]
    assert list(p2_tables.table_state_candidates(twins)["chosen"]) == [True, False]


def test_jammed_table_states_are_the_first_three_at_or_above_table_rho_with_mean_z_over_d_plus_one():
    rho = [0.78, 0.785, 0.79, 0.795, 0.80, 0.805, 0.81]
    z = [3.5, 3.6, 0.5, 1.0, 3.5, 4.0, 4.2]  # jams between 0.795 and 0.80 (the states below 0.79 do not count)
    # 0.79-0.80: mean 1.67; 0.795-0.805: mean 2.83; 0.80-0.81: mean 3.9 >= 3
    assert p2_tables.jammed_table_states(rho, z, 0.79) == (4, 5, 6)
    assert p2_tables.jammed_table_states(rho, z, 0.79, dimension=3) is None  # 3D needs mean Z >= 4
    assert p2_tables.jammed_table_states(rho, [3.0] * 7, 0.79) == (2, 3, 4)  # jammed already: the literal start
    analyses = [state_analysis(r, x, zz, 1.0 + 0.01 * k) for r in (0, 1) for k, (x, zz) in enumerate(zip(rho, z))]
    table = p2_tables.table_state_candidates(analyses, "jammed", 0.79)
    assert list(table[["rho_a", "rho_b", "rho_c"]].iloc[0]) == [0.80, 0.805, 0.81]
    assert table.attrs["rule"] == "jammed"
    picked = p2_tables.chosen_states(analyses, table)  # the candidates beyond a, b, c are left out
    assert [float(ds["rho"]) for ds in picked] == [0.80, 0.805, 0.81]
    # the literal rule keeps the three states it is given; the jammed one refuses data that never jam
    literal = p2_tables.table_state_candidates([a for a in analyses if 0.785 <= float(a["rho"]) <= 0.795])
    assert list(literal[["rho_a", "rho_b", "rho_c"]].iloc[0]) == [0.785, 0.79, 0.795]
    unjammed = [state_analysis(0, x, 1.0, 1.0) for x in rho]
    with pytest.raises(ValueError, match="mean Z >= 3"):
        p2_tables.table_state_candidates(unjammed, "jammed", 0.79)
    with pytest.raises(ValueError, match="rule must be"):
        p2_tables.table_state_candidates(analyses, "nearest")


def test_table_states_refuse_incomplete_or_mismatched_states():
    with pytest.raises(ValueError, match="need a, b, c"):
        p2_tables.table_state_candidates([state_analysis(0, 0.79, 3.0, 1.0)])
    table = p2_tables.table_state_candidates([state_analysis(0, r, 3.0, 1.0) for r in (0.788, 0.791, 0.794)])
    with pytest.raises(ValueError, match="expected"):
        p2_tables.chosen_states([state_analysis(0, r, 3.0, 1.0) for r in (0.70, 0.71, 0.72)], table)


# --- sampling: distances between states k samples apart -----------------------------------------------------------
def test_lagged_distances_compare_states_k_samples_apart():
    analyses = worked_example_analyses()
    diagrams = [p2_distances.analysis_diagram(ds, "normal", 0) for ds in analyses]  # f, g, g
    rho = [0.70, 0.71, 0.72]
    lag1 = p2_distances.lagged_distances(diagrams, rho, 1, homology_dims=(0,))
    np.testing.assert_allclose(lag1["beta0_d_W1"], [5.5, 0.0], atol=1e-9)
    np.testing.assert_allclose(lag1["rho"], [0.71, 0.72])
    lag2 = p2_distances.lagged_distances(diagrams, rho, 2, homology_dims=(0,))
    assert len(lag2) == 1 and lag2.loc[0, "rho_previous"] == 0.70
    for metric, value in WORKED.items():  # (f, g) again, two samples apart
        assert lag2.loc[0, p2.table_column(0, metric)] == pytest.approx(value, rel=1e-6)
    with pytest.raises(ValueError):
        p2_distances.lagged_distances(diagrams, rho, 0)


def test_lagged_summary_splits_pairs_by_p2_regime():
    # states at rho 0.70 .. 0.84, Z crossing 3 at 0.79; PD0 = one point whose birth grows by 1 per state
    rho = np.round(np.arange(0.70, 0.8401, 0.02), 3)
    z = 3.0 + (rho - 0.79) * 10
    diagrams = [p2_distances.diagram_from_points(np.array([5.0 + k]), np.array([1.0]), np.array([False]), 0)
                for k in range(rho.size)]
    summary = p2_distances.lagged_distance_summary({1e-4: (rho, z, diagrams, 12.0)}, [1, 2]).set_index(["lag", "window"])
    windows = p2_distances.SAMPLING_WINDOWS
    # both states of a pair inside the window: 0.70-0.72, 0.72-0.74 | 0.76-0.78 | 0.80-0.82, 0.82-0.84
    assert [summary.loc[(1, w), "pairs"] for w in windows] == [2, 1, 2]
    assert [summary.loc[(2, w), "pairs"] for w in windows] == [1, 0, 1]
    assert summary.loc[(1, windows[0]), "beta0_d_B"] == pytest.approx(1.0)  # L∞ shift of one point by 1
    assert summary.loc[(2, windows[0]), "beta0_d_B"] == pytest.approx(2.0)
    assert np.isnan(summary.loc[(2, windows[1]), "beta0_d_W1"])
    assert summary["rho_J"].iloc[0] == pytest.approx(0.79) and summary["simulation_s"].iloc[0] == 12.0
    md = p2_distances.lagged_distance_markdown(summary.reset_index())
    assert "ρ_J = 0.790" in md and "| 0.0001 | 2 | 0.0400 |" in md


def test_a_comparison_of_two_zero_rates_is_not_evaluated():
    # no loop changes at all in either system before jamming (beta1 distances 0): IV.C-5 cannot compare them
    data = both_systems()
    for name in data:
        early = data[name]["rho"] < 0.74
        data[name]["distance"].loc[dict(homology_dim=1, rho=data[name]["rho"][early])] = 0.0
    table = p2_validation.p2_validation(data, paper_tables()).set_index("claim_id")
    assert table.loc["IV.C-5", "verdict"] == claims.NOT_EVALUATED
    assert "both rates are 0" in table.loc["IV.C-5", "evidence"]


# --- explanations of the claims that do not hold -----------------------------------------------------------------
def test_every_claim_has_an_explanation():
    assert set(p2_explanations.EXPLANATIONS) == {c.id for c in p2_validation.CLAIMS}


def test_explanations_are_given_exactly_where_a_claim_does_not_hold():
    table = p2_validation.p2_validation(both_systems(), paper_tables()).set_index("claim_id")
    for claim_id, row in table.iterrows():
        assert (row["explanation"] != "") == (row["verdict"] != claims.HOLDS), claim_id
    assert table.loc["V-2", "explanation"].startswith("Not a small-system effect")
    # without network measures the diagnostic says why it is missing instead of failing
    assert "no never-dying class counts" in table.loc["V-2", "explanation"]


def measures_with_never_dying_changes(ds, changing_pairs):
    """network_measures-like dataset for distances `ds`: one more state than pairs, the count of never-dying
    normal PD1 classes changing at the given pair indices (0 = first pair) of every realization."""
    n_pairs = ds.sizes["rho"]
    rho = np.concatenate([[float(ds["rho"][0]) - 0.005], ds["rho"].values])
    steps = np.zeros(n_pairs, dtype=int)
    steps[list(changing_pairs)] = 1
    count = np.concatenate([[10], 10 + np.cumsum(steps)])
    values = np.zeros((ds.sizes["realization"], n_pairs + 1, 3, 2), dtype=int)
    values[:, :, FORCE_KINDS.index("normal"), 1] = count
    return xr.Dataset({"essential_count": (("realization", "rho", "force_kind", "homology_dim"), values)},
                      coords={"realization": ds["realization"].values, "rho": rho, "force_kind": list(FORCE_KINDS),
                              "homology_dim": [0, 1]})


def test_never_dying_diagnostic_counts_the_pairs_that_change_the_class_count():
    ds = p2_shaped()  # rho_J = 0.78; pairs after it: later states 0.785 .. 0.900 (24 per realization)
    after = np.flatnonzero(ds["rho"].values > 0.78)
    assert after.size == 24
    changing = after[::4]  # 6 of the 24
    ds["distance"].loc[dict(force_kind="normal", homology_dim=1, metric="bottleneck")] = 0.02
    ds["distance"].loc[dict(force_kind="normal", homology_dim=1, metric="bottleneck",
                            rho=ds["rho"].values[changing])] = 0.5
    ctx = p2_judging.Context({p2.FRICTIONAL: p2_judging.Curves(p2.FRICTIONAL, ds, 2, claims.ClaimTolerances())}, None,
                      claims.ClaimTolerances(), p2.FRICTIONAL, p2.FRICTIONLESS,
                      {p2.FRICTIONAL: measures_with_never_dying_changes(ds, changing)})
    text = p2_explanations._never_dying_events(lambda c: c.frictional, 1, "after")(ctx)
    assert "25 % of the 72 consecutive pairs" in text and "median d_B of the other pairs 0.02" in text
    # a measures file that does not match the distances is not used
    ctx.measures[p2.FRICTIONAL] = measures_with_never_dying_changes(ds.isel(rho=slice(1, None)), [])
    with pytest.raises(claims.NotEvaluated, match="different states"):
        p2_explanations._never_dying_events(lambda c: c.frictional, 1, "after")(ctx)


def test_table_state_diagnostic_reports_where_a_b_c_lie():
    states = p2_tables.table_state_candidates([state_analysis(r, rho, z, f) for r in (0, 1, 2)
                                        for rho, z, f in zip((0.788, 0.791, 0.794), (2.8, 2.9, 3.0), (1.0, 2.0, 4.0))])
    curves = p2_judging.Curves(p2.FRICTIONAL, p2_shaped(), 2, claims.ClaimTolerances())
    ctx = p2_judging.Context({p2.FRICTIONAL: curves}, None,
                      claims.ClaimTolerances(), p2.FRICTIONAL, p2.FRICTIONLESS, {}, states)
    text = p2_explanations._table_state_diagnostic(ctx)
    assert "realization 0 (the quietest of 3" in text and "<F_n> x 4.00" in text and "Z 2.80 -> 3.00" in text


def test_equal_depth_diagnostic_compares_each_system_above_its_own_jamming():
    # after jamming both systems change at a rate set by the depth above their own rho_J alone: at equal depth the
    # quotients are 1, though at equal rho the frictionless one (rho_J 0.80, later than 0.78) is faster
    systems = both_systems()
    for name, ds in systems.items():
        rho_j = p2.jamming_density(ds, 2)
        depth = ds["rho"] - rho_j
        rate = xr.where(depth > 0, 5.0 * np.exp(-depth / 0.02), 1.0)
        for metric in ("bottleneck", "wasserstein_1", "wasserstein_2"):
            ds["distance"].loc[dict(force_kind="normal", homology_dim=0, metric=metric)] = rate
    tol = claims.ClaimTolerances()
    ctx = p2_judging.Context({name: p2_judging.Curves(name, ds, 2, tol) for name, ds in systems.items()}, None, tol,
                             p2.FRICTIONAL, p2.FRICTIONLESS)
    text = p2_explanations._at_equal_depth(0)(ctx)
    assert text.endswith("d_B 1, d_W1 1, d_W2 1") and "0 < rho - rho_J <=" in text, text
    at_equal_rho = [ctx.system(n).mean("normal", 0, "bottleneck") for n in (p2.FRICTIONLESS, p2.FRICTIONAL)]
    beyond = at_equal_rho[0].index > max(ctx.system(n).jammed() for n in systems)
    assert np.median(at_equal_rho[0][beyond]) > 1.5 * np.median(at_equal_rho[1][beyond])
    with pytest.raises(claims.NotEvaluated):
        p2_explanations._at_equal_depth(0)(p2_judging.Context({p2.FRICTIONAL: ctx.system(p2.FRICTIONAL)}, None,
                                                               tol, p2.FRICTIONAL, p2.FRICTIONLESS))


# --- issue 25: rates just before jamming, vacuous passes, markers, explanation basis, robustness ----------------
def test_the_fall_after_jamming_is_measured_against_the_rates_just_before_it():
    # loops vanish in the dilute regime (rho < 0.74): the rates just before jamming, [rho_J - 0.05, rho_J), are
    # untouched, so the fall after jamming stands (the dilute regime is not what slows)
    data = both_systems(frictional={"modify": scaled(1, p2.METRICS, 0.0, lambda x: x < 0.74)})
    assert verdicts(data, paper_tables())["IV.A-11a"] == claims.HOLDS
    # the rates just before jamming as slow as after it: no fall, however fast the dilute regime changed
    slow = both_systems(frictional={"modify": scaled(1, p2.METRICS, 1e-4, lambda x: (x >= J - 0.05) & (x < J))})
    table = p2_validation.p2_validation(slow, paper_tables()).set_index("claim_id")
    assert table.loc["IV.A-11a", "verdict"] == claims.FAILS
    assert "[rho_J - 0.05, rho_J)" in table.loc["IV.A-11a", "evidence"]
    assert "the factor 10.0 is ours" in table.loc["IV.A-11a", "criterion"]
    assert table.loc["IV.A-11a", "measured"] < 10


def test_no_loops_at_all_before_jamming_without_friction_is_a_vacuous_pass():
    # mu = 0 with no loop changes at all well below jamming: IV.C-5 "changes much less" holds only on zeros
    vacuous = both_systems(frictionless={"loop_factors": (0.0, 4.0, 2.0)})
    table = p2_validation.p2_validation(vacuous, paper_tables()).set_index("claim_id")
    assert table.loc["IV.C-5", "verdict"] == claims.HOLDS and table.loc["IV.C-5", "marker"] == claims.VACUOUS
    fair = p2_validation.p2_validation(both_systems(), paper_tables()).set_index("claim_id")
    assert fair.loc["IV.C-5", "verdict"] == claims.HOLDS and fair.loc["IV.C-5", "marker"] == ""
    assert "1 vacuous" in claims.verdict_summary(table.reset_index())


def test_a_verdict_within_ten_percent_of_its_threshold_is_marginal():
    # IV.A-2: median d_B before jamming >= 10 / 1.5; tolerance set so the measured median sits 5 % above it
    table = p2_validation.p2_validation(both_systems(), paper_tables()).set_index("claim_id")
    median = table.loc["IV.A-2", "measured"]
    assert table.loc["IV.A-2", "marker"] == ""
    near = p2_validation.p2_validation(both_systems(), paper_tables(),
                                       tolerances=claims.ClaimTolerances(value_factor=10 / (0.95 * median)))
    near = near.set_index("claim_id")
    assert near.loc["IV.A-2", "verdict"] == claims.HOLDS and near.loc["IV.A-2", "marker"] == claims.MARGINAL


def test_every_explanation_says_measured_with_its_command_or_hypothesis():
    table = p2_validation.p2_validation(both_systems(frictional={"after": 3000.0}), paper_tables())
    table = table.set_index("claim_id")
    for claim_id, (cause, command, _) in p2_explanations.EXPLANATIONS.items():
        assert command in (p2_explanations.SAMPLING, p2_explanations.CAMPAIGN, p2_explanations.THIS_TABLE,
                           p2_explanations.HYPOTHESIS_ONLY), claim_id
    assert table.loc["IV.A-11a", "explanation_basis"] == f"measured: {p2_explanations.THIS_TABLE}"
    assert p2_explanations.EXPLANATIONS["IV.A-5"][1] == p2_explanations.SAMPLING
    # a cause that only rules out another ("not a small-system effect") is no measured cause
    for claim_id in ("IV.B-3", "V-1", "V-2"):
        assert p2_explanations.EXPLANATIONS[claim_id][1] == p2_explanations.HYPOTHESIS_ONLY, claim_id
        assert re.search("no cause measured|not measured", p2_explanations.EXPLANATIONS[claim_id][0], re.I), claim_id
    # V-1 fails with 2, 3, 5 and 20 paper-size realizations: not explained away as "few realizations"
    v1 = p2_explanations.EXPLANATIONS["V-1"][0]
    assert "Few realizations" not in v1 and "2, 3, 5 and 20 paper-size realizations" in v1
    few = [claim_id for claim_id, (cause, _, _) in p2_explanations.EXPLANATIONS.items()
           if cause.startswith("Few realizations")]
    assert few and all(p2_explanations.EXPLANATIONS[c][1] == p2_explanations.HYPOTHESIS_ONLY for c in few)


def test_robustness_is_the_share_of_bootstrap_resamples_and_is_seeded():
    data = both_systems()
    first = p2_validation.p2_validation(data, paper_tables(), resamples=8, seed=3).set_index("claim_id")
    again = p2_validation.p2_validation(data, paper_tables(), resamples=8, seed=3).set_index("claim_id")
    pd.testing.assert_series_equal(first["robustness"], again["robustness"])
    assert first.loc["IV.C-1", "robustness"] == 1.0  # mu = 0 jams later in every resample
    # Tables I-III: one realization, no resample; the row says so
    assert first.loc["III.D-1", "robustness"] == f"one run: {p2.FRICTIONAL}"
    assert np.isnan(p2_validation.p2_validation(data, paper_tables()).set_index("claim_id").loc["IV.C-1", "robustness"])
    # one realization whose loops change early carries IV.C-5's failure: the other resamples hold
    carried = both_systems()
    carried[p2.FRICTIONLESS]["distance"].loc[dict(realization=0, homology_dim=1)] *= 40.0
    table = p2_validation.p2_validation(carried, paper_tables(), resamples=20, seed=0).set_index("claim_id")
    assert 0.0 < table.loc["IV.C-5", "robustness"] < 1.0


def test_pd1_points_are_counted_per_state_and_need_the_diagrams():
    counts = p2.diagram_point_counts(pd1_diagrams(7, n_realizations=2), "normal", 1)
    assert counts.dims == ("realization", "rho") and counts.shape == (2, RHO.size) and (counts == 7).all()
    assert (p2.diagram_point_counts(pd1_diagrams(7), "normal", 0) == 1).all()
    assert (p2.diagram_point_counts(pd1_diagrams(7), "tangential", 1) == 0).all()
    table = p2_validation.p2_validation(both_systems(), paper_tables()).set_index("claim_id")
    for claim_id in ("IV.C-8a", "IV.C-8b"):
        assert table.loc[claim_id, "verdict"] == claims.NOT_EVALUATED and "diagrams.nc" in table.loc[claim_id, "evidence"]


def test_another_reading_is_set_beside_the_claims_it_changes():
    # distances under another never-dying convention in which the rates no longer fall after jamming: IV.A-11a
    # turns and gets a row of that reading beside its own; claims the reading leaves alone get none
    other = both_systems(frictional={"after": 3000.0})
    table = p2_validation.p2_validation(both_systems(), paper_tables(),
                                        beside={"never-dying apart": {"distances": other}})
    primary, beside = table[table["reading"] == ""], table[table["reading"] == "never-dying apart"]
    assert len(primary) == len(p2_validation.CLAIMS)
    assert "IV.A-11a" in set(beside["claim_id"]) and "IV.C-1" not in set(beside["claim_id"])
    assert beside.set_index("claim_id").loc["IV.A-11a", "verdict"] == claims.FAILS
    assert primary.set_index("claim_id").loc["IV.A-11a", "verdict"] == claims.HOLDS
    assert claims.verdict_counts(table)[claims.FAILS] == claims.verdict_counts(primary)[claims.FAILS]
    # the literal states of Tables I-III beside the table's own: only the table claims can turn
    literal = p2_validation.p2_validation(both_systems(), paper_tables(),
                                          beside={"literal rho = 0.79": {"tables": table_variation(swap_rows)()}})
    turned = literal[literal["reading"] == "literal rho = 0.79"].set_index("claim_id")
    assert set(turned.index) <= {"III.D-1", "III.D-2", "III.D-3", "III.D-4"}
    assert turned.loc["III.D-2", "verdict"] == claims.FAILS


def _under(convention: str, systems: dict) -> dict:
    for ds in systems.values():
        ds.attrs["essential_convention"] = convention
    return systems


def test_a_miss_that_holds_without_the_never_dying_floor_has_the_floor_as_its_measured_cause(monkeypatch):
    # control 3 (docs/validation/controls.md §3): the claim judged again with never-dying classes left out; where
    # it then holds the floor is the demonstrated cause, where it fails too the floor is ruled out
    shipped = _under("minus_one", both_systems(frictional={"after": 3000.0}))  # IV.A-11a fails
    label = "never-dying classes left out"
    for drop, verdict, basis, words in (
            (both_systems(), claims.HOLDS, p2_explanations.DROP_CONTROL, "is its demonstrated cause"),
            (both_systems(frictional={"after": 3000.0}), claims.FAILS, "", "ruled out as its only cause")):
        table = p2_validation.p2_validation(shipped, paper_tables(),
                                            beside={label: {"distances": _under("drop", drop)}})
        primary = table[table["reading"] == ""].set_index("claim_id").loc["IV.A-11a"]
        assert primary["verdict"] == claims.FAILS
        # IV.A-11a's cause is the floor: refuted by the control, it is left a hypothesis
        assert words in primary["explanation"]
        assert primary["explanation_basis"] == (f"{claims.MEASURED}: {basis}" if basis else claims.HYPOTHESIS)
        beside = table[table["reading"] == label].set_index("claim_id")
        assert ("IV.A-11a" in beside.index) is (verdict == claims.HOLDS)  # a row beside only where it turns
    # a miss with another measured cause, failing under `drop` too, keeps its cause and its basis
    monkeypatch.setitem(p2_explanations.EXPLANATIONS, "IV.B-3", ("A cause measured elsewhere.",
                                                                 p2_explanations.SAMPLING, ()))
    alike = {"tangential_w_near": 1.0}  # IV.B-3: tangential d_W1, d_W2 as large as the normal ones near rho_J
    table = p2_validation.p2_validation(_under("minus_one", both_systems(frictional=alike)), paper_tables(),
                                        beside={label: {"distances": _under("drop", both_systems(frictional=alike))}})
    row = table[table["reading"] == ""].set_index("claim_id").loc["IV.B-3"]
    assert row["verdict"] == claims.FAILS and "is not all that makes it fail" in row["explanation"]
    assert row["explanation_basis"] == f"{claims.MEASURED}: {p2_explanations.SAMPLING}"
    # another reading beside (never-dying classes apart) is no control of the floor
    table = p2_validation.p2_validation(shipped, paper_tables(),
                                        beside={"apart": {"distances": _under("apart", both_systems())}})
    assert "Control, never-dying classes left out" not in table[table["reading"] == ""].set_index("claim_id").loc[
        "IV.A-11a", "explanation"]


# --- the judges changed after the verdicts were read (issue 53), each marked in the table --------------------------
def _judged(tables=None, frictionless=None) -> pd.DataFrame:
    tables = tables if tables is not None else paper_tables()
    return p2_validation.p2_validation(both_systems(None, frictionless), tables, diagrams=DIAGRAMS).set_index("claim_id")


@pytest.mark.parametrize("quotient, marker", [(1.105, claims.MARGINAL), (1.5, "")])
def test_table_i_quotient_margin_is_measured_against_p2s_own(quotient, marker):
    # beta1: d_W1 grows `quotient` times more than d_W2 from (a,b) to (a,c); P2's own quotient is 2.91. At 1.105
    # ours lies within a tenth of P2's distance from 1 (log scale): marginal, though 10.5 % above 1
    def beta1(t):
        w1, w2 = p2.table_column(1, W1), p2.table_column(1, W2)
        growth_w2 = t["table1"].loc["(a,c)", w2] / t["table1"].loc["(a,b)", w2]
        t["table1"].loc["(a,c)", w1] = t["table1"].loc["(a,b)", w1] * growth_w2 * quotient

    row = _judged(table_variation(beta1)()).loc["III.D-2"]
    assert row["verdict"] == claims.HOLDS and row["marker"] == marker
    assert "P2's own quotients: beta0 1.88, beta1 2.91" in row["evidence"]
    assert row["judge_changed_after_reading"].startswith("2026-12-05: its margin is measured against P2's own")
    assert claims.reference_margin(1.105, 1.0, 2.91) < 0.1 < claims.relative_margin(1.105, 1.0)


@pytest.mark.parametrize("spread, marker", [(1.97, claims.MARGINAL), (1.6, "")])
def test_table_iii_spread_margin_is_measured_against_p2s_own(spread, marker):
    # every column of Table III spread `spread` times (largest / smallest quadrant); P2's own median is 1.46
    def even(t):
        t["table3"] = t["table3"] * 0 + 1.0
        t["table3"].iloc[0] = spread

    row = _judged(table_variation(even)()).loc["III.D-4"]
    assert row["verdict"] == claims.HOLDS and row["marker"] == marker and "P2's own 1.46" in row["evidence"]


@pytest.mark.parametrize("peak, marker", [(0.72, ""), (0.715, claims.MARGINAL)])
def test_iv_c_4_is_marginal_within_two_sampling_steps(peak, marker):
    # the lead of the frictional system's slowing down is the difference of two maxima on a 0.005 grid: 0.015
    # (three steps) is resolved, 0.01 (two steps) is not
    row = _judged(frictionless={"peak": peak}).loc["IV.C-4"]
    assert row["verdict"] == claims.HOLDS and row["marker"] == marker and "two sampling steps 0.01" in row["evidence"]
    assert row["judge_changed_after_reading"].startswith("2026-12-05: marginal when the lead lies within two")


def test_more_loops_without_friction_is_judged_below_and_above_both_rho_j():
    split = _judged().loc[["IV.C-8a", "IV.C-8b"]]
    assert list(split["verdict"]) == [claims.HOLDS, claims.HOLDS]
    assert "below both rho_J" in split.loc["IV.C-8a", "evidence"] and "rho < 0.78" in split.loc["IV.C-8a", "evidence"]
    assert "above both rho_J" in split.loc["IV.C-8b", "evidence"] and "rho > 0.8" in split.loc["IV.C-8b", "evidence"]
    assert all("IV.C-8: does not hold" in text for text in split["judge_changed_after_reading"])
    assert "IV.C-8" not in {c.id for c in p2_validation.CLAIMS}
    # as in the campaign: fewer loops without friction before its later jamming, more after both: 8a alone fails
    campaign_like = p2_validation.p2_validation(both_systems(), paper_tables(), diagrams={
        p2.FRICTIONAL: pd1_diagrams(lambda x: 7 if x < 0.78 else 1290),
        p2.FRICTIONLESS: pd1_diagrams(lambda x: 1 if x < 0.80 else 1350)}).set_index("claim_id")
    assert campaign_like.loc["IV.C-8a", "verdict"] == claims.FAILS
    assert campaign_like.loc["IV.C-8b", "verdict"] == claims.HOLDS


def test_only_changed_judges_are_marked():
    from forcenet.report.judge_changes import P2_CHANGES

    table = _judged()
    marked = table[table["judge_changed_after_reading"] != ""]
    assert set(marked.index) == set(P2_CHANGES) and set(P2_CHANGES) <= {c.id for c in p2_validation.CLAIMS}
