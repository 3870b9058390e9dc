"""The report's display simplifier: the forms a teacher would write, never another value.

The forms are checked against the trigonometric identities written out by hand;
the values against the engine's expressions of every example, at random states.
"""

from __future__ import annotations

import random

import pytest
import sympy
from lagrangian_test_support import eom_of, example_names, integrals_of
from sympy import cos, sin, symbols

from lagrangian.output import course_form
from lagrangian.output._display_form import display_form
from lagrangian.output._report.build import report_notation

A, C, m, g, a, m1, m2, l1, l2 = symbols("A C m g a m1 m2 l1 l2")
th, thd, psd, phd, t1, t2, t1dd = symbols("theta theta_dot psi_dot phi_dot theta1 theta2 theta1_ddot")
CONSTANTS = {"A", "C", "m", "g", "a", "m1", "m2", "l1", "l2"}


def form(e):
    return display_form(e, CONSTANTS)


def test_sin_squared_plus_cos_squared():
    e = l1**2 * m2 * t1dd * sin(t2)**2 + l1**2 * m2 * t1dd * cos(t2)**2
    assert form(e) == m2 * l1**2 * t1dd
    # Two different coefficients: nothing to apply (the top's M_ψψ = A sin²θ + C cos²θ stays).
    assert form(A * sin(th)**2 + C * cos(th)**2) == A * sin(th)**2 + C * cos(th)**2


def test_angle_addition_collapses():
    # The double pendulum's U_P written on R2's axes: −m2 g (l1 cos θ1 + ½ l2 cos(θ1 + θ2)).
    u = m2 * g * (cos(t1 + t2) * (-l1 * cos(t2) - l2 / 2) - l1 * sin(t1 + t2) * sin(t2))
    assert sympy.expand(form(u) + m2 * g * (l1 * cos(t1) + l2 / 2 * cos(t1 + t2))) == 0
    assert not form(u).has(cos(t2)) and not form(u).has(sin(t2))
    # ∂U/∂θ2 of the double pendulum with absolute angles: sin θ1 cos(θ1 − θ2) − sin(θ1 − θ2) cos θ1 = sin θ2.
    assert form(m2 * l2 * g * sin(t1) * cos(t1 - t2) - m2 * l2 * g * sin(t1 - t2) * cos(t1)) == m2 * l2 * g * sin(t2)
    # cos u cos v − sin u sin v = cos(u + v), sin u cos v + cos u sin v = sin(u + v).
    assert form(a * cos(t1) * cos(t2) - a * sin(t1) * sin(t2)) == a * cos(t1 + t2)
    assert form(a * sin(t1) * cos(t2) + a * cos(t1) * sin(t2)) == a * sin(t1 + t2)


def test_common_factors_out_and_parameters_gathered():
    # The top's F_ψ: θ̇ sinθ [C φ̇ + 2 (C − A) ψ̇ cosθ].
    f_psi = -sin(th) * (2 * A * psd * thd * cos(th) - C * thd * (phd + psd * cos(th))) + C * psd * thd * sin(th) * cos(th)
    from lagrangian.output._notation import Notation

    assert sympy.expand(form(f_psi) - f_psi) == 0
    assert Notation(("psi", "theta", "phi"), ("A", "C")).text(form(f_psi)) == "θ̇ sinθ (2 (C − A) ψ̇ cosθ + C φ̇)"
    # The seed's ∂T/∂θ keeps the spin φ̇ + ψ̇ cosθ: a rewrite without identity must be much shorter to be kept.
    dT = A * psd**2 * sin(th) * cos(th) - C * psd * sin(th) * (phd + psd * cos(th))
    assert form(dT) == dT


def test_report_order_writes_constants_first_masses_leading():
    from lagrangian.output._notation import Notation

    n = Notation(("psi", "theta", "phi"), ("A", "C"))
    # A sum of constants is written with the constants (after the number), starting with a positive term.
    assert n.text(sympy.Mul(2, C - A, psd, cos(th), evaluate=False)) == "2 (C − A) ψ̇ cosθ"
    assert n.text(thd * (A - C)) == "(A − C) θ̇"
    eom = eom_of("double_pendulum.toml")
    n = report_notation(course_form(eom, ()), eom.model)
    assert list(n.parameters[:2]) == ["m1", "m2"]
    assert n.text(l1 * l2 * m2) == "m2 l1 l2"


def _random_values(e: sympy.Basic, rng: random.Random) -> dict:
    return {s: sympy.Float(rng.uniform(0.3, 1.7)) for s in e.free_symbols}


@pytest.mark.slow
def test_every_example_keeps_its_values_at_random_states():
    """Every expression the report prints of every example (T, U, each equation's parts, M, F) has, once
    rewritten, the engine's value at three random states and parameter values."""
    rng = random.Random(11)
    rewritten = 0
    # The bicycle's expressions are past MAX_OPS (printed as derived, or summarized): 5 s of course form for nothing.
    for name in [n for n in example_names() if n != "whipple_bicycle.toml"]:
        eom = eom_of(name)
        f = course_form(eom, integrals_of(name))
        n = report_notation(f, eom.model)
        exprs = [t.expression for t in f.T] + [u.expression for u in f.U]
        for row in f.equations:
            exprs += [row.dT_dqd, row.dT_dq, row.dU_dq, row.Q_nc, row.lhs, row.rhs]
        exprs += [x for row in f.M for x in row] + list(f.F)
        for e in exprs:
            e = e if isinstance(e, sympy.Basic) else e._sympy_()
            shown = n.rewrite(e)
            if shown == e:
                continue
            rewritten += 1
            for _ in range(3):
                values = _random_values(e, rng)
                want, got = complex(e.xreplace(values).evalf()), complex(shown.xreplace(values).evalf())
                assert abs(want - got) <= 1e-9 * (1 + abs(want)), (name, e, shown)
    assert rewritten >= 10  # the check above is not empty


def test_a_constant_subtracted_comes_last():
    """The pendulum's rod: x² + y² − l² = 0, as written on the board (not −l² + x² + y²)."""
    from lagrangian.output._notation import Notation

    x, y = symbols("x y")
    n = Notation(("x", "y"), ("m", "l", "g"))
    assert n.text(x**2 + y**2 - symbols("l")**2) == "x² + y² − l²"
    assert n.latex(x**2 + y**2 - symbols("l")**2) == "x^{2} + y^{2} - l^{2}"


def test_like_terms_are_collected_as_a_teacher_would() -> None:
    # The double pendulum's ∂T/∂θ̇2 as derived writes (θ̇1 + θ̇2) twice; a teacher writes
    # ⅓ m2 l2² (θ̇1 + θ̇2) + ½ m2 l1 l2 θ̇1 cosθ2 (rule 4), and leaves a square as it is.
    m2, l1, l2, a, b, t2, C, p, s, th = sympy.symbols("m2 l1 l2 theta1_dot theta2_dot theta2 C phi_dot psi_dot theta")
    derived = sympy.Rational(1, 2) * m2 * l2 * (l1 * a * sympy.cos(t2) + sympy.Rational(1, 2) * l2 * (a + b)) \
        + sympy.Rational(1, 12) * m2 * l2**2 * (a + b)
    shown = display_form(derived, ["m2", "l1", "l2"])
    assert shown == sympy.Rational(1, 3) * m2 * l2**2 * (a + b) + sympy.Rational(1, 2) * m2 * l1 * l2 * a * sympy.cos(t2)
    assert sympy.expand(shown - derived) == 0
    spin = sympy.Rational(1, 2) * C * (p + s * sympy.cos(th)) ** 2  # ½ C (φ̇ + ψ̇ cosθ)²: nothing to collect
    assert display_form(spin, ["C"]) == spin
