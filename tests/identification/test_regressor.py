"""The inverse-dynamics regressor and its base parameters against Pinocchio, on the URDF arms.

Pinocchio's ``computeJointTorqueRegressor`` gives Y(q, q̇, q̈) with τ = Y π, π the ten standard
parameters of each joint's body (m, m c, I about the joint frame's origin, Pinocchio's order
m, mx, my, mz, Ixx, Ixy, Iyy, Ixz, Iyz, Izz): the columns of our regressor for a link read with
``inertial_parameters=True`` must be the same columns, and its base parameters the same numbers.
"""

import re
import warnings

import numpy as np
import pytest
from lagrangian_test_support import EXAMPLES_DIR
from urdf_robots import Peer, robot_data_file

import lagrangian
from lagrangian.identification import Regressor, base_parameters
from lagrangian.model.urdf import INERTIAL_PARAMETERS, inertial_parameter_names, parse_urdf, read_urdf

pin = pytest.importorskip("pinocchio", reason="Pinocchio (`pip install pin`) is the referee of these tests")

#: Our order of the ten parameters within Pinocchio's (m, mx, my, mz, Ixx, Ixy, Iyy, Ixz, Iyz, Izz).
PIN_ORDER = [INERTIAL_PARAMETERS.index(k) for k in ("m", "mx", "my", "mz", "Ixx", "Ixy", "Iyy", "Ixz", "Iyz", "Izz")]


def _panda() -> str | None:
    path = robot_data_file("panda_description/urdf/panda.urdf")
    if path is None:
        return None
    # the fingers welded shut: a 7-joint arm (a mimic joint has no standard regressor in Pinocchio)
    return re.sub(r"<mimic[^>]*/>", "", path.read_text()).replace('type="prismatic"', 'type="fixed"')


def _arm(name: str) -> str:
    if name == "rrr_arm":
        return (EXAMPLES_DIR / "rrr_arm.urdf").read_text()
    text = _panda()
    if text is None:
        pytest.skip("example-robot-data is not installed (pip install example-robot-data)")
    return text


class Arm:
    """Our regressor of every inertial parameter of an arm, and Pinocchio's, column for column."""

    def __init__(self, text: str) -> None:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            self.model = parse_urdf(text, inertial_parameters=True, damping=False)
        self.eom = lagrangian.derive(self.model)
        groups = inertial_parameter_names(self.model)
        self.fitted = [name for names in groups.values() for name in names]
        self.regressor = Regressor(self.eom, self.fitted)
        self.peer = Peer(pin, text, list(self.eom.coordinates))
        joints = read_urdf_text_joints(text)
        # Pinocchio's columns of the joint whose child link is each of our bodies, in our order
        self.columns = []
        for body in groups:
            joint = next(j for j, child in joints.items() if child == body)
            first = 10 * (self.peer.model.getJointId(joint) - 1)
            self.columns += [first + PIN_ORDER.index(k) for k in range(10)]
        self.values = np.array([self.model.parameter_values[name] for name in self.regressor.parameters])

    def ours(self, q, v, a):
        return self.regressor.evaluate(0.0, np.hstack([q, v]), a, self.values)

    def pinocchio(self, q, v, a):
        rows = []
        for qi, vi, ai in zip(q, v, a, strict=True):
            qp, vp = self.peer.state(qi, vi)
            ap = np.zeros(self.peer.model.nv)
            ap[self.peer.v_index] = ai
            Y = pin.computeJointTorqueRegressor(self.peer.model, self.peer.data, qp, vp, ap)
            rows.append(Y[np.ix_(self.peer.v_index, self.columns)])
        return np.array(rows)


def read_urdf_text_joints(text: str) -> dict[str, str]:
    """Joint name → child link, of the moving joints."""
    import tempfile
    from pathlib import Path

    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "robot.urdf"
        path.write_text(text)
        robot = read_urdf(path)
    return {name: j.child for name, j in robot.joints.items() if j.moves}


@pytest.fixture(scope="module", params=["rrr_arm", "panda"])
def arm(request):
    return Arm(_arm(request.param))


def _states(n, count, seed=0):
    rng = np.random.default_rng(seed)
    return rng.uniform(-2, 2, (count, n)), rng.uniform(-2, 2, (count, n)), rng.uniform(-2, 2, (count, n))


def test_regressor_columns_are_pinocchios(arm):
    q, v, a = _states(arm.regressor.n, 20)
    _, Y = arm.ours(q, v, a)
    Y_pin = arm.pinocchio(q, v, a)
    np.testing.assert_allclose(Y, Y_pin, atol=1e-11 * np.abs(Y_pin).max())


def test_regressor_times_the_files_parameters_is_pinocchios_inverse_dynamics(arm):
    # r(θ) = M q̈ − F with the inputs off is the torque that makes the motion: Pinocchio's rnea
    q, v, a = _states(arm.regressor.n, 10, seed=1)
    r, Y = arm.ours(q, v, a)
    theta = np.array([arm.model.parameter_values[name] for name in arm.fitted])
    tau = []
    for qi, vi, ai in zip(q, v, a, strict=True):
        qp, vp = arm.peer.state(qi, vi)
        ap = np.zeros(arm.peer.model.nv)
        ap[arm.peer.v_index] = ai
        tau.append(pin.rnea(arm.peer.model, arm.peer.data, qp, vp, ap)[arm.peer.v_index])
    np.testing.assert_allclose(r, tau, atol=1e-10 * np.abs(tau).max())
    np.testing.assert_allclose(Y @ theta, r, atol=1e-10 * np.abs(tau).max())  # r is Y θ: no term without θ


def test_linear_in_every_inertial_parameter(arm):
    assert arm.regressor.linear_in(arm.values, np.random.default_rng(3)) == []


def test_base_parameters_equal_those_of_pinocchios_regressor(arm):
    q, v, a = _states(arm.regressor.n, 12 * len(arm.fitted) // arm.regressor.n, seed=2)
    _, Y = arm.ours(q, v, a)
    base = base_parameters(Y.reshape(-1, len(arm.fitted)), arm.fitted)
    Y_pin = arm.pinocchio(q, v, a).reshape(-1, len(arm.fitted))
    norms = np.linalg.norm(Y_pin, axis=0)
    acting = norms > 1e-12 * norms.max()  # Pinocchio's zero columns hold round-off (1e-17)
    assert base.rank == np.linalg.matrix_rank(Y_pin[:, acting] / norms[acting], tol=1e-8)
    theta = np.array([arm.model.parameter_values[name] for name in arm.fitted])
    ours = base.matrix() @ theta
    # Pinocchio's regressor alone: the base parameters θ_b solve Y₁ θ_b = Y π over many states
    Y1 = Y_pin[:, list(base.independent)]
    theirs, *_ = np.linalg.lstsq(Y1, Y_pin @ theta, rcond=None)
    np.testing.assert_allclose(ours, theirs, rtol=1e-8, atol=1e-10 * np.abs(theirs).max())


def test_rrr_arm_base_parameters_are_the_grouping_rules_combinations():
    # Khalil & Dombre's grouping rules for revolute joints: the forearm's mass m acts through the elbow,
    # 0.5 m along the upper arm's x, as m d = 0.5 m on its first moment and m d² = 0.25 m on its inertias
    # about y and z; the waist turns about z0, so the column shows only Izz, with what the links above add.
    arm = Arm(_arm("rrr_arm"))
    combos = {}
    for seed in (4, 9):  # the combinations do not depend on the states sampled
        q, v, a = _states(3, 60, seed=seed)
        _, Y = arm.ours(q, v, a)
        combos[seed] = base_parameters(Y.reshape(-1, len(arm.fitted)), arm.fitted).combinations()
    assert combos[4] == combos[9]
    assert len(combos[4]) == 15
    for expected in ("Izz_column + Izz_upper_arm + 0.25 m_forearm + Izz_forearm", "mx_upper_arm + 0.5 m_forearm",
                     "Iyy_upper_arm + 0.25 m_forearm", "Ixx_upper_arm - Izz_upper_arm - 0.25 m_forearm",
                     "Ixy_upper_arm - 0.5 my_forearm", "Ixx_forearm - Izz_forearm", "Iyy_forearm"):
        assert expected in combos[4]
