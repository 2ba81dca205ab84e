"""An imported LAMMPS run ordered by its timesteps (``source.sequence: {coordinate: timestep}``), built end to end
through the job functions: import, per-state analysis, stacking, and P2's distances between consecutive states.

The dumps hold three states of four disks (radius 0.5) on the corners of a unit square in a 4 × 4 box, every
contact carrying a normal force of 2 (⟨F_n⟩ = 2, so each is 1 in units of ⟨F⟩), at timesteps 0, 100 and 250:

- timestep 0, a chain 1–2–3–4: 3 contacts, Z = 6/4 = 1.5, one cluster, no loop (β0 = 1, β1 = 0);
- timestep 100, the closed square 1–2–3–4–1: 4 contacts, Z = 2, one cluster around one hole (β0 = 1, β1 = 1; no
  diagonal, so no triangle fills it);
- timestep 250, the two contacts 1–2 and 3–4: Z = 1, two clusters (β0 = 2, β1 = 0).

ρ = 4 π 0.5² / 16 = π / 16 in every state: a compression could not hold them (one ρ), a sequence can. Every class is
born at F/⟨F⟩ = 1 and never dies (P2's convention draws it at death −1), so the bottleneck distance between two
states' diagrams is the lifespan 2 / 2 = 1 for each class one state has more than the other: PD0 0 then 1, PD1 1
then 1.
"""
from __future__ import annotations

import logging
import math

import numpy as np
import pytest

from forcenet.datasets import paths, read_dataset, read_snapshot
from forcenet.datasets.schema import FORCE_KINDS

POSITIONS = [(1.0, 1.0), (2.0, 1.0), (2.0, 2.0), (1.0, 2.0)]
#: timestep → the contacts (atom ids) of that state
STATES = {0: [(1, 2), (2, 3), (3, 4)], 100: [(1, 2), (2, 3), (3, 4), (4, 1)], 250: [(1, 2), (3, 4)]}
PAIR_COLUMNS = ("c_pid[1]", "c_pid[2]", "c_pf[1]", "c_pf[2]", "c_pf[3]", "c_pf[4]")
HEAD = "ITEM: TIMESTEP\n{}\nITEM: NUMBER OF {}\n{}\nITEM: BOX BOUNDS ff ff pp\n0 4\n0 4\n-0.5 0.5\n"


def write_dumps(folder) -> tuple[str, str]:
    """The atoms dump (dump custom) and pairs dump (dump local) of `STATES`, one frame per timestep."""
    atoms, pairs = folder / "atoms.dump", folder / "pairs.dump"
    atoms.write_text("".join(
        HEAD.format(step, "ATOMS", len(POSITIONS)) + "ITEM: ATOMS id type x y z radius\n"
        + "".join(f"{k} 1 {x} {y} 0 0.5\n" for k, (x, y) in enumerate(POSITIONS, start=1)) for step in STATES))
    pairs.write_text("".join(
        HEAD.format(step, "ENTRIES", len(contacts)) + f"ITEM: ENTRIES {' '.join(PAIR_COLUMNS)}\n"
        + "".join(f"{i} {j} 2.0 0 0 0\n" for i, j in contacts) for step, contacts in STATES.items()))
    return str(atoms), str(pairs)


def sequence_config(atoms: str, pairs: str) -> dict:
    from forcenet.catalog import expand_config, read_config_file

    config = read_config_file("config/example_sequence.yaml")
    config["studies"] = {"p1": {"systems": []}, "p2": {**config["studies"]["p2"], "systems": ["steps"]}}
    config["systems"] = {"steps": {
        "dimension": 2, "units": {"length": "mm", "force": "N"},
        "source": {"format": "lammps", "sequence": {"coordinate": "timestep"}, "timesteps": list(STATES),
                   "pair_columns": {"i": "c_pid[1]", "j": "c_pid[2]", "normal": "c_pf[1]",
                                    "tangential": ["c_pf[2]", "c_pf[3]", "c_pf[4]"]},
                   "runs": [{"atoms": atoms, "pairs": pairs}]}}}
    return expand_config(config)


def test_a_lammps_run_ordered_by_timestep_builds_end_to_end(tmp_path, monkeypatch):
    from forcenet.importers import import_run
    from forcenet.importers.scan import RECORD_DIR_ENV
    from forcenet.pipeline import aggregate, analyze_snapshot, snapshot_analysis_params
    from forcenet.pipeline_p2 import p2_distances, p2_run_summary

    monkeypatch.setenv(RECORD_DIR_ENV, str(tmp_path / "records"))
    config = sequence_config(*write_dumps(tmp_path))
    results, labels = str(tmp_path / "results"), paths.state_labels(3)  # state000 … state002: a sequence's files
    snapshots = [paths.snapshot(results, "steps", "r00", label) for label in labels]
    import_run(config=config, system="steps", realization=0, outputs=snapshots)
    analyses = [paths.analysis(results, "steps", "r00", label) for label in labels]
    params = snapshot_analysis_params(config, "steps")
    assert params["remove_rattlers"] == "none"  # P2's rule: every disk stays, though none has three contacts
    for snapshot, analysis in zip(snapshots, analyses):
        analyze_snapshot(snapshot, analysis, params, logging.getLogger("test"))

    imported = [read_snapshot(path) for path in snapshots]
    assert [s.attrs["state_coordinate_value"] for s in imported] == [0.0, 100.0, 250.0]
    assert [s.attrs["state_coordinate"] for s in imported] == ["timestep"] * 3
    states = [read_dataset(path, "analysis") for path in analyses]
    assert [float(s["rho"]) for s in states] == pytest.approx([math.pi / 16] * 3)
    assert [float(s["Z"]) for s in states] == pytest.approx([1.5, 2.0, 1.0])
    normal = FORCE_KINDS.index("normal")
    assert [float(s["mean_force"][normal]) for s in states] == pytest.approx([2.0] * 3)
    # F ≥ 0.5 ⟨F⟩: every contact; F ≥ 1.5 ⟨F⟩: none
    betti = [s["betti"].sel(force_kind="normal").sel(threshold=[0.5, 1.5], method="nearest") for s in states]
    assert [b.sel(homology_dim=0).values.tolist() for b in betti] == [[1, 0], [1, 0], [2, 0]]
    assert [b.sel(homology_dim=1).values.tolist() for b in betti] == [[0, 0], [1, 0], [0, 0]]

    measures_path, diagrams_path = paths.network_measures(results, "steps"), paths.diagrams(results, "steps")
    aggregate(analyses=analyses, realizations=[0], rhos=[0.0, 100.0, 250.0], measures_path=measures_path,
              diagrams_path=diagrams_path, config=config, system="steps")
    measures = read_dataset(measures_path, "network_measures")
    assert measures.attrs["state_coordinate"] == "timestep"
    assert measures["rho"].values.tolist() == [0.0, 100.0, 250.0]  # the state axis is the timestep, in memory too
    np.testing.assert_allclose(measures["Z"].values, [[1.5, 2.0, 1.0]])
    np.testing.assert_allclose(measures["rho_measured"].values, [[math.pi / 16] * 3])

    run = paths.p2_run(results, "steps", "r00")
    p2_run_summary(analyses=analyses, output=run, config=config, system="steps", realization="r00",
                   conventions=["minus_one"])
    distances_path = paths.distances(results, "steps")
    p2_distances(runs=[run], realizations=[0], output=distances_path, essential_convention="minus_one",
                 config=config, system="steps")
    distances = read_dataset(distances_path, "distances")
    assert distances["rho"].values.tolist() == [100.0, 250.0]  # each pair at its later state's timestep
    bottleneck = distances["distance"].sel(realization=0, force_kind="normal", metric="bottleneck")
    np.testing.assert_allclose(bottleneck.sel(homology_dim=0).values, [0.0, 1.0])
    np.testing.assert_allclose(bottleneck.sel(homology_dim=1).values, [1.0, 1.0])
    np.testing.assert_allclose(distances["Z"].values, [[2.0, 1.0]])
