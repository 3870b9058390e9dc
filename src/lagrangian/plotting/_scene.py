"""What an animation draws, as arrays over the frame times: the scene of a model.

* a rigid body: the polyline through its fixed point, the declared points attached to it
  (those whose position from G has constant components in the body's frame, e.g. the
  hinge A of a double pendulum's first rod) and its centre G; in 3D also its frame's
  axes at G and, when it has an axis from its anchor to G (the top's OG), a disk
  perpendicular to that axis with a spoke fixed in the body, which shows the spin;
* a particle: a dot, and a rod to its nearest partner at constant distance (the pivot of
  a pendulum, the cart of a cart-pendulum, the previous mass of a chain);
* springs and dampers: a line between their ends.

A motion whose points all stay in one plane is drawn in 2D, in that plane, with the
vertical of the page against gravity when gravity lies in the plane.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..dynamics import EquationsOfMotion
from ..model import GALILEAN_FRAME, Damper, Gravity, Spring
from ..numerics import Trajectory
from ._geometry import Samples, constant_in, frame_basis, in_R0, parameter_values, point_positions, symmetry_axis

__all__ = ["Scene", "build_scene", "PLANAR"]

#: Smallest/largest singular value of the centred point cloud below which it is a plane.
PLANAR = 1e-9
#: Largest motion of a point, relative to the scene's size, for it to be drawn as fixed.
FIXED = 1e-12
#: Disk radius and axis length, as fractions of a body's size (anchor to G).
DISK_RADIUS, AXIS_LENGTH = 0.45, 0.5


@dataclass(frozen=True)
class Scene:
    """Arrays over F frames, all in R0 components (3D) or in the plane's (2D).

    ``lines``: (name, (F, k, d)) polylines (bodies, rods); ``dots``: (name, (F, d));
    ``springs``: (F, 2, d); ``axes``: (F, 3, 2, d) three short segments per body;
    ``disks``: (F, m, d) closed curves; ``spokes``: (F, 2, d); ``fixed``: (p, d).
    ``plane``: the 2 × 3 matrix whose rows are the page's axes in R0 (2D), else None;
    ``plane_names``: their names, e.g. ("y0", "z0"); ``trails``: (F, d) paths of every
    centre of mass and particle.
    """

    t: np.ndarray
    lines: tuple[tuple[str, np.ndarray], ...]
    dots: tuple[tuple[str, np.ndarray], ...]
    springs: tuple[np.ndarray, ...]
    fixed: np.ndarray
    axes: tuple[np.ndarray, ...] = ()
    disks: tuple[np.ndarray, ...] = ()
    spokes: tuple[np.ndarray, ...] = ()
    plane: np.ndarray | None = None
    plane_names: tuple[str, str] = ("", "")
    trails: tuple[np.ndarray, ...] = field(default=())
    axis_names: tuple[str, str, str] = ("x0", "y0", "z0")

    @property
    def dimension(self) -> int:
        return 3 if self.plane is None else 2

    def bounds(self) -> tuple[np.ndarray, np.ndarray]:
        """Lower and upper corners of everything drawn, each (d,)."""
        clouds = [a.reshape(-1, a.shape[-1]) for _, a in self.lines] + [a for _, a in self.dots]
        clouds += [a.reshape(-1, a.shape[-1]) for a in (*self.springs, *self.axes, *self.disks, *self.spokes)]
        clouds.append(self.fixed.reshape(-1, self.fixed.shape[-1]) if self.fixed.size else
                      np.zeros((1, self.dimension)))
        pts = np.concatenate(clouds)
        return pts.min(axis=0), pts.max(axis=0)


def _attached(eom: EquationsOfMotion, body) -> list[str]:  # type: ignore[no-untyped-def]
    """Declared points whose position from G has constant components in the body's frame."""
    kin = eom.kinematics
    moving = set(kin.q) | {kin.t}
    out = []
    for p in eom.model.points:
        comps = kin.frames.express(kin.position(p.name) - kin.position(body.name), body.frame)
        if not any(c.free_symbols & moving for c in comps):
            out.append(p.name)
    if body.fixed_point and body.fixed_point not in out:
        out.insert(0, body.fixed_point)
    return out


def _unit(v: np.ndarray) -> np.ndarray:
    n = np.linalg.norm(v, axis=-1, keepdims=True)
    return v / np.where(n > 0, n, 1.0)


def _gravity_direction(trajectory: Trajectory, eom: EquationsOfMotion) -> np.ndarray | None:
    """The unit vector of the first gravity field (constant in R0), or None."""
    for load in eom.model.loads:
        if isinstance(load, Gravity):
            comps = in_R0(eom, load.field)
            values = parameter_values(trajectory, eom)
            try:
                g = np.array([float(c.subs({s: values.get(str(s), np.nan) for s in c.free_symbols}))
                              for c in comps])
            except (TypeError, ValueError, RuntimeError):
                return None
            if np.all(np.isfinite(g)) and np.linalg.norm(g) > 0:
                return g / np.linalg.norm(g)
    return None




def _name(v: np.ndarray, names: tuple[str, ...]) -> str:
    k = int(np.argmax(np.abs(v)))
    if abs(abs(v[k]) - 1) > 1e-9:
        return ""
    return ("" if v[k] > 0 else "−") + names[k]


def _plane(points: np.ndarray, gravity: np.ndarray | None,
           names: tuple[str, ...]) -> tuple[np.ndarray, tuple[str, str]] | None:
    """The page's axes (2 × 3) when every point lies in one plane, else None."""
    centred = points - points.mean(axis=0)
    _, s, vt = np.linalg.svd(centred, full_matrices=False)
    if s[-1] > PLANAR * s[0]:
        return None
    normal = vt[2]
    if s[1] <= PLANAR * s[0]:  # all on one line (or one point): the plane holding it and gravity
        line = vt[0] if s[0] > 0 else np.eye(3)[0]
        across = np.cross(line, gravity) if gravity is not None else np.zeros(3)
        if np.linalg.norm(across) < 1e-9:
            e = np.eye(3)[int(np.argmin(np.abs(line)))]
            across = e - (e @ line) * line
        normal = across / np.linalg.norm(across)
    k = int(np.argmax(np.abs(normal)))
    if abs(abs(normal[k]) - 1) < 1e-9:  # a plane of R0's axes: use them exactly
        normal = np.eye(3)[k]
    if gravity is not None and abs(gravity @ normal) < 1e-9:
        up = -gravity
    else:
        others = [i for i in range(3) if i != k]
        guess = np.eye(3)[others[1]] if abs(abs(normal[k]) - 1) < 1e-9 else vt[1]
        up = guess - (guess @ normal) * normal
        if np.linalg.norm(up) < 1e-9:
            up = np.cross(normal, vt[0])
        up = up / np.linalg.norm(up)
    right = np.cross(up, normal)
    j = int(np.argmax(np.abs(right)))
    if right[j] < 0:
        right = -right
    return np.array([right, up]), (_name(right, names), _name(up, names))


def build_scene(trajectory: Trajectory, eom: EquationsOfMotion, times: np.ndarray, *,
                view: str = "auto") -> Scene:
    """The `Scene` at ``times`` (positions by interpolating q between the trajectory's samples).

    ``view``: ``"auto"`` (2D when the motion is planar), ``"2d"`` or ``"3d"``.
    """
    model = eom.model
    samples = Samples.at(trajectory, times)
    names = [p.name for p in model.points] + [b.name for b in model.bodies] + [p.name for p in model.particles]
    pos = point_positions(trajectory, eom, names, samples)
    lines: list[tuple[str, np.ndarray]] = []
    dots: list[tuple[str, np.ndarray]] = []
    axes, disks, spokes = [], [], []
    wheels: list[bool] = []  # a wheel's disk is the body itself; an anchored body's disk only shows its spin
    attached_to = {body.name: _attached(eom, body) for body in model.bodies}
    full = point_positions(trajectory, eom, names)  # the whole run: constant distances are checked on it
    for body in model.bodies:
        attached = attached_to[body.name]
        anchor = body.fixed_point or (min(attached, key=lambda p: np.linalg.norm(pos[p][0] - pos[body.name][0]))
                                      if attached else body.name)
        chain = sorted({*attached, body.name}, key=lambda p: np.linalg.norm(pos[p][0] - pos[anchor][0]))
        lines.append((body.name, np.stack([pos[p] for p in chain], axis=1)))
        g = pos[body.name]
        size = max(float(np.max(np.linalg.norm(pos[p] - g, axis=1))) for p in chain) if len(chain) > 1 else 0.0
        basis = frame_basis(trajectory, eom, body.frame, samples)
        radius = None
        if anchor != body.name:  # a disk across the axis anchor → G (the top's OG)
            normal, radius = _unit(g - pos[anchor]), DISK_RADIUS * size
        else:  # a wheel: a disk across its axis of symmetry, out to a point it keeps touching (a contact)
            k = "xyz".index(symmetry_axis(eom, body.name) or "z")
            normal = basis[:, k]
            reach = [d for p in model.points if (d := constant_in(full, p.name, body.name)) is not None]
            if symmetry_axis(eom, body.name) and reach:
                radius = min(reach)
                size = radius
        if size == 0.0:
            size = 0.1 * max(float(np.max(np.abs(g))), 1.0)
        ends = g[:, None, :] + AXIS_LENGTH * size * basis  # (F, 3, 3)
        axes.append(np.stack([np.broadcast_to(g[:, None, :], ends.shape), ends], axis=2))
        if radius:
            # The body axis most across the normal; among equals (x and y of a top, both exactly ⊥ z,
            # differing in rounding only) the first, so the spoke is x whatever the rounding.
            tilt = np.abs(np.einsum("fkj,fj->fk", basis, normal)).mean(axis=0)
            k = int(np.flatnonzero(tilt <= tilt.min() + 1e-9)[0])
            e1 = _unit(basis[:, k] - np.sum(basis[:, k] * normal, axis=1, keepdims=True) * normal)
            e2 = np.cross(normal, e1)
            s = np.linspace(0, 2 * np.pi, 49)
            disks.append(g[:, None, :] + radius * (np.cos(s)[None, :, None] * e1[:, None, :]
                                                   + np.sin(s)[None, :, None] * e2[:, None, :]))
            spokes.append(np.stack([g, g + radius * e1], axis=1))
            wheels.append(anchor == body.name)
    # Particles, and a rod to the nearest partner at constant distance (checked on the full run).
    candidates = [p.name for p in model.points] + [b.name for b in model.bodies]
    pivots: list[str] = []
    for particle in model.particles:
        dots.append((particle.name, pos[particle.name]))
        best, best_d = None, np.inf
        for other in candidates:
            d = constant_in(full, other, particle.name)
            if d is not None and d < best_d:
                best, best_d = other, d
        if best is not None:
            pivots.append(best)
            lines.append((f"{best}{particle.name}", np.stack([pos[best], pos[particle.name]], axis=1)))
        candidates.append(particle.name)
    springs = [np.stack([pos[load.ends[0]], pos[load.ends[1]]], axis=1)
               for load in model.loads if isinstance(load, (Spring, Damper))]
    # Points of the ground that hold something: fixed points, pivots of rods, spring anchors.
    used = {b.fixed_point for b in model.bodies if b.fixed_point} | set(pivots)
    used |= {end for load in model.loads if isinstance(load, (Spring, Damper)) for end in load.ends}
    used |= {p for points in attached_to.values() for p in points}
    scale = max(float(np.max(np.abs(np.concatenate(list(full.values()))))), 1e-300)
    fixed = np.array([pos[p][0] for p in (x.name for x in model.points)
                      if p in used and np.ptp(full[p], axis=0).max() <= FIXED * scale]).reshape(-1, 3)
    movers = [pos[b.name] for b in model.bodies] + [pos[p.name] for p in model.particles]
    trails = tuple(movers)

    axis_names = tuple(model.frame(GALILEAN_FRAME).axes)
    plane = None
    plane_names = ("", "")
    if view != "3d":
        cloud = np.concatenate([a.reshape(-1, 3) for _, a in lines] + [a for _, a in dots]
                               + [a.reshape(-1, 3) for a in springs] + [fixed.reshape(-1, 3)]
                               + [a.reshape(-1, 3) for a, w in zip(disks, wheels) if w])
        decorated = np.concatenate([cloud] + [a.reshape(-1, 3) for a in (*disks, *spokes)])
        gravity = _gravity_direction(trajectory, eom)
        # The plane of everything, else the plane of the bodies' lines, wheels and particles
        # (a double pendulum: the disks across its rods are dropped).
        found = _plane(decorated, gravity, axis_names) or _plane(cloud, gravity, axis_names)
        if found is not None:
            plane, plane_names = found
        elif view == "2d":
            _, _, vt = np.linalg.svd(cloud - cloud.mean(axis=0), full_matrices=False)
            plane = vt[:2]
    if plane is None:
        return Scene(samples.t, tuple(lines), tuple(dots), tuple(springs), fixed, tuple(axes), tuple(disks),
                     tuple(spokes), None, ("", ""), trails, axis_names)

    def flat(a: np.ndarray) -> np.ndarray:
        return a @ plane.T

    normal = np.cross(plane[0], plane[1])
    origin = cloud[0]
    scale = max(float(np.ptp(cloud, axis=0).max()), 1e-300)

    def in_plane(a: np.ndarray) -> bool:
        return bool(np.max(np.abs((a.reshape(-1, 3) - origin) @ normal)) <= PLANAR * 1e3 * scale)

    kept = [(d, sp) for d, sp in zip(disks, spokes) if in_plane(d) and in_plane(sp)]
    return Scene(samples.t, tuple((n, flat(a)) for n, a in lines), tuple((n, flat(a)) for n, a in dots),
                 tuple(flat(a) for a in springs), flat(fixed) if fixed.size else np.zeros((0, 2)),
                 disks=tuple(flat(d) for d, _ in kept), spokes=tuple(flat(sp) for _, sp in kept),
                 plane=plane, plane_names=plane_names, trails=tuple(flat(a) for a in trails), axis_names=axis_names)
