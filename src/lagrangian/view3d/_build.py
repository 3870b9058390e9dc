"""Building the `Scene` of a model and its motions: carriers and their poses, parts, tracks, triads, arcs.

Positions come from the model's kinematics evaluated at the frame times (`_evaluate`): the
runs' q and q̇ are interpolated linearly to those times (the output times of the main run,
at most ``max_frames`` of them), then every pose is computed from the interpolated q, so a
rod keeps its length between samples.  The browser interpolates further between frames
(positions linearly, orientations by slerp).  Shapes are the model's (`lagrangian.model.Shape`)
or inferred (`_infer`): a body shows the homogeneous solid of its inertia, rods from its joint
point to its other points, its hinge or ball joint; a particle a sphere.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field

import numpy as np
import symengine as se

from ..errors import OutputError
from ..model import GALILEAN_FRAME, ORIGIN, Model, Shape, Vector
from ._decorations import arcs, arrows, fixed_tracks, framing, links, triads, up_direction
from ._evaluate import Evaluator, quaternions
from ._infer import PALETTE, attached_points, body_solid, inferred_parts, model_point
from ._mesh import Mesh, read_mesh
from ._scene import Carrier, Link, Part, Run, Scene, Track

__all__ = ["MAX_FRAMES", "Motion", "build_scene"]

#: Most paths drawn when none are asked for.
DEFAULT_TRACES = 4
#: Up to this many bodies, every body's tip is followed and every velocity drawable; beyond, the free ends'.
FEW = 8
#: Most frames kept from a run's output times (evenly chosen among them): 100 frames/s for a minute.
MAX_FRAMES = 6000
#: Sizes of what has no size of its own, as fractions of the scene's length L.
ROD_RADIUS, PARTICLE_RADIUS, HINGE_RADIUS, TRIAD_LENGTH = 0.012, 0.04, 0.022, 0.3
#: The grey of joints.
JOINT_COLOR = "#555555"
_IDENTITY = (0.0, 0.0, 0.0, 1.0)


@dataclass(frozen=True)
class Motion:
    """A run to draw: its times and states in the model's coordinate order, and how it is shown.

    Parameters
    ----------
    label : str
        The run's name.
    t : ndarray of shape (N,)
        The times.
    q : ndarray of shape (N, n)
        The coordinates.
    qd : ndarray of shape (N, n)
        The rates.
    extra : mapping of str to ndarray
        Extra columns (reactions).
    ghost : bool
        Overlaid, translucent.
    beside : bool
        Drawn next to the main run.
    """

    label: str
    t: np.ndarray
    q: np.ndarray
    qd: np.ndarray
    extra: Mapping[str, np.ndarray] = field(default_factory=dict)
    ghost: bool = False
    beside: bool = False


def _quat(m: np.ndarray) -> tuple[float, float, float, float]:
    return tuple(float(x) for x in quaternions(m[None])[0])  # type: ignore[return-value]


def _frame_times(motion: Motion, max_frames: int) -> np.ndarray:
    t = np.asarray(motion.t, dtype=float)
    if len(t) <= max_frames:
        return t
    return t[np.unique(np.linspace(0, len(t) - 1, max_frames).round().astype(int))]


def _at(motion: Motion, times: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """q and q̇ of ``motion`` at ``times`` (linear interpolation; held at its ends outside its span)."""
    def interp(a: np.ndarray) -> np.ndarray:
        a = np.asarray(a, dtype=float).reshape(len(motion.t), -1)
        if len(motion.t) == 1:
            return np.repeat(a, len(times), axis=0)
        return np.column_stack([np.interp(times, motion.t, a[:, k]) for k in range(a.shape[1])]) \
            if a.shape[1] else np.zeros((len(times), 0))
    return interp(motion.q), interp(motion.qd)


class _Builder:
    def __init__(self, model: Model, values: Mapping[str, float], motions: Sequence[Motion], max_frames: int) -> None:
        if not motions:
            raise OutputError("There is nothing to show: no motion and no configuration.",
                              fix="give a trajectory, or the model to see it at rest")
        self.model = model
        self.ev = Evaluator(model, values)
        self.motions = list(motions)
        self.t = _frame_times(self.motions[0], max_frames)
        self.states = [_at(m, self.t) for m in self.motions]
        self.carriers: list[Carrier] = []
        self.origins: list[Vector] = []
        self.parts: list[Part] = []
        self.tracks: list[Track] = []
        self.track_vectors: list[Vector | None] = []
        self.notes: list[str] = []
        self._random: np.ndarray | None = None
        self.L = 1.0
        self.colors: dict[str, str] = {}
        for k, name in enumerate([b.name for b in model.bodies] + [p.name for p in model.particles]):
            self.colors[name] = PALETTE[k % len(PALETTE)]

    # -- carriers and tracks ------------------------------------------------------------------------
    def carrier(self, name: str, label: str, kind: str, frame: str, origin: Vector) -> int:
        for k, c in enumerate(self.carriers):
            if c.frame == frame and c.name == name:
                return k
        self.carriers.append(Carrier(name, label, kind, frame))
        self.origins.append(origin)
        return len(self.carriers) - 1

    def track(self, name: str, label: str, kind: str, position: Vector | None) -> int:
        for k, tr in enumerate(self.tracks):
            if tr.name == name:
                return k
        self.tracks.append(Track(name, label, kind))
        self.track_vectors.append(position)
        return len(self.tracks) - 1

    def evaluate(self) -> None:
        """Poses of the carriers and positions of the tracks, for every run."""
        frames = sorted({c.frame for c in self.carriers})
        self.poses, self.points = [], []
        for t_q in self.states:
            q, qd = t_q
            bases = self.ev.bases(frames, self.t, q, qd)
            origins = self.ev.vectors(self.origins, self.t, q, qd)
            poses = np.zeros((len(self.t), len(self.carriers), 7))
            for k, c in enumerate(self.carriers):
                poses[:, k, :3] = origins[:, k]
                poses[:, k, 3:] = quaternions(np.asarray(bases[c.frame]))
            self.poses.append(poses)
            self.points.append(self.ev.vectors([v for v in self.track_vectors if v is not None], self.t, q, qd))
        self.bases0 = self.ev.bases(frames, self.t[:1], self.states[0][0][:1], self.states[0][1][:1])

    # -- the scene's size ----------------------------------------------------------------------------------------
    def length(self) -> float:
        """L: the extent of every point of the model over the main run (1 for a system of one point)."""
        q, qd = self.states[0]
        names = [p.name for p in self.model.points] + [b.name for b in self.model.bodies] + \
            [p.name for p in self.model.particles]
        xyz = self.ev.vectors([model_point(self.model, n) for n in names], self.t, q, qd).reshape(-1, 3)
        extent = float(np.max(np.ptp(xyz, axis=0))) if len(xyz) else 0.0
        if extent <= 0:
            extent = float(np.max(np.abs(xyz))) if len(xyz) else 0.0
        return extent if extent > 0 else 1.0


def _size(expr: se.Basic | None, values: Mapping[str, float]) -> float | None:
    if expr is None:
        return None
    value = float(expr.subs({se.Symbol(k): v for k, v in values.items()}))
    if not (math.isfinite(value) and value > 0):
        raise OutputError(f"A size of a shape is {value:g} with these parameter values; sizes are positive.",
                          fix="check the shape's sizes and the parameters they use")
    return value


def build_scene(model: Model, motions: Sequence[Motion], values: Mapping[str, float], *, title: str | None = None,
                lang: str = "en", traces: Sequence[str] | None = None, vectors: Sequence[str] | None = None,
                max_frames: int = MAX_FRAMES) -> Scene:
    """The `Scene` of ``model`` moving as ``motions`` (the first is the main run; one state: at rest).

    ``values`` gives every parameter its number.  ``traces`` names the points whose paths are drawn
    (default: the particles and the tips of the bodies that turn about a point); ``vectors`` names the
    arrows shown at first (``"V(P)"`` a velocity, ``"R_O"`` a reaction column of the run, a force's load
    name); every one available can be switched on in the viewer.

    The steps: the tracked points (`_add_tracks`), the parts drawn on each carrier (`_add_parts`), the
    links, triads and arcs between them, the points traced (`_traced`), the arrows, the framing, and the
    runs placed (`_runs`).

    Parameters
    ----------
    model : Model
        The model.
    motions : sequence of Motion
        The runs; the first is the main run (one state: at rest).
    values : mapping of str to float
        Every parameter's number.
    title : str, optional
        The scene's title (default: the model's name).
    lang : {"en", "fr"}, optional
        The language of the labels.
    traces : sequence of str, optional
        The points whose paths are drawn (default: the particles and the tips of the bodies that turn
        about a point).
    vectors : sequence of str, optional
        The arrows shown at first (``"V(P)"`` a velocity, ``"R_O"`` a reaction column of the run, a
        force's load name); every one available can be switched on in the viewer.
    max_frames : int, optional
        The most frame times.

    Returns
    -------
    Scene
        Everything to draw.
    """
    b = _Builder(model, values, motions, max_frames)
    _add_tracks(b, model)
    attached_to = attached_points(model, b.ev)
    anchors = {body.name: _anchor(model, body, attached_to) for body in model.bodies}
    length = _add_parts(b, model, attached_to, anchors)
    found_links = links(b, length)
    found_triads = triads(b, anchors, attached_to, length)
    b.evaluate()
    fixed = fixed_tracks(b, found_links, anchors)
    b.tracks = [Track(tr.name, tr.label, tr.kind, k in fixed) for k, tr in enumerate(b.tracks)]
    up = up_direction(b)
    found_arcs = arcs(b, found_triads, length)
    traced = _traced(b, model, traces, found_links, anchors, attached_to)
    found_arrows = arrows(b, vectors, length, traced)
    centre, radius, direction = framing(b, up, length)
    runs, centre, radius = _runs(b, up, direction, centre, radius)
    axis_names = tuple(model.frame(GALILEAN_FRAME).axes)
    return Scene(title or model.name, b.t.copy(), tuple(b.carriers), tuple(b.parts), tuple(b.tracks), tuple(runs),
                 tuple(found_links), tuple(found_triads), tuple(found_arcs), tuple(found_arrows), tuple(traced), up,
                 axis_names,  # type: ignore[arg-type]
                 length, centre, radius, tuple(float(x) for x in direction), lang, tuple(b.notes))  # type: ignore[arg-type]


def _add_tracks(b: _Builder, model: Model) -> None:
    """Tracks: every declared point, each body's G, each particle."""
    for p in model.points:
        b.track(p.name, p.name, "point", p.position)
    centre_labels = _centre_labels(model)
    for body in model.bodies:
        b.track(body.name, centre_labels[body.name], "centre", body.center)
    for particle in model.particles:
        b.track(particle.name, particle.name, "particle", particle.position)


def _add_parts(b: _Builder, model: Model, attached_to: dict[str, dict[str, np.ndarray]],
               anchors: Mapping[str, str]) -> float:
    """The parts drawn: each body a carrier at G turning with its frame, with its declared shapes or
    the solid inferred from its points (and the track of its tip); each particle a sphere or its
    shapes; the shapes declared on frames.  Returns the scene's length scale."""
    declared: dict[str, list[Shape]] = {}
    for shape in model.shapes:
        declared.setdefault(shape.on, []).append(shape)
    meshes: dict[str, Mesh] = {}
    solids = {body.name: body_solid(b, body, attached_to[body.name], anchors[body.name]) for body in model.bodies
              if body.name not in declared}
    length = b.L = max([b.length()] + [max(s.size) for s in solids.values() if s is not None])
    for body in model.bodies:
        k = b.carrier(body.name, body.name, "body", body.frame, body.center)
        attached, anchor = attached_to[body.name], anchors[body.name]
        color = b.colors[body.name]
        if body.name in declared:
            for shape in declared.pop(body.name):
                b.parts.append(_declared_part(b, shape, k, body.center, body.frame, color, meshes))
            continue
        extent = inferred_parts(b, body, k, attached, anchor, color, length, solids[body.name])
        others = {anchors[o.name] for o in model.bodies if o.name != body.name}
        leaf = not set(attached) & others  # nothing hangs from it: its tip is a free end (the top's apex)
        if anchor != body.name and extent is not None and (leaf or len(model.bodies) <= FEW):
            gp = attached.get(anchor)
            if gp is not None and np.linalg.norm(gp) > 1e-12:
                unit = -gp / np.linalg.norm(gp)
                tip = Vector({body.frame: tuple(se.Float(float(x)) for x in unit * extent)}) + body.center
                b.track(f"tip:{body.name}", "", "tip", tip)
    for particle in model.particles:
        k = b.carrier(particle.name, particle.name, "particle", GALILEAN_FRAME, particle.position)
        color = b.colors[particle.name]
        if particle.name in declared:
            for shape in declared.pop(particle.name):
                b.parts.append(_declared_part(b, shape, k, particle.position, GALILEAN_FRAME, color, meshes))
        else:
            b.parts.append(Part(particle.name, k, "sphere", (PARTICLE_RADIUS * length,), (0.0, 0.0, 0.0), _IDENTITY,
                                color, 1.0, "particle"))
    for owner, shapes in declared.items():  # on a frame: a URDF link fixed to the ground, a massless link
        for shape in shapes:
            k = b.carrier(owner, owner, "ground" if owner == GALILEAN_FRAME else "frame", owner, shape.center)
            b.parts.append(_declared_part(b, shape, k, shape.center, owner, "#9a9a9a", meshes))
    return length


def _traced(b: _Builder, model: Model, traces: Sequence[str] | None, found_links: Sequence[Link],
            anchors: Mapping[str, str], attached_to: dict[str, dict[str, np.ndarray]]) -> list[int]:
    """The tracks whose paths are drawn: those named, else the free ends (the particles no rod hangs from
    and the bodies nothing hangs from: the second rod of a double pendulum, the top, a chain's last
    link: their tip, else their G), at most `DEFAULT_TRACES`."""
    if traces is None:
        pivots = {link.a for link in found_links if link.kind == "rod"}
        index = {tr.name: k for k, tr in enumerate(b.tracks)}
        traced = [index[p.name] for p in model.particles if index[p.name] not in pivots]
        for body in model.bodies:
            others = {anchors[o.name] for o in model.bodies if o.name != body.name}
            if not set(attached_to[body.name]) & others:
                traced.append(index.get(f"tip:{body.name}", index[body.name]))
        return traced[-DEFAULT_TRACES:]
    names = {tr.name: k for k, tr in enumerate(b.tracks)}
    unknown = [n for n in traces if n not in names]
    if unknown:
        raise OutputError(f"There is no point `{unknown[0]}` to trace.",
                          fix="trace a declared point, a body (its centre G), a particle or tip:BODY; points: "
                              + ", ".join(sorted(names)))
    return [names[n] for n in traces]


def _runs(b: _Builder, up: tuple[float, float, float], direction: np.ndarray, centre: tuple[float, float, float],
          radius: float) -> tuple[list[Run], tuple[float, float, float], float]:
    """Each motion as a run of poses and points; a run drawn ``beside`` the main one is offset across the
    view by 2.2 radii, and the framing (centre, radius) widened to hold both."""
    runs = []
    offset_axis = np.cross(up, direction)
    offset_axis /= max(np.linalg.norm(offset_axis), 1e-12)
    for motion, poses, points in zip(b.motions, b.poses, b.points, strict=True):
        offset = (0.0, 0.0, 0.0)
        if motion.beside:
            x, y, z = offset_axis * 2.2 * radius
            offset = (float(x), float(y), float(z))
        runs.append(Run(motion.label, poses.astype(np.float32), points.astype(np.float32), offset, motion.ghost))
    if any(m.beside for m in b.motions):
        cx, cy, cz = (float(c + x * 1.1 * radius) for c, x in zip(centre, offset_axis, strict=True))
        centre = (cx, cy, cz)
        radius *= 2.2
    return runs, centre, radius


def _centre_labels(model: Model) -> dict[str, str]:
    """G for one body; G1, G2 for S1, S2; else G_S."""
    names = [b.name for b in model.bodies]
    if len(names) == 1:
        return {names[0]: "G"}
    digits = {n: n[len(n.rstrip("0123456789")):] for n in names}
    if all(digits.values()) and len(set(digits.values())) == len(names):
        return {n: "G" + d for n, d in digits.items()}
    return {n: f"G_{n}" for n in names}


def _anchor(model: Model, body, attached: Mapping[str, Mapping[str, np.ndarray]]) -> str:
    """The body's joint point: its fixed point, else a point it shares with another body or the ground (O)."""
    if body.fixed_point:
        return body.fixed_point
    for name in attached[body.name]:
        if name == ORIGIN or any(name in attached[o.name] for o in model.bodies if o.name != body.name):
            return name
    return body.name


def _declared_part(b: _Builder, shape: Shape, carrier: int, origin: Vector, frame: str, color: str,
                   meshes: dict[str, Mesh]) -> Part:
    """A model's shape, placed in its carrier's frame (origin ``origin``)."""
    ev, values = b.ev, b.ev.values
    where = f"{shape.location.file or 'the model'}:{shape.location.line or '?'}"
    rotation = np.array(shape.rotation) if shape.rotation is not None else np.eye(3)
    turn = np.eye(3)
    if shape.frame != frame:
        comps = [ev.constant_in(Vector({shape.frame: tuple(se.Integer(int(i == k)) for i in range(3))}), frame)
                 for k in range(3)]
        if any(c is None for c in comps):
            raise OutputError(f"The shape of `{shape.on}` ({where}) is fixed in `{shape.frame}`, which turns relative "
                              f"to `{frame}`.", fix="give the shape in the body's frame")
        turn = np.column_stack([c for c in comps if c is not None])
    rotation = turn @ rotation
    offset = ev.constant_in(shape.center - origin, frame)
    if offset is None:
        raise OutputError(f"The shape of `{shape.on}` ({where}) is centred at a point that moves in the body.",
                          fix="place it at a point fixed in the body (`center` from `from`)")
    position = np.array(offset)
    radius = _size(shape.radius, values)
    length = _size(shape.length, values)
    mesh = None
    size: tuple[float, ...]
    if shape.kind == "rod" and shape.ends is not None:
        ends = [ev.constant_in(model_point(b.model, e) - origin, frame) for e in shape.ends]
        if any(e is None for e in ends):
            raise OutputError(f"The rod of `{shape.on}` ({where}) joins points that move in the body.",
                              fix="join points fixed in it")
        a, c = np.array(ends[0]), np.array(ends[1])
        axis = c - a
        length = float(np.linalg.norm(axis))
        position = (a + c) / 2
        if length > 0:
            from ..model import rotation_to

            rotation = np.array(rotation_to(axis / length))
    if shape.kind == "sphere":
        size = (radius,)  # type: ignore[assignment]
    elif shape.kind in ("cylinder", "disk", "rod"):
        default = (radius or 0.0) / 10 if shape.kind == "disk" else 0.0
        size = (radius if radius is not None else ROD_RADIUS * b.L, length or default)
    elif shape.kind == "box":
        size = tuple(_size(x, values) for x in shape.size)  # type: ignore[misc, union-attr]
    else:
        key = str(shape.mesh)
        if key not in meshes:
            meshes[key] = read_mesh(key, shape.location, f"the mesh of `{shape.on}`")
        raw = meshes[key]
        groups = raw.groups if shape.color is None else tuple((a, n, None) for a, n, _ in raw.groups)
        mesh = Mesh((raw.vertices * np.array(shape.scale, dtype=np.float32)).astype(np.float32), raw.triangles,
                    groups)
        size = ()
    return Part(shape.on, carrier, shape.kind, tuple(float(x) for x in size), tuple(float(x) for x in position),  # type: ignore[arg-type]
                _quat(rotation), shape.color or color, 1.0 if shape.opacity is None else shape.opacity, "declared",
                mesh, spoke=shape.kind in ("disk", "cylinder"))
