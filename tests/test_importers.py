"""Importers (`forcenet.importers`): the shipped LAMMPS example gives the network our engine evaluates on the same
states, the hand-made contact table gives hand-counted Betti numbers and clusters, and malformed input stops with
one line naming the file and the line or column, writing nothing (issue 26 items 2 and 4)."""
from __future__ import annotations

import json
import shutil
from pathlib import Path

import numpy as np
import pytest
import yaml

from forcenet import pipeline
from forcenet.checks import checked_system
from forcenet.datasets import read_dataset, read_snapshot
from forcenet.datasets.diagrams import diagram_points
from forcenet.datasets.runs import run_expectation
from forcenet.importers import SourceError, import_run, source_states
from forcenet.importers import lammps, table
from forcenet.network import snapshot_network
from forcenet.topology import betti_curves, persistence_diagrams
from forcenet.plotting.networks import prepare_p1_fig01_networks
from forcenet.systems import ConfigError, ImportedSystem
from conftest import load_config
from naive_topology import components, pd0_elder_rule

REPO = Path(__file__).resolve().parents[1]
EXAMPLE = load_config("example_import.yaml")
LAMMPS_DIR = REPO / "data" / "examples" / "lammps_2d"
TABLE_DIR = REPO / "data" / "examples" / "table_2d"
#: the dumps print 10 significant digits (bench/lammps/make_import_example.py): forces agree to that precision
PRINTED = 1e-8


@pytest.fixture(autouse=True)
def at_repository_root(monkeypatch, tmp_path):
    monkeypatch.chdir(REPO)  # the example config's paths are relative to the repository root
    # the records of scanned sources (forcenet.importers.scan) go to the test's folder, not the checkout's
    monkeypatch.setenv("FORCENET_SOURCE_RECORDS", str(tmp_path / "source-records"))


# --- the LAMMPS examples against our engine on the same states --------------------------------------------------
def lammps_entry(folder: str, dimension: int) -> dict:
    """A `source:` entry for a shipped LAMMPS example (columns as config/example_import.yaml's lammps_2d)."""
    source = {**EXAMPLE["systems"]["lammps_2d"]["source"],
              "runs": [{"atoms": f"data/examples/{folder}/atoms.dump", "pairs": f"data/examples/{folder}/pairs.dump"}]}
    return {"dimension": dimension, "rho": list(EXAMPLE_RHO[folder]), "source": source}


#: the states' ρ of the shipped LAMMPS examples (bench/lammps/make_import_example.py --rho)
EXAMPLE_RHO = {"lammps_2d": (0.82, 0.84, 0.86), "lammps_3d": (0.58, 0.60, 0.62)}


def engine_contacts(folder: str, k: int):
    """State k of the example's states.npz evaluated by our engine, as its snapshots record contacts
    (`Simulation.contact_forces`) after the one spring increment LAMMPS made (bench/lammps_same_state.py's `damping`
    probe: the linear law in 2D, Hertz with every term × √R_eff in 3D)."""
    from forcenet.dem.engine import ContactLaw, Simulation

    z = np.load(REPO / "data" / "examples" / folder / "states.npz")
    law = ContactLaw(**{key: float(z[key]) for key in ("normal_stiffness", "tangential_stiffness", "normal_damping",
                                                       "tangential_damping", "friction", "beta")},
                     radius_scaled=bool(z["radius_scaled"]))
    sim = Simulation(position=z[f"positions{k}"], radius=z[f"radii{k}"], mass=z[f"masses{k}"], law=law,
                     time_step=float(z["dt"]), box_lo=z[f"box_lo{k}"], box_hi=z[f"box_hi{k}"],
                     velocity=z[f"velocities{k}"], walls="flat")
    sim.record(spring_dt=sim.time_step, spring=sim.contacts.spring, wall_spring=sim.walls.wall_spring)
    return sim.contact_forces(), z, sim


@pytest.mark.parametrize("folder, dimension", [("lammps_2d", 2), ("lammps_3d", 3)])
def test_the_lammps_examples_give_the_network_our_engine_evaluates_on_the_same_states(folder, dimension):
    states = source_states(lammps_entry(folder, dimension), 0)
    z = np.load(REPO / "data" / "examples" / folder / "states.npz")
    assert [s.timestep for s in states] == list(z["timesteps"]) == [1000, 2000, 3000]
    for k, state in enumerate(states):
        ours, z, sim = engine_contacts(folder, k)
        assert state.dimension == dimension and len(state.radius) > 300
        # a contact is a pair with a force (forcenet.network); LAMMPS lists neighbours without one as zero rows
        carries = (np.abs(ours.force_normal).sum(1) + np.abs(ours.force_tangential).sum(1)) > 0
        np.testing.assert_array_equal(state.contact_i, ours.contact_i[carries])
        np.testing.assert_array_equal(state.contact_j, ours.contact_j[carries])
        scale = np.abs(ours.force_normal).max()
        np.testing.assert_allclose(state.force_normal, ours.force_normal[carries], rtol=0, atol=PRINTED * scale)
        np.testing.assert_allclose(state.force_tangential, ours.force_tangential[carries], rtol=0,
                                   atol=PRINTED * scale)
        np.testing.assert_allclose(state.position, z[f"positions{k}"], rtol=PRINTED)
        assert state.rho == pytest.approx(sim.packing_fraction, rel=PRINTED)  # ρ from the dump's box
        # wall forces: fix wall/gran/region's per-atom output holds one wall contact per atom; ours lists each wall
        # a particle touches (a corner disk touches two), so the particles with one wall contact are compared
        pushing = np.abs(ours.wall_contact_force).sum(1) > 0  # a wall contact with a force, as for pairs
        particle, force, wall_id = (ours.wall_contact_particle[pushing], ours.wall_contact_force[pushing],
                                    ours.wall_contact_wall[pushing])
        walls_of = np.bincount(particle, minlength=len(state.radius))
        assert set(state.wall_particle.tolist()) == set(np.flatnonzero(walls_of).tolist())
        single = np.flatnonzero(walls_of[particle] == 1)
        assert len(single) > 30
        imported = dict(zip(state.wall_particle.tolist(), state.wall_force))
        np.testing.assert_allclose([imported[p] for p in particle[single]], force[single], rtol=0,
                                   atol=PRINTED * scale)
        np.testing.assert_array_equal([dict(zip(state.wall_particle.tolist(), state.wall_id))[p]
                                       for p in particle[single]], wall_id[single])
    # the comparison has teeth: the tangential forces are far above the precision it is made to
    assert len(states[0].contact_i) > 300 and np.abs(ours.force_tangential).max() > 1e4 * PRINTED * scale


def test_imported_and_engine_snapshots_pass_the_same_contract_and_record_their_source(tmp_path):
    outputs = [str(tmp_path / f"rho{label}.nc") for label in ("0.820", "0.840", "0.860")]
    import_run(config=EXAMPLE, system="lammps_2d", realization=0, outputs=outputs)
    ds = read_snapshot(outputs[1], expect=run_expectation(checked_system("lammps_2d", EXAMPLE), EXAMPLE))
    assert ds.attrs["source_format"] == "lammps" and ds.attrs["source_timestep"] == 2000
    assert json.loads(ds.attrs["source_files"]) == ["data/examples/lammps_2d/atoms.dump",
                                                    "data/examples/lammps_2d/pairs.dump"]
    from forcenet.importers import file_sha256
    assert json.loads(ds.attrs["source_sha256"])[0] == file_sha256(LAMMPS_DIR / "atoms.dump")
    assert ds.attrs["seed"] == -1 and "velocity" not in ds and float(ds.rho) == pytest.approx(0.84, abs=1e-6)
    spec = checked_system("lammps_2d", EXAMPLE)
    assert isinstance(spec, ImportedSystem) and spec.rho_labels == ["0.820", "0.840", "0.860"]
    assert spec.particles == 324 and spec.dimension == 2


# --- the hand-made table: hand-countable clusters and Betti numbers --------------------------------------------
def analysed_table(tmp_path, rule):
    """The first state of the table example, imported and analysed with rattler rule `rule`."""
    outputs = [str(tmp_path / f"rho{label}.nc") for label in checked_system("table_2d", EXAMPLE).rho_labels]
    import_run(config=EXAMPLE, system="table_2d", realization=0, outputs=outputs)
    analysis = {**pipeline.snapshot_analysis_params(EXAMPLE, "table_2d"), "remove_rattlers": rule}
    out = str(tmp_path / "analysis.nc")
    pipeline.analyze_run(snapshots=outputs[:1], outputs=[out], analysis=analysis)
    return read_dataset(out, "analysis").sel(force_kind="total")


def test_the_hand_made_table_gives_the_hand_counted_clusters_and_betti_numbers(tmp_path):
    """A square of four disks (edges 2), a separate pair (0.5), a lone disk; ⟨F⟩ = (4·2 + 0.5)/5 = 1.7, so the
    square's edges are 1.176 ⟨F⟩ and the pair's 0.294 ⟨F⟩."""
    kept = analysed_table(tmp_path / "none", "none")  # P2's rule: every particle kept
    assert float(kept["mean_force"]) == pytest.approx(1.7)
    clusters = kept["cluster_count"]
    assert int(clusters.sel(threshold=0.0)) == 3       # square, pair and the lone disk (a cluster at F_th ≤ 0)
    assert int(clusters.sel(threshold=0.05)) == 2      # the square and the pair
    assert int(kept["betti"].sel(homology_dim=0, threshold=0.0)) == 3
    assert int(clusters.sel(threshold=0.5)) == 1       # the pair (0.294) is gone
    assert int(clusters.sel(threshold=1.2)) == 0       # above the square's 1.176
    assert int(kept["betti"].sel(homology_dim=1, threshold=0.0)) == 1  # the square's loop
    assert int(kept["betti"].sel(homology_dim=1, threshold=1.2)) == 0
    assert int(kept["betti"].sel(homology_dim=0, threshold=0.5)) == 1
    assert int(kept["percolates"].sel(threshold=0.0)) == 0  # only the x_lo wall is touched
    once = analysed_table(tmp_path / "once", "once")  # P1's rule: the pair's disks (one contact) and the lone one go
    assert int(once["cluster_count"].sel(threshold=0.0)) == 1
    assert int(once["betti"].sel(homology_dim=0, threshold=0.0)) == 1
    assert int(once["betti"].sel(homology_dim=1, threshold=0.0)) == 1
    assert int(once["n_particles"]) == 7 and float(once["Z"]) == pytest.approx(10 / 7)


# --- malformed input: one line naming the file and the line or column, nothing written ---------------------------
PARTICLES = "id,x,y,radius\n1,1.0,1.0,0.5\n2,2.0,1.0,0.5\n3,2.0,2.0,0.5\n"
CONTACTS = "i,j,fn,ft\n1,2,1.0,0.1\n2,3,0.5,0.0\n"
TABLE_CASES = {
    # case: (particles text, contacts text, dimension, file, where and what the message says)
    "missing column": (PARTICLES.replace("radius", "r"), CONTACTS, 2, "p.csv", "column 'radius': missing"),
    "NaN position": (PARTICLES.replace("2.0,1.0", "nan,1.0"), CONTACTS, 2, "p.csv",
                     "line 3, column 'x': nan is not finite"),
    "negative radius": (PARTICLES.replace("2.0,2.0,0.5", "2.0,2.0,-0.5"), CONTACTS, 2, "p.csv",
                        "line 4, column 'radius': radius -0.5 is not positive"),
    "NaN force": (PARTICLES, CONTACTS.replace("0.5,0.0", "NaN,0.0"), 2, "c.csv",
                  "line 3, column 'fn': NaN is not finite"),
    "no such particle": (PARTICLES, CONTACTS.replace("2,3,", "2,9,"), 2, "c.csv",
                         "line 3, column 'j': no particle with id 9 in"),
    "2D file declared 3D": (PARTICLES, CONTACTS, 3, "p.csv", "column 'z': missing: the system is declared 3D"),
    "missing force column": (PARTICLES, CONTACTS.replace("ft", "f_t"), 2, "c.csv", "column 'ft': missing"),
}


@pytest.mark.parametrize("case", sorted(TABLE_CASES))
def test_a_malformed_table_stops_with_one_line_and_writes_nothing(tmp_path, case):
    particles, contacts, dimension, bad, expected = TABLE_CASES[case]
    (tmp_path / "p.csv").write_text(particles)
    (tmp_path / "c.csv").write_text(contacts)
    state = {"particles": str(tmp_path / "p.csv"), "contacts": str(tmp_path / "c.csv")}
    config = {"realizations": 1, "systems": {"t": {"dimension": dimension, "source": {
        "format": "table", "forces": "magnitudes", "runs": [[state]]}}}}
    out = tmp_path / "out" / "rho0.500.nc"
    with pytest.raises(SourceError) as caught:
        import_run(config=config, system="t", realization=0, outputs=[str(out)])
    message = str(caught.value)
    assert message.startswith(f"{tmp_path / bad}, ") and expected in message and "\n" not in message, message
    assert not out.parent.exists()
    # the workflow reads no source file when it parses the config: the import job is the first to read either
    config["systems"]["t"]["rho"] = [0.5]
    assert checked_system("t", config).rho_labels == ["0.500"]


def test_a_good_table_with_vectors_reads(tmp_path):
    (tmp_path / "p.csv").write_text(PARTICLES)
    (tmp_path / "c.csv").write_text("i,j,fn_x,fn_y,ft_x,ft_y\n2,1,1.0,0.0,0.0,0.25\n")
    state = table.read_state(tmp_path / "p.csv", tmp_path / "c.csv", 2, "vectors")
    # given as (2, 1): stored as (0, 1) with the forces on particle 1 (index 0), reversed
    assert (state.contact_i.tolist(), state.contact_j.tolist()) == ([0], [1])
    np.testing.assert_array_equal(state.force_normal, [[-1.0, 0.0]])
    np.testing.assert_array_equal(state.force_tangential, [[0.0, -0.25]])
    np.testing.assert_allclose(state.box_lo, [0.5, 0.5])  # the particles' bounding box
    np.testing.assert_allclose(state.rho, 3 * np.pi * 0.25 / 4.0)


def copy_dumps(tmp_path) -> tuple[Path, Path]:
    atoms, pairs = tmp_path / "atoms.dump", tmp_path / "pairs.dump"
    shutil.copy(LAMMPS_DIR / "atoms.dump", atoms)
    shutil.copy(LAMMPS_DIR / "pairs.dump", pairs)
    return atoms, pairs


def edit_line(path: Path, number: int, change) -> None:
    lines = path.read_text().splitlines()
    lines[number - 1] = change(lines[number - 1])
    path.write_text("\n".join(lines) + "\n")


def lammps_import(tmp_path, atoms, pairs, dimension=2):
    entry = {"dimension": dimension, "source": {**EXAMPLE["systems"]["lammps_2d"]["source"],
                                                "runs": [{"atoms": str(atoms), "pairs": str(pairs)}]}}
    out = tmp_path / "out"
    with pytest.raises(SourceError) as caught:
        import_run(config={"systems": {"l": entry}}, system="l", realization=0,
                   outputs=[str(out / f"rho0.{k}.nc") for k in range(3)])
    assert not out.exists()
    assert "\n" not in str(caught.value)
    return str(caught.value)


def test_lammps_dumps_whose_timesteps_differ_are_refused(tmp_path):
    atoms, pairs = copy_dumps(tmp_path)
    second = [k + 1 for k, line in enumerate(pairs.read_text().splitlines()) if line == "ITEM: TIMESTEP"][1]
    edit_line(pairs, second + 1, lambda line: "2500")
    message = lammps_import(tmp_path, atoms, pairs)
    assert message.startswith(f"{pairs}, line {second}: timestep 2500 where {atoms} has timestep 2000"), message
    atoms, pairs = copy_dumps(tmp_path)
    text = atoms.read_text()
    atoms.write_text(text[:text.rindex("ITEM: TIMESTEP")])  # the atoms dump lacks the last timestep
    assert "timestep 3000 has no match in" in lammps_import(tmp_path, atoms, pairs)


def test_lammps_nan_missing_column_and_dimension_are_refused(tmp_path):
    atoms, pairs = copy_dumps(tmp_path)
    edit_line(atoms, 11, lambda line: " ".join(["nan" if k == 2 else v for k, v in enumerate(line.split())]))
    assert lammps_import(tmp_path, atoms, pairs).startswith(f"{atoms}, line 11, column 'x': NaN or infinite value")
    atoms, pairs = copy_dumps(tmp_path)
    edit_line(atoms, 9, lambda line: line.replace(" radius", " size"))
    assert lammps_import(tmp_path, atoms, pairs).startswith(f"{atoms}, column 'radius': missing")
    atoms, pairs = copy_dumps(tmp_path)
    message = lammps_import(tmp_path, atoms, pairs, dimension=3)
    assert message.startswith(f"{atoms}, column 'z' (timestep 1000, line 1): every atom at z = 0: a 2D state, but "
                              "the system is declared 3D"), message
    atoms, pairs = copy_dumps(tmp_path)
    edit_line(pairs, 10, lambda line: " ".join(["99999" if k == 1 else v for k, v in enumerate(line.split())]))
    message = lammps_import(tmp_path, atoms, pairs)
    assert message.startswith(f"{pairs}, line 10, column 'c_pid[2]': atom id 99999 is not in {atoms} at timestep "
                              "1000"), message
    atoms, pairs = copy_dumps(tmp_path)
    edit_line(atoms, 11, lambda line: " ".join(["-0.5" if k == 5 else v for k, v in enumerate(line.split())]))
    assert lammps_import(tmp_path, atoms, pairs).startswith(f"{atoms}, line 11, column 'radius': radius -0.5 is not "
                                                            "positive")


def test_a_3d_lammps_dump_reads(tmp_path):
    atoms, pairs = tmp_path / "a.dump", tmp_path / "p.dump"
    head = "ITEM: TIMESTEP\n5\nITEM: NUMBER OF {}\n{}\nITEM: BOX BOUNDS ff ff ff\n0 2\n0 2\n0 2\n"
    atoms.write_text(head.format("ATOMS", 2) + "ITEM: ATOMS id type x y z radius\n1 1 0.5 0.5 0.5 0.5\n"
                     "2 1 0.5 0.5 1.4 0.5\n")
    pairs.write_text(head.format("ENTRIES", 1) + "ITEM: ENTRIES c_pid[1] c_pid[2] c_pf[1] c_pf[2] c_pf[3] c_pf[4]\n"
                     "2 1 3.0 0.5 0 0\n")
    source = {"format": "lammps"}
    (state,) = lammps.read_run({"atoms": atoms, "pairs": pairs}, 3, source)
    assert state.timestep == 5 and state.dimension == 3
    np.testing.assert_allclose(state.rho, 2 * 4 / 3 * np.pi * 0.125 / 8)
    # given on atom 2 from atom 1: stored on atom 1 (index 0) from atom 2, so both forces reversed
    np.testing.assert_allclose(state.force_normal, [[0, 0, -3.0]])
    np.testing.assert_allclose(state.force_tangential, [[-0.5, 0, 0]])



def periodic_dumps(tmp_path, bounds: str, wall: bool = False) -> tuple[Path, Path]:
    """Two disks of radius 0.5 touching across the x faces of a 10 × 4 box (x = 0.2 and 9.4: 0.8 apart through the
    face), a third 0.1 from the x_lo face and 0.9 from y_lo (with a wall force with `wall`); the pair's normal force
    given as a magnitude, 2.0."""
    atoms, pairs = tmp_path / "a.dump", tmp_path / "p.dump"
    head = "ITEM: TIMESTEP\n7\nITEM: NUMBER OF {}\n{}\nITEM: BOX BOUNDS " + bounds + "\n0 10\n0 4\n-0.5 0.5\n"
    extra = " fx" if wall else ""
    atoms.write_text(head.format("ATOMS", 3) + f"ITEM: ATOMS id x y z radius{extra}\n"
                     + f"1 0.2 2.0 0 0.5{' 0' if wall else ''}\n2 9.4 2.0 0 0.5{' 0' if wall else ''}\n"
                     + f"3 0.1 0.9 0 0.5{' 1.5' if wall else ''}\n")
    pairs.write_text(head.format("ENTRIES", 1) + "ITEM: ENTRIES c_pid[1] c_pid[2] c_pf[1] c_pf[2] c_pf[3] c_pf[4]\n"
                     "1 2 2.0 0 0 0\n")
    return atoms, pairs


def test_a_periodic_lammps_box_joins_a_pair_across_its_face(tmp_path):
    atoms, pairs = periodic_dumps(tmp_path, "pp ff pp")  # a 2D run: z is periodic by LAMMPS's rule and not counted
    (state,) = lammps.read_run({"atoms": atoms, "pairs": pairs}, 2, {"format": "lammps"})
    assert state.periodic_axes == "x"
    # atom 1 at x = 0.2 is pushed by atom 2's image at x = -0.6, so in +x (a bounded box would say -x)
    np.testing.assert_allclose(state.force_normal, [[2.0, 0.0]])
    atoms, pairs = periodic_dumps(tmp_path, "ff ff pp")
    (bounded,) = lammps.read_run({"atoms": atoms, "pairs": pairs}, 2, {"format": "lammps"})
    assert bounded.periodic_axes == ""
    np.testing.assert_allclose(bounded.force_normal, [[-2.0, 0.0]])


def test_a_periodic_import_records_its_axes_and_its_overlaps_go_through_the_face(tmp_path):
    from forcenet.datasets.schema import PERIODIC_AXES_ATTR
    from forcenet.report.p1 import relative_overlaps

    atoms, pairs = periodic_dumps(tmp_path, "pp pp pp")
    entry = {"dimension": 2, "source": {"format": "lammps", "runs": [{"atoms": str(atoms), "pairs": str(pairs)}]}}
    out = tmp_path / "rho.nc"
    import_run(config={"systems": {"p": entry}}, system="p", realization=0, outputs=[str(out)])
    with read_snapshot(out) as snapshot:
        assert snapshot.attrs[PERIODIC_AXES_ATTR] == "xy"
        overlaps, _ = relative_overlaps(snapshot)
        drawn = prepare_p1_fig01_networks({"p": snapshot}, rattler_rule=False).table
    np.testing.assert_allclose(overlaps, [(1.0 - 0.8) / 1.0])  # 0.8 apart through the face, not 9.2
    # P1 Fig. 1 draws the contact from atom 1 to atom 2's image beyond the x_lo face, not across the box
    edge = drawn[drawn["element"] == "contact"].iloc[0]
    # an import without a units block: its lengths in the source's unit, named so (issue 56)
    assert (edge["x_i [source length unit]"], edge["x_j [source length unit]"]) == pytest.approx((0.2, -0.6))
    atoms, pairs = periodic_dumps(tmp_path, "ff ff pp")
    import_run(config={"systems": {"p": entry}}, system="p", realization=0, outputs=[str(out)])
    with read_snapshot(out) as snapshot:
        assert PERIODIC_AXES_ATTR not in snapshot.attrs
        overlaps, _ = relative_overlaps(snapshot)
    np.testing.assert_allclose(overlaps, [(1.0 - 9.2) / 1.0])


@pytest.mark.parametrize("columns, atom_rows", [
    ("xs ys", ["0.02 0.5", "0.94 0.5", "0.01 0.225"]),  # scaled: fractions of the 10 x 4 box
    ("xu yu", ["10.2 2.0", "-0.6 2.0", "0.1 0.9"]),  # unwrapped: atoms 1 and 2 one box length outside, in x
    ("xsu ys", ["1.02 0.5", "-0.06 0.5", "0.01 0.225"]),
])
def test_scaled_and_unwrapped_lammps_positions_give_the_same_state(tmp_path, columns, atom_rows):
    atoms, pairs = periodic_dumps(tmp_path, "pp ff pp")
    (expected,) = lammps.read_run({"atoms": atoms, "pairs": pairs}, 2, {"format": "lammps"})
    text = atoms.read_text().replace("id x y z radius", f"id {columns} z radius")
    rows = text.splitlines()
    first = rows.index(f"ITEM: ATOMS id {columns} z radius") + 1
    for k, row in enumerate(atom_rows):
        cells = rows[first + k].split()
        rows[first + k] = " ".join([cells[0], *row.split(), *cells[3:]])
    atoms.write_text("\n".join(rows) + "\n")
    (state,) = lammps.read_run({"atoms": atoms, "pairs": pairs}, 2, {"format": "lammps"})
    np.testing.assert_allclose(state.position, expected.position, atol=1e-12)  # folded back into the periodic x
    np.testing.assert_allclose(state.force_normal, expected.force_normal)
    assert state.periodic_axes == "x"


def test_a_lammps_diameter_column_gives_the_radii(tmp_path):
    atoms, pairs = periodic_dumps(tmp_path, "ff ff pp")
    (expected,) = lammps.read_run({"atoms": atoms, "pairs": pairs}, 2, {"format": "lammps"})
    text = atoms.read_text().replace("id x y z radius", "id x y z diameter").replace(" 0.5\n", " 1.0\n")
    atoms.write_text(text.replace("3 0.1 0.9 0 1.0", "3 0.1 0.9 0 1.2"))
    (state,) = lammps.read_run({"atoms": atoms, "pairs": pairs}, 2, {"format": "lammps"})
    np.testing.assert_allclose(state.radius, [0.5, 0.5, 0.6])
    np.testing.assert_allclose(state.position, expected.position)
    atoms.write_text(text.replace("3 0.1 0.9 0 1.0", "3 0.1 0.9 0 0"))
    with pytest.raises(SourceError, match="column 'diameter'.*diameter 0 is not positive"):
        lammps.read_run({"atoms": atoms, "pairs": pairs}, 2, {"format": "lammps"})


def test_unwrapped_positions_stay_where_they_are_on_a_bounded_axis_and_a_dump_without_positions_is_named(tmp_path):
    atoms, pairs = periodic_dumps(tmp_path, "ff ff pp")
    atoms.write_text(atoms.read_text().replace("id x y z radius", "id xu y z radius").replace("9.4 2.0", "10.4 2.0"))
    (state,) = lammps.read_run({"atoms": atoms, "pairs": pairs}, 2, {"format": "lammps"})
    assert state.position[1, 0] == pytest.approx(10.4)
    atoms.write_text(atoms.read_text().replace("id xu y z radius", "id q y z radius"))
    with pytest.raises(SourceError, match=r"column 'x': missing \(the positions: one of x, xs, xu, xsu; the columns"):
        lammps.read_run({"atoms": atoms, "pairs": pairs}, 2, {"format": "lammps"})


def test_a_ring_of_contacts_around_a_periodic_import_percolates(tmp_path):
    from forcenet.measures import cluster_curves
    from forcenet.network import snapshot_network

    # four touching disks along y = 2 at x = 0.5 … 3.5 in a box 4 wide; the fourth contact, 4–1, goes through
    # the x face when x is periodic (in the bounded box it would join disks 3 apart: a loop, but no wall)
    atoms, pairs = tmp_path / "a.dump", tmp_path / "p.dump"
    for bounds in ("pp ff pp", "ff ff pp"):
        head = "ITEM: TIMESTEP\n7\nITEM: NUMBER OF {}\n{}\nITEM: BOX BOUNDS " + bounds + "\n0 4\n0 4\n-0.5 0.5\n"
        atoms.write_text(head.format("ATOMS", 4) + "ITEM: ATOMS id x y z radius\n"
                         + "".join(f"{k + 1} {k + 0.5} 2.0 0 0.5\n" for k in range(4)))
        pairs.write_text(head.format("ENTRIES", 4) + "ITEM: ENTRIES c_pid[1] c_pid[2] c_pf[1] c_pf[2] c_pf[3] "
                         "c_pf[4]\n1 2 2.0 0 0 0\n2 3 2.0 0 0 0\n3 4 2.0 0 0 0\n4 1 1.0 0 0 0\n")
        entry = {"dimension": 2, "source": {"format": "lammps", "runs": [{"atoms": str(atoms), "pairs": str(pairs)}]}}
        out = tmp_path / f"{bounds[:2]}.nc"
        import_run(config={"systems": {"p": entry}}, system="p", realization=0, outputs=[str(out)])
        with read_snapshot(out) as snapshot:
            network = snapshot_network(snapshot, rattler_rule="once")
            attrs = pipeline.analysis_attrs(snapshot, str(out), {"remove_rattlers": "once", "fill_tetrahedra": True})
        assert attrs.get("periodic_axes") == ("x" if bounds == "pp ff pp" else None)  # the analysis says so too
        # F_th in <F> = 1.75: the ring closes at F_th <= 1/1.75
        curves = cluster_curves(network, np.array([0.0, 0.5, 0.6]))
        expected = [True, True, False] if bounds == "pp ff pp" else [False, False, False]
        np.testing.assert_array_equal(curves.percolates, expected)


def test_walls_only_on_the_bounded_faces_of_a_periodic_box(tmp_path):
    atoms, pairs = periodic_dumps(tmp_path, "pp ff pp", wall=True)
    source = {"format": "lammps", "wall_columns": ["fx", "fx"]}
    (state,) = lammps.read_run({"atoms": atoms, "pairs": pairs}, 2, source)
    # atom 3 (index 2) at x = 0.1, y = 0.9: x has no faces, so its wall is y_lo (wall id 2)
    np.testing.assert_array_equal(state.wall_particle, [2])
    np.testing.assert_array_equal(state.wall_id, [2])
    atoms, pairs = periodic_dumps(tmp_path, "ff ff pp", wall=True)
    (bounded,) = lammps.read_run({"atoms": atoms, "pairs": pairs}, 2, source)
    np.testing.assert_array_equal(bounded.wall_id, [0])  # in a bounded box the nearest face, x_lo
    atoms, pairs = periodic_dumps(tmp_path, "pp pp pp", wall=True)
    with pytest.raises(SourceError, match="every axis of the box is periodic: no walls"):
        lammps.read_run({"atoms": atoms, "pairs": pairs}, 2, source)


def test_a_periodic_table_joins_a_pair_across_its_face_and_names_what_it_cannot_read(tmp_path):
    particles, contacts = tmp_path / "p.csv", tmp_path / "c.csv"
    particles.write_text("id,x,y,radius\n1,0.2,2.0,0.5\n2,9.4,2.0,0.5\n3,0.1,0.9,0.5\n")
    contacts.write_text("i,j,fn,ft\n1,2,2.0,0.0\n")
    box = {"lo": [0, 0], "hi": [10, 4]}
    state = table.read_state(particles, contacts, 2, "magnitudes", box=box, periodic=["x"])
    assert state.periodic_axes == "x"
    np.testing.assert_allclose(state.force_normal, [[2.0, 0.0]])  # from 2's image at x = -0.6, through the face
    bounded = table.read_state(particles, contacts, 2, "magnitudes", box=box)
    assert bounded.periodic_axes == ""
    np.testing.assert_allclose(bounded.force_normal, [[-2.0, 0.0]])
    with pytest.raises(SourceError, match="p.csv, box: a periodic box must be given"):
        table.read_state(particles, contacts, 2, "magnitudes", periodic=["x"])
    with pytest.raises(SourceError, match="source.periodic: axis 'z' is not an axis of a 2D system"):
        table.read_state(particles, contacts, 2, "magnitudes", box=box, periodic=["z"])
    contacts.write_text("i,j,fn,ft\n1,2,2.0,0.0\n3,x_lo,1.0,0.0\n")
    with pytest.raises(SourceError, match="c.csv, line 3, column 'j': wall x_lo on an axis the box is periodic on"):
        table.read_state(particles, contacts, 2, "magnitudes", box=box, periodic=["x"])
    assert table.read_state(particles, contacts, 2, "magnitudes", box=box, periodic=["y"]).wall_id.tolist() == [0]


# --- the config: schema and checks of a `source:` entry -----------------------------------------------------------
def checked(config):
    from forcenet.workflow_io import CONFIG_SCHEMA, checked_config

    return checked_config(config, REPO / CONFIG_SCHEMA)


def test_the_example_config_passes_and_a_bad_source_entry_names_its_key():
    systems = checked(EXAMPLE)
    assert sorted(systems) == ["lammps_2d", "lammps_2d_p2", "lammps_sheared_2d", "table_2d"]
    assert "material" not in EXAMPLE
    tilted = {**EXAMPLE, "systems": {**EXAMPLE["systems"], "lammps_2d": {**EXAMPLE["systems"]["lammps_2d"], "source": {
        **EXAMPLE["systems"]["lammps_2d"]["source"], "box": {"lo": [0, 0], "hi": [4, 4], "tilt": [1, 0, 0, 2]}}}}}
    with pytest.raises(ConfigError, match="config key 'systems.lammps_2d.source.box.tilt'"):
        checked(tilted)
    both = {**EXAMPLE, "systems": {**EXAMPLE["systems"], "lammps_2d": {**EXAMPLE["systems"]["lammps_2d"], "source": {
        **EXAMPLE["systems"]["lammps_2d"]["source"], "pair_columns": {"normal": "c_pf[1]", "total": ["a", "b"]}}}}}
    with pytest.raises(ConfigError, match="config key 'systems.lammps_2d.source.pair_columns.normal'"):
        checked(both)  # a total force is split by forcenet: not given beside its parts
    mixed = {**EXAMPLE, "systems": {**EXAMPLE["systems"], "table_2d": {**EXAMPLE["systems"]["table_2d"],
                                                                        "force_law": "hertz"}}}
    with pytest.raises(ConfigError, match="config key 'systems.table_2d': .*'force_law' was unexpected"):
        checked(mixed)
    no_forces = {k: v for k, v in EXAMPLE["systems"]["table_2d"]["source"].items() if k != "forces"}
    with pytest.raises(ConfigError, match="config key 'systems.table_2d.source': 'forces' is a required property"):
        checked({**EXAMPLE, "systems": {"table_2d": {"dimension": 2, "source": no_forces}},
                 "studies": {"p1": {"systems": ["table_2d"]}}})
    same_rho = [dict(state, box={"lo": [0, 0], "hi": [6, 4]})
                for state in EXAMPLE["systems"]["table_2d"]["source"]["runs"][0]]
    flat = {"dimension": 2, "source": {**EXAMPLE["systems"]["table_2d"]["source"], "runs": [same_rho]}}
    # states at one ρ, or in the wrong order: found when the files are read (the import job, forcenet-check-config)
    config = {**EXAMPLE, "systems": {"table_2d": flat}, "studies": {"p1": {"systems": ["table_2d"]}}}
    with pytest.raises(ConfigError, match="config key 'systems.table_2d.rho': not given: an imported compression"):
        checked(config)
    with pytest.raises(SourceError, match="particles.csv, systems.table_2d.source.runs\\[0\\]: states with the same ρ "
                                          "at 3 decimals .* is one run with source.sequence"):
        import_run(config=config, system="table_2d", realization=0, outputs=["a.nc", "b.nc", "c.nc"])
    backwards = {"dimension": 2, "rho": [0.229, 0.233, 0.237],
                 "source": {**EXAMPLE["systems"]["table_2d"]["source"],
                            "runs": [EXAMPLE["systems"]["table_2d"]["source"]["runs"][0][::-1]]}}
    config = {**EXAMPLE, "systems": {"table_2d": backwards}, "studies": {"p1": {"systems": ["table_2d"]}}}
    assert checked(config)["table_2d"].rho_labels == ["0.229", "0.233", "0.237"]
    with pytest.raises(SourceError, match="particles_2.csv, state 0: ρ = 0.23[0-9]* \\(0.237 at 3 decimals\\), but "
                                          "systems.table_2d.rho declares 0.229 for state 0"):
        import_run(config=config, system="table_2d", realization=0, outputs=["a.nc", "b.nc", "c.nc"])
    with pytest.raises(ConfigError, match="config key 'systems.table_2d.rho': declares 2 state\\(s\\), but "
                                          "source.runs\\[0\\] lists 3"):
        checked({**config, "systems": {"table_2d": {**backwards, "rho": [0.2, 0.3]}}})
    with pytest.raises(ConfigError, match="config key 'systems.lammps_2d.source.runs': lists 1 run\\(s\\), but "
                                          "realizations is 2: one run per realization"):
        checked({**EXAMPLE, "realizations": 2})
    # a LAMMPS dump says its own periodic axes (BOX BOUNDS); a table names them, known axes only
    lammps_periodic = {**EXAMPLE["systems"]["lammps_2d"],
                       "source": {**EXAMPLE["systems"]["lammps_2d"]["source"], "periodic": ["x"]}}
    with pytest.raises(ConfigError, match="config key 'systems.lammps_2d.source.periodic': not allowed in this entry"):
        checked({**EXAMPLE, "systems": {**EXAMPLE["systems"], "lammps_2d": lammps_periodic}})
    lammps_forces = {**EXAMPLE["systems"]["lammps_2d"],
                     "source": {**EXAMPLE["systems"]["lammps_2d"]["source"], "forces": "vectors"}}
    with pytest.raises(ConfigError, match="config key 'systems.lammps_2d.source.forces': not allowed in this entry"):
        checked({**EXAMPLE, "systems": {**EXAMPLE["systems"], "lammps_2d": lammps_forces}})
    table_w = {**EXAMPLE["systems"]["table_2d"], "source": {**EXAMPLE["systems"]["table_2d"]["source"],
                                                             "periodic": ["w"]}}
    with pytest.raises(ConfigError, match="config key 'systems.table_2d.source.periodic"):
        checked({**EXAMPLE, "systems": {**EXAMPLE["systems"], "table_2d": table_w}})


def euler_characteristic(edges, fill_tetrahedra: bool) -> int:
    """V − E + T (− Q with `fill_tetrahedra`) of the clique complex of `edges`, by plain clique search: the
    vertices touched, the edges, the common neighbours of each edge, then of each triangle. Unfilled (P1's B2
    counts hollow 4-cliques), a tetrahedron adds no cell: its hollow surface is a 2-cycle, B2 counts it."""
    neighbours = {}
    for a, b in edges:
        neighbours.setdefault(a, set()).add(b)
        neighbours.setdefault(b, set()).add(a)
    pairs = {tuple(sorted(e)) for e in edges}
    triangles = {tuple(sorted((a, b, c))) for a, b in pairs for c in neighbours[a] & neighbours[b]}
    tetrahedra = {tuple(sorted((*tri, d))) for tri in triangles
                  for d in neighbours[tri[0]] & neighbours[tri[1]] & neighbours[tri[2]]}
    return len(neighbours) - len(pairs) + len(triangles) - (len(tetrahedra) if fill_tetrahedra else 0)


def test_a_3d_lammps_state_is_imported_and_analysed(tmp_path):
    config = {**EXAMPLE, "systems": {"lammps_3d": lammps_entry("lammps_3d", 3)}, "studies": {}}
    spec = checked_system("lammps_3d", config)
    assert spec.rho_labels == ["0.580", "0.600", "0.620"] and spec.dimension == 3
    snapshot, analysis = tmp_path / "rho0.620.nc", tmp_path / "a.nc"
    outputs = [str(tmp_path / f"rho{label}.nc") for label in spec.rho_labels]
    import_run(config=config, system="lammps_3d", realization=0, outputs=outputs)
    pipeline.analyze_run(snapshots=[str(snapshot)], outputs=[str(analysis)],
                         analysis=pipeline.snapshot_analysis_params(config, "lammps_3d"),
                         expect=run_expectation(checked_system("lammps_3d", config), config))
    ds = read_dataset(analysis, "analysis")
    assert list(ds["homology_dim"].values) == [0, 1, 2] and ds.attrs["source_format"] == "lammps"
    assert int(ds["betti"].sel(force_kind="total", homology_dim=0, threshold=0.0)) >= 1
    assert json.loads(ds.attrs["source_files"])[0] == "data/examples/lammps_3d/atoms.dump"
    # "analysed": the stored file is the analysis of this very snapshot, recomputed here from the imported state
    params = pipeline.snapshot_analysis_params(config, "lammps_3d")
    theta = ds["threshold"].values
    with read_snapshot(snapshot) as snap:
        total = np.linalg.norm(snap["force_normal"].values + snap["force_tangential"].values, axis=1)
        networks = {kind: snapshot_network(snap, kind, rattler_rule=params["remove_rattlers"], wall_contacts="kept")
                    for kind in ("total", "normal", "tangential")}
    assert float(ds["mean_force"].sel(force_kind="total")) == pytest.approx(total.mean(), rel=1e-12)  # P1's ⟨F⟩
    for kind, network in networks.items():
        diagrams = persistence_diagrams(network, fill_tetrahedra=params["fill_tetrahedra"])
        np.testing.assert_array_equal(ds["betti"].sel(force_kind=kind).values, betti_curves(diagrams, theta, 2))
        for k in (0, 1, 2):
            stored, ours = diagram_points(ds, kind, k), diagrams.points(k)
            np.testing.assert_array_equal(np.sort(stored.birth), np.sort(ours[:, 0]))
            np.testing.assert_array_equal(np.sort(stored.death), np.sort(ours[:, 1]))
    # and against slow references on the total network: PD0 by union–find with the elder rule, B0 by
    # breadth-first search, and the Euler characteristic V − E + T (− Q) = B0 − B1 + B2 of the complex
    network = networks["total"]
    keep = np.flatnonzero(network.particle_mask)
    compact = {v: k for k, v in enumerate(keep)}
    edges = [(compact[a], compact[b]) for a, b in zip(network.edge_i.tolist(), network.edge_j.tolist())]
    force = network.force.tolist()
    assert {v for e in edges for v in e} == set(range(len(keep)))  # no kept particle without a contact
    finite, essential = pd0_elder_rule(len(keep), edges, force)
    pd0 = diagram_points(ds, "total", 0)
    stored = sorted(zip(pd0.birth[~pd0.essential].tolist(), pd0.death[~pd0.essential].tolist()))
    np.testing.assert_allclose(np.array(stored).reshape(-1, 2), np.array(finite).reshape(-1, 2), rtol=1e-12)
    np.testing.assert_allclose(np.sort(pd0.birth[pd0.essential]), essential, rtol=1e-12)
    betti = ds["betti"].sel(force_kind="total").values
    for t, level in enumerate(theta):
        strong = [e for e, f in zip(edges, force) if f >= level]
        assert betti[0, t] == len(components(len(keep), strong, np.ones(len(strong)), 0.5))
        assert betti[0, t] - betti[1, t] + betti[2, t] == euler_characteristic(strong, params["fill_tetrahedra"])


def test_gzipped_dumps_and_tables_read_as_the_plain_files_and_a_broken_one_is_named(tmp_path):
    import gzip

    plain = lammps.read_run({"atoms": LAMMPS_DIR / "atoms.dump", "pairs": LAMMPS_DIR / "pairs.dump"}, 2,
                            {"format": "lammps"})
    for name in ("atoms.dump", "pairs.dump"):  # as LAMMPS's dump custom/gz and local/gz write them
        (tmp_path / f"{name}.gz").write_bytes(gzip.compress((LAMMPS_DIR / name).read_bytes()))
    zipped = lammps.read_run({"atoms": tmp_path / "atoms.dump.gz", "pairs": tmp_path / "pairs.dump.gz"}, 2,
                             {"format": "lammps"})
    assert len(zipped) == len(plain) == 3
    for a, b in zip(zipped, plain):
        np.testing.assert_array_equal(a.position, b.position)
        np.testing.assert_array_equal(a.force_normal, b.force_normal)
        np.testing.assert_array_equal(a.force_tangential, b.force_tangential)
    for name in ("particles.csv", "contacts.csv"):
        (tmp_path / f"{name}.gz").write_bytes(gzip.compress((TABLE_DIR / name).read_bytes()))
    table_zipped = table.read_state(tmp_path / "particles.csv.gz", tmp_path / "contacts.csv.gz", 2, "magnitudes")
    table_plain = table.read_state(TABLE_DIR / "particles.csv", TABLE_DIR / "contacts.csv", 2, "magnitudes")
    np.testing.assert_array_equal(table_zipped.force_normal, table_plain.force_normal)
    (tmp_path / "broken.dump.gz").write_bytes(b"not gzip at all")
    with pytest.raises(SourceError, match="broken.dump.gz: cannot be read"):
        lammps.read_run({"atoms": tmp_path / "broken.dump.gz", "pairs": tmp_path / "pairs.dump.gz"}, 2,
                        {"format": "lammps"})


def test_a_stacked_file_of_an_imported_system_records_no_seed_as_its_snapshots():
    """network_measures.nc and distances.nc of an import say seed −1, as its snapshots do; a simulated system's
    stacked files give the config's base seed."""
    config = load_config("smoke.yaml")
    imported = ImportedSystem(name="my_table", dimension=2, rho_grid=(0.8,), source={})
    assert pipeline.stacked_seed(config, imported) == -1
    assert pipeline.stacked_seed(config, checked_system("2d_linear", config)) == config["seed"]
