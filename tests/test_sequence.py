"""Imported sequences (issue 56): runs ordered by strain, time, frame or timestep at any ρ, their state axis on disk,
P2's distances along them, the figures and products that fit them, and each refusal naming the option that accepts
the data."""
from __future__ import annotations

import numpy as np
import pandas as pd
import pytest
import xarray as xr

from forcenet.checks import checked_system
from forcenet.importers import SourceError
from forcenet.importers.system import measured_labels
from forcenet.datasets import paths
from forcenet.datasets.io import read_dataset, sequence_in_memory, sequence_on_disk, write_netcdf
from forcenet.datasets.paths import state_labels
from forcenet.importers.sequence import coordinate_values
from forcenet.plotting.registry import FIGURES_BY_ID, figure_fit
from forcenet.systems import ConfigError, ImportedSystem
from forcenet.workflow_io import read_config_file

SEQUENCE_CONFIG = "config/example_sequence.yaml"


def table_entry(sequence, states=3):
    return {"dimension": 2, "source": {"format": "table", "forces": "magnitudes", "sequence": sequence,
                                       "runs": [[{"particles": "p.csv", "contacts": "c.csv"}] * states]}}


def lammps_entry(sequence):
    return {"dimension": 2, "source": {"format": "lammps", "sequence": sequence, "runs": [{}]}}


def test_each_coordinate_gives_its_values_in_the_runs_order():
    assert coordinate_values(table_entry({"coordinate": "frame"}), [0, 1, 2], "s") == (0.0, 1.0, 2.0)
    assert coordinate_values(table_entry({"coordinate": "strain", "values": [0, 0.01, 0.03]}), [0, 1, 2], "s") == (
        0.0, 0.01, 0.03)
    assert coordinate_values(lammps_entry({"coordinate": "timestep"}), [100, 200, 400], "s") == (100.0, 200.0, 400.0)
    assert coordinate_values(lammps_entry({"coordinate": "time", "per_timestep": 0.5}), [100, 200], "s") == (
        50.0, 100.0)
    assert coordinate_values(table_entry({"coordinate": "timestep"}), [0, 1], "s") == (0.0, 1.0)  # a table's index
    assert state_labels(3) == ["state000", "state001", "state002"]
    assert state_labels(1001)[-1] == "state1000"


def test_a_sequence_that_cannot_be_had_or_does_not_increase_is_refused_naming_the_option():
    with pytest.raises(ValueError, match=r"config key 's.sequence': coordinate strain needs values \(one per state, "
                                         r"in order\); coordinate frame takes the states' order"):
        coordinate_values(table_entry({"coordinate": "strain"}), [0, 1, 2], "s")
    with pytest.raises(ValueError, match=r"coordinate time needs values \(one per state\) or per_timestep"):
        coordinate_values(lammps_entry({"coordinate": "time"}), [0, 10], "s")
    with pytest.raises(ValueError, match=r"config key 's.sequence.values': 2 values for 3 states: give one per state"):
        coordinate_values(table_entry({"coordinate": "strain", "values": [0, 1]}), [0, 1, 2], "s")
    with pytest.raises(ValueError, match=r"the strain of state 2 \(0.01\) does not exceed that of state 1 \(0.02\)"):
        coordinate_values(table_entry({"coordinate": "strain", "values": [0, 0.02, 0.01]}), [0, 1, 2], "s")


def test_the_shipped_sequence_is_one_run_at_constant_rho_keyed_by_its_strain():
    config = read_config_file(SEQUENCE_CONFIG)
    from forcenet.catalog import expand_config

    config = expand_config(config)
    spec = checked_system("table_shear_2d", config)
    assert isinstance(spec, ImportedSystem) and spec.is_sequence and spec.coordinate == "strain"
    assert len(spec.rho_grid) == 12 and spec.rho_grid[:3] == (0.0, 0.002, 0.004)
    assert set(measured_labels("table_shear_2d", config["systems"]["table_shear_2d"])) == {"0.853"}  # one ρ
    assert spec.rho_labels[:2] == ["state000", "state001"] and not spec.movies
    assert paths.snapshot("results", "table_shear_2d", "r00", "state003") == "results/sim/table_shear_2d/r00/state003.nc"
    assert paths.snapshot("results", "x", "r00", "0.840") == "results/sim/x/r00/rho0.840.nc"
    # the same states without sequence: states at one ρ are refused, naming the option that accepts them
    entry = {**config["systems"]["table_shear_2d"]}
    entry["source"] = {k: v for k, v in entry["source"].items() if k != "sequence"}
    with pytest.raises(SourceError, match=r"states with the same ρ .* is one run with source.sequence"):
        measured_labels("flat", entry)  # forcenet-check-config and the import job read the files; parsing does not
    with pytest.raises(ConfigError, match=r"'systems.flat.rho': not given"):
        checked_system("flat", {**config, "systems": {"flat": entry}})
    with pytest.raises(ConfigError, match=r"'systems.table_shear_2d.rho': a sequence's states are keyed by its "
                                          r"coordinate \(strain\)"):
        checked_system("table_shear_2d", {**config, "systems": {"table_shear_2d": {
            **config["systems"]["table_shear_2d"], "rho": [0.853]}}})


def stacked(coordinate=None):
    rho = xr.Variable(("rho",), [0.0, 0.5, 1.0], attrs={"units": "1", "long_name": "grid"})
    ds = xr.Dataset({"Z": xr.Variable(("realization", "rho"), np.ones((1, 3)), {"units": "1", "long_name": "Z"}),
                     "point_rho": xr.Variable(("point",), [0.5], {"units": "1", "long_name": "p"})},
                    coords={"rho": rho}, attrs={"system": "s"})
    if coordinate:
        ds.attrs.update(state_coordinate=coordinate, state_coordinate_units="s")
    return ds


def test_a_sequences_state_axis_is_named_after_its_coordinate_on_disk_and_rho_in_memory(tmp_path):
    disk = sequence_on_disk(stacked("time"))
    assert set(disk.dims) == {"realization", "time", "point"} and "point_time" in disk
    assert disk["time"].attrs == {"units": "s", "long_name": "time of the state (source.sequence)"}
    back = sequence_in_memory(disk)
    assert "rho" in back.dims and back["point_rho"].values.tolist() == [0.5]
    assert sequence_on_disk(stacked()) is not None and "rho" in sequence_on_disk(stacked()).dims  # a compression


def test_p2_distances_run_along_a_sequence_at_constant_rho():
    from forcenet.report.p2_distances import consecutive_distances

    def analysis(birth):
        return xr.Dataset({"rho": 0.85, "Z": 4.0,
                           "diagram_force_kind": ("point", [1]), "diagram_homology_dim": ("point", [0]),
                           "birth": ("point", [birth]), "death": ("point", [0.0]), "essential": ("point", [0])},
                          coords={"force_kind": ["total", "normal", "tangential"]})

    states = [analysis(1.0), analysis(1.5), analysis(1.25)]
    with pytest.raises(ValueError, match="strictly increasing rho"):
        consecutive_distances(states, force_kinds=["normal"], homology_dims=[0])
    out = consecutive_distances(states, force_kinds=["normal"], homology_dims=[0], sequence=True)
    # one point each: the bottleneck distance is the change of its lifespan, 0.5 then 0.25
    assert out["distance"].sel(metric="bottleneck").values.ravel().tolist() == pytest.approx([0.5, 0.25])
    assert out["rho_previous"].values.tolist() == [0.85, 0.85]


def test_figures_that_need_several_states_or_a_compression_leave_the_others_out_with_a_note():
    several = FIGURES_BY_ID["p1_fig06_betti0"]
    kept, notes = figure_fit(several, ["a", "b"], {"a": 1, "b": 5})
    assert kept == ["b"] and notes == ["p1_fig06_betti0: a left out: it has 1 state, and the figure draws a measure "
                                       "over the states of a run"]
    kept, notes = figure_fit(several, ["a"], {"a": 1})
    assert kept == [] and len(notes) == 1 and notes[0].startswith("p1_fig06_betti0: not made: a left out")
    assert figure_fit(FIGURES_BY_ID["p1_fig01_networks"], ["a"], {"a": 1}) == (["a"], [])
    kept, notes = figure_fit(FIGURES_BY_ID["p2_fig01_snapshots_differences"], ["s"], {"s": 12}, sequences=["s"])
    assert kept == [] and "sequence at constant ρ" in notes[0]


def test_a_figure_csv_names_a_sequences_axis_after_its_coordinate():
    from forcenet.pipeline_figures import with_state_columns
    from forcenet.plotting.figure_data import FigureData
    from forcenet.plotting.style import STATE_AXES, state_axis_label

    STATE_AXES.clear()
    STATE_AXES.update({"seq": ("time", "s")})
    try:
        data = FigureData(pd.DataFrame({"system": ["seq"], "rho": [1.0], "realization_mean": [2.0]}))
        assert list(with_state_columns(data).table.columns) == ["system", "t [s]", "realization_mean"]
        mixed = FigureData(pd.DataFrame({"system": ["seq", "dem"], "rho": [1.0, 0.8], "realization_mean": [2, 3]}))
        assert with_state_columns(mixed).table["state_axis"].tolist() == ["t [s]", "rho"]
        assert state_axis_label("seq") == "time $t$ [s]" and state_axis_label("dem") == r"packing fraction $\rho$"
    finally:
        STATE_AXES.clear()


@pytest.mark.workflow
def test_the_shipped_sequence_builds_as_one_run(tmp_path):
    """config/example_sequence.yaml: P1 measures against the strain, P2 distances along it, no empty figure, no movie,
    validation tables saying why they list no claim."""
    import shutil

    from conftest import REPO, snakemake

    shutil.copytree(REPO / "data/examples/table_shear_2d", tmp_path / "data/examples/table_shear_2d")
    done = snakemake(tmp_path, config=REPO / SEQUENCE_CONFIG)
    assert done.returncode == 0, done.stderr[-3000:]
    assert "forcenet: note: movies of table_shear_2d: not made" in done.stderr
    results = tmp_path / "results/example_sequence"
    measures = read_dataset(paths.network_measures(results, "table_shear_2d"), "network_measures")
    assert measures.sizes["rho"] == 12 and measures.attrs["state_coordinate"] == "strain"
    with xr.open_dataset(paths.distances(results, "table_shear_2d_p2")) as on_disk:
        assert on_disk.sizes["strain"] == 11 and np.all(np.isfinite(on_disk["distance"].values))
        assert on_disk["strain"].attrs["long_name"] == "strain of the state (source.sequence)"
    with xr.open_dataset(paths.snapshot(results, "table_shear_2d", "r00", "state000")) as snapshot:
        assert snapshot["position"].attrs["units"] == "mm" and snapshot["force_normal"].attrs["units"] == "N"
    # the source's units downstream (issue 56 item 4), the stacked file's seed −1 as its snapshots'
    assert measures["mean_force"].attrs["units"] == "N" and measures.attrs["seed"] == -1
    assert "x_i [mm]" in pd.read_csv(paths.figure(results, "p1_fig01_networks", "csv")).columns
    assert "strain" in pd.read_csv(paths.figure(results, "p1_fig06_betti0", "csv")).columns
    assert not list(tmp_path.glob("results/example_sequence/movies/*.mp4"))
    assert "No claim applies" in (results / "tables/p1_validation.md").read_text(encoding="utf-8")
    assert "p2_table1, p2_table2, p2_table3: not made" in (results / "tables/skipped.md").read_text(encoding="utf-8")


def test_an_imported_systems_units_reach_its_analysis_and_network_figures(tmp_path):
    """Issue 56 item 4: the shipped sequence (mm, N) keeps its units downstream: the analysis' ⟨F⟩ in N, the network
    figures' axes and CSV columns in mm; a figure drawing snapshots of two units names each row's."""
    import logging

    import matplotlib.pyplot as plt

    from forcenet.catalog import expand_config
    from forcenet.datasets import read_snapshot
    from forcenet.importers import import_run
    from forcenet.pipeline import analyze_snapshot, snapshot_analysis_params
    from forcenet.plotting import networks

    config = expand_config(read_config_file(SEQUENCE_CONFIG))
    outputs = [str(tmp_path / f"{label}.nc") for label in state_labels(12)]
    import_run(config=config, system="table_shear_2d", realization=0, outputs=outputs)
    analyze_snapshot(outputs[0], str(tmp_path / "analysis.nc"), snapshot_analysis_params(config, "table_shear_2d"),
                     logging.getLogger("test"))
    analysis = read_dataset(str(tmp_path / "analysis.nc"), "analysis")
    assert analysis["mean_force"].attrs["units"] == "N" and analysis["threshold"].attrs["units"] == "<F>"
    snapshot = read_snapshot(outputs[0])
    data = networks.prepare_p1_fig01_networks({"table_shear_2d": snapshot}, rattler_rule=True)
    assert {"x_i [mm]", "y_j [mm]", "x [mm]", "radius [mm]"} <= set(data.table.columns)
    # the state's place on the run's axis is its strain, not its ρ (the CSV names that column after the strain)
    assert set(data.table["rho"]) == {float(snapshot.attrs["state_coordinate_value"])} != {float(snapshot["rho"])}
    assert not any("d_ave" in column for column in data.table.columns)
    figure = networks.draw_p1_fig01_networks(data)
    assert (figure.axes[0].get_xlabel(), figure.axes[0].get_ylabel()) == ("$x$ [mm]", "$y$ [mm]")
    plt.close(figure)
    # beside a snapshot in d_ave (our engine's unit), each row names its own unit and each panel's axes say it
    engine = snapshot.copy()
    for name in ("position", "radius", "box_lo", "box_hi"):
        engine[name].attrs["units"] = "d_ave"
    mixed = networks.prepare_p1_fig01_networks({"table_shear_2d": snapshot, "engine": engine}, rattler_rule=True)
    assert "x_i [length_unit]" in mixed.table and set(mixed.table["length_unit"]) == {"mm", "d_ave"}
    figure = networks.draw_p1_fig01_networks(mixed)
    labels = {figure.axes[k].get_xlabel() for k in range(2)}
    assert labels == {"$x$ [mm]", networks.POSITION_LABELS[0]}
    plt.close(figure)
