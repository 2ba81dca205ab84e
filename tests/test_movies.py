"""Compression movies: an MP4 with one frame per snapshot (network) or per view angle (B0/N surface), frames with
the figure's axes, colour bar and ρ label; a movie that fails half-way leaves no file under its name."""
from __future__ import annotations

import imageio_ffmpeg
import matplotlib.pyplot as plt
import numpy as np
import pytest
from matplotlib.animation import FFMpegWriter
from matplotlib.collections import LineCollection

from conftest import load_config
from forcenet.plotting import movies
from forcenet.plotting.style import use_system_styles
from test_plotting_p1 import make_snapshot
from test_report_p1 import make_p1_measures

pytestmark = pytest.mark.slow


@pytest.fixture
def frames_seen(monkeypatch):
    """(number of axes, titles, colour-bar labels, contact segments drawn, azimuths of the 3D axes in degrees)
    of every frame handed to the encoder."""
    seen = []
    original = FFMpegWriter.grab_frame

    def grab(writer, **kwargs):
        fig = writer.fig
        data = [ax for ax in fig.axes if ax.get_label() != "<colorbar>"]
        bars = [ax.get_ylabel() for ax in fig.axes if ax.get_label() == "<colorbar>"]
        # the network's edges: its LineCollection (Line3DCollection is one too), one colour value (F/<F>) per edge
        segments = sum(len(c.get_array()) for ax in data for c in ax.collections
                       if isinstance(c, LineCollection) and c.get_array() is not None)
        azimuths = [float(ax.azim) for ax in data if hasattr(ax, "azim")]
        seen.append((len(fig.axes), [ax.get_title() for ax in fig.axes if ax.get_title()], bars, segments, azimuths))
        return original(writer, **kwargs)

    monkeypatch.setattr(FFMpegWriter, "grab_frame", grab)
    return seen


def frame_count(path) -> int:
    return imageio_ffmpeg.count_frames_and_secs(str(path))[0]


@pytest.mark.parametrize("dimension", [2, 3])
def test_network_movie_has_one_labelled_frame_per_snapshot(dimension, tmp_path, frames_seen):
    snapshots = [make_snapshot(dimension, seed=seed).assign(rho=0.80 + 0.01 * seed) for seed in range(4)]
    output = tmp_path / "network.mp4"
    assert movies.network_movie(snapshots, output, rattler_rule="once") == 4
    assert frame_count(output) == 4
    assert len(frames_seen) == 4
    for (n_axes, titles, bars, _, _), snapshot in zip(frames_seen, snapshots):
        assert n_axes == 2 and bars == [r"$F/\langle F\rangle$"]
        assert f"{float(snapshot['rho']):.3f}" in titles[0]  # the ρ label of that frame


@pytest.mark.parametrize("dimension", [2, 3])
def test_network_movie_frame_of_an_unjammed_snapshot_without_loaded_contacts(dimension, tmp_path, frames_seen):
    """Below jamming every particle can be a rattler: that frame has no edge, but it is drawn, with its ρ label,
    beside a frame that has edges."""
    loose = make_snapshot(dimension, seed=0)
    loose = loose.assign(force_normal=0.0 * loose["force_normal"], force_tangential=0.0 * loose["force_tangential"],
                         rho=0.44)
    output = tmp_path / "network.mp4"
    assert movies.network_movie([loose, make_snapshot(dimension, seed=1)], output, rattler_rule="once") == 2
    assert frame_count(output) == 2
    assert "0.440" in frames_seen[0][1][0]
    assert frames_seen[0][3] == 0 and frames_seen[1][3] > 0  # no loaded contact, then the loaded network's edges
    # only loose snapshots: one colour scale still exists
    assert movies.network_movie([loose], tmp_path / "loose.mp4", rattler_rule="once") == 1


def test_b0_surface_movie_turns_around_the_surface(tmp_path, frames_seen):
    use_system_styles(load_config("smoke.yaml")["system_info"])  # the catalog's labels, as the movie job takes them
    output = tmp_path / "surface.mp4"
    assert movies.b0_surface_movie(make_p1_measures(), "3d_hertz", output, frames=8) == 8
    assert frame_count(output) == 8
    n_axes, titles, bars, _, _ = frames_seen[0]
    assert n_axes == 2 and bars == [r"$B_0/N$"] and "3D" in titles[0]
    # one full turn in 8 equal steps: each frame 45 degrees on from the last, no angle twice
    azimuths = np.array([frame[4][0] for frame in frames_seen])
    np.testing.assert_allclose(np.diff(azimuths), 45.0)
    assert azimuths[-1] - azimuths[0] == pytest.approx(315.0)
    with pytest.raises(ValueError, match="no B0/N data"):
        movies.b0_surface_movie(make_p1_measures(), "2d_unknown", tmp_path / "x.mp4")


def test_a_failed_movie_leaves_no_file_under_its_name(tmp_path, monkeypatch):
    calls = []

    def fail_second(*args):
        calls.append(1)
        if len(calls) == 2:
            raise RuntimeError("drawing failed")
        return draw(*args)

    draw = movies.networks.draw_network_panel
    monkeypatch.setattr(movies.networks, "draw_network_panel", fail_second)
    output = tmp_path / "network.mp4"
    with pytest.raises(RuntimeError, match="drawing failed"):
        movies.network_movie([make_snapshot(2), make_snapshot(2)], output, rattler_rule="once")
    plt.close("all")
    assert not output.exists()
    with pytest.raises(ValueError, match="at least one snapshot"):
        movies.network_movie([], output, rattler_rule="once")
