"""The animation: its frames, its scene (what is drawn where), and its file."""

from __future__ import annotations

import shutil

import numpy as np
import pytest
from PIL import Image

from lagrangian.errors import OutputError
from lagrangian.plotting import animate
from lagrangian.plotting._geometry import point_positions
from lagrangian.plotting._scene import build_scene


def test_gif_has_the_requested_frames_and_rate(run, tmp_path):
    eom, traj = run("double_pendulum.toml")
    path = animate(traj, eom, tmp_path / "a.gif", frames=7, fps=20, size=2.0, dpi=50)
    with Image.open(path) as im:
        assert im.format == "GIF"
        assert im.n_frames == 7
        assert im.size == (100, 100)
        assert im.info["duration"] == 50
        im.seek(3)
        # the background stays exactly white (one palette for all frames)
        assert im.convert("RGB").getpixel((1, 1)) == (255, 255, 255)


def test_gif_frames_differ_even_for_a_system_at_rest(run, tmp_path):
    # Pillow merges identical consecutive frames; the time shown keeps them distinct.
    eom, traj = run("simple_pendulum.toml", theta=0.0)
    path = animate(traj, eom, tmp_path / "rest.gif", frames=5, size=2.0, dpi=40)
    with Image.open(path) as im:
        assert im.n_frames == 5


def test_planar_motion_is_drawn_in_its_plane(run):
    eom, traj = run("simple_pendulum.toml")
    scene = build_scene(traj, eom, traj.t[::10])
    assert scene.dimension == 2
    assert scene.plane_names == ("y0", "z0")  # z0 up, against gravity
    (name, rod), = scene.lines
    assert name == "OP"
    op = point_positions(traj, eom, ["P"])["P"]
    np.testing.assert_allclose(rod[:, 1], op[::10, 1:], rtol=0, atol=1e-15)
    np.testing.assert_array_equal(scene.fixed, [[0.0, 0.0]])


def test_frames_between_samples_interpolate_q_not_positions(run):
    # Linear interpolation of positions would shorten the rod between samples; of θ, it keeps |OP| = l.
    eom, traj = run("simple_pendulum.toml")
    times = (traj.t[:-1:7] + traj.t[1::7]) / 2
    (_, rod), = build_scene(traj, eom, times).lines
    np.testing.assert_allclose(np.linalg.norm(rod[:, 1] - rod[:, 0], axis=1), traj.parameters["l"], atol=1e-12)
    theta = np.interp(times, traj.t, traj.column("theta"))
    l = traj.parameters["l"]
    np.testing.assert_allclose(rod[:, 1], np.column_stack([l * np.sin(theta), -l * np.cos(theta)]), atol=1e-12)


def test_a_wheel_is_drawn_as_its_disk(run):
    # The coin rolls upright: its disk, of radius r = |GI| (I the contact point), is across its axle y1.
    eom, traj = run("rolling_coin.toml")
    scene = build_scene(traj, eom, traj.t[::20])
    assert scene.dimension == 3
    (disk,) = scene.disks
    (_, g), = scene.lines
    g = g[:, 0]
    r = traj.parameters["r"]
    np.testing.assert_allclose(np.linalg.norm(disk - g[:, None, :], axis=2), r, atol=1e-12)
    psi = traj.column("psi")[::20]
    axle = np.column_stack([-np.sin(psi), np.cos(psi), 0 * psi])  # y1
    np.testing.assert_allclose(np.einsum("fmj,fj->fm", disk - g[:, None, :], axle), 0.0, atol=1e-12)


def test_double_pendulum_rods_go_through_their_hinges(run):
    eom, traj = run("double_pendulum.toml")
    scene = build_scene(traj, eom, traj.t[:5])
    rods = dict(scene.lines)
    pos = point_positions(traj, eom, ["O", "A", "S1", "S2"])
    plane = scene.plane
    for name, chain in (("S1", ["O", "S1", "A"]), ("S2", ["A", "S2"])):
        expected = np.stack([pos[p][:5] @ plane.T for p in chain], axis=1)
        np.testing.assert_allclose(rods[name], expected, atol=1e-12)


def test_top_is_drawn_in_3d_with_a_spinning_disk(run):
    eom, traj = run("lagrange_top.toml")
    scene = build_scene(traj, eom, traj.t[::50])
    assert scene.dimension == 3
    (name, body), = scene.lines
    o, g = body[:, 0], body[:, -1]
    np.testing.assert_allclose(o, 0.0, atol=0)
    np.testing.assert_allclose(np.linalg.norm(g, axis=1), traj.parameters["a"], atol=1e-12)
    axis = g / np.linalg.norm(g, axis=1)[:, None]
    (disk,) = scene.disks
    np.testing.assert_allclose(np.einsum("fmj,fj->fm", disk - g[:, None, :], axis), 0.0, atol=1e-15)
    # The spoke turns with φ: its angle from the line of nodes u = (cosψ, sinψ, 0) is φ.
    (spoke,) = scene.spokes
    d = spoke[:, 1] - spoke[:, 0]
    d /= np.linalg.norm(d, axis=1)[:, None]
    psi, phi = traj.column("psi")[::50], traj.column("phi")[::50]
    u = np.column_stack([np.cos(psi), np.sin(psi), 0 * psi])
    np.testing.assert_allclose(np.einsum("fj,fj->f", d, u), np.cos(phi), atol=1e-12)


def test_bad_options(run, tmp_path):
    eom, traj = run("simple_pendulum.toml")
    with pytest.raises(OutputError, match="frames"):
        animate(traj, eom, tmp_path / "a.gif", frames=1)
    with pytest.raises(OutputError, match="frame rate"):
        animate(traj, eom, tmp_path / "a.gif", fps=0)
    with pytest.raises(OutputError, match=r"\.gif"):
        animate(traj, eom, tmp_path / "a.avi")
    assert not list(tmp_path.iterdir())


@pytest.mark.skipif(shutil.which("ffmpeg") is not None, reason="ffmpeg is installed")
def test_mp4_without_ffmpeg_says_so(run, tmp_path):
    eom, traj = run("simple_pendulum.toml")
    with pytest.raises(OutputError, match="ffmpeg"):
        animate(traj, eom, tmp_path / "a.mp4", frames=3)


@pytest.mark.skipif(shutil.which("ffmpeg") is None, reason="needs ffmpeg")
def test_mp4_with_ffmpeg(run, tmp_path):
    eom, traj = run("simple_pendulum.toml")
    path = animate(traj, eom, tmp_path / "a.mp4", frames=4, size=2.0, dpi=40)
    assert path.stat().st_size > 0
    assert [p.name for p in tmp_path.iterdir()] == ["a.mp4"]
