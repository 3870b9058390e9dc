"""The columns of a collocation point, and the problem's names, values and bounds resolved against them.

At every collocation point the decision variables are one column

    z = (q_1..q_n, q̇_1..q̇_n, q̈_1..q̈_n, u_1..u_p, λ_1..λ_m)

named as a `Trajectory` names them (``x``, ``x_dot``, ``x_ddot``, the inputs, ``lambda_<row>``):
the accelerations are unknowns of their own, so that the dynamics enter as the implicit rows
M(q) q̈ − F(q, q̇, u) − Aᵀλ = 0 (no M⁻¹).  `Layout` knows the names and the SymEngine symbol of
each entry; `resolve_*` turn the user's values, bounds and expressions (text in the model grammar,
never evaluated) into numbers and SymEngine expressions, with a `ProblemError` that names what is
unknown and lists what is known.
"""

from __future__ import annotations

import math
import re
from collections.abc import Iterator, Mapping, Sequence
from contextlib import contextmanager
from dataclasses import dataclass
from typing import Any

import numpy as np
import symengine as se

from ..dynamics import EquationsOfMotion
from ..errors import ProblemError
from ..model import ExpressionError, parse_expression

__all__ = [
    "T_END",
    "Layout",
    "at",
    "layout_of",
    "parameter_values",
    "resolve_expression",
    "resolve_path",
    "resolve_value",
]

#: The name of the duration's bounds in ``bounds`` (a free final time).
T_END = "t_end"
#: Comparison operators of a path constraint, split off before the two sides are parsed.
_COMPARISON = re.compile(r"<=|>=|==")


@dataclass(frozen=True)
class Layout:
    """The entries of z at one collocation point (module docstring), with their names and symbols.

    Attributes
    ----------
    coordinates, inputs, multipliers : names, in model order.
    symbols : the SymEngine symbol of every entry of z, in order.
    parameters : name → symbol of every model parameter that is not an input.
    t : the time symbol.
    """

    coordinates: tuple[str, ...]
    inputs: tuple[str, ...]
    multipliers: tuple[str, ...]
    symbols: tuple[se.Symbol, ...]
    parameters: Mapping[str, se.Symbol]
    t: se.Symbol

    @property
    def n(self) -> int:
        return len(self.coordinates)

    @property
    def names(self) -> tuple[str, ...]:
        c = self.coordinates
        return (*c, *(f"{x}_dot" for x in c), *(f"{x}_ddot" for x in c), *self.inputs, *self.multipliers)

    @property
    def width(self) -> int:
        return len(self.symbols)

    def slice(self, part: str) -> slice:
        """The rows of ``"q"``, ``"qd"``, ``"qdd"``, ``"u"`` or ``"lambda"`` in z."""
        n, p = self.n, len(self.inputs)
        starts = {"q": 0, "qd": n, "qdd": 2 * n, "u": 3 * n, "lambda": 3 * n + p}
        sizes = {"q": n, "qd": n, "qdd": n, "u": p, "lambda": len(self.multipliers)}
        return slice(starts[part], starts[part] + sizes[part])

    def index(self, name: str, what: str) -> int:
        """The row of the column ``name``; ``what`` says where it was named (for the message)."""
        names = self.names
        if name in names:
            return names.index(name)
        raise ProblemError(f"{what} names `{name}`, which is neither a coordinate, a rate, an acceleration, an "
                           "input nor a multiplier of the model.", symbol=str(name),
                           fix="the names are " + ", ".join(names))

    def scope(self) -> dict[str, se.Basic]:
        """Every name an expression of the problem may use: the columns, the parameters and t."""
        names: dict[str, se.Basic] = dict(zip(self.names, self.symbols, strict=True))
        names.update(self.parameters)
        names["t"] = self.t
        return names


@contextmanager
def at(table: str, key: str) -> Iterator[None]:
    """A `ProblemError` raised inside is about ``key`` of the problem's ``table`` (a problem file's line)."""
    try:
        yield
    except ProblemError as exc:
        if exc.table is None:
            exc.table, exc.symbol = table, str(key)
        raise


def layout_of(eom: EquationsOfMotion) -> Layout:
    """The `Layout` of ``eom``'s collocation points.

    Raises
    ------
    ProblemError
        When the model declares no input: there would be nothing to choose.
    """
    model = eom.model
    inputs = tuple(p.name for p in model.parameters if p.input)
    if not inputs:
        raise ProblemError(f"The model `{model.name}` has no input, so there is nothing to optimize.",
                           fix="declare the input in [inputs] (`F = { unit = \"N\" }`) and use it in a load "
                               "(`push = { force = \"F*R0.x\", at = \"C\" }`)")
    multipliers = tuple(str(row.multiplier) for row in eom.constraints)
    symbols = (*eom.q, *eom.qd, *eom.qdd, *(se.Symbol(u) for u in inputs),
               *(row.multiplier for row in eom.constraints))
    parameters = {p.name: se.Symbol(p.name) for p in model.parameters if not p.input}
    return Layout(eom.coordinates, inputs, multipliers, tuple(symbols), parameters, eom.t)


def parameter_values(eom: EquationsOfMotion, overrides: Mapping[str, Any]) -> dict[str, float]:
    """The value of every parameter that is not an input: the model's, overridden by ``overrides``.

    A parameter without a value is left out (an expression that uses it is refused when converted).
    """
    model = eom.model
    known = {p.name: p for p in model.parameters}
    for name, value in overrides.items():
        if name not in known:
            raise ProblemError(f"`{name}` is not a parameter of `{model.name}`.", symbol=str(name),
                               fix="the parameters are " + ", ".join(p.name for p in model.parameters if not p.input))
        if known[name].input:
            raise ProblemError(f"`{name}` is an input: the optimization chooses it.", symbol=str(name),
                               fix=f"bound it instead (bounds = {{ {name} = [low, high] }})")
        if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
            raise ProblemError(f"The parameter `{name}` = {value!r} is not a finite number.", symbol=str(name),
                               fix=f"give `{name}` a number")
    out = {}
    for p in model.parameters:
        if p.input:
            continue
        value = overrides.get(p.name, model.parameter_values.get(p.name))
        if value is not None:
            out[p.name] = float(value)
    return out


def _parse(text: str, names: Mapping[str, se.Basic], what: str) -> se.Basic:
    try:
        expr = parse_expression(text, names)
    except ExpressionError as exc:
        raise ProblemError(f"In {what} `{text}`: {exc.message}", symbol=exc.symbol, fix=exc.fix) from None
    if not isinstance(expr, se.Basic):
        raise ProblemError(f"{what} `{text}` is a vector; a scalar is needed here.", fix="write a scalar expression")
    return expr


def resolve_value(value: Any, layout: Layout, values: Mapping[str, float], what: str) -> float:
    """A number, or text in the model grammar of the parameters (``"pi/2"``), as a finite float."""
    if isinstance(value, str):
        expr = _parse(value, layout.parameters, what)
        expr = expr.xreplace({se.Symbol(k): se.RealDouble(v) for k, v in values.items()})
        try:
            number = float(expr)
        except (RuntimeError, TypeError, ValueError):
            raise ProblemError(f"{what} = `{value}` has no numeric value (a parameter without a value?).",
                               fix="give the parameters it uses a value") from None
    elif isinstance(value, (int, float, np.floating, np.integer)) and not isinstance(value, bool):
        number = float(value)
    else:
        raise ProblemError(f"{what} = {value!r} is neither a number nor an expression.", fix="give a number")
    if not math.isfinite(number):
        raise ProblemError(f"{what} = {value!r} is not finite.", fix="give a finite number (or leave it free)")
    return number


def resolve_bound(value: Any, layout: Layout, values: Mapping[str, float], what: str, default: float) -> float:
    """One side of a bound: None or ±inf is no bound (``default``); else `resolve_value`."""
    if value is None:
        return default
    if isinstance(value, (int, float)) and not isinstance(value, bool) and math.isinf(value):
        return float(value)
    if isinstance(value, str) and value.strip().lstrip("+-") in ("inf", "infinity"):
        return -math.inf if value.strip().startswith("-") else math.inf
    return resolve_value(value, layout, values, what)


def resolve_expression(value: Any, layout: Layout, what: str) -> se.Basic:
    """An expression of the columns, the parameters and t: text in the model grammar, or SymEngine."""
    if isinstance(value, str):
        return _parse(value, layout.scope(), what)
    if isinstance(value, se.Basic):
        return value
    if isinstance(value, (int, float)) and not isinstance(value, bool):
        return se.RealDouble(float(value))
    raise ProblemError(f"{what} must be an expression (text), not {type(value).__name__}.",
                       fix="write it like a model file's expressions, e.g. \"x^2 + theta_dot^2\"")


def resolve_path(path: Sequence[str] | Mapping[str, Sequence[Any]], layout: Layout,
                 values: Mapping[str, float]) -> list[tuple[se.Basic, float, float, str]]:
    """The path constraints as (g, low, high, text): ``"x^2 + y^2 <= 1"``, ``"0 <= x <= 1"``, ``"x == 0"``.

    The text is split at its comparison operators and each side read with the model grammar (the
    bounds: numbers or expressions of the parameters).
    """
    out = []
    items = path.items() if isinstance(path, Mapping) else [(text, None) for text in path]
    for text, pair in items:
        if not isinstance(text, str):
            raise ProblemError(f"A path constraint is text, not {type(text).__name__}.",
                               fix="write e.g. \"x^2 + y^2 <= 1\"")
        what = f"the path constraint `{text}`"
        if pair is not None:
            if isinstance(pair, str) or len(pair) != 2:
                raise ProblemError(f"The bounds of {what} must be a pair (low, high).", fix="e.g. [0, 1]")
            low = resolve_bound(pair[0], layout, values, what, -math.inf)
            high = resolve_bound(pair[1], layout, values, what, math.inf)
            g = resolve_expression(text, layout, what)
        else:
            g, low, high = _comparison(text, layout, values, what)
        if low > high:
            raise ProblemError(f"In {what} the low bound {low:g} is above the high bound {high:g}.",
                               fix="swap them")
        out.append((g, low, high, text))
    return out


def _comparison(text: str, layout: Layout, values: Mapping[str, float], what: str) -> tuple[se.Basic, float, float]:
    parts = _COMPARISON.split(text)
    ops = _COMPARISON.findall(text)
    fix = "write \"EXPR <= HIGH\", \"LOW <= EXPR <= HIGH\", \"EXPR >= LOW\" or \"EXPR == VALUE\""
    if not ops or len(ops) > 2 or (len(ops) == 2 and (ops[0] != ops[1] or ops[0] == "==")):
        raise ProblemError(f"{what} is not a comparison that can be read.", fix=fix)
    if len(ops) == 2:  # low <= g <= high, or high >= g >= low
        a = resolve_value(parts[0].strip(), layout, values, what)
        b = resolve_value(parts[2].strip(), layout, values, what)
        low, high = (a, b) if ops[0] == "<=" else (b, a)
        return resolve_expression(parts[1].strip(), layout, what), low, high
    left, right = parts[0].strip(), parts[1].strip()
    g = resolve_expression(left, layout, what) - resolve_expression(right, layout, what)
    if ops[0] == "<=":
        return g, -math.inf, 0.0
    if ops[0] == ">=":
        return g, 0.0, math.inf
    return g, 0.0, 0.0
