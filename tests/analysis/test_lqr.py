"""The LQR state feedback: its gain against python-control, its closed loop, its file form, its refusals.

* K equals python-control's ``control.lqr`` on the same A, B, Q, R (an independent Riccati solver);
* the nonlinear closed loop of the cart-pole, compiled, brings θ = 0.2 rad back to upright;
* the closed loop's Jacobian at the point, by central differences of the compiled right-hand side
  (u = u* − K (x − x*) inside it), has the eigenvalues of A − B K;
* a pendulum held off its equilibrium by a torque: u* = m g l sin θ*, written out;
* an uncontrollable pair is refused, naming the mode the input cannot move.
"""

from __future__ import annotations

import math

import control
import numpy as np
import pytest

import lagrangian
from lagrangian.analysis import ControlError, Feedback, lqr
from lagrangian.numerics import compile_system, simulate

CART_POLE = "examples/inverted_pendulum_cart.toml"


@pytest.fixture(scope="module")
def cart_pole() -> lagrangian.EquationsOfMotion:
    return lagrangian.derive(lagrangian.load_model(CART_POLE))


@pytest.fixture(scope="module")
def feedback(cart_pole) -> Feedback:
    return lqr(cart_pole, {"x": 0, "theta": 0}, Q={"theta": 10, "x": 2}, R=0.5)


def test_the_gain_equals_python_controls(feedback):
    K, _, E = control.lqr(feedback.A, feedback.B, feedback.Q, feedback.R)
    assert np.allclose(feedback.K, K, rtol=1e-9, atol=1e-12)
    assert np.allclose(np.sort_complex(feedback.eigenvalues), np.sort_complex(E), rtol=1e-9)
    assert feedback.stable


def test_the_furuta_pendulums_gain_equals_python_controls():
    fb = lqr("examples/furuta_pendulum.toml", Q=[1, 20, 1, 1], R=[[50.0]])
    assert fb.states == ("phi", "alpha", "phi_dot", "alpha_dot") and fb.x_star[1] == pytest.approx(math.pi)
    K, _, _ = control.lqr(fb.A, fb.B, fb.Q, fb.R)
    assert np.allclose(fb.K, K, rtol=1e-9, atol=1e-12)


def test_the_cart_poles_linearization_is_the_textbook_one(feedback, cart_pole):
    # θ̈ = (mc + m) g θ/(mc l) − F/(mc l), ẍ = −m g θ/mc + F/mc (the model file's comment, by hand)
    mc, m, l, g = (cart_pole.model.parameter_values[k] for k in ("mc", "m", "l", "g"))
    A = np.zeros((4, 4))
    A[0, 2] = A[1, 3] = 1
    A[2, 1], A[3, 1] = -m * g / mc, (mc + m) * g / (mc * l)
    B = np.array([[0], [0], [1 / mc], [-1 / (mc * l)]])
    assert np.allclose(feedback.A, A) and np.allclose(feedback.B, B)


@pytest.mark.parametrize("Q", [{"theta": 10, "x": 2}, [2, 10, 1, 1], np.diag([2.0, 10, 1, 1])])
def test_weights_by_name_by_diagonal_or_as_a_matrix_are_the_same(cart_pole, feedback, Q):
    assert np.allclose(lqr(cart_pole, {"x": 0, "theta": 0}, Q=Q, R={"F": 0.5}).K, feedback.K, rtol=1e-12)


def test_the_nonlinear_closed_loop_brings_the_pendulum_back_upright(cart_pole, feedback):
    traj = simulate(cart_pole, 15.0, inputs=feedback, initial={"theta": 0.2}, n_out=151)
    assert np.abs(traj.q[-1]).max() < 1e-3 and np.abs(traj.qd[-1]).max() < 1e-3
    assert np.abs(traj.q[:, 1]).max() == pytest.approx(0.2)  # it never falls further than it started
    # the force applied is the law's, at every output
    x = np.column_stack([traj.q, traj.qd])
    assert np.allclose(traj.column("F"), feedback(x)[:, 0], rtol=0, atol=1e-12)


def test_the_closed_loops_jacobian_has_the_eigenvalues_of_a_minus_bk(cart_pole, feedback):
    system = compile_system(cart_pole, inputs=feedback)
    p = system.parameter_vector()
    y0 = np.zeros(4)
    h = math.sqrt(np.finfo(float).eps)
    J = np.column_stack([(system.rhs(0.0, y0 + h * e, p) - system.rhs(0.0, y0 - h * e, p)) / (2 * h)
                         for e in np.eye(4)])
    expected = np.sort_complex(np.linalg.eigvals(feedback.A - feedback.B @ feedback.K))
    assert np.allclose(np.sort_complex(np.linalg.eigvals(J)), expected, rtol=1e-6, atol=1e-6)
    assert np.allclose(np.sort_complex(feedback.eigenvalues), expected, rtol=1e-12)


HELD_PENDULUM = """
[model]
name = "pendulum with a motor"

[parameters]
m = 0.5
l = 0.8
g = 9.81

[inputs]
tau = { unit = "N*m" }

[coordinates]
theta = { initial = 0.35, rate = 0.0 }

[frames]
R1 = { from = "R0", rotation = ["theta", "z"] }

[particles.P]
mass = "m"
position = "l*R1.x"

[loads]
weight = { gravity = "g*R0.x" }
motor = { torque = "tau*R0.z", on = "R1" }
"""


def test_a_point_held_by_the_input_uses_the_holding_torque():
    eom = lagrangian.derive(lagrangian.parse_model(HELD_PENDULUM))
    fb = lqr(eom, {"theta": 0.3}, Q={"theta": 100})
    assert fb.u_star[0] == pytest.approx(0.5 * 9.81 * 0.8 * math.sin(0.3), rel=1e-12)  # m g l sin θ*
    # m l² θ̈ = −m g l sin θ + τ: A, B at θ* by hand
    assert np.allclose(fb.A, [[0, 1], [-9.81 * math.cos(0.3) / 0.8, 0]])
    assert np.allclose(fb.B, [[0], [1 / (0.5 * 0.8 ** 2)]])
    traj = simulate(eom, 8.0, inputs=fb, n_out=81)
    assert traj.q[-1, 0] == pytest.approx(0.3, abs=1e-6)


TWO_CARTS = """
[model]
name = "two carts"

[parameters]
m = 1.0

[inputs]
F = {}

[coordinates]
x1 = { initial = 0.0 }
x2 = { initial = 0.0 }

[particles.A]
mass = "m"
position = "x1*R0.x"

[particles.B]
mass = "m"
position = "x2*R0.y"

[loads]
push = { force = "F*R0.x", at = "A" }
"""


def test_an_uncontrollable_pair_is_refused_naming_the_mode():
    eom = lagrangian.derive(lagrangian.parse_model(TWO_CARTS))
    with pytest.raises(ControlError, match=r"not stabilizable: the mode λ = 0 \(in x2, x2_dot\) is not moved by the inputs F"):
        lqr(eom, {"x1": 0, "x2": 0})


@pytest.mark.parametrize(("kwargs", "message"), [
    ({"Q": {"phi": 1}}, "`phi` in Q is not one of its names"),
    ({"Q": [1, 2]}, "Q has shape \\(2,\\); it must be 4×4"),
    ({"Q": [[1, 2, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]]}, "Q is not symmetric"),
    ({"Q": {"x": -1}}, "positive semidefinite"),
    ({"R": 0}, "R must be positive definite"),
    ({"Q": {"x": math.nan}}, "not finite"),
])
def test_bad_weights_are_refused_clearly(cart_pole, kwargs, message):
    with pytest.raises(ControlError, match=message):
        lqr(cart_pole, {"x": 0, "theta": 0}, **kwargs)


def test_a_model_without_inputs_is_refused():
    with pytest.raises(ControlError, match="declares no input"):
        lqr("examples/simple_pendulum.toml", {"theta": 0})


def test_the_feedback_file_round_trips(tmp_path, feedback):
    path = feedback.save(tmp_path / "fb.json")
    back = Feedback.load(path)
    for name in ("K", "x_star", "u_star", "A", "B", "Q", "R", "eigenvalues"):
        assert np.array_equal(getattr(back, name), getattr(feedback, name))
    assert back.states == feedback.states and back.inputs == feedback.inputs
    assert not list(tmp_path.glob(".fb.json.*"))  # written atomically: no temporary file left
    path.write_text('{"schema": "lagrangian.feedback", "version": 7}')
    with pytest.raises(ControlError, match="version 7"):
        Feedback.load(path)
    path.write_text("{not json")
    with pytest.raises(ControlError, match="is not JSON"):
        Feedback.load(path)
    doc = feedback.to_dict()
    doc["K"] = [[1.0, 2.0]]
    with pytest.raises(ControlError, match=r"`K` of the feedback has shape \(1, 2\), expected \(1, 4\)"):
        Feedback.from_dict(doc)


def test_about_a_steady_motion_the_reference_advances_with_it():
    # The Furuta arm spinning at Ω with the pendulum hanging (α = 0): φ is absent from the equations,
    # so this is a steady motion; the law regulates about φ*(t) = φ0 + Ω t, not about φ0.
    eom = lagrangian.derive(lagrangian.load_model("examples/furuta_pendulum.toml"))
    omega = 2.0
    fb = lqr(eom, {"phi": 0, "alpha": 0, "phi_dot": omega}, Q={"phi": 1, "alpha": 10}, R=1e5)
    assert fb.x_star_rate.tolist() == [omega, 0, 0, 0] and fb.u_star[0] == pytest.approx(0, abs=1e-15)
    K, _, _ = control.lqr(fb.A, fb.B, fb.Q, fb.R)
    assert np.allclose(fb.K, K, rtol=1e-9, atol=1e-12)
    traj = simulate(eom, 20.0, inputs=fb, initial={"phi": 0.0, "alpha": 0.3, "phi_dot": omega}, n_out=201)
    assert abs(traj.qd[-1, 0] - omega) < 1e-4 and abs(traj.q[-1, 1]) < 1e-4
    assert abs(traj.q[-1, 0] - omega * traj.t[-1]) < 1e-3  # back on φ*(t)
    x = np.column_stack([traj.q, traj.qd])
    assert np.allclose(traj.column("tau"), fb(x, traj.t)[:, 0], rtol=0, atol=1e-12)
