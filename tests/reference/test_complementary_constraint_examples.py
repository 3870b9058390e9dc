"""The examples with complementary constraints, simulated, against
independent truths.

* Pendulum with the rod's tension (examples/pendulum_tension.toml): the motion is the
  simple pendulum's (examples/simple_pendulum.toml, in the angle θ, a different
  formulation), and T = m (g cos θ + l θ̇²) > 0 along it.
* Disk rolling down an incline: x = ⅓ g sin α t², friction force ⅓ m g sin α up the slope.
* Rolling upright coin: ψ̇ and φ̇ constant, G on a circle of radius r φ̇ / ψ̇ (closed form),
  lateral friction force m (r φ̇) ψ̇ towards the centre.
* Top with R_O from the multipliers: the Euler angles follow the principal top's motion
  (examples/lagrange_top.toml) and R_O equals the resultant-theorem value m γ(G) − P
  computed by `lagrangian.analysis.reaction_history` from that motion.

Errors are measured against the integrator's tolerances (rtol = atol = 1e-10 by default):
a multiple of 1e-8 leaves room for the error accumulated over the run.
"""

from __future__ import annotations

import functools

import numpy as np
import pytest
from lagrangian_test_support import EXAMPLES_DIR

import lagrangian
from lagrangian.analysis import reaction_history
from lagrangian.numerics import simulate

#: Global error allowed after a run at rtol = atol = 1e-10 (a few hundred steps).
GLOBAL = 1e-8


@functools.cache
def run(name: str, t_end: float = 2.0, n_out: int = 201):  # type: ignore[no-untyped-def]
    eom = lagrangian.derive(lagrangian.load_model(EXAMPLES_DIR / name))
    return eom, simulate(eom, t_end, n_out=n_out)


def parameter(name: str, key: str) -> float:
    model = lagrangian.load_model(EXAMPLES_DIR / name)
    return float(model.parameter_values[key])  # type: ignore[arg-type]


def test_pendulum_in_cartesian_coordinates_follows_the_simple_pendulum() -> None:
    _, traj = run("pendulum_tension.toml")
    _, angle = run("simple_pendulum.toml")
    l = parameter("pendulum_tension.toml", "l")
    x, y = traj.q.T
    theta = np.arctan2(x, -y)
    assert np.allclose(theta, angle.q[:, 0], rtol=0, atol=GLOBAL)
    assert np.allclose(np.hypot(x, y), l, rtol=0, atol=1e-12)


def test_pendulum_tension_is_the_closed_form_and_positive() -> None:
    _, traj = run("pendulum_tension.toml")
    m, g, l = (parameter("pendulum_tension.toml", k) for k in ("m", "g", "l"))
    x, y = traj.q.T
    xd, yd = traj.qd.T
    theta = np.arctan2(x, -y)
    theta_dot = (x * yd - y * xd) / l**2
    expected = m * (g * np.cos(theta) + l * theta_dot**2)
    R = np.column_stack([traj.extra["R_length_x0"], traj.extra["R_length_y0"]])
    tension = -(R[:, 0] * x + R[:, 1] * y) / l  # the rod pulls P towards O
    assert np.all(tension > 0)
    assert np.allclose(tension, expected, rtol=GLOBAL, atol=0)
    assert np.allclose(tension, -2 * l * traj.extra["lambda_length"], rtol=1e-12)


def test_disk_rolls_down_with_two_thirds_of_g_sin_alpha() -> None:
    _, traj = run("rolling_disk_incline.toml")
    m, g, r, alpha = (parameter("rolling_disk_incline.toml", k) for k in ("m", "g", "r", "alpha"))
    a = 2 / 3 * g * np.sin(alpha)
    assert np.allclose(traj.qdd[:, 0], a, rtol=1e-12)
    assert np.allclose(traj.q[:, 0], a * traj.t**2 / 2, rtol=0, atol=GLOBAL)
    assert np.allclose(traj.q[:, 1], traj.q[:, 0] / r, rtol=0, atol=GLOBAL)  # no slip: x = r φ
    friction = traj.extra["R_rolling_x1"]  # along x1, down the slope
    assert np.allclose(friction, -m * g * np.sin(alpha) / 3, rtol=1e-12)
    assert np.all(traj.extra["R_rolling_z1"] == 0)  # the normal reaction is principal here


def test_rolling_coin_runs_on_its_circle() -> None:
    _, traj = run("rolling_coin.toml")
    m, r = (parameter("rolling_coin.toml", k) for k in ("m", "r"))
    model = lagrangian.load_model(EXAMPLES_DIR / "rolling_coin.toml")
    c = {k.name: k for k in model.coordinates}
    psi0, psid, phid = c["psi"].initial, c["psi"].rate, c["phi"].rate
    x0, y0 = c["x"].initial, c["y"].initial
    v = r * phid
    radius = v / psid
    t = traj.t
    assert np.allclose(traj.qd[:, 2], psid, rtol=1e-12) and np.allclose(traj.qd[:, 3], phid, rtol=1e-12)
    x = x0 + radius * (np.sin(psi0 + psid * t) - np.sin(psi0))
    y = y0 - radius * (np.cos(psi0 + psid * t) - np.cos(psi0))
    assert np.allclose(traj.q[:, 0], x, rtol=0, atol=GLOBAL)
    assert np.allclose(traj.q[:, 1], y, rtol=0, atol=GLOBAL)
    centre = np.array([x0 - radius * np.sin(psi0), y0 + radius * np.cos(psi0)])
    assert np.allclose(np.hypot(traj.q[:, 0] - centre[0], traj.q[:, 1] - centre[1]), radius, atol=GLOBAL)
    # Friction: none along the heading, m v ψ̇ across it (towards the centre: +y1 for ψ̇ > 0).
    assert np.allclose(traj.extra["R_rolling_x1"], 0, atol=1e-12)
    assert np.allclose(traj.extra["R_rolling_y1"], m * v * psid, rtol=1e-9)
    assert traj.drift["drift_rolling_x1_dot"] < 1e-12 and traj.drift["drift_rolling_y1_dot"] < 1e-12
    assert traj.drift["E"] < 1e-9


@pytest.mark.slow
def test_top_with_the_pivot_complementary_moves_as_the_seed_top_and_gives_R_O() -> None:
    _, traj = run("top_reaction.toml", 1.0, 201)
    principal, angles = run("lagrange_top.toml", 1.0, 201)
    assert np.allclose(traj.q[:, 3:], angles.q, rtol=0, atol=GLOBAL)
    assert np.allclose(traj.qd[:, 3:], angles.qd, rtol=0, atol=1e-6)  # rates: the top spins at 50 rad/s
    R_O = reaction_history(principal, angles)["R_O"].force  # m γ(G) − P from the Euler-angle motion
    ours = np.column_stack([traj.extra[f"R_pivot_{a}"] for a in ("x0", "y0", "z0")])
    scale = np.max(np.abs(R_O))
    assert np.allclose(ours, R_O, rtol=0, atol=1e-8 * scale)
    # And from this trajectory's own G: m γ(G) − P, with P = −m g z0.
    m, g = parameter("top_reaction.toml", "m"), parameter("top_reaction.toml", "g")
    assert np.allclose(ours, m * traj.qdd[:, :3] + [0.0, 0.0, m * g], rtol=0, atol=1e-10 * scale)
    assert traj.drift["drift_pivot_z0"] < 1e-12 and traj.drift["E"] < 1e-9


@pytest.mark.parametrize("name", ["pendulum_tension.toml", "rolling_disk_incline.toml", "rolling_coin.toml",
                                  "top_reaction.toml"])
def test_every_constraint_holds_along_the_run(name: str) -> None:
    eom, traj = run(name) if name != "top_reaction.toml" else run(name, 1.0, 201)
    rows = [r.name for r in eom.constraints]
    assert rows
    for row in rows:
        assert traj.drift[f"drift_{row}_dot"] < 1e-12, row
        if f"drift_{row}" in traj.drift:
            assert traj.drift[f"drift_{row}"] < 1e-12, row
