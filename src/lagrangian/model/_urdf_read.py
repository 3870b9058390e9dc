"""Read a URDF file into plain, checked records of links and joints, each with its line.

URDF (the Unified Robot Description Format of ROS) describes a robot as a tree of
*links* (rigid bodies: mass, centre of mass and inertia in ``<inertial>``) joined by
*joints* (``revolute``, ``continuous``, ``prismatic``, ``fixed``...), each placing its
child link relative to its parent link by an ``<origin xyz rpy>`` and moving it about or
along its ``<axis>``.  Specification: http://wiki.ros.org/urdf/XML (links, joints).

Files come from strangers, so the XML is read by defusedxml's parser, which refuses
entity declarations (the "billion laughs" bomb), external entities and external DTDs
before expat expands anything; nothing in the file is executed or fetched.  Every
element keeps its line, so each error says file, line, element and name.

What this module checks (without any kinematics): numbers are plain finite decimals,
names are unique, every joint joins two known links, the links form one tree (no link
with two parent joints, no cycle), axes have a length, masses are positive and inertia
matrices physical.  Building the `Model` is `lagrangian.model.urdf`'s job.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass, field
from pathlib import Path
from typing import overload

import numpy as np

from ..errors import ModelError

__all__ = ["UrdfInertial", "UrdfVisual", "UrdfLink", "UrdfLimits", "UrdfMimic", "UrdfJoint", "UrdfRobot", "read_urdf_text",
           "read_urdf_file",
           "MAX_BYTES", "SUPPORTED_JOINTS"]

#: Largest URDF accepted, in bytes: the largest robot of example-robot-data (TIAGo dual) is 210 kB,
#: and a 5 MB file of tens of thousands of links already takes seconds to read.
MAX_BYTES = 5 * 2**20
#: Joint types that become the model's joints (a floating joint makes its child link a free body).
SUPPORTED_JOINTS = ("revolute", "continuous", "prismatic", "fixed", "floating", "planar")
#: A plain decimal number (Python's float() also reads "1_0", "infinity" and other digits).
_NUMBER = re.compile(r"[+-]?(?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d+)?\Z", re.ASCII)
#: Relative tolerance of the physical checks of an inertia matrix (rounding of the file's digits).
_INERTIA_TOL = 1e-9


@dataclass(frozen=True, slots=True)
class UrdfInertial:
    """``<inertial>``: mass m, the frame of the centre of mass (origin xyz, rpy) and I_G in that frame."""

    mass: float
    xyz: tuple[float, float, float]
    rpy: tuple[float, float, float]
    inertia: np.ndarray  # 3×3, symmetric: [[ixx, ixy, ixz], [ixy, iyy, iyz], [ixz, iyz, izz]]
    line: int


@dataclass(frozen=True, slots=True)
class UrdfVisual:
    """``<visual>``: a box (``size``), cylinder (radius, length), sphere (radius) or mesh (file, scale), placed
    by its origin (xyz, rpy) in the link's frame, with its material's colour (r, g, b, a) when given."""

    kind: str
    dimensions: tuple[float, ...]
    xyz: tuple[float, float, float]
    rpy: tuple[float, float, float]
    mesh: str | None
    scale: tuple[float, float, float]
    rgba: tuple[float, float, float, float] | None
    line: int


@dataclass(frozen=True, slots=True)
class UrdfLink:
    """``<link>``: a rigid body, massless when it has no ``<inertial>`` (or a zero one), and how it looks."""

    name: str
    line: int
    inertial: UrdfInertial | None
    visuals: tuple[UrdfVisual, ...] = ()


@dataclass(frozen=True, slots=True)
class UrdfLimits:
    """``<limit>`` of a joint: position range, largest effort and speed (None where not given)."""

    lower: float | None = None
    upper: float | None = None
    effort: float | None = None
    velocity: float | None = None


@dataclass(frozen=True, slots=True)
class UrdfMimic:
    """``<mimic joint multiplier offset>``: this joint's value is multiplier·q_joint + offset."""

    joint: str
    multiplier: float
    offset: float
    line: int


@dataclass(frozen=True, slots=True)
class UrdfJoint:
    """``<joint>``: type, parent and child links, origin (xyz, rpy), unit axis, limits, mimic, damping."""

    name: str
    type: str
    parent: str
    child: str
    xyz: tuple[float, float, float]
    rpy: tuple[float, float, float]
    axis: tuple[float, float, float]
    limits: UrdfLimits
    mimic: UrdfMimic | None
    damping: float
    friction: float
    line: int

    @property
    def moves(self) -> bool:
        """Whether the joint has a degree of freedom (not ``fixed``)."""
        return self.type != "fixed"


@dataclass(frozen=True, slots=True)
class UrdfRobot:
    """The checked tree: links and joints in file order, the root link, and notes on what was skipped."""

    name: str
    source: str | None
    links: dict[str, UrdfLink]
    joints: dict[str, UrdfJoint]
    root: str
    notes: tuple[str, ...] = field(default=())
    #: link -> the names of the joints whose parent it is, in file order (filled when read)
    child_joints: dict[str, tuple[str, ...]] = field(default_factory=dict, repr=False)

    def children(self, link: str) -> list[UrdfJoint]:
        """The joints whose parent is ``link``, in file order."""
        return [self.joints[name] for name in self.child_joints.get(link, ())]


# -- the safe XML parse, with lines ---------------------------------------------------------------------
class _Element:
    """An XML element: tag (namespace dropped), attributes, children and line of its start tag."""

    __slots__ = ("tag", "attrib", "children", "line")

    def __init__(self, tag: str, attrib: dict[str, str], line: int) -> None:
        self.tag = tag.rpartition("}")[2]
        self.attrib = attrib
        self.children: list[_Element] = []
        self.line = line

    def find(self, tag: str) -> _Element | None:
        for child in self.children:
            if child.tag == tag:
                return child
        return None


class _Builder:
    """The parser's target: builds `_Element`s, reading each start tag's line from expat."""

    def __init__(self) -> None:
        self.expat = None
        self.stack: list[_Element] = []
        self.root: _Element | None = None

    def start(self, tag: str, attrib: dict[str, str]) -> None:
        element = _Element(tag, dict(attrib), self.expat.CurrentLineNumber if self.expat else 0)
        if self.stack:
            self.stack[-1].children.append(element)
        else:
            self.root = element
        self.stack.append(element)

    def end(self, tag: str) -> None:
        self.stack.pop()

    def data(self, text: str) -> None:  # text content plays no part in URDF's geometry
        pass

    def close(self) -> _Element | None:
        return self.root


def _parse_xml(data: bytes, source: str | None) -> _Element:
    """The element tree of ``data``; entities, external references and malformed XML refused with their line."""
    try:
        from defusedxml import DefusedXmlException
        from defusedxml.ElementTree import DefusedXMLParser, ParseError
    except ImportError:  # pragma: no cover - defusedxml is a dependency
        raise ModelError("reading a URDF needs the `defusedxml` package (a safe XML parser)", file=source,
                         fix="install it: pip install defusedxml") from None
    builder = _Builder()
    parser = DefusedXMLParser(target=builder, forbid_dtd=False, forbid_entities=True, forbid_external=True)
    builder.expat = parser.parser
    try:
        parser.feed(data)
        root = parser.close()
    except DefusedXmlException as exc:
        kind = type(exc).__name__
        what = ("declares an entity (`<!ENTITY ...>`)" if kind == "EntitiesForbidden" else
                "refers to an external entity" if kind == "ExternalReferenceForbidden" else "has a DTD")
        raise ModelError(f"the URDF {what}; entities are refused (an XML bomb or a file read can hide there)",
                         file=source, line=parser.parser.CurrentLineNumber, symbol=getattr(exc, "name", None),
                         fix="remove the <!DOCTYPE ...> and <!ENTITY ...> declarations and write the values out "
                             "(xacro files must be expanded first: `xacro robot.urdf.xacro > robot.urdf`)") from None
    except ParseError as exc:
        line, column = getattr(exc, "position", (None, None))
        message = str(exc).split(": line")[0]
        raise ModelError(f"the URDF is not well-formed XML: {message}", file=source, line=line,
                         column=None if column is None else column + 1,
                         fix="correct the XML at that place (every tag closed, attributes in quotes)") from None
    if root is None:  # pragma: no cover - expat reports an empty document as a ParseError
        raise ModelError("the URDF is empty", file=source, fix="give a <robot> element")
    return root


# -- reading the elements ----------------------------------------------------------------------------------------
class _Reader:
    def __init__(self, source: str | None) -> None:
        self.source = source
        self.notes: list[str] = []
        self.materials: dict[str, tuple[float, ...]] = {}

    def fail(self, element: _Element | int, message: str, *, fix: str, symbol: str | None = None) -> ModelError:
        line = element if isinstance(element, int) else element.line
        return ModelError(message, fix=fix, file=self.source, line=line, symbol=symbol)

    def note(self, element: _Element, message: str) -> None:
        self.notes.append(f"{self.source or '<urdf>'}:{element.line}: note: {message}")

    def name(self, element: _Element, what: str) -> str:
        name = element.attrib.get("name")
        if not name or not name.strip():
            raise self.fail(element, f"<{element.tag}> without a `name`", fix=f'give the {what} a name, e.g. '
                            f'<{element.tag} name="{what}1">')
        return name

    def numbers(self, element: _Element, key: str, count: int, default: tuple[float, ...] | None,
                owner: str) -> tuple[float, ...]:
        text = element.attrib.get(key)
        if text is None:
            if default is None:
                raise self.fail(element, f"<{element.tag}> of {owner} has no `{key}`", symbol=key,
                                fix=f'give it, e.g. <{element.tag} {key}="{" ".join(["0"] * count)}"/>')
            return default
        words = text.split()
        out = []
        for word in words:
            value = float(word) if _NUMBER.match(word) else math.nan
            if not math.isfinite(value):
                raise self.fail(element, f"`{key}` of <{element.tag}> of {owner} must be {count} finite decimal "
                                f"number{'s' if count > 1 else ''}: `{word[:40]}` is not one", symbol=key,
                                fix="write plain decimal numbers such as 0.25 or -1.5e-3, separated by spaces")
            out.append(value)
        if len(out) != count:
            raise self.fail(element, f"`{key}` of <{element.tag}> of {owner} must hold {count} number"
                            f"{'s' if count > 1 else ''}, not {len(out)}: `{text[:60]}`", symbol=key,
                            fix=f'e.g. {key}="{" ".join(["0"] * count)}"')
        return tuple(out)

    @overload
    def number(self, element: _Element | None, key: str, owner: str, default: float) -> float: ...

    @overload
    def number(self, element: _Element | None, key: str, owner: str, default: None) -> float | None: ...

    def number(self, element: _Element | None, key: str, owner: str, default: float | None) -> float | None:
        if element is None or key not in element.attrib:
            return default
        return self.numbers(element, key, 1, None, owner)[0]

    def origin(self, parent: _Element, owner: str) -> tuple[tuple[float, ...], tuple[float, ...]]:
        origin = parent.find("origin")
        if origin is None:
            return (0.0, 0.0, 0.0), (0.0, 0.0, 0.0)
        return (self.numbers(origin, "xyz", 3, (0.0, 0.0, 0.0), owner),
                self.numbers(origin, "rpy", 3, (0.0, 0.0, 0.0), owner))

    # -- links -------------------------------------------------------------------------------
    def link(self, element: _Element) -> UrdfLink:
        name = self.name(element, "link")
        owner = f"link `{name}`"
        visuals = tuple(v for v in (self.visual(child, owner) for child in element.children
                                    if child.tag == "visual") if v is not None)
        inertial = element.find("inertial")
        if inertial is None:
            return UrdfLink(name, element.line, None, visuals)
        mass_el = inertial.find("mass")
        if mass_el is None:
            raise self.fail(inertial, f"the <inertial> of {owner} has no <mass>", symbol=name,
                            fix='give it, e.g. <mass value="1.0"/>, or remove <inertial> for a massless link')
        mass = self.numbers(mass_el, "value", 1, None, owner)[0]
        inertia_el = inertial.find("inertia")
        if inertia_el is None:
            raise self.fail(inertial, f"the <inertial> of {owner} has no <inertia>: its mass {mass:g} kg is "
                            "given but not how it is spread", symbol=name,
                            fix='give <inertia ixx="..." ixy="0" ixz="0" iyy="..." iyz="0" izz="..."/> '
                                "(the inertia at the centre of mass, in the <inertial>'s frame)")
        i = {k: self.numbers(inertia_el, k, 1, None, owner)[0] for k in ("ixx", "ixy", "ixz", "iyy", "iyz", "izz")}
        matrix = np.array([[i["ixx"], i["ixy"], i["ixz"]], [i["ixy"], i["iyy"], i["iyz"]],
                           [i["ixz"], i["iyz"], i["izz"]]])
        if mass < 0 or (mass == 0 and np.any(matrix != 0)):
            raise self.fail(mass_el, f"the mass of {owner} is {mass:g} kg: a link's mass must be positive",
                            symbol=name, fix="give its positive mass in kg; for a massless link (a frame) remove "
                            "the <inertial> element or set the mass and every inertia entry to 0")
        self.check_inertia(inertia_el, matrix, owner, name)
        if mass == 0:
            return UrdfLink(name, element.line, None, visuals)  # the zero <inertial> of many exported frames
        xyz, rpy = self.origin(inertial, owner)
        inertial_data = UrdfInertial(mass, xyz, rpy, matrix, inertial.line)  # type: ignore[arg-type]
        return UrdfLink(name, element.line, inertial_data, visuals)

    def visual(self, element: _Element, owner: str) -> UrdfVisual | None:
        """A ``<visual>``'s geometry, origin and colour; None (with a note) for a geometry URDF does not define."""
        geometry = element.find("geometry")
        shape = geometry.children[0] if geometry is not None and geometry.children else None
        if shape is None or shape.tag not in ("box", "cylinder", "sphere", "mesh"):
            self.note(element, f"a <visual> of {owner} has no box, cylinder, sphere or mesh geometry: not drawn")
            return None
        xyz, rpy = self.origin(element, owner)
        mesh, scale = None, (1.0, 1.0, 1.0)
        if shape.tag == "box":
            dims = self.numbers(shape, "size", 3, None, owner)
        elif shape.tag == "cylinder":
            dims = (self.numbers(shape, "radius", 1, None, owner)[0], self.numbers(shape, "length", 1, None, owner)[0])
        elif shape.tag == "sphere":
            dims = self.numbers(shape, "radius", 1, None, owner)
        else:
            dims = ()
            mesh = shape.attrib.get("filename")
            if not mesh:
                raise self.fail(shape, f"the <mesh> of {owner} has no `filename`", symbol="filename",
                                fix='name the mesh file, e.g. <mesh filename="meshes/link1.stl"/>')
            scale = self.numbers(shape, "scale", 3, (1.0, 1.0, 1.0), owner)  # type: ignore[assignment]
        if any(d < 0 for d in dims):
            raise self.fail(shape, f"a size of the <{shape.tag}> of {owner} is negative", symbol=shape.tag,
                            fix="sizes are lengths in metres, ≥ 0")
        material = element.find("material")
        rgba = None
        if material is not None:
            color = material.find("color")
            if color is not None:
                rgba = self.numbers(color, "rgba", 4, None, owner)
                if not all(0 <= c <= 1 for c in rgba):
                    raise self.fail(color, f"the colour of {owner} has components outside [0, 1]", symbol="rgba",
                                    fix='rgba holds four numbers in [0, 1], e.g. rgba="0.8 0.1 0.1 1"')
            elif material.attrib.get("name"):
                rgba = self.materials.get(material.attrib["name"])
        return UrdfVisual(shape.tag, dims, xyz, rpy, mesh, scale, rgba, element.line)  # type: ignore[arg-type]

    def read_materials(self, root: _Element) -> None:
        """The colours of the robot's named ``<material>`` elements, which a visual may refer to by name."""
        for element in root.children:
            color = element.find("color") if element.tag == "material" else None
            if color is not None and element.attrib.get("name") and "rgba" in color.attrib:
                rgba = self.numbers(color, "rgba", 4, None, f"material `{element.attrib['name']}`")
                self.materials[element.attrib["name"]] = tuple(min(max(c, 0.0), 1.0) for c in rgba)

    def check_inertia(self, element: _Element, matrix: np.ndarray, owner: str, name: str) -> None:
        """I_G must be positive semi-definite with each moment at most the sum of the other two.

        A zero inertia (a point mass) and a zero moment about one axis (a thin rod) are kept;
        a negative principal moment, or one larger than the two others together
        (A + B ≥ C for any body), is not the inertia of any mass distribution.
        """
        scale = max(float(np.max(np.abs(matrix))), 1e-300)
        moments = np.linalg.eigvalsh(matrix)
        tol = _INERTIA_TOL * scale
        if moments[0] < -tol:
            raise self.fail(element, f"the inertia of {owner} is not positive semi-definite: its principal "
                            f"moments are {', '.join(f'{m:.6g}' for m in moments)} kg·m²", symbol=name,
                            fix="check the signs of ixx, iyy, izz and the size of the products ixy, ixz, iyz "
                                "(URDF gives the matrix entries, the products of inertia with their minus sign)")
        a, b, c = moments
        if c > a + b + tol:
            raise self.fail(element, f"the inertia of {owner} breaks the triangle inequality: its principal "
                            f"moments {a:.6g}, {b:.6g}, {c:.6g} kg·m² have {c:.6g} > {a:.6g} + {b:.6g}",
                            symbol=name, fix="no mass distribution has such moments; check ixx, iyy and izz")

    # -- joints ------------------------------------------------------------------------------
    def joint(self, element: _Element) -> UrdfJoint:
        name = self.name(element, "joint")
        owner = f"joint `{name}`"
        kind = element.attrib.get("type")
        if kind not in SUPPORTED_JOINTS:
            raise self.fail(element, f"{owner} has type `{kind}`, which is not a URDF joint type" if kind else
                            f"{owner} has no `type`", symbol=name,
                            fix="use revolute, continuous, prismatic, fixed, floating or planar")
        ends = {}
        for end in ("parent", "child"):
            el = element.find(end)
            if el is None or not el.attrib.get("link"):
                raise self.fail(el or element, f"{owner} has no <{end} link=\"...\"/>", symbol=name,
                                fix=f'name its {end} link, e.g. <{end} link="link1"/>')
            ends[end] = el.attrib["link"]
        xyz, rpy = self.origin(element, owner)
        axis: tuple[float, ...] = (1.0, 0.0, 0.0)  # URDF's default
        if kind != "fixed":
            axis_el = element.find("axis")
            if axis_el is not None:
                axis = self.numbers(axis_el, "xyz", 3, (1.0, 0.0, 0.0), owner)
                norm = math.sqrt(sum(a * a for a in axis))
                if norm < 1e-9:
                    raise self.fail(axis_el, f"the axis of {owner} has length {norm:g}: a joint axis needs a "
                                    "direction", symbol=name, fix='give a non-zero direction, e.g. xyz="0 0 1"')
                axis = tuple(a / norm for a in axis)
        limit = element.find("limit")
        limits = UrdfLimits(*(self.number(limit, k, owner, None) for k in ("lower", "upper", "effort", "velocity")))
        mimic = None
        mimic_el = element.find("mimic")
        if mimic_el is not None:
            if not mimic_el.attrib.get("joint"):
                raise self.fail(mimic_el, f"the <mimic> of {owner} names no joint", symbol=name,
                                fix='name the joint it follows: <mimic joint="..." multiplier="1" offset="0"/>')
            mimic = UrdfMimic(mimic_el.attrib["joint"], self.number(mimic_el, "multiplier", owner, 1.0),
                              self.number(mimic_el, "offset", owner, 0.0), mimic_el.line)
        dynamics = element.find("dynamics")
        damping = self.number(dynamics, "damping", owner, 0.0)
        friction = self.number(dynamics, "friction", owner, 0.0)
        if dynamics is not None and damping < 0:  # without <dynamics>, both are 0
            raise self.fail(dynamics, f"the damping of {owner} is {damping:g}: a damper dissipates, its "
                            "coefficient is not negative", symbol=name,
                            fix="give a damping ≥ 0 (N·m·s/rad or N·s/m)")
        if dynamics is not None and friction:
            self.note(dynamics, f"the dry friction {friction:g} of {owner} is left out (only the viscous damping "
                      "is modelled)")
        return UrdfJoint(name, kind, ends["parent"], ends["child"], xyz, rpy, axis,  # type: ignore[arg-type]
                         limits, mimic, damping, friction, element.line)

    # -- the robot -------------------------------------------------------------------------------
    def robot(self, root: _Element) -> UrdfRobot:
        if root.tag != "robot":
            raise self.fail(root, f"the file's root element is <{root.tag}>, not <robot>: this is not a URDF",
                            symbol=root.tag, fix="give a URDF file, whose content is one <robot name=\"...\"> "
                                                 "element (expand xacro files first)")
        links: dict[str, UrdfLink] = {}
        joints: dict[str, UrdfJoint] = {}
        elements: dict[str, _Element] = {}
        skipped: dict[str, list[int]] = {}
        self.read_materials(root)
        for element in root.children:
            if element.tag == "link":
                link = self.link(element)
                self.unique(element, link.name, links, "link")
                links[link.name] = link
            elif element.tag == "joint":
                joint = self.joint(element)
                self.unique(element, joint.name, joints, "joint")
                joints[joint.name] = joint
                elements[joint.name] = element
            elif element.tag != "material":  # transmission, gazebo, ros2_control...: actuators, simulator settings
                skipped.setdefault(element.tag, []).append(element.line)
        for tag, lines in skipped.items():
            why = ("the joint efforts are the model's inputs tau_<joint> instead; gearing and motor inertia are "
                   "not modelled" if tag == "transmission" else "no part in the dynamics")
            self.notes.append(f"{self.source or '<urdf>'}:{lines[0]}: note: {len(lines)} <{tag}> element"
                              f"{'s' if len(lines) > 1 else ''} skipped ({why})")
        if not links:
            raise self.fail(root, "the URDF has no <link>", fix="describe the robot's links and joints")
        parent_joint: dict[str, UrdfJoint] = {}
        for joint in joints.values():
            for end in ("parent", "child"):
                link = getattr(joint, end)
                if link not in links:
                    raise self.fail(elements[joint.name].find(end) or elements[joint.name],
                                    f"joint `{joint.name}` has unknown {end} link `{link}`", symbol=link,
                                    fix="declare that <link>, or correct the name; links: "
                                        + ", ".join(list(links)[:12]) + (" ..." if len(links) > 12 else ""))
            if joint.child in parent_joint:
                first = parent_joint[joint.child]
                raise self.fail(elements[joint.name], f"link `{joint.child}` is the child of two joints, "
                                f"`{first.name}` (line {first.line}) and `{joint.name}`: the links form a closed "
                                "loop, which URDF cannot describe", symbol=joint.child,
                                fix="keep one of the two joints (a URDF is a tree); close the loop with a "
                                    "constraint in a TOML model instead")
            parent_joint[joint.child] = joint
        roots = [name for name in links if name not in parent_joint]
        if not roots:
            joint = next(iter(parent_joint.values()))
            raise self.fail(elements[joint.name], self.cycle_message(parent_joint, joint.child),
                            symbol=joint.child, fix="a URDF is a tree: remove a joint of the cycle")
        unreached = self.unreached(links, roots[0], parent_joint)
        if unreached:
            looped = parent_joint.get(unreached[0])
            if looped is not None and self.in_cycle(parent_joint, unreached[0]):
                raise self.fail(elements[looped.name], self.cycle_message(parent_joint, unreached[0]),
                                symbol=unreached[0], fix="a URDF is a tree: remove a joint of the cycle")
        if len(roots) > 1:
            raise self.fail(links[roots[1]].line, f"links `{roots[0]}` and `{roots[1]}` are both roots (no "
                            "joint has them as child): the robot is in separate pieces", symbol=roots[1],
                            fix=f"join `{roots[1]}` to the robot with a joint, or remove it")
        self.check_mimics(joints, elements)
        child_joints: dict[str, list[str]] = {}
        for joint in joints.values():
            child_joints.setdefault(joint.parent, []).append(joint.name)
        return UrdfRobot(root.attrib.get("name", ""), self.source, links, joints, roots[0], tuple(self.notes),
                         {link: tuple(names) for link, names in child_joints.items()})

    def unique(self, element: _Element, name: str, seen: dict, what: str) -> None:
        if name in seen:
            raise self.fail(element, f"two {what}s are named `{name}` (the first at line {seen[name].line})",
                            symbol=name, fix=f"rename one of them: {what} names are unique")

    @staticmethod
    def unreached(links: dict[str, UrdfLink], root: str, parent_joint: dict[str, UrdfJoint]) -> list[str]:
        children: dict[str, list[str]] = {}
        for child, joint in parent_joint.items():
            children.setdefault(joint.parent, []).append(child)
        seen, todo = {root}, [root]
        while todo:
            for child in children.get(todo.pop(), []):
                if child not in seen:
                    seen.add(child)
                    todo.append(child)
        return [name for name in links if name not in seen]

    @staticmethod
    def in_cycle(parent_joint: dict[str, UrdfJoint], link: str) -> bool:
        seen = set()
        while link in parent_joint and link not in seen:
            seen.add(link)
            link = parent_joint[link].parent
        return link in seen

    @staticmethod
    def cycle_message(parent_joint: dict[str, UrdfJoint], start: str) -> str:
        chain, link = [], start
        while link not in chain:
            chain.append(link)
            link = parent_joint[link].parent
        cycle = chain[chain.index(link):] + [link]
        return "the joints form a cycle: " + " → ".join(f"`{c}`" for c in reversed(cycle)) + " (parent to child)"

    def check_mimics(self, joints: dict[str, UrdfJoint], elements: dict[str, _Element]) -> None:
        for joint in joints.values():
            mimic = joint.mimic
            if mimic is None:
                continue
            led = joints.get(mimic.joint)
            problem = (f"follows unknown joint `{mimic.joint}`" if led is None else
                       "follows itself" if led.name == joint.name else
                       f"follows `{led.name}`, which is fixed" if not led.moves else
                       f"follows `{led.name}`, which itself follows `{led.mimic.joint}`" if led.mimic else
                       f"is {joint.type} but follows the {led.type} joint `{led.name}`"
                       if (joint.type == "prismatic") != (led.type == "prismatic") else None)
            if joint.type == "fixed":
                problem = "is fixed and cannot follow another joint"
            elif led is not None and {"floating", "planar"} & {joint.type, led.type}:
                problem = (f"makes the {joint.type} joint `{joint.name}` follow the {led.type} joint `{led.name}`: "
                           "only revolute, continuous and prismatic joints follow each other")
            if problem:
                raise self.fail(mimic.line, f"the <mimic> of joint `{joint.name}` {problem}", symbol=mimic.joint,
                                fix="name a moving joint of the same kind that follows no other joint")


def read_urdf_text(data: bytes | str, *, source: str | None = None) -> UrdfRobot:
    """Parse and check the URDF ``data`` (``source`` names it in messages)."""
    if isinstance(data, str):
        data = data.encode("utf-8")
    if len(data) > MAX_BYTES:
        raise ModelError(f"the URDF is {len(data) / 2**20:.0f} MB, more than the {MAX_BYTES // 2**20} MB read",
                         file=source, fix="give the robot's URDF (meshes stay in their own files)")
    reader = _Reader(source)
    return reader.robot(_parse_xml(data, source))


def read_urdf_file(path: str | Path) -> UrdfRobot:
    """`read_urdf_text` of the file at ``path``."""
    path = Path(path)
    try:
        size = path.stat().st_size
        if size > MAX_BYTES:
            raise ModelError(f"the URDF `{path}` is {size / 2**20:.0f} MB, more than the {MAX_BYTES // 2**20} MB "
                             "read", file=str(path), fix="give the robot's URDF (meshes stay in their own files)")
        data = path.read_bytes()
    except FileNotFoundError:
        raise ModelError(f"URDF file `{path}` does not exist", file=str(path), fix="check the path") from None
    except IsADirectoryError:
        raise ModelError(f"`{path}` is a directory, not a URDF file", file=str(path), fix="check the path") from None
    except OSError as exc:
        raise ModelError(f"cannot read URDF file `{path}`: {exc.strerror or exc}", file=str(path),
                         fix="check the path and its permissions") from None
    return read_urdf_text(data, source=str(path))
