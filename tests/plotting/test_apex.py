"""The apex path on the unit sphere and the nutation figure of the heavy symmetric top."""

from __future__ import annotations

import numpy as np
import pytest

import lagrangian.plotting._apex as apex
from lagrangian.plotting import apex_path, plot_apex_sphere, plot_nutation, turning_angles

#: Output spacing of the top's run is 5e-4 s and |θ̇| ≤ ~1 rad/s near the turning points,
#: where θ̇ = 0: sampling misses the extreme θ by at most ~ θ̈ (Δt/2)²/2 ≈ 1e-6 rad.
SAMPLING = 1e-5


def test_sphere_path_lies_on_the_unit_sphere_and_spans_the_run_theta(run):
    eom, traj = run("lagrange_top.toml")
    fig = plot_apex_sphere(traj, eom)
    ax = fig.axes[0]
    path = ax.get_lines()[0]
    x, y, z = (np.asarray(a, dtype=float) for a in path.get_data_3d())
    points = np.column_stack([x, y, z])
    np.testing.assert_array_equal(points, apex_path(traj, eom))
    np.testing.assert_allclose(np.linalg.norm(points, axis=1), 1.0, rtol=0, atol=1e-12)
    theta = np.arccos(np.clip(z, -1, 1))
    th = traj.column("theta")
    assert abs(theta.min() - th.min()) < 1e-10 and abs(theta.max() - th.max()) < 1e-10


def test_turning_circles_match_the_simulated_extremes(run):
    eom, traj = run("lagrange_top.toml")
    angles = turning_angles(traj, eom)
    th = traj.column("theta")
    assert angles.theta1 < angles.theta2
    assert abs(angles.theta1 - th.min()) < SAMPLING
    assert abs(angles.theta2 - th.max()) < SAMPLING


def test_turning_circles_from_the_top_analysis_when_it_applies(run):
    pytest.importorskip("lagrangian.analysis._top")
    from lagrangian.analysis._top import analyse_top

    eom, traj = run("lagrange_top.toml")
    angles = turning_angles(traj, eom)
    assert angles.source == "analysis"
    expected = analyse_top(eom, parameters=dict(traj.parameters))
    assert (angles.theta1, angles.theta2) == (expected.theta1, expected.theta2)


def test_turning_circles_fall_back_to_the_run(run, monkeypatch):
    monkeypatch.setattr(apex, "_analysed", lambda *args: None)
    eom, traj = run("lagrange_top.toml")
    angles = turning_angles(traj, eom)
    th = traj.column("theta")
    assert angles.source == "simulation"
    # arccos of the tip's z0 component: θ to round-off
    np.testing.assert_allclose((angles.theta1, angles.theta2), (th.min(), th.max()), rtol=0, atol=1e-12)
    fig = plot_nutation(traj, eom)
    assert "simulation" in fig.axes[1].get_title()


def test_nutation_figure_data(run):
    eom, traj = run("lagrange_top.toml")
    fig = plot_nutation(traj, eom)
    polar, flat = fig.axes
    angle, radius = (np.asarray(a, dtype=float) for a in polar.get_lines()[0].get_data())
    psi, theta = traj.column("psi"), traj.column("theta")
    np.testing.assert_allclose(np.degrees(theta), radius, atol=1e-9)
    # The polar angle is the azimuth of the tip, ψ − 90° (mod 360°).
    np.testing.assert_allclose(np.cos(angle), np.cos(psi - np.pi / 2), atol=1e-10)
    np.testing.assert_allclose(np.sin(angle), np.sin(psi - np.pi / 2), atol=1e-10)
    x, y = (np.asarray(a, dtype=float) for a in flat.get_lines()[0].get_data())
    np.testing.assert_allclose(np.degrees(theta), y, atol=1e-9)
    # θ1 and θ2 as horizontal lines on the (ψ, θ) panel
    levels = sorted({float(line.get_ydata()[0]) for line in flat.get_lines()[1:]})
    angles = turning_angles(traj, eom)
    np.testing.assert_allclose(levels, np.degrees([angles.theta1, angles.theta2]))
