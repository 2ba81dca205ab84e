"""The conventions of real inputs (issue 56 item 3, docs/importing.md "Conventions of real inputs"): several wall
fixes in one LAMMPS run, signed tangential components, contacts given once from each side. For each option: the
refusal without it, whose one line names the option that accepts the data, and a passing case with the forces as
given; both importers read the same option the same way."""
from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from forcenet import pipeline
from forcenet.datasets import read_dataset, read_snapshot
from forcenet.datasets.io import schema_problems
from forcenet.datasets.schema import SNAPSHOT_IMPORT_VARIABLES
from forcenet.importers import SourceError, import_run
from forcenet.importers import lammps, table
from forcenet.systems import ConfigError
from conftest import load_config

REPO = Path(__file__).resolve().parents[1]
EXAMPLE = load_config("example_import.yaml")


@pytest.fixture(autouse=True)
def at_repository_root(monkeypatch, tmp_path):
    monkeypatch.chdir(REPO)
    monkeypatch.setenv("FORCENET_SOURCE_RECORDS", str(tmp_path / "source-records"))


def refusal(read, *args, **kwargs) -> str:
    """The message of the `SourceError` that `read(*args, **kwargs)` raises: one line."""
    with pytest.raises(SourceError) as caught:
        read(*args, **kwargs)
    assert "\n" not in str(caught.value)
    return str(caught.value)


# --- several wall fixes per LAMMPS run -----------------------------------------------------------------------------
#: LAMMPS's granular examples bound a box with one `fix wall/gran` per axis; their per-atom forces (the `contacts`
#: keyword's columns 2-4) dumped as fx_* (the x fix) and fy_* (the y fix). Atom 1 sits in the x_lo/y_lo corner and
#: touches both walls; atom 2 touches y_lo only; atom 3 touches x_hi only.
CORNER_ATOMS = ("ITEM: TIMESTEP\n100\nITEM: NUMBER OF ATOMS\n3\nITEM: BOX BOUNDS ff ff pp\n0 4\n0 4\n-0.5 0.5\n"
                "ITEM: ATOMS id type x y z radius fxx fxy fyx fyy\n"
                "1 1 0.5 0.5 0 0.5 2.0 0.1 0.2 3.0\n"
                "2 1 1.45 0.5 0 0.5 0 0 0.0 1.5\n"
                "3 1 3.5 2.0 0 0.5 -1.0 0.25 0 0\n")
CORNER_PAIRS = ("ITEM: TIMESTEP\n100\nITEM: NUMBER OF ENTRIES\n1\nITEM: BOX BOUNDS ff ff pp\n0 4\n0 4\n-0.5 0.5\n"
                "ITEM: ENTRIES c_pid[1] c_pid[2] c_pf[1] c_pf[2] c_pf[3] c_pf[4]\n"
                "1 2 0.8 0 0.05 0\n")
TWO_FIXES = [{"columns": ["fxx", "fxy"], "walls": ["x_lo", "x_hi"]},
             {"columns": ["fyx", "fyy"], "walls": ["y_lo", "y_hi"]}]


def corner_dumps(tmp_path, atoms: str = CORNER_ATOMS, pairs: str = CORNER_PAIRS) -> dict:
    (tmp_path / "atoms.dump").write_text(atoms)
    (tmp_path / "pairs.dump").write_text(pairs)
    return {"atoms": str(tmp_path / "atoms.dump"), "pairs": str(tmp_path / "pairs.dump")}


def test_a_corner_particle_touching_two_walls_gets_two_wall_contacts_with_the_forces_as_given(tmp_path):
    run = corner_dumps(tmp_path)
    (state,) = lammps.read_run(run, 2, {"format": "lammps", "wall_columns": TWO_FIXES})
    # atom 1 (index 0): x_lo (0) from the x fix and y_lo (2) from the y fix; atom 2: y_lo; atom 3: x_hi (1)
    assert state.wall_particle.tolist() == [0, 0, 1, 2]
    assert state.wall_id.tolist() == [0, 2, 2, 1]
    np.testing.assert_array_equal(state.wall_force, [[2.0, 0.1], [0.2, 3.0], [0.0, 1.5], [-1.0, 0.25]])
    # the same columns as one source (the single-fix form): one contact per atom, the corner atom's at one face
    (single,) = lammps.read_run(run, 2, {"format": "lammps", "wall_columns": ["fyx", "fyy"]})
    assert single.wall_particle.tolist() == [0, 1]
    # the snapshot keeps both of the corner's contacts
    out = tmp_path / "out" / "rho0.147.nc"
    config = {"systems": {"c": {"dimension": 2, "source": {"format": "lammps", "runs": [run],
                                                           "wall_columns": TWO_FIXES}}}}
    import_run(config=config, system="c", realization=0, outputs=[str(out)])
    ds = read_snapshot(out)
    assert ds["wall_contact_particle"].values.tolist() == [0, 0, 1, 2]
    assert ds["wall_contact_wall"].values.tolist() == [0, 2, 2, 1]


def test_wall_sources_on_one_wall_are_summed_per_wall_when_the_config_says_so(tmp_path):
    # a second fix on the bottom wall (a rough floor beside the flat y wall): atom 2 has a force from both
    atoms = CORNER_ATOMS.split("ITEM: ATOMS")[0] + ("ITEM: ATOMS id type x y z radius fxx fxy fyx fyy gx gy\n"
                                                    "1 1 0.5 0.5 0 0.5 2.0 0.1 0.2 3.0 0 0\n"
                                                    "2 1 1.45 0.5 0 0.5 0 0 0.0 1.5 0.1 0.5\n"
                                                    "3 1 3.5 2.0 0 0.5 -1.0 0.25 0 0 0 0\n")
    run = corner_dumps(tmp_path, atoms)
    three = [*TWO_FIXES, {"columns": ["gx", "gy"], "walls": ["y_lo"]}]
    (separate,) = lammps.read_run(run, 2, {"format": "lammps", "wall_columns": three})
    assert separate.wall_particle.tolist() == [0, 0, 1, 1, 2] and separate.wall_id.tolist() == [0, 2, 2, 2, 1]
    (summed,) = lammps.read_run(run, 2, {"format": "lammps", "wall_columns": three, "wall_forces": "summed_per_wall"})
    assert summed.wall_particle.tolist() == [0, 0, 1, 2] and summed.wall_id.tolist() == [0, 2, 2, 1]
    np.testing.assert_allclose(summed.wall_force, [[2.0, 0.1], [0.2, 3.0], [0.1, 2.0], [-1.0, 0.25]])


def test_a_wall_source_that_cannot_be_placed_is_named(tmp_path):
    run = corner_dumps(tmp_path)
    with pytest.raises(SourceError, match=r"^source.wall_columns\[1\], walls: 'z_lo' is not a wall of a 2D system"):
        lammps.read_run(run, 2, {"format": "lammps", "wall_columns": [TWO_FIXES[0], {**TWO_FIXES[1],
                                                                                      "walls": ["z_lo"]}]})
    run = corner_dumps(tmp_path, CORNER_ATOMS.replace("ff ff pp", "pp ff pp"), CORNER_PAIRS.replace("ff ff pp",
                                                                                                    "pp ff pp"))
    message = refusal(lammps.read_run, run, 2, {"format": "lammps", "wall_columns": TWO_FIXES})
    assert message == (f"{run['atoms']}, timestep 100 (line 1): wall forces in source.wall_columns[0], whose walls "
                       "(x_lo, x_hi) lie on periodic axes of the box: no walls there")


def test_table_rows_of_one_particle_at_one_wall_follow_the_same_rule(tmp_path):
    (tmp_path / "p.csv").write_text("id,x,y,radius\n1,0.5,0.5,0.5\n2,1.5,0.5,0.5\n")
    (tmp_path / "c.csv").write_text("i,j,f_x,f_y\n1,x_lo,2.0,0.1\n1,y_lo,0.2,3.0\n2,y_lo,0,1.5\n2,y_lo,0.1,0.5\n")
    box = {"lo": [0, 0], "hi": [4, 4]}
    state = table.read_state(tmp_path / "p.csv", tmp_path / "c.csv", 2, "total", box=box)
    assert state.wall_particle.tolist() == [0, 0, 1, 1] and state.wall_id.tolist() == [0, 2, 2, 2]
    summed = table.read_state(tmp_path / "p.csv", tmp_path / "c.csv", 2, "total", box=box,
                              source={"wall_forces": "summed_per_wall"})
    assert summed.wall_particle.tolist() == [0, 0, 1] and summed.wall_id.tolist() == [0, 2, 2]
    np.testing.assert_allclose(summed.wall_force, [[2.0, 0.1], [0.2, 3.0], [0.1, 2.0]])


# --- signed tangential components ----------------------------------------------------------------------------------
PARTICLES = "id,x,y,radius\n13,1.0,1.0,0.5\n43,1.9,1.0,0.5\n7,1.0,1.9,0.5\n"
SIGNED = "i,j,fn,ft\n13,43,1.0,-0.25\n13,7,0.5,0.1\n"


def table_files(tmp_path, contacts: str, particles: str = PARTICLES) -> tuple[Path, Path]:
    (tmp_path / "p.csv").write_text(particles)
    (tmp_path / "c.csv").write_text(contacts)
    return tmp_path / "p.csv", tmp_path / "c.csv"


def test_a_signed_tangential_component_is_refused_naming_the_option_and_read_as_it_states(tmp_path):
    p, c = table_files(tmp_path, SIGNED)
    assert refusal(table.read_state, p, c, 2, "magnitudes") == (
        f"{c}, line 2, column 'ft': a force magnitude must be ≥ 0, got -0.25: a signed tangential component is read "
        "with source.signed_tangential: magnitude (|ft| taken) or vector (its sign kept, along the normal turned by "
        "+90°)")
    # a negative normal force is no convention: refused under either value
    p, c = table_files(tmp_path, SIGNED.replace("1.0,-0.25", "-1.0,-0.25"))
    with pytest.raises(SourceError, match="line 2, column 'fn': a force magnitude must be ≥ 0, got -1$"):
        table.read_state(p, c, 2, "magnitudes", source={"signed_tangential": "vector"})
    p, c = table_files(tmp_path, SIGNED)
    # contact 13-43: n from 43 to 13 is -x, turned by +90° is -y
    magnitude = table.read_state(p, c, 2, "magnitudes", source={"signed_tangential": "magnitude"})
    np.testing.assert_allclose(magnitude.force_normal[0], [-1.0, 0.0])
    np.testing.assert_allclose(magnitude.force_tangential[0], [0.0, -0.25])
    vector = table.read_state(p, c, 2, "magnitudes", source={"signed_tangential": "vector"})
    np.testing.assert_allclose(vector.force_tangential[0], [0.0, 0.25])
    np.testing.assert_allclose(vector.force_tangential[1], magnitude.force_tangential[1])  # a positive ft: the same


def test_signed_tangential_is_refused_where_it_cannot_apply(tmp_path):
    p, c = table_files(tmp_path, "i,j,fn_x,fn_y,ft_x,ft_y\n13,43,-1,0,0,-0.25\n")
    with pytest.raises(SourceError, match="^source.signed_tangential: applies to a tangential force given as one "
                                          "column"):
        table.read_state(p, c, 2, "vectors", source={"signed_tangential": "vector"})
    p, c = table_files(tmp_path, SIGNED, "id,x,y,z,radius\n13,1,1,1,0.5\n43,1.9,1,1,0.5\n7,1,1.9,1,0.5\n")
    with pytest.raises(SourceError, match="^source.signed_tangential: vector: the sign of one tangential component "
                                          "names a direction only in 2D"):
        table.read_state(p, c, 3, "magnitudes", source={"signed_tangential": "vector"})
    state = table.read_state(p, c, 3, "magnitudes", source={"signed_tangential": "magnitude"})
    np.testing.assert_allclose(np.linalg.norm(state.force_tangential, axis=1), [0.25, 0.1])


LAMMPS_ATOMS = ("ITEM: TIMESTEP\n5\nITEM: NUMBER OF ATOMS\n3\nITEM: BOX BOUNDS ff ff pp\n0 4\n0 4\n-0.5 0.5\n"
                "ITEM: ATOMS id x y z radius\n13 1.0 1.0 0 0.5\n43 1.9 1.0 0 0.5\n7 1.0 1.9 0 0.5\n")
LAMMPS_PAIRS = ("ITEM: TIMESTEP\n5\nITEM: NUMBER OF ENTRIES\n{}\nITEM: BOX BOUNDS ff ff pp\n0 4\n0 4\n-0.5 0.5\n"
                "ITEM: ENTRIES id1 id2 fn ft\n{}")
ONE_COLUMN = {"format": "lammps", "pair_columns": {"i": "id1", "j": "id2", "normal": "fn", "tangential": "ft"}}


def by_atom_ids(state, ids) -> dict:
    """{(smaller id, larger id): (F_n, F_t on the smaller id's particle, disagreement or None)} of a state whose
    particles have `ids` in index order."""
    contacts = {}
    for k, (a, b) in enumerate(zip(state.contact_i, state.contact_j)):
        sign = 1.0 if ids[a] < ids[b] else -1.0
        disagreement = None if state.force_disagreement is None else state.force_disagreement[k]
        contacts[tuple(sorted((ids[a], ids[b])))] = (sign * state.force_normal[k], sign * state.force_tangential[k],
                                                     disagreement)
    return contacts


def assert_same_contacts(dumped, tabled):
    """The LAMMPS state (atoms in id order: 7, 13, 43) and the table's (file order: 13, 43, 7) hold the same
    contacts with the same forces."""
    ours, theirs = by_atom_ids(dumped, [7, 13, 43]), by_atom_ids(tabled, [13, 43, 7])
    assert sorted(ours) == sorted(theirs)
    for pair, (fn, ft, disagreement) in theirs.items():
        np.testing.assert_allclose(ours[pair][0], fn)
        np.testing.assert_allclose(ours[pair][1], ft)
        np.testing.assert_allclose(np.asarray(ours[pair][2], float), np.asarray(disagreement, float))


def test_a_lammps_one_column_tangential_is_signed_as_in_a_table(tmp_path):
    run = corner_dumps(tmp_path, LAMMPS_ATOMS, LAMMPS_PAIRS.format(2, "13 43 1.0 -0.25\n13 7 0.5 0.1\n"))
    assert refusal(lammps.read_run, run, 2, ONE_COLUMN).startswith(
        f"{run['pairs']}, line 10, column 'ft': a force magnitude must be ≥ 0, got -0.25: a signed tangential "
        "component is read with source.signed_tangential")
    p, c = table_files(tmp_path, SIGNED)
    for rule in ("magnitude", "vector"):
        (state,) = lammps.read_run(run, 2, {**ONE_COLUMN, "signed_tangential": rule})
        same = table.read_state(p, c, 2, "magnitudes", source={"signed_tangential": rule})
        assert_same_contacts(state, same)
    with pytest.raises(SourceError, match="^source.signed_tangential: applies to a tangential force given as one"):
        lammps.read_run(run, 2, {**ONE_COLUMN, "pair_columns": {**ONE_COLUMN["pair_columns"], "tangential":
                                                                ["fn", "ft"]}, "signed_tangential": "magnitude"})


# --- contacts given once from each side ----------------------------------------------------------------------------
TWO_SIDED = "i,j,fn,ft\n13,43,1.0,0.2\n13,7,0.5,0.1\n43,13,1.2,0.1\n"


def test_a_contact_given_from_each_side_is_refused_naming_the_option(tmp_path):
    p, c = table_files(tmp_path, TWO_SIDED)
    assert refusal(table.read_state, p, c, 2, "magnitudes") == (
        f"{c}, line 4: contact 13-43 appears twice, once from each side (first on line 2): source.duplicate_contacts: "
        "mean merges them (the mean of the two estimates, their disagreement recorded)")
    same_side = TWO_SIDED.replace("43,13,1.2", "13,43,1.2")
    p, c = table_files(tmp_path, same_side)
    for source in ({}, {"duplicate_contacts": "mean"}):  # a repeated row is no second estimate
        with pytest.raises(SourceError, match=r"line 4: contact 13-43 appears twice from the same side \(first on line "
                                              r"2\): a repeated row\? source.duplicate_contacts: mean merges a contact "
                                              r"given once from each side"):
            table.read_state(p, c, 2, "magnitudes", source=source)
    p, c = table_files(tmp_path, TWO_SIDED + "43,13,1.1,0.1\n")
    with pytest.raises(SourceError, match="line 5: contact 13-43 appears 3 times \\(first on line 2\\): "
                                          "source.duplicate_contacts: mean merges a contact given twice"):
        table.read_state(p, c, 2, "magnitudes", source={"duplicate_contacts": "mean"})


def test_a_contact_given_from_each_side_is_merged_by_the_mean_and_its_disagreement_kept(tmp_path):
    p, c = table_files(tmp_path, TWO_SIDED)
    state = table.read_state(p, c, 2, "magnitudes", source={"duplicate_contacts": "mean"})
    # particles in file order: 13 → 0, 43 → 1, 7 → 2; contacts (0, 1) and (0, 2)
    assert (state.contact_i.tolist(), state.contact_j.tolist()) == ([0, 0], [1, 2])
    # 13-43: |F_n| 1.0 and 1.2 along -x (on 13), |F_t| 0.2 and 0.1 along -y: the mean, and the difference's norm
    np.testing.assert_allclose(state.force_normal[0], [-1.1, 0.0])
    np.testing.assert_allclose(state.force_tangential[0], [0.0, -0.15])
    np.testing.assert_allclose(state.force_disagreement, [np.hypot(0.2, 0.1), np.nan])
    # the same contacts from the total force on each side (the sign of the second row reversed): the same merge
    p, c = table_files(tmp_path, "i,j,f_x,f_y\n13,43,-1.0,-0.2\n13,7,0,-0.5\n43,13,1.2,0.1\n")
    total = table.read_state(p, c, 2, "total", source={"duplicate_contacts": "mean"})
    np.testing.assert_allclose(total.force_normal[0] + total.force_tangential[0], [-1.1, -0.15])
    np.testing.assert_allclose(total.force_disagreement[0], np.hypot(0.2, 0.1))


def test_the_merged_snapshot_records_the_disagreement_with_units_and_long_name_and_is_analysed(tmp_path):
    p, c = table_files(tmp_path, TWO_SIDED)
    config = {**EXAMPLE, "systems": {"t": {"dimension": 2, "units": {"length": "mm", "force": "N"}, "source": {
        "format": "table", "forces": "magnitudes", "duplicate_contacts": "mean", "signed_tangential": "vector",
        "box": {"lo": [0, 0], "hi": [3, 3]}, "runs": [[{"particles": str(p), "contacts": str(c)}]]}}}}
    out = tmp_path / "out" / "rho0.262.nc"
    import_run(config=config, system="t", realization=0, outputs=[str(out)])
    ds = read_snapshot(out)
    assert schema_problems(ds, "snapshot") == []
    variable = ds["contact_force_disagreement"]
    assert variable.dims == ("contact",) and variable.attrs["units"] == "N"
    assert variable.attrs["long_name"] == SNAPSHOT_IMPORT_VARIABLES["contact_force_disagreement"].long_name
    np.testing.assert_allclose(variable.values, [np.hypot(0.2, 0.1), np.nan])
    analysis = {**pipeline.snapshot_analysis_params(config, "t"), "remove_rattlers": "none"}
    pipeline.analyze_run(snapshots=[str(out)], outputs=[str(tmp_path / "a.nc")], analysis=analysis)
    measures = read_dataset(tmp_path / "a.nc", "analysis").sel(force_kind="normal")
    assert float(measures["mean_force"]) == pytest.approx((1.1 + 0.5) / 2)  # the merged 1.1 and the once-given 0.5
    # without the option the snapshot has no such variable, as our engine's
    p, c = table_files(tmp_path, SIGNED.replace("-0.25", "0.25"))
    plain = {**config, "systems": {"t": {**config["systems"]["t"], "source": {
        **{k: v for k, v in config["systems"]["t"]["source"].items() if k != "duplicate_contacts"}}}}}
    import_run(config=plain, system="t", realization=0, outputs=[str(out)])
    assert "contact_force_disagreement" not in read_snapshot(out)


def test_a_lammps_pair_listed_from_each_side_is_refused_or_merged_as_in_a_table(tmp_path):
    # `newton off` across processors: each of two processors lists the pair from its own atom
    rows = "13 43 1.0 0.2\n13 7 0.5 0.1\n43 13 1.2 0.1\n"
    run = corner_dumps(tmp_path, LAMMPS_ATOMS, LAMMPS_PAIRS.format(3, rows))
    assert refusal(lammps.read_run, run, 2, ONE_COLUMN) == (
        f"{run['pairs']}, line 12: the pair of atoms 13, 43 appears twice, once from each side at timestep 5 (first "
        "on line 10): source.duplicate_contacts: mean merges them (the mean of the two estimates, their disagreement "
        "recorded)")
    (state,) = lammps.read_run(run, 2, {**ONE_COLUMN, "duplicate_contacts": "mean"})
    p, c = table_files(tmp_path, TWO_SIDED)
    same = table.read_state(p, c, 2, "magnitudes", source={"duplicate_contacts": "mean"})
    assert_same_contacts(state, same)


# --- the config: each option in the schema, a wrong value named by its key -----------------------------------------
def checked(config):
    from forcenet.workflow_io import CONFIG_SCHEMA, checked_config

    return checked_config(config, REPO / CONFIG_SCHEMA)


def with_source(system: str, **changes):
    entry = EXAMPLE["systems"][system]
    return {**EXAMPLE, "systems": {**EXAMPLE["systems"], system: {**entry, "source": {**entry["source"], **changes}}}}


def test_the_options_pass_the_schema_and_a_wrong_value_names_its_key():
    checked(with_source("table_2d", signed_tangential="vector", duplicate_contacts="mean",
                        wall_forces="summed_per_wall"))
    checked(with_source("lammps_2d", signed_tangential="magnitude", duplicate_contacts="mean", wall_forces="separate",
                        wall_columns=[{"columns": ["f_walls[2]", "f_walls[3]"], "walls": ["x_lo", "x_hi", "y_lo"]}]))
    for key, value in (("signed_tangential", "signed"), ("duplicate_contacts", "sum"), ("wall_forces", "each")):
        with pytest.raises(ConfigError, match=f"config key 'systems.table_2d.source.{key}'"):
            checked(with_source("table_2d", **{key: value}))
    with pytest.raises(ConfigError, match="config key 'systems.lammps_2d.source.wall_columns.0': 'walls' is a "
                                          "required property"):
        checked(with_source("lammps_2d", wall_columns=[{"columns": ["a", "b"]}]))  # a fix's walls must be stated
    with pytest.raises(ConfigError, match="config key 'systems.table_2d.source.wall_columns': not allowed"):
        checked(with_source("table_2d", wall_columns=["a", "b"]))
