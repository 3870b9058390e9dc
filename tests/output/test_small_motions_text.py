"""What the small-motion section says besides the numbers: the closed-form pulsations, what M, D, G, K, N are,
Lagrange–Dirichlet with neutral directions, and the numbers written when the letters would be too long.

Hand derivations: the cart's inverted pendulum hanging (θ = π) has M = [[mc + m, −m l], [−m l, m l²]],
K = diag(0, m g l), so det(K − ω² M) = 0 gives ω² = 0 (the cart's drift) and ω² = (mc + m) g/(mc l).
"""

from __future__ import annotations

import pytest
import sympy
from lagrangian_test_support import EXAMPLES_DIR

import lagrangian
from lagrangian.output import report
from lagrangian.output._report.document import Para, math_of
from lagrangian.output._report.steps import small_motions


def _cart() -> lagrangian.EquationsOfMotion:
    return lagrangian.derive(lagrangian.load_model(EXAMPLES_DIR / "inverted_pendulum_cart.toml"))


def _text(section) -> str:  # type: ignore[no-untyped-def]
    return " ".join(x for b in section.blocks if isinstance(b, Para) for x in b.runs if isinstance(x, str))


@pytest.mark.slow
def test_the_pulsation_of_the_hanging_cart_pendulum_is_given_in_letters():
    section = report(_cart(), lang="en", small_motions={"x": 0, "theta": "pi"}).document.section("small motions")
    maths = " ".join(math_of(section.blocks))
    mc, m, l, g = sympy.symbols("mc m l g", positive=True)
    w2 = sympy.Symbol("w2")
    K = sympy.Matrix([[0, 0], [0, m * g * l]])
    M = sympy.Matrix([[mc + m, -m * l], [-m * l, m * l**2]])
    nonzero = [r for r in sympy.solve((K - w2 * M).det(), w2) if r != 0]
    assert len(nonzero) == 1 and sympy.simplify(nonzero[0] - (mc + m) * g / (mc * l)) == 0
    assert r"\omega_{1}^{2} = \frac{g \left(\mathrm{mc} + m\right)}{\mathrm{mc} l}" in maths
    assert "4.42945" in maths and r"\mathrm{s^{-1}}" in maths


def test_the_section_says_what_d_g_k_n_are_and_where_lagrange_dirichlet_applies():
    section = report(_cart(), lang="en", small_motions={"x": 0, "theta": "pi"}).document.section("small motions")
    text = _text(section)
    assert "the damping and the gyroscopic terms" in text and "the circulatory terms" in text
    assert "gives the action of the inputs" in text
    # K = diag(0, m g l) is not positive definite: the verdict is about θ, with x set aside.
    assert "restricted to the coordinates" in text and "may drift" in text


@pytest.mark.slow
def test_coefficients_too_long_in_letters_are_written_with_numbers(monkeypatch):
    # The path the bicycle takes (its reduced K runs to 10⁴ characters an entry), on the double pendulum.
    monkeypatch.setattr(small_motions, "LETTERS_MAX_CHARS", 10)
    eom = lagrangian.derive(lagrangian.load_model(EXAMPLES_DIR / "double_pendulum.toml"))
    section = report(eom, lang="fr", small_motions={"theta1": 0, "theta2": 0}).document.section("small motions")
    notes = [b for b in section.blocks if isinstance(b, Para) and b.style == "note"]
    assert notes and "le plus long compterait" in "".join(x for x in notes[0].runs if isinstance(x, str))
    maths = " ".join(math_of(section.blocks))
    assert "m_{1}" not in maths and "9,81" not in maths  # numbers, not letters
