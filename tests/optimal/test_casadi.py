"""SymEngine → CasADi: the converted graph evaluates as SymEngine does, and shares what the outputs share."""

import math

import numpy as np
import pytest
import symengine as se

ca = pytest.importorskip("casadi")

from lagrangian.errors import ModelError
from lagrangian.optimal import casadi_expressions

x, y, m = se.symbols("x y m")


def _value(expr, X, at):
    return float(ca.Function("f", [X], [expr])(at))


def test_every_function_of_the_model_grammar_evaluates_as_symengine_does():
    X = ca.SX.sym("X", 2)
    exprs = [se.sin(x) * se.cos(y) + se.tan(x / 3), se.asin(x / 2) + se.acos(y / 3) + se.atan(x * y),
             se.sinh(x) - se.cosh(y) + se.tanh(x + y), se.exp(-x ** 2) * se.log(2 + y), se.sqrt(1 + x ** 2),
             se.Abs(x - y) + se.sign(x - y), x ** 3 / y ** 2 + y ** -5 + (1 + x) ** se.Rational(3, 2),
             m * se.pi + se.E * x, 1 / se.cos(x) + 1 / se.tan(y), x ** y]
    converted = casadi_expressions(exprs, {x: X[0], y: X[1], m: 2.5})
    rng = np.random.default_rng(3)
    for _ in range(5):
        a, b = rng.uniform(0.2, 0.9, 2)
        for expr, sx in zip(exprs, converted, strict=True):
            expected = float(expr.xreplace({x: a, y: b, m: 2.5}).n())
            assert math.isclose(_value(sx, X, [a, b]), expected, rel_tol=1e-13, abs_tol=1e-14), expr


def test_derivatives_are_exact():
    X = ca.SX.sym("X")
    f = casadi_expressions([se.sin(x) ** 2 * se.exp(x)], {x: X})[0]
    df = ca.Function("df", [X], [ca.jacobian(f, X)])
    a = 0.7
    assert float(df(a)) == pytest.approx(2 * math.sin(a) * math.cos(a) * math.exp(a) + math.sin(a) ** 2 * math.exp(a),
                                         rel=1e-15)


def test_a_subexpression_shared_by_outputs_is_one_node():
    # sin(x)*cos(y) appears in both outputs: converted once, the graph computes it once.
    X = ca.SX.sym("X", 2)
    s = se.sin(x) * se.cos(y)
    symbols = {x: X[0], y: X[1]}
    together = casadi_expressions([s ** 2 + x, s ** 3 + y], symbols)
    apart = casadi_expressions([s ** 2 + x], symbols) + casadi_expressions([s ** 3 + y], symbols)
    shared = ca.Function("f", [X], together).n_instructions()
    repeated = ca.Function("f", [X], apart).n_instructions()
    assert shared <= repeated - 2  # one sin and one cos fewer (SymEngine writes s² as sin²x cos²y)


def test_named_intermediates_are_converted_in_dependency_order():
    w1, w2 = se.symbols("_w1 _w2")
    X = ca.SX.sym("X")
    # w2 is given before the w1 it uses: the order of computation comes from the dependencies
    out = casadi_expressions([w2 * w1], {x: X}, definitions=[(w1, se.sin(x)), (w2, w1 + x)])
    assert _value(out[0], X, 0.4) == pytest.approx((math.sin(0.4) + 0.4) * math.sin(0.4), rel=1e-15)


def test_a_deep_expression_is_not_limited_by_the_recursion_limit():
    X = ca.SX.sym("X")
    expr = x
    for _ in range(3000):
        expr = se.sin(expr)
    assert _value(casadi_expressions([expr], {x: X})[0], X, 0.5) == pytest.approx(
        float(expr.xreplace({x: 0.5}).n()), rel=1e-12)


def test_an_unknown_symbol_is_named():
    with pytest.raises(ModelError, match="`y`"):
        casadi_expressions([x + y], {x: ca.SX.sym("X")})
