"""A motion in the view: sampled frames, vectors along it, runs overlaid and beside, the still pictures."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest
from view_test_support import motion

import lagrangian
from lagrangian.errors import OutputError
from lagrangian.numerics import reaction_columns_along
from lagrangian.view3d import view


def test_the_frames_are_the_output_times_and_the_velocity_is_l_theta_dot():
    eom, traj = motion("simple_pendulum.toml", 1.0, 101)
    scene = view(traj, eom).scene
    np.testing.assert_array_equal(scene.t, traj.t)
    l, theta, rate = traj.parameters["l"], traj.column("theta"), traj.column("theta_dot")
    # OP = −l z1 = l (0, sin θ, −cos θ), so V(P/R0) = l θ̇ (0, cos θ, sin θ).
    (v,) = [a for a in scene.arrows if a.name == "V(P)"]
    expected = l * rate[:, None] * np.column_stack([0 * theta, np.cos(theta), np.sin(theta)])
    np.testing.assert_allclose(v.values, expected, atol=1e-6 * l * np.abs(rate).max())
    p = scene.track("P")
    np.testing.assert_allclose(scene.runs[0].points[:, p], l * np.column_stack(
        [0 * theta, np.sin(theta), -np.cos(theta)]), atol=1e-6)
    assert v.scale * np.linalg.norm(v.values, axis=1).max() == pytest.approx(0.3 * scene.size, rel=1e-5)


def test_the_reaction_at_o_is_drawn_from_the_trajectory_columns():
    eom, traj = motion("lagrange_top.toml", 0.5, 101)
    traj = replace(traj, extra=reaction_columns_along(eom, traj))
    scene = view(traj, eom, vectors=["R_O"]).scene
    (r,) = [a for a in scene.arrows if a.name == "R_O"]
    assert r.shown and r.kind == "reaction" and scene.tracks[r.track].name == "O"
    np.testing.assert_allclose(r.values, np.column_stack([traj.extra[f"R_O_{a}"] for a in ("x0", "y0", "z0")]),
                               rtol=1e-6)
    with pytest.raises(OutputError, match="no vector `R_A`"):
        view(traj, eom, vectors=["R_A"])


def test_ghosts_overlay_and_a_run_beside_is_apart():
    eom, first = motion("double_pendulum.toml", 1.0, 101)
    second = lagrangian.simulate(eom, 1.0, n_out=51, initial={"theta1": 0.9})
    shown = view(first, eom, ghosts=[second], beside=second, labels=["replay", "member", "optimal"])
    runs = shown.scene.runs
    assert [r.label for r in runs] == ["replay", "member", "optimal"] and [r.ghost for r in runs] == [False, True, False]
    assert runs[1].offset == (0.0, 0.0, 0.0)
    # The ghost is sampled at the main run's times: its rod is where its own θ1 puts it then.
    g1 = shown.scene.track("S1")
    th1 = np.interp(first.t, second.t, second.column("theta1"))
    np.testing.assert_allclose(runs[1].points[:, g1], 0.5 * np.column_stack([0 * th1, np.sin(th1), -np.cos(th1)]),
                               atol=1e-5)
    # Beside: shifted across the view, farther than the pendulum reaches (l1 + l2 = 1.8 m).
    shift = np.array(runs[2].offset)
    assert np.linalg.norm(shift) > 1.8 and abs(shift @ np.array(shown.scene.view_direction)) < 1e-9
    with pytest.raises(OutputError, match="coordinates"):
        view(first, eom, ghosts=[motion("simple_pendulum.toml", 1.0, 101)[1]])


def test_a_trajectory_needs_its_model():
    _, traj = motion("simple_pendulum.toml", 1.0, 101)
    with pytest.raises(OutputError, match="does not carry its model"):
        view(traj)


def test_a_still_by_matplotlib_where_no_browser_is_asked_for():
    eom, traj = motion("double_pendulum.toml", 1.0, 101)
    png = view(traj, eom).png(width=400, height=300, time=0.5, browser=False)
    assert png.startswith(b"\x89PNG\r\n\x1a\n")
    from io import BytesIO

    from PIL import Image

    image = np.asarray(Image.open(BytesIO(png)).convert("RGB"))
    assert image.shape[:2] == (300, 400)
    red = (image[..., 0] > 180) & (image[..., 1] < 90) & (image[..., 2] < 90)
    blue = (image[..., 2] > 150) & (image[..., 0] < 80)
    assert red.sum() > 30 and blue.sum() > 30  # both rods, in the 3-D page's colours


def test_the_latex_report_gets_a_still_drawn_by_matplotlib_where_no_browser_is(monkeypatch, tmp_path):
    monkeypatch.setattr("lagrangian.view3d._still.find_chromium", lambda: None)
    r = lagrangian.report(lagrangian.lagrange_top(), lang="en", verification=False)
    r.save(tmp_path / "top.tex")
    tex = (tmp_path / "top.tex").read_text(encoding="utf-8")
    assert r"\includegraphics[width=\linewidth]{top-figure-1.png}" in tex and "The system in its initial position" in tex
    from io import BytesIO

    from PIL import Image

    image = np.asarray(Image.open(BytesIO((tmp_path / "top-figure-1.png").read_bytes())).convert("RGB"))
    blue = (image[..., 2] > 150) & (image[..., 0] < 90)
    assert blue.sum() > 50  # the top's disk, in its colour
