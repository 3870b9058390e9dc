"""URDF floating and planar joints, and the floating base: against MuJoCo and Pinocchio's FreeFlyer.

A floating joint makes its child link a free body (`lagrangian.model._free`), integrated on a
unit quaternion (`numerics._free_system`); its state (r, e, q; v in R0, ω in the body, q̇) is
MuJoCo's free joint's, so q̈, M and the bias forces compare entry by entry.  Pinocchio's
FreeFlyer takes the linear velocity in the body's basis: v = R v_local, and its acceleration
is that of v_local, v̇ = R (a_local + ω ∧ v_local).
"""

from __future__ import annotations

import re

import numpy as np
import pytest

import lagrangian
from lagrangian.model.urdf import parse_urdf
from lagrangian.numerics import FreeBodySystem
from lagrangian.numerics._euler import matrix_from_quaternion, rate_matrix, rate_matrix_derivative

mujoco = pytest.importorskip("mujoco", reason="MuJoCo (`pip install mujoco`) is a referee of these tests")
pin = pytest.importorskip("pinocchio", reason="Pinocchio (`pip install pin`) is a referee of these tests")

from urdf_robots import robot_data_file

#: A base thrown with a two-link leg and an arm: rpy origins, full inertias off the joint axes, a general
#: axis, a continuous joint about −z; the floating joint is placed by its origin (where the base starts).
WALKER = """<?xml version="1.0"?>
<robot name="walker">
  <link name="world"/>
  <link name="base"><inertial><origin xyz="0.02 -0.01 0.03" rpy="0.1 0.2 0.3"/><mass value="3"/>
    <inertia ixx="0.05" ixy="0.002" ixz="0.001" iyy="0.08" iyz="0.003" izz="0.07"/></inertial></link>
  <link name="thigh"><inertial><origin xyz="0 0 -0.1"/><mass value="0.6"/>
    <inertia ixx="0.004" ixy="0" ixz="0" iyy="0.004" iyz="0" izz="0.0005"/></inertial></link>
  <link name="shin"><inertial><origin xyz="0.01 0 -0.12" rpy="0 0.1 0"/><mass value="0.3"/>
    <inertia ixx="0.002" ixy="0" ixz="0.0001" iyy="0.002" iyz="0" izz="0.0002"/></inertial></link>
  <link name="arm"><inertial><origin xyz="0.1 0 0"/><mass value="0.4"/>
    <inertia ixx="0.0002" ixy="0" ixz="0" iyy="0.002" iyz="0" izz="0.002"/></inertial></link>
  <joint name="free" type="floating"><parent link="world"/><child link="base"/>
    <origin xyz="0.1 -0.2 1.0" rpy="0.3 -0.2 0.5"/></joint>
  <joint name="hip" type="revolute"><parent link="base"/><child link="thigh"/>
    <origin xyz="0.1 0.05 -0.05" rpy="0.2 0 0"/><axis xyz="0 1 0"/>
    <limit lower="-2" upper="2" effort="10" velocity="5"/></joint>
  <joint name="knee" type="revolute"><parent link="thigh"/><child link="shin"/>
    <origin xyz="0 0 -0.2"/><axis xyz="0.6 0.8 0"/>
    <limit lower="-2" upper="2" effort="10" velocity="5"/></joint>
  <joint name="shoulder" type="continuous"><parent link="base"/><child link="arm"/>
    <origin xyz="-0.1 0 0.1" rpy="0 0 0.4"/><axis xyz="0 0 -1"/></joint>
</robot>
"""
JOINTS = ["hip", "knee", "shoulder"]


class MuJoCo:
    """MuJoCo's model of a URDF text (constraints off: no contacts, no joint limits)."""

    def __init__(self, text: str) -> None:
        self.model = mujoco.MjModel.from_xml_string(text)
        self.model.opt.disableflags |= mujoco.mjtDisableBit.mjDSBL_CONSTRAINT
        self.data = mujoco.MjData(self.model)

    def dofs(self, joints: list[str]) -> tuple[list[int], list[int]]:
        ids = [mujoco.mj_name2id(self.model, mujoco.mjtObj.mjOBJ_JOINT, name) for name in joints]
        return [int(self.model.jnt_qposadr[i]) for i in ids], [int(self.model.jnt_dofadr[i]) for i in ids]

    def set(self, y: np.ndarray, joints: list[str], tau: np.ndarray | None = None) -> list[int]:
        """Our state (r, e, q; v, ω, q̇) into MuJoCo's; returns our velocity order as MuJoCo's dof indices."""
        n = len(joints)
        qpos, dofs = self.dofs(joints)
        d = self.data
        d.qpos[:7] = y[:7]
        d.qpos[qpos] = y[7:7 + n]
        d.qvel[:6] = y[7 + n:13 + n]
        d.qvel[dofs] = y[13 + n:13 + 2 * n]
        d.qfrc_applied[:] = 0.0
        if tau is not None:
            d.qfrc_applied[dofs] = tau
        mujoco.mj_forward(self.model, d)
        return [0, 1, 2, 3, 4, 5, *dofs]

    def mass(self) -> np.ndarray:
        out = np.zeros((self.model.nv, self.model.nv))
        mujoco.mj_fullM(self.model, self.data, out)
        return out


class FreeFlyer:
    """Pinocchio's model of a URDF with a free flyer (the file's floating joint, or ``root_joint``)."""

    def __init__(self, path_or_text: str, *, root: bool) -> None:
        if root:
            self.model = pin.buildModelFromUrdf(path_or_text, pin.JointModelFreeFlyer())
        else:
            self.model = pin.buildModelFromXML(path_or_text)
        self.data = self.model.createData()
        free = next(j for j in self.model.joints if j.nq == 7)
        self.placement = self.model.jointPlacements[free.id]

    def state(self, y: np.ndarray, joints: list[str]) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        n = len(joints)
        pose = pin.SE3(matrix_from_quaternion(y[3:7]), y[:3])
        local = self.placement.inverse() * pose  # the free flyer's q is relative to its joint's placement
        q, v = pin.neutral(self.model), np.zeros(self.model.nv)
        q[:7] = pin.SE3ToXYZQUAT(local)
        R = pose.rotation
        v[:3], v[3:6] = R.T @ y[7 + n:10 + n], y[10 + n:13 + n]
        for name, qj, vj in zip(joints, y[7:7 + n], y[13 + n:13 + 2 * n], strict=True):
            j = self.model.joints[self.model.getJointId(name)]
            q[j.idx_q:j.idx_q + j.nq] = (np.cos(qj), np.sin(qj)) if j.nq == 2 else qj
            v[j.idx_v] = vj
        return q, v, R

    def order(self, joints: list[str]) -> list[int]:
        return [0, 1, 2, 3, 4, 5, *(self.model.joints[self.model.getJointId(n)].idx_v for n in joints)]


def _random_state(rng: np.random.Generator, n: int) -> np.ndarray:
    e = rng.normal(size=4)
    return np.concatenate([rng.normal(size=3), e / np.linalg.norm(e), rng.uniform(-1.5, 1.5, n),
                           rng.normal(size=6), rng.uniform(-2, 2, n), [0.0]])


@pytest.fixture(scope="module")
def walker() -> FreeBodySystem:
    return FreeBodySystem(parse_urdf(WALKER, damping=False))


def test_a_floating_joint_makes_its_child_a_free_body_starting_at_its_origin(walker) -> None:
    model = walker.model
    assert [c.name for c in model.coordinates] == ["free_x", "free_y", "free_z", "free_yaw", "free_pitch",
                                                   "free_roll", *JOINTS]
    assert (model.bodies[0].name, model.bodies[0].free) == ("base", True)
    assert model.inputs == ("tau_hip", "tau_knee", "tau_shoulder")  # a free body has no actuator
    mj = MuJoCo(WALKER)
    y0 = walker.initial_state()
    e = mj.model.qpos0[3:7] * np.sign(mj.model.qpos0[3] * y0[3])
    assert np.allclose(y0[:3], mj.model.qpos0[:3], atol=1e-15) and np.allclose(y0[3:7], e, atol=1e-15)


def test_accelerations_mass_matrix_and_bias_agree_with_mujoco_and_pinocchio(walker) -> None:
    mj, ff = MuJoCo(WALKER), FreeFlyer(WALKER, root=False)
    rng = np.random.default_rng(11)
    n, nq = len(JOINTS), 7 + len(JOINTS)
    for _ in range(4):
        y, tau = _random_state(rng, n), rng.uniform(-2, 2, n)
        p = walker.parameter_vector({f"tau_{j}": t for j, t in zip(JOINTS, tau, strict=True)})
        ours = walker.rhs(0.0, y, p)[nq:nq + 6 + n]
        M, F = walker.mass_forces(0.0, y, p)
        order = mj.set(y, JOINTS, tau)
        assert np.max(np.abs(ours - mj.data.qacc[order])) < 1e-10 * max(1.0, np.max(np.abs(ours)))
        assert np.max(np.abs(M - mj.mass()[np.ix_(order, order)])) < 1e-12
        bias = np.concatenate([np.zeros(6), tau]) - F  # M q̈ = τ − (C q̇ + g): MuJoCo's qfrc_bias
        assert np.max(np.abs(bias - mj.data.qfrc_bias[order])) < 1e-10
        q, v, R = ff.state(y, JOINTS)
        t = np.zeros(ff.model.nv)
        t[ff.order(JOINTS)[6:]] = tau
        a = pin.aba(ff.model, ff.data, q, v, t)[ff.order(JOINTS)]
        v_local = R.T @ y[nq:nq + 3]
        theirs = np.concatenate([R @ (a[:3] + np.cross(y[nq + 3:nq + 6], v_local)), a[3:]])
        assert np.max(np.abs(ours - theirs)) < 1e-10 * max(1.0, np.max(np.abs(ours)))
        T = np.eye(6 + n)
        T[:3, :3] = R.T  # Pinocchio's velocities from ours
        crba = pin.crba(ff.model, ff.data, q)
        crba = np.triu(crba) + np.triu(crba, 1).T
        assert np.max(np.abs(M - T.T @ crba[np.ix_(ff.order(JOINTS), ff.order(JOINTS))] @ T)) < 1e-12


def test_free_fall_is_mujocos_and_keeps_energy_and_angular_momentum(walker) -> None:
    start = {"free_roll_dot": 1.5, "free_yaw_dot": -0.7, "hip_dot": 2.0, "knee": 0.4, "shoulder_dot": -3.0,
             "free_x_dot": 0.3, "free_z_dot": 2.0}
    traj = lagrangian.simulate(walker, 0.5, initial=start, rtol=1e-12, atol=1e-12, n_out=6)
    assert traj.drift["E"] < 1e-10 and max(traj.drift[f"sigma_G_{a}"] for a in ("x0", "y0", "z0")) < 1e-10
    mj = MuJoCo(WALKER)
    mj.model.opt.integrator = mujoco.mjtIntegrator.mjINT_RK4
    mj.model.opt.timestep = 2.5e-4
    y0 = walker.initial_state(start)
    order = mj.set(y0, JOINTS)
    qpos, _ = mj.dofs(JOINTS)
    for _ in range(2000):
        mujoco.mj_step(mj.model, mj.data)
    y = walker.state_of(np.concatenate([traj.q[-1], traj.qd[-1]])[None, :])[0]
    e = np.array([traj.extra[f"base_e{k}"][-1] for k in "wxyz"])
    omega = np.array([traj.extra[f"base_omega_{a}"][-1] for a in "xyz"])
    assert np.max(np.abs(mj.data.qpos[:3] - traj.q[-1, :3])) < 1e-10
    assert np.max(np.abs(mj.data.qpos[3:7] * np.sign(mj.data.qpos[3] * e[0]) - e)) < 1e-10
    assert np.max(np.abs(mj.data.qpos[qpos] - traj.q[-1, 6:])) < 1e-10
    assert np.max(np.abs(mj.data.qvel[order][:3] - y[10:13])) < 1e-10
    assert np.max(np.abs(mj.data.qvel[order][3:6] - omega)) < 1e-10
    assert np.max(np.abs(mj.data.qvel[order][6:] - traj.qd[-1, 6:])) < 1e-10


def test_the_courses_equations_in_yaw_pitch_roll_are_mujocos_dynamics(walker) -> None:
    compiled = lagrangian.compile_system(lagrangian.derive(walker.model))  # M q̈ = F in the model's coordinates
    mj = MuJoCo(WALKER)
    rng = np.random.default_rng(5)
    n = len(JOINTS)
    p = compiled.parameter_vector()
    for _ in range(3):
        q = np.concatenate([rng.normal(size=3), rng.uniform(-1.2, 1.2, 3), rng.uniform(-1, 1, n)])
        qd = rng.uniform(-1, 1, 6 + n)
        qdd = compiled.rhs(0.0, np.concatenate([q, qd]), p)[6 + n:]
        order = mj.set(walker.state_of(np.concatenate([q, qd])[None, :])[0], JOINTS)
        J = rate_matrix("zyx", q[3:6])
        angles = np.linalg.solve(J, mj.data.qacc[order][3:6] - rate_matrix_derivative("zyx", q[3:6], qd[3:6]))
        theirs = np.concatenate([mj.data.qacc[order][:3], angles, mj.data.qacc[order][6:]])
        assert np.max(np.abs(qdd - theirs)) < 1e-9 * max(1.0, np.max(np.abs(qdd)))


def _without_meshes(text: str) -> str:
    text = re.sub(r"<visual>.*?</visual>", "", text, flags=re.DOTALL)
    return re.sub(r"<collision>.*?</collision>", "", text, flags=re.DOTALL)


def test_a_quadruped_with_a_floating_base_is_pinocchios_free_flyer_and_mujocos() -> None:
    path = robot_data_file("solo_description/robots/solo12.urdf")
    if path is None:
        pytest.skip("example-robot-data is not installed")
    model = lagrangian.load_urdf(path, floating_base=True, damping=False)
    system = FreeBodySystem(model)
    joints = list(system.coordinates[6:])
    assert len(joints) == 12 and system.coordinates[:6] == ("base_x", "base_y", "base_z", "base_yaw", "base_pitch",
                                                              "base_roll")
    ff = FreeFlyer(str(path), root=True)
    text = _without_meshes(path.read_text())
    root = re.search(r'<link name="([^"]+)"', text).group(1)  # type: ignore[union-attr]
    mj = MuJoCo(text.replace("</robot>", f'<link name="world_"/><joint name="root_" type="floating">'
                                         f'<parent link="world_"/><child link="{root}"/></joint></robot>'))
    rng = np.random.default_rng(2)
    p = system.parameter_vector()
    nq = 7 + len(joints)
    for _ in range(3):
        y = _random_state(rng, len(joints))
        ours = system.rhs(0.0, y, p)[nq:nq + 6 + len(joints)]
        q, v, R = ff.state(y, joints)
        a = pin.aba(ff.model, ff.data, q, v, np.zeros(ff.model.nv))[ff.order(joints)]
        theirs = np.concatenate([R @ (a[:3] + np.cross(y[nq + 3:nq + 6], R.T @ y[nq:nq + 3])), a[3:]])
        assert np.max(np.abs(ours - theirs)) < 1e-10 * max(1.0, np.max(np.abs(ours)))
        order = mj.set(y, joints)
        M, F = system.mass_forces(0.0, y, p)
        assert np.max(np.abs(M - mj.mass()[np.ix_(order, order)])) < 1e-12
        assert np.max(np.abs(-F - mj.data.qfrc_bias[order])) < 1e-10


PLANAR = WALKER.replace('<joint name="free" type="floating"><parent link="world"/><child link="base"/>\n'
                        '    <origin xyz="0.1 -0.2 1.0" rpy="0.3 -0.2 0.5"/></joint>',
                        '<joint name="free" type="planar"><parent link="world"/><child link="base"/>\n'
                        '    <origin xyz="0.1 -0.2 1.0" rpy="0.3 -0.2 0.5"/><axis xyz="{axis}"/></joint>')


@pytest.mark.parametrize("axis", ["0 0 1", "1 0 0"])
def test_a_planar_joint_is_mujocos_slide_slide_hinge(axis: str) -> None:
    text = PLANAR.format(axis=axis)
    model = parse_urdf(text, damping=False)
    assert [c.name for c in model.coordinates][:3] == ["free_x", "free_y", "free_theta"]
    assert model.inputs[:3] == ("tau_free_x", "tau_free_y", "tau_free_theta")
    compiled = lagrangian.compile_system(lagrangian.derive(model))
    mj = MuJoCo(text)
    rng = np.random.default_rng(3)
    p = compiled.parameter_vector()
    for _ in range(3):
        y = rng.uniform(-1, 1, 12)
        M, _ = compiled.mass_forces(0.0, y, p)
        mj.data.qpos[:], mj.data.qvel[:] = y[:6], y[6:]  # MuJoCo's order is ours: slide, slide, hinge, joints
        mujoco.mj_forward(mj.model, mj.data)
        assert np.max(np.abs(M - mj.mass())) < 1e-12
        assert np.max(np.abs(compiled.rhs(0.0, y, p)[6:] - mj.data.qacc)) < 1e-10


def test_constant_joint_torques_run_on_the_quaternion_route_and_a_varying_one_is_refused(walker) -> None:
    model = walker.model
    held = lagrangian.simulate(model, 0.05, inputs={"tau_hip": 0.5}, n_out=3)
    assert held.status == "completed"
    # The hip's motor works while it pushes: E is no integral of that run; σ_G still is (an internal torque).
    assert "E" not in held.integrals and "sigma_G_z0" in held.integrals
    assert "E" in lagrangian.simulate(model, 0.05, n_out=3).integrals  # motors off
    with pytest.raises(lagrangian.SimulationError, match="quaternion route runs with constant inputs only"):
        lagrangian.simulate(model, 0.05, inputs={"tau_hip": "0.5*sin(t)"}, n_out=3)
