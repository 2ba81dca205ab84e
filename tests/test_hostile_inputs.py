"""Hostile files and interrupted writes (issue 57): each bad input a new user might hand the importers, the config
reader or a netCDF write, with the one line that now refuses it (file and line or column, or the config key).
docs/reliability.md lists every case tried and its outcome."""
from __future__ import annotations

import gzip
import logging
import os
import signal
from pathlib import Path

import numpy as np
import pytest

from forcenet.importers import SourceError, import_run, source_states

PAIR_COLUMNS = {"i": "c_pid[1]", "j": "c_pid[2]", "normal": "c_pf[1]", "tangential": ["c_pf[2]", "c_pf[3]", "c_pf[4]"]}
#: a 2D state of three disks, two contacts: the atoms' rows are lines 10–12 of ATOMS, the pairs' lines 10–11 of PAIRS
HEAD = "ITEM: TIMESTEP\n5\nITEM: NUMBER OF {}\n{}\nITEM: BOX BOUNDS ff ff pp\n0 4\n0 4\n-0.5 0.5\n"
ATOM_ROWS = ["1 1 1.0 1.0 0 0.5", "2 1 1.9 1.0 0 0.5", "3 1 1.0 1.9 0 0.5"]
PAIR_ROWS = ["1 2 1.0 0 0.1 0", "1 3 0.5 0 0 0"]


def dumps(tmp_path: Path, atom_rows=ATOM_ROWS, pair_rows=PAIR_ROWS) -> tuple[Path, Path]:
    atoms, pairs = tmp_path / "atoms.dump", tmp_path / "pairs.dump"
    atoms.write_text(HEAD.format("ATOMS", len(atom_rows)) + "ITEM: ATOMS id type x y z radius\n"
                     + "".join(row + "\n" for row in atom_rows))
    pairs.write_text(HEAD.format("ENTRIES", len(pair_rows)) + "ITEM: ENTRIES " + " ".join(
        ["c_pid[1]", "c_pid[2]", "c_pf[1]", "c_pf[2]", "c_pf[3]", "c_pf[4]"]) + "\n"
                     + "".join(row + "\n" for row in pair_rows))
    return atoms, pairs


def lammps_entry(atoms, pairs) -> dict:
    return {"dimension": 2, "source": {"format": "lammps", "pair_columns": PAIR_COLUMNS,
                                       "runs": [{"atoms": str(atoms), "pairs": str(pairs)}]}}


def refused(tmp_path, entry, outputs=1) -> str:
    """The one-line message the import job stops with; nothing is written."""
    out = tmp_path / "out"
    with pytest.raises(SourceError) as caught:
        import_run(config={"realizations": 1, "systems": {"s": entry}}, system="s", realization=0,
                   outputs=[str(out / f"rho{k}.nc") for k in range(outputs)])
    assert not out.exists()
    message = str(caught.value)
    assert "\n" not in message, message
    return message


def test_the_small_dumps_read_with_any_line_ends(tmp_path):
    atoms, pairs = dumps(tmp_path)
    (state,) = source_states(lammps_entry(atoms, pairs), 0)
    assert state.contact_i.tolist() == [0, 0] and state.contact_j.tolist() == [1, 2]
    atoms.write_bytes(atoms.read_bytes().replace(b"\n", b"\r\n"))  # written on Windows: still whole lines
    (again,) = source_states(lammps_entry(atoms, pairs), 0)
    np.testing.assert_array_equal(again.position, state.position)


# case: (atoms text or None (the good one), pairs text or None, the file the message names, what it says)
def _cut(text: str, marker: str) -> str:
    return text[:text.index(marker) + len(marker)] + "\n"


GOOD_ATOMS = HEAD.format("ATOMS", 3) + "ITEM: ATOMS id type x y z radius\n" + "".join(r + "\n" for r in ATOM_ROWS)
GOOD_PAIRS = (HEAD.format("ENTRIES", 2) + "ITEM: ENTRIES c_pid[1] c_pid[2] c_pf[1] c_pf[2] c_pf[3] c_pf[4]\n"
              + "".join(r + "\n" for r in PAIR_ROWS))
LAMMPS_CASES = {
    "cut after ITEM: TIMESTEP": (_cut(GOOD_ATOMS, "ITEM: TIMESTEP"), None, "atoms.dump",
                                 "line 2: the file ends where the integer after 'ITEM: TIMESTEP' (line 1) should be"),
    "cut after ITEM: NUMBER OF ATOMS": (_cut(GOOD_ATOMS, "ITEM: NUMBER OF ATOMS"), None, "atoms.dump",
                                        "line 4: the file ends where the integer after 'ITEM: NUMBER OF ATOMS' "
                                        "(line 3) should be"),
    "cut after ITEM: NUMBER OF ENTRIES": (None, _cut(GOOD_PAIRS, "ITEM: NUMBER OF ENTRIES"), "pairs.dump",
                                          "line 4: the file ends where the integer after"),
    "cut inside the box bounds": (_cut(GOOD_ATOMS, "0 4\n0 4"), None, "atoms.dump",
                                  "line 8: the file ends where line 3 of the 3 lines of box bounds (line 1) should be"),
    "cut before the announced rows": (GOOD_ATOMS[:GOOD_ATOMS.rindex("3 1 ")], None, "atoms.dump",
                                      "line 12: the file ends where row 3 of the 3 that timestep 5 (line 1) "
                                      "announces should be"),
    "cut inside the last value": (GOOD_ATOMS[:-2], None, "atoms.dump",
                                  "line 12: the file ends inside this line ('3 1 1.0 1.9 0 0.'), without its final "
                                  "newline"),
    "fractional atom id": (GOOD_ATOMS.replace("\n2 1 1.9", "\n1.5 1 1.9"), None, "atoms.dump",
                           "line 11, column 'id': atom id 1.5 is not an integer"),
    "NaN atom id": (GOOD_ATOMS.replace("\n3 1 1.0", "\nnan 1 1.0"), None, "atoms.dump",
                    "line 12, column 'id': atom id nan is not an integer"),
    "repeated atom id": (GOOD_ATOMS.replace("\n3 1 1.0", "\n1 1 1.0"), None, "atoms.dump",
                         "line 12, column 'id': atom id 1 repeats (first on line 10)"),
    "fractional pair id": (None, GOOD_PAIRS.replace("1 3 0.5", "1 2.5 0.5"), "pairs.dump",
                           "line 11, column 'c_pid[2]': atom id 2.5 is not an integer"),
    "NaN pair id": (None, GOOD_PAIRS.replace("1 3 0.5", "nan 3 0.5"), "pairs.dump",
                    "line 11, column 'c_pid[1]': atom id nan is not an integer"),
    "negative normal force": (None, GOOD_PAIRS.replace("1 3 0.5", "1 3 -0.5"), "pairs.dump",
                              "line 11, column 'c_pf[1]': a force magnitude must be ≥ 0, got -0.5"),
    "coincident atoms": (GOOD_ATOMS.replace("3 1 1.0 1.9", "3 1 1.0 1.0"), None, "atoms.dump",
                         "lines 10 and 12: atoms 1 and 3 are at the same position (1, 1) at timestep 5"),
    "a row one value short": (GOOD_ATOMS.replace("2 1 1.9 1.0 0 0.5", "2 1 1.9 1.0 0"), None, "atoms.dump",
                              "line 11: 5 values for the 6 columns"),
    "a word for a number": (GOOD_ATOMS.replace("2 1 1.9", "2 1 x1.9"), None, "atoms.dump",
                            "line 11: not a number in '2 1 x1.9 1.0 0 0.5'"),
    "no atoms": (HEAD.format("ATOMS", 0) + "ITEM: ATOMS id type x y z radius\n", None, "atoms.dump",
                 "timestep 5 (line 1): no atoms"),
    "a negative count": (GOOD_ATOMS.replace("ATOMS\n3", "ATOMS\n-3"), None, "atoms.dump",
                         "line 4: a negative number of rows (-3)"),
    "infinite box bounds": (GOOD_ATOMS.replace("0 4\n0 4", "0 inf\n0 4"), None, "atoms.dump",
                            "line 6: box bounds that are NaN or infinite"),
    "box bounds hi below lo": (GOOD_ATOMS.replace("0 4\n0 4", "0 4\n4 0"), None, "atoms.dump",
                               "line 7: box bounds 4 0: hi must exceed lo"),
    "timestep not an integer": (GOOD_ATOMS.replace("TIMESTEP\n5", "TIMESTEP\n5.5"), None, "atoms.dump",
                                "line 2: expected one integer after 'ITEM: TIMESTEP', found '5.5'"),
}


@pytest.mark.parametrize("case", sorted(LAMMPS_CASES))
def test_a_hostile_lammps_dump_is_refused_naming_its_file_and_line(tmp_path, case):
    atoms_text, pairs_text, bad, expected = LAMMPS_CASES[case]
    atoms, pairs = dumps(tmp_path)
    if atoms_text is not None:
        atoms.write_text(atoms_text)
    if pairs_text is not None:
        pairs.write_text(pairs_text)
    message = refused(tmp_path, lammps_entry(atoms, pairs))
    assert message.startswith(f"{tmp_path / bad}, {expected}"), message


def corrupt_gzip(path: Path, text: str, at: int | None = None) -> None:
    """`text` gzipped, with 8 bytes of its compressed data overwritten (header and trailer intact) at byte `at`
    (default: the middle, which gzip's CRC check finds; 10, the first deflate block's header: zlib.error)."""
    data = bytearray(gzip.compress(text.encode(), mtime=0))
    at = len(data) // 2 if at is None else at
    data[at:at + 8] = b"\xff" * 8
    path.write_bytes(bytes(data))


def test_a_corrupt_gzip_stream_is_refused_naming_its_file(tmp_path):
    atoms, pairs = dumps(tmp_path)
    rows = [f"{k} 1 {0.5 + (k % 40):.6f} {0.5 + (k // 40):.6f} 0 0.25" for k in range(1, 2001)]
    zipped = tmp_path / "atoms.dump.gz"
    corrupt_gzip(zipped, HEAD.format("ATOMS", len(rows)) + "ITEM: ATOMS id type x y z radius\n"
                 + "".join(r + "\n" for r in rows))
    message = refused(tmp_path, lammps_entry(zipped, pairs))
    assert message.startswith(f"{zipped}, after line ") and ": cannot be read (CRC check failed" in message, message
    corrupt_gzip(zipped, HEAD.format("ATOMS", len(rows)) + "ITEM: ATOMS id type x y z radius\n", at=10)
    message = refused(tmp_path, lammps_entry(zipped, pairs))  # issue 57: an uncaught zlib.error naming no file
    assert message == (f"{zipped}: cannot be read (Error -3 while decompressing data: invalid block type; a corrupt "
                       "gzip stream)"), message
    table = tmp_path / "particles.csv.gz"
    corrupt_gzip(table, "id,x,y,radius\n" + "".join(f"{k},{k}.5,0.5,0.25\n" for k in range(2000)))
    entry = {"dimension": 2, "source": {"format": "table", "forces": "magnitudes",
                                        "runs": [[{"particles": str(table), "contacts": str(table)}]]}}
    message = refused(tmp_path, entry)
    assert message.startswith(f"{table}: cannot be read (") and "\n" not in message, message


def test_a_byte_order_mark_and_a_frame_without_pairs_read(tmp_path):
    atoms, pairs = dumps(tmp_path, pair_rows=[])
    atoms.write_text("\ufeff" + GOOD_ATOMS)  # a Windows editor's UTF-8
    (state,) = source_states(lammps_entry(atoms, pairs), 0)
    assert len(state.radius) == 3 and len(state.contact_i) == 0


def test_particles_that_do_not_fit_their_box_are_named_by_the_import_job(tmp_path):
    atoms, pairs = dumps(tmp_path, atom_rows=["1 1 1.0 1.0 0 0.5", "2 1 1.9 1.0 0 50", "3 1 1.0 1.9 0 0.5"])
    assert refused(tmp_path, {**lammps_entry(atoms, pairs), "rho": [0.147]}) == (
        f"{atoms}, timestep 5: ρ = 491: the particles' area is not below the box's (radii and box in different units? "
        "diameters given as radii?)")


def test_a_gzipped_dump_named_without_gz_is_said_to_be_one(tmp_path):
    atoms, pairs = dumps(tmp_path)
    atoms.write_bytes(gzip.compress(atoms.read_bytes()))
    message = refused(tmp_path, lammps_entry(atoms, pairs))
    assert message == (f"{atoms}: cannot be read ('utf-8' codec can't decode byte 0x8b in position 1: invalid start "
                       "byte; the file is gzip-compressed: name it atoms.dump.gz)"), message


TABLE_PARTICLES = "id,x,y,radius\n1,1.0,1.0,0.5\n2,1.9,1.0,0.5\n3,1.0,1.9,0.5\n"
TABLE_CONTACTS = "i,j,fn,ft\n1,2,1.0,0.1\n1,3,0.5,0.0\n"
#: written by a fixed-format writer (%.6f): every value of a column has 6 digits after the decimal point
FIXED_PARTICLES = "id,x,y,radius\n" + "".join(f"{k},{x:.6f},{y:.6f},0.500000\n" for k, x, y in
                                              [(1, 1.0, 1.0), (2, 1.9, 1.0), (3, 1.0, 1.9), (4, 3.0, 3.0)])
TABLE_CASES = {
    "a byte-order mark is no part of the header": ("\ufeff" + TABLE_PARTICLES.replace("2,1.9", "2,x"), None, "p.csv",
                                                   "line 3, column 'x': 'x' is not a number"),
    "a row with more cells than its header": (TABLE_PARTICLES.replace("2,1.9,1.0,0.5", "2,1.9,1.0,0.5,7"), None,
                                             "p.csv", "line 3: 5 cells, but the header (line 1) names 4 columns"),
    "coincident particles": (TABLE_PARTICLES.replace("3,1.0,1.9", "3,1.0,1.0"), None, "p.csv",
                             "lines 2 and 4: particles 1 and 3 are at the same position (1, 1)"),
    "negative normal force": (None, TABLE_CONTACTS.replace("1,3,0.5", "1,3,-0.5"), "c.csv",
                              "line 3, column 'fn': a force magnitude must be ≥ 0, got -0.5"),
    "fractional particle id": (TABLE_PARTICLES.replace("\n2,1.9", "\n1.5,1.9"), None, "p.csv",
                               "line 3, column 'id': '1.5' is not an integer id"),
    "no final newline, the last row cut before its last cell": (TABLE_PARTICLES[:-9], None, "p.csv",
                                                                "line 4: the file ends inside this line ('3,1.0'), "
                                                                "without its final newline, and 2 of the header's 4 "
                                                                "cells: cut short"),
    "no final newline, the last cell empty": (None, TABLE_CONTACTS[:-4], "c.csv",
                                              "line 3: the file ends inside this line ('1,3,0.5,'), without its final "
                                              "newline, and 3 of the header's 4 cells"),
    "no final newline, the last value shorter than the fixed-format ones above": (
        FIXED_PARTICLES[:-6], None, "p.csv", "line 5: the file ends inside this line ('4,3.000000,3.000000,0.5'), "
        "without its final newline, and its last value '0.5' is shorter than the 3 above it (6 characters after the "
        "decimal point each): cut short while it was being written? If the line is complete, end the file with a "
        "newline"),
}


@pytest.mark.parametrize("case", sorted(TABLE_CASES))
def test_a_hostile_table_is_refused_naming_its_file_and_line(tmp_path, case):
    particles_text, contacts_text, bad, expected = TABLE_CASES[case]
    (tmp_path / "p.csv").write_text(particles_text or TABLE_PARTICLES)
    (tmp_path / "c.csv").write_text(contacts_text or TABLE_CONTACTS)
    entry = {"dimension": 2, "source": {"format": "table", "forces": "magnitudes", "runs": [[
        {"particles": str(tmp_path / "p.csv"), "contacts": str(tmp_path / "c.csv")}]]}}
    message = refused(tmp_path, entry)
    assert message.startswith(f"{tmp_path / bad}, {expected}"), message



@pytest.mark.parametrize("particles", [
    FIXED_PARTICLES[:-1], "id,x,y,radius\n1,1,1,0.5\n2,1.9,1,0.45\n3,1,1.9,0.5\n4,3,3,0.4", TABLE_PARTICLES[:-1]],
    ids=["fixed-format, the last value whole", "values of varying length", "two rows above the last"])
def test_a_table_without_a_final_newline_is_refused_and_reads_once_the_newline_is_added(tmp_path, particles):
    """A cut inside the last value cannot be told from a whole one (values of varying length, too few rows above),
    so a file without its final newline is refused, naming its last line and the way out; with the newline added
    the same rows read."""
    (tmp_path / "c.csv").write_text(TABLE_CONTACTS)
    entry = {"dimension": 2, "source": {"format": "table", "forces": "magnitudes", "runs": [[
        {"particles": str(tmp_path / "p.csv"), "contacts": str(tmp_path / "c.csv")}]]}}
    (tmp_path / "p.csv").write_text(particles)
    message = refused(tmp_path, entry)
    assert message.startswith(f"{tmp_path / 'p.csv'}, line "), message
    assert message.endswith("without its final newline: cut short while it was being written? If the line is "
                            "complete, end the file with a newline"), message
    (tmp_path / "p.csv").write_text(particles + "\n")
    (state,) = source_states(entry, 0)
    assert state.radius[-1] == float(particles.rpartition(",")[2])
    assert state.contact_i.tolist() == [0, 0] and state.contact_j.tolist() == [1, 2]
    np.testing.assert_allclose(np.linalg.norm(state.force_normal, axis=1), [1.0, 0.5])

# --- interrupted writes ------------------------------------------------------------------------------------------
@pytest.fixture
def ctrl_c_raises():
    """SIGINT handled as in an interactive Python (KeyboardInterrupt) for the test, and the inherited disposition
    restored after it: a shell that starts the suite in the background (`nohup ... &`) starts it with SIGINT
    ignored, and Python keeps it ignored, so without this no Ctrl-C would reach the code under test."""
    inherited = signal.signal(signal.SIGINT, signal.default_int_handler)
    yield
    signal.signal(signal.SIGINT, signal.SIG_DFL if inherited is None else inherited)


def test_a_ctrl_c_during_a_netcdf_write_ends_it_cleanly_with_no_lock_held(tmp_path, monkeypatch, ctrl_c_raises):
    """Issue 57: one Ctrl-C that arrived inside xarray's write deadlocked 5 of 20 jobs on its file lock. Now the
    signal waits until the file is renamed into place, then raises KeyboardInterrupt; the lock is free after."""
    import xarray as xr
    from xarray.backends.netCDF4_ import NETCDF4_PYTHON_LOCK

    from forcenet.datasets import open_dataset, provenance_attrs, write_netcdf

    ds = xr.Dataset({"x": xr.Variable(("n",), np.arange(5.0), attrs={"units": "1", "long_name": "x"})},
                    attrs=provenance_attrs(system="s", realization=0, seed=0, config={}, title="t"))
    original = xr.Dataset.to_netcdf

    def interrupted(self, *args, **kwargs):
        os.kill(os.getpid(), signal.SIGINT)  # Ctrl-C, delivered while xarray writes
        return original(self, *args, **kwargs)

    monkeypatch.setattr(xr.Dataset, "to_netcdf", interrupted)
    target = tmp_path / "out.nc"
    with pytest.raises(KeyboardInterrupt):
        write_netcdf(ds, target)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["out.nc"]  # complete, no temporary file left
    assert NETCDF4_PYTHON_LOCK.acquire(blocking=False)
    NETCDF4_PYTHON_LOCK.release()
    assert signal.getsignal(signal.SIGINT) is signal.default_int_handler
    monkeypatch.setattr(xr.Dataset, "to_netcdf", original)
    np.testing.assert_array_equal(open_dataset(target)["x"].values, np.arange(5.0))


def test_a_write_that_fails_leaves_no_partial_file_and_restores_ctrl_c(tmp_path, monkeypatch, ctrl_c_raises):
    import xarray as xr

    from forcenet.datasets import provenance_attrs, write_netcdf

    ds = xr.Dataset(attrs=provenance_attrs(system="s", realization=0, seed=0, config={}, title="t"))

    def full_disk(self, path, *args, **kwargs):
        Path(path).write_bytes(b"CDF half")
        raise OSError(28, "No space left on device")

    monkeypatch.setattr(xr.Dataset, "to_netcdf", full_disk)
    with pytest.raises(OSError):
        write_netcdf(ds, tmp_path / "out.nc")
    assert list(tmp_path.iterdir()) == []
    assert signal.getsignal(signal.SIGINT) is signal.default_int_handler



def test_a_ctrl_c_to_a_process_that_ignores_it_is_dropped_after_the_write(tmp_path, monkeypatch):
    """A process started with SIGINT ignored (a background job of a non-interactive shell) keeps ignoring it: the
    Ctrl-C held back during the write is not delivered after it, and the write completes."""
    import xarray as xr

    from forcenet.datasets import open_dataset, provenance_attrs, write_netcdf

    ds = xr.Dataset({"x": xr.Variable(("n",), np.arange(3.0), attrs={"units": "1", "long_name": "x"})},
                    attrs=provenance_attrs(system="s", realization=0, seed=0, config={}, title="t"))
    original = xr.Dataset.to_netcdf

    def interrupted(self, *args, **kwargs):
        os.kill(os.getpid(), signal.SIGINT)
        return original(self, *args, **kwargs)

    inherited = signal.signal(signal.SIGINT, signal.SIG_IGN)
    try:
        monkeypatch.setattr(xr.Dataset, "to_netcdf", interrupted)
        write_netcdf(ds, tmp_path / "out.nc")
        assert signal.getsignal(signal.SIGINT) == signal.SIG_IGN
    finally:
        signal.signal(signal.SIGINT, signal.SIG_DFL if inherited is None else inherited)
    monkeypatch.setattr(xr.Dataset, "to_netcdf", original)
    np.testing.assert_array_equal(open_dataset(tmp_path / "out.nc")["x"].values, np.arange(3.0))

# --- reading a source: once per content, at the import job --------------------------------------------------------
@pytest.fixture
def records(tmp_path, monkeypatch) -> Path:
    from forcenet.importers.scan import RECORD_DIR_ENV

    folder = tmp_path / "records"
    monkeypatch.setenv(RECORD_DIR_ENV, str(folder))
    return folder


def test_parsing_reads_no_source_content_and_records_each_files_status(tmp_path, records):
    from forcenet.importers import imported_system, run_files
    from forcenet.importers.scan import record_path

    atoms, pairs = dumps(tmp_path)
    entry = {**lammps_entry(atoms, pairs), "rho": [0.147]}
    first = imported_system("s", entry)
    assert first.rho_labels == ["0.147"] and first.particles == 3  # the declared ρ; the atoms dump's first header
    stamp = record_path(atoms).stat().st_mtime_ns
    assert stamp == atoms.stat().st_mtime_ns  # a first record: outputs already built stay current
    assert imported_system("s", entry) == first and record_path(atoms).stat().st_mtime_ns == stamp
    # other content under an older modification time (cp -p, an archive): the record moves, the import job reruns
    atoms.write_text(GOOD_ATOMS.replace("1 1 1.0 1.0 0 0.5", "1 1 1.0 1.0 0 0.45"))
    os.utime(atoms, ns=(stamp - 10**9, stamp - 10**9))
    imported_system("s", entry)
    assert record_path(atoms).stat().st_mtime_ns > stamp
    assert run_files(entry, 0) == [str(atoms), str(pairs), str(record_path(atoms)), str(record_path(pairs))]
    # a bad pairs dump and an atoms dump cut after its first header: neither is read when the config is parsed
    pairs.write_text("not a dump\n")
    atoms.write_text(_cut(GOOD_ATOMS, "ITEM: BOX BOUNDS ff ff pp"))
    assert imported_system("s", entry).rho_labels == ["0.147"]
    assert refused(tmp_path, entry).startswith(f"{atoms}, line 6: the file ends where line 1 of the 3 lines of box "
                                               "bounds")


def test_the_first_states_particles_come_from_a_bounded_read_of_its_head(tmp_path):
    from forcenet.importers.scan import first_state_particles

    atoms, pairs = dumps(tmp_path)
    assert first_state_particles(lammps_entry(atoms, pairs)) == 3  # ITEM: NUMBER OF ATOMS
    atoms.write_text("not a dump\n")
    assert first_state_particles(lammps_entry(atoms, pairs)) == 0  # unknown: the import job names the problem
    table = tmp_path / "p.csv"
    table.write_text("# a comment\nid,x,y,radius\n1,1,1,0.5\n2,2,1,0.5\n3,1,2,0.5\n")
    entry = {"dimension": 2, "source": {"format": "table", "runs": [[{"particles": str(table)}]]}}
    assert first_state_particles(entry) == 3  # the rows under the header, comments left out
    table.write_text("id,x,y,radius\n" + "".join(f"{k},{k}.25,0.5,0.25\n" for k in range(1, 20001)))
    assert 18000 < first_state_particles(entry) < 22000  # past 64 KiB: scaled to the size (longer ids later)


def test_forcenet_check_config_says_in_its_help_that_it_reads_every_source(capsys):
    from forcenet.workflow_io import check_config_main

    assert check_config_main(["--help"]) == 0
    assert "reads every source file in full" in " ".join(capsys.readouterr().out.split())
    assert check_config_main([]) == 2


@pytest.mark.parametrize("content, expected", [(None, "cannot be read (No such file or directory)"),
                                               ("", "empty (0 bytes)"), ("/", "not a file (a folder?)")])
def test_a_missing_or_empty_pairs_file_is_named_when_the_config_is_parsed(tmp_path, records, content, expected):
    from forcenet.importers import imported_system

    atoms, pairs = dumps(tmp_path)
    pairs.unlink()
    if content == "/":
        pairs.mkdir()
    elif content is not None:
        pairs.write_text(content)
    with pytest.raises(SourceError) as caught:
        imported_system("s", lammps_entry(atoms, pairs))
    assert str(caught.value) == f"{pairs}: {expected}"


def test_overlaps_past_ten_percent_are_logged_and_a_changed_rho_is_refused(tmp_path, records, caplog):
    atoms, pairs = dumps(tmp_path, atom_rows=["1 1 1.0 1.0 0 0.5", "2 1 1.7 1.0 0 0.5", "3 1 1.0 1.9 0 0.5"])
    config = {"realizations": 1, "systems": {"s": {**lammps_entry(atoms, pairs), "rho": [0.147]}}}
    log = logging.getLogger("forcenet.test.import")
    import_run(config=config, system="s", realization=0, outputs=[str(tmp_path / "out" / "rho0.147.nc")], log=log)
    warnings = [r.getMessage() for r in caplog.records if r.levelno == logging.WARNING]
    assert warnings == [f"{atoms}: timestep 5 has overlaps up to 30.0 % of the sum of the radii (particles 0 and 1), "
                        "past the 10 % P1 states: check the source's units and radii"]
    config["systems"]["s"]["rho"] = [0.150]  # a ρ the files do not give: refused before anything is written
    with pytest.raises(SourceError, match=r"atoms.dump, timestep 5: ρ = 0.14726 \(0.147 at 3 decimals\), but "
                                          r"systems.s.rho declares 0.150 for state 0: declare the ρ the files give"):
        import_run(config=config, system="s", realization=0, outputs=[str(tmp_path / "other" / "rho0.150.nc")])
    assert not (tmp_path / "other").exists()


# --- config values that passed every check and failed at job time --------------------------------------------------
SCHEMA = Path(__file__).resolve().parents[1] / "workflow" / "schemas" / "config.schema.yaml"


@pytest.mark.parametrize("rule, table_rho, expected", [
    ("jammed", 0.896, "config key 'studies.p2.table_rho': is 0.896, but system '2d_poly_mu05' has 2 grid point(s) at or "
                     "above it (its grid ends at 0.9), and the jammed states a, b, c need 3: lower table_rho or extend "
                     "the grid"),
    ("literal", 0.95, "config key 'studies.p2.table_rho': is 0.95, outside system '2d_poly_mu05''s grid (0.63 … 0.9): "
                      "the literal states a, b, c are the three nearest it"),
])
def test_a_table_rho_beyond_the_p2_grid_is_refused_naming_the_key(rule, table_rho, expected):
    from conftest import load_config
    from forcenet.systems import ConfigError
    from forcenet.workflow_io import checked_config

    config = load_config()
    config["studies"]["p2"].update(table_rho=table_rho, table_states=rule)
    with pytest.raises(ConfigError) as caught:
        checked_config(config, SCHEMA)
    assert str(caught.value) == expected


def test_a_grid_past_random_close_packing_gets_one_note_in_the_dry_run(capsys):
    from conftest import load_config
    from forcenet.workflow_io import checked_config

    config = load_config()
    checked_config(config, SCHEMA)
    (note,) = capsys.readouterr().err.splitlines()
    assert note.startswith("forcenet: note: systems.2d_linear.rho (0.88), systems.2d_hertz.rho (0.9), "
                           "systems.3d_hertz.rho (0.7) and 2 more end past random close packing (disks ≈ 0.84, "
                           "spheres ≈ 0.64): expect the largest overlaps above P1's 10 % of a diameter"), note
    for name, spec in config["systems"].items():
        spec["rho"] = {"start": spec["rho"]["start"], "stop": 0.83 if spec["dimension"] == 2 else 0.62,
                       "step": spec["rho"].get("step", 0.01)}
    checked_config(config, SCHEMA)
    assert capsys.readouterr().err == ""


def test_forcenet_check_config_reads_every_source_file_in_full(tmp_path, records, capsys):
    """The workflow reads no source file when it parses a config; the checker reads what the import jobs will, so a
    cut pairs dump is named before any job, and a compression that declares no ρ is told the files' values."""
    import yaml

    from conftest import load_config
    from forcenet.workflow_io import check_config_main

    atoms, pairs = dumps(tmp_path)
    config = load_config("example_import.yaml")
    config["systems"] = {"s": lammps_entry(atoms, pairs)}
    config["studies"] = {"p1": {"systems": ["s"]}}
    path = tmp_path / "config.yaml"
    path.write_text(yaml.safe_dump(config))
    assert check_config_main([str(path)]) == 1
    assert capsys.readouterr().err.splitlines()[-1] == f"{path}: its files give systems.s.rho: [0.147]"
    config["systems"]["s"]["rho"] = [0.147]
    path.write_text(yaml.safe_dump(config))
    assert check_config_main([str(path)]) == 0
    pairs.write_text(_cut(GOOD_PAIRS, "ITEM: NUMBER OF ENTRIES"))
    assert check_config_main([str(path)]) == 1
    assert capsys.readouterr().err.splitlines()[-1] == (
        f"{path}: invalid: {pairs}, line 4: the file ends where the integer after 'ITEM: NUMBER OF ENTRIES' (line 3) "
        "should be: cut short?")
