"""Declaring how bodies and particles look: ``[shapes]`` of a model file, read into `Shape` values.

A shape plays no part in the dynamics: the 3-D view and the animation draw it
(`lagrangian.view3d`), and infer one from the inertia and the points wherever the model
gives none.  In a model file::

    [shapes]
    S = { kind = "disk", radius = "r", thickness = 0.01, color = "#d62728" }
    rod = { kind = "rod", between = ["O", "A"], radius = 0.01 }      # a rod between two points
    P = { kind = "sphere", radius = 0.05, opacity = 0.6 }
    arm = { kind = "mesh", mesh = "arm.stl", scale = 0.001 }          # beside the model file
    [[shapes.S2]]                                                      # several shapes on one body
    kind = "cylinder"  ...

or as ``shape = { ... }`` inside ``[bodies.S]`` or ``[particles.P]``.  Sizes are numbers or
expressions in the parameters (read by the project's grammar, never evaluated as code);
``axis`` is an axis of the body's frame (``"x"``, ``"-y"``...) or three numbers; ``center``
a vector from ``from`` (default the body's G, the particle itself); colours are ``#rgb``,
``#rrggbb``, a basic CSS colour name or three numbers in [0, 1].  A mesh file is checked here
(suffix, existence, size) and read by the view, whose errors also name this declaration.
"""

from __future__ import annotations

import math
import re
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
import symengine as se

from ..errors import ModelError
from .spec import GALILEAN_FRAME, SHAPE_KINDS, Body, Frame, Location, Particle, Point, Shape
from .vectors import Vector

if TYPE_CHECKING:  # pragma: no cover
    from ._assemble import Assembler, Raw
    from ._toml import _Reader
    from .build import ModelBuilder

__all__ = [
    "COLORS",
    "MAX_MESH_BYTES",
    "MESH_SUFFIXES",
    "SHAPE_KEYS",
    "build_shapes",
    "declare_shapes_from_toml",
    "parse_color",
    "rotation_to",
]

#: The keys each kind takes, beside the common ones (`_COMMON`).
SHAPE_KEYS = {
    "sphere": {"radius"},
    "cylinder": {"radius", "length", "axis"},
    "disk": {"radius", "thickness", "axis"},
    "box": {"size"},
    "rod": {"radius", "length", "axis", "between"},
    "mesh": {"mesh", "scale"},
}
_COMMON = {"kind", "center", "from", "color", "opacity", "rotation"}
#: Mesh files the view reads: STL (binary or ASCII), Wavefront OBJ, COLLADA.
MESH_SUFFIXES = (".stl", ".obj", ".dae")
#: Largest mesh file accepted (the Panda's largest visual mesh is 1.6 MB).
MAX_MESH_BYTES = 32 * 2**20
#: Basic CSS colour names (CSS Color Module Level 3, the 16 HTML names and a few common ones).
COLORS = {
    "black": "#000000", "silver": "#c0c0c0", "gray": "#808080", "grey": "#808080", "white": "#ffffff",
    "maroon": "#800000", "red": "#ff0000", "purple": "#800080", "fuchsia": "#ff00ff", "magenta": "#ff00ff",
    "green": "#008000", "lime": "#00ff00", "olive": "#808000", "yellow": "#ffff00", "navy": "#000080",
    "blue": "#0000ff", "teal": "#008080", "aqua": "#00ffff", "cyan": "#00ffff", "orange": "#ffa500",
    "brown": "#a52a2a", "pink": "#ffc0cb", "gold": "#ffd700", "steelblue": "#4682b4", "darkgray": "#a9a9a9",
    "darkgrey": "#a9a9a9", "lightgray": "#d3d3d3", "lightgrey": "#d3d3d3",
}
_HEX = re.compile(r"#([0-9a-fA-F]{3}|[0-9a-fA-F]{6})\Z")


def parse_color(value: Any) -> str:
    """``value`` as ``#rrggbb``; ValueError (with what was wrong) when it is not a colour.

    >>> parse_color("#c33"), parse_color("Steelblue"), parse_color([1, 0.5, 0])
    ('#cc3333', '#4682b4', '#ff8000')
    """
    if isinstance(value, str):
        text = value.strip()
        if _HEX.match(text):
            digits = text[1:]
            if len(digits) == 3:
                digits = "".join(c * 2 for c in digits)
            return "#" + digits.lower()
        if text.lower() in COLORS:
            return COLORS[text.lower()]
        raise ValueError(f"`{value[:40]}` is not a colour")
    if isinstance(value, Sequence) and len(value) in (3, 4) and all(
            isinstance(v, (int, float)) and not isinstance(v, bool) for v in value):
        rgb = [float(v) for v in value[:3]]
        if all(math.isfinite(v) and 0.0 <= v <= 1.0 for v in rgb):
            return "#" + "".join(f"{round(v * 255):02x}" for v in rgb)
        raise ValueError(f"the components {list(value)} are not three numbers in [0, 1]")
    raise ValueError(f"`{str(value)[:40]}` is not a colour")


# -- the model file ----------------------------------------------------------------------------------------------
def declare_shapes_from_toml(reader: _Reader, b: ModelBuilder) -> None:
    """The ``[shapes]`` table and the ``shape`` key of bodies and particles, declared on ``b``."""
    entries: list[tuple[tuple[str, ...], str, Any]] = []
    for table in ("bodies", "particles"):
        for name, value in reader.table(table).items():
            if isinstance(value, dict) and "shape" in value:
                entries.append(((table, name, "shape"), name, value["shape"]))
    for name, value in reader.table("shapes").items():
        entries.append((("shapes", name), name, value))
    for path, on, value in entries:
        items = value if isinstance(value, list) else [value]
        for item in items:
            if not isinstance(item, dict):
                raise reader.fail(path, f"the shape of `{on}` must be a table, not `{str(item)[:40]}`", symbol=on,
                                  fix='e.g. S = { kind = "cylinder", radius = 0.1, length = 0.5 }')
            where = reader.at(*path)
            keys = []
            for key in item:
                hit = reader.index.get((*path, key))
                if hit is not None:
                    keys.append((key, hit[0], 0))
            b.shape(on, location=Location(where.file, where.line, tuple(keys)), **item)


# -- the checks --------------------------------------------------------------------------------------------------
def build_shapes(asm: Assembler, raws: Sequence[Raw], bodies: Sequence[Body], particles: Sequence[Particle],
                 frames: Sequence[Frame], points: Mapping[str, Point]) -> tuple[Shape, ...]:
    """The checked `Shape` of each ``shape`` declaration, in order."""
    owners: dict[str, tuple[str, Vector]] = {b.name: (b.frame, b.center) for b in bodies}
    owners.update({p.name: (GALILEAN_FRAME, p.position) for p in particles})
    frame_names = {f.name for f in frames}
    return tuple(_Shape(asm, raw, owners, frame_names, points).build() for raw in raws)


class _Shape:
    """One declaration's checks, each error at the declaration's (or its key's) line."""

    def __init__(self, asm: Assembler, raw: Raw, owners: Mapping[str, tuple[str, Vector]], frames: set[str],
                 points: Mapping[str, Point]) -> None:
        self.asm, self.raw, self.owners, self.frames, self.points = asm, raw, owners, frames, points
        self.data = raw.data

    def fail(self, message: str, *, key: str | None = None, fix: str) -> ModelError:
        return self.asm.error(self.raw, message, key=key, symbol=self.raw.name, fix=fix)

    def build(self) -> Shape:
        on, d = self.raw.name, self.data
        if on not in self.owners and on not in self.frames:
            known = ", ".join(sorted(self.owners)) or "none"
            raise self.fail(f"a shape is given to `{on}`, which is not a body or a particle of the model",
                            fix=f"give shapes to bodies or particles (here: {known}), or correct the name")
        kind = d.get("kind")
        if kind not in SHAPE_KINDS:
            raise self.fail(f"the shape of `{on}` has kind `{kind}`" if kind is not None else
                            f"the shape of `{on}` has no `kind`", key="kind",
                            fix="kind is one of " + ", ".join(SHAPE_KINDS))
        allowed = _COMMON | SHAPE_KEYS[kind]
        unknown = sorted(k for k, v in d.items() if v is not None and k not in allowed)
        if unknown:
            raise self.fail(f"a {kind} has no key `{unknown[0]}` (shape of `{on}`)", key=unknown[0],
                            fix=f"the keys of a {kind} are " + ", ".join(sorted(allowed)))
        frame, origin = self.owners.get(on, (on, Vector.zero()))
        if d.get("from") is not None:
            if d["from"] not in self.points:
                raise self.fail(f"the shape of `{on}` is placed from unknown point `{d['from']}`", key="from",
                                fix="use a declared point, a body (its centre G) or a particle")
            origin = self.points[d["from"]].position
        center = origin
        if d.get("center") is not None:
            center = origin + self.asm.expr(self.raw, "the centre of the shape", d["center"], vector=True,
                                            key="center")
        radius = self.size("radius", kind)
        length = self.size("thickness" if kind == "disk" else "length", kind)
        size = None
        if kind == "box":
            values = d.get("size")
            if not isinstance(values, Sequence) or isinstance(values, str) or len(values) != 3:
                raise self.fail(f"the box of `{on}` needs `size`, its three sides", key="size",
                                fix='e.g. size = [0.4, 0.2, "h"]')
            size = tuple(self.expression(v, "size") for v in values)
        if kind in ("sphere", "cylinder", "disk") and radius is None:
            raise self.fail(f"the {kind} of `{on}` has no `radius`", key="radius", fix="give radius = ...")
        if kind == "cylinder" and length is None:
            raise self.fail(f"the cylinder of `{on}` has no `length`", key="length", fix="give length = ...")
        ends = self.ends(kind)
        if kind == "rod" and ends is None and length is None:
            raise self.fail(f"the rod of `{on}` needs its ends (`between`) or its `length`", key="between",
                            fix='e.g. between = ["O", "A"]')
        return Shape(on, kind, frame, center, rotation=self.axis(kind), radius=radius, length=length,
                     size=size, ends=ends, mesh=self.mesh(kind), scale=self.scale(), color=self.color(),
                     opacity=self.opacity(), location=self.raw.location)

    def expression(self, value: Any, key: str) -> se.Basic:
        """A size: constant (parameters only), positive and finite where the values are known."""
        what = "thickness" if key == "thickness" else key
        expr = self.asm.expr(self.raw, f"the {what} of the shape", value, key=key)
        moving = sorted(str(s) for s in expr.free_symbols if s not in self.asm.constants)
        if moving:
            raise self.fail(f"the {what} of the shape of `{self.raw.name}` depends on `{moving[0]}`: a shape's "
                            "sizes are constants", key=key, fix="write it with numbers and parameters only")
        known = {s: v for s, v in self.asm.constants.items() if v is not None}
        if expr.free_symbols <= set(known):
            try:
                number = float(expr.subs(known))
            except (TypeError, RuntimeError, ValueError):
                number = math.nan
            if not (math.isfinite(number) and number > 0):
                raise self.fail(f"the {what} of the shape of `{self.raw.name}` is {number:g}: a size is a positive "
                                "number", key=key, fix="give a positive size")
        return expr

    def size(self, key: str, kind: str) -> se.Basic | None:
        value = self.data.get(key)
        return None if value is None else self.expression(value, key)

    def ends(self, kind: str) -> tuple[str, str] | None:
        value = self.data.get("between")
        if value is None:
            return None
        if (not isinstance(value, Sequence) or isinstance(value, str) or len(value) != 2
                or not all(isinstance(v, str) for v in value)):
            raise self.fail(f"`between` of the rod of `{self.raw.name}` must name two points", key="between",
                            fix='e.g. between = ["O", "A"]')
        for name in value:
            if name not in self.points:
                raise self.fail(f"the rod of `{self.raw.name}` ends at unknown point `{name}`", key="between",
                                fix="use declared points (or a body's centre, or a particle)")
        return (value[0], value[1])

    def axis(self, kind: str) -> tuple[tuple[float, float, float], ...] | None:
        """The rotation taking the shape's z to the given axis of the frame (None: no axis given)."""
        if self.data.get("rotation") is not None:
            m = np.array(self.data["rotation"], dtype=float)
            if m.shape != (3, 3) or not np.allclose(m @ m.T, np.eye(3), atol=1e-9) or np.linalg.det(m) < 0:
                raise self.fail(f"`rotation` of the shape of `{self.raw.name}` is not a rotation matrix", key="rotation",
                                fix="give three rows of three numbers, an orthogonal matrix of determinant 1")
            return tuple((float(row[0]), float(row[1]), float(row[2])) for row in m)
        value = self.data.get("axis")
        if value is None:
            return None
        if isinstance(value, str):
            named = re.fullmatch(r"\s*([+-]?)\s*([xyz])\s*", value)
            if not named:
                raise self.fail(f"`axis` `{value[:40]}` of the shape of `{self.raw.name}` is not an axis",
                                key="axis", fix='write "x", "y", "z" (or "-x"...), or three numbers [ax, ay, az]')
            direction = np.eye(3)["xyz".index(named.group(2))] * (-1.0 if named.group(1) == "-" else 1.0)
        else:
            ok = (isinstance(value, Sequence) and len(value) == 3
                  and all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in value))
            direction = np.array([float(v) for v in value]) if ok else np.zeros(3)
            if not (ok and np.all(np.isfinite(direction)) and np.linalg.norm(direction) > 0):
                raise self.fail(f"`axis` of the shape of `{self.raw.name}` must be an axis or three numbers, not "
                                f"`{str(value)[:40]}`", key="axis", fix='e.g. axis = "x" or axis = [0, 1, 1]')
        return rotation_to(direction / np.linalg.norm(direction))

    def mesh(self, kind: str) -> str | None:
        value = self.data.get("mesh")
        if kind != "mesh":
            return None
        if not isinstance(value, str) or not value.strip():
            raise self.fail(f"the mesh of `{self.raw.name}` names no file", key="mesh",
                            fix='give the file, e.g. mesh = "part.stl" (STL, OBJ or DAE, beside the model file)')
        return str(resolve_mesh(value, self.raw.location, owner=f"the mesh of `{self.raw.name}`",
                                key_location=self.raw.location.of("mesh")))

    def scale(self) -> tuple[float, float, float]:
        value = self.data.get("scale")
        if value is None:
            return (1.0, 1.0, 1.0)
        values = [value] * 3 if isinstance(value, (int, float)) and not isinstance(value, bool) else value
        ok = (isinstance(values, Sequence) and not isinstance(values, str) and len(values) == 3
              and all(isinstance(v, (int, float)) and not isinstance(v, bool) and math.isfinite(v) and v != 0
                      for v in values))
        if not ok:
            raise self.fail(f"`scale` of the mesh of `{self.raw.name}` must be a nonzero number or three",
                            key="scale", fix="e.g. scale = 0.001 (a mesh in millimetres) or [1, 1, 2]")
        return tuple(float(v) for v in values)  # type: ignore[return-value]

    def color(self) -> str | None:
        value = self.data.get("color")
        if value is None:
            return None
        try:
            return parse_color(value)
        except ValueError as exc:
            raise self.fail(f"the colour of the shape of `{self.raw.name}`: {exc}", key="color",
                            fix='write "#rrggbb", "#rgb", a CSS name such as "steelblue", or [r, g, b] in [0, 1]') \
                from None

    def opacity(self) -> float | None:
        value = self.data.get("opacity")
        if value is None:
            return None
        if not (isinstance(value, (int, float)) and not isinstance(value, bool) and 0 <= value <= 1):
            raise self.fail(f"the opacity of the shape of `{self.raw.name}` is `{str(value)[:40]}`, not a number in "
                            "[0, 1]", key="opacity", fix="0 is invisible, 1 opaque: e.g. opacity = 0.5")
        return float(value)


def rotation_to(axis: np.ndarray) -> tuple[tuple[float, float, float], ...]:
    """A rotation (columns: the new x, y, z) taking z to the unit ``axis`` by the shortest turn.

    Parameters
    ----------
    axis : ndarray of shape (3,)
        A unit vector.

    Returns
    -------
    tuple of three tuples of three float
        The rotation matrix.
    """
    z = np.array([0.0, 0.0, 1.0])
    v = np.cross(z, axis)
    s, c = float(np.linalg.norm(v)), float(axis @ z)
    if s < 1e-15:
        m = np.eye(3) if c > 0 else np.diag([1.0, -1.0, -1.0])
    else:
        k = np.array([[0, -v[2], v[1]], [v[2], 0, -v[0]], [-v[1], v[0], 0]]) / s
        m = np.eye(3) + s * k + (1 - c) * (k @ k)
    return tuple((float(row[0]), float(row[1]), float(row[2])) for row in m)


def resolve_mesh(name: str, where: Location, *, owner: str, key_location: Location | None = None,
                 base: Path | None = None) -> Path:
    """The mesh file ``name`` (relative to the model file's folder, or ``base``), checked: suffix, existence, size.

    Raises
    ------
    ModelError
        At the declaration's line, naming the file and the fix.
    """
    loc = key_location or where
    path = Path(name)
    if not path.is_absolute():
        folder = base if base is not None else (Path(where.file).parent if where.file else Path.cwd())
        path = folder / path
    if path.suffix.lower() not in MESH_SUFFIXES:
        raise ModelError(f"{owner} is `{name}`, whose format the view cannot read", file=loc.file, line=loc.line,
                         symbol=name, fix="give an STL (.stl), Wavefront OBJ (.obj) or COLLADA (.dae) file")
    try:
        size = path.stat().st_size
        is_file = path.is_file()
    except OSError:
        raise ModelError(f"{owner}, `{name}`, does not exist (looked for `{path}`)", file=loc.file, line=loc.line,
                         symbol=name, fix="check the file name; a relative path starts at the model file's folder") \
            from None
    if not is_file:
        raise ModelError(f"{owner}, `{name}`, is not a file", file=loc.file, line=loc.line, symbol=name,
                         fix="name the mesh file itself")
    if size > MAX_MESH_BYTES:
        raise ModelError(f"{owner}, `{name}`, is {size / 2**20:.0f} MB, more than the {MAX_MESH_BYTES // 2**20} MB "
                         "the view reads", file=loc.file, line=loc.line, symbol=name,
                         fix="simplify the mesh (fewer triangles), e.g. with a mesh decimation tool")
    return path.resolve()
