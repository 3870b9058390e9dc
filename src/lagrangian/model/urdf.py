"""A URDF robot as a `Model`: frames, points and bodies through `ModelBuilder`, joint efforts as inputs.

`load_urdf` reads the file (`lagrangian.model._urdf_read`, a safe XML parser, every
element with its line) and declares the robot with the same builder as a TOML model, so
T, U, Q_i and L(q_i) are derived for it as for any other system:

- each moving joint j (revolute, continuous, prismatic) gives a coordinate q_j (its
  name), a frame ``R_<child link>`` and, for a revolute joint, the elementary rotation
  (q_j, x|y|z) of the course; the joint's constant placement (origin xyz, rpy and the
  direction of its axis) becomes at most three constant elementary rotations before
  it, with angles that are multiples of π/2 written exactly;
- the links rigidly joined by ``fixed`` joints are merged into one body per moving
  frame (mass, centre of mass and inertia at G added with Huygens' theorem, computed in
  floating point), named after the joint's child link; the root link is fixed to R0;
- gravity is g = 9.81 m/s² along −z of the root link (``-g*R0.z``), as in ROS;
- each independent joint gets an input ``tau_<joint>``, the joint torque (revolute) or
  force (prismatic) of its actuator: the generalized force Q_j = τ_j, so that
  `lagrangian.linearize` gives B = [0; M⁻¹ S] at once;
- ``<dynamics damping>`` becomes the Rayleigh function D = ½ Σ c_j q̇_j²;
- a ``<mimic>`` joint follows its leader: its value is multiplier·q_leader + offset,
  no coordinate of its own (Pinocchio's ``mimic=True``);
- joint limits are recorded in each coordinate's description and in `UrdfRobot`.

Reference: URDF XML specification, http://wiki.ros.org/urdf/XML; the composition of
inertias: the seed's course (théorème de Huygens), Featherstone, *Rigid Body Dynamics
Algorithms* (2008), §2.12.
"""

from __future__ import annotations

from fractions import Fraction
import math
import re
import warnings
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import symengine as se

from ..errors import ModelError
from ._assemble import RESERVED
from ._texts import Text
from ._urdf_read import UrdfJoint, UrdfRobot, read_urdf_file, read_urdf_text
from ._vector import Vector
from .build import ModelBuilder
from .spec import GALILEAN_FRAME, ORIGIN, Location, Model

__all__ = ["load_urdf", "parse_urdf", "read_urdf", "UrdfRobot", "UrdfNote", "GRAVITY"]

#: Most joints with a coordinate: the derivation expands M's n² entries, and a file from a stranger
#: must not start an endless one (as `lagrangian.model.zoo.MAX_LINKS` for the zoo's chains).
MAX_JOINTS = 100
#: Standard gravity, m/s², along −z of the root link (ROS's and Pinocchio's convention).
GRAVITY = 9.81
#: Below this (relative to the largest entry), a computed rotation or inertia entry is rounding noise.
_NOISE = 1e-14


class UrdfNote(UserWarning):
    """What `load_urdf` skipped (transmissions, dry friction, simulator settings), one warning each.

    The command line prints them as ``file:line: note: ...``.
    """


def _warn(robot: UrdfRobot) -> UrdfRobot:
    for note in robot.notes:
        warnings.warn(note, UrdfNote, stacklevel=3)
    return robot


def read_urdf(path: str | Path) -> UrdfRobot:
    """The checked links and joints of the URDF at ``path`` (limits, mimics and notes included)."""
    return read_urdf_file(path)


def load_urdf(path: str | Path, *, damping: bool = True) -> Model:
    """Read the URDF file at ``path`` into a `Model` (see the module docstring).

    ``damping=False`` leaves out the joints' ``<dynamics damping>`` (Pinocchio's ``aba``
    ignores it too).  What is skipped (transmissions, dry friction, ``<gazebo>``...) is
    said by a `UrdfNote` warning each.

    Raises
    ------
    ModelError
        Naming the file, line and element of the first problem: malformed XML, an
        entity declaration, a floating or planar joint, a cycle, a bad mass, inertia or axis.

    Examples
    --------
    >>> from lagrangian.model.urdf import parse_urdf
    >>> model = parse_urdf('''<robot name="pendulum">
    ...   <link name="base"/>
    ...   <link name="rod"><inertial><origin xyz="0 0 -0.5"/><mass value="1"/>
    ...     <inertia ixx="0.02" ixy="0" ixz="0" iyy="0.02" iyz="0" izz="0"/></inertial></link>
    ...   <joint name="hinge" type="continuous"><parent link="base"/><child link="rod"/>
    ...     <axis xyz="1 0 0"/></joint>
    ... </robot>''')
    >>> [c.name for c in model.coordinates], model.inputs
    (['hinge'], ('tau_hinge',))
    """
    return _Translation(_warn(read_urdf_file(path)), damping=damping).model()


def parse_urdf(text: str | bytes, *, source: str | None = None, damping: bool = True) -> Model:
    """`load_urdf` of URDF ``text`` (``source`` names it in error messages)."""
    return _Translation(_warn(read_urdf_text(text, source=source)), damping=damping).model()


# -- numbers and rotations --------------------------------------------------------------------------------------
def _elementary(axis: int, angle: float) -> np.ndarray:
    """The rotation matrix of ``angle`` about basis axis ``axis`` (0, 1, 2 for x, y, z)."""
    c, s = math.cos(angle), math.sin(angle)
    i, j = (axis + 1) % 3, (axis + 2) % 3
    r = np.eye(3)
    r[i, i] = r[j, j] = c
    r[j, i], r[i, j] = s, -s
    return r


def rpy_matrix(rpy: tuple[float, float, float]) -> np.ndarray:
    """URDF's ``rpy``: roll about x, then pitch about y, then yaw about z, all fixed axes: Rz·Ry·Rx."""
    roll, pitch, yaw = rpy
    return _elementary(2, yaw) @ _elementary(1, pitch) @ _elementary(0, roll)


#: An angle this close to a multiple of π/4 (rad) is taken as exactly that: the double nearest to π/2,
#: and rounding in the products of rotations, not a truncated π (the UR5's 1.57079632679 is kept).
ANGLE_SNAP = 1e-13


def _exact_angle(angle: float) -> se.Basic | None:
    """``angle`` as a SymEngine number: None for 0, kπ/4 exactly within `ANGLE_SNAP`, else rational.

    Exact multiples of π/4 keep cos and sin exact (0, ±1, ±√2/2), so that products of
    constant rotations simplify instead of carrying cos(0.785398163397448) as a symbol.
    """
    eighth = round(angle / (math.pi / 4))
    if abs(angle - eighth * math.pi / 4) <= ANGLE_SNAP:
        eighth = (eighth + 3) % 8 - 3  # in (−π, π]: −3 ... 4
        return None if eighth == 0 else se.pi * se.Rational(eighth, 4)
    return _number(angle)


def rotation_steps(c: np.ndarray) -> list[tuple[se.Basic, str]]:
    """Elementary rotations (angle, axis) whose product, each about the previous frame's axis, is ``c``.

    One rotation when ``c`` turns about a basis axis, else the intrinsic z-y'-x''
    sequence c = Rz(a)·Ry(b)·Rx(c) (URDF's rpy read backwards); zero angles are dropped.
    """
    for k, axis in enumerate("xyz"):
        i, j = (k + 1) % 3, (k + 2) % 3
        if abs(c[k, k] - 1) < 1e-13 and abs(c[k, i]) + abs(c[k, j]) + abs(c[i, k]) + abs(c[j, k]) < 1e-13:
            angle = _exact_angle(math.atan2(c[j, i], c[i, i]))
            return [] if angle is None else [(angle, axis)]
    pitch = math.asin(max(-1.0, min(1.0, -c[2, 0])))
    if math.cos(pitch) > 1e-9:
        yaw, roll = math.atan2(c[1, 0], c[0, 0]), math.atan2(c[2, 1], c[2, 2])
    else:  # gimbal lock: yaw and roll turn about the same line
        yaw, roll = math.atan2(-c[0, 1], c[1, 1]), 0.0
    steps = [(_exact_angle(a), axis) for a, axis in ((yaw, "z"), (pitch, "y"), (roll, "x"))]
    return [(a, axis) for a, axis in steps if a is not None]


#: URDF joint types as a French mechanics course names the joints (liaison pivot, glissière…).
_KIND_FR = {"revolute": "pivot", "continuous": "pivot (sans butée)", "prismatic": "glissière",
            "fixed": "encastrement", "floating": "libre", "planar": "appui plan"}


def _number(x: float) -> se.Basic:
    """A float as an exact SymEngine rational, its 15 significant digits (the file's decimals, as written).

    Exact numbers, not doubles: the derivation recognises a potential (the weight's U) by
    an identity Q_i + ∂U/∂q_i ≡ 0 tested to far below double rounding, which two orders of
    double products would fail; and 15 digits drop the rounding noise of the rotations
    (0.20000000000000004 is 1/5), well below the 1e-10 to which M agrees with Pinocchio.
    """
    if x == 0:
        return se.Integer(0)
    if x == int(x) and abs(x) < 1e6:
        return se.Integer(int(x))
    f = Fraction(f"{float(x):.15g}")
    return se.Rational(f.numerator, f.denominator)


def _clean(values: np.ndarray, scale: float | None = None) -> np.ndarray:
    """``values`` with the rounding noise of rotations (below 1e-14 of the largest entry) set to 0."""
    out = np.array(values, dtype=float)
    top = float(np.max(np.abs(out))) if scale is None else scale
    out[np.abs(out) <= _NOISE * top] = 0.0
    return out


def _vector(frame: str, components: np.ndarray) -> Vector:
    return Vector({frame: tuple(_number(float(x)) for x in components)})


def _axis_to(a: np.ndarray) -> np.ndarray:
    """A rotation A with A·z = a (the unit axis ``a``), by the shortest turn."""
    z = np.array([0.0, 0.0, 1.0])
    v = np.cross(z, a)
    s, c = float(np.linalg.norm(v)), float(a[2])
    if s < 1e-15:
        return np.eye(3) if c > 0 else _elementary(0, math.pi)
    k = np.array([[0, -v[2], v[1]], [v[2], 0, -v[0]], [-v[1], v[0], 0]]) / s
    return np.eye(3) + s * k + (1 - c) * (k @ k)


# -- the translation ----------------------------------------------------------------------------------------------
@dataclass
class _Carrier:
    """A frame moving with one joint (or R0), with the links fixed to it and their merged mass."""

    frame: str
    point: str
    body: str | None = None
    line: int | None = None
    masses: list[tuple[float, np.ndarray, np.ndarray]] = field(default_factory=list)  # (m, OG, I_G) in `frame`


class _Names:
    """Model names from URDF names: identifiers, unique, never a reserved name."""

    def __init__(self) -> None:
        self.used = set(RESERVED) | {"g"}

    def take(self, text: str, prefix: str = "", suffixes: tuple[str, ...] = ()) -> str:
        base = prefix + re.sub(r"\W", "_", text, flags=re.ASCII)
        if not base[:1].isalpha():
            base = "n" + base
        name, k = base, 1
        while any(name + s in self.used for s in ("", *suffixes)):
            k += 1
            name = f"{base}_{k}"
        self.used.update(name + s for s in ("", *suffixes))
        return name


class _Translation:
    """Declares the robot on a `ModelBuilder`, joint by joint from the root (module docstring)."""

    def __init__(self, robot: UrdfRobot, *, damping: bool) -> None:
        self.robot = robot
        self.damping = damping
        self.names = _Names()
        self.b = ModelBuilder(robot.name or "robot", self.description(), source=robot.source)
        self.coordinate: dict[str, str] = {}  # independent joint -> coordinate name
        self.value: dict[str, se.Basic] = {}  # moving joint -> its value q_j, or the mimic's expression
        self.rate: dict[str, se.Basic] = {}  # moving joint -> its rate
        self.carriers: list[_Carrier] = []
        #: link -> (carrier, R, p): the link's frame in its carrier's, x_carrier = R x_link + p
        self.pose: dict[str, tuple[_Carrier, np.ndarray, np.ndarray]] = {}

    def where(self, line: int | None) -> Location:
        return Location(self.robot.source, line)

    def description(self) -> str:
        kinds: dict[str, int] = {}
        for joint in self.robot.joints.values():
            kinds[joint.type] = kinds.get(joint.type, 0) + 1
        joints = ", ".join(f"{n} {kind}" for kind, n in kinds.items()) or "no"
        fr = ", ".join(f"{n} encastrement{'s' * (n > 1)}" if kind == "fixed" else
                       f"{n} liaison{'s' * (n > 1)} {_KIND_FR.get(kind, kind)}" for kind, n in kinds.items()) or "aucune"
        return Text({"fr": f"robot URDF à {len(self.robot.links)} corps ; liaisons : {fr}",
                     "en": f"URDF robot with {len(self.robot.links)} links and {joints} joints"})

    def model(self) -> Model:
        robot, b = self.robot, self.b
        order = self.tree_order()
        moving = [j for j in order if j.moves and j.mimic is None]
        if len(moving) > MAX_JOINTS:
            raise ModelError(f"the robot has {len(moving)} moving joints, more than the {MAX_JOINTS} this "
                             "derivation takes", file=robot.source, line=moving[MAX_JOINTS].line,
                             symbol=moving[MAX_JOINTS].name, fix="fix some joints (type=\"fixed\"), or split "
                             "the robot")
        self.check_masses_move()
        b.parameter("g", GRAVITY, unit="m/s^2", description=Text({
            "fr": "accélération de la pesanteur, selon −z du corps de base",
            "en": "gravitational acceleration, along -z of the root link"}))
        for joint in order:  # coordinates, rates and inputs first: the mimics refer to them
            if joint.moves and joint.mimic is None:
                q = self.names.take(joint.name, suffixes=("_dot", "_ddot"))
                self.coordinate[joint.name] = q
                unit = "m" if joint.type == "prismatic" else "rad"
                b.coordinate(q, initial=0.0, rate=0.0, unit=unit, description=self.joint_text(joint),
                             location=self.where(joint.line))
                self.value[joint.name] = se.Symbol(q)
                self.rate[joint.name] = se.Symbol(q + "_dot")
        for joint in order:
            if joint.mimic is not None:
                m = joint.mimic
                self.value[joint.name] = _number(m.multiplier) * self.value[m.joint] + _number(m.offset)
                self.rate[joint.name] = _number(m.multiplier) * self.rate[m.joint]
        root = _Carrier(GALILEAN_FRAME, ORIGIN)
        self.pose[robot.root] = (root, np.eye(3), np.zeros(3))
        for joint in order:
            self.joint(joint)
        self.bodies()
        self.efforts()
        return b.build()

    def tree_order(self) -> list[UrdfJoint]:
        """The joints depth-first from the root, children in file order (Pinocchio's order)."""
        # depth-first with an explicit stack (a deep chain must not hit Python's recursion limit)
        out: list[UrdfJoint] = []
        stack = list(reversed(self.robot.children(self.robot.root)))
        while stack:
            joint = stack.pop()
            out.append(joint)
            stack.extend(reversed(self.robot.children(joint.child)))
        return out

    @staticmethod
    def joint_text(joint: UrdfJoint) -> Text:
        lim = joint.limits
        unit, effort = ("m", "N") if joint.type == "prismatic" else ("rad", "N·m")
        speed = "m/s" if joint.type == "prismatic" else "rad/s"

        def num(x: float, lang: str) -> str:  # French: decimal comma and a minus sign, not a hyphen
            return f"{x:g}".replace(".", ",").replace("-", "\u2212") if lang == "fr" else f"{x:g}"

        texts = {}
        for lang, (head, limits, force, pace) in {
                "fr": (f"liaison {_KIND_FR.get(joint.type, joint.type)} « {joint.name} »", "limites", "effort", "vitesse"),
                "en": (f"{joint.type} joint “{joint.name}”", "limits", "effort", "speed")}.items():
            text = f"{head} ({joint.parent} → {joint.child})"
            if joint.type != "continuous" and lim.lower is not None and lim.upper is not None and lim.lower < lim.upper:
                sep = " ; " if lang == "fr" else ", "  # the French interval [a ; b]: its numbers have decimal commas
                text += f", {limits} [{num(lim.lower, lang)}{sep}{num(lim.upper, lang)}] {unit}"
            if lim.effort:
                text += f", {force} ≤ {num(lim.effort, lang)} {effort}"
            if lim.velocity:
                text += f", {pace} ≤ {num(lim.velocity, lang)} {speed}"
            texts[lang] = text
        return Text(texts)

    def check_masses_move(self) -> None:
        """Every independent joint must move some mass, or its Lagrange equation reads 0 = 0 (M singular)."""
        robot = self.robot
        below: dict[str, float] = {}

        def mass(link: str) -> float:  # iterative: the subtree's mass
            total, todo = 0.0, [link]
            while todo:
                name = todo.pop()
                inertial = robot.links[name].inertial
                total += inertial.mass if inertial else 0.0
                todo.extend(j.child for j in robot.children(name))
            return total

        followers: dict[str, list[UrdfJoint]] = {}
        for joint in robot.joints.values():
            if joint.mimic is not None:
                followers.setdefault(joint.mimic.joint, []).append(joint)
        for joint in robot.joints.values():
            if joint.moves and joint.mimic is None:
                below[joint.name] = mass(joint.child) + sum(mass(f.child) for f in followers.get(joint.name, []))
                if below[joint.name] == 0:
                    raise ModelError(
                        f"joint `{joint.name}` moves no mass: its child link `{joint.child}` and the links after "
                        "it have no <inertial>, so its Lagrange equation would read 0 = 0 (M is singular)",
                        file=robot.source, line=joint.line, symbol=joint.name,
                        fix=f"give `{joint.child}` (or a link after it) an <inertial> with its mass and inertia, "
                            "or make the joint fixed")

    # -- geometry ----------------------------------------------------------------------------------
    def joint(self, joint: UrdfJoint) -> None:
        carrier, r_parent, p_parent = self.pose[joint.parent]
        r_joint = r_parent @ rpy_matrix(joint.rpy)  # the joint frame J in the carrier's frame
        p_joint = _clean(p_parent + r_parent @ np.array(joint.xyz), max(1e-3, float(np.max(np.abs(p_parent)))))
        if not joint.moves:
            self.pose[joint.child] = (carrier, r_joint, p_joint)
            return
        child = self.names.take(joint.child)
        frame, point = self.names.take(joint.child, "R_"), self.names.take(joint.child, "O_")
        where = self.where(joint.line)
        axis = np.array(joint.axis)
        if np.any(np.abs(p_joint) > 0):
            self.b.point(point, _vector(carrier.frame, p_joint), relative_to=carrier.point, location=where)
        else:
            point = carrier.point
        q = self.value[joint.name]
        if joint.type == "prismatic":
            constant = _clean(r_joint, 1.0)
            steps = rotation_steps(constant)
            if steps:
                self.b.frame(frame, carrier.frame, rotation=steps, location=where)
            else:
                frame = carrier.frame
            slider = self.names.take(joint.child, "S_")
            self.b.point(slider, _vector(frame, _clean(axis, 1.0)) * q, relative_to=point, location=where)
            new = _Carrier(frame, slider, child, joint.line)
            self.pose[joint.child] = (new, np.eye(3), np.zeros(3))
        else:
            k = next((k for k in range(3) if abs(abs(axis[k]) - 1) < 1e-12), None)
            if k is not None:  # about ±x, ±y or ±z: rotate by ±q about it
                align, angle, name = np.eye(3), (q if axis[k] > 0 else -q), "xyz"[k]
            else:  # a general axis a = A z: the frame J·A turns by q about its z
                align, angle, name = _axis_to(axis), q, "z"
            steps = rotation_steps(_clean(r_joint @ align, 1.0))
            self.b.frame(frame, carrier.frame, rotation=[*steps, (angle, name)], location=where)
            new = _Carrier(frame, point, child, joint.line)
            self.pose[joint.child] = (new, align.T, np.zeros(3))
        self.carriers.append(new)

    def bodies(self) -> None:
        """One body per moving frame: the links fixed to it merged (Huygens), at G in that frame."""
        for link in self.robot.links.values():
            carrier, r, p = self.pose[link.name]
            if link.inertial is None or carrier.body is None:
                continue  # massless, or fixed to R0 (its weight is a constant of U)
            inertial = link.inertial
            r_com = r @ rpy_matrix(inertial.rpy)
            carrier.masses.append((inertial.mass, p + r @ np.array(inertial.xyz),
                                   r_com @ inertial.inertia @ r_com.T))
        for carrier in self.carriers:
            if not carrier.masses:
                continue
            mass = sum(m for m, _, _ in carrier.masses)
            center = sum(m * c for m, c, _ in carrier.masses) / mass
            inertia = np.zeros((3, 3))
            with np.errstate(over="ignore", invalid="ignore"):  # an overflow is refused just below
                for m, c, i_g in carrier.masses:
                    d = c - center
                    inertia += i_g + m * (float(d @ d) * np.eye(3) - np.outer(d, d))
            if not (np.all(np.isfinite(inertia)) and np.all(np.isfinite(center)) and math.isfinite(mass)):
                # Each number of the file is finite, their products (m d² of Huygens' theorem) are not.
                raise ModelError(f"the links fixed to the frame of `{carrier.body}` (merged by their fixed joints) "
                                 "have a centre of mass or an inertia that overflows a double (an offset or a mass "
                                 "too large: m d² past 1e308)", file=self.robot.source, line=carrier.line,
                                 symbol=carrier.body, fix="check the <origin> offsets and masses of these links "
                                                          "(metres and kilograms)")
            inertia = _clean((inertia + inertia.T) / 2)
            center = _clean(center, max(1e-3, float(np.max(np.abs(center)))))
            matrix = [[_number(float(x)) for x in row] for row in inertia]
            self.b.body(carrier.body, frame=carrier.frame, mass=_number(mass), center=_vector(carrier.frame, center),
                        center_from=carrier.point, inertia={"at": "G", "frame": carrier.frame, "matrix": matrix},
                        location=self.where(carrier.line))
        if any(carrier.masses for carrier in self.carriers):
            self.b.gravity("weight", Vector.basis(GALILEAN_FRAME, "z") * -se.Symbol("g"))

    def efforts(self) -> None:
        """The actuators' τ_j (Q_j = τ_j, an input each) and the joints' viscous damping D = ½ Σ c_j q̇_j²."""
        components = {}
        for joint_name, q in self.coordinate.items():
            joint = self.robot.joints[joint_name]
            tau = self.names.take(joint_name, "tau_")
            what, quoi = ("force", "effort") if joint.type == "prismatic" else ("torque", "couple")
            self.b.input(tau, unit="N" if joint.type == "prismatic" else "N*m",
                         description=Text({"fr": f"{quoi} de l'actionneur de la liaison « {joint_name} »",
                                           "en": f"actuator {what} of joint “{joint_name}”"}),
                         location=self.where(joint.line))
            components[q] = se.Symbol(tau)
        if components:
            self.b.generalized_force("actuators", components)
        if not self.damping:
            return
        damped = [j for j in self.robot.joints.values() if j.moves and j.damping > 0]
        terms = [se.Rational(1, 2) * _number(j.damping) * self.rate[j.name] ** 2 for j in damped]
        if terms:  # viscous friction in each of those joints: they are not perfect (the report says so)
            self.b.dissipation("joint_damping", se.Add(*terms), joints=[self.coordinate[j.name] for j in damped if j.name in self.coordinate])
