"""The scene description: what the 3-D view and the animation draw, as one frozen value.

A `Scene` holds no drawing code.  Rigid *carriers* (a body: its centre G and its frame; a
particle; a frame shown as a triad at its origin) move; each has a pose per frame time and
run, position + unit quaternion.  *Parts* are shapes fixed to a carrier (a disk, a rod, a
box, a mesh...).  *Tracks* are points followed in R0 (O, A, G, the apex of a top), joined by
*links* (a particle's rod to its pivot, springs, dampers) and traced; *arrows* are vectors
along the motion (a velocity, R_O(t), a force); *arcs* mark the course's angles at the initial
configuration.  The browser's viewer (`lagrangian.view3d.html`) and the matplotlib animation
(`lagrangian.view3d._wireframe`) both draw from it, so they cannot disagree.

`Scene.document` is its JSON form: numbers of poses and tracks as float32 in base64, the
rest as plain JSON; names and labels stay data (the page writes them as text, never as HTML).
"""

from __future__ import annotations

import base64
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ._mesh import Mesh

__all__ = ["FORMAT", "Arc", "Arrow", "Carrier", "Link", "Part", "Run", "Scene", "Track", "Triad"]

#: The version of `Scene.document`, read by the viewer.
FORMAT = "lagrangian.view/1"


@dataclass(frozen=True)
class Carrier:
    """Something rigid that moves: ``kind`` ``"body"``, ``"particle"``, ``"frame"`` (a triad) or ``"ground"``."""

    name: str
    label: str
    kind: str
    frame: str


@dataclass(frozen=True)
class Part:
    """A shape fixed to carrier ``carrier``: its centre at ``position`` and its axes turned by ``rotation``
    (unit quaternion x, y, z, w) in the carrier's frame.

    ``kind`` and ``size``: ``sphere`` (radius,), ``cylinder``, ``disk`` and ``rod`` (radius, length) along
    the part's z, ``box`` (a, b, c), ``cone`` (radius, height) along z, ``mesh`` () its triangles.
    ``source`` says where it comes from: ``declared`` (the model file, URDF), ``inertia`` (the solid of
    the same inertia), ``points`` (a rod between points of the body), ``particle``, ``hinge``, ``ball``.
    ``spoke`` marks a disk or cylinder with a stripe that shows its spin.
    """

    owner: str
    carrier: int
    kind: str
    size: tuple[float, ...]
    position: tuple[float, float, float]
    rotation: tuple[float, float, float, float]
    color: str
    opacity: float
    source: str
    mesh: Mesh | None = None
    spoke: bool = False


@dataclass(frozen=True)
class Track:
    """A point followed in R0: ``kind`` ``"point"`` (declared), ``"centre"`` (a body's G), ``"particle"``,
    ``"tip"`` (the end of a body's axis, the apex of a top); ``fixed`` when it never moves and holds something."""

    name: str
    label: str
    kind: str
    fixed: bool = False


@dataclass(frozen=True)
class Link:
    """A segment between tracks ``a`` and ``b``: ``kind`` ``"rod"``, ``"spring"`` or ``"damper"``."""

    name: str
    kind: str
    a: int
    b: int
    color: str
    radius: float


@dataclass(frozen=True)
class Triad:
    """The axes of ``frame`` on carrier ``carrier``, at ``position`` in its frame (a body's frame at its joint
    point); an axis named ``""`` is not drawn (another triad at the same place already draws it)."""

    frame: str
    carrier: int
    axes: tuple[str, str, str]
    length: float
    position: tuple[float, float, float] = (0.0, 0.0, 0.0)


@dataclass(frozen=True)
class Arc:
    """An angle at the initial configuration: the arc's points (n, 3) in R0 and where its label goes."""

    label: str
    points: np.ndarray
    at: tuple[float, float, float]


@dataclass(frozen=True)
class Arrow:
    """A vector along the main run at track ``track``: ``values`` (F, 3) in R0, drawn ``scale`` times as long
    (metres per unit); ``kind`` ``"velocity"``, ``"reaction"`` or ``"force"``; ``shown`` when on at first."""

    name: str
    label: str
    kind: str
    track: int
    values: np.ndarray
    scale: float
    unit: str
    color: str
    shown: bool = False


@dataclass(frozen=True)
class Run:
    """One motion: ``poses`` (F, K, 7) position and quaternion of each carrier, ``points`` (F, P, 3) of each
    track; drawn shifted by ``offset``, translucent when ``ghost`` (an ensemble member)."""

    label: str
    poses: np.ndarray
    points: np.ndarray
    offset: tuple[float, float, float] = (0.0, 0.0, 0.0)
    ghost: bool = False


@dataclass(frozen=True)
class Scene:
    """Everything drawn, at the frame times ``t`` (F,); see the module docstring.

    Parameters
    ----------
    title : str
        The scene's title.
    t : ndarray of shape (F,)
        The frame times.
    carriers : tuple of Carrier
        The rigid things that move.
    parts : tuple of Part
        The shapes fixed to the carriers.
    tracks : tuple of Track
        The points followed in R0.
    runs : tuple of Run
        The poses and tracks of each run, per frame.
    links : tuple of Link
        Rods, springs and dampers between tracks.
    triads : tuple of Triad
        The frames shown as three axes.
    arcs : tuple of Arc
        The course's angles at the initial configuration.
    arrows : tuple of Arrow
        Vectors along the motion.
    traces : tuple of int
        The tracks whose paths are drawn.
    up : (float, float, float)
        The vertical, in R0.
    axis_names : (str, str, str)
        The names of R0's axes.
    size : float
        The scene's length L, what sizes without one of their own are fractions of.
    centre : (float, float, float)
        The centre of what is drawn.
    radius : float
        The radius of what is drawn.
    view_direction : (float, float, float)
        The direction the camera looks from.
    lang : str
        The language of the labels.
    notes : tuple of str
        What the view had to guess or leave out, in words.
    """

    title: str
    t: np.ndarray
    carriers: tuple[Carrier, ...]
    parts: tuple[Part, ...]
    tracks: tuple[Track, ...]
    runs: tuple[Run, ...]
    links: tuple[Link, ...] = ()
    triads: tuple[Triad, ...] = ()
    arcs: tuple[Arc, ...] = ()
    arrows: tuple[Arrow, ...] = ()
    traces: tuple[int, ...] = ()
    up: tuple[float, float, float] = (0.0, 0.0, 1.0)
    axis_names: tuple[str, str, str] = ("x0", "y0", "z0")
    size: float = 1.0
    centre: tuple[float, float, float] = (0.0, 0.0, 0.0)
    radius: float = 1.0
    view_direction: tuple[float, float, float] = (0.6, -0.7, 0.4)
    lang: str = "en"
    notes: tuple[str, ...] = field(default=())

    @property
    def at_rest(self) -> bool:
        """One frame: the model in its initial configuration, nothing to play."""
        return len(self.t) == 1

    def track(self, name: str) -> int:
        """The index of the track ``name``.

        Parameters
        ----------
        name : str
            A point, a body's name for its G, a particle, ``tip:S``.

        Returns
        -------
        int
            Its index in ``tracks``.
        """
        for k, tr in enumerate(self.tracks):
            if tr.name == name:
                return k
        raise KeyError(f"no track {name!r}")

    def world(self, run: int = 0) -> np.ndarray:
        """Each part's pose in R0 at each frame of ``run``.

        Parameters
        ----------
        run : int, optional
            The run.

        Returns
        -------
        ndarray of shape (F, parts, 4, 4)
            Homogeneous matrices.
        """
        poses = self.runs[run].poses
        f = len(self.t)
        out = np.zeros((f, len(self.parts), 4, 4))
        for k, part in enumerate(self.parts):
            carrier = _matrices(poses[:, part.carrier, :])
            local = _matrices(np.array([[*part.position, *part.rotation]]))[0]
            out[:, k] = carrier @ local
        out[:, :, :3, 3] += np.array(self.runs[run].offset)
        return out

    @property
    def document(self) -> dict[str, Any]:
        """The scene as JSON-ready data (``FORMAT``): what the viewer reads."""
        def b64(a: np.ndarray, dtype: Any = np.float32) -> str:
            return base64.b64encode(np.ascontiguousarray(a, dtype=dtype).tobytes()).decode("ascii")

        parts = []
        for p in self.parts:
            item: dict[str, Any] = {"owner": p.owner, "carrier": p.carrier, "kind": p.kind, "size": list(p.size),
                                    "position": list(p.position), "rotation": list(p.rotation), "color": p.color,
                                    "opacity": p.opacity, "source": p.source, "spoke": p.spoke}
            if p.mesh is not None:
                small = len(p.mesh.vertices) < 65536
                item["mesh"] = {"vertices": b64(p.mesh.vertices), "count": len(p.mesh.triangles),
                                "triangles": b64(p.mesh.triangles, np.uint16 if small else np.uint32),
                                "index": "uint16" if small else "uint32",
                                "groups": [[a, n, c] for a, n, c in p.mesh.groups]}
            parts.append(item)
        return {
            "format": FORMAT, "title": self.title, "lang": self.lang,
            "frames": len(self.t), "t": b64(self.t, np.float64),
            "carriers": [{"name": c.name, "label": c.label, "kind": c.kind, "frame": c.frame} for c in self.carriers],
            "parts": parts,
            "tracks": [{"name": t.name, "label": t.label, "kind": t.kind, "fixed": t.fixed} for t in self.tracks],
            "runs": [{"label": r.label, "poses": b64(r.poses), "points": b64(r.points), "offset": list(r.offset),
                      "ghost": r.ghost} for r in self.runs],
            "links": [{"name": k.name, "kind": k.kind, "a": k.a, "b": k.b, "color": k.color, "radius": k.radius}
                      for k in self.links],
            "triads": [{"frame": t.frame, "carrier": t.carrier, "axes": list(t.axes), "length": t.length,
                        "position": list(t.position)} for t in self.triads],
            "arcs": [{"label": a.label, "points": np.round(a.points, 6).tolist(), "at": list(a.at)} for a in self.arcs],
            "arrows": [{"name": a.name, "label": a.label, "kind": a.kind, "track": a.track, "values": b64(a.values),
                        "scale": a.scale, "unit": a.unit, "color": a.color, "shown": a.shown} for a in self.arrows],
            "traces": list(self.traces), "up": list(self.up), "axis_names": list(self.axis_names),
            "size": self.size, "centre": list(self.centre), "radius": self.radius,
            "view_direction": list(self.view_direction),
        }


def _matrices(poses: np.ndarray) -> np.ndarray:
    """Homogeneous 4 × 4 matrices of poses (N, 7): position and quaternion (x, y, z, w)."""
    x, y, z, w = (poses[:, 3 + k] for k in range(4))
    out = np.zeros((len(poses), 4, 4))
    out[:, 0, 0] = 1 - 2 * (y * y + z * z)
    out[:, 0, 1] = 2 * (x * y - z * w)
    out[:, 0, 2] = 2 * (x * z + y * w)
    out[:, 1, 0] = 2 * (x * y + z * w)
    out[:, 1, 1] = 1 - 2 * (x * x + z * z)
    out[:, 1, 2] = 2 * (y * z - x * w)
    out[:, 2, 0] = 2 * (x * z - y * w)
    out[:, 2, 1] = 2 * (y * z + x * w)
    out[:, 2, 2] = 1 - 2 * (x * x + y * y)
    out[:, :3, 3] = poses[:, :3]
    out[:, 3, 3] = 1.0
    return out
