"""Euler angles ⇄ quaternions and angular velocity (`numerics._euler`), against finite differences and SciPy."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from lagrangian.numerics._euler import (
    euler_from_matrix,
    euler_matrix,
    matrix_from_quaternion,
    quaternion_from_matrix,
    rate_matrix,
    rate_matrix_derivative,
)

SEQUENCES = ["zxz", "zyx", "xyz", "yzy", "xzx"]


def _omega_by_differences(sequence: str, angles: np.ndarray, rates: np.ndarray, accel: np.ndarray, t: float,
                          h: float = 1e-5) -> np.ndarray:
    """ω in B's basis from Rᵀ Ṙ = [ω∧], Ṙ by central differences along θ(t) = θ + θ̇ t + ½ θ̈ t²."""
    def R(s: float) -> np.ndarray:
        return euler_matrix(sequence, angles + rates * s + 0.5 * accel * s * s)

    W = R(t).T @ (R(t + h) - R(t - h)) / (2 * h)
    return np.array([W[2, 1], W[0, 2], W[1, 0]])


@pytest.mark.parametrize("sequence", SEQUENCES)
def test_rate_matrix_and_its_derivative_match_finite_differences(sequence: str) -> None:
    rng = np.random.default_rng(7)
    for _ in range(3):
        angles, rates, accel = rng.uniform(-2, 2, 3), rng.uniform(-1, 1, 3), rng.uniform(-1, 1, 3)
        assert np.allclose(rate_matrix(sequence, angles) @ rates,
                           _omega_by_differences(sequence, angles, rates, accel, 0.0), atol=1e-9)
        h = 1e-3
        omega_dot = (_omega_by_differences(sequence, angles, rates, accel, h)
                     - _omega_by_differences(sequence, angles, rates, accel, -h)) / (2 * h)
        ours = rate_matrix(sequence, angles) @ accel + rate_matrix_derivative(sequence, angles, rates)
        assert np.allclose(ours, omega_dot, atol=1e-6)


@pytest.mark.parametrize("sequence", SEQUENCES)
def test_matrix_is_scipys_intrinsic_rotation_and_quaternions_round_trip(sequence: str) -> None:
    rng = np.random.default_rng(3)
    angles = rng.uniform(-3, 3, (5, 3))
    R = euler_matrix(sequence, angles)
    assert np.allclose(R, Rotation.from_euler(sequence.upper(), angles).as_matrix(), atol=1e-14)
    e = quaternion_from_matrix(R)
    assert np.allclose(np.linalg.norm(e, axis=1), 1.0, atol=1e-15) and np.all(e[:, 0] >= 0)
    assert np.allclose(matrix_from_quaternion(e), R, atol=1e-14)
    assert np.allclose(matrix_from_quaternion(2.5 * e), R, atol=1e-14)  # R of e/|e|: the norm does not matter


@pytest.mark.parametrize(("sequence", "middle"), [("zxz", (0.3, 0.5)), ("zxz", (-0.3, -0.5)), ("zyx", (1.2, -0.4)),
                                                 ("zyx", (2.0, 0.3))])
def test_angles_follow_a_motion_on_its_branch_and_turns(sequence: str, middle: tuple[float, float]) -> None:
    # A motion whose angles leave (−π, π] and whose middle angle is on either branch (θ < 0 for z-x-z;
    # pitch beyond π/2 for z-y-x): SciPy's angles jump by 2π or to the other branch; ours follow the motion,
    # the turns of the fast angle too on sparse outputs, from the angular velocity.
    t = np.linspace(0, 2.4, 400)
    angles = np.column_stack([-2.5 - 1.5 * t, middle[0] + middle[1] * t, 3.0 + 2.0 * t])
    R = euler_matrix(sequence, angles)
    assert np.allclose(euler_from_matrix(sequence, R, angles[0]), angles, atol=1e-9)
    sparse = slice(None, None, 57)  # 0.34 s apart: the third angle turns by 0.7 rad between samples, ψ by 0.5
    fast = angles * [1, 1, 6.0]
    rates = np.tile([-1.5, middle[1], 12.0], (len(t), 1))
    omega = np.einsum("nij,nj->ni", rate_matrix(sequence, fast), rates)
    back = euler_from_matrix(sequence, euler_matrix(sequence, fast)[sparse], fast[0], omega[sparse], t[sparse])
    assert np.allclose(back, fast[sparse], atol=1e-9)


def test_rate_matrix_is_singular_where_the_angles_are() -> None:
    assert abs(np.linalg.det(rate_matrix("zxz", np.array([0.3, 0.0, -1.0])))) < 1e-15
    assert abs(np.linalg.det(rate_matrix("zyx", np.array([0.3, np.pi / 2, -1.0])))) < 1e-15
    assert abs(abs(np.linalg.det(rate_matrix("zxz", np.array([0.3, 0.4, -1.0])))) - np.sin(0.4)) < 1e-15
