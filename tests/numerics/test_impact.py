"""The contact problems of impacts and persistent contact (`numerics._impact`), against hand derivations.

* Two exact solvers of the linear complementarity problem w = W z + q ≥ 0, z ≥ 0, zᵀw = 0 — the
  enumeration of the modes and Lemke's pivoting — agree on random positive semi-definite problems,
  and each answer is checked by the three conditions themselves.
* A point mass m hitting a plane with velocity (v_t, v_n), v_n < 0, Newton's e and Coulomb's μ
  (any mechanics text, e.g. Brogliato, *Nonsmooth Mechanics*, §4.2): P_n = −m (1 + e) v_n; it
  sticks (v_t⁺ = 0, P_t = −m v_t) when |v_t| ≤ μ (1 + e)|v_n|, else slides with
  v_t⁺ = v_t − sign(v_t) μ (1 + e)|v_n|.
* The simultaneous impact of a chain of equal balls (Newton's cradle): W = (1/m) tridiag(−1, 2, −1),
  and for the first ball arriving at v every contact closes, W P = (1 + e) v e₁.
* Without friction, when the contacts approach, the energy never increases:
  T⁺ − T⁻ = −½ Σ_k (1 − e_k) P_k |ġ_k⁻| (random masses, rows and e ∈ [0, 1]).
"""

from __future__ import annotations

import numpy as np
import pytest

from lagrangian.numerics._impact import CLOSED, OPEN, SLIDE_NEG, SLIDE_POS, delassus, enumerate_modes, lemke, solve_lcp


def _check_lcp(W: np.ndarray, q: np.ndarray, z: np.ndarray, tol: float = 1e-9) -> None:
    w = W @ z + q
    scale = max(1.0, float(np.abs(q).max()))
    assert np.all(z >= -tol * scale) and np.all(w >= -tol * scale)
    assert abs(float(z @ w)) <= tol * scale * max(1.0, float(np.abs(z).max()))


@pytest.mark.parametrize("seed", range(8))
def test_enumeration_and_lemke_solve_the_same_positive_semidefinite_problems(seed: int) -> None:
    rng = np.random.default_rng(seed)
    m = int(rng.integers(1, 7))
    B = rng.normal(size=(m, m + 2))
    W = B @ B.T  # positive definite: the solution is unique
    q = rng.normal(size=m)
    z1, _ = enumerate_modes(W, q)
    z2 = lemke(W, q)
    assert z2 is not None
    _check_lcp(W, q, z1)
    _check_lcp(W, q, z2)
    assert np.allclose(z1, z2, atol=1e-9 * max(1.0, np.abs(q).max()))


def test_lemke_takes_over_beyond_the_enumeration() -> None:
    rng = np.random.default_rng(3)
    B = rng.normal(size=(14, 16))
    W, q = B @ B.T, rng.normal(size=14)  # 2^14 combinations: more than MAX_COMBINATIONS
    z, modes = solve_lcp(W, q)
    _check_lcp(W, q, z)
    assert all((m == CLOSED) == (z[i] > 0) or abs(z[i]) < 1e-12 for i, m in enumerate(modes))


def test_a_body_wedged_between_two_surfaces_has_no_solution() -> None:
    # x ≥ 0 and −x ≥ 0 at x = 0, moving at v = 1 with e = 0.5: ẋ⁺ ≥ 0 and −ẋ⁺ ≥ e·1 contradict.
    m, v, e = 1.0, 1.0, 0.5
    J = np.array([[1.0], [-1.0]])
    W, _ = delassus(np.array([[m]]), J)
    s = J @ [v]
    q = s - (-e * np.minimum(s, 0))
    assert enumerate_modes(W, q) is None
    assert lemke(W, q) is None
    assert enumerate_modes(W, J @ [v]) is not None  # plastic (e = 0): the body stops


@pytest.mark.parametrize(("vt", "stick"), [(0.5, True), (-0.5, True), (3.0, False), (-3.0, False)])
def test_a_point_hitting_a_plane_with_friction_sticks_or_slides_as_coulomb_says(vt: float, stick: bool) -> None:
    m, e, mu, vn = 2.0, 0.5, 0.4, -2.0  # μ (1 + e)|v_n| = 1.2
    M = m * np.eye(2)  # coordinates (x tangential, z normal)
    J = np.array([[0.0, 1.0], [1.0, 0.0]])  # rows: the normal gap's rate ż, the sliding velocity ẋ
    W, X = delassus(M, J)
    qd = np.array([vt, vn])
    q = J @ qd - np.array([-e * vn, 0.0])
    z, modes = solve_lcp(W, q, mu=np.array([mu]), tangent=[1])
    after = qd + X @ z
    assert z[0] == pytest.approx(-m * (1 + e) * vn, rel=1e-12)
    assert after[1] == pytest.approx(-e * vn, rel=1e-12)
    if stick:
        assert modes == (CLOSED,) and abs(after[0]) < 1e-12 and z[1] == pytest.approx(-m * vt, rel=1e-12)
    else:
        assert modes == ((SLIDE_POS,) if vt > 0 else (SLIDE_NEG,))
        assert after[0] == pytest.approx(vt - np.sign(vt) * mu * (1 + e) * abs(vn), rel=1e-12)
        assert abs(z[1]) == pytest.approx(mu * z[0], rel=1e-12)


@pytest.mark.parametrize("balls", [3, 4, 5])
@pytest.mark.parametrize("e", [1.0, 0.5, 0.0])
def test_the_simultaneous_impact_of_a_chain_of_balls(balls: int, e: float) -> None:
    m, v = 0.3, 1.7
    M = m * np.eye(balls)
    J = np.zeros((balls - 1, balls))
    for k in range(balls - 1):  # gap k: x_{k+1} − x_k − d
        J[k, k], J[k, k + 1] = -1.0, 1.0
    W, X = delassus(M, J)
    assert np.allclose(W, (2 * np.eye(balls - 1) - np.eye(balls - 1, k=1) - np.eye(balls - 1, k=-1)) / m)
    qd = np.zeros(balls)
    qd[0] = v
    s = J @ qd
    z, modes = solve_lcp(W, s + e * np.minimum(s, 0))
    # Every contact closes: W P = (1 + e) v e₁, so P_k = (1 + e) m v (B − k)/B, k = 1 … B − 1.
    k = np.arange(1, balls)
    assert np.allclose(z, (1 + e) * m * v * (balls - k) / balls, rtol=1e-12) and set(modes) == {CLOSED}
    after = qd + X @ z
    assert after[0] == pytest.approx(v * (1 - (balls - 1) * (1 + e) / balls), abs=1e-12)
    assert np.allclose(after[1:], (1 + e) * v / balls, rtol=1e-12)
    assert m * after.sum() == pytest.approx(m * v, rel=1e-12)  # momentum
    lost = 0.5 * m * v**2 - 0.5 * m * after @ after
    assert lost == pytest.approx(0.5 * (1 - e) * z[0] * v, abs=1e-12)  # ½ Σ (1 − e) P_k |ġ_k⁻|: only ġ₁⁻ = −v


@pytest.mark.parametrize("seed", range(6))
def test_frictionless_impacts_never_add_energy(seed: int) -> None:
    rng = np.random.default_rng(100 + seed)
    n, m = 4, 3
    B = rng.normal(size=(n, n))
    M = B @ B.T + n * np.eye(n)
    J = rng.normal(size=(m, n))
    e = rng.uniform(0, 1, m)
    qd = rng.normal(size=n)
    J *= -np.sign(J @ qd)[:, None]  # every contact approaching: ġ_k⁻ < 0
    W, X = delassus(M, J)
    s = J @ qd
    z, _ = solve_lcp(W, s + e * np.minimum(s, 0))
    after = qd + X @ z
    T0, T1 = 0.5 * qd @ M @ qd, 0.5 * after @ M @ after
    # The identity T⁺ − T⁻ = ½ (q̇⁺ + q̇⁻)ᵀ M (q̇⁺ − q̇⁻) = ½ Σ_k P_k (ġ_k⁺ + ġ_k⁻) = −½ Σ_k (1 − e_k) P_k |ġ_k⁻|.
    assert T1 - T0 == pytest.approx(0.5 * z @ (J @ after + s), abs=1e-10 * T0)
    assert T1 - T0 == pytest.approx(-0.5 * np.sum((1 - e) * z * np.abs(s)), abs=1e-10 * T0)
    assert T1 <= T0 * (1 + 1e-12)


def test_a_bilateral_row_stays_satisfied_through_the_impact() -> None:
    # A pendulum in Cartesian coordinates (rod x² + y² = l², row A_b = (x, y)) hits a wall x ≥ 0.
    m, l, e = 1.0, 1.0, 0.7
    x, y = 0.0, -l
    A_b = np.array([[x, y]])
    J = np.array([[1.0, 0.0]])
    W, X = delassus(m * np.eye(2), J, A_b)
    qd = np.array([-2.0, 0.0])  # towards the wall, tangent to the circle
    s = J @ qd
    z, _ = solve_lcp(W, s + e * np.minimum(s, 0))
    after = qd + X @ z
    assert after[0] == pytest.approx(2.0 * e, rel=1e-12) and abs(A_b @ after)[0] < 1e-14


def test_modes_can_be_restricted_and_ordered() -> None:
    # One contact, q ≥ 0 (nothing pushes it closed): open and closed (z = 0) are both solutions; the order picks.
    W, q = np.array([[1.0]]), np.array([0.0])
    assert enumerate_modes(W, q, order=lambda modes: -modes[0])[1] == (CLOSED,)
    assert enumerate_modes(W, q, order=lambda modes: modes[0])[1] == (OPEN,)
    assert enumerate_modes(W, np.array([-1.0]), allowed=[(OPEN,)]) is None
