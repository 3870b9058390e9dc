"""The frame tree: orientation of every frame, change of basis, and Ω(F/R0).

Each frame comes from its parent by one elementary rotation of angle α about an
axis e shared by both (R0 →(ψ, z0)→ R1 →(θ, u)→ R2 →(φ, z)→ R).  So

    Ω(F/R0) = Σ over the chain α̇_k e_k        (composition of rotation rates)

which is kept as a sum of pieces, each in its own frame, exactly as the course
writes ψ̇ z0 + θ̇ u + φ̇ z.  A change of basis walks the tree through the lowest
common ancestor and merges consecutive rotations about the same axis (R_z(α)R_z(β)
= R_z(α+β)), so planar chains give cos(q1 + q2), not a product of sines and cosines.
"""

from __future__ import annotations

from functools import lru_cache

import symengine as se

from ..model import GALILEAN_FRAME, Model, Vector
from ..model._vector import AXES, is_structural_zero
from ._time import TimeDerivative

__all__ = ["FrameTree"]

Components = tuple[se.Basic, se.Basic, se.Basic]

_ZERO = se.Integer(0)


def _rotate(axis: int, angle: se.Basic, v: Components) -> Components:
    """Components in the parent of a vector with components ``v`` in the child.

    The child is the parent turned by ``angle`` about their common ``axis``.
    """
    if is_structural_zero(angle):
        return v
    c, s = se.cos(angle), se.sin(angle)
    i, j = (axis + 1) % 3, (axis + 2) % 3
    out = list(v)
    out[i] = c * v[i] - s * v[j]
    out[j] = s * v[i] + c * v[j]
    return tuple(out)  # type: ignore[return-value]


class FrameTree:
    """Orientation data of every frame of a model, with cached conversions."""

    def __init__(self, model: Model, d_dt: TimeDerivative) -> None:
        self.frames = {f.name: f for f in model.frames}
        self.d_dt = d_dt
        self._depth = {}
        for f in model.frames:  # parents come first
            self._depth[f.name] = 0 if f.parent is None else self._depth[f.parent] + 1
        self._path = lru_cache(maxsize=None)(self._path_uncached)
        self._omega: dict[str, Vector] = {}
        self._omega_in: dict[tuple[str, str], Components] = {}

    def axes(self, frame: str) -> tuple[str, str, str]:
        return self.frames[frame].axes

    # -- change of basis -------------------------------------------------------------------
    def _path_uncached(self, src: str, dst: str) -> tuple[tuple[int, se.Basic], ...]:
        """Rotations (axis, angle) that take components in ``src`` to components in ``dst``."""
        up, down = [], []
        a, b = src, dst
        while self._depth[a] > self._depth[b]:
            up.append(a)
            a = self.frames[a].parent  # type: ignore[assignment]
        while self._depth[b] > self._depth[a]:
            down.append(b)
            b = self.frames[b].parent  # type: ignore[assignment]
        while a != b:
            up.append(a)
            down.append(b)
            a = self.frames[a].parent  # type: ignore[assignment]
            b = self.frames[b].parent  # type: ignore[assignment]
        steps: list[tuple[int, se.Basic]] = []
        for name in up:
            rot = self.frames[name].rotation
            steps.append((AXES[rot.axis], rot.angle))  # type: ignore[union-attr]
        for name in reversed(down):
            rot = self.frames[name].rotation
            steps.append((AXES[rot.axis], -rot.angle))  # type: ignore[union-attr]
        merged: list[tuple[int, se.Basic]] = []
        for axis, angle in steps:
            if merged and merged[-1][0] == axis:
                merged[-1] = (axis, merged[-1][1] + angle)
            else:
                merged.append((axis, angle))
        return tuple((ax, an) for ax, an in merged if not is_structural_zero(an))

    def convert(self, comps: Components, src: str, dst: str) -> Components:
        """Components in ``dst`` of the vector whose components in ``src`` are ``comps``."""
        if src == dst:
            return comps
        for axis, angle in self._path(src, dst):
            comps = _rotate(axis, angle, comps)
        return comps

    def express(self, v: Vector, frame: str) -> Components:
        """The three components of ``v`` in the basis of ``frame``."""
        total: Components | None = None
        for src, comps in v:
            conv = self.convert(comps, src, frame)
            total = conv if total is None else (total[0] + conv[0], total[1] + conv[1], total[2] + conv[2])
        if total is None:
            return (_ZERO, _ZERO, _ZERO)
        return total

    def lift(self, v: Vector) -> Vector:
        """The same vector with each piece moved to the highest frame where its components are unchanged.

        A vector along the rotation axis of F is the same vector in F's parent (a R.z = a R2.z
        when R comes from R2 by a rotation about z): differentiating it there gives the
        short expressions a student writes, with no angle of the final rotation in them.
        """
        out: dict[str, Components] = {}
        for frame, comps in v:
            f = self.frames[frame]
            while f.parent is not None:
                k = AXES[f.rotation.axis]  # type: ignore[union-attr]
                if any(not is_structural_zero(comps[i]) for i in range(3) if i != k):
                    break
                f = self.frames[f.parent]
            _accumulate(out, f.name, comps)
        return Vector._trusted(out)

    def best_frame(self, *vectors: Vector) -> str:
        """A frame in which to compute products of ``vectors``: the deepest one they use."""
        frames = [f for v in vectors for f in v.frames]
        if not frames:
            return GALILEAN_FRAME
        return max(frames, key=lambda f: (frames.count(f), self._depth[f]))

    def dot(self, u: Vector, v: Vector, frame: str | None = None) -> se.Basic:
        if u.is_zero() or v.is_zero():
            return se.Integer(0)
        frame = frame or self.best_frame(u, v)
        a, b = self.express(u, frame), self.express(v, frame)
        return se.Add(*(x * y for x, y in zip(a, b)))

    def cross(self, u: Vector, v: Vector, frame: str | None = None) -> Vector:
        if u.is_zero() or v.is_zero():
            return Vector.zero()
        frame = frame or self.best_frame(u, v)
        return Vector({frame: _cross(self.express(u, frame), self.express(v, frame))})

    # -- angular velocity ------------------------------------------------------------------
    def omega(self, frame: str) -> Vector:
        """Ω(frame/R0) = Σ α̇_k e_k along the chain from R0, one piece per rotation."""
        if frame not in self._omega:
            f = self.frames[frame]
            if f.parent is None:
                self._omega[frame] = Vector.zero()
            else:
                rot = f.rotation
                rate = self.d_dt(rot.angle, accelerations=False)  # type: ignore[union-attr]
                own = Vector.basis(frame, rot.axis) * rate  # type: ignore[union-attr]
                self._omega[frame] = self.omega(f.parent) + own
        return self._omega[frame]

    def omega_in(self, frame: str, basis: str) -> Components:
        """Components of Ω(frame/R0) in the basis of ``basis`` (cached)."""
        key = (frame, basis)
        if key not in self._omega_in:
            self._omega_in[key] = self.express(self.omega(frame), basis)
        return self._omega_in[key]

    # -- derivative of a vector with respect to R0 ------------------------------------------
    def derivative(self, v: Vector, *, accelerations: bool = True) -> Vector:
        """d v/dt relative to R0:  Σ_F [ (d/dt of the components in F) + Ω(F/R0) ∧ v_F ].

        (Formule de dérivation vectorielle: each piece is differentiated in its own frame.)
        """
        out: dict[str, Components] = {}
        for frame, comps in self.lift(v):
            own = tuple(self.d_dt(c, accelerations=accelerations) for c in comps)
            transport = _cross(self.omega_in(frame, frame), comps)
            _accumulate(out, frame, tuple(a + b for a, b in zip(own, transport)))  # type: ignore[arg-type]
        return Vector._trusted(out)


def _accumulate(out: dict[str, Components], frame: str, comps: Components) -> None:
    """``out += Vector({frame: comps})`` on a dict of pieces, with `Vector.__add__`'s piece order.

    A zero piece is not added, and a piece that sums to zero leaves the dict (a later piece
    in that frame then goes to the end), exactly as the sum of Vectors would do.
    """
    if all(is_structural_zero(c) for c in comps):
        return
    old = out.get(frame)
    if old is None:
        out[frame] = comps
        return
    total = (old[0] + comps[0], old[1] + comps[1], old[2] + comps[2])
    if all(is_structural_zero(c) for c in total):
        del out[frame]
    else:
        out[frame] = total


def _cross(a: Components, b: Components) -> Components:
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])
