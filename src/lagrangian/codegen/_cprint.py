"""SymEngine expressions → C99 source, with common subexpressions shared.

SymEngine's own ``ccode`` prints ``pow(x, 3)`` (a libm call in the hot loop) and large
integers as C integer literals that overflow; this printer writes small integer powers as
products, every number as a double literal, and only the functions a model can contain
(`lagrangian.model._expr.FUNCTIONS` and what differentiation makes of them).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence

import symengine as se

from .._abs_derivative import settled
from ..errors import ModelError

__all__ = ["c_block", "c_expression", "c_sequence"]

_FUNCTIONS = {
    "sin": "sin", "cos": "cos", "tan": "tan", "asin": "asin", "acos": "acos", "atan": "atan",
    "sinh": "sinh", "cosh": "cosh", "tanh": "tanh", "exp": "exp", "log": "log", "Abs": "fabs",
    "asinh": "asinh", "acosh": "acosh", "atanh": "atanh",
}
# What SymEngine makes of the model's functions without being asked: tan(pi/2 - x) is cot(x),
# 1/cos(x) may come back as sec(x).  libm has none of them: f(x) = 1/g(x), and a(x) = b(1/x).
_RECIPROCALS = {"cot": "tan", "sec": "cos", "csc": "sin", "coth": "tanh", "sech": "cosh", "csch": "sinh"}
_INVERSE_RECIPROCALS = {"acot": "atan", "asec": "acos", "acsc": "asin", "acoth": "atanh", "asech": "acosh",
                        "acsch": "asinh"}


def _number(value: float) -> str:
    text = repr(float(value))
    if text in ("inf", "-inf", "nan"):
        raise _overflow(text)
    return text if any(ch in text for ch in ".en") else text + ".0"


def _overflow(text: str) -> ModelError:
    """Every number of a model is a finite double, but their products in M and F need not be
    (``1e308*x`` in a position: T has 1e308² = inf)."""
    return ModelError(f"the equations of motion contain the number {text}: numbers of the model, each finite, "
                      "overflow a double once multiplied together in M q'' = F.",
                      fix="use smaller numbers in the model (other units, or a scaled coordinate)")


def c_expression(expr: se.Basic, names: Mapping[se.Basic, str]) -> str:
    """The C text of one expression.

    Parameters
    ----------
    expr : SymEngine expression
        The expression.
    names : mapping of SymEngine expression to str
        Each free symbol to its C name.

    Returns
    -------
    str
        A C expression.
    """
    if expr in names:
        return names[expr]
    if expr.is_Number:
        try:
            value = float(expr)  # a complex number raises here: it has no place in M or F
        except OverflowError:  # an integer or a rational past 1.8e308
            raise _overflow("past 1.8e308") from None
        return f"({_number(value)})" if value < 0 else _number(value)
    if expr == se.pi:
        return "3.141592653589793"
    if expr == se.E:
        return "2.718281828459045"
    if expr.is_Symbol:
        raise KeyError(f"no C name for the symbol `{expr}`")
    if isinstance(expr, se.Add):
        return "(" + " + ".join(c_expression(a, names) for a in expr.args) + ")"
    if isinstance(expr, se.Mul):
        num, den = [], []
        for factor in expr.args:
            if isinstance(factor, se.Pow) and factor.args[1].is_Number and factor.args[1] < 0:
                den.append(c_expression(factor.args[0] ** (-factor.args[1]), names))
            else:
                num.append(c_expression(factor, names))
        text = "*".join(num) if num else "1.0"
        return f"({text}/({'*'.join(den)}))" if den else f"({text})"
    if isinstance(expr, se.Pow):
        base, exponent = expr.args
        b = c_expression(base, names)
        if isinstance(exponent, se.Integer):
            k = int(exponent)
            if 1 <= k <= 6:
                return "(" + "*".join([b] * k) + ")"
            if -6 <= k <= -1:
                return "(1.0/(" + "*".join([b] * -k) + "))"
            return f"pow({b}, {_number(k)})"
        if exponent == se.Rational(1, 2):
            return f"sqrt({b})"
        if exponent == se.Rational(-1, 2):
            return f"(1.0/sqrt({b}))"
        if exponent == se.Rational(3, 2):
            return f"({b}*sqrt({b}))"
        return f"pow({b}, {c_expression(exponent, names)})"
    name = type(expr).__name__
    if name in _FUNCTIONS and len(expr.args) == 1:
        return f"{_FUNCTIONS[name]}({c_expression(expr.args[0], names)})"
    if name in _RECIPROCALS and len(expr.args) == 1:
        return f"(1.0/{_RECIPROCALS[name]}({c_expression(expr.args[0], names)}))"
    if name in _INVERSE_RECIPROCALS and len(expr.args) == 1:
        return f"{_INVERSE_RECIPROCALS[name]}(1.0/({c_expression(expr.args[0], names)}))"
    if name in ("Sign", "sign"):
        x = c_expression(expr.args[0], names)
        return f"(({x}) > 0.0 ? 1.0 : (({x}) < 0.0 ? -1.0 : 0.0))"
    if name == "Derivative":  # d|u|/dx, left unevaluated by SymEngine: sign(u) du/dx (`settled`)
        plain = settled(expr)
        if plain != expr:
            return c_expression(plain, names)
    raise ModelError(f"the equations of motion contain `{str(expr)[:200]}` ({name}), which the compiled code cannot "
                     "evaluate; it supports "
                     f"{', '.join(sorted([*_FUNCTIONS, *_RECIPROCALS, *_INVERSE_RECIPROCALS]))}, powers and sign.",
                     fix="write the model with these functions (e.g. a derivative that SymEngine leaves unevaluated "
                         "comes from a function of a coordinate that is not differentiable there)")


def c_block(outputs: Sequence[tuple[str, se.Basic]], names: Mapping[se.Basic, str], prefix: str = "x") -> list[str]:
    """Write statements assigning each ``(target, expression)``, common subexpressions computed once.

    The subexpressions come from SymEngine's ``cse``; they become ``const double`` locals named
    ``<prefix>0, <prefix>1, ...`` (blocks in one function need distinct prefixes).  The free symbols of
    the expressions must already be the caller's own, named with a leading underscore, so that the two
    sets cannot clash.

    Parameters
    ----------
    outputs : sequence of (str, SymEngine expression)
        (C target, expression) pairs.
    names : mapping of SymEngine expression to str
        Each free symbol to its C name.
    prefix : str, optional
        The prefix of the locals.

    Returns
    -------
    list of str
        The C statements.
    """
    exprs = [e if isinstance(e, se.Basic) else se.RealDouble(float(e)) for _, e in outputs]
    replacements, reduced = se.cse(exprs) if exprs else ([], [])
    local = dict(names)
    lines = []
    for k, (sym, value) in enumerate(replacements):
        lines.append(f"    const double {prefix}{k} = {c_expression(value, local)};")
        local[sym] = f"{prefix}{k}"
    for (target, _), value in zip(outputs, reduced, strict=True):
        lines.append(f"    {target} = {c_expression(value, local)};")
    return lines


def c_sequence(definitions: Sequence[tuple[se.Symbol, se.Basic]], outputs: Sequence[tuple[str, se.Basic]],
               names: Mapping[se.Basic, str], prefix: str = "x") -> list[str]:
    """Write statements defining each named intermediate in turn, then assigning each output, with CSE over all.

    SymEngine's ``cse`` may pull out of a later definition a piece that an earlier one also holds, so
    the lines are written in dependency order (each local after what it reads), not simply the common
    subexpressions first as in `c_block`.

    Parameters
    ----------
    definitions : sequence of (SymEngine Symbol, SymEngine expression)
        (symbol, expression) with each expression in earlier symbols; the symbols must be in ``names``.
    outputs : sequence of (str, SymEngine expression)
        (C target, expression) pairs.
    names : mapping of SymEngine expression to str
        Each free symbol to its C name.
    prefix : str, optional
        The prefix of the locals.

    Returns
    -------
    list of str
        The C statements.
    """
    exprs = [e for _, e in definitions] + [e if isinstance(e, se.Basic) else se.RealDouble(float(e))
                                           for _, e in outputs]
    replacements, reduced = se.cse(exprs) if exprs else ([], [])
    local = dict(names)
    value: dict[se.Basic, se.Basic] = {}
    for k, (sym, expr) in enumerate(replacements):
        local[sym] = f"{prefix}{k}"
        value[sym] = expr
    for (sym, _), expr in zip(definitions, reduced[:len(definitions)], strict=True):  # then the outputs
        value[sym] = expr
    done: set[se.Basic] = set()
    lines: list[str] = []

    def emit(root: se.Basic) -> None:
        stack = [(root, False)]
        while stack:
            sym, ready = stack.pop()
            if sym in done:
                continue
            if ready:
                done.add(sym)
                lines.append(f"    const double {local[sym]} = {c_expression(value[sym], local)};")
                continue
            stack.append((sym, True))
            stack.extend((s, False) for s in value[sym].free_symbols if s in value and s not in done)

    for sym, _ in definitions:
        emit(sym)
    for (target, _), expr in zip(outputs, reduced[len(definitions):], strict=True):
        for s in expr.free_symbols:
            if s in value:
                emit(s)
        lines.append(f"    {target} = {c_expression(expr, local)};")
    return lines
