"""Sign assumptions and coordinate ranges in the derivation.

Truth: the closed form of each system (a spring of natural length L fixed to a wall at
x = −L pulls the mass back with −k x; a weight on a taut string of length ℓ over a step...),
and the same model derived without assumptions, evaluated where the assumptions hold.
"""

from __future__ import annotations

import numpy as np
import pytest
import symengine as se

import lagrangian
from lagrangian._identity import is_zero

WALL = """
[parameters]
m = 1.0
k = 2.0
L = {L}
[coordinates]
x = {{ initial = 0.1, rate = 0.0{range} }}
[points]
W = "{wall}*R0.x"
[particles.P]
mass = "m"
position = "x*R0.x"
[loads]
spring = {{ spring = {ends}, stiffness = "k", rest_length = "L" }}
"""

x, k, L = se.Symbol("x"), se.Symbol("k"), se.Symbol("L")


def derive(text: str) -> lagrangian.EquationsOfMotion:
    return lagrangian.derive(lagrangian.parse_model(text, source="model.toml"))


def wall(L: str = "{ value = 1.0, positive = true }", range: str = ', range = [-0.5, 0.5]', wall: str = "-L",
         ends: str = '["W", "P"]') -> lagrangian.EquationsOfMotion:
    return derive(WALL.format(L=L, range=range, wall=wall, ends=ends))


@pytest.mark.parametrize(("L_decl", "bounds", "general"), [
    ("{ value = 1.0, positive = true }", ", range = [-0.5, 0.5]", False),   # x + L ≥ 0 at L = 1 only
    ("{ value = 1.0, positive = true }", ', range = ["-L", "L"]', True),    # x + L ≥ 0 for every L
    ("{ positive = true }", ', range = ["-L", "inf"]', True),               # symbolic L, open upper side
])
def test_spring_from_a_wall_gives_minus_k_x(L_decl: str, bounds: str, general: bool) -> None:
    eom = wall(L_decl, bounds)
    (F,) = eom.F
    assert is_zero(F + k * x) and F == -k * x  # the closed form, and written as such
    assert is_zero(eom.U - k * x**2 / 2)
    (fact,) = eom.assumptions
    assert fact.sign == 1 and fact.general is general and is_zero(fact.expression - (x + L))
    assert ("at the declared values" in fact.reason) is not general


def test_the_simplified_force_is_the_force_where_the_assumptions_hold() -> None:
    plain = wall("1.0", "")  # no assumption: −k sgn(x + L)(|x + L| − L)
    (F,) = plain.F
    assert F != -k * x and not plain.assumptions
    for value in np.linspace(-0.5, 0.5, 7):
        assert float(F.subs({x: value, k: 2.0, L: 1.0})) == pytest.approx(-2.0 * value, abs=1e-14)


def test_a_wall_on_the_other_side_uses_a_negative_sign() -> None:
    # W at x = +L, spring written from P to W: ℓ = |x − L| = L − x where x ≤ L.
    eom = wall(range=', range = ["-L", "L"]', wall="L", ends='["P", "W"]')
    (F,) = eom.F
    assert F == -k * x
    (fact,) = eom.assumptions
    assert fact.general and is_zero(fact.sign * fact.expression - (L - x))


@pytest.mark.parametrize(("L_decl", "bounds"), [
    ("1.0", ", range = [-0.5, 0.5]"),                           # no declared sign, but the value proves it
    ("{ value = 1.0, positive = true }", ", range = [-2, 2]"),  # x + L changes sign within the range
    ("{ value = 1.0, positive = true }", ""),                   # no range: x may be anything
])
def test_simplified_only_with_a_proof(L_decl: str, bounds: str) -> None:
    eom = wall(L_decl, bounds)
    (F,) = eom.F
    if L_decl == "1.0":  # values alone (no declared sign) still prove x + 1 ≥ 0 over [-0.5, 0.5]
        assert F == -k * x and not eom.assumptions[0].general
    else:
        assert F != -k * x and not eom.assumptions


def test_abs_in_a_given_potential_and_interval_arithmetic() -> None:
    text = """
[parameters]
k = { value = 2.0, positive = true }
L = 1.0
a = 0.5
[coordinates]
x = { initial = 0.0, rate = 0.0, range = [-3.2, 3.2] }
[particles.P]
mass = "1"
position = "x*R0.x"
[loads]
well = { potential = "k*abs(L + a*cos(x))" }
"""
    eom = derive(text)
    a = se.Symbol("a")
    # L + a cos x ∈ [0.5, 1.5] over the range (interval arithmetic at the values): |·| drops.
    assert is_zero(eom.U - k * (L + a * se.cos(x)))
    (F,) = eom.F
    assert is_zero(F - k * a * se.sin(x))
    assert not eom.assumptions[0].general


def test_models_without_assumptions_are_untouched() -> None:
    eom = lagrangian.derive(lagrangian.load_model(
        __import__("lagrangian_test_support").EXAMPLES_DIR / "simple_pendulum.toml"))
    assert eom.assumptions == ()


@pytest.mark.parametrize(("wall_at", "ends"), [("-L", '["W", "P"]'), ("L", '["P", "W"]')])
def test_newton_euler_agrees_under_the_same_assumptions(wall_at: str, ends: str) -> None:
    from lagrangian.analysis import verify

    eom = wall(range=', range = ["-L", "L"]', wall=wall_at, ends=ends)
    assert eom.F == (-k * x,)
    assert verify(eom).agrees
