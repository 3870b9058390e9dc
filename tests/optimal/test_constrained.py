"""A model with a complementary constraint: its multiplier is a decision variable, and its optimum is the
optimum of the same system written without the constraint.

The pendulum in Cartesian coordinates (x, y), the rod kept as the complementary constraint
x² + y² − l² = 0 with its multiplier λ, against the pendulum in its angle θ: the same motion
problem (from hanging at rest to θ = 1 rad at rest in 2 s, least ∫F² dt, F horizontal on the bob).
The rod's tension by hand, along r̂ = OP/l = (sin θ, −cos θ): the bob's radial acceleration is
−l θ̇², its weight gives m g cos θ, the force F sin θ, the rod −T_rod, so T_rod = m l θ̇² + m g cos θ
+ F sin θ; the rod's reaction is λ ∇f = 2λ l r̂ = −T_rod r̂.
"""

import numpy as np
import pytest

pytest.importorskip("casadi")

import lagrangian
from lagrangian.errors import ProblemError
from lagrangian.model import parse_model
from lagrangian.optimal import optimize

COMMON = """
[parameters]
m = 1.0
l = 0.5
g = 9.81
[inputs]
F = {}
[loads]
weight = { gravity = "-g*R0.y" }
push = { force = "F*R0.x", at = "P" }
"""
CARTESIAN = COMMON + """
[model]
name = "Pendulum in Cartesian coordinates"
[coordinates]
x = { initial = 0.0, rate = 0.0 }
y = { initial = -0.5, rate = 0.0 }
[particles.P]
mass = "m"
position = "x*R0.x + y*R0.y"
[constraints]
length = { holonomic = "x^2 + y^2 - l^2" }
"""
ANGLE = COMMON + """
[model]
name = "Pendulum"
[coordinates]
theta = { initial = 0.0, rate = 0.0 }
[frames]
R1 = { from = "R0", rotation = ["theta", "z"] }
[particles.P]
mass = "m"
position = "-l*R1.y"
"""
M, L, G, N = 1.0, 0.5, 9.81, 40
X_END = L * np.sin(1.0)


@pytest.fixture(scope="module")
def cartesian():
    return lagrangian.derive(parse_model(CARTESIAN))


@pytest.fixture(scope="module")
def constrained_optimum(cartesian):
    return optimize(cartesian, t_end=2.0, initial={"x": 0, "x_dot": 0}, final={"x": X_END, "x_dot": 0}, nodes=N,
                    guess={"y": -L})


@pytest.mark.slow
def test_the_constrained_optimum_is_the_angle_models(constrained_optimum):
    angle = optimize(lagrangian.derive(parse_model(ANGLE)), t_end=2.0, initial={"theta": 0, "theta_dot": 0},
                     final={"theta": 1.0, "theta_dot": 0}, nodes=N)
    best = constrained_optimum
    assert best.status == "optimal" and angle.status == "optimal"
    # Two transcriptions of one continuous problem, both fourth order: they agree to the mesh's accuracy
    assert best.objective == pytest.approx(angle.objective, rel=2e-4)
    assert best.q[0] == pytest.approx([0.0, -L]) and best.q[-1][1] == pytest.approx(-L * np.cos(1.0), abs=1e-4)


@pytest.mark.slow
def test_the_multiplier_is_the_rods_tension(constrained_optimum):
    best = constrained_optimum
    x, y = best.q.T
    xd, yd = best.qd.T
    theta = np.arctan2(x, -y)
    theta_dot = (x * yd - y * xd) / L ** 2
    tension = M * L * theta_dot ** 2 + M * G * np.cos(theta) + best.column("F") * np.sin(theta)
    lam = best.column("lambda_length")
    assert np.max(np.abs(lam + tension / (2 * L))) < 2e-3 * np.max(np.abs(lam))


def test_the_constraint_drift_is_reported_and_small(constrained_optimum):
    drift = constrained_optimum.drift
    assert set(drift) == {"drift_length", "drift_length_dot"}
    assert drift["drift_length"] < 1e-4 and drift["drift_length_dot"] < 1e-3
    assert constrained_optimum.replay.within


def test_a_full_initial_state_is_checked_against_the_constraint(cartesian):
    best = optimize(cartesian, t_end=2.0, initial={"x": 0, "x_dot": 0, "y": -L, "y_dot": 0},
                    final={"x": X_END, "x_dot": 0}, nodes=20, verify=False)
    assert best.status == "optimal"
    with pytest.raises(ProblemError, match="break the complementary constraints"):
        optimize(cartesian, t_end=2.0, initial={"x": 0.1, "x_dot": 0, "y": -L, "y_dot": 0},
                 final={"x": X_END}, nodes=20, verify=False)
    with pytest.raises(ProblemError, match="independent coordinates"):
        optimize(cartesian, t_end=2.0, initial={"x": 0, "x_dot": 0},
                 final={"x": X_END, "x_dot": 0, "y": -L * np.cos(1.0), "y_dot": 0}, nodes=20, verify=False)
