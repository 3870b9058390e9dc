"""Small URDF robots written for the tests, and the numeric M, q̈ of ours and of Pinocchio on them.

Each robot exercises part of the format: rpy origins, axes along ±x, ±y, ±z and general
directions, prismatic and continuous joints, fixed joints (merged), a branching tree, a
massless world link, a mimic joint and joint damping.
"""

from __future__ import annotations

from importlib import metadata
from pathlib import Path

import numpy as np
import symengine as se

import lagrangian

#: A planar double pendulum hanging down along −z at q = 0 (rods along −z, axes along y).
DOUBLE_PENDULUM = """<?xml version="1.0"?>
<robot name="double_pendulum">
  <link name="world"/>
  <link name="rod1">
    <inertial><origin xyz="0 0 -0.5"/><mass value="1.0"/>
      <inertia ixx="0.0833" ixy="0" ixz="0" iyy="0.0833" iyz="0" izz="0.001"/></inertial>
  </link>
  <link name="rod2">
    <inertial><origin xyz="0 0 -0.4"/><mass value="0.8"/>
      <inertia ixx="0.0427" ixy="0" ixz="0" iyy="0.0427" iyz="0" izz="0.0008"/></inertial>
  </link>
  <joint name="shoulder" type="continuous">
    <parent link="world"/><child link="rod1"/><origin xyz="0 0 2"/><axis xyz="0 1 0"/>
  </joint>
  <joint name="elbow" type="revolute">
    <parent link="rod1"/><child link="rod2"/><origin xyz="0 0 -1"/><axis xyz="0 1 0"/>
    <limit lower="-2.5" upper="2.5" effort="30" velocity="4"/>
    <dynamics damping="0.2" friction="0.0"/>
  </joint>
</robot>
"""

#: A 4-joint spatial arm: rpy origins, full inertias off the joint axes, a general axis, a slider.
SPATIAL_ARM = """<?xml version="1.0"?>
<robot name="spatial_arm">
  <link name="base"/>
  <link name="l1"><inertial><origin xyz="0.01 0.02 0.1" rpy="0.1 0.2 0.3"/><mass value="2"/>
    <inertia ixx="0.03" ixy="0.001" ixz="0.002" iyy="0.04" iyz="0.003" izz="0.02"/></inertial></link>
  <link name="l2"><inertial><origin xyz="0.2 0.01 0" rpy="0 0.4 0"/><mass value="1.5"/>
    <inertia ixx="0.01" ixy="0" ixz="0.001" iyy="0.05" iyz="0" izz="0.05"/></inertial></link>
  <link name="l3"><inertial><origin xyz="0.15 0 0.02"/><mass value="0.7"/>
    <inertia ixx="0.002" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial></link>
  <link name="l4"><inertial><origin xyz="0 0.03 0.05" rpy="-0.3 0.1 0.2"/><mass value="0.4"/>
    <inertia ixx="0.001" ixy="0.0001" ixz="0" iyy="0.0012" iyz="0" izz="0.0008"/></inertial></link>
  <joint name="j1" type="revolute"><parent link="base"/><child link="l1"/><origin xyz="0 0 0.2"/>
    <axis xyz="0 0 1"/><limit lower="-3" upper="3" effort="50" velocity="2"/></joint>
  <joint name="j2" type="revolute"><parent link="l1"/><child link="l2"/>
    <origin xyz="0 0.05 0.3" rpy="1.5707963267948966 0 0.3"/><axis xyz="0 0 -1"/>
    <limit lower="-2" upper="2" effort="50" velocity="2"/></joint>
  <joint name="j3" type="continuous"><parent link="l2"/><child link="l3"/>
    <origin xyz="0.4 0 0" rpy="0.2 -0.3 0.1"/><axis xyz="0.3 0.5 0.8"/></joint>
  <joint name="j4" type="prismatic"><parent link="l3"/><child link="l4"/>
    <origin xyz="0.1 0 0.05" rpy="0 1.5707963267948966 0.4"/><axis xyz="1 0 0"/>
    <limit lower="0" upper="0.2" effort="100" velocity="0.5"/></joint>
</robot>
"""

#: A branching tree on a fixed base: a slider along a general axis carrying a welded tool (merged
#: into the cart) and a swinging arm about −y with a massless flag; the world link is massless.
TREE = """<?xml version="1.0"?>
<robot name="tree">
  <link name="world"/>
  <link name="base"><inertial><mass value="3"/>
    <inertia ixx="0.1" ixy="0" ixz="0" iyy="0.1" iyz="0" izz="0.1"/></inertial></link>
  <link name="cart"><inertial><origin xyz="0.05 0 0.01"/><mass value="2"/>
    <inertia ixx="0.02" ixy="0" ixz="0" iyy="0.03" iyz="0" izz="0.04"/></inertial></link>
  <link name="tool"><inertial><origin xyz="0 0.1 0" rpy="0.3 0 0"/><mass value="0.5"/>
    <inertia ixx="0.001" ixy="0.0001" ixz="0" iyy="0.002" iyz="0" izz="0.002"/></inertial></link>
  <link name="arm"><inertial><origin xyz="0 0 -0.3"/><mass value="1"/>
    <inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.001"/></inertial></link>
  <link name="flag"><inertial><mass value="0"/>
    <inertia ixx="0" ixy="0" ixz="0" iyy="0" iyz="0" izz="0"/></inertial></link>
  <link name="finger"><inertial><origin xyz="0 0 -0.05"/><mass value="0.1"/>
    <inertia ixx="0.0001" ixy="0" ixz="0" iyy="0.0001" iyz="0" izz="0.00001"/></inertial></link>
  <joint name="bolt" type="fixed"><parent link="world"/><child link="base"/>
    <origin xyz="0 0 1" rpy="0 0 0.5"/></joint>
  <joint name="slide" type="prismatic"><parent link="base"/><child link="cart"/>
    <origin xyz="0.1 0 0" rpy="0 0.2 0"/><axis xyz="1 1 0"/>
    <limit lower="-1" upper="1" effort="100" velocity="1"/></joint>
  <joint name="weld" type="fixed"><parent link="cart"/><child link="tool"/>
    <origin xyz="0.2 0 0.1" rpy="0.5 0.1 -0.2"/></joint>
  <joint name="swing" type="revolute"><parent link="cart"/><child link="arm"/><origin xyz="0 0.1 0"/>
    <axis xyz="0 -1 0"/><limit lower="-1" upper="1" effort="10" velocity="3"/></joint>
  <joint name="tag" type="fixed"><parent link="arm"/><child link="flag"/></joint>
  <joint name="pinch" type="revolute"><parent link="flag"/><child link="finger"/>
    <origin xyz="0 0 -0.6" rpy="0 0 1.5707963267948966"/><axis xyz="1 0 0"/>
    <limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
  <joint name="pinch2" type="revolute"><parent link="tool"/><child link="finger2"/>
    <origin xyz="0 0.2 0"/><axis xyz="1 0 0"/><mimic joint="pinch" multiplier="-0.5" offset="0.1"/>
    <limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
  <link name="finger2"><inertial><origin xyz="0 0 -0.05"/><mass value="0.2"/>
    <inertia ixx="0.0002" ixy="0" ixz="0" iyy="0.0002" iyz="0" izz="0.00002"/></inertial></link>
  <transmission name="t1"><type>SimpleTransmission</type></transmission>
</robot>
"""


def robot_data_file(relative: str) -> Path | None:
    """A file of the ``example-robot-data`` package (its URDFs), or None when it is not installed."""
    try:
        dist = metadata.distribution("example-robot-data")
    except metadata.PackageNotFoundError:
        return None
    path = Path(dist.locate_file(f"cmeel.prefix/share/example-robot-data/robots/{relative}"))
    return path if path.is_file() else None


class Ours:
    """Our M(q) and F(q, q̇) of a model, as numeric functions of (q, q̇) (inputs and parameters by name)."""

    def __init__(self, model: lagrangian.Model) -> None:
        self.model = model
        self.eom = eom = lagrangian.derive(model)
        self.names = [p.name for p in model.parameters]
        args = [*eom.q, *eom.qd, *(p.symbol for p in model.parameters)]
        self.n = len(eom.q)
        # one function with common subexpressions shared: M, F, T, U
        self._all = se.Lambdify(args, [*(e for row in eom.M for e in row), *eom.F, eom.T, eom.U], cse=True)

    def _args(self, q, v, values) -> np.ndarray:
        p = [values.get(name, parameter.value) for name, parameter in zip(self.names, self.model.parameters, strict=True)]
        return np.concatenate([q, v, np.array(p, dtype=float)])

    def _eval(self, q, v, values) -> tuple[np.ndarray, np.ndarray, float, float]:
        out = np.asarray(self._all(self._args(q, v, values or {}))).ravel()
        n = self.n
        return out[:n * n].reshape(n, n), out[n * n:n * n + n], float(out[-2]), float(out[-1])

    def mass(self, q, values=None) -> np.ndarray:
        return self._eval(q, np.zeros(self.n), values)[0]

    def acceleration(self, q, v, values=None) -> np.ndarray:
        m, f, _, _ = self._eval(q, v, values)
        return np.linalg.solve(m, f)

    def energies(self, q, v) -> tuple[float, float]:
        return self._eval(q, v, None)[2:]


class Peer:
    """Pinocchio's model of the same URDF, indexed by our coordinates (joint names)."""

    def __init__(self, pin, text: str, coordinates: list[str], *, mimic: bool = False) -> None:
        self.pin = pin
        self.model = pin.buildModelFromXML(text, mimic=True) if mimic else pin.buildModelFromXML(text)
        self.data = self.model.createData()
        self.mimic = mimic
        self.joints = [self.model.joints[self.model.getJointId(name)] for name in coordinates]
        self.v_index = [j.idx_v for j in self.joints]

    def state(self, q, v) -> tuple[np.ndarray, np.ndarray]:
        qp, vp = self.pin.neutral(self.model), np.zeros(self.model.nv)
        for j, qi, vi in zip(self.joints, q, v, strict=True):
            if j.nq == 2:  # a continuous joint: (cos q, sin q)
                qp[j.idx_q:j.idx_q + 2] = np.cos(qi), np.sin(qi)
            else:
                qp[j.idx_q] = qi
            vp[j.idx_v] = vi
        return qp, vp

    def mass(self, q) -> np.ndarray:
        qp, _ = self.state(q, np.zeros(len(q)))
        m = self.pin.crba(self.model, self.data, qp)
        m = np.triu(m) + np.triu(m, 1).T
        return m[np.ix_(self.v_index, self.v_index)]

    def acceleration(self, q, v, tau=None) -> np.ndarray:
        qp, vp = self.state(q, v)
        t = np.zeros(self.model.nv)
        if tau is not None:
            t[self.v_index] = tau
        if self.mimic:  # aba does not take mimic joints: M q̈ = τ − h(q, q̇)
            m = self.pin.crba(self.model, self.data, qp)
            m = np.triu(m) + np.triu(m, 1).T
            a = np.linalg.solve(m, t - self.pin.nonLinearEffects(self.model, self.data, qp, vp))
        else:
            a = self.pin.aba(self.model, self.data, qp, vp, t)
        return a[self.v_index]

    def energies(self, q, v) -> tuple[float, float]:
        qp, vp = self.state(q, v)
        return (float(self.pin.computeKineticEnergy(self.model, self.data, qp, vp)),
                float(self.pin.computePotentialEnergy(self.model, self.data, qp)))
