"""Positions, frame bases and accelerations in R0, evaluated along a trajectory.

The kinematics gives every vector symbolically (OP, the basis of a frame, γ(G)); here each
is written in the basis of R0 (x0, y0, z0) and evaluated numerically at the samples of a
trajectory with SymEngine's ``Lambdify``, as arrays of shape (N, 3).  The tip of a body
axis, e.g. the top's z, is the unit vector

    z = sinθ sinψ x0 − sinθ cosψ y0 + cosθ z0,

whose Euler angles (ψ, θ) are recovered by `axis_angles`.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import numpy as np
import symengine as se

from ..dynamics import EquationsOfMotion
from ..errors import OutputError
from ..model import GALILEAN_FRAME, Vector
from ..numerics import Trajectory

__all__ = ["Samples", "parameter_values", "evaluate", "in_R0", "point_positions", "frame_basis",
           "default_axis", "symmetry_axis", "apex_path", "axis_angles", "constant_in"]


@dataclass(frozen=True)
class Samples:
    """The state at N times: ``t`` (N,), ``q``, ``qd``, ``qdd`` (N, n)."""

    t: np.ndarray
    q: np.ndarray
    qd: np.ndarray
    qdd: np.ndarray

    @classmethod
    def of(cls, trajectory: Trajectory) -> Samples:
        return cls(trajectory.t, trajectory.q, trajectory.qd, trajectory.qdd)

    @classmethod
    def at(cls, trajectory: Trajectory, times: np.ndarray) -> Samples:
        """The state at ``times`` by linear interpolation between the trajectory's samples."""
        t = trajectory.t

        def interp(a: np.ndarray) -> np.ndarray:
            return np.column_stack([np.interp(times, t, a[:, k]) for k in range(a.shape[1])]) \
                if a.shape[1] else np.zeros((len(times), 0))

        return cls(np.asarray(times, dtype=float), interp(trajectory.q), interp(trajectory.qd),
                   interp(trajectory.qdd))


def parameter_values(trajectory: Trajectory, eom: EquationsOfMotion) -> dict[str, float]:
    """The value of every parameter: the trajectory's, else the model's.

    Raises
    ------
    OutputError
        When a parameter the geometry needs has no value anywhere.
    """
    values: dict[str, float] = {}
    for p in eom.model.parameters:
        v = trajectory.parameters.get(p.name, p.value)
        if v is not None:
            values[p.name] = float(v)
    return values


def evaluate(eom: EquationsOfMotion, trajectory: Trajectory, exprs: Sequence[se.Basic],
             samples: Samples | None = None) -> np.ndarray:
    """The expressions of (t, q, q̇, q̈, parameters) at each sample, shape (N, len(exprs))."""
    samples = Samples.of(trajectory) if samples is None else samples
    kin = eom.kinematics
    values = parameter_values(trajectory, eom)
    names = list(values)
    args = [kin.t, *kin.q, *kin.qd, *kin.qdd, *(se.Symbol(n) for n in names)]
    free = set().union(*(e.free_symbols for e in exprs)) if exprs else set()
    missing = sorted(str(s) for s in free - set(args))
    if missing:
        raise OutputError(f"The parameter `{missing[0]}` has no value, and the figure needs it.",
                          fix=f"give `{missing[0]}` a value in the model file or with --set {missing[0]}=...")
    N = len(samples.t)
    if not exprs:
        return np.zeros((N, 0))
    f = se.Lambdify(args, list(exprs), backend="lambda", cse=True)
    X = np.column_stack([samples.t, samples.q, samples.qd, samples.qdd,
                         np.broadcast_to([values[n] for n in names], (N, len(names)))])
    return np.asarray(f(X), dtype=float).reshape(N, len(exprs))


def in_R0(eom: EquationsOfMotion, v: Vector) -> tuple[se.Basic, se.Basic, se.Basic]:
    """The components of ``v`` on (x0, y0, z0)."""
    return eom.kinematics.frames.express(v, GALILEAN_FRAME)


def _vectors(eom: EquationsOfMotion, trajectory: Trajectory, vectors: Sequence[Vector],
             samples: Samples | None) -> np.ndarray:
    exprs = [c for v in vectors for c in in_R0(eom, v)]
    return evaluate(eom, trajectory, exprs, samples).reshape(-1, len(vectors), 3)


def point_positions(trajectory: Trajectory, eom: EquationsOfMotion, names: Sequence[str],
                    samples: Samples | None = None) -> dict[str, np.ndarray]:
    """OP in R0 components for each point (a body's name is its centre G), each (N, 3)."""
    kin = eom.kinematics
    values = _vectors(eom, trajectory, [kin.position(n) for n in names], samples)
    return {n: values[:, k, :] for k, n in enumerate(names)}


def frame_basis(trajectory: Trajectory, eom: EquationsOfMotion, frame: str,
                samples: Samples | None = None) -> np.ndarray:
    """The unit vectors x, y, z of ``frame`` in R0 components, shape (N, 3, 3) (row k = axis k)."""
    return _vectors(eom, trajectory, [Vector.basis(frame, a) for a in "xyz"], samples)


def default_axis(eom: EquationsOfMotion, body: str | None = None) -> tuple[str, str]:
    """(body, axis letter) whose tip `apex_path` follows by default.

    The body: the first one with a fixed point, else the first body.  The axis: the axis of
    the body's frame that carries G from its fixed point (the top: OG = a z, so z), else its
    axis of symmetry (`symmetry_axis`: a coin's axle), else z.
    """
    bodies = eom.model.bodies
    if not bodies:
        raise OutputError(f"The model `{eom.model.name}` has no rigid body, so no body axis to follow.",
                          fix="the apex figures are for models with a rigid body")
    if body is None:
        body = next((b.name for b in bodies if b.fixed_point), bodies[0].name)
    b = eom.model.body(body) if body in {x.name for x in bodies} else None
    if b is None:
        raise OutputError(f"There is no body `{body}` in the model.",
                          fix="choose one of " + ", ".join(x.name for x in bodies))
    if b.fixed_point:
        kin = eom.kinematics
        comps = kin.frames.express(kin.position(b.name) - kin.position(b.fixed_point), b.frame)
        nonzero = [i for i, c in enumerate(comps) if not _is_zero(c)]
        if len(nonzero) == 1:
            return b.name, "xyz"[nonzero[0]]
    return b.name, symmetry_axis(eom, b.name) or "z"


def symmetry_axis(eom: EquationsOfMotion, body: str) -> str | None:
    """The axis (x, y or z) of the body's frame with the one distinct principal moment, if any.

    The inertia must be diagonal with two equal moments (A, A, C: the axis of C), and that
    axis of the inertia's frame must be the same axis of the body's frame (R2.z = R.z for
    the top, whose R turns from R2 about z).
    """
    b = eom.model.body(body)
    m = b.inertia.matrix
    if any(not _is_zero(m[i][j]) for i in range(3) for j in range(3) if i != j):
        return None
    d = [m[k][k] for k in range(3)]
    for k in range(3):
        i, j = [x for x in range(3) if x != k]
        if _is_zero(d[i] - d[j]) and not _is_zero(d[k] - d[i]):
            comps = eom.kinematics.frames.express(Vector.basis(b.inertia.frame, "xyz"[k]), b.frame)
            if all(_is_zero(c - (1 if n == k else 0)) for n, c in enumerate(comps)):
                return "xyz"[k]
    return None


def _is_zero(expr: se.Basic) -> bool:
    return se.expand(expr) == 0


def apex_path(trajectory: Trajectory, eom: EquationsOfMotion, body: str | None = None,
              axis: str | None = None, samples: Samples | None = None) -> np.ndarray:
    """The tip of a body axis (a unit vector) in R0 components along the trajectory, shape (N, 3).

    ``body`` and ``axis`` (``"x"``, ``"y"`` or ``"z"`` of the body's frame) default to
    `default_axis`: for the top, z, whose Euler angles are (ψ, θ).

    Parameters
    ----------
    trajectory : Trajectory
        A simulated motion.
    eom : EquationsOfMotion
        Its equations.
    body : str, optional
        The body (default: `default_axis`'s).
    axis : str, optional
        ``"x"``, ``"y"`` or ``"z"`` of the body's frame (default: `default_axis`'s: for the top, z,
        whose Euler angles are (ψ, θ)).
    samples : Samples, optional
        The frames' rotations along the run, when already computed.

    Returns
    -------
    ndarray of shape (N, 3)
        The tip, in R0 components.
    """
    name, default = default_axis(eom, body)
    axis = axis or default
    if axis not in ("x", "y", "z"):
        raise OutputError(f"`{axis}` is not an axis.", fix="use x, y or z (an axis of the body's frame)")
    frame = eom.model.body(name).frame
    return _vectors(eom, trajectory, [Vector.basis(frame, axis)], samples)[:, 0, :]


def axis_angles(tip: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The angles (ψ, θ) of unit vectors tip = (sinθ sinψ, −sinθ cosψ, cosθ), ψ unwrapped.

    θ ∈ [0, π] is the angle from z0; ψ is the angle of the line of nodes ``u = z0 ∧ tip / |z0 ∧ tip|``
    from x0, the precession angle of the axis.

    Parameters
    ----------
    tip : ndarray of shape (N, 3)
        Unit vectors.

    Returns
    -------
    psi : ndarray of shape (N,)
        The precession angle ψ, unwrapped.
    theta : ndarray of shape (N,)
        The angle θ from z0.
    """
    theta = np.arccos(np.clip(tip[:, 2], -1.0, 1.0))
    psi = np.unwrap(np.arctan2(tip[:, 0], -tip[:, 1]))
    return psi, theta


def constant_in(values: Mapping[str, np.ndarray], a: str, b: str, rtol: float = 1e-9) -> float | None:
    """|AB| when it is the same at every sample (to ``rtol``), else None."""
    d = np.linalg.norm(values[b] - values[a], axis=1)
    if len(d) == 0 or d.max() == 0:
        return None
    return float(d.mean()) if d.max() - d.min() <= rtol * max(d.max(), 1e-300) else None
