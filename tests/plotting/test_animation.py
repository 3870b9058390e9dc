"""The animation: its frames, its scene (what is drawn where), and its file."""

from __future__ import annotations

import shutil

import numpy as np
import pytest
from PIL import Image

from lagrangian.errors import OutputError
from lagrangian.plotting import animate
from lagrangian.plotting._animation import motion_scene
from lagrangian.plotting._geometry import point_positions


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
    scene = motion_scene(traj, eom, traj.t[::10])
    assert scene.dimension == 2
    assert scene.plane_names == ("y0", "z0")  # z0 up, against gravity
    (name, _, rod), = scene.lines
    assert name == "OP"
    op = point_positions(traj, eom, ["P"])["P"]
    np.testing.assert_allclose(rod[:, 1], op[::10, 1:], rtol=0, atol=1e-6)  # float32 in the scene
    np.testing.assert_array_equal(scene.fixed, [[0.0, 0.0]])


def test_frames_between_samples_interpolate_q_not_positions(run):
    # Linear interpolation of positions would shorten the rod between samples; of θ, it keeps |OP| = l.
    eom, traj = run("simple_pendulum.toml")
    times = (traj.t[:-1:7] + traj.t[1::7]) / 2
    (_, _, rod), = motion_scene(traj, eom, times).lines
    np.testing.assert_allclose(np.linalg.norm(rod[:, 1] - rod[:, 0], axis=1), traj.parameters["l"], atol=1e-6)
    theta = np.interp(times, traj.t, traj.column("theta"))
    l = traj.parameters["l"]
    np.testing.assert_allclose(rod[:, 1], np.column_stack([l * np.sin(theta), -l * np.cos(theta)]), atol=1e-6)


def test_a_wheel_is_drawn_as_its_disk(run):
    # The coin rolls upright: its disk, of radius r (C = m r²/2 about its axle y1), is across y1, centred at G.
    eom, traj = run("rolling_coin.toml")
    scene = motion_scene(traj, eom, traj.t[::20])
    assert scene.dimension == 3
    (_, disk), = scene.disks
    g = point_positions(traj, eom, ["S"])["S"][::20]
    r = traj.parameters["r"]
    np.testing.assert_allclose(np.linalg.norm(disk - g[:, None, :], axis=2), r, atol=1e-6)
    psi = traj.column("psi")[::20]
    axle = np.column_stack([-np.sin(psi), np.cos(psi), 0 * psi])  # y1
    np.testing.assert_allclose(np.einsum("fmj,fj->fm", disk - g[:, None, :], axle), 0.0, atol=1e-6)


def test_double_pendulum_rods_go_from_hinge_to_hinge(run):
    # Each rod is the solid of its inertia (A = m l²/12 at G: length l), so rod S1 spans O to A.
    eom, traj = run("double_pendulum.toml")
    scene = motion_scene(traj, eom, traj.t[:5])
    rods = {name: a for name, _, a in scene.lines}
    pos = point_positions(traj, eom, ["O", "A", "S2"])
    plane = scene.plane
    a = pos["A"][:5] @ plane.T
    ends = {"S1": (pos["O"][:5] @ plane.T, a), "S2": (a, (2 * pos["S2"][:5] - pos["A"][:5]) @ plane.T)}
    for name, (p, q) in ends.items():
        rod = rods[name]
        assert (np.allclose(rod[:, 0], p, atol=1e-6) and np.allclose(rod[:, 1], q, atol=1e-6)) or \
            (np.allclose(rod[:, 0], q, atol=1e-6) and np.allclose(rod[:, 1], p, atol=1e-6))


def test_top_is_drawn_in_3d_with_a_spinning_disk(run):
    eom, traj = run("lagrange_top.toml")
    scene = motion_scene(traj, eom, traj.t[::50])
    assert scene.dimension == 3
    (_, stem), = [(n, a) for n, _, a in scene.lines]
    o, apex = stem[:, 0], stem[:, -1]  # the axle, from O through G to the apex
    np.testing.assert_allclose(o, 0.0, atol=1e-7)
    g = point_positions(traj, eom, ["S"])["S"][::50]
    np.testing.assert_allclose(np.linalg.norm(g, axis=1), traj.parameters["a"], atol=1e-12)
    axis = g / np.linalg.norm(g, axis=1)[:, None]
    np.testing.assert_allclose(np.cross(apex, axis), 0.0, atol=1e-6)  # G on the axle, the apex beyond it
    assert np.all(np.einsum("fj,fj->f", apex, axis) > traj.parameters["a"])
    (_, disk), = scene.disks
    np.testing.assert_allclose(np.einsum("fmj,fj->fm", disk - g[:, None, :], axis), 0.0, atol=1e-6)
    # The disk's radius r gives its C: C = m r²/2, with C the top's moment about its axis.
    r = np.linalg.norm(disk[0, 0] - g[0])
    assert abs(traj.parameters["m"] * r ** 2 / 2 - traj.parameters["C"]) < 1e-6
    # The spoke turns with φ: its angle from the line of nodes u = (cosψ, sinψ, 0) is φ.
    (spoke,) = scene.spokes
    d = spoke[:, 1] - spoke[:, 0]
    d /= np.linalg.norm(d, axis=1)[:, None]
    psi, phi = traj.column("psi")[::50], traj.column("phi")[::50]
    u = np.column_stack([np.cos(psi), np.sin(psi), 0 * psi])
    np.testing.assert_allclose(np.einsum("fj,fj->f", d, u), np.cos(phi), atol=1e-5)


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
