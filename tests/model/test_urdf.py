"""URDF robots: our M, q̈, T and U against Pinocchio's crba, aba and energies on the same file.

Pinocchio reads the URDF with its own parser (urdfdom) and computes the dynamics by the
recursive algorithms (CRBA, ABA); ours come from Lagrange's equations of the model that
`load_urdf` declares.  They agree to rounding at random states (1e-10 asked).
"""

from __future__ import annotations

import warnings
from pathlib import Path

import numpy as np
import pytest
from urdf_robots import DOUBLE_PENDULUM, SPATIAL_ARM, TREE, Ours, Peer, robot_data_file

import lagrangian
from lagrangian.model.urdf import UrdfNote, parse_urdf, read_urdf, rotation_steps, rpy_matrix

pin = pytest.importorskip("pinocchio", reason="Pinocchio (`pip install pin`) is the referee of these tests")

TOL = 1e-10


def _model(text: str, **kw) -> lagrangian.Model:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UrdfNote)
        return parse_urdf(text, source="robot.urdf", **kw)


def _compare(ours: Ours, peer: Peer, *, states: int = 4, seed: int = 0, damping=None) -> None:
    rng = np.random.default_rng(seed)
    n = ours.n
    for _ in range(states):
        q, v = rng.uniform(-1.2, 1.2, n), rng.uniform(-2, 2, n)
        np.testing.assert_allclose(ours.mass(q), peer.mass(q), rtol=TOL, atol=TOL)
        tau = None if damping is None else -damping * v  # aba has no joint damping: give it as τ
        np.testing.assert_allclose(ours.acceleration(q, v), peer.acceleration(q, v, tau), rtol=TOL, atol=TOL)


RRR_ARM = (Path(__file__).resolve().parents[2] / "examples" / "rrr_arm.urdf").read_text(encoding="utf-8")


@pytest.mark.parametrize("text", [DOUBLE_PENDULUM, SPATIAL_ARM, RRR_ARM],
                         ids=["double_pendulum", "spatial_arm", "example_rrr_arm"])
def test_mass_matrix_and_accelerations_are_pinocchios(text):
    ours = Ours(_model(text, damping=False))
    _compare(ours, Peer(pin, text, list(ours.eom.coordinates)))


def test_a_tree_with_fixed_prismatic_and_mimic_joints_is_pinocchios_with_mimic():
    ours = Ours(_model(TREE))
    assert ours.eom.coordinates == ("slide", "swing", "pinch")  # depth first; `pinch2` follows `pinch`
    assert {b.name for b in ours.model.bodies} == {"cart", "arm", "finger", "finger2"}  # tool merged into cart
    _compare(ours, Peer(pin, TREE, list(ours.eom.coordinates), mimic=True))


def test_joint_damping_is_a_rayleigh_function_and_torques_are_inputs():
    ours = Ours(_model(DOUBLE_PENDULUM))
    assert ours.model.inputs == ("tau_shoulder", "tau_elbow")
    peer = Peer(pin, DOUBLE_PENDULUM, list(ours.eom.coordinates))
    _compare(ours, peer, damping=np.array([0.0, 0.2]))
    q, v, tau = np.array([0.3, -0.7]), np.array([1.1, 0.4]), np.array([2.5, -1.5])
    got = ours.acceleration(q, v, {"tau_shoulder": tau[0], "tau_elbow": tau[1]})
    np.testing.assert_allclose(got, peer.acceleration(q, v, tau - np.array([0, 0.2]) * v), rtol=TOL, atol=TOL)


def test_the_course_view_T_and_U_are_pinocchios_energies():
    ours = Ours(_model(SPATIAL_ARM))
    peer = Peer(pin, SPATIAL_ARM, list(ours.eom.coordinates))
    rng = np.random.default_rng(3)
    zero = None
    for _ in range(3):
        q, v = rng.uniform(-1, 1, 4), rng.uniform(-1, 1, 4)
        (t, u), (tp, up) = ours.energies(q, v), peer.energies(q, v)
        assert t == pytest.approx(tp, rel=TOL, abs=TOL)
        zero = u - up if zero is None else zero  # U is defined up to a constant
        assert u - up == pytest.approx(zero, abs=TOL)
    # the weight's U is found (exact numbers); the actuators' τ_i(t) are inputs, given non-conservative
    # efforts, so U is the weight's alone (T + U the mechanical energy) and there is no Lagrangian L
    used = {str(s) for s in ours.eom.U.free_symbols}
    assert "g" in used and not any(name.startswith("tau_") for name in used) and ours.eom.L is None


def test_linearization_B_is_the_inverse_mass_matrix_on_the_joints():
    model = _model(DOUBLE_PENDULUM)
    eom = lagrangian.derive(model)
    lin = lagrangian.linearize(eom, {"shoulder": 0, "elbow": 0})  # hanging down: an equilibrium
    peer = Peer(pin, DOUBLE_PENDULUM, list(eom.coordinates))
    minv = np.linalg.inv(peer.mass(np.zeros(2)))
    B = np.array(lin.B.tolist(), dtype=float)
    np.testing.assert_allclose(B, np.vstack([np.zeros((2, 2)), minv]), rtol=TOL, atol=TOL)
    assert tuple(lin.inputs) == ("tau_shoulder", "tau_elbow")


def test_without_gravity_every_configuration_linearizes_to_B_equal_M_inverse():
    eom = lagrangian.derive(_model(SPATIAL_ARM, damping=False))
    q = {"j1": 0.4, "j2": -0.3, "j3": 1.1, "j4": 0.05}
    lin = lagrangian.linearize(eom, q, parameters={"g": 0.0})
    peer = Peer(pin, SPATIAL_ARM, list(eom.coordinates))
    B = np.array(lin.B.tolist(), dtype=float)
    np.testing.assert_allclose(B[4:], np.linalg.inv(peer.mass(np.array(list(q.values())))), rtol=1e-9, atol=TOL)


def test_limits_are_recorded_and_skipped_elements_noted(tmp_path):
    path = tmp_path / "tree.urdf"
    path.write_text(TREE)
    robot = read_urdf(path)
    assert robot.joints["slide"].limits.upper == 1.0 and robot.joints["swing"].limits.effort == 10.0
    assert robot.root == "world" and robot.joints["pinch2"].mimic.multiplier == -0.5
    with pytest.warns(UrdfNote, match=r"tree.urdf:\d+: note: 1 <transmission> element skipped"):
        model = lagrangian.load_urdf(path)
    swing = model.coordinate("swing")
    assert swing.unit == "rad" and "limits [-1, 1] rad" in swing.description
    assert "effort ≤ 10 N·m" in swing.description
    assert model.coordinate("slide").unit == "m"
    with pytest.warns(UrdfNote):
        assert lagrangian.load_model(path) == model  # every path reader takes a .urdf


@pytest.mark.parametrize("rpy", [(0.0, 0.0, 0.0), (np.pi / 2, 0, 0), (0, -np.pi / 2, 0), (np.pi, 0, 0),
                                 (0.3, -0.2, 2.9), (0.1, np.pi / 2, 0.4), (-1.0, 0.5, -2.0)])
def test_constant_rotations_are_rebuilt_from_elementary_steps(rpy):
    target = rpy_matrix(rpy)
    out = np.eye(3)
    for angle, axis in rotation_steps(target):
        out = out @ pin.utils.rotate(axis, float(angle))  # Pinocchio's elementary rotation, independent of ours
    np.testing.assert_allclose(out, target, atol=1e-14)


# -- robots of example-robot-data -----------------------------------------------------------------------------------
@pytest.mark.parametrize("relative, mimic", [
    ("double_pendulum_description/urdf/double_pendulum.urdf", False),
    ("ur_description/urdf/ur5_robot.urdf", False),
    ("panda_description/urdf/panda.urdf", True),
], ids=["double_pendulum", "ur5", "panda"])
def test_example_robot_data_robots_are_pinocchios(relative, mimic):
    path = robot_data_file(relative)
    if path is None:
        pytest.skip("example-robot-data is not installed (pip install example-robot-data)")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UrdfNote)
        model = lagrangian.load_urdf(path, damping=False)
    ours = Ours(model)
    _compare(ours, Peer(pin, path.read_text(), list(ours.eom.coordinates), mimic=mimic), states=2)
