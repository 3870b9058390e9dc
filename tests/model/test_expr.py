"""The safe expression grammar of model files (`lagrangian.model.parse_expression`).

Numbers, declared names, ``+ - * / ^ **``, parentheses, a fixed list of functions and
the basis vectors ``F.x`` of declared frames — nothing else, and never evaluated as code.
"""

from __future__ import annotations

import re
import time
from pathlib import Path

import pytest
import symengine as se
import sympy as sp

import lagrangian.model as model_pkg
from lagrangian.model import FUNCTIONS, ExpressionError, Vector, parse_expression

x, y, a, b, c = se.symbols("x y a b c")
NAMES = {"x": x, "y": y, "a": a, "b": b, "c": c}
FRAMES = ("R0", "R1", "R")


def parse(text: str) -> se.Basic | Vector:
    return parse_expression(text, NAMES, FRAMES)


def same(text: str, expected: se.Basic) -> None:
    """``text`` parses to exactly ``expected`` (structurally after expansion, no float involved)."""
    value = parse(text)
    assert not isinstance(value, Vector)
    assert se.expand(value - expected) == 0, f"{text!r} gave {value}, not {expected}"


def refused(text: str) -> ExpressionError:
    with pytest.raises(ExpressionError) as info:
        parse(text)
    err = info.value
    assert err.message and err.column >= 1 and err.fix, f"incomplete error for {text!r}: {err.message}"
    return err


# -- precedence and associativity -------------------------------------------------------------
@pytest.mark.parametrize(
    "text, expected",
    [
        ("-x^2", -(x**2)),
        ("-x**2", -(x**2)),
        ("(-x)^2", x**2),
        ("-2^2", se.Integer(-4)),
        ("(-2)^2", se.Integer(4)),
        ("2^3^2", se.Integer(512)),  # right-associative: 2^(3^2)
        ("2**3**2", se.Integer(512)),
        ("2^3**2", se.Integer(512)),
        ("(2^3)^2", se.Integer(64)),
        ("2^-1", se.Rational(1, 2)),
        ("2^-x", 2 ** (-x)),
        ("x^-2^2", x ** (-4)),  # the exponent of ^ is a unary: -(2^2)
        ("a + b*c", a + b * c),
        ("(a + b)*c", (a + b) * c),
        ("a - b - c", a - b - c),  # left-associative
        ("a/b/c", a / b / c),
        ("a/b*c", a * c / b),
        ("a*b^2", a * b**2),
        ("-a*b", -a * b),
        ("--a", a),
        ("+a", a),
        ("a - -b", a + b),
        ("2*x^2^-1", 2 * x ** se.Rational(1, 2)),
        ("  a  +  b  ", a + b),
        ("sin(x)^2 + cos(x)^2", se.sin(x) ** 2 + se.cos(x) ** 2),
        ("-sin(x)^2", -(se.sin(x) ** 2)),
    ],
)
def test_precedence(text: str, expected: se.Basic) -> None:
    same(text, expected)


def test_power_binds_tighter_than_unary_minus_in_a_product() -> None:
    same("a*-x^2", -a * x**2)


# -- exact numbers -----------------------------------------------------------------------------
@pytest.mark.parametrize(
    "text, expected",
    [
        ("0.1", se.Rational(1, 10)),
        ("0.25", se.Rational(1, 4)),
        (".5", se.Rational(1, 2)),
        ("2.", se.Integer(2)),
        ("1e3", se.Integer(1000)),
        ("1E3", se.Integer(1000)),
        ("1.5e-3", se.Rational(3, 2000)),
        ("6.674e-11", se.Rational(6674, 10**14)),
        ("9.81", se.Rational(981, 100)),
        ("0.1 + 0.2", se.Rational(3, 10)),
        ("007", se.Integer(7)),
    ],
)
def test_decimals_are_exact(text: str, expected: se.Basic) -> None:
    value = parse(text)
    assert value == expected
    assert value.is_Rational, f"{text!r} gave the inexact {value!r}"


def test_exact_arithmetic_keeps_rationals() -> None:
    same("0.1*x + 0.2*x - 0.3*x", se.Integer(0))
    same("1/3 + 1/6", se.Rational(1, 2))


# -- names, constants, functions --------------------------------------------------------------------
def test_declared_names_and_pi() -> None:
    same("a*pi", a * se.pi)


@pytest.mark.parametrize("name", sorted(FUNCTIONS))
def test_every_allowed_function(name: str) -> None:
    value = parse(f"{name}(x)")
    assert value == FUNCTIONS[name](x)


def test_fixed_list_of_functions() -> None:
    assert set(FUNCTIONS) == {"sin", "cos", "tan", "asin", "acos", "atan", "sinh", "cosh", "tanh", "exp",
                              "log", "sqrt", "abs"}


def test_unknown_symbol() -> None:
    err = refused("a + bb")
    assert err.symbol == "bb" and err.column == 5 and "unknown symbol `bb`" in err.message
    assert "declare `bb`" in err.fix


def test_unknown_function() -> None:
    err = refused("a + exec(b)")
    assert err.symbol == "exec" and err.column == 5 and "unknown function `exec`" in err.message
    assert "sin" in err.fix


def test_function_takes_one_argument() -> None:
    err = refused("atan(a, b)")
    assert err.symbol == "atan" and err.column == 7 and "one argument" in err.message


def test_function_name_alone_is_not_a_value() -> None:
    err = refused("sin + 1")
    assert err.symbol == "sin"


# -- vectors and their typing ------------------------------------------------------------------------
def test_vector_expressions() -> None:
    v = parse("a*R.x - b*R0.z + R1.y/2")
    assert isinstance(v, Vector)
    assert v == a * Vector.basis("R", "x") - b * Vector.basis("R0", "z") + Vector.basis("R1", "y") / 2
    assert isinstance(parse("-R.x"), Vector)
    assert isinstance(parse("(a + b)*(R.x + R0.y)"), Vector)
    assert isinstance(parse("R.x*a"), Vector)


@pytest.mark.parametrize(
    "text, column, words",
    [
        ("a*R.x + b", 7, "cannot add a vector and a scalar"),
        ("a - R.x", 3, "cannot subtract a vector and a scalar"),
        ("R.x*R0.y", 4, "product of two vectors"),
        ("a/R.x", 2, "cannot divide by a vector"),
        ("R.x^2", 4, "vector cannot be raised to a power"),
        ("a^R.x", 2, "vector cannot be raised to a power"),
        ("sin(R.x)", 1, "`sin` of a vector"),
        ("R + a", 1, "`R` is a frame, not a scalar"),
        ("a*R9.x", 3, "unknown frame `R9`"),
        ("R.w", 3, "followed by `w`"),
        ("R.", 3, "followed by nothing"),
        ("a.x", 1, "`a` is a scalar, not a frame"),
    ],
)
def test_vector_scalar_typing_errors(text: str, column: int, words: str) -> None:
    err = refused(text)
    assert words in err.message
    assert err.column == column, f"{text!r}: column {err.column}, not {column}"


# -- columns of errors -----------------------------------------------------------------------------
@pytest.mark.parametrize(
    "text, column",
    [
        ("a + b*", 7),  # missing operand, at the end
        ("a $ b", 3),  # bad character
        ("   $", 4),  # leading blanks counted
        ("a + (b", 7),  # unclosed parenthesis, at the end
        ("a + b)", 6),  # stray parenthesis
        ("a b", 3),  # missing operator
        ("2x", 2),
        ("a + foo(b)", 5),
        ("(a + b", 7),
        ("a ^ ^ b", 5),
        ("", 1),
        ("   ", 1),
    ],
)
def test_error_columns(text: str, column: int) -> None:
    assert refused(text).column == column


# -- no code, ever -----------------------------------------------------------------------------------
@pytest.mark.parametrize(
    "text",
    [
        '__import__("os")',
        "__import__('os').system('false')",
        "__import__(os)",
        "x.__class__",
        "x.__class__.__bases__",
        "R.__dict__",
        "lambda: 1",
        "lambda x: x",
        '"text"',
        "'text'",
        "x[0]",
        "x if y else a",
        "x == y",
        "x; y",
        "eval(x)",
        "exec(x)",
        "open(x)",
        "getattr(x, y)",
        "a @ b",
        "a % b",
        "a // b",
        "{a}",
        "[a]",
        "a, b",
        "`a`",
        "θ",
    ],
)
def test_code_is_refused(text: str) -> None:
    refused(text)


def test_attribute_access_names_the_object() -> None:
    err = refused("x.__class__")
    assert err.symbol == "x"
    err = refused("R.__class__")
    assert err.symbol == "__class__" and "x, y and z" in err.message


def test_nothing_is_executed(monkeypatch: pytest.MonkeyPatch) -> None:
    """Parsing code-like text never reaches Python's evaluators or SymPy's parsers."""
    import builtins

    def forbidden(*args: object, **kwargs: object) -> None:
        raise AssertionError("an evaluator was called")

    import sympy.parsing.sympy_parser as sympy_parser

    monkeypatch.setattr(builtins, "eval", forbidden)
    monkeypatch.setattr(builtins, "exec", forbidden)
    monkeypatch.setattr(sp, "sympify", forbidden)
    monkeypatch.setattr(sympy_parser, "parse_expr", forbidden)
    assert parse("sin(x)^2 + 0.1*a") == se.sin(x) ** 2 + a / 10
    assert parse("0.1*a*R.x") == a * Vector.basis("R", "x") / 10
    for text in ['__import__("os")', "eval(x)", "exec(x)", "sympify(x)", "parse_expr(x)"]:
        refused(text)


def test_source_of_the_model_package_uses_no_evaluator() -> None:
    """No eval, exec, sympify or parse_expr anywhere in the package's source."""
    root = Path(model_pkg.__file__).resolve().parents[1]
    pattern = re.compile(r"\b(eval|exec|sympify|parse_expr|literal_eval)\s*\(|\bS\s*\(\s*['\"]")
    offenders = []
    for path in sorted(root.rglob("*.py")):
        for number, line in enumerate(path.read_text(encoding="utf-8").splitlines(), start=1):
            code = line.split("#", 1)[0]
            if pattern.search(code):
                offenders.append(f"{path.relative_to(root)}:{number}: {line.strip()}")
    assert not offenders, "\n".join(offenders)


def test_text_only() -> None:
    with pytest.raises(TypeError):
        parse_expression(3, NAMES)  # type: ignore[arg-type]


# -- untrusted sizes ---------------------------------------------------------------------------------
def _quick(text: str, seconds: float = 2.0) -> ExpressionError:
    start = time.perf_counter()
    err = refused(text)
    assert time.perf_counter() - start < seconds, f"{text!r} took too long to refuse"
    return err


def test_huge_exponent_is_refused_quickly() -> None:
    err = _quick("9^9^9")
    assert "too large" in err.message and err.column == 2


@pytest.mark.parametrize("text", ["2^-2000", "x^100000", "((9^999)^999)^999", "(2^1000)^1000",
                                  "(3^500*2^500)^1000", "1e99999999", "1e-99999999", "1" * 5000,
                                  "x^(10^400)"])
def test_huge_numbers_are_refused_quickly(text: str) -> None:
    assert "too large" in _quick(text).message


def test_large_but_reasonable_numbers_are_exact() -> None:
    assert parse("2^1000") == se.Integer(2) ** 1000
    assert parse("1e300") == se.Integer(10) ** 300
    assert parse("x^32") == x**32  # symbolic powers: the degree limit (32) applies


def test_division_by_zero() -> None:
    assert "division by zero" in refused("a/(b - b)").message
    assert refused("a/0").column == 2
    assert "division by zero" in refused("0^-1").message
    assert "not defined" in refused("log(0)").message


def test_deeply_nested_parentheses() -> None:
    same("(" * 50 + "x" + ")" * 50, x)
    err = _quick("(" * 9_000 + "x" + ")" * 9_000, seconds=10)  # within the length limit (20,000)
    assert "nested too deeply" in err.message


@pytest.mark.slow
def test_long_chains_of_signs() -> None:
    same("-" * 40 + "x", x)
    assert "nested too deeply" in _quick("-" * 19_000 + "x", seconds=10).message


def test_long_flat_sums_are_fine() -> None:
    same(" + ".join(["x"] * 2000), 2000 * x)
