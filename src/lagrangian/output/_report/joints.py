"""Step 1 of the report: the constraints that the model's parameterization takes as principal.

A model does not list its constraints: it places every body and particle as a function of
the principal parameters q_i (and of t), which *is* the choice of principal constraints
(seed, "Démarche d'application", step 1).  This module reads them back, element by
element, in the order of the model:

* the element's *support* is the earlier element whose parameters are a largest proper
  subset of its own (or the fixed frame R0), and its *new* parameters d are the others;
  the constraint then removes 6 − d (a body) or 3 − d (a particle) degrees of freedom;
* a body with a fixed point X is "X point fixe" (three rotations left: the seed's top) or
  a pivot about the axis of its one rotation; a body that shares a point A with its
  support and turns about one axis relative to it is a pivot of axis (A, e); three
  rotations, a ball joint;
* a particle at constant distance from a point X of its support hangs from a massless rod
  (or taut string) XP; a component of XP along an axis of R0 that stays constant keeps it
  in a plane; two such components put it on a line (a rail).

A body whose centre keeps constant components along axes of a fixed frame and that turns
about fewer than three axes (a coin kept upright on a plane, a disk on an incline) is a
"body plane": the report writes those components and the rotations left.  Anything else is
reported as "the placement of E" with its count.  Every constraint here is holonomic (the
model gives positions, not velocity relations) and principal; it is perfect unless a
Coulomb friction load acts at the element, a joint damper acts across it, or a dissipation
function declares that it acts in that joint (a URDF's damping): then ``losses`` names them,
their virtual power is not zero and they enter Q_i(nc).
"""

from __future__ import annotations

from dataclasses import dataclass

import symengine as se

from ..._identity import are_zero
from ...dynamics import EquationsOfMotion
from ...model import GALILEAN_FRAME, ORIGIN, Vector
from ...model.vectors import AXES

__all__ = ["Joint", "joints", "degrees_of_freedom", "constraint_counts", "planar_normal"]


@dataclass(frozen=True, slots=True)
class Joint:
    """One principal constraint, as the report states it.

    ``kind`` is ``"fixed point"``, ``"pivot"``, ``"ball joint"``, ``"rod"``, ``"line"``,
    ``"plane"`` or ``"placement"`` (none of those shapes).  ``support`` is the element it
    ties ``element`` to (None: the fixed frame R0); ``point`` is the fixed point, the
    joint's centre or the rod's anchor; ``axis`` the pivot axis or the rail's direction
    (a display name such as ``"x0"``); ``normals`` the axes of R0 along which the element
    keeps a constant offset from ``point`` (planes); ``length`` the rod's length |XP|.  ``rotation`` is the virtual rotation
    relative to the support, Ω*(E) − Ω*(support), and ``star`` the q_i* it uses.
    """

    kind: str
    element: str
    is_body: bool
    support: str | None
    point: str | None
    axis: str | None
    normals: tuple[str, ...]
    length: se.Basic | None
    equations: int
    coordinates: tuple[str, ...]
    time_dependent: bool
    rotation: Vector | None = None
    holonomic: bool = True
    principal: bool = True
    #: (load name, "coulomb" or "damper") of the loads that make it not perfect.
    losses: tuple[tuple[str, str], ...] = ()
    #: For a "body plane": the frame whose axes ``normals`` are, the constant components of OG
    #: along them, and the axes the body may still turn about.
    frame: str | None = None
    offsets: tuple[se.Basic, ...] = ()
    turns: tuple[str, ...] = ()

    @property
    def perfect(self) -> bool:
        return not self.losses


def _free(e: se.Basic) -> set[se.Basic]:
    return set(e.free_symbols)


def _constant(kin, exprs: list[se.Basic]) -> list[bool]:
    """Which expressions are free of q and t *as functions* (∂/∂q_i ≡ 0 and ∂/∂t ≡ 0)."""
    moving = set(kin.q) | {kin.t}
    out: list[bool | None] = []
    tests: list[se.Basic] = []
    where: list[tuple[int, int]] = []
    for k, e in enumerate(exprs):
        hit = _free(e) & moving
        if not hit:
            out.append(True)
            continue
        out.append(None)
        start = len(tests)
        tests += [e.diff(s) for s in hit]
        where.append((k, start))
    if tests:
        zero = are_zero(tests)
        bounds = [start for _, start in where] + [len(tests)]
        for (k, start), stop in zip(where, bounds[1:], strict=True):
            out[k] = all(zero[start:stop])
    return [bool(x) for x in out]


class _Reader:
    """The elements of a model with their parameters, frames and points, for `joints`."""

    def __init__(self, eom: EquationsOfMotion) -> None:
        self.eom = eom
        self.kin = eom.kinematics
        model = eom.model
        self.model = model
        self.frames = {f.name: f for f in model.frames}
        # Constraints are stated relative to the frame the equations are written in (R0, or R).
        self.base = model.reference.frame if model.reference is not None else GALILEAN_FRAME
        q_names = {c.symbol: c.name for c in model.coordinates}
        self.q_names = q_names
        self.elements: list[tuple[str, bool]] = ([(b.name, True) for b in model.bodies]
                                                 + [(p.name, False) for p in model.particles])
        self.coords: dict[str, frozenset[str]] = {}
        self.timed: dict[str, bool] = {}
        for name, is_body in self.elements:
            position = self.kin.position(name)
            symbols = set(position.free_symbols())
            frames = set(position.frames) | ({self.model.body(name).frame} if is_body else set())
            for top in frames:
                for frame in self.chain(top):
                    symbols |= _free(self.frames[frame].rotation.angle)  # type: ignore[union-attr]
            self.coords[name] = frozenset(q_names[s] for s in symbols if s in q_names)
            self.timed[name] = self.kin.t in symbols

    def chain(self, frame: str, stop: str | None = None) -> list[str]:
        """Frames from just below ``stop`` (the base frame) down to ``frame``; empty if ``stop`` is not an ancestor."""
        if stop is None:
            below_base = self.chain(frame, self.base) if self.base != GALILEAN_FRAME else []
            if below_base or frame == self.base:
                return below_base
            stop = GALILEAN_FRAME
        out = []
        f = frame
        while f != stop:
            out.append(f)
            parent = self.frames[f].parent
            if parent is None:
                return []
            f = parent
        return out[::-1]

    def frame_of(self, element: str | None) -> str:
        if element is None:
            return self.base
        for b in self.model.bodies:
            if b.name == element:
                return b.frame
        return GALILEAN_FRAME

    def support(self, name: str) -> str | None:
        """The earlier element whose parameters are the largest proper subset of ``name``'s."""
        mine = self.coords[name]
        best, size = None, 0
        for other, _ in self.elements:
            if other == name:
                continue
            theirs = self.coords[other]
            if theirs < mine and len(theirs) > size:
                best, size = other, len(theirs)
        return best

    def fixed_in(self, point: str, element: str | None) -> bool:
        """Whether ``point`` is a point of ``element`` (of R0 when None)."""
        kin = self.kin
        if element is None:
            return kin.is_fixed(point)
        d = kin.position(point) - kin.position(element)
        if element not in {b.name for b in self.model.bodies}:
            return d.is_zero() or all(_constant(kin, list(kin.frames.express(d, self.base))))
        comps = kin.frames.express(d, self.frame_of(element))
        return all(_constant(kin, list(comps)))

    def moves_with_q(self, point: str) -> bool:
        """Whether ``point``'s position depends on a principal parameter (through its frames too)."""
        position = self.kin.position(point)
        symbols = set(position.free_symbols())
        for top in position.frames:
            for frame in self.chain(top):
                symbols |= _free(self.frames[frame].rotation.angle)  # type: ignore[union-attr]
        return bool(symbols & set(self.q_names))

    def points(self) -> list[str]:
        return [ORIGIN] + [p.name for p in self.model.points if p.name != ORIGIN]

    def rotations(self, element: str, support: str | None) -> list[tuple[str, str]] | None:
        """(frame, axis display name) of each rotation with a q_i between support and element."""
        path = self.chain(self.frame_of(element), self.frame_of(support))
        if not path and self.frame_of(element) != self.frame_of(support):
            return None
        out = []
        for f in path:
            rot = self.frames[f].rotation
            if _free(rot.angle) & set(self.q_names):  # type: ignore[union-attr]
                if not rot.elementary:  # type: ignore[union-attr]
                    return None  # about a vector n: no axis name to give (the joint is described generally)
                out.append((f, self.frames[f].axes[AXES[rot.axis]]))  # type: ignore[union-attr]
        return out


def _body_joint(r: _Reader, name: str, support: str | None, new: tuple[str, ...]) -> Joint:
    kin = r.kin
    body = r.model.body(name)
    timed = r.timed[name]
    rotations = r.rotations(name, support)
    candidates = [body.fixed_point] if body.fixed_point else [p for p in r.points()
                                                               if r.fixed_in(p, support) and r.fixed_in(p, name)]
    if rotations is not None and candidates and len(rotations) == len(new) and rotations and not timed:
        point = candidates[0]
        rel = tuple(a - b for a, b in zip(kin.partial_omegas(body.frame),
                                         kin.partial_omegas(r.frame_of(support)), strict=True))
        rotation = Vector.zero()
        for part, star in zip(rel, kin.q_star, strict=True):
            rotation = rotation + part * star
        if len(rotations) == 1:
            return Joint("pivot", name, True, support, point, rotations[0][1], (), None, 5, new, timed, rotation)
        kind = "fixed point" if body.fixed_point and support is None else "ball joint"
        if len(rotations) == 3:
            return Joint(kind, name, True, support, point, None, (), None, 3, new, timed, rotation)
    if support is None and rotations is not None and not timed and len(rotations) < 3:
        found = _body_plane(r, name, len(new), len(rotations))
        if found is not None:
            frame, normals, offsets = found
            return Joint("body plane", name, True, None, None, None, normals, None, 6 - len(new), new, timed,
                         frame=frame, offsets=offsets, turns=tuple(axis for _, axis in rotations))
    return Joint("placement", name, True, support, None, None, (), None, 6 - len(new), new, timed)


def _fixed_frames(r: _Reader) -> list[str]:
    """The base frame, then the frames turned from it by constant angles (an incline's frame)."""
    moving = set(r.kin.q) | {r.kin.t}
    out = [r.base]
    for f in r.model.frames:
        path = r.chain(f.name, r.base)
        if path and all(not (_free(r.frames[x].rotation.angle) & moving) for x in path):  # type: ignore[union-attr]
            out.append(f.name)
    return out


def _body_plane(r: _Reader, name: str, new: int, turns: int) -> tuple[str, tuple[str, ...], tuple[se.Basic, ...]] | None:
    """(frame, axes, values) with OG·axis = value constant, when they and the blocked rotations count 6 − new."""
    kin = r.kin
    d = kin.position(name) - kin.position(ORIGIN)
    for frame in _fixed_frames(r):
        comps = list(kin.frames.express(d, frame))
        flat = _constant(kin, comps)
        normals = tuple(r.frames[frame].axes[k] for k in range(3) if flat[k])
        if normals and len(normals) + (3 - turns) == 6 - new:
            return frame, normals, tuple(se.expand(comps[k]) for k in range(3) if flat[k])
    return None


def _particle_joint(r: _Reader, name: str, support: str | None, new: tuple[str, ...]) -> Joint:
    kin = r.kin
    timed = r.timed[name]
    wanted = 3 - len(new)
    if support is None:
        # Fixed points first, then points moved by a prescribed motion (the Kapitza pendulum's pivot).
        q = set(kin.q)
        anchors = sorted((p for p in r.points() if not (kin.position(p).free_symbols() & q)
                          and not r.moves_with_q(p)), key=lambda p: not kin.is_fixed(p))
    elif support in {p.name for p in r.model.particles}:
        anchors = [support]
    else:
        anchors = [p for p in r.points() if r.fixed_in(p, support)] + [support]
    # The axes of the base frame first, then those of the frames turned from it by constant angles (a block
    # on an incline stays on a line of the incline's frame, not of R0's).
    frames = _fixed_frames(r)
    for anchor in anchors:
        d = kin.position(name) - kin.position(anchor)
        squared = kin.frames.dot(d, d)
        for frame in frames:
            axes = r.frames[frame].axes
            comps = list(kin.frames.express(d, frame))
            *flat, rigid = _constant(kin, comps + [squared])
            normals = tuple(axes[k] for k in range(3) if flat[k])
            if rigid and len(normals) <= 1 and 1 + len(normals) == wanted:
                # |XP|² is constant as a function: its value at q = 0, t = 0 is its simplest form (l² rather
                # than l² cos²θ + l² sin²θ).
                at_zero = se.expand(squared.xreplace({s: se.Integer(0) for s in (*kin.q, kin.t)}))
                length = _root(at_zero if at_zero != 0 else squared)
                return Joint("rod", name, False, support, anchor, None, normals, length, wanted, new, timed,
                             frame=frame)
            if len(normals) == 2 and wanted == 2:
                direction = next(axes[k] for k in range(3) if not flat[k])
                return Joint("line", name, False, support, anchor, direction, normals, None, 2, new, timed,
                             frame=frame)
            if len(normals) == 1 and wanted == 1:
                return Joint("plane", name, False, support, anchor, None, normals, None, 1, new, timed, frame=frame)
    return Joint("placement", name, False, support, None, None, (), None, wanted, new, timed)


def _root(squared: se.Basic) -> se.Basic:
    """√(X²) = X for a length (lengths are positive): l² → l, l1² l2² → l1 l2, else the square root."""
    factors = squared.args if isinstance(squared, se.Mul) else (squared,)
    if all(isinstance(f, se.Pow) and f.args[1] == 2 for f in factors):
        return se.Mul(*(f.args[0] for f in factors))
    return se.sqrt(squared)


def joints(eom: EquationsOfMotion) -> tuple[Joint, ...]:
    """The principal constraints of a model, one per body or particle, in model order."""
    r = _Reader(eom)
    order = [c.name for c in eom.model.coordinates]
    out = []
    for name, is_body in r.elements:
        support = r.support(name)
        base = r.coords[support] if support is not None else frozenset()
        new = tuple(c for c in order if c in r.coords[name] - base)
        joint = (_body_joint if is_body else _particle_joint)(r, name, support, new)
        if joint.equations > 0:  # a free element (six or three parameters of its own) has no constraint
            out.append(_with_losses(r, joint))
    return tuple(out)


def _with_losses(r: _Reader, joint: Joint) -> Joint:
    """The joint with the friction loads that act in it: Coulomb friction at the element, a damper across it."""
    from dataclasses import replace

    from ...model import CoulombFriction, Dissipation, JointDamper

    losses: list[tuple[str, str]] = []
    points = {p.name for p in r.model.points}
    for load in r.model.loads:
        if isinstance(load, Dissipation) and set(load.joints) & set(joint.coordinates):
            losses.append((load.name, "damper"))  # a URDF's <dynamics damping>: viscous friction in the joint
            continue
        if isinstance(load, CoulombFriction):
            at_element = load.at == joint.element or (
                joint.is_body and load.at in points and r.fixed_in(load.at, joint.element))
            if at_element:
                losses.append((load.name, "coulomb"))
        elif isinstance(load, JointDamper):
            ends = {r.frame_of(x) if x in {b.name for b in r.model.bodies} else x for x in load.bodies}
            if joint.is_body and ends == {r.frame_of(joint.element), r.frame_of(joint.support)}:
                losses.append((load.name, "damper"))
    return replace(joint, losses=tuple(losses)) if losses else joint


def degrees_of_freedom(eom: EquationsOfMotion, found: tuple[Joint, ...]) -> tuple[int, int, int] | None:
    """(6 × bodies + 3 × particles, constraint equations, n) when they balance, else None.

    They balance when each principal parameter is new for exactly one element: then the
    count 6 N_S + 3 N_P − (equations) = n of the course holds.
    """
    n = len(eom.coordinates)
    news = [c for j in found for c in j.coordinates]
    if sorted(news) != sorted(eom.coordinates):
        return None
    free = 6 * len(eom.model.bodies) + 3 * len(eom.model.particles)
    total = sum(j.equations for j in found)
    return (free, total, n) if free - total == n else None


def constraint_counts(eom: EquationsOfMotion) -> tuple[int, int, int]:
    """(n, h, k): principal parameters, complementary holonomic rows, nonholonomic rows.

    The degrees of freedom are n − h − k (independent velocities); the position depends on
    n − h independent parameters (a nonholonomic row restricts only the velocities).  A velocity
    row that integrates (the disk on an incline) counts as holonomic here, as in step 7.
    """
    from ...dynamics import describe_constraints

    holonomic_names = {info.name for info in describe_constraints(eom) if info.kind == "holonomic"}
    # A unilateral contact is an inequality g ≥ 0: it removes no parameter (only while closed).
    contacts = {c.name for c in eom.model.constraints if c.unilateral}
    rows = [row for row in eom.constraints if row.constraint not in contacts]
    h = sum(1 for row in rows if row.kind == "holonomic" or row.constraint in holonomic_names)
    return len(eom.coordinates), h, len(rows) - h


def planar_normal(eom: EquationsOfMotion) -> int | None:
    """The axis k of R0 normal to the plane of the motion when it is planar by construction, else None.

    Planar: the k-th R0 component of every partial velocity ∂V(P)/∂q̇_i of every centre vanishes
    identically, and every partial angular velocity ∂Ω(S)/∂q̇_i is along that axis.
    """
    kin, model = eom.kinematics, eom.model
    if not eom.coordinates or (model.reference is not None and not model.reference.is_galilean_frame):
        return None
    express = kin.frames.express
    centres = [b.name for b in model.bodies] + [p.name for p in model.particles]
    if not centres:
        return None
    velocities = [express(v, GALILEAN_FRAME) for name in centres for v in kin.partial_velocities(name)]
    omegas = [express(w, GALILEAN_FRAME) for b in model.bodies for w in kin.partial_omegas(b.frame)]
    for k in range(3):
        along = [v[k] for v in velocities] + [w[j] for w in omegas for j in range(3) if j != k]
        if all(are_zero(along)):
            return k
    return None

