"""The frame tree: orientation of every frame, change of basis, and Ω(F/R0).

Each frame comes from its parent by one rotation of angle α about an axis e shared by
both: an elementary one (R0 →(ψ, z0)→ R1 →(θ, u)→ R2 →(φ, z)→ R), or one about a
constant unit vector n of the parent (the Earth about cos λ y0 + sin λ z0), whose change
of basis is Rodrigues' formula v ↦ cos α v + sin α n ∧ v + (1 − cos α)(n·v) n.  So

    Ω(F/R0) = Σ over the chain α̇_k e_k        (composition of rotation rates)

which is kept as a sum of pieces, each in its own frame, exactly as the course
writes ψ̇ z0 + θ̇ u + φ̇ z.  A change of basis walks the tree through the lowest
common ancestor and merges consecutive rotations about the same axis (R_z(α)R_z(β)
= R_z(α+β)), so planar chains give cos(q1 + q2), not a product of sines and cosines.
"""

from __future__ import annotations

import symengine as se

from ..model import GALILEAN_FRAME, Model, Vector
from ..model.vectors import AXES, Components, add3, cross, is_structural_zero, sum_of, turn, turn_about
from ._time import TimeDerivative

__all__ = ["FrameTree", "rotation_rate"]

_ZERO = se.Integer(0)
_ZERO_TYPE = type(_ZERO)


def rotation_rate(rotation, rate: se.Basic) -> Components:
    """The rotation rate α̇ e of ``rotation`` in the child's basis, e its axis.

    Parameters
    ----------
    rotation : Rotation
        The elementary rotation.
    rate : SymEngine expression
        The rate α̇ of its angle.

    Returns
    -------
    tuple of three SymEngine expressions
        The components of α̇ e in the child's basis.
    """
    if rotation.elementary:
        comps = [_ZERO, _ZERO, _ZERO]
        comps[AXES[rotation.axis]] = rate
        return tuple(comps)
    return tuple(rate * a if not is_structural_zero(a) else _ZERO for a in rotation.direction)


class FrameTree:
    """Orientation data of every frame of a model, with cached conversions.

    Parameters
    ----------
    model : Model
        The model whose frames it holds.
    d_dt : TimeDerivative
        The time derivative of expressions in q, q̇ and t.
    """

    def __init__(self, model: Model, d_dt: TimeDerivative) -> None:
        self.frames = {f.name: f for f in model.frames}
        self.d_dt = d_dt
        self._depth: dict[str, int] = {}
        for f in model.frames:  # parents come first
            self._depth[f.name] = 0 if f.parent is None else self._depth[f.parent] + 1
        self._paths: dict[tuple[str, str], tuple[tuple[int | Components, se.Basic, se.Basic], ...]] = {}
        self._omega: dict[str, Vector] = {}
        self._omega_in: dict[tuple[str, str], Components] = {}

    def axes(self, frame: str) -> tuple[str, str, str]:
        return self.frames[frame].axes

    # -- change of basis -------------------------------------------------------------------
    def _path_uncached(self, src: str, dst: str) -> tuple[tuple[int | Components, se.Basic, se.Basic], ...]:
        """Rotations (axis, cos angle, sin angle) that take components in ``src`` to components in ``dst``.

        The axis is an index (x, y, z) or the components of a constant unit vector n.
        """
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
        steps: list[tuple[int | Components, se.Basic]] = []
        for name in up:
            rot = self.frames[name].rotation
            steps.append((_axis_key(rot), rot.angle))  # type: ignore[union-attr]
        for name in reversed(down):
            rot = self.frames[name].rotation
            steps.append((_axis_key(rot), -rot.angle))  # type: ignore[union-attr]
        merged: list[tuple[int | Components, se.Basic]] = []
        for axis, angle in steps:
            if merged and merged[-1][0] == axis:
                merged[-1] = (axis, merged[-1][1] + angle)
            else:
                merged.append((axis, angle))
        # Each rotation with its cosine and sine, made once per path.
        return tuple((ax, se.cos(an), se.sin(an)) for ax, an in merged if not is_structural_zero(an))

    def convert(self, comps: Components, src: str, dst: str) -> Components:
        """Convert the components ``comps`` of a vector from the basis of ``src`` to that of ``dst``.

        Parameters
        ----------
        comps : tuple of three SymEngine expressions
            The components in ``src``.
        src : str
            The frame they are given in.
        dst : str
            The frame wanted.

        Returns
        -------
        tuple of three SymEngine expressions
            The components in ``dst``.
        """
        if src == dst:
            return comps
        path = self._paths.get((src, dst))
        if path is None:
            path = self._paths[(src, dst)] = self._path_uncached(src, dst)
        for axis, c, s in path:
            comps = turn(axis, c, s, comps) if type(axis) is int else turn_about(axis, c, s, comps)  # type: ignore[arg-type]
        return comps

    def express(self, v: Vector, frame: str) -> Components:
        """The three components of ``v`` in the basis of ``frame``.

        Parameters
        ----------
        v : Vector
            The vector.
        frame : str
            The frame whose basis is wanted.

        Returns
        -------
        tuple of three SymEngine expressions
            The components.
        """
        total: Components | None = None
        for src, comps in v:
            conv = self.convert(comps, src, frame)
            total = conv if total is None else add3(total, conv)
        if total is None:
            return (_ZERO, _ZERO, _ZERO)
        return total

    def lift(self, v: Vector) -> Vector:
        """The same vector with each piece moved to the highest frame where its components are unchanged.

        A vector along the rotation axis of F is the same vector in F's parent (a R.z = a R2.z
        when R comes from R2 by a rotation about z): differentiating it there gives the
        short expressions a student writes, with no angle of the final rotation in them.

        Parameters
        ----------
        v : Vector
            The vector.

        Returns
        -------
        Vector
            The same vector, its pieces in frames as high in the tree as they can be.
        """
        out: dict[str, Components] = {}
        moved = False
        for frame, comps in v:
            f = self.frames[frame]
            while f.parent is not None:
                if not f.rotation.elementary:  # type: ignore[union-attr]
                    break  # (a piece along a general axis n is rare: left where it is)
                k = AXES[f.rotation.axis]  # type: ignore[union-attr]
                if any(type(comps[i]) is not _ZERO_TYPE for i in range(3) if i != k):
                    break
                f = self.frames[f.parent]
                moved = True
            _accumulate(out, f.name, comps)
        return Vector._trusted(out) if moved else v

    def best_frame(self, *vectors: Vector) -> str:
        """A frame in which to compute products of ``vectors``: the deepest one they use.

        Parameters
        ----------
        *vectors : Vector
            The vectors to be multiplied.

        Returns
        -------
        str
            The deepest frame they use.
        """
        # The most used frame, the deepest among equals, the first met among those
        # (what max(frames, key=(count, depth)) gives on the list of their frames).
        if len(vectors) == 2:
            # The common case dot(u, v) of two one-piece vectors: the deeper frame, u's among equals.
            fu, fv = vectors[0].frames, vectors[1].frames
            if len(fu) == 1 and len(fv) == 1:
                a, b = fu[0], fv[0]
                return b if a != b and self._depth[b] > self._depth[a] else a
        counts: dict[str, int] = {}
        for v in vectors:
            for f in v.frames:
                counts[f] = counts.get(f, 0) + 1
        if not counts:
            return GALILEAN_FRAME
        depth = self._depth
        best, best_key = GALILEAN_FRAME, (-1, -1)
        for f, count in counts.items():
            key = (count, depth[f])
            if key > best_key:
                best, best_key = f, key
        return best

    def dot(self, u: Vector, v: Vector, frame: str | None = None) -> se.Basic:
        if u.is_zero() or v.is_zero():
            return _ZERO
        frame = frame or self.best_frame(u, v)
        a = self.express(u, frame)
        b = a if v is u else self.express(v, frame)
        return sum_of([x * y for x, y in zip(a, b, strict=True) if type(x) is not _ZERO_TYPE and type(y) is not _ZERO_TYPE])

    def cross(self, u: Vector, v: Vector, frame: str | None = None) -> Vector:
        if u.is_zero() or v.is_zero():
            return Vector.zero()
        frame = frame or self.best_frame(u, v)
        return Vector({frame: cross(self.express(u, frame), self.express(v, frame))})

    # -- angular velocity ------------------------------------------------------------------
    def omega(self, frame: str) -> Vector:
        """Ω(frame/R0) = Σ α̇_k e_k along the chain from R0, one piece per rotation.

        Parameters
        ----------
        frame : str
            The frame.

        Returns
        -------
        Vector
            Ω(frame/R0).
        """
        if frame not in self._omega:
            f = self.frames[frame]
            if f.parent is None:
                self._omega[frame] = Vector.zero()
            else:
                rot = f.rotation
                rate = self.d_dt(rot.angle, accelerations=False)  # type: ignore[union-attr]
                own = Vector._trusted({frame: rotation_rate(rot, rate)})  # rate × (frame.axis)
                parent = self.omega(f.parent)
                self._omega[frame] = own if parent.is_zero() else parent + own
        return self._omega[frame]

    def omega_in(self, frame: str, basis: str) -> Components:
        """The components of Ω(frame/R0) in the basis of ``basis`` (cached).

        Parameters
        ----------
        frame : str
            The frame whose rotation rate is wanted.
        basis : str
            The frame whose basis is wanted.

        Returns
        -------
        tuple of three SymEngine expressions
            The components.
        """
        key = (frame, basis)
        if key not in self._omega_in:
            self._omega_in[key] = self.express(self.omega(frame), basis)
        return self._omega_in[key]

    # -- derivative of a vector with respect to R0 ------------------------------------------
    def derivative(self, v: Vector, *, accelerations: bool = True) -> Vector:
        """The derivative d v/dt relative to R0:  Σ_F [ (d/dt of the components in F) + Ω(F/R0) ∧ v_F ].

        (Formule de dérivation vectorielle: each piece is differentiated in its own frame.)

        Parameters
        ----------
        v : Vector
            The vector, a function of q, q̇ and t.
        accelerations : bool, optional
            False leaves out the terms in q̈ (the derivative of the rates is taken as zero).

        Returns
        -------
        Vector
            The derivative d v/dt relative to R0.
        """
        out: dict[str, Components] = {}
        d_dt = self.d_dt
        for frame, comps in self.lift(v):
            own = tuple(c if type(c) is _ZERO_TYPE else d_dt(c, accelerations=accelerations) for c in comps)
            _accumulate(out, frame, add3(own, cross(self.omega_in(frame, frame), comps)))
        return Vector._trusted(out)


def _axis_key(rotation) -> int | Components:
    """The axis of a `Rotation` as `turn` or `turn_about` takes it: an index, or n's components."""
    return AXES[rotation.axis] if rotation.elementary else rotation.direction


def _accumulate(out: dict[str, Components], frame: str, comps: Components) -> None:
    """``out += Vector({frame: comps})`` on a dict of pieces, with `Vector.__add__`'s piece order.

    A zero piece is not added, and a piece that sums to zero leaves the dict (a later piece
    in that frame then goes to the end), exactly as the sum of Vectors would do.
    """
    if type(comps[0]) is _ZERO_TYPE and type(comps[1]) is _ZERO_TYPE and type(comps[2]) is _ZERO_TYPE:
        return
    old = out.get(frame)
    if old is None:
        out[frame] = comps
        return
    total = add3(old, comps)
    if type(total[0]) is _ZERO_TYPE and type(total[1]) is _ZERO_TYPE and type(total[2]) is _ZERO_TYPE:
        del out[frame]
    else:
        out[frame] = total
