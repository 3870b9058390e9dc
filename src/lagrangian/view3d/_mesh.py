"""Triangle meshes from STL (binary or ASCII), Wavefront OBJ and COLLADA (.dae) files, read as data.

Files come from strangers: nothing in them is executed, fetched or expanded.  COLLADA is XML,
read by defusedxml (no entity, no external reference, no DTD fetched), and only its geometry
is used: ``<triangles>``, ``<polylist>`` and ``<polygons>`` of ``<library_geometries>``,
placed by the ``<node>`` transforms (``<matrix>``, ``<translate>``, ``<rotate>``, ``<scale>``)
of its visual scene, in metres (``<unit meter>``), with ``<up_axis>`` turned to z, and each
group's diffuse colour.  Polygons are cut into triangles as fans.  Every problem is a
`ModelError` at the declaration of the shape (the model file and line), naming the mesh file
and, where it has one, the mesh's own line.

Specifications: STL (3D Systems, *StereoLithography Interface Specification*, 1989);
OBJ (Wavefront *Advanced Visualizer* manual, appendix B1); COLLADA 1.4.1 (Khronos, 2008).
"""

from __future__ import annotations

import math
import re
import struct
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from ..errors import ModelError
from ..model import Location

if TYPE_CHECKING:
    from xml.etree.ElementTree import Element

__all__ = ["MAX_TRIANGLES", "Mesh", "read_mesh"]

#: Most triangles a mesh may have (the Panda arm's eleven visual meshes have 170,000 in all).
MAX_TRIANGLES = 2_000_000


@dataclass(frozen=True)
class Mesh:
    """``vertices`` (V, 3) float32 and ``triangles`` (T, 3) uint32; ``groups`` (first triangle, count, colour)."""

    vertices: np.ndarray
    triangles: np.ndarray
    groups: tuple[tuple[int, int, str | None], ...] = field(default=())


class _Bad(Exception):
    """A problem in the mesh file, with its line when known."""

    def __init__(self, message: str, line: int | None = None) -> None:
        super().__init__(message)
        self.message, self.line = message, line


def read_mesh(path: str | Path, where: Location, owner: str) -> Mesh:
    """The mesh at ``path``; ``where`` and ``owner`` ("the mesh of link `hand`") locate the errors.

    Raises
    ------
    ModelError
        A missing or unreadable file, a malformed one (with its line), too many triangles.
    """
    path = Path(path)
    try:
        data = path.read_bytes()
    except OSError as exc:
        raise ModelError(f"{owner}, `{path}`, cannot be read: {exc.strerror or exc}", file=where.file,
                         line=where.line, symbol=path.name, fix="check that the mesh file exists and is readable") \
            from None
    suffix = path.suffix.lower()
    try:
        if suffix == ".stl":
            mesh = _stl(data)
        elif suffix == ".obj":
            mesh = _obj(data)
        elif suffix == ".dae":
            mesh = _dae(data)
        else:
            raise _Bad("the format is not STL, OBJ or DAE")
    except _Bad as exc:
        at = f" (line {exc.line} of the mesh)" if exc.line else ""
        raise ModelError(f"{owner}, `{path.name}`, is not a valid {suffix[1:].upper()} mesh: {exc.message}{at}",
                         file=where.file, line=where.line, symbol=path.name,
                         fix="export the mesh again (binary STL, OBJ or COLLADA), or give the part a simple shape "
                             "(sphere, cylinder, box)") from None
    if len(mesh.triangles) == 0:
        raise ModelError(f"{owner}, `{path.name}`, holds no triangle", file=where.file, line=where.line,
                         symbol=path.name, fix="give a mesh with faces")
    return mesh


def _finish(vertices: np.ndarray, triangles: np.ndarray, groups: tuple = ()) -> Mesh:
    if len(triangles) > MAX_TRIANGLES:
        raise _Bad(f"it has {len(triangles):,} triangles, more than the {MAX_TRIANGLES:,} the view draws")
    vertices = np.asarray(vertices, dtype=np.float64).reshape(-1, 3)
    if not np.all(np.isfinite(vertices)):
        raise _Bad("a vertex coordinate is not a finite number")
    triangles = np.asarray(triangles, dtype=np.int64).reshape(-1, 3)
    if len(triangles) and (triangles.min() < 0 or triangles.max() >= len(vertices)):
        raise _Bad("a face refers to a vertex the file does not have")
    # Shared vertices once (an STL repeats each vertex of every triangle that has it).
    unique, inverse = np.unique(vertices.astype(np.float32), axis=0, return_inverse=True)
    return Mesh(unique, inverse.reshape(-1)[triangles].astype(np.uint32), tuple(groups))


# -- STL ---------------------------------------------------------------------------------------------------------
def _stl(data: bytes) -> Mesh:
    if len(data) >= 84:
        count = struct.unpack_from("<I", data, 80)[0]
        if 84 + 50 * count == len(data):  # binary: 80-byte header, count, 50 bytes per triangle
            if count > MAX_TRIANGLES:
                raise _Bad(f"it has {count:,} triangles, more than the {MAX_TRIANGLES:,} the view draws")
            records = np.frombuffer(data, dtype=np.dtype([("n", "<f4", 3), ("v", "<f4", (3, 3)), ("a", "<u2")]),
                                    count=count, offset=84)
            return _finish(records["v"].reshape(-1, 3), np.arange(3 * count).reshape(-1, 3))
    try:
        text = data.decode("ascii")
    except UnicodeDecodeError:
        raise _Bad("it is neither a binary STL (its size does not match its triangle count) nor ASCII text") \
            from None
    if not text.lstrip().startswith("solid"):
        raise _Bad("an ASCII STL starts with `solid`; a binary one has 84 + 50 × (triangles) bytes", 1)
    vertices: list[list[float]] = []
    for number, line in enumerate(text.splitlines(), 1):
        words = line.split()
        if words and words[0] == "vertex":
            if len(words) != 4:
                raise _Bad("a vertex has three coordinates", number)
            vertices.append([_float(w, number) for w in words[1:]])
        elif words and words[0] == "endfacet" and len(vertices) % 3:
            raise _Bad("a facet has three vertices", number)
    if len(vertices) % 3:
        raise _Bad("the last facet is incomplete")
    return _finish(np.array(vertices).reshape(-1, 3), np.arange(len(vertices)).reshape(-1, 3))


def _float(word: str, line: int | None) -> float:
    try:
        value = float(word)
    except ValueError:
        raise _Bad(f"`{word[:30]}` is not a number", line) from None
    if not math.isfinite(value):
        raise _Bad(f"`{word[:30]}` is not a finite number", line)
    return value


# -- OBJ ---------------------------------------------------------------------------------------------------------
def _obj(data: bytes) -> Mesh:
    try:
        text = data.decode("utf-8")
    except UnicodeDecodeError:
        raise _Bad("it is not UTF-8 text") from None
    vertices: list[list[float]] = []
    triangles: list[list[int]] = []
    for number, line in enumerate(text.splitlines(), 1):
        words = line.split("#", 1)[0].split()
        if not words:
            continue
        if words[0] == "v":
            if len(words) < 4:
                raise _Bad("a vertex `v` has three coordinates", number)
            vertices.append([_float(w, number) for w in words[1:4]])
        elif words[0] == "f":
            if len(words) < 4:
                raise _Bad("a face `f` has at least three vertices", number)
            ids = []
            for w in words[1:]:
                head = w.split("/", 1)[0]
                if not re.fullmatch(r"-?\d+", head):
                    raise _Bad(f"`{w[:30]}` is not a vertex number", number)
                k = int(head)
                k = k - 1 if k > 0 else len(vertices) + k  # 1-based, or counted back from the last vertex
                if not 0 <= k < len(vertices):
                    raise _Bad(f"the face refers to vertex {head}, which is not defined before it", number)
                ids.append(k)
            triangles.extend([ids[0], ids[i], ids[i + 1]] for i in range(1, len(ids) - 1))
            if len(triangles) > MAX_TRIANGLES:
                raise _Bad(f"it has more than the {MAX_TRIANGLES:,} triangles the view draws", number)
    return _finish(np.array(vertices, dtype=float).reshape(-1, 3), np.array(triangles, dtype=np.int64))


# -- COLLADA -----------------------------------------------------------------------------------------------------
def _dae(data: bytes) -> Mesh:
    """A COLLADA file's triangles, as its visual scene places them (else every geometry as it is), in metres
    with z up, coloured by their materials (`_Collada`)."""
    reader = _Collada(_xml(data))
    scale = np.diag([reader.meters, reader.meters, reader.meters, 1.0])
    scenes = reader.findall(reader.root, "library_visual_scenes/visual_scene")
    if scenes:
        for node in scenes[0]:
            if node.tag == reader.ns + "node":
                reader.walk(node, reader.upright @ scale, 0)
    else:  # no scene: every geometry as it is
        for geometry in reader.findall(reader.root, "library_geometries/geometry"):
            reader.add_geometry(geometry, reader.upright @ scale, {})
    return reader.mesh()


class _Collada:
    """The steps of reading a COLLADA document: its units and up axis (`__init__`), each node's transform
    (`local_transform`), the scene walked node by node (`walk`), each geometry's primitives placed
    (`add_geometry`), and the pieces joined into one mesh (`mesh`)."""

    def __init__(self, root: Element) -> None:
        self.root = root
        self.ns = root.tag[:root.tag.index("}") + 1] if root.tag.startswith("{") else ""
        if root.tag != self.ns + "COLLADA":
            raise _Bad(f"its root element is <{root.tag.removeprefix(self.ns)}>, not <COLLADA>")
        self.by_id = {e.get("id"): e for e in root.iter() if e.get("id")}
        unit = self.find(root, "asset/unit")
        self.meters = _float(unit.get("meter", "1"), None) if unit is not None else 1.0
        up = self.find(root, "asset/up_axis")
        self.upright = np.eye(4)
        if up is not None and (up.text or "").strip() == "Y_UP":  # y up → z up: (x, y, z) ↦ (x, −z, y)
            self.upright[:3, :3] = [[1, 0, 0], [0, 0, -1], [0, 1, 0]]
        elif up is not None and (up.text or "").strip() == "X_UP":
            self.upright[:3, :3] = [[0, -1, 0], [1, 0, 0], [0, 0, 1]]
        self.colours = _material_colours(root, self.by_id, self.find, self.findall)
        self.pieces: list[tuple[np.ndarray, np.ndarray, str | None]] = []

    def find(self, node: Element, path: str) -> Element | None:
        return node.find("/".join(self.ns + p for p in path.split("/")))

    def findall(self, node: Element, path: str) -> list[Element]:
        return node.findall("/".join(self.ns + p for p in path.split("/")))

    def add_geometry(self, geometry: Element, transform: np.ndarray, bindings: dict[str, str]) -> None:
        """Each triangles, polylist or polygons primitive of the geometry, moved by ``transform``, with the
        colour of the material its symbol is bound to."""
        mesh = self.find(geometry, "mesh")
        if mesh is None:
            return
        for tag in ("triangles", "polylist", "polygons"):
            for prim in self.findall(mesh, tag):
                points, tris = _primitive(prim, tag, mesh, self.by_id, self.ns)
                moved = points @ transform[:3, :3].T + transform[:3, 3]
                colour = self.colours.get(bindings.get(prim.get("material", ""), prim.get("material", "")))
                self.pieces.append((moved, tris, colour))

    def local_transform(self, node: Element) -> np.ndarray:
        """The node's transform: its <matrix>, <translate>, <rotate> (axis, degrees) and <scale> in order."""
        local = np.eye(4)
        for child in node:
            tag = child.tag.removeprefix(self.ns)
            if tag == "matrix":
                m = np.array([_float(w, None) for w in (child.text or "").split()])
                if m.size != 16:
                    raise _Bad("a <matrix> has 16 numbers")
                local = local @ m.reshape(4, 4)
            elif tag == "translate":
                v = [_float(w, None) for w in (child.text or "").split()]
                step = np.eye(4)
                step[:3, 3] = (v + [0, 0, 0])[:3]
                local = local @ step
            elif tag == "rotate":
                v = [_float(w, None) for w in (child.text or "").split()]
                if len(v) != 4:
                    raise _Bad("a <rotate> has an axis and an angle in degrees")
                from ._evaluate import rotation_matrices

                axis = np.array(v[:3])
                step = np.eye(4)
                if np.linalg.norm(axis) > 0:
                    step[:3, :3] = rotation_matrices(axis / np.linalg.norm(axis), np.array([math.radians(v[3])]))[0]
                local = local @ step
            elif tag == "scale":
                v = [_float(w, None) for w in (child.text or "").split()]
                local = local @ np.diag((v + [1, 1, 1])[:3] + [1])
        return local

    def walk(self, node: Element, transform: np.ndarray, depth: int) -> None:
        """A scene node and its children (instances of geometries and nodes), at most 64 deep."""
        if depth > 64:
            raise _Bad("the scene's nodes are nested more than 64 deep")
        here = transform @ self.local_transform(node)
        ns = self.ns
        for child in node:
            tag = child.tag.removeprefix(ns)
            if tag == "instance_geometry":
                geometry = self.by_id.get((child.get("url") or "").lstrip("#"))
                if geometry is None:
                    raise _Bad(f"<instance_geometry> refers to `{child.get('url')}`, which the file does not have")
                bindings = {m.get("symbol", ""): (m.get("target") or "").lstrip("#")
                            for m in child.iter(ns + "instance_material")}
                self.add_geometry(geometry, here, bindings)
            elif tag == "node":
                self.walk(child, here, depth + 1)
            elif tag == "instance_node":
                target = self.by_id.get((child.get("url") or "").lstrip("#"))
                if target is not None and depth < 64:
                    self.walk(target, here, depth + 1)

    def mesh(self) -> Mesh:
        """The pieces as one mesh, a group (first triangle, count, colour) per piece."""
        if not self.pieces:
            raise _Bad("it has no triangles, polylist or polygons in a geometry")
        vertices, triangles, groups, offset, first = [], [], [], 0, 0
        for points, tris, colour in self.pieces:
            vertices.append(points)
            triangles.append(tris + offset)
            groups.append((first, len(tris), colour))
            offset += len(points)
            first += len(tris)
        return _finish(np.concatenate(vertices), np.concatenate(triangles), tuple(groups))


def _xml(data: bytes):
    from defusedxml import DefusedXmlException
    from defusedxml.ElementTree import ParseError, fromstring

    try:
        return fromstring(data, forbid_dtd=False, forbid_entities=True, forbid_external=True)
    except DefusedXmlException:
        raise _Bad("it declares an entity or an external reference, which are refused") from None
    except ParseError as exc:
        line = getattr(exc, "position", (None,))[0]
        raise _Bad(f"the XML is not well formed ({str(exc).split(':')[0]})", line) from None


def _numbers(element, what: str, integer: bool = False) -> np.ndarray:
    text = (element.text or "") if element is not None else ""
    try:
        values = np.array(text.split(), dtype=np.int64 if integer else np.float64)
    except ValueError:
        raise _Bad(f"<{what}> holds something that is not a number") from None
    if not integer and not np.all(np.isfinite(values)):
        raise _Bad(f"<{what}> holds a number that is not finite")
    return values


def _primitive(prim, tag: str, mesh, by_id: dict, ns: str) -> tuple[np.ndarray, np.ndarray]:
    """The positions and triangles (fans of each polygon) of one ``<triangles>``/``<polylist>``/``<polygons>``."""
    inputs = prim.findall(ns + "input")
    stride = 1 + max((int(i.get("offset", "0")) for i in inputs), default=0)
    vertex = next((i for i in inputs if i.get("semantic") == "VERTEX"), None)
    if vertex is None:
        raise _Bad(f"a <{tag}> has no VERTEX input")
    offset = int(vertex.get("offset", "0"))
    source = by_id.get((vertex.get("source") or "").lstrip("#"))
    if source is not None and source.tag == ns + "vertices":
        position = next((i for i in source.findall(ns + "input") if i.get("semantic") == "POSITION"), None)
        source = by_id.get((position.get("source") or "").lstrip("#")) if position is not None else None
    if source is None:
        raise _Bad(f"a <{tag}>'s VERTEX input refers to positions the file does not have")
    floats = _numbers(source.find(ns + "float_array"), "float_array")
    accessor = source.find(f"{ns}technique_common/{ns}accessor")
    step = int(accessor.get("stride", "3")) if accessor is not None else 3
    if step < 3 or floats.size % step:
        raise _Bad("a position source's stride does not divide its numbers")
    points = floats.reshape(-1, step)[:, :3]
    if tag == "polygons":
        polygons = [_numbers(p, "p", True) for p in prim.findall(ns + "p")]
        counts = np.array([len(p) // stride for p in polygons])
        indices = np.concatenate(polygons) if polygons else np.zeros(0, np.int64)
    else:
        indices = _numbers(prim.find(ns + "p"), "p", True)
        if tag == "polylist":
            counts = _numbers(prim.find(ns + "vcount"), "vcount", True)
        else:
            counts = np.full(indices.size // (3 * stride), 3)
    if indices.size != int(counts.sum()) * stride:
        raise _Bad(f"a <{tag}>'s <p> does not hold the indices its counts announce")
    ids = indices.reshape(-1, stride)[:, offset]
    if ids.size and (ids.min() < 0 or ids.max() >= len(points)):
        raise _Bad(f"a <{tag}> refers to a vertex the file does not have")
    if int(np.maximum(counts - 2, 0).sum()) > MAX_TRIANGLES:
        raise _Bad(f"it has more than the {MAX_TRIANGLES:,} triangles the view draws")
    tris = []
    start = 0
    for n in counts:
        n = int(n)
        if n >= 3:
            fan = ids[start:start + n]
            tris.append(np.column_stack([np.full(n - 2, fan[0]), fan[1:-1], fan[2:]]))
        start += n
    return points, (np.concatenate(tris) if tris else np.zeros((0, 3), np.int64))


def _material_colours(root, by_id: dict, find, findall) -> dict[str, str]:
    """material id → ``#rrggbb`` of its effect's diffuse colour, where it has one."""
    out = {}
    for material in findall(root, "library_materials/material"):
        effect_ref = find(material, "instance_effect")
        effect = by_id.get((effect_ref.get("url") or "").lstrip("#")) if effect_ref is not None else None
        if effect is None:
            continue
        diffuse = next((e for e in effect.iter() if e.tag.endswith("diffuse")), None)
        color = next((e for e in diffuse.iter() if e.tag.endswith("color")), None) if diffuse is not None else None
        if color is not None:
            try:
                rgb = [min(max(float(w), 0.0), 1.0) for w in (color.text or "").split()[:3]]
            except ValueError:
                continue
            if len(rgb) == 3:
                out[material.get("id", "")] = "#" + "".join(f"{round(c * 255):02x}" for c in rgb)
    return out
