"""Triclinic (tilted) periodic boxes, as LAMMPS writes them for sheared packings (`forcenet.boxes`, the importers):
the nearest image against a search over every lattice translation, LAMMPS's bounding box undone, a hand-built ring
of disks around a tilted box imported from a dump and from a table (its forces, overlaps, winding and drawing),
every tilt that cannot be refused with one line, LAMMPS's own sheared run, and whole contact forces split along the
line of centres (a tilted box's nearest image gives that line)."""
from __future__ import annotations

import itertools
from pathlib import Path

import numpy as np
import pytest

from forcenet import boxes, pipeline
from forcenet.datasets import read_snapshot
from forcenet.datasets.io import schema_problems
from forcenet.datasets.schema import BOX_TILT_ATTR, PERIODIC_AXES_ATTR
from forcenet.importers import SourceError, import_run, lammps, table
from forcenet.network import (QUADRANTS, network_from_edge_forces, quadrant_mask, restrict_to_quadrant,
                              snapshot_network)


# --- geometry against slow references --------------------------------------------------------------------------------
def nearest_by_search(delta: np.ndarray, vectors: np.ndarray, reach: int = 3) -> np.ndarray:
    """The shortest of delta − n @ vectors over every n in {−reach … reach}^d (the periodic axes' rows only)."""
    d = len(vectors)
    periodic = [k for k in range(d) if vectors[k, k] > 0]
    best = delta.copy()
    for n in itertools.product(range(-reach, reach + 1), repeat=len(periodic)):
        count = np.zeros(d)
        count[periodic] = n
        candidate = delta - count @ vectors
        shorter = np.linalg.norm(candidate, axis=1) < np.linalg.norm(best, axis=1)
        best[shorter] = candidate[shorter]
    return best


def half_width(vectors: np.ndarray) -> float:
    """Half the smallest distance between opposite faces of the box (edge vectors as rows)."""
    reciprocal = np.linalg.inv(vectors)  # columns: the faces' normals over their spacing
    return 0.5 / np.max(np.linalg.norm(reciprocal, axis=0))


@pytest.mark.parametrize("lo, hi, tilt, axes", [
    ([0, 0], [10, 8], [3.0], "xy"),
    ([-2, 1], [6, 9], [-4.0], "xy"),  # LAMMPS's largest tilt, half the x length
    ([1, 0], [7, 5], [2.5], "y"),  # x bounded (no image along a), y periodic and tilted
    ([0, 0, 0], [6, 5, 7], [1.5, -2.0, 2.2], "xyz"),
    ([0, 0, 0], [6, 5, 7], [0.0, 2.0, -2.5], "xz"),  # y bounded: its edge untilted, z's tilted along x and y
])
def test_the_nearest_image_in_a_tilted_box_is_the_shortest_of_every_lattice_translation(lo, hi, tilt, axes):
    rng = np.random.default_rng(len(axes) + len(lo))
    vectors = boxes.box_vectors(lo, hi, tilt)
    period = boxes.box_periods(axes, lo, hi, tilt)
    assert boxes.tilt_problem(axes, tilt, len(lo)) is None
    n = 400
    position = lo + rng.uniform(0, 1, (n, len(lo))) @ vectors
    i, j = rng.integers(0, n, 3000), rng.integers(0, n, 3000)
    branch = boxes.branch_vectors(position, i, j, period)
    best = nearest_by_search(position[i] - position[j], period)
    close = np.linalg.norm(best, axis=1) < half_width(vectors)
    assert close.sum() > 300 and (~close).sum() > 300  # both kinds of pair are drawn
    np.testing.assert_allclose(branch[close], best[close], atol=1e-9)  # exact for pairs closer than half the box
    assert np.all(np.linalg.norm(branch, axis=1) >= np.linalg.norm(best, axis=1) - 1e-9)
    # the shift is a whole number of edge vectors of the periodic axes, none along a bounded one
    counts = boxes.image_counts(position, i, j, period)
    np.testing.assert_allclose(position[i] - position[j] - counts @ period, branch, atol=1e-9)
    bounded = [k for k, label in enumerate("xyz"[:len(lo)]) if label not in axes]
    assert not counts[:, bounded].any()


def test_an_orthogonal_box_gives_the_axis_by_axis_image_and_fold_as_before():
    rng = np.random.default_rng(3)
    position = rng.uniform(-5, 15, (200, 3))
    i, j = rng.integers(0, 200, 500), rng.integers(0, 200, 500)
    lengths = np.array([10.0, 0.0, 7.0])
    expected = np.where(lengths > 0, np.round((position[i] - position[j]) / np.where(lengths > 0, lengths, 1)), 0)
    np.testing.assert_array_equal(boxes.image_counts(position, i, j, lengths), expected)
    np.testing.assert_array_equal(boxes.image_counts(position, i, j, boxes.box_periods("xz", [0] * 3, [10, 4, 7])),
                                  expected)
    folded = boxes.fold_into_box(position, [0, 0, 0], [10, 4, 7], [True, False, True])
    np.testing.assert_allclose(folded[:, [0, 2]], np.mod(position[:, [0, 2]], [10, 7]))
    np.testing.assert_array_equal(folded[:, 1], position[:, 1])


def test_folding_into_a_tilted_box_moves_points_by_whole_edges_into_it():
    rng = np.random.default_rng(4)
    lo, hi, tilt = [1, -1, 0], [5, 4, 3], [1.0, -1.5, 2.0]
    vectors = boxes.box_vectors(lo, hi, tilt)
    inside = lo + rng.uniform(0, 1, (100, 3)) @ vectors
    moved = inside + rng.integers(-3, 4, (100, 3)) @ vectors
    np.testing.assert_allclose(boxes.fold_into_box(moved, lo, hi, [True] * 3, tilt), inside, atol=1e-9)
    s = boxes.fractional_coordinates(inside, lo, hi, tilt)
    assert np.all((s >= 0) & (s < 1))
    # only the periodic axes fold: z stays where it was given
    partly = boxes.fold_into_box(moved, lo, hi, [True, True, False], tilt)
    np.testing.assert_allclose(boxes.fractional_coordinates(partly, lo, hi, tilt)[:, 2],
                               boxes.fractional_coordinates(moved, lo, hi, tilt)[:, 2], atol=1e-9)


def test_the_corners_and_tilted_faces_of_a_box():
    np.testing.assert_allclose(boxes.box_corners([0, 0], [4, 3], [1.0])[[0, 2, 3, 1]], [[0, 0], [4, 0], [5, 3], [1, 3]])
    np.testing.assert_array_equal(boxes.tilted_faces([1.0], 2), [True, False])  # b leans along x: x's faces tilt
    np.testing.assert_array_equal(boxes.tilted_faces([0.0, 0.0, 2.0], 3), [False, True, False])
    np.testing.assert_array_equal(boxes.tilted_faces([0.0, 1.0, 0.0], 3), [True, False, False])
    assert not boxes.tilted_faces([0.0, 0.0, 0.0], 3).any()


@pytest.mark.parametrize("axes, tilt, dimension, problem", [
    ("xy", [1.0, 0.0], 2, "a 2D box has 1 tilt factor(s) (xy), got 2"),
    ("xyz", [1.0], 3, "a 3D box has 3 tilt factor(s) (xy, xz, yz), got 1"),
    ("xy", [np.nan], 2, "must be finite"),
    ("x", [0.5], 2, "tilt xy = 0.5 but the box is not periodic along y"),
    ("xy", [0.0, 0.5, 0.0], 3, "tilt xz = 0.5 but the box is not periodic along z"),
    ("xz", [0.5, 0.0, 0.0], 3, "tilt xy = 0.5 but the box is not periodic along y"),
])
def test_a_tilt_that_cannot_be_is_named(axes, tilt, dimension, problem):
    assert problem in boxes.tilt_problem(axes, tilt, dimension)
    assert boxes.tilt_problem(axes, [0.0] * len(boxes.tilt_labels(dimension)), dimension) is None  # zero: orthogonal


def test_a_network_takes_edge_vectors_in_lammps_form_only():
    ring = dict(edge_i=[0], edge_j=[1], force=[1.0], position=[[0.0, 0.0], [1.0, 1.0]])
    assert network_from_edge_forces(**ring, period=[[4.0, 0.0], [1.0, 4.0]]).period.tolist() == [[4, 0], [1, 4]]
    np.testing.assert_array_equal(network_from_edge_forces(**ring, period=[4.0, 0.0]).period, [[4, 0], [0, 0]])
    for bad in ([[4.0, 1.0], [0.0, 4.0]], [[0.0, 0.0], [1.0, 0.0]], [[4.0, 0.0], [np.inf, 4.0]]):
        with pytest.raises(ValueError, match="edge vectors in LAMMPS's triclinic form"):
            network_from_edge_forces(**ring, period=bad)


def test_the_quadrants_of_a_tilted_box_are_its_four_equal_parallelograms():
    lo, hi, tilt = [0, 0], [4, 4], [2.0]
    vectors = boxes.box_vectors(lo, hi, tilt)
    s = np.array([[0.3, 0.9], [0.7, 0.2], [0.2, 0.1], [0.8, 0.6]])
    position = lo + s @ vectors  # the first at x = 3.0, right of the centre's x = 2, yet in the left half of a
    expected = {"top left": [True, False, False, False], "bottom right": [False, True, False, False],
                "bottom left": [False, False, True, False], "top right": [False, False, False, True]}
    for name in QUADRANTS:
        np.testing.assert_array_equal(quadrant_mask(position, lo, hi, name, tilt), expected[name])
    assert quadrant_mask(position, lo, hi, "top right")[0]  # read as orthogonal, the first would be top right


# --- a ring of disks around a tilted box ---------------------------------------------------------------------------
#: four disks of radius 0.52 along the tilted edge b = (1, 4) of a 4 × 4 box with xy = 1, at fractional coordinates
#: (1/2, k/4 + 1/8): consecutive disks 1.0308 apart along b/4 = (0.25, 1); the fourth touches the first through the
#: y faces (their nearest images are b/4 apart only with the tilt: an orthogonal box would put them 1.25 apart)
RING = np.array([[0.5 * 4 + (k / 4 + 1 / 8) * 1.0, 4 * (k / 4 + 1 / 8)] for k in range(4)])
RING_PAIRS = "1 2 2.0 0 0 0\n2 3 2.0 0 0 0\n3 4 2.0 0 0 0\n4 1 1.0 0 0 0\n"


def ring_dumps(folder: Path, bounds: str = "xy xz yz pp pp pp", box: str = "0 5 1\n0 4 0\n-0.5 0.5 0\n",
               columns: str = "x y", rows=None) -> tuple[Path, Path]:
    """The ring as LAMMPS dumps it: a triclinic box's bounding box (x from 0 to 4 + xy) with its tilt factors."""
    atoms, pairs = folder / "a.dump", folder / "p.dump"
    head = "ITEM: TIMESTEP\n7\nITEM: NUMBER OF {}\n{}\nITEM: BOX BOUNDS " + bounds + "\n" + box
    rows = [f"{float(x)!r} {float(y)!r}" for x, y in RING] if rows is None else rows
    atoms.write_text(head.format("ATOMS", 4) + f"ITEM: ATOMS id {columns} z radius\n"
                     + "".join(f"{k + 1} {row} 0 0.52\n" for k, row in enumerate(rows)))
    pairs.write_text(head.format("ENTRIES", 4) + "ITEM: ENTRIES c_pid[1] c_pid[2] c_pf[1] c_pf[2] c_pf[3] c_pf[4]\n"
                     + RING_PAIRS)
    return atoms, pairs


def test_a_triclinic_dump_gives_the_box_and_the_contact_through_its_tilted_face(tmp_path):
    atoms, pairs = ring_dumps(tmp_path)
    (state,) = lammps.read_run({"atoms": atoms, "pairs": pairs}, 2, {"format": "lammps"})
    np.testing.assert_allclose(state.box_lo, [0, 0])
    np.testing.assert_allclose(state.box_hi, [4, 4])  # the bounding box's x_hi 5 less the tilt
    np.testing.assert_allclose(state.tilt, [1.0])
    assert state.periodic_axes == "xy"
    np.testing.assert_allclose(state.rho, 4 * np.pi * 0.52 ** 2 / 16)  # a tilt keeps the area lx ly
    # contacts 1–2, 1–4, 2–3, 3–4, each on the first disk from the second: the next disk up the ring pushes down
    # along b, but disk 4's image through the y faces lies below disk 1 and pushes it up along b/4 = (0.25, 1)
    along_b = np.array([0.25, 1.0]) / np.hypot(0.25, 1.0)
    np.testing.assert_allclose(state.force_normal, [-2.0 * along_b, 1.0 * along_b, -2.0 * along_b, -2.0 * along_b])
    # read as an orthogonal box, the same dump would push disk 1 from (2.875, -0.5): along (-0.75, 1)
    orthogonal, _ = ring_dumps(tmp_path, bounds="pp pp pp", box="0 4\n0 4\n-0.5 0.5\n")
    (flat,) = lammps.read_run({"atoms": orthogonal, "pairs": pairs}, 2, {"format": "lammps"})
    np.testing.assert_allclose(flat.force_normal[1], np.array([-0.75, 1.0]) / 1.25)


def test_a_3d_triclinic_dump_undoes_the_bounding_box_and_tilts_every_edge(tmp_path):
    lo, hi, tilt = np.array([0.0, 0, 0]), np.array([4.0, 4, 4]), np.array([1.0, 0.5, -1.0])
    vectors = boxes.box_vectors(lo, hi, tilt)
    xy, xz, yz = tilt
    bounding = (f"{lo[0] + min(0, xy, xz, xy + xz)} {hi[0] + max(0, xy, xz, xy + xz)} {xy}\n"
                f"{lo[1] + min(0, yz)} {hi[1] + max(0, yz)} {xz}\n{lo[2]} {hi[2]} {yz}\n")
    s = np.array([[0.5, 0.5, 0.05], [0.5, 0.5, 0.95]])  # 0.1 c apart through the z faces
    position = lo + s @ vectors
    atoms, pairs = tmp_path / "a.dump", tmp_path / "p.dump"
    head = "ITEM: TIMESTEP\n3\nITEM: NUMBER OF {}\n{}\nITEM: BOX BOUNDS xy xz yz pp pp pp\n" + bounding
    atoms.write_text(head.format("ATOMS", 2) + "ITEM: ATOMS id x y z radius\n"
                     + "".join(f"{k + 1} {float(x)!r} {float(y)!r} {float(z)!r} 0.21\n" for k, (x, y, z) in enumerate(position)))
    pairs.write_text(head.format("ENTRIES", 1) + "ITEM: ENTRIES c_pid[1] c_pid[2] c_pf[1] c_pf[2] c_pf[3] c_pf[4]\n"
                     "1 2 1.0 0 0 0\n")
    (state,) = lammps.read_run({"atoms": atoms, "pairs": pairs}, 3, {"format": "lammps"})
    np.testing.assert_allclose(state.box_lo, lo, atol=1e-12)
    np.testing.assert_allclose(state.box_hi, hi, atol=1e-12)
    np.testing.assert_allclose(state.tilt, tilt)
    c = vectors[2]
    np.testing.assert_allclose(state.force_normal, [0.1 * c / np.linalg.norm(0.1 * c)], atol=1e-12)


@pytest.mark.parametrize("columns, rows", [
    ("xs ys", [f"0.5 {k / 4 + 1 / 8!r}" for k in range(4)]),  # fractions of the edges a and b together
    ("xu yu", [f"{float(x) + 1.0!r} {float(y) + 4.0!r}" for x, y in RING[:3]] + [f"{float(RING[3, 0]) - 8.0!r} {float(RING[3, 1])!r}"]),
    ("xsu ysu", [f"0.5 {k / 4 + 1 / 8 + (k == 2)!r}" for k in range(4)]),
])
def test_scaled_and_unwrapped_positions_in_a_triclinic_box_give_the_same_state(tmp_path, columns, rows):
    atoms, pairs = ring_dumps(tmp_path)
    (expected,) = lammps.read_run({"atoms": atoms, "pairs": pairs}, 2, {"format": "lammps"})
    atoms, pairs = ring_dumps(tmp_path, columns=columns, rows=rows)
    (state,) = lammps.read_run({"atoms": atoms, "pairs": pairs}, 2, {"format": "lammps"})
    np.testing.assert_allclose(state.position, expected.position, atol=1e-12)
    np.testing.assert_allclose(state.force_normal, expected.force_normal, atol=1e-12)


def test_a_triclinic_dump_that_cannot_be_read_is_named(tmp_path):
    atoms, pairs = ring_dumps(tmp_path, columns="xs y", rows=[f"0.5 {float(y)!r}" for y in RING[:, 1]])
    with pytest.raises(SourceError, match=r"a.dump, column 'y': scaled and unscaled positions \(xs y\) in a "
                                          "triclinic box"):
        lammps.read_run({"atoms": atoms, "pairs": pairs}, 2, {"format": "lammps"})
    atoms, pairs = ring_dumps(tmp_path, bounds="xy xz yz pp ff pp")
    with pytest.raises(SourceError, match=r"a.dump, timestep 7 \(line 1\): tilt xy = 1 but the box is not periodic "
                                          "along y"):
        lammps.read_run({"atoms": atoms, "pairs": pairs}, 2, {"format": "lammps"})
    atoms, pairs = ring_dumps(tmp_path, box="0 5 1\n0 4 0.5\n-0.5 0.5 0\n")
    with pytest.raises(SourceError, match="tilt factors xz = 0.5, yz = 0 out of the plane of a 2D system"):
        lammps.read_run({"atoms": atoms, "pairs": pairs}, 2, {"format": "lammps"})
    atoms, pairs = ring_dumps(tmp_path, box="0 5 1\n0 4\n-0.5 0.5 0\n")
    with pytest.raises(SourceError, match="a.dump, line 7: expected three lines of box bounds 'lo hi' and a tilt"):
        lammps.read_run({"atoms": atoms, "pairs": pairs}, 2, {"format": "lammps"})
    atoms, pairs = ring_dumps(tmp_path, bounds="xy xz yz ff pp pp")  # x bounded: its faces lean with b
    atoms.write_text(atoms.read_text().replace("z radius", "z radius fx").replace(" 0.52\n", " 0.52 0.3\n"))
    with pytest.raises(SourceError, match="wall forces in source.wall_columns on a tilted face of a triclinic box"):
        lammps.read_run({"atoms": atoms, "pairs": pairs}, 2, {"format": "lammps", "wall_columns": ["fx", "fx"]})
    atoms, pairs = ring_dumps(tmp_path)
    with pytest.raises(SourceError, match="source.box, tilt: a 2D box has 1 tilt factor"):
        lammps.read_run({"atoms": atoms, "pairs": pairs}, 2,
                        {"format": "lammps", "box": {"lo": [0, 0], "hi": [4, 4], "tilt": [1.0, 0.0, 0.0]}})


def test_a_triclinic_import_records_its_tilt_winds_around_the_box_and_is_drawn_through_the_face(tmp_path):
    from forcenet.measures import cluster_curves
    from forcenet.plotting.networks import prepare_p1_fig01_networks
    from forcenet.report.p1 import relative_overlaps

    atoms, pairs = ring_dumps(tmp_path)
    entry = {"dimension": 2, "source": {"format": "lammps", "runs": [{"atoms": str(atoms), "pairs": str(pairs)}]}}
    out = tmp_path / "rho.nc"
    import_run(config={"systems": {"t": entry}}, system="t", realization=0, outputs=[str(out)])
    with read_snapshot(out) as snapshot:
        assert snapshot.attrs[PERIODIC_AXES_ATTR] == "xy"
        np.testing.assert_allclose(snapshot.attrs[BOX_TILT_ATTR], [1.0])
        network = snapshot_network(snapshot, rattler_rule="once")
        attrs = pipeline.analysis_attrs(snapshot, str(out), {"remove_rattlers": "once", "fill_tetrahedra": True})
        overlaps, _ = relative_overlaps(snapshot)
        drawn = prepare_p1_fig01_networks({"t": snapshot}, rattler_rule=False)
        bad = snapshot.copy()
        bad.attrs[PERIODIC_AXES_ATTR] = "x"
        assert any(f"'{BOX_TILT_ATTR}': tilt xy = 1 but the box is not periodic along y" in p
                   for p in schema_problems(bad, "snapshot"))
    np.testing.assert_allclose(attrs[BOX_TILT_ATTR], [1.0])  # the analysis file says so too
    # every pair overlaps by the same 1.04 - 1.0308, the one through the tilted face included
    np.testing.assert_allclose(overlaps, [(1.04 - np.hypot(0.25, 1.0)) / 1.04] * 4)
    # ⟨F⟩ = 1.75: the ring winds around y while its weakest contact is in, F_th <= 1/1.75
    curves = cluster_curves(network, np.array([0.0, 0.5, 0.6]))
    np.testing.assert_array_equal(curves.percolates, [True, True, False])
    edges = drawn.table[drawn.table["element"] == "contact"]
    through = edges[(edges["i"] == 0) & (edges["j"] == 3)].iloc[0]
    assert (through["x_j [source length unit]"], through["y_j [source length unit]"]) == pytest.approx(
        tuple(RING[0] - [0.25, 1.0]))  # an import without a units block: the source's unit
    np.testing.assert_allclose(drawn.layout["box"][0][2], [1.0])


def test_a_triclinic_table_gives_the_dumps_state_and_keeps_walls_off_its_tilted_faces(tmp_path):
    atoms, pairs = ring_dumps(tmp_path)
    (expected,) = lammps.read_run({"atoms": atoms, "pairs": pairs}, 2, {"format": "lammps"})
    particles, contacts = tmp_path / "p.csv", tmp_path / "c.csv"
    particles.write_text("id,x,y,radius\n" + "".join(f"{k + 1},{float(x)!r},{float(y)!r},0.52\n" for k, (x, y) in enumerate(RING)))
    contacts.write_text("i,j,fn,ft\n" + "".join(",".join(row.split()[:3]) + ",0\n" for row in RING_PAIRS.splitlines()))
    box = {"lo": [0, 0], "hi": [4, 4], "tilt": [1.0]}
    state = table.read_state(particles, contacts, 2, "magnitudes", box=box, periodic=["x", "y"])
    np.testing.assert_allclose(state.force_normal, expected.force_normal, atol=1e-12)
    np.testing.assert_allclose(state.tilt, [1.0])
    with pytest.raises(SourceError, match="p.csv, box.tilt: tilt xy = 1 but the box is not periodic along y"):
        table.read_state(particles, contacts, 2, "magnitudes", box=box, periodic=["x"])
    contacts.write_text(contacts.read_text() + "2,x_lo,1.0,0.0\n")
    with pytest.raises(SourceError, match="c.csv, line 6, column 'j': wall x_lo on a tilted face"):
        table.read_state(particles, contacts, 2, "magnitudes", box=box, periodic=["y"])


# --- LAMMPS's own sheared run (data/examples/lammps_triclinic_2d, bench/lammps/make_triclinic_example.py) -----------
def test_the_image_forcenet_joins_is_the_one_lammps_used_in_its_sheared_run():
    """The normal force read as a magnitude, directed by forcenet's nearest image in the tilted box, equals LAMMPS's
    own vector (pair/local fx fy, along the branch vector to the image its neighbour list holds) to the dumps' 10
    printed digits, the contacts through the tilted faces included; an orthogonal reading gets exactly those wrong."""
    from forcenet.boxes import box_periods, image_counts

    folder = Path(__file__).resolve().parents[1] / "data" / "examples" / "lammps_triclinic_2d"
    run = {"atoms": folder / "atoms.dump", "pairs": folder / "pairs.dump"}
    columns = {"i": "c_pid[1]", "j": "c_pid[2]", "tangential": ["c_pf[4]", "c_pf[5]", "c_pf[6]"]}
    ours = lammps.read_run(run, 2, {"format": "lammps", "pair_columns": {**columns, "normal": "c_pf[1]"}})
    theirs = lammps.read_run(run, 2, {"format": "lammps", "pair_columns": {**columns, "normal": ["c_pf[2]", "c_pf[3]"]}})
    assert [state.tilt.tolist() for state in ours] == [[3.0], [4.0], [5.0]]
    for state, lammps_state in zip(ours, theirs):
        scale = np.abs(lammps_state.force_normal).max()
        np.testing.assert_allclose(state.force_normal, lammps_state.force_normal, atol=1e-8 * scale)
        counts = image_counts(state.position, state.contact_i, state.contact_j,
                              box_periods("xy", state.box_lo, state.box_hi, state.tilt))
        through_y = counts[:, 1] != 0  # through the faces the tilt leans
        assert through_y.sum() >= 10
        flat = lammps.normal_unit_vectors(state.position, state.contact_i, state.contact_j,
                                          box_periods("xy", state.box_lo, state.box_hi))
        direction = lammps_state.force_normal / np.linalg.norm(lammps_state.force_normal, axis=1)[:, None]
        wrong = np.abs(flat - direction).max(axis=1) > 1e-6
        np.testing.assert_array_equal(wrong, through_y)


def test_a_shear_at_constant_volume_is_not_a_compression(tmp_path):
    """Two states at one ρ are refused as a compression's (keyed by ρ), naming the option that makes them one run
    (a sequence, tests/test_sequence.py); one of them alone imports."""
    from forcenet.importers import SourceError, imported_system
    from forcenet.importers.system import measured_labels
    from forcenet.systems import ConfigError

    atoms, pairs = ring_dumps(tmp_path)
    for dump in (atoms, pairs):  # a second timestep, sheared further in the same box: the same ρ
        text = dump.read_text()
        dump.write_text(text + text.replace("ITEM: TIMESTEP\n7\n", "ITEM: TIMESTEP\n8\n").replace("0 5 1\n", "0 5.5 1.5\n"))
    entry = {"dimension": 2, "source": {"format": "lammps", "runs": [{"atoms": str(atoms), "pairs": str(pairs)}]}}
    with pytest.raises(SourceError, match=r"a.dump, systems.s.source.runs\[0\]: states with the same ρ at 3 "
                                          r"decimals \(0.212, 0.212\).*one run with source.sequence"):
        measured_labels("s", entry)  # forcenet-check-config; the import job says the same
    with pytest.raises(ConfigError, match=r"'systems.s.rho': declares 2 state\(s\), but source.timesteps picks 1"):
        imported_system("s", {**entry, "rho": [0.2, 0.212], "source": {**entry["source"], "timesteps": [8]}})
    later = imported_system("s", {**entry, "rho": [0.212], "source": {**entry["source"], "timesteps": [8]}})
    assert later.rho_grid == (0.212,)
    (state,) = lammps.read_run(entry["source"]["runs"][0], 2, {"format": "lammps", "timesteps": [8]})
    np.testing.assert_allclose(state.tilt, [1.5])


# --- a whole contact force, split along the line of centres ---------------------------------------------------------
def test_a_total_force_splits_into_its_part_along_the_line_of_centres_and_the_rest():
    from forcenet.importers.common import split_total_force

    fn, ft = split_total_force(np.array([[3.0, 4.0], [-1.0, 2.0]]), np.array([[1.0, 0.0], [0.6, 0.8]]))
    np.testing.assert_allclose(fn, [[3.0, 0.0], [0.6, 0.8]])  # (-1, 2) · (0.6, 0.8) = 1
    np.testing.assert_allclose(ft, [[0.0, 4.0], [-1.6, 1.2]])
    rng = np.random.default_rng(5)
    n = rng.normal(size=(50, 3))
    n /= np.linalg.norm(n, axis=1)[:, None]
    total = rng.normal(size=(50, 3))
    fn, ft = split_total_force(total, n)
    np.testing.assert_allclose(fn + ft, total)
    np.testing.assert_allclose(np.cross(fn, n), 0, atol=1e-12)  # along n
    np.testing.assert_allclose(np.einsum("cd,cd->c", ft, n), 0, atol=1e-12)  # across it


def test_a_table_of_total_forces_is_split_along_the_line_to_the_nearest_image(tmp_path):
    particles, contacts = tmp_path / "p.csv", tmp_path / "c.csv"
    particles.write_text("id,x,y,radius\n1,0.2,2.0,0.45\n2,9.4,2.3,0.45\n3,5.0,0.3,0.5\n")
    contacts.write_text("i,j,f_x,f_y\n1,2,2.0,0.5\n3,y_lo,0.2,1.5\n")
    box = {"lo": [0, 0], "hi": [10, 4]}
    state = table.read_state(particles, contacts, 2, "total", box=box, periodic=["x"])
    n = np.array([0.8, -0.3]) / np.hypot(0.8, -0.3)  # from 2's image at (-0.6, 2.3) to 1, through the x face
    np.testing.assert_allclose(state.force_normal, [(2.0 * n[0] + 0.5 * n[1]) * n])
    np.testing.assert_allclose(state.force_normal + state.force_tangential, [[2.0, 0.5]])
    np.testing.assert_allclose(state.wall_force, [[0.2, 1.5]])  # a wall's force is kept whole
    contacts.write_text("i,j,f_x,f_y,f_z\n1,2,2.0,0.5,0\n")
    with pytest.raises(SourceError, match="c.csv.*'f_z': present, but the system is declared 2D"):
        table.read_state(particles, contacts, 2, "total", box=box, periodic=["x"])


def test_lammps_total_forces_give_its_normal_and_tangential_vectors(tmp_path):
    """LAMMPS's sheared run with a column of each pair's whole force (pair/local fx fy plus p1 p2): split along our
    nearest image in the tilted box it gives back LAMMPS's normal and tangential vectors."""
    folder = Path(__file__).resolve().parents[1] / "data" / "examples" / "lammps_triclinic_2d"
    lines = (folder / "pairs.dump").read_text().splitlines()
    for k, line in enumerate(lines):
        if line.startswith("ITEM: ENTRIES"):
            lines[k] = line + " t_x t_y"
        elif line and not line.startswith("ITEM") and len(line.split()) == 8:
            cells = [float(v) for v in line.split()]
            lines[k] = line + f" {cells[3] + cells[5]!r} {cells[4] + cells[6]!r}"
    pairs = tmp_path / "pairs.dump"
    pairs.write_text("\n".join(lines) + "\n")
    run = {"atoms": folder / "atoms.dump", "pairs": pairs}
    whole = lammps.read_run(run, 2, {"format": "lammps", "pair_columns": {"total": ["t_x", "t_y"]}})
    split = lammps.read_run(run, 2, {"format": "lammps", "pair_columns": {
        "normal": ["c_pf[2]", "c_pf[3]"], "tangential": ["c_pf[4]", "c_pf[5]", "c_pf[6]"]}})
    for ours, theirs in zip(whole, split):
        scale = np.abs(theirs.force_normal).max()
        assert np.abs(theirs.force_tangential).max() > 0.05 * scale  # friction carries a share
        np.testing.assert_allclose(ours.force_normal, theirs.force_normal, atol=1e-8 * scale)
        np.testing.assert_allclose(ours.force_tangential, theirs.force_tangential, atol=1e-8 * scale)


def test_p2_quarters_a_sheared_snapshot_along_its_tilted_edges(tmp_path):
    """P2 Tables II–III's blocks of the shipped sheared state at xy = 5 are the four parallelograms cut at half the
    edge vectors a and b (counted here from the dump's own text, not from the code: they differ from an orthogonal
    cut at the centre's x and y), and the table's diagrams are those blocks' own."""
    from forcenet.report.p2_distances import p2_network, quadrant_diagrams
    from forcenet.topology import persistence_diagrams

    folder = Path(__file__).resolve().parents[1] / "data" / "examples" / "lammps_triclinic_2d"
    entry = {"dimension": 2, "source": {"format": "lammps", "timesteps": [210000], "pair_columns": {
        "normal": "c_pf[1]", "tangential": ["c_pf[4]", "c_pf[5]", "c_pf[6]"]},
        "runs": [{"atoms": str(folder / "atoms.dump"), "pairs": str(folder / "pairs.dump")}]}}
    out = tmp_path / "rho0.864.nc"
    import_run(config={"systems": {"s": entry}}, system="s", realization=0, outputs=[str(out)])
    with read_snapshot(out) as snapshot:
        network = p2_network(snapshot, "normal", False)
        blocks = quadrant_diagrams(network, snapshot)
        lo, hi, position = snapshot["box_lo"].values, snapshot["box_hi"].values, snapshot["position"].values
    # the reference: timestep 210000's block of atoms.dump read by hand. LAMMPS writes the bounding box
    # (xlo + min(0, xy), xhi + max(0, xy)), so the box is undone by hand; a = (lx, 0), b = (xy, ly), and a centre
    # x = lo + s_x a + s_y b has s_y = (y − ylo) / ly, s_x = (x − xlo − s_y xy) / lx; ≥ 1/2 is the upper/right half
    text = (folder / "atoms.dump").read_text().splitlines()
    at = text.index("210000")
    (xlo_b, xhi_b, xy), (ylo, yhi, _) = (map(float, text[at + k].split()) for k in (4, 5))
    xlo, xhi = xlo_b - min(0.0, xy), xhi_b - max(0.0, xy)
    columns = text[at + 7].split()[2:]
    atoms = np.array([[float(v) for v in line.split()] for line in text[at + 8:at + 8 + int(text[at + 2])]])
    x, y = atoms[:, columns.index("x")], atoms[:, columns.index("y")]
    assert xy == 5.0 and len(x) == 200
    s_y = (y - ylo) / (yhi - ylo)
    s_x = (x - xlo - s_y * xy) / (xhi - xlo)
    tilted = {name: int(np.count_nonzero(((s_x >= 0.5) == bool(right)) & ((s_y >= 0.5) == bool(top))))
              for name, (right, top) in QUADRANTS.items()}
    mid_x, mid_y = 0.5 * (xlo + xhi), 0.5 * (ylo + yhi)
    straight = [int(np.count_nonzero(((x >= mid_x) == bool(right)) & ((y >= mid_y) == bool(top))))
                for right, top in QUADRANTS.values()]
    assert sum(tilted.values()) == sum(straight) == 200 and list(tilted.values()) != straight  # the tilt matters
    np.testing.assert_allclose([lo, hi], [[xlo, ylo], [xhi, yhi]])
    counts = {name: int(quadrant_mask(position, lo, hi, name, [xy]).sum()) for name in QUADRANTS}
    assert counts == tilted
    assert [int(quadrant_mask(position, lo, hi, name).sum()) for name in QUADRANTS] == straight
    for name in QUADRANTS:
        expected = persistence_diagrams(restrict_to_quadrant(network, lo, hi, name, [5.0]))
        np.testing.assert_array_equal(blocks[name].birth, expected.birth)
        np.testing.assert_array_equal(blocks[name].death, expected.death)
