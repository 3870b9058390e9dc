"""Orientations and positions in R0 at many states, composed numerically frame by frame.

A frame F obtained from its parent P by the rotation α about P's axis k (or a constant
unit vector n) has its basis, as columns of R0 components, C_F = C_P · R_k(α), with R_k
the elementary rotation matrix (Rodrigues' R = cos α I + sin α [n]× + (1 − cos α) n nᵀ for
n), the same convention as the kinematics' change of basis (`lagrangian.kinematics._frames`).
A point's OP, written on the bases of several frames, is Σ_F C_F · (its components on F).
Only the rotation angles and those components are evaluated symbolically (SymEngine's
``Lambdify`` over t, q, q̇ and the parameters), so a chain of 30 frames costs 30 small
matrix products per state rather than expressions that grow with the chain.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np
import symengine as se

from ..errors import OutputError
from ..model import GALILEAN_FRAME, TIME, Model, Vector

__all__ = ["Evaluator", "quaternions", "rotation_matrices"]


def rotation_matrices(axis: int | np.ndarray, angle: np.ndarray) -> np.ndarray:
    """R(α) for each angle, shape (N, 3, 3): about basis axis ``axis`` or the unit vector ``axis`` (3,)."""
    c, s = np.cos(angle), np.sin(angle)
    out = np.zeros((len(angle), 3, 3))
    if isinstance(axis, (int, np.integer)):
        i, j = (axis + 1) % 3, (axis + 2) % 3
        out[:, axis, axis] = 1.0
        out[:, i, i] = c
        out[:, j, j] = c
        out[:, j, i] = s
        out[:, i, j] = -s
        return out
    n = np.asarray(axis, dtype=float)
    cross = np.array([[0, -n[2], n[1]], [n[2], 0, -n[0]], [-n[1], n[0], 0]])
    return (c[:, None, None] * np.eye(3) + s[:, None, None] * cross
            + (1 - c)[:, None, None] * np.outer(n, n))


def quaternions(matrices: np.ndarray) -> np.ndarray:
    """Unit quaternions (x, y, z, w) of rotation matrices (N, 3, 3), w ≥ 0 and continuous along N.

    Shepperd's method (J. Guidance Control 1, 1978): from the largest of w², x², y², z², so no
    division by a small number; consecutive quaternions are kept on the same side (q and −q are
    the same rotation) so that the browser's slerp between samples takes the short way.
    """
    m = matrices
    tr = m[:, 0, 0] + m[:, 1, 1] + m[:, 2, 2]
    candidates = np.stack([tr, m[:, 0, 0], m[:, 1, 1], m[:, 2, 2]], axis=1)
    k = np.argmax(candidates, axis=1)
    q = np.empty((len(m), 4))
    for case in range(4):
        sel = k == case
        if not np.any(sel):
            continue
        a = m[sel]
        if case == 0:
            r = np.sqrt(1 + tr[sel])
            w, x = r / 2, (a[:, 2, 1] - a[:, 1, 2]) / (2 * r)
            y, z = (a[:, 0, 2] - a[:, 2, 0]) / (2 * r), (a[:, 1, 0] - a[:, 0, 1]) / (2 * r)
        elif case == 1:
            r = np.sqrt(1 + a[:, 0, 0] - a[:, 1, 1] - a[:, 2, 2])
            x, w = r / 2, (a[:, 2, 1] - a[:, 1, 2]) / (2 * r)
            y, z = (a[:, 0, 1] + a[:, 1, 0]) / (2 * r), (a[:, 0, 2] + a[:, 2, 0]) / (2 * r)
        elif case == 2:
            r = np.sqrt(1 - a[:, 0, 0] + a[:, 1, 1] - a[:, 2, 2])
            y, w = r / 2, (a[:, 0, 2] - a[:, 2, 0]) / (2 * r)
            x, z = (a[:, 0, 1] + a[:, 1, 0]) / (2 * r), (a[:, 1, 2] + a[:, 2, 1]) / (2 * r)
        else:
            r = np.sqrt(1 - a[:, 0, 0] - a[:, 1, 1] + a[:, 2, 2])
            z, w = r / 2, (a[:, 1, 0] - a[:, 0, 1]) / (2 * r)
            x, y = (a[:, 0, 2] + a[:, 2, 0]) / (2 * r), (a[:, 1, 2] + a[:, 2, 1]) / (2 * r)
        q[sel] = np.stack([x, y, z, w], axis=1)
    q /= np.linalg.norm(q, axis=1, keepdims=True)
    for i in range(1, len(q)):  # the same hemisphere as the previous sample
        if q[i] @ q[i - 1] < 0:
            q[i] = -q[i]
    return q


class Evaluator:
    """The numbers of a model at states (t, q, q̇): frame bases, point positions, vectors in R0.

    ``values`` gives every parameter a number; a symbol with none is an `OutputError` that
    says which, and how to give it.
    """

    def __init__(self, model: Model, values: Mapping[str, float]) -> None:
        self.model = model
        self.values = dict(values)
        self.frames = {f.name: f for f in model.frames}
        q = [c.symbol for c in model.coordinates]
        qd = [c.rate_symbol for c in model.coordinates]
        self.parameters = [p.name for p in model.parameters if p.name in self.values]
        self.arguments = [TIME, *q, *qd, *(se.Symbol(n) for n in self.parameters)]
        self._known = set(self.arguments)
        self._tree: Any = None  # the FrameTree, made on first use (imported then: the kinematics is heavy)

    def _lambdify(self, exprs: Sequence[se.Basic]):
        free = set().union(*(e.free_symbols for e in exprs)) if exprs else set()
        missing = sorted(str(s) for s in free - self._known)
        if missing:
            name = missing[0]
            raise OutputError(f"The parameter `{name}` has no value, and the view needs it.",
                              fix=f"give `{name}` a value in the model file or with --set {name}=...")
        return se.Lambdify(self.arguments, list(exprs), backend="lambda", cse=True) if exprs else None

    def columns(self, t: np.ndarray, q: np.ndarray, qd: np.ndarray, exprs: Sequence[se.Basic]) -> np.ndarray:
        """Each expression at each state, shape (N, len(exprs))."""
        n = len(t)
        if not exprs:
            return np.zeros((n, 0))
        f = self._lambdify(exprs)
        x = np.column_stack([t, q, qd, np.broadcast_to([self.values[p] for p in self.parameters],
                                                       (n, len(self.parameters)))])
        return np.asarray(f(x), dtype=float).reshape(n, len(exprs))

    def bases(self, frames: Sequence[str], t: np.ndarray, q: np.ndarray, qd: np.ndarray) -> dict[str, np.ndarray]:
        """C_F for ``frames`` and their ancestors, (N, 3, 3), whose columns are F's axes in R0 components."""
        needed: list[str] = []
        for name in frames:
            chain = []
            while name is not None and name not in needed and name not in chain:
                chain.append(name)
                name = self.frames[name].parent  # type: ignore[assignment]
            needed.extend(reversed(chain))
        rotated = [f for f in needed if self.frames[f].rotation is not None]
        exprs: list[se.Basic] = []
        for f in rotated:
            rot = self.frames[f].rotation
            exprs.append(rot.angle)  # type: ignore[union-attr]
            if not rot.elementary:  # type: ignore[union-attr]
                exprs.extend(rot.direction)  # type: ignore[union-attr,arg-type]
        values = self.columns(t, q, qd, exprs)
        out: dict[str, np.ndarray] = {GALILEAN_FRAME: np.broadcast_to(np.eye(3), (len(t), 3, 3))}
        k = 0
        for f in needed:
            frame = self.frames[f]
            if frame.rotation is None:
                out[f] = np.broadcast_to(np.eye(3), (len(t), 3, 3))
                continue
            angle = values[:, k]
            k += 1
            if frame.rotation.elementary:
                turn = rotation_matrices("xyz".index(frame.rotation.axis), angle)
            else:
                n = values[0, k:k + 3]
                k += 3
                turn = rotation_matrices(n / np.linalg.norm(n), angle)
            out[f] = np.einsum("nij,njk->nik", out[frame.parent], turn)  # type: ignore[index]
        return out

    def vectors(self, vectors: Sequence[Vector], t: np.ndarray, q: np.ndarray, qd: np.ndarray) -> np.ndarray:
        """Each vector's R0 components at each state, shape (N, len(vectors), 3)."""
        pieces = [(k, frame, comps) for k, v in enumerate(vectors) for frame, comps in v]
        bases = self.bases(sorted({frame for _, frame, _ in pieces}), t, q, qd)
        values = self.columns(t, q, qd, [c for _, _, comps in pieces for c in comps])
        out = np.zeros((len(t), len(vectors), 3))
        for j, (k, frame, _) in enumerate(pieces):
            out[:, k, :] += np.einsum("nij,nj->ni", bases[frame], values[:, 3 * j:3 * j + 3])
        return out

    def constant_in(self, v: Vector, frame: str) -> tuple[float, float, float] | None:
        """The components of ``v`` on ``frame`` when they are constants (their numbers), else None.

        Constant means free of t, q and q̇ as a function (∂/∂x ≡ 0 by the randomized identity test,
        so cos² + sin² forms count as constant), e.g. GA for the hinge A of a rod, in the rod's frame.
        """
        from .._identity import are_zero
        from ..kinematics import FrameTree, TimeDerivative

        if self._tree is None:
            self._tree = FrameTree(self.model, TimeDerivative.of((), (), (), TIME))
        comps = self._tree.express(v, frame)
        moving = {TIME} | {c.symbol for c in self.model.coordinates} | {c.rate_symbol for c in self.model.coordinates}
        used = set().union(*(c.free_symbols for c in comps)) & moving
        if used and not all(are_zero([se.diff(c, x) for c in comps for x in used])):
            return None
        subs = {se.Symbol(n): self.values[n] for n in self.parameters} | {x: 0.3 for x in used}
        try:
            out = tuple(float(c.subs(subs)) for c in comps)
        except (TypeError, RuntimeError, ValueError):
            return None
        return out if all(np.isfinite(out)) else None  # type: ignore[return-value]
