"""Euler angles ⇄ unit quaternions and angular velocity, numerically, for any sequence of three axes.

A free body's frame B comes from R0 by three elementary rotations, each about an axis of the
previous frame (`lagrangian.model._free.FreeJoint.sequence`, ``"zxz"`` for the course's ψ, θ, φ):

    R = R_{a1}(θ1) R_{a2}(θ2) R_{a3}(θ3),       R_a(α) the rotation of α about axis a,

R taking B's components to R0's.  Its angular velocity in B's basis is

    ω = J(θ) θ̇,   J = [R3ᵀ R2ᵀ e_{a1},  R3ᵀ e_{a2},  e_{a3}],

and det J = ±sin θ2 (first and last axes alike: proper Euler angles) or ±cos θ2 (three
different axes: Cardan angles), zero at the singular configurations where θ1 and θ3 turn about
the same line.  Differentiating the columns (dR_aᵀ/dα = −[e_a∧] R_aᵀ),

    J̇ θ̇ = θ̇1 (−θ̇2 R3ᵀ (e_{a2} ∧ R2ᵀ e_{a1}) − θ̇3 e_{a3} ∧ c1) − θ̇2 θ̇3 e_{a3} ∧ c2,

with c1, c2 the first two columns, so θ̈ = J⁻¹(ω̇ − J̇ θ̇) where J is regular.

The angles of a rotation matrix are those of SciPy's `Rotation.as_euler` (intrinsic, Bernardes
& Viollet 2022), or the second solution, (θ1 + π, −θ2, θ3 + π) for proper angles and
(θ1 + π, π − θ2, θ3 + π) for Cardan angles: along a motion, the one on the branch of the initial
angles (sin θ2, or cos θ2, keeps its sign unless the motion goes exactly through the
singularity), each angle on the turn (2πk) nearest to its value predicted from the previous
sample and its rate, so that a motion's angles are continuous and count their turns.

Quaternions are (w, x, y, z), Hamilton's convention: R v = e ⊗ (0, v) ⊗ e*.
"""

from __future__ import annotations

import warnings

import numpy as np

__all__ = [
    "SINGULAR",
    "elementary",
    "euler_from_matrix",
    "euler_matrix",
    "matrix_from_quaternion",
    "quaternion_from_matrix",
    "rate_matrix",
    "rate_matrix_derivative",
]

#: Where |det J| (|sin θ2| or |cos θ2|) is below this, the angles' rates are not defined (NaN).
SINGULAR = 1e-9

_AXIS = {"x": 0, "y": 1, "z": 2}


def elementary(axis: str, angle: np.ndarray) -> np.ndarray:
    """R_a(α) for each angle: shape (N, 3, 3), the rotation of α about basis axis ``axis``."""
    angle = np.asarray(angle, dtype=float)
    a = _AXIS[axis]
    i, j = (a + 1) % 3, (a + 2) % 3
    out = np.zeros((*angle.shape, 3, 3))
    c, s = np.cos(angle), np.sin(angle)
    out[..., a, a] = 1.0
    out[..., i, i] = c
    out[..., j, j] = c
    out[..., j, i] = s
    out[..., i, j] = -s
    return out


def euler_matrix(sequence: str, angles: np.ndarray) -> np.ndarray:
    """R = R_{a1}(θ1) R_{a2}(θ2) R_{a3}(θ3) for angles of shape (N, 3): shape (N, 3, 3)."""
    angles = np.asarray(angles, dtype=float)
    out = elementary(sequence[0], angles[..., 0])
    for k in (1, 2):
        out = out @ elementary(sequence[k], angles[..., k])
    return out


def matrix_from_quaternion(e: np.ndarray) -> np.ndarray:
    """R of the quaternions e (N, 4), each divided by its norm first."""
    e = np.asarray(e, dtype=float)
    e = e / np.linalg.norm(e, axis=-1, keepdims=True)
    w, x, y, z = e[..., 0], e[..., 1], e[..., 2], e[..., 3]
    out = np.empty((*e.shape[:-1], 3, 3))
    out[..., 0, 0] = 1 - 2 * (y * y + z * z)
    out[..., 0, 1] = 2 * (x * y - w * z)
    out[..., 0, 2] = 2 * (x * z + w * y)
    out[..., 1, 0] = 2 * (x * y + w * z)
    out[..., 1, 1] = 1 - 2 * (x * x + z * z)
    out[..., 1, 2] = 2 * (y * z - w * x)
    out[..., 2, 0] = 2 * (x * z - w * y)
    out[..., 2, 1] = 2 * (y * z + w * x)
    out[..., 2, 2] = 1 - 2 * (x * x + y * y)
    return out


def quaternion_from_matrix(R: np.ndarray) -> np.ndarray:
    """The unit quaternion (w, x, y, z), w ≥ 0, of each rotation matrix (N, 3, 3)."""
    from scipy.spatial.transform import Rotation

    xyzw = Rotation.from_matrix(np.asarray(R, dtype=float).reshape(-1, 3, 3)).as_quat()
    out = np.concatenate([xyzw[:, 3:], xyzw[:, :3]], axis=1)
    out[out[:, 0] < 0] *= -1
    return out.reshape(*np.shape(R)[:-2], 4)


def _alternative(sequence: str, angles: np.ndarray) -> np.ndarray:
    other = angles + np.array([np.pi, 0.0, np.pi])
    other[..., 1] = -angles[..., 1] if sequence[0] == sequence[2] else np.pi - angles[..., 1]
    return other


def _nearest_turn(angles: np.ndarray, previous: np.ndarray) -> np.ndarray:
    return angles + 2 * np.pi * np.round((previous - angles) / (2 * np.pi))


def euler_from_matrix(sequence: str, R: np.ndarray, start: np.ndarray, omega: np.ndarray | None = None,
                      t: np.ndarray | None = None) -> np.ndarray:
    """The angles (N, 3) of rotations R (N, 3, 3) along a motion, from ``start`` (3,): see the module docstring.

    The branch is that of ``start`` throughout: sin θ2 (proper angles) or cos θ2 (Cardan angles)
    keeps its sign along a motion that does not go exactly through the singularity, where it
    vanishes.  Each angle takes the turn (2πk) nearest to its value predicted from the previous
    sample, θ + (t_k − t_{k−1}) θ̇ with θ̇ = J⁻¹ ω when ``omega`` (N, 3) and ``t`` are given (else the
    previous value itself): so the outputs must be dense enough for that prediction to be within π.
    """
    from scipy.spatial.transform import Rotation

    with warnings.catch_warnings():  # at a singular configuration SciPy says so; the rates are NaN there anyway
        warnings.simplefilter("ignore", UserWarning)
        raw = Rotation.from_matrix(np.asarray(R, dtype=float).reshape(-1, 3, 3)).as_euler(sequence.upper())
    candidates = (raw, _alternative(sequence, raw))
    proper = sequence[0] == sequence[2]

    def side(angles: np.ndarray) -> float:
        return float(np.sign(np.sin(angles[1]) if proper else np.cos(angles[1])))

    out = np.empty_like(raw)
    previous = np.asarray(start, dtype=float)
    branch = side(previous)
    predicted = previous
    for k in range(len(raw)):
        chosen = [c[k] for c in candidates if branch == 0 or side(c[k]) == branch]
        if len(chosen) != 1:  # exactly singular (or the start is): the candidate nearest the prediction
            chosen = sorted((c[k] for c in candidates),
                            key=lambda c: float(np.sum(np.abs(_nearest_turn(c, predicted) - predicted))))
        out[k] = previous = _nearest_turn(chosen[0], predicted)
        if branch == 0:
            branch = side(previous)
        predicted = previous
        if omega is not None and t is not None and k + 1 < len(raw):
            J = rate_matrix(sequence, previous)
            if abs(np.linalg.det(J)) >= SINGULAR:
                predicted = previous + (t[k + 1] - t[k]) * np.linalg.solve(J, omega[k])
    return out


def _columns(sequence: str, angles: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """(c1, c2, c3, R2ᵀ e_{a1}), each (N, 3): J's columns in B's basis."""
    e = np.eye(3)
    e1, e2, e3 = (e[_AXIS[a]] for a in sequence)
    R2t = np.swapaxes(elementary(sequence[1], angles[..., 1]), -1, -2)
    R3t = np.swapaxes(elementary(sequence[2], angles[..., 2]), -1, -2)
    r2e1 = R2t @ e1
    c1 = np.einsum("...ij,...j->...i", R3t, r2e1)
    c2 = R3t @ e2
    c3 = np.broadcast_to(e3, c1.shape)
    return c1, c2, c3, r2e1


def rate_matrix(sequence: str, angles: np.ndarray) -> np.ndarray:
    """J (N, 3, 3) with ω = J θ̇ (ω in B's basis)."""
    c1, c2, c3, _ = _columns(sequence, np.asarray(angles, dtype=float))
    return np.stack([c1, c2, c3], axis=-1)


def rate_matrix_derivative(sequence: str, angles: np.ndarray, rates: np.ndarray) -> np.ndarray:
    """J̇ θ̇ (N, 3) (module docstring)."""
    angles, rates = np.asarray(angles, dtype=float), np.asarray(rates, dtype=float)
    c1, c2, _, r2e1 = _columns(sequence, angles)
    e = np.eye(3)
    e2, e3 = e[_AXIS[sequence[1]]], e[_AXIS[sequence[2]]]
    R3t = np.swapaxes(elementary(sequence[2], angles[..., 2]), -1, -2)
    d1, d2, d3 = rates[..., 0:1], rates[..., 1:2], rates[..., 2:3]
    dc1 = -d2 * np.einsum("...ij,...j->...i", R3t, np.cross(e2, r2e1)) - d3 * np.cross(e3, c1)
    dc2 = -d3 * np.cross(e3, c2)
    return d1 * dc1 + d2 * dc2
