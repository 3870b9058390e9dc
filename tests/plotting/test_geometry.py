"""Positions and body axes evaluated along trajectories, against the closed forms of the examples."""

from __future__ import annotations

import numpy as np
import pytest

from lagrangian.plotting._geometry import apex_path, axis_angles, default_axis, point_positions

#: Round-off of a few products of sines and cosines of O(1) angles.
ROUND_OFF = 1e-12


def test_top_axis_tip_is_the_unit_vector_of_the_euler_angles(run):
    # z = sinθ sinψ x0 − sinθ cosψ y0 + cosθ z0 (R0 →ψ,z0→ R1 →θ,u→ R2)
    eom, traj = run("lagrange_top.toml")
    assert default_axis(eom) == ("S", "z")
    tip = apex_path(traj, eom)
    psi, theta = traj.column("psi"), traj.column("theta")
    expected = np.column_stack([np.sin(theta) * np.sin(psi), -np.sin(theta) * np.cos(psi), np.cos(theta)])
    np.testing.assert_allclose(tip, expected, rtol=0, atol=ROUND_OFF)
    np.testing.assert_allclose(np.linalg.norm(tip, axis=1), 1.0, rtol=0, atol=ROUND_OFF)


def test_axis_angles_give_back_psi_and_theta(run):
    eom, traj = run("lagrange_top.toml")
    psi, theta = axis_angles(apex_path(traj, eom))
    np.testing.assert_allclose(theta, traj.column("theta"), rtol=0, atol=1e-10)
    offset = np.round((psi[0] - traj.column("psi")[0]) / (2 * np.pi)) * 2 * np.pi
    np.testing.assert_allclose(psi - offset, traj.column("psi"), rtol=0, atol=1e-10)


def test_axis_angles_of_random_directions():
    rng = np.random.default_rng(3)
    psi = rng.uniform(-np.pi, np.pi, 50)
    theta = rng.uniform(0.01, np.pi - 0.01, 50)
    tip = np.column_stack([np.sin(theta) * np.sin(psi), -np.sin(theta) * np.cos(psi), np.cos(theta)])
    p, t = axis_angles(tip[np.argsort(psi)])
    np.testing.assert_allclose(t, theta[np.argsort(psi)], atol=1e-12)
    np.testing.assert_allclose(np.mod(p + np.pi, 2 * np.pi) - np.pi, np.sort(psi), atol=1e-12)


def test_other_axes_of_the_top_are_unit_and_orthogonal(run):
    eom, traj = run("lagrange_top.toml")
    x, y, z = (apex_path(traj, eom, "S", a) for a in "xyz")
    for v in (x, y):
        np.testing.assert_allclose(np.linalg.norm(v, axis=1), 1.0, atol=ROUND_OFF)
    np.testing.assert_allclose(np.cross(x, y), z, atol=ROUND_OFF)


def test_simple_pendulum_bob_position(run):
    # OP = −l z1 with R1 turned by θ about x0: OP = (0, l sinθ, −l cosθ)
    eom, traj = run("simple_pendulum.toml")
    l = traj.parameters["l"]
    theta = traj.column("theta")
    op = point_positions(traj, eom, ["P"])["P"]
    np.testing.assert_allclose(op, np.column_stack([0 * theta, l * np.sin(theta), -l * np.cos(theta)]),
                               atol=ROUND_OFF)


def test_no_body_no_axis(run):
    from lagrangian.errors import OutputError

    eom, traj = run("simple_pendulum.toml")
    with pytest.raises(OutputError, match="no rigid body"):
        apex_path(traj, eom)
    eom, traj = run("lagrange_top.toml")
    with pytest.raises(OutputError, match="no body `T`"):
        apex_path(traj, eom, "T")
