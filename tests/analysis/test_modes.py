"""Modes and verdicts of linearized motions with an ignorable coordinate or a defective eigenvalue 0,
against SciPy's generalized eigenproblem on hand-written M, K, closed forms and the ranks of A's powers."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
import scipy.linalg
from lagrangian_test_support import EXAMPLES_DIR
from more_systems import TWO_CARTS as TWO_CARTS_FREE
from more_systems import eom as system_eom

import lagrangian
from lagrangian import linearize
from lagrangian.cli.main import main


def _finite_roots(K: np.ndarray, M: np.ndarray) -> np.ndarray:
    """ω > 0 with det(K − ω² M) = 0, by SciPy's QZ on the pencil (no symmetric shortcut)."""
    w2 = scipy.linalg.eig(K, M, right=False)
    w2 = w2[np.isfinite(w2)].real
    return np.sort(np.sqrt(w2[w2 > 1e-9 * max(1.0, np.abs(w2).max())]))


def _cart() -> lagrangian.EquationsOfMotion:
    return lagrangian.derive(lagrangian.load_model(EXAMPLES_DIR / "inverted_pendulum_cart.toml"))


# -- pulsations with an ignorable coordinate ---------------------------------------------------

def test_the_hanging_cart_pendulum_oscillates_at_the_root_of_det_K_minus_w2_M_not_with_the_cart_held():
    mc, m, l, g = 1.0, 0.2, 0.6, 9.81
    # Hand derivation: T = ½ (mc + m) ẋ² + m l ẋ θ̇ cos θ + ½ m l² θ̇², U = m g l cos θ; at θ = π
    M = np.array([[mc + m, -m * l], [-m * l, m * l**2]])
    K = np.array([[0.0, 0.0], [0.0, m * g * l]])
    expected = _finite_roots(K, M)
    assert expected == pytest.approx([math.sqrt((mc + m) * g / (mc * l))], rel=1e-12)  # 4.4294, not √(g/l)
    lin = linearize(_cart(), {"x": 0, "theta": "pi"})
    modes = lin.modes()
    assert modes.pulsations == pytest.approx(expected, rel=1e-10)
    assert sorted(abs(z.imag) for z in lin.stability().eigenvalues) == pytest.approx([expected[0]] * 2, rel=1e-10)
    phi = modes.shapes[0]
    assert phi["x"] / phi["theta"] == pytest.approx(m * l / (mc + m), rel=1e-10)  # the cart swings back: p_x = 0


def test_the_furuta_pendulum_hanging_has_the_pulsation_of_the_reduced_system():
    J, m, r, l, g = 0.02, 0.1, 0.3, 0.25, 9.81
    M = np.array([[J + m * r**2, m * r * l], [m * r * l, m * l**2]])
    K = np.diag([0.0, m * g * l])
    lin = linearize(system_eom("furuta"), {"phi": 0, "theta": 0})
    np.testing.assert_allclose(np.array(lin.second_order.M.tolist(), dtype=float), M, rtol=1e-12)
    w = lin.modes().pulsations
    assert w == pytest.approx(_finite_roots(K, M), rel=1e-10)
    assert w[0] == pytest.approx(math.sqrt(g / l * (J + m * r**2) / J), rel=1e-12)
    assert w[0] == pytest.approx(float(np.abs(lin.eigenvalues().imag).max()), rel=1e-10)


@pytest.mark.slow
def test_the_pulsations_agree_with_the_eigenvalues_in_the_text_the_json_and_the_report(capsys):
    path = str(EXAMPLES_DIR / "inverted_pendulum_cart.toml")
    good, wrong = "4.42944692", "4.04351332"  # √((mc + m) g/(mc l)) and √(g/l), the cart held
    assert main(["linearize", path, "--at", "x=0", "--at", "theta=pi"]) == 0
    text = capsys.readouterr().out
    pulsation_line = next(line for line in text.splitlines() if line.startswith("Pulsations"))
    assert good in pulsation_line and wrong not in text
    assert main(["modes", path, "--at", "x=0", "--at", "theta=pi", "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert doc["modes"]["pulsations"] == pytest.approx([4.429446918], rel=1e-9)
    section = lagrangian.report(_cart(), lang="en", small_motions={"x": 0, "theta": "pi"}).markdown()
    assert "4.42945" in section and "4.04351" not in section


# -- a defective eigenvalue 0 -------------------------------------------------------------------

def _jordan_sizes(A: np.ndarray) -> list[int]:
    """Sizes of the Jordan blocks of 0 from the ranks of A, A², ... (the matrix is exact here)."""
    n = A.shape[0]
    ranks = [n] + [np.linalg.matrix_rank(np.linalg.matrix_power(A, k)) for k in range(1, n + 1)]
    at_least = [ranks[k - 1] - ranks[k] for k in range(1, n + 1)]
    return sorted((k for k in range(1, n + 1) for _ in range(at_least[k - 1] - (at_least[k] if k < n else 0))),
                  reverse=True)


def test_a_shift_of_the_tilt_drives_the_position_secular_growth_not_neutral():
    m, k = 1.0, 2.0
    lin = linearize(system_eom("thrust"), {"x": 0, "theta": 0})
    A = lin.numeric()[0]
    # Hand derivation: m δẍ = k δθ, J δθ̈ = 0, state (x, θ, ẋ, θ̇).
    np.testing.assert_array_equal(A, [[0, 0, 1, 0], [0, 0, 0, 1], [0, k / m, 0, 0], [0, 0, 0, 0]])
    assert np.any(A @ A)  # A² ≠ 0: not a set of neutral directions
    assert _jordan_sizes(A) == [4]  # x grows like t³ after a change of θ̇
    st = lin.stability()
    assert st.stable is False and st.verdict == "unstable (secular growth)"
    assert "theta_dot" in st.reason and "t^3" in st.reason
    modes = lin.modes()
    assert modes.zero.secular and modes.zero.blocks == (3,)  # x set aside: θ̇ → θ → ẋ
    assert not any("a shift of it is another steady motion" in why for name, why in modes.neutral if name != "x")


def test_a_drift_of_the_ignorable_cart_and_of_two_carts_together_stays_neutral():
    hanging = linearize(_cart(), {"x": 0, "theta": "pi"})
    assert _jordan_sizes(hanging.numeric()[0]) == [2]  # ẋ → x: the cart drifts, a shift of x is a rest
    assert hanging.stability().verdict == "stable"
    carts = linearize(system_eom("two_carts"), {"x1": 0, "x2": 0})
    A = carts.numeric()[0]
    assert _jordan_sizes(A) == [2]  # a change of the common momentum: both drift together, a shift is a rest
    st = carts.stability()
    assert st.verdict != "unstable (secular growth)" and not carts.modes().zero.secular
    assert carts.modes().pulsations == pytest.approx([math.sqrt(2 * 4.0 / 1.0)], rel=1e-12)


def test_a_point_of_a_circle_of_rests_drifts_along_it_and_is_not_called_unstable():
    # U = k (x² + y² − a²)²: at a point of the circle K has the tangent as null direction, a Jordan block of
    # size 2 (a change of momentum along the circle, a drift), split by rounding into eigenvalues ±1e-8.
    text = TWO_CARTS_FREE.replace("k/2*(x2 - x1)^2", "k*(x1^2 + x2^2 - 1)^2")
    eom = lagrangian.derive(lagrangian.parse_model(text))
    lin = linearize(eom, {"x1": math.cos(0.3), "x2": math.sin(0.3)})
    assert lin.modes().zero.blocks == (2,) and not lin.modes().zero.secular
    assert lin.stability().verdict not in ("unstable", "unstable (secular growth)")
