"""`lagrangian.output.feedback_text`: what ``lagrangian lqr`` prints, read back and checked.

The gain printed row by row is python-control's `lqr` K on the cart-pole's A and B linearized by
hand below, and the closed-loop eigenvalues printed are python-control's; a feedback written by
hand (two inputs, a full Q) shows the layout of K's rows and the non-diagonal weights.
"""

from __future__ import annotations

import re

import control
import numpy as np
import pytest
from lagrangian_test_support import EXAMPLES_DIR

import lagrangian
from lagrangian.analysis import Feedback
from lagrangian.output import feedback_text

CART_POLE = EXAMPLES_DIR / "inverted_pendulum_cart.toml"


def _cart_pole_by_hand(mc: float, m: float, l: float, g: float) -> tuple[np.ndarray, np.ndarray]:
    """A, B of the cart-pole about upright, x = (x, θ, ẋ, θ̇).

    P = (x + l sin θ, l cos θ): T = ½ mc ẋ² + ½ m (ẋ² + 2 l cos θ ẋ θ̇ + l² θ̇²), U = m g l cos θ, so at
    θ = 0: M = [[mc + m, m l], [m l, m l²]], M q̈ = (F, m g l θ).
    """
    M = np.array([[mc + m, m * l], [m * l, m * l * l]])
    Minv = np.linalg.inv(M)
    A = np.zeros((4, 4))
    A[:2, 2:] = np.eye(2)
    A[2:, :2] = Minv @ np.array([[0.0, 0.0], [0.0, m * g * l]])
    B = np.zeros((4, 1))
    B[2:, 0] = Minv @ np.array([1.0, 0.0])
    return A, B


def _numbers(text: str) -> list[complex]:
    """``-5.35487, -0.765745 +0.489942i`` → the complex numbers, in order."""
    out = []
    for part in text.split(", "):
        m = re.fullmatch(r"(\S+) ([+-]\S+)i", part)
        out.append(complex(float(m[1]), float(m[2])) if m else complex(float(part)))
    return out


@pytest.fixture(scope="module")
def cart_pole():
    return lagrangian.derive(lagrangian.load_model(CART_POLE))


def test_the_printed_gain_and_eigenvalues_are_python_controls(cart_pole):
    fb = lagrangian.lqr(cart_pole, {"x": 0, "theta": 0}, Q={"theta": 10, "x": 2}, R=0.5)
    text = feedback_text(fb)
    values = cart_pole.model.parameter_values
    A, B = _cart_pole_by_hand(*(float(values[k]) for k in ("mc", "m", "l", "g")))
    K, _, E = control.lqr(A, B, np.diag([2.0, 10.0, 1.0, 1.0]), [[0.5]])
    lines = text.splitlines()
    assert lines[0] == "Inverted pendulum on a cart: LQR state feedback u = u* - K (x - x*)"
    assert lines[1:5] == ["point x*: x = 0, theta = 0, x_dot = 0, theta_dot = 0", "inputs u*: F = 0", "gain K:",
                          "  row of F:"]
    rows = [line.split() for line in lines[5:9]]
    assert [r[0] for r in rows] == ["x", "theta", "x_dot", "theta_dot"]
    assert np.allclose([float(r[1]) for r in rows], np.ravel(K), rtol=5e-6)  # printed to 6 digits
    assert lines[9] == "weights: Q = diag(x: 2, theta: 10, x_dot: 1, theta_dot: 1), R = diag(F: 0.5)"
    open_loop = _numbers(lines[10].removeprefix("open-loop eigenvalues (A): "))
    assert np.allclose(open_loop, sorted(np.linalg.eigvals(A), key=lambda z: z.real), rtol=5e-6, atol=1e-9)
    closed = _numbers(lines[11].removeprefix("closed-loop eigenvalues (A - B K): "))
    assert np.allclose(sorted(closed, key=lambda z: (z.real, z.imag)), sorted(E, key=lambda z: (z.real, z.imag)),
                       rtol=5e-6)
    assert lines[12] == "verdict: the closed loop is asymptotically stable about the point (linearized)"
    assert text.endswith("\n") and len(lines) == 13


def test_two_inputs_and_a_full_q_are_written_row_by_row_and_as_matrices():
    A = np.array([[0.0, 1.0], [2.0, 0.0]])  # x'' = 2 x + u1 + 3 u2: unstable, with two inputs
    B = np.array([[0.0, 0.0], [1.0, 3.0]])
    Q = np.array([[2.0, 0.5], [0.5, 1.0]])
    R = np.eye(2)
    K, _, _ = control.lqr(A, B, Q, R)
    fb = Feedback("by hand", ("x", "x_dot"), ("u1", "u2"), K, [0.25, 0.0], [-0.5, 0.0], A, B, Q, R)
    text = feedback_text(fb)
    lines = text.splitlines()
    assert lines[1] == "point x*: x = 0.25, x_dot = 0"
    assert lines[2] == "inputs u*: u1 = -0.5, u2 = 0"
    assert lines[4] == "  row of u1:" and lines[7] == "  row of u2:"
    assert lines[5] == f"    x      {K[0, 0]:.6g}" and lines[9] == f"    x_dot  {K[1, 1]:.6g}"
    assert "\nweights: Q = [[2.  0.5]\n [0.5 1. ]], R = [[1. 0.]\n [0. 1.]]\n" in text  # NumPy's own layout
    assert "open-loop eigenvalues (A): -1.41421, 1.41421" in lines
    assert lines[-1].startswith("verdict: the closed loop is asymptotically stable")


def test_an_unstable_closed_loop_is_said_so():
    A = np.array([[0.0, 1.0], [2.0, 0.0]])
    B = np.array([[0.0], [1.0]])
    fb = Feedback("zero gain", ("x", "x_dot"), ("u",), [[0.0, 0.0]], [0, 0], [0], A, B, np.eye(2), [[1.0]])
    assert feedback_text(fb).splitlines()[-1] == "verdict: NOT stable"
