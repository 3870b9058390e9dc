"""Linearizing about a point held by nonzero inputs (a robot's gravity-compensating torques).

A and B at (q0, 0, u0) are checked against central differences of the compiled right-hand
side, and, on a URDF arm, against Pinocchio's `computeABADerivatives` (∂q̈/∂q, ∂q̈/∂v, M⁻¹)
and the torques against its `computeGeneralizedGravity`.
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest
from urdf_robots import DOUBLE_PENDULUM, SPATIAL_ARM, Peer

import lagrangian
from lagrangian.analysis import LinearizationError, holding_inputs
from lagrangian.cli.main import main
from lagrangian.model.urdf import UrdfNote, parse_urdf
from lagrangian.model.zoo import serial_arm
from lagrangian.numerics import compile_system


def _urdf(text: str) -> lagrangian.Model:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UrdfNote)
        return parse_urdf(text, source="robot.urdf", damping=False)


def _finite_differences(eom, q0, u0: dict, h: float = 1e-6) -> tuple[np.ndarray, np.ndarray]:
    system = compile_system(eom)
    n = len(q0)
    inputs = list(eom.model.inputs)

    def f(x, u):
        return system.rhs(0.0, x, system.parameter_vector(dict(zip(inputs, u, strict=True))))

    x0, uu = np.concatenate([q0, np.zeros(n)]), np.array([u0[k] for k in inputs])
    A = np.column_stack([(f(x0 + h * e, uu) - f(x0 - h * e, uu)) / (2 * h) for e in np.eye(2 * n)])
    B = np.column_stack([(f(x0, uu + h * e) - f(x0, uu - h * e)) / (2 * h) for e in np.eye(len(uu))])
    assert np.abs(f(x0, uu)).max() < 1e-9  # held: q̈ = 0 at the point
    return A, B


def test_a_and_b_at_nonzero_torques_are_the_compiled_rhs_derivatives():
    eom = lagrangian.derive(serial_arm(4))
    q0 = np.array([0.3, -0.4, 0.7, 0.2])
    at = {f"q{k + 1}": float(v) for k, v in enumerate(q0)}
    tau = holding_inputs(eom, at)
    assert np.abs(list(tau.values())).max() > 1.0  # gravity needs real torques there
    lin = lagrangian.linearize(eom, {**at, **tau})
    assert {k: float(lin.point[k]) for k in tau} == pytest.approx(tau)
    A, B = lin.numeric()
    A_fd, B_fd = _finite_differences(eom, q0, tau)
    np.testing.assert_allclose(A, A_fd, rtol=1e-6, atol=1e-6 * np.abs(A_fd).max())
    np.testing.assert_allclose(B, B_fd, rtol=1e-6, atol=1e-6 * np.abs(B_fd).max())
    with pytest.raises(LinearizationError, match="not an equilibrium"):
        lagrangian.linearize(eom, at)  # the same point without its torques falls


def test_held_urdf_arm_is_pinocchios_aba_derivatives_and_gravity():
    pin = pytest.importorskip("pinocchio", reason="Pinocchio is the referee")
    model = _urdf(SPATIAL_ARM)
    eom = lagrangian.derive(model)
    q0 = np.array([0.4, -0.6, 0.9, 0.05])
    at = dict(zip(eom.coordinates, map(float, q0), strict=True))
    tau = holding_inputs(eom, at)
    peer = Peer(pin, SPATIAL_ARM, list(eom.coordinates))
    qp, vp = peer.state(q0, np.zeros(len(q0)))
    gravity = pin.computeGeneralizedGravity(peer.model, peer.data, qp)[peer.v_index]
    np.testing.assert_allclose([tau[k] for k in model.inputs], gravity, rtol=1e-10, atol=1e-10)
    lin = lagrangian.linearize(eom, {**at, **tau})
    A, B = lin.numeric()
    torque = np.zeros(peer.model.nv)
    torque[peer.v_index] = gravity
    pin.computeABADerivatives(peer.model, peer.data, qp, vp, torque)
    idx = np.ix_(peer.v_index, peer.v_index)
    n = len(q0)
    minv = np.triu(peer.data.Minv) + np.triu(peer.data.Minv, 1).T
    np.testing.assert_allclose(A[n:, :n], peer.data.ddq_dq[idx], rtol=1e-9, atol=1e-9)
    np.testing.assert_allclose(A[n:, n:], peer.data.ddq_dv[idx], rtol=1e-9, atol=1e-9)
    np.testing.assert_allclose(B[n:], minv[idx], rtol=1e-9, atol=1e-9)


def test_cli_hold_and_input_values_at_the_point(tmp_path, capsys):
    path = tmp_path / "pendulum.urdf"
    path.write_text(DOUBLE_PENDULUM)
    assert main(["linearize", str(path), "--at", "shoulder=0.5", "--at", "elbow=0.3", "--hold"]) == 0
    out = capsys.readouterr().out
    assert "tau_shoulder = 8.366" in out and "inputs u = (tau_shoulder, tau_elbow)" in out
    # the same torques given by hand: the same point; one missing: not an equilibrium (exit 2... with the residual)
    eom = lagrangian.derive(lagrangian.load_urdf(path))
    tau = holding_inputs(eom, {"shoulder": 0.5, "elbow": 0.3})
    argv = ["linearize", str(path), "--at", "shoulder=0.5", "--at", "elbow=0.3",
            "--at", f"tau_shoulder={tau['tau_shoulder']!r}", "--at", f"tau_elbow={tau['tau_elbow']!r}"]
    assert main(argv) == 0 and capsys.readouterr().out == out
    assert main(argv[:-2]) != 0
    assert "not an equilibrium" in capsys.readouterr().err


def test_no_torque_holds_an_unactuated_joint_away_from_equilibrium():
    model = _urdf(DOUBLE_PENDULUM)
    eom = lagrangian.derive(model)
    with pytest.raises(LinearizationError, match="no values of the inputs tau_shoulder hold the point"):
        holding_inputs(eom, {"shoulder": 0.5, "elbow": 0.3, "tau_elbow": 0.0}, inputs=["tau_shoulder"])


def test_a_point_held_by_computed_torques_shows_no_rounding_as_circulatory_forces() -> None:
    # The held point's K is numeric; its skew part N was 1e-16 entries of rounding (examples/rrr_arm.urdf).
    from pathlib import Path

    root = Path(__file__).resolve().parents[2]
    eom = lagrangian.derive(lagrangian.load_model(root / "examples" / "rrr_arm.urdf"))
    at = {"waist": 0.0, "shoulder": 0.5, "elbow": -0.3}
    lin = lagrangian.linearize(eom, {**at, **lagrangian.holding_inputs(eom, at)})
    N = lin.second_order.N
    assert all(N[i, j] == 0 for i in range(N.rows) for j in range(N.cols))
    K = lin.second_order.K
    assert float(K[1, 1]) > 0 and float(K[1, 2]) == float(K[2, 1])
