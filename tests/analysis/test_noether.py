"""First integrals from symmetries (Noether) and the constant speeds of nonholonomic models, against
closed forms: σ_O = Π_O Ω of a free rigid body, the total momentum of two particles, the rolling coin."""

from __future__ import annotations

import math

import numpy as np
import pytest
import symengine as se
from lagrangian_test_support import EXAMPLES_DIR

import lagrangian
from lagrangian.model import parse_model

FREE_BODY = """
[model]
name = "Free rigid body about a fixed point (Euler–Poinsot)"
[parameters]
A = 0.02
B = 0.03
C = 0.05
m = 1.0
[coordinates]
psi = {}
theta = {}
phi = {}
[frames]
R1 = { from = "R0", rotation = ["psi", "z"] }
R2 = { from = "R1", rotation = ["theta", "x"] }
R = { from = "R2", rotation = ["phi", "z"] }
[bodies.S]
frame = "R"
mass = "m"
center = "0*R.z"
fixed_point = "O"
inertia = { at = "O", frame = "R", diagonal = ["A", "B", "C"] }
"""

TWO_PARTICLES = """
[model]
name = "Two particles joined by a spring, in a plane, no gravity"
[parameters]
m1 = 1.0
m2 = 2.0
k = 10.0
l0 = 0.5
[coordinates]
x1 = {}
y1 = {}
x2 = {}
y2 = {}
[points]
P1 = "x1*R0.x + y1*R0.y"
P2 = "x2*R0.x + y2*R0.y"
[particles.a]
mass = "m1"
position = "x1*R0.x + y1*R0.y"
[particles.b]
mass = "m2"
position = "x2*R0.x + y2*R0.y"
[loads]
spring = { spring = ["P1", "P2"], stiffness = "k", rest_length = "l0" }
"""


def _euler_sigma(state: dict[str, float], A: float, B: float, C: float) -> np.ndarray:
    """σ_O = Π_O Ω in R0 for Euler angles (z, x, z): Ω in the body basis, then P = Rz(ψ) Rx(θ) Rz(φ)."""
    psi, theta, phi = state["psi"], state["theta"], state["phi"]
    pd, td, fd = state["psi_dot"], state["theta_dot"], state["phi_dot"]
    w = np.array([pd * math.sin(theta) * math.sin(phi) + td * math.cos(phi),
                  pd * math.sin(theta) * math.cos(phi) - td * math.sin(phi),
                  pd * math.cos(theta) + fd])

    def rz(a):
        return np.array([[math.cos(a), -math.sin(a), 0], [math.sin(a), math.cos(a), 0], [0, 0, 1]])

    def rx(a):
        return np.array([[1, 0, 0], [0, math.cos(a), -math.sin(a)], [0, math.sin(a), math.cos(a)]])

    return rz(psi) @ rx(theta) @ rz(phi) @ (np.diag([A, B, C]) @ w)


@pytest.mark.slow
def test_free_rigid_body_keeps_all_three_components_of_its_angular_momentum():
    eom = lagrangian.derive(parse_model(FREE_BODY))
    integrals = {fi.name: fi for fi in lagrangian.first_integrals(eom)}
    assert {"sigma_O_x0", "sigma_O_y0", "E"} <= set(integrals)
    assert "sigma_O_z0" not in integrals  # σ_O·z0 is the momentum of ψ, already found
    assert integrals["sigma_O_x0"].kind == "symmetry" and "Noether" in integrals["sigma_O_x0"].reason
    psi_momentum = next(fi for fi in integrals.values() if fi.coordinate == "psi")
    rng = np.random.default_rng(4)
    for _ in range(5):
        state = dict(zip(["psi", "theta", "phi", "psi_dot", "theta_dot", "phi_dot"], rng.uniform(0.2, 1.4, 6), strict=True))
        subs = {se.Symbol(k): v for k, v in state.items()} | {se.Symbol(k): v for k, v in
                                                                 dict(A=0.02, B=0.03, C=0.05, m=1.0).items()}
        sigma = _euler_sigma(state, 0.02, 0.03, 0.05)
        got = [float(integrals[n].expression.subs(subs)) for n in ("sigma_O_x0", "sigma_O_y0")]
        got.append(float(psi_momentum.expression.subs(subs)))
        np.testing.assert_allclose(got, sigma, rtol=1e-12)


@pytest.mark.slow
def test_free_rigid_body_integrals_along_a_simulation():
    eom = lagrangian.derive(parse_model(FREE_BODY))
    traj = lagrangian.simulate(eom, 2.0, initial={"psi": 0.1, "theta": 0.8, "phi": 0.3, "psi_dot": 1.0,
                                                  "theta_dot": 2.0, "phi_dot": 3.0}, rtol=1e-11, atol=1e-12)
    for name in ("sigma_O_x0", "sigma_O_y0"):
        assert traj.drift[name] < 1e-9
        values = traj.monitors[name]
        assert np.ptp(values) < 1e-9 * np.abs(values).max()


def test_two_particles_keep_momentum_and_angular_momentum():
    eom = lagrangian.derive(parse_model(TWO_PARTICLES))
    integrals = {fi.name: fi for fi in lagrangian.first_integrals(eom)}
    assert {"P_x0", "P_y0", "sigma_O_z0", "E"} == set(integrals)
    x1, y1, x2, y2 = (se.Symbol(n) for n in ("x1", "y1", "x2", "y2"))
    xd1, yd1, xd2, yd2 = (se.Symbol(n + "_dot") for n in ("x1", "y1", "x2", "y2"))
    m1, m2 = 1.0, 2.0
    expected = {"P_x0": m1 * xd1 + m2 * xd2, "P_y0": m1 * yd1 + m2 * yd2,
                "sigma_O_z0": m1 * (x1 * yd1 - y1 * xd1) + m2 * (x2 * yd2 - y2 * xd2)}
    for name, closed in expected.items():
        diff = integrals[name].expression.subs({se.Symbol("m1"): m1, se.Symbol("m2"): m2}) - closed
        assert se.expand(diff) == 0


def test_gravity_breaks_the_horizontal_rotations_of_the_top():
    eom = lagrangian.derive(lagrangian.load_model(EXAMPLES_DIR / "lagrange_top.toml"))
    assert {fi.name for fi in lagrangian.first_integrals(eom)} == {"K", "H", "E"}


def test_rolling_coin_keeps_its_rolling_rate():
    """Upright coin: ψ̇ (the momentum of ψ) and φ̇ (from the reduced equations) are constant."""
    eom = lagrangian.derive(lagrangian.load_model(EXAMPLES_DIR / "rolling_coin.toml"))
    integrals = {fi.name: fi for fi in lagrangian.first_integrals(eom)}
    assert integrals["phi_dot"].kind == "nonholonomic"
    assert integrals["phi_dot"].expression == se.Symbol("phi_dot")
    traj = lagrangian.simulate(eom, 3.0)
    assert np.ptp(traj.qd[:, eom.coordinates.index("phi")]) < 1e-8
    assert np.ptp(traj.qd[:, eom.coordinates.index("psi")]) < 1e-8
    assert traj.drift["phi_dot"] < 1e-8
