"""Time series, phase portraits and drift figures hold exactly the trajectory's data."""

from __future__ import annotations

import numpy as np

from lagrangian.numerics import Trajectory
from lagrangian.plotting import plot_drift, plot_phase, plot_time_series, relative_drift


def _line(ax, k=0):
    line = ax.get_lines()[k]
    return np.asarray(line.get_xdata(), dtype=float), np.asarray(line.get_ydata(), dtype=float)


def test_time_series_panels_are_q_and_qdot(run):
    eom, traj = run("double_pendulum.toml")
    fig = plot_time_series(traj, eom)
    axes = fig.axes
    assert len(axes) == 2 * len(traj.coordinates)
    for i, _ in enumerate(traj.coordinates):
        for k, data in enumerate((traj.q[:, i], traj.qd[:, i])):
            x, y = _line(axes[2 * i + k])
            np.testing.assert_array_equal(x, traj.t)
            np.testing.assert_array_equal(y, data)
    # Course notation: θ₁ and its rate, in radians.
    assert axes[0].get_ylabel() == r"$\theta_{1}$ (rad)"
    assert axes[1].get_ylabel() == r"$\dot{\theta}_{1}$ (rad/s)"


def test_time_series_units_of_a_length(run):
    eom, traj = run("cart_pendulum.toml")
    axes = plot_time_series(traj, eom).axes
    assert axes[0].get_ylabel() == "$x$ (m)" and axes[1].get_ylabel() == r"$\dot{x}$ (m/s)"


def test_top_labels_are_greek(run):
    eom, traj = run("lagrange_top.toml")
    labels = [ax.get_ylabel() for ax in plot_time_series(traj, eom).axes]
    assert labels[::2] == [r"$\psi$ (rad)", r"$\theta$ (rad)", r"$\varphi$ (rad)"]


def test_phase_portraits(run):
    eom, traj = run("spherical_pendulum.toml")
    fig = plot_phase(traj, eom)
    visible = [ax for ax in fig.axes if ax.get_visible()]
    assert len(visible) == len(traj.coordinates)
    for i, ax in enumerate(visible):
        x, y = _line(ax)
        np.testing.assert_array_equal(x, traj.q[:, i])
        np.testing.assert_array_equal(y, traj.qd[:, i])


def test_drift_figure_data_are_the_monitors(run):
    eom, traj = run("lagrange_top.toml")
    fig = plot_drift(traj, eom)
    energy, drift = fig.axes
    for k, name in enumerate(("T", "U", "E")):
        np.testing.assert_array_equal(_line(energy, k)[1], traj.monitors[name])
    assert drift.get_yscale() == "log"
    # The dashed line is the drift tolerance (the run's default one here).
    lines = [line for line in drift.get_lines() if len(line.get_xdata()) and line.get_linestyle() != "--"]
    assert len(lines) == len(traj.integrals)
    for line, name in zip(lines, traj.integrals, strict=True):
        series = traj.monitors[name]
        # Independent of relative_drift: the definition, written out (S >= |I(t0)|, docs/simulation.md).
        assert traj.scales[name] >= abs(series[0])
        expected = np.abs(series - series[0]) / traj.scales[name]
        y = np.asarray(line.get_ydata(), dtype=float)
        shown = ~np.isnan(y)
        np.testing.assert_array_equal(y[shown], expected[shown])
        assert np.all(expected[~shown] == 0)
        assert np.nanmax(y) == traj.drift[name]


def test_relative_drift_is_relative_to_the_scale_of_the_run():
    # E.g. K = 0 for a top launched with no angular momentum about z0: the drift is relative to the
    # scale S the run recorded (the size of K's terms), as in the run's own conservation monitor;
    # without one, to max|I| (an integral that stays 0 has an absolute drift).
    t = np.array([0.0, 1.0, 2.0])
    zeros = np.zeros((3, 1))
    monitors = {"K": np.array([0.0, 1e-13, -3e-13]), "E": np.array([2.0, 2.5, 1.0]), "Z": np.zeros(3)}
    traj = Trajectory(model_name="m", coordinates=("x",), parameters={}, t=t, q=zeros, qd=zeros, qdd=zeros,
                      monitors=monitors, integrals=("K", "E", "Z"), drift={}, method="dop853", steps=0,
                      rhs_calls=0, scales={"K": 0.5})
    np.testing.assert_array_equal(relative_drift(traj, "K"), [0.0, 2e-13, 6e-13])
    np.testing.assert_array_equal(relative_drift(traj, "E"), [0.0, 0.2, 0.4])
    np.testing.assert_array_equal(relative_drift(traj, "Z"), [0.0, 0.0, 0.0])
