"""Shapes inferred from a body's inertia and points, where the model declares none.

The principal moments of Π_G (λ1 ≤ λ2 ≤ λ3, mass m) choose a homogeneous solid with the
same inertia, centred at G along the principal axes:

* two equal moments A and a distinct C (a body of revolution about C's axis): a cylinder of
  radius r and length h with C = m r²/2 and A = m (3 r² + h²)/12, so r = √(2C/m) and
  h = √((12A − 6C)/m); a *disk* when h is small beside r (C = 2A: the flat disk), a *rod*
  when C = 0 (A = m l²/12: l = √(12A/m));
* three equal moments: with an axis the model gives (the symmetry axis of the inertia as
  declared, or the line from the fixed point to G: the seed's top, whose A − m a² = C at G), a
  disk of radius √(2C/m) across it — the course's figure of a top, true to C, while the disk's
  own A (C/2) leaves the rest of A to what the figure does not show; without an axis, a sphere of
  radius √(5A/2m) (A = 2/5 m R²);
* otherwise a box of sides a_i = √(6 (λj + λk − λi)/m) along the principal axes
  (λi = m (a_j² + a_k²)/12).

Formulas: any table of moments of inertia of homogeneous solids (e.g. Goldstein, *Classical
Mechanics*, 3rd ed., §5.3; Landau & Lifshitz, *Mechanics*, §32, problem 2).  Besides that
solid, a body shows thin rods from its joint point (its fixed point, else the point it shares
with another body) to the other declared points fixed in it (the course's figure of a rod
OA), and a hinge where its frame turns about one axis from its parent's.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import symengine as se

from ..model import GALILEAN_FRAME, Body, Model, Vector
from ._evaluate import Evaluator

__all__ = [
    "PALETTE",
    "Solid",
    "attached_points",
    "body_solid",
    "inertia_at_g",
    "inferred_parts",
    "joint_axis",
    "model_point",
    "solid_of_inertia",
]

#: Relative tolerance under which two principal moments are equal (or a moment is zero).
EQUAL = 1e-6
#: The opacity of the solid of a body turning about a fixed point (a top): its axis, its fixed point and the
#: frames there stay visible through it.
SEE_THROUGH = 0.8
#: A cylinder shorter than this fraction of its radius is drawn as a disk.
FLAT = 0.25
#: The colours of bodies then particles, in model order (matplotlib's tab10: the GIF uses the same).
PALETTE = ("#1f77b4", "#d62728", "#2ca02c", "#ff7f0e", "#9467bd", "#8c564b", "#e377c2", "#17becf", "#bcbd22",
           "#7f7f7f")


@dataclass(frozen=True)
class Solid:
    """A homogeneous solid: ``kind`` (cylinder, disk, rod, sphere, box), ``size`` (radius, length) for the first
    three, (radius,) for a sphere, (a, b, c) for a box; ``axes`` (3 × 3, columns) in the body frame: a
    cylinder's axis is the third column."""

    kind: str
    size: tuple[float, ...]
    axes: np.ndarray


def solid_of_inertia(moments: np.ndarray, axes: np.ndarray, mass: float,
                     preferred: np.ndarray | None = None) -> Solid | None:
    """The solid of mass ``mass`` whose principal moments at G are ``moments`` (ascending) about ``axes``.

    ``axes``: the principal axes (columns, body frame) in the order of ``moments``.  ``preferred``:
    a direction of the body (unit, body frame) taken as the axis of revolution when the three
    moments are equal.  None when the mass or the moments are zero (a point mass).
    """
    top = float(np.max(moments))
    if not (mass > 0 and top > 0 and np.all(np.isfinite(moments))):
        return None
    tol = EQUAL * top
    l1, l2, l3 = (max(float(x), 0.0) for x in moments)
    if l3 - l1 <= tol:  # isotropic: a sphere, or a cylinder about the axis the model gives
        if preferred is None:
            return Solid("sphere", (math.sqrt(5 * l2 / (2 * mass)),), axes)
        r = math.sqrt(2 * l2 / mass)
        return Solid("disk", (r, r / 8), _frame_with_z(preferred))
    elif l2 - l1 <= tol:  # A = λ1 = λ2 < C = λ3: flattened, about the third axis
        frame, a, c = axes, (l1 + l2) / 2, l3
    elif l3 - l2 <= tol:  # C = λ1 < A = λ2 = λ3: elongated, about the first axis
        frame, a, c = axes[:, [1, 2, 0]], (l2 + l3) / 2, l1
    else:
        sides = tuple(math.sqrt(max(6 * (l1 + l2 + l3 - 2 * li) / mass, 0.0)) for li in (l1, l2, l3))
        return Solid("box", sides, _right_handed(axes))
    frame = _right_handed(frame)
    if c <= tol:  # a thin rod: A = m l²/12
        return Solid("rod", (0.0, math.sqrt(12 * a / mass)), frame)
    r = math.sqrt(2 * c / mass)
    h = math.sqrt(max((12 * a - 6 * c) / mass, 0.0))
    return Solid("disk" if h < FLAT * r else "cylinder", (r, h), frame)


def _right_handed(frame: np.ndarray) -> np.ndarray:
    return frame if np.linalg.det(frame) > 0 else frame * np.array([-1.0, 1.0, 1.0])


def _frame_with_z(z: np.ndarray) -> np.ndarray:
    """A right-handed orthonormal frame (columns) whose third axis is the unit vector ``z``."""
    e = np.eye(3)[int(np.argmin(np.abs(z)))]
    x = e - (e @ z) * z
    x /= np.linalg.norm(x)
    return np.column_stack([x, np.cross(z, x), z])


def inertia_at_g(model: Model, body: Body, ev: Evaluator, frame_turn: np.ndarray) -> np.ndarray | None:
    """Π_G in the body frame's basis, numbers (None when an entry has no value).

    ``frame_turn`` is the rotation (columns: the inertia frame's axes on the body frame) at one
    state: the identity when the inertia is given in the body frame, else constant or leaving Π
    unchanged (which the derivation checks).  Huygens' theorem moves Π from the point it is given
    at to G: Π_G = Π_P − m [(d·d) I − d dᵀ], d = GP.
    """
    subs = {se.Symbol(n): v for n, v in ev.values.items()}
    try:
        given = np.array([[float(e.subs(subs)) for e in row] for row in body.inertia.matrix])
        mass = float(body.mass.subs(subs))
    except (TypeError, RuntimeError, ValueError):
        return None
    if body.inertia.at != "G":
        d = ev.constant_in(model_point(model, body.inertia.at) - body.center, body.inertia.frame)
        if d is None:
            return None
        dv = np.array(d)
        given = given - mass * ((dv @ dv) * np.eye(3) - np.outer(dv, dv))
    pi = frame_turn @ given @ frame_turn.T
    return (pi + pi.T) / 2


def model_point(model: Model, name: str) -> Vector:
    """OP of a declared point, a body's centre G or a particle."""
    for items in (model.points, model.particles):
        for p in items:
            if p.name == name:
                return p.position
    return model.body(name).center


def attached_points(model: Model, ev: Evaluator, states: int = 5) -> dict[str, dict[str, np.ndarray]]:
    """For each body, the declared points fixed in it (GP constant on its frame), with GP on that frame.

    Decided numerically on a few random states (seeded): GP = C_Bᵀ (OP − OG) the same at each, to
    1e-9 of the model's size — O(bodies × points) numbers, where a symbolic test costs a derivative per
    coordinate of each component.
    """
    if not model.bodies:
        return {}
    rng = np.random.default_rng(20261127)
    n = len(model.coordinates)
    q0 = np.array([c.initial or 0.0 for c in model.coordinates])
    q = q0 + rng.uniform(-1.0, 1.0, (states, n))
    qd = rng.uniform(-1.0, 1.0, (states, n))
    t = rng.uniform(0.0, 1.0, states)
    names = [p.name for p in model.points]
    fixed = {b.fixed_point for b in model.bodies if b.fixed_point and b.fixed_point not in names}
    names += sorted(fixed)
    where = ev.vectors([model_point(model, name) for name in names] + [b.center for b in model.bodies], t, q, qd)
    bases = ev.bases([b.frame for b in model.bodies], t, q, qd)
    scale = max(float(np.max(np.abs(where))), 1e-300)
    out: dict[str, dict[str, np.ndarray]] = {}
    for k, body in enumerate(model.bodies):
        g = where[:, len(names) + k]
        c = np.asarray(bases[body.frame])
        local = np.einsum("sji,spj->spi", c, where[:, :len(names)] - g[:, None, :])  # Cᵀ (P − G), (states, P, 3)
        still = np.ptp(local, axis=0).max(axis=1) <= 1e-9 * scale
        out[body.name] = {name: local[0, j] for j, name in enumerate(names) if still[j]}
    return out


def joint_axis(model: Model, body: Body, ev: Evaluator, *, ground: bool = False) -> tuple[str, np.ndarray | None]:
    """How the body turns on what carries it: ``("hinge", axis)`` (one rotation about an axis, the axis
    unit on the body frame), ``("ball", None)`` (several), or ``("none", None)``.

    The rotations counted are those between the body's frame and the nearest frame above it that
    is R0 or another body's, whose angle moves (has t or a coordinate in it): a URDF joint's
    constant placement rotations do not count.  With ``ground``, a joint with another body is ``"none"``:
    only a joint on R0 counts.
    """
    moving = {se.Symbol("t")} | {c.symbol for c in model.coordinates}
    carriers = {b.frame for b in model.bodies if b.name != body.name} | {GALILEAN_FRAME}
    turns = []
    name: str | None = body.frame
    while name is not None and name not in carriers:
        frame = model.frame(name)
        if frame.rotation is not None and frame.rotation.angle.free_symbols & moving:
            turns.append(frame)
        name = frame.parent
    if not turns or (ground and name != GALILEAN_FRAME):
        return "none", None
    if len(turns) > 1:
        return "ball", None
    frame = turns[0]
    axis = Vector({frame.name: frame.rotation.unit_vector})  # type: ignore[union-attr]
    comps = ev.constant_in(axis, body.frame)
    if comps is None:
        return "ball", None
    v = np.array(comps)
    return "hinge", v / np.linalg.norm(v)


def _xyz(v: np.ndarray) -> tuple[float, float, float]:
    """The three components of ``v`` as floats."""
    return float(v[0]), float(v[1]), float(v[2])


def body_solid(builder, body: Body, attached: dict[str, np.ndarray], anchor: str) -> Solid | None:
    """The homogeneous solid of the body's inertia at G (None without values, or for a point mass)."""
    model, ev = builder.model, builder.ev
    state = builder.states[0]
    bases = ev.bases([body.frame, body.inertia.frame], builder.t[:1], state[0][:1], state[1][:1])
    turn = np.asarray(bases[body.frame][0]).T @ np.asarray(bases[body.inertia.frame][0])
    pi = inertia_at_g(model, body, ev, turn)
    try:
        mass = float(body.mass.subs({se.Symbol(k): v for k, v in ev.values.items()}))
    except (TypeError, RuntimeError, ValueError):
        return None
    if pi is None or not mass > 0:
        return None
    moments, axes = np.linalg.eigh(pi)
    direction = _joint_direction(attached, anchor, body)
    return solid_of_inertia(moments, axes, mass, _declared_axis(body, turn) if direction is None else direction)


def _joint_direction(attached: dict[str, np.ndarray], anchor: str, body: Body) -> np.ndarray | None:
    """The unit vector from the joint point to G (body frame), or None."""
    gp = attached.get(anchor) if anchor != body.name else None
    if gp is None or np.linalg.norm(gp) <= 1e-12 * max(float(np.max(np.abs(gp))), 1e-300) or not np.any(gp):
        return None
    return -gp / np.linalg.norm(gp)


def inferred_parts(builder, body: Body, carrier: int, attached: dict[str, np.ndarray], anchor: str,
                   color: str, length: float, solid: Solid | None) -> float | None:
    """Add the parts of a body the model gives no shape: the solid of its inertia at G, rods from its joint
    point to its other points, its joint.  Returns how far the body reaches from G along the line from its
    joint point (the apex of a top: where its tip is), or None when it has no such line."""
    from ..model import rotation_to
    from ._build import HINGE_RADIUS, JOINT_COLOR, ROD_RADIUS, _quat
    from ._scene import Part

    direction = _joint_direction(attached, anchor, body)
    reach = None
    if solid is not None:
        kind, size = solid.kind, solid.size
        if kind == "rod":
            size = (ROD_RADIUS * 1.3 * length, size[1])
        elif kind == "disk":
            size = (size[0], max(size[1], size[0] / 12))
        builder.parts.append(Part(body.name, carrier, kind, tuple(float(x) for x in size), (0.0, 0.0, 0.0),
                                  _quat(solid.axes), color, SEE_THROUGH if body.fixed_point else 1.0, "inertia",
                                  spoke=kind in ("disk", "cylinder")))
        if direction is not None:
            reach = _extent_along(solid, direction)
            if solid.kind in ("disk", "cylinder", "sphere"):  # a top's axle goes through its disk to its apex
                reach = max(reach, 0.6 * max(solid.size))
    # Rods from the joint point to the body's other points (the course's rod OA), or to G (to the apex, beyond
    # it, for a body turning about a point: the top's axle).
    start = attached.get(anchor) if anchor != body.name else None
    if start is not None:
        others = [gp for name, gp in attached.items() if name != anchor and np.linalg.norm(gp - start) > 1e-9 * length]
        through = [direction * reach] if reach is not None and direction is not None and solid is not None and \
            solid.kind != "rod" else [np.zeros(3)]
        for end in others or through:
            if solid is not None and solid.kind == "rod" and _inside_rod(solid, start, end):
                continue
            axis = end - start
            span = float(np.linalg.norm(axis))
            if span <= 1e-12 * length:
                continue
            builder.parts.append(Part(body.name, carrier, "rod", (ROD_RADIUS * length, span),
                                      _xyz((start + end) / 2),
                                      _quat(np.array(rotation_to(axis / span))), color, 1.0, "points"))
        kind, axis = joint_axis(builder.model, body, builder.ev)
        if kind == "hinge" and axis is not None:
            builder.parts.append(Part(body.name, carrier, "cylinder",
                                      (HINGE_RADIUS * length, 4 * HINGE_RADIUS * length),
                                      _xyz(start), _quat(np.array(rotation_to(axis))),
                                      JOINT_COLOR, 1.0, "hinge"))
        elif kind == "ball":
            builder.parts.append(Part(body.name, carrier, "sphere", (1.4 * HINGE_RADIUS * length,),
                                      _xyz(start), (0.0, 0.0, 0.0, 1.0), JOINT_COLOR, 1.0, "ball"))
    if solid is None and start is None:
        builder.parts.append(Part(body.name, carrier, "sphere", (0.04 * length,), (0.0, 0.0, 0.0), (0.0, 0.0, 0.0, 1.0),
                                  color, 1.0, "particle"))
        builder.notes.append(f"body `{body.name}`: no inertia with values and no points to draw it by: a small sphere")
    return reach


def _declared_axis(body: Body, turn: np.ndarray) -> np.ndarray | None:
    """The axis of the distinct moment of the inertia as declared (the top's z: A, A, C at O), body frame."""
    m = body.inertia.matrix
    if any(not _zero(m[i][j]) for i in range(3) for j in range(3) if i != j):
        return None
    d = [m[k][k] for k in range(3)]
    for k in range(3):
        i, j = [x for x in range(3) if x != k]
        if _zero(d[i] - d[j]) and not _zero(d[k] - d[i]):
            return turn[:, k] / np.linalg.norm(turn[:, k])
    return None


def _zero(e: se.Basic) -> bool:
    return se.expand(e) == 0


def _extent_along(solid: Solid, direction: np.ndarray) -> float:
    """How far the solid reaches from its centre along the unit ``direction`` (body frame)."""
    local = solid.axes.T @ direction
    if solid.kind == "sphere":
        return solid.size[0]
    if solid.kind == "box":
        return float(np.sum(np.abs(local) * np.array(solid.size) / 2))
    r, h = solid.size
    along = abs(local[2])
    return float(along * h / 2 + math.sqrt(max(1 - along ** 2, 0.0)) * r)


def _inside_rod(solid: Solid, a: np.ndarray, b: np.ndarray) -> bool:
    """Whether the segment ab lies along the thin rod ``solid`` (centred at G, along its z) and within it."""
    axis = solid.axes[:, 2]
    half = solid.size[1] / 2
    for p in (a, b):
        along = float(p @ axis)
        if np.linalg.norm(p - along * axis) > 1e-6 * max(half, 1e-300) or abs(along) > half * (1 + 1e-6):
            return False
    return True
