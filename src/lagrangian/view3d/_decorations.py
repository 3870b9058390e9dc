"""What a textbook figure adds to the bodies: links, fixed points, frames, angles, vectors, the viewpoint.

* a particle is joined by a rod to its nearest partner at a constant distance (its pivot, the
  cart it hangs from), springs and dampers join their ends;
* the points that hold something and never move are the ground's (drawn as fixed points);
* each frame of the model is a triad at its origin: R0 at O, a body's frame at its joint point
  (the double pendulum's R1 at O, R2 at A), an intermediate frame (the top's R1, R2) at the
  joint point of the body it leads to; an axis already drawn there under the same name is not
  drawn twice;
* each rotation by a coordinate is an arc at the initial configuration, in the plane across
  its axis, from the parent's axis to the child's (ψ from x0 to u about z0), labelled with the
  angle in the course's letters;
* arrows: the velocity V(P/R0) of each particle and centre of mass, each reaction column of the
  run (R_O from m γ(G) = P + R_O), each force at a point, each kind at one scale;
* the vertical of the view is against gravity, and a planar motion is seen across its plane.

Whether something moves, or keeps its distance, is decided on a few random states of the
model, not on the run, so the model at rest is drawn like its motion.
"""

from __future__ import annotations

import re
from collections.abc import Mapping, Sequence
from typing import TYPE_CHECKING

import numpy as np
import symengine as se

from .._greek import greek_text
from ..errors import OutputError
from ..model import GALILEAN_FRAME, ORIGIN, Damper, Gravity, PointForce, Spring
from ._infer import model_point
from ._scene import Arc, Arrow, Link, Triad

if TYPE_CHECKING:  # pragma: no cover
    from ._build import _Builder

__all__ = ["arcs", "arrows", "fixed_tracks", "framing", "links", "triads", "up_direction"]

#: Random states on which constancy (a point that does not move, a distance that does not change) is decided.
_STATES = 5
_ARROW_COLORS = {"velocity": "#2ca02c", "reaction": "#d62728", "force": "#ff7f0e"}


def _random_points(b: _Builder) -> np.ndarray:
    """Every track's position at a few random states: (states, tracks, 3)."""
    random = getattr(b, "_random", None)
    if random is None:
        rng = np.random.default_rng(20261127)
        n = len(b.model.coordinates)
        q0 = b.states[0][0][0] if n else np.zeros(0)
        q = q0 + rng.uniform(-1.0, 1.0, (_STATES, n))
        qd = rng.uniform(-1.0, 1.0, (_STATES, n))
        t = rng.uniform(0.0, 1.0, _STATES)
        vectors = [v if v is not None else model_point(b.model, tr.name) for tr, v in zip(b.tracks, b.track_vectors, strict=True)]
        random = b._random = b.ev.vectors(vectors, t, q, qd)
    return random


def _still(values: np.ndarray, scale: float) -> bool:
    return bool(np.ptp(values, axis=0).max() <= 1e-9 * scale)


def links(b: _Builder, length: float) -> list[Link]:
    """Rods from particles to their pivots, springs, dampers."""
    from ._build import ROD_RADIUS

    out: list[Link] = []
    index = {tr.name: k for k, tr in enumerate(b.tracks)}
    candidates = [p.name for p in b.model.points] + [body.name for body in b.model.bodies]
    for particle in b.model.particles:
        best, best_d = None, np.inf
        for other in candidates:
            pts = _random_points(b)
            d = np.linalg.norm(pts[:, index[particle.name]] - pts[:, index[other]], axis=1)
            if d.min() > 0 and np.ptp(d) <= 1e-9 * max(d.max(), 1e-300) and d.mean() < best_d:
                best, best_d = other, float(d.mean())
        if best is not None:
            out.append(Link(f"{best}{particle.name}", "rod", index[best], index[particle.name],
                            b.colors[particle.name], ROD_RADIUS * length))
        candidates.append(particle.name)
    for load in b.model.loads:
        if isinstance(load, (Spring, Damper)):
            kind = "spring" if isinstance(load, Spring) else "damper"
            a, c = load.ends
            out.append(Link(load.name, kind, index[a], index[c], "#7f7f00" if kind == "spring" else "#444444",
                            0.035 * length))
    return out


def fixed_tracks(b: _Builder, found_links: Sequence[Link], anchors: Mapping[str, str]) -> set[int]:
    """The ground's points: they never move, and hold something of the ground's — a body's fixed point, the
    joint point of a body that turns on the ground, a link's end (a pendulum's pivot, a spring's anchor)."""
    from ._infer import joint_axis

    index = {tr.name: k for k, tr in enumerate(b.tracks)}
    holding = {index[body.fixed_point] for body in b.model.bodies if body.fixed_point in index}
    holding |= {link.a for link in found_links} | {link.b for link in found_links}
    for body in b.model.bodies:
        if anchors.get(body.name) in index and joint_axis(b.model, body, b.ev, ground=True)[0] != "none":
            holding.add(index[anchors[body.name]])
    pts = _random_points(b)
    scale = max(float(np.max(np.abs(pts))), 1e-300)
    return {k for k in holding if b.tracks[k].kind == "point" and _still(pts[:, k], scale)}


#: Most bodies for which the frames between bodies' frames (the top's R1, R2) get a triad of their own.
INTERMEDIATE_TRIADS = 6


def triads(b: _Builder, anchors: Mapping[str, str], attached: Mapping[str, Mapping[str, np.ndarray]],
           length: float) -> list[Triad]:
    """A triad per frame of the model (not the ``_`` frames of a rotation sequence), at its origin.

    A body's frame is drawn on the body itself (its carrier, at its joint point); a frame between two
    bodies' (the top's R1 and R2) gets a carrier of its own, for models of at most `INTERMEDIATE_TRIADS`
    bodies."""
    model = b.model
    parents = {f.name: f.parent for f in model.frames}

    def descends(frame: str, ancestor: str) -> bool:
        name: str | None = frame
        while name is not None:
            if name == ancestor:
                return True
            name = parents[name]
        return False

    out: list[Triad] = []
    drawn: dict[str, set[str]] = {}
    for frame in model.frames:
        if frame.name.startswith("_"):
            continue
        position = (0.0, 0.0, 0.0)
        own = next((body for body in model.bodies if body.frame == frame.name), None)
        if frame.name == GALILEAN_FRAME:
            anchor = ORIGIN
            k = b.carrier(f"frame:{frame.name}", frame.name, "frame", frame.name, model_point(model, anchor))
        elif own is not None:
            anchor = anchors[own.name]
            k = b.carrier(own.name, own.name, "body", own.frame, own.center)
            if anchor in attached[own.name]:
                position = tuple(float(x) for x in attached[own.name][anchor])  # type: ignore[assignment]
        else:
            owner = next((body for body in model.bodies if descends(body.frame, frame.name)), None)
            if owner is None or len(model.bodies) > INTERMEDIATE_TRIADS:
                continue  # a frame no body turns with (a reference frame, a massless link's): not drawn
            anchor = anchors[owner.name]
            k = b.carrier(f"frame:{frame.name}", frame.name, "frame", frame.name, model_point(model, anchor))
        seen = drawn.setdefault(anchor, set())
        # x_R_column (a URDF link's frame): the letter alone, the frame's name being shown at its origin.
        axes = tuple("" if name in seen else (name[0] if name == f"{name[0]}_{frame.name}" else name)
                     for name in frame.axes)
        seen.update(frame.axes)
        size = (0.35 if frame.name == GALILEAN_FRAME else 0.25) * length
        out.append(Triad(frame.name, k, axes, size, position))  # type: ignore[arg-type]
    return out


def up_direction(b: _Builder) -> tuple[float, float, float]:
    """Against the first gravity field (its direction at the start), else z0."""
    for load in b.model.loads:
        if isinstance(load, Gravity):
            g = b.ev.vectors([load.field], b.t[:1], b.states[0][0][:1], b.states[0][1][:1])[0, 0]
            if np.all(np.isfinite(g)) and np.linalg.norm(g) > 0:
                return tuple(float(x) for x in -g / np.linalg.norm(g))  # type: ignore[return-value]
    return (0.0, 0.0, 1.0)


def _angle_label(angle: se.Basic) -> str:
    text = str(angle).replace("**", "^").replace("*", " ")
    return re.sub(r"[A-Za-z_][A-Za-z_0-9]*", lambda m: greek_text(m.group(0)), text).replace("-", "−")


def arcs(b: _Builder, found: Sequence[Triad], length: float) -> list[Arc]:
    """The course's angles at the start of the main run, one arc per rotation by a coordinate."""
    model = b.model
    moving = {c.symbol for c in model.coordinates}
    origin_of = {t.frame: t.carrier for t in found}
    children: dict[str, list[str]] = {}
    for f in model.frames:
        if f.parent is not None:
            children.setdefault(f.parent, []).append(f.name)

    def carrier_of(name: str) -> int | None:
        todo = [name]
        while todo:
            here = todo.pop(0)
            if here in origin_of:
                return origin_of[here]
            todo.extend(children.get(here, []))
        return None

    q0, qd0 = b.states[0][0][:1], b.states[0][1][:1]
    frames = [f for f in model.frames if f.rotation is not None and f.rotation.elementary
              and f.rotation.angle.free_symbols & moving]
    if not frames:
        return []
    bases = b.ev.bases([f.name for f in frames], b.t[:1], q0, qd0)
    angles = b.ev.columns(b.t[:1], q0, qd0, [f.rotation.angle for f in frames])[0]  # type: ignore[union-attr]
    out: list[Arc] = []
    rings: dict[int, int] = {}
    for frame, alpha in zip(frames, angles, strict=True):
        k = carrier_of(frame.name)
        if k is None or abs(alpha) < 1e-3:
            continue
        centre = b.poses[0][0, k, :3]
        c = np.asarray(bases[frame.parent][0])  # type: ignore[index]
        axis = "xyz".index(frame.rotation.axis)  # type: ignore[union-attr]
        e_i, e_j = c[:, (axis + 1) % 3], c[:, (axis + 2) % 3]
        ring = rings.get(k, 0)
        rings[k] = ring + 1
        rho = (0.16 + 0.05 * ring) * length
        s = np.linspace(0.0, alpha, 25)
        points = centre + rho * (np.cos(s)[:, None] * e_i + np.sin(s)[:, None] * e_j)
        mid = centre + 1.18 * rho * (np.cos(alpha / 2) * e_i + np.sin(alpha / 2) * e_j)
        label = _angle_label(frame.rotation.angle)  # type: ignore[union-attr]
        out.append(Arc(label, points, (float(mid[0]), float(mid[1]), float(mid[2]))))
    return out


def arrows(b: _Builder, shown: Sequence[str] | None, length: float, traced: Sequence[int] = ()) -> list[Arrow]:
    """Velocities of particles and centres of mass (of the traced ones only, past `FEW` of them), the run's
    reaction columns, the forces at points."""
    from ..kinematics import Kinematics
    from ._build import FEW

    model = b.model
    index = {tr.name: k for k, tr in enumerate(b.tracks)}
    q, qd = b.states[0]
    found: list[tuple[str, str, str, int, np.ndarray, str]] = []  # name, label, kind, track, values, unit
    movers = [body.name for body in model.bodies] + [p.name for p in model.particles]
    if len(movers) > FEW:
        ends = {b.tracks[k].name.removeprefix("tip:") for k in traced}
        movers = [name for name in movers if name in ends or f"V({name})" in (shown or ())]
    if movers:
        kin = Kinematics(model)
        values = b.ev.vectors([kin.velocity(name) for name in movers], b.t, q, qd)
        for k, name in enumerate(movers):
            label = b.tracks[index[name]].label
            found.append((f"V({name})", f"V({label})", "velocity", index[name], values[:, k], "m/s"))
    extra = b.motions[0].extra
    axes = tuple(model.frame(GALILEAN_FRAME).axes)
    for column in extra:
        m = re.fullmatch(r"R_(.+)_" + re.escape(axes[0]), column)
        if m and m.group(1) in index and all(f"R_{m.group(1)}_{a}" in extra for a in axes):
            t_run = b.motions[0].t
            cols = [np.interp(b.t, t_run, np.asarray(extra[f"R_{m.group(1)}_{a}"], dtype=float)) for a in axes]
            found.append((f"R_{m.group(1)}", f"R_{m.group(1)}", "reaction", index[m.group(1)],
                          np.column_stack(cols), "N"))
    forces = [load for load in model.loads if isinstance(load, PointForce) and load.at in index]
    if forces:
        values = b.ev.vectors([load.force for load in forces], b.t, q, qd)
        for k, load in enumerate(forces):
            found.append((load.name, load.name, "force", index[load.at], values[:, k], "N"))
    names = {name for name, *_ in found}
    unknown = [n for n in (shown or ()) if n not in names]
    if unknown:
        raise OutputError(f"There is no vector `{unknown[0]}` to draw.",
                          fix="choose among " + (", ".join(sorted(names)) or "none (this model has none)"))
    scales: dict[str, float] = {}
    for kind in ("velocity", "force"):
        biggest = max((float(np.max(np.linalg.norm(v, axis=1))) for _, _, k, _, v, _ in found
                       if (k == kind or (kind == "force" and k == "reaction")) and len(v)), default=0.0)
        scales[kind] = 0.3 * length / biggest if biggest > 0 else 1.0
    return [Arrow(name, label, kind, track, values.astype(np.float32), scales["velocity" if kind == "velocity"
                                                                              else "force"],
                  unit, _ARROW_COLORS[kind], name in (shown or ())) for name, label, kind, track, values, unit in found]


def framing(b: _Builder, up: tuple[float, float, float], length: float) -> tuple[tuple[float, float, float], float,
                                                                                   np.ndarray]:
    """The centre and radius of what is drawn (main run and ghosts), and the direction the camera looks from."""
    from ._scene import _matrices

    clouds = [points.reshape(-1, 3) for m, points in zip(b.motions, b.points, strict=True) if not m.beside]
    for m, poses in zip(b.motions, b.poses, strict=True):  # each part's centre, widened by its reach
        if m.beside:
            continue
        for part in b.parts:
            frames = _matrices(poses[:, part.carrier, :])
            centres = frames[:, :3, :3] @ np.array(part.position) + frames[:, :3, 3]
            reach = _reach(part)
            clouds.append(np.concatenate([centres - reach, centres + reach]))
    cloud = np.concatenate(clouds) if clouds else np.zeros((1, 3))
    lo, hi = cloud.min(axis=0), cloud.max(axis=0)
    centre = (lo + hi) / 2
    radius = max(float(np.linalg.norm(hi - lo)) / 2, 0.25 * length, 1e-6)
    u = np.array(up)
    e1 = np.array([1.0, 0.0, 0.0]) - u[0] * u
    if np.linalg.norm(e1) < 1e-6:
        e1 = np.array([0.0, 1.0, 0.0]) - u[1] * u
    e1 /= np.linalg.norm(e1)
    e2 = np.cross(u, e1)
    elev, azim = np.radians(20.0), np.radians(-60.0)
    side = np.cos(azim) * e1 + np.sin(azim) * e2
    tilted = _tilted_axis(b, u)
    if tilted is not None:  # a top leaning over: seen from the side, its axis across the view
        across = np.cross(u, tilted)
        side = across if across @ side >= 0 else -across
    direction = np.cos(elev) * side + np.sin(elev) * u
    moving = _random_points(b).reshape(-1, 3)  # where the model can go, not only where the run went
    if len(moving) >= 3:
        centred = moving - moving.mean(axis=0)
        _, s, vt = np.linalg.svd(centred, full_matrices=False)
        if s[0] > 0 and s[-1] <= 1e-9 * s[0] and s[1] > 1e-9 * s[0]:  # a planar system: look across its plane
            normal = vt[2] if vt[2] @ direction >= 0 else -vt[2]
            direction = normal
    return tuple(float(x) for x in centre), radius, direction / np.linalg.norm(direction)  # type: ignore[return-value]


def _tilted_axis(b: _Builder, up: np.ndarray) -> np.ndarray | None:
    """The horizontal part (unit) of the line from a body's fixed point to its G at the start, if it leans."""
    index = {tr.name: k for k, tr in enumerate(b.tracks)}
    for body in b.model.bodies:
        if body.fixed_point in index:
            d = b.points[0][0, index[body.name]] - b.points[0][0, index[body.fixed_point]]
            h = d - (d @ up) * up
            if np.linalg.norm(h) > 0.05 * np.linalg.norm(d) > 0:
                return h / np.linalg.norm(h)
    return None


def _reach(part) -> float:
    """How far a part reaches from its centre."""
    size = part.size
    if part.mesh is not None:
        return float(np.max(np.linalg.norm(part.mesh.vertices, axis=1)))
    if part.kind == "sphere":
        return size[0]
    if part.kind == "box":
        return float(np.linalg.norm(size)) / 2
    return float(np.hypot(size[0], size[1] / 2))
