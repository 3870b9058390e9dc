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
- joint limits are recorded in each coordinate's description and in `UrdfRobot`;
- with ``inertial_parameters=True``, each body's ten standard inertial parameters are model
  parameters instead of numbers (`INERTIAL_PARAMETERS`): its mass m, first moment m c and inertia
  I_O about the origin of its frame, in that frame, valued from the file — the convention of
  Pinocchio's ``Inertia.toDynamicParameters`` and of robot identification (Khalil & Dombre,
  *Modeling, Identification and Control of Robots*, 2002, §9.3), in which the joint torques are
  linear (`lagrangian.identify`).
- a ``floating`` joint (six degrees of freedom) makes its child link a free body
  (`lagrangian.model._free`): the coordinates ``<joint>_x, _y, _z`` place its origin along R0's
  axes and ``<joint>_yaw, _pitch, _roll`` turn it (URDF's rpy convention, R = Rz·Ry·Rx), starting
  at the joint's origin; ``load_urdf(path, floating_base=True)`` does the same for the root
  link (Pinocchio's ``root_joint=JointModelFreeFlyer()``), so that a legged robot, whose file
  has no joint to the world, flies free; `simulate` integrates such a body on a unit quaternion;
- a ``planar`` joint (three degrees of freedom) moves its child link in the plane normal to its
  axis: ``<joint>_x``, ``<joint>_y`` along the joint frame's first two axes, then turns it by
  ``<joint>_theta`` about the axis (MuJoCo's slide, slide, hinge).
- each ``<visual>`` (box, cylinder, sphere, mesh) becomes a `Shape` of the body (or frame) its
  link is carried by, placed by the link's pose and the visual's origin; a mesh path is
  resolved beside the file (``package://name/...`` in the folder ``name`` above it), and a
  mesh that cannot be found is left out with a note (the view then infers the link's shape).

Reference: URDF XML specification, http://wiki.ros.org/urdf/XML; the composition of
inertias: the seed's course (théorème de Huygens), Featherstone, *Rigid Body Dynamics
Algorithms* (2008), §2.12.
"""

from __future__ import annotations

import math
import re
import warnings
from dataclasses import dataclass, field
from fractions import Fraction
from pathlib import Path
from typing import Any

import numpy as np
import symengine as se

from ..errors import ModelError
from ._assemble import RESERVED
from ._texts import Text
from ._urdf_read import UrdfJoint, UrdfRobot, read_urdf_file, read_urdf_text
from .build import ModelBuilder
from .spec import GALILEAN_FRAME, ORIGIN, Location, Model
from .vectors import Vector

__all__ = ["load_urdf", "parse_urdf", "read_urdf", "UrdfRobot", "UrdfNote", "GRAVITY", "INERTIAL_PARAMETERS",
           "inertial_parameter_names"]

#: Most joints with a coordinate: the derivation expands M's n² entries, and a file from a stranger
#: must not start an endless one (as `lagrangian.model.zoo.MAX_LINKS` for the zoo's chains).
MAX_JOINTS = 100
#: Standard gravity, m/s², along −z of the root link (ROS's and Pinocchio's convention).
GRAVITY = 9.81
#: Below this (relative to the largest entry), a computed rotation or inertia entry is rounding noise.
_NOISE = 1e-14
#: The ten standard inertial parameters of a body (``inertial_parameters=True``), each named
#: ``<prefix>_<body>``: m, the first moment m c (c: centre of mass from the frame's origin) and the
#: inertia matrix I_O about that origin, components in the body's frame (Pinocchio's order is
#: m, mx, my, mz, Ixx, Ixy, Iyy, Ixz, Iyz, Izz).
INERTIAL_PARAMETERS = ("m", "mx", "my", "mz", "Ixx", "Ixy", "Ixz", "Iyy", "Iyz", "Izz")


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


def load_urdf(path: str | Path, *, damping: bool = True, inertial_parameters: bool = False,
              floating_base: bool = False) -> Model:
    """Read the URDF file at ``path`` into a `Model` (see the module docstring).

    What is skipped (transmissions, dry friction, ``<gazebo>``...) is said by a `UrdfNote` warning each.

    Parameters
    ----------
    path : str or Path
        The URDF file.
    damping : bool, optional
        ``damping=False`` leaves out the joints' ``<dynamics damping>`` (Pinocchio's ``aba``
        ignores it too).
    inertial_parameters : bool, optional
        ``inertial_parameters=True`` declares each body's ten standard inertial parameters
        (`INERTIAL_PARAMETERS`: m, m c, I_O in the body's frame, about its origin) as parameters named
        ``m_<body>``, ``mx_<body>``, ..., ``Izz_<body>`` (`inertial_parameter_names`), valued from the
        file, instead of numbers: the motion is the same, and the joint torques are linear in them
        (identification).
    floating_base : bool, optional
        ``floating_base=True`` makes the root link a free body (six coordinates ``base_x, base_y,
        base_z, base_yaw, base_pitch, base_roll``), as a floating joint from the world would.

    Returns
    -------
    Model
        The robot, one coordinate per moving joint and one input ``tau_<joint>`` per actuated one.

    Raises
    ------
    ModelError
        Naming the file, line and element of the first problem: malformed XML, an
        entity declaration, a cycle, a bad mass, inertia or axis, a floating joint below a
        moving link or carrying no mass.

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
    return _Translation(_warn(read_urdf_file(path)), damping=damping, inertial=inertial_parameters,
                        floating_base=floating_base).model()


def parse_urdf(text: str | bytes, *, source: str | None = None, damping: bool = True,
               inertial_parameters: bool = False, floating_base: bool = False) -> Model:
    """`load_urdf` of URDF ``text`` (``source`` names it in error messages).

    Parameters
    ----------
    text : str or bytes
        A URDF document.
    source : str, optional
        Names the text in error messages.
    damping : bool, optional
        As in `load_urdf`.
    inertial_parameters : bool, optional
        As in `load_urdf`.
    floating_base : bool, optional
        As in `load_urdf`.

    Returns
    -------
    Model
        The robot.
    """
    return _Translation(_warn(read_urdf_text(text, source=source)), damping=damping,
                        inertial=inertial_parameters, floating_base=floating_base).model()


def inertial_parameter_names(model: Model) -> dict[str, tuple[str, ...]]:
    """Body name → the names of its ten standard inertial parameters, in `INERTIAL_PARAMETERS` order.

    Empty for a model read without ``inertial_parameters=True``.
    """
    names = {p.name for p in model.parameters}
    out = {}
    for body in model.bodies:
        mine = tuple(f"{prefix}_{body.name}" for prefix in INERTIAL_PARAMETERS)
        if all(name in names for name in mine):
            out[body.name] = mine
    return out


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


def _yaw_pitch_roll(c: np.ndarray) -> tuple[float, float, float]:
    """(yaw, pitch, roll) with c = Rz(yaw) Ry(pitch) Rx(roll) (URDF's rpy read backwards), pitch in [−π/2, π/2]."""
    pitch = math.asin(max(-1.0, min(1.0, -c[2, 0])))
    if math.cos(pitch) > 1e-9:
        return math.atan2(c[1, 0], c[0, 0]), pitch, math.atan2(c[2, 1], c[2, 2])
    return math.atan2(-c[0, 1], c[1, 1]), pitch, 0.0


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
    free: bool = False  # carried by a floating joint: a free body


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

    def __init__(self, robot: UrdfRobot, *, damping: bool, inertial: bool = False,
                 floating_base: bool = False) -> None:
        self.robot = robot
        self.damping = damping
        self.inertial = inertial
        self.floating_base = floating_base
        self.names = _Names()
        self.b = ModelBuilder(robot.name or "robot", self.description(), source=robot.source)
        self.coordinate: dict[str, str] = {}  # independent joint -> coordinate name (its first, for planar)
        self.coordinates: dict[str, list[str]] = {}  # independent joint -> its coordinate names
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
        if self.floating_base:
            self.free_coordinates("base", None, self.robot.root)
        for joint in order:  # coordinates, rates and inputs first: the mimics refer to them
            if joint.type in ("floating", "planar"):
                self.free_coordinates(joint.name, joint, joint.child)
            elif joint.moves and joint.mimic is None:
                q = self.names.take(joint.name, suffixes=("_dot", "_ddot"))
                self.coordinate[joint.name] = q
                self.coordinates[joint.name] = [q]
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
        if self.floating_base:
            self.pose[robot.root] = (self.free_carrier(robot.root, None), np.eye(3), np.zeros(3))
        for joint in order:
            self.joint(joint)
        self.bodies()
        self.efforts()
        self.visuals()
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

    # -- free and planar joints --------------------------------------------------------------------
    #: The coordinates of a floating joint (and of ``floating_base``): position along R0, yaw-pitch-roll.
    _FREE = (("x", "m"), ("y", "m"), ("z", "m"), ("yaw", "rad"), ("pitch", "rad"), ("roll", "rad"))
    _PLANAR = (("x", "m"), ("y", "m"), ("theta", "rad"))

    def free_coordinates(self, prefix: str, joint: UrdfJoint | None, child: str) -> None:
        """Declare the coordinates of a floating (or planar) joint, or of the root made free.

        A floating joint's coordinates start at its placement in R0 (through the fixed joints
        above it), so that the child starts where the file puts it.
        """
        kind = joint.type if joint is not None else "floating"
        start = [0.0] * 6
        if kind == "floating" and joint is not None:
            r, p = self.fixed_placement(joint)
            start = [*p, *_yaw_pitch_roll(r)]
        names = []
        for k, (suffix, unit) in enumerate(self._FREE if kind == "floating" else self._PLANAR):
            q = self.names.take(f"{prefix}_{suffix}", suffixes=("_dot", "_ddot"))
            names.append(q)
            what = {"x": "x", "y": "y", "z": "z", "theta": "θ", "yaw": "yaw", "pitch": "pitch", "roll": "roll"}[suffix]
            base = f"`{joint.name}`" if joint is not None else "of the base"
            text = Text({"fr": f"liaison {_KIND_FR[kind]} {base} ({child}) : {what}",
                         "en": f"{kind} joint {base} ({child}): {what}"})
            self.b.coordinate(q, initial=float(start[k]), rate=0.0, unit=unit, description=text,
                              location=self.where(joint.line if joint is not None else None))
        self.coordinates[joint.name if joint is not None else ""] = names
        if joint is not None:
            self.coordinate[joint.name] = names[0]

    def fixed_placement(self, joint: UrdfJoint) -> tuple[np.ndarray, np.ndarray]:
        """(R, p) of ``joint``'s frame in R0, through the fixed joints from the root; refused below a moving one."""
        parent_joint = {j.child: j for j in self.robot.joints.values()}
        chain, link = [joint], joint.parent
        while link in parent_joint:
            above = parent_joint[link]
            if above.moves:
                raise ModelError(f"joint `{joint.name}` is floating, but its parent link `{joint.parent}` moves (with "
                                 f"joint `{above.name}`): a free body hangs from the world, not from a moving link",
                                 file=self.robot.source, line=joint.line, symbol=joint.name,
                                 fix="make the floating joint's parent the root link (the world), or fix the joints "
                                     "above it")
            chain.append(above)
            link = above.parent
        r, p = np.eye(3), np.zeros(3)
        for j in reversed(chain):
            p = p + r @ np.array(j.xyz)
            r = r @ rpy_matrix(j.rpy)
        return r, _clean(p, max(1e-3, float(np.max(np.abs(p)))))

    def free_carrier(self, child: str, joint: UrdfJoint | None) -> _Carrier:
        """The free body of a floating joint: its origin at x R0.x + y R0.y + z R0.z, turned by yaw, pitch, roll."""
        names = self.coordinates[joint.name if joint is not None else ""]
        line = joint.line if joint is not None else None
        where = self.where(line)
        x, y, z, yaw, pitch, roll = (se.Symbol(q) for q in names)
        point = self.names.take(child, "O_")
        self.b.point(point, Vector({GALILEAN_FRAME: (x, y, z)}), location=where)
        frame = self.names.take(child, "R_")
        self.b.frame(frame, GALILEAN_FRAME, rotation=[(yaw, "z"), (pitch, "y"), (roll, "x")], location=where)
        carrier = _Carrier(frame, point, self.names.take(child), line, free=True)
        self.carriers.append(carrier)
        return carrier

    def planar(self, joint: UrdfJoint, carrier: _Carrier, r_joint: np.ndarray, p_joint: np.ndarray) -> None:
        """A planar joint: x, y along the joint frame's first two axes (z along the axis), then θ about it."""
        where = self.where(joint.line)
        x, y, theta = (se.Symbol(q) for q in self.coordinates[joint.name])
        align = _axis_to(np.array(joint.axis))
        base = carrier.point
        if np.any(np.abs(p_joint) > 0):
            base = self.names.take(joint.child, "O_")
            self.b.point(base, _vector(carrier.frame, p_joint), relative_to=carrier.point, location=where)
        steps = rotation_steps(_clean(r_joint @ align, 1.0))
        plane = carrier.frame
        if steps:
            plane = self.names.take(joint.child, "P_")
            self.b.frame(plane, carrier.frame, rotation=steps, location=where)
        slider = self.names.take(joint.child, "S_")
        self.b.point(slider, Vector({plane: (x, y, se.Integer(0))}), relative_to=base, location=where)
        frame = self.names.take(joint.child, "R_")
        self.b.frame(frame, plane, rotation=[(theta, "z")], location=where)
        new = _Carrier(frame, slider, self.names.take(joint.child), joint.line)
        self.pose[joint.child] = (new, align.T, np.zeros(3))
        self.carriers.append(new)

    # -- geometry ----------------------------------------------------------------------------------
    def joint(self, joint: UrdfJoint) -> None:
        carrier, r_parent, p_parent = self.pose[joint.parent]
        r_joint = r_parent @ rpy_matrix(joint.rpy)  # the joint frame J in the carrier's frame
        p_joint = _clean(p_parent + r_parent @ np.array(joint.xyz), max(1e-3, float(np.max(np.abs(p_parent)))))
        if not joint.moves:
            self.pose[joint.child] = (carrier, r_joint, p_joint)
            return
        if joint.type == "floating":  # its parent is fixed in R0 (checked by `fixed_placement`)
            self.pose[joint.child] = (self.free_carrier(joint.child, joint), np.eye(3), np.zeros(3))
            return
        if joint.type == "planar":
            self.planar(joint, carrier, r_joint, p_joint)
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
            if not carrier.masses and carrier.free:
                raise ModelError(f"link `{carrier.body}` is free (a floating joint, or the floating base) but carries no "
                                 "mass: neither it nor a link fixed to it has an <inertial>", file=self.robot.source,
                                 line=carrier.line, symbol=carrier.body,
                                 fix="give the link its <inertial> (mass and inertia), or make free the link that has "
                                     "them (the robot's base)")
            if not carrier.masses or carrier.body is None:  # masses are gathered on a body's carrier only
                continue
            mass = sum(m for m, _, _ in carrier.masses)
            center = np.asarray(sum(m * c for m, c, _ in carrier.masses)) / mass
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
            if self.inertial:
                self.symbolic_body(carrier, mass, center, inertia)
                continue
            matrix = [[_number(float(x)) for x in row] for row in inertia]
            self.b.body(carrier.body, frame=carrier.frame, mass=_number(mass), center=_vector(carrier.frame, center),
                        center_from=carrier.point, inertia={"at": "G", "frame": carrier.frame, "matrix": matrix},
                        free=carrier.free, location=self.where(carrier.line))
        if any(carrier.masses for carrier in self.carriers):
            self.b.gravity("weight", Vector.basis(GALILEAN_FRAME, "z") * -se.Symbol("g"))

    def symbolic_body(self, carrier: _Carrier, mass: float, center: np.ndarray, inertia: np.ndarray) -> None:
        """The body of ``carrier`` over its ten standard inertial parameters (`INERTIAL_PARAMETERS`).

        m, h = m c and I_O = I_G + m (|c|² 1 − c cᵀ) (Huygens), c = OG in the carrier's frame from
        its point O; the body is then declared with G = O + h/m and its inertia at O, so that T,
        M and F are those of the file's numbers for the default values.
        """
        body = carrier.body
        assert body is not None, "bodies() gives the carriers of a body only"
        names = [self.names.take(f"{prefix}_{body}") for prefix in INERTIAL_PARAMETERS]
        if names != [f"{prefix}_{body}" for prefix in INERTIAL_PARAMETERS]:
            raise ModelError(f"the inertial parameters of link `{body}` cannot be named `m_{body}`, ...: a "
                             "name is taken by a joint or another link", file=self.robot.source,
                             line=carrier.line, symbol=body, fix="rename the link or joint whose name clashes")
        first = mass * center
        at_origin = _clean(inertia + mass * (float(center @ center) * np.eye(3) - np.outer(center, center)))
        values = [mass, *first, at_origin[0, 0], at_origin[0, 1], at_origin[0, 2], at_origin[1, 1],
                  at_origin[1, 2], at_origin[2, 2]]
        units = ["kg", *["kg*m"] * 3, *["kg*m^2"] * 6]
        for name, value, unit, prefix in zip(names, values, units, INERTIAL_PARAMETERS, strict=True):
            what = {"m": ("masse", "mass"), "mx": ("moment statique m c_x", "first moment m c_x"),
                    "my": ("moment statique m c_y", "first moment m c_y"),
                    "mz": ("moment statique m c_z", "first moment m c_z")}.get(
                prefix, (f"inertie {prefix[1:]} en l'origine", f"inertia {prefix[1:]} about the origin"))
            self.b.parameter(name, float(value), unit=unit,
                             description=Text({"fr": f"{what[0]} du corps `{body}` (repère {carrier.frame})",
                                               "en": f"{what[1]} of body `{body}` (frame {carrier.frame})"}))
        m, mx, my, mz, ixx, ixy, ixz, iyy, iyz, izz = (se.Symbol(name) for name in names)
        self.b.body(body, frame=carrier.frame, mass=m, center=Vector({carrier.frame: (mx / m, my / m, mz / m)}),
                    center_from=carrier.point,
                    inertia={"at": carrier.point, "frame": carrier.frame,
                             "matrix": [[ixx, ixy, ixz], [ixy, iyy, iyz], [ixz, iyz, izz]]},
                    location=self.where(carrier.line))

    def visuals(self) -> None:
        """Each link's ``<visual>`` elements as shapes of the body (or frame) that carries the link."""
        declared = {carrier.body for carrier in self.carriers if carrier.masses}
        for link in self.robot.links.values():
            carrier, r, p = self.pose[link.name]
            on = carrier.body if carrier.body is not None and carrier.body in declared else carrier.frame
            for visual in link.visuals:
                where = self.where(visual.line)
                mesh = None
                if visual.kind == "mesh":
                    mesh = self.mesh_path(visual, link.name)
                    if mesh is None:
                        continue
                r_visual = _clean(r @ rpy_matrix(visual.rpy), 1.0)
                center = _clean(p + r @ np.array(visual.xyz), max(1e-3, float(np.max(np.abs(p)))))
                dims = visual.dimensions
                sizes: dict[str, dict[str, Any]] = dict(box={"size": [_number(x) for x in dims]},
                                                        cylinder={"radius": _number(dims[0]) if dims else None,
                                                                  "length": _number(dims[1]) if len(dims) > 1
                                                                  else None},
                                                        sphere={"radius": _number(dims[0]) if dims else None},
                                                        mesh={"mesh": mesh, "scale": list(visual.scale)})
                size = sizes[visual.kind]
                color = opacity = None
                if visual.rgba is not None:
                    color, opacity = list(visual.rgba[:3]), visual.rgba[3]
                if any(v is not None and v == 0 for k, v in size.items() if k in ("radius", "length")) or (
                        visual.kind == "box" and 0 in dims):
                    continue  # a flat or empty visual (some exporters write them): nothing to draw
                self.b.shape(on, visual.kind, center=_vector(carrier.frame, center), from_point=carrier.point,
                             rotation=tuple(tuple(float(x) for x in row) for row in r_visual), color=color,
                             opacity=opacity, location=where, **size)

    def mesh_path(self, visual, link: str) -> str | None:
        """The mesh file of ``visual``: beside the URDF, absolute (``file://``), or ``package://name/...`` resolved
        in the first folder named ``name`` above the URDF; None, with a note, when it cannot be read."""
        from ._shapes import resolve_mesh

        name = visual.mesh
        base = Path(self.robot.source).resolve().parent if self.robot.source else Path.cwd()
        if name.startswith("package://"):
            package, _, rest = name[len("package://"):].partition("/")
            folder = next((d for d in (base, *base.parents) if d.name == package), None)
            if folder is None:
                warnings.warn(f"{self.robot.source or '<urdf>'}:{visual.line}: note: the mesh `{name}` of link "
                              f"`{link}` is in package `{package}`, which is no folder above the URDF: not drawn",
                              UrdfNote, stacklevel=4)
                return None
            name, base = rest, folder
        elif name.startswith("file://"):
            name = name[len("file://"):]
        try:
            return str(resolve_mesh(name, Location(self.robot.source, visual.line), owner=f"the mesh of link `{link}`",
                                    base=base))
        except ModelError as exc:
            warnings.warn(f"{self.robot.source or '<urdf>'}:{visual.line}: note: {exc.message}: not drawn", UrdfNote,
                          stacklevel=4)
            return None

    def efforts(self) -> None:
        """The actuators' τ_j (Q_j = τ_j, an input each) and the joints' viscous damping D = ½ Σ c_j q̇_j²."""
        components = {}
        for joint_name, names in self.coordinates.items():
            joint = self.robot.joints.get(joint_name)
            if joint is None or joint.type == "floating":
                continue  # a free body has no actuator
            for q in names:
                tau = self.names.take(q if joint.type == "planar" else joint_name, "tau_")
                force = joint.type == "prismatic" or (joint.type == "planar" and not q.endswith("theta"))
                what, quoi = ("force", "effort") if force else ("torque", "couple")
                self.b.input(tau, unit="N" if force else "N*m",
                             description=Text({"fr": f"{quoi} de l’actionneur de la liaison « {joint_name} »",
                                               "en": f"actuator {what} of joint “{joint_name}”"}),
                             location=self.where(joint.line))
                components[q] = se.Symbol(tau)
        if components:
            self.b.generalized_force("actuators", components)
        if not self.damping:
            return
        # Not of a floating or planar joint (no rate of its own in `self.rate`).
        damped = [j for j in self.robot.joints.values() if j.moves and j.damping > 0 and j.name in self.rate]
        terms = [se.Rational(1, 2) * _number(j.damping) * self.rate[j.name] ** 2 for j in damped]
        if terms:  # viscous friction in each of those joints: they are not perfect (the report says so)
            self.b.dissipation("joint_damping", se.Add(*terms),
                               joints=[self.coordinate[j.name] for j in damped if j.name in self.coordinate])
