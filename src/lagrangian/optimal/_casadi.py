"""SymEngine expressions → CasADi ``SX`` graphs, with their common subexpressions shared.

CasADi differentiates what it is given exactly and sparsely (forward and reverse automatic
differentiation on its expression graph), so the equations of motion enter an optimization as
the graph of M(q) q̈ − F(q, q̇, u): no finite differences, no M⁻¹.  `casadi_expressions` builds
that graph from the expressions `derive` produced, the way `codegen._cprint` prints them as C:

* SymEngine's ``cse`` pulls out the subexpressions that several outputs share (``sin θ``,
  ``m l cos θ``); each becomes one ``SX`` node that every output refers to, so the graph — and
  the derivatives CasADi takes of it — holds it once;
* named intermediates (a recursive form's link velocities and forces, `dynamics._recursive`)
  are converted once each, in dependency order;
* a conversion is memoized per SymEngine node, so a subtree repeated inside one output is also
  one ``SX`` node;
* the walk is iterative (an explicit stack), so the depth of an expression is not bounded by
  Python's recursion limit.

The symbols are mapped by the caller: to ``SX`` symbols (decision variables, unknown parameters
to identify) or to numbers (known parameter values, folded into the graph as constants).

Only the functions a model can contain are converted (`lagrangian.model._expr.FUNCTIONS` and what
differentiation makes of them, as in `codegen._cprint`); anything else is a `ModelError` naming it.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from typing import Any

import symengine as se

from .._abs_derivative import settled
from ..errors import ModelError, OptimizationError

__all__ = ["casadi", "casadi_expressions"]


def casadi() -> Any:
    """The ``casadi`` module, or an `OptimizationError` that says how to install it."""
    try:
        import casadi as ca
    except ImportError as exc:
        raise OptimizationError(f"Optimal control needs CasADi, which cannot be imported ({exc}).",
                                fix="pip install 'lagrangian[optimize]' (CasADi's wheel ships IPOPT)") from None
    return ca


#: SymEngine function name → CasADi's unary operation code, or (code, reciprocal) for what SymEngine makes
#: of the model's functions without being asked (sec(x) = 1/cos(x), acot(x) = atan(1/x): see `_cprint`).
_UNARY = {"sin": "SIN", "cos": "COS", "tan": "TAN", "asin": "ASIN", "acos": "ACOS", "atan": "ATAN", "sinh": "SINH",
          "cosh": "COSH", "tanh": "TANH", "asinh": "ASINH", "acosh": "ACOSH", "atanh": "ATANH", "exp": "EXP",
          "log": "LOG", "Abs": "FABS", "Sign": "SIGN", "sign": "SIGN"}
_RECIPROCAL = {"cot": "TAN", "sec": "COS", "csc": "SIN", "coth": "TANH", "sech": "COSH", "csch": "SINH"}
_OF_RECIPROCAL = {"acot": "ATAN", "asec": "ACOS", "acsc": "ASIN", "acoth": "ATANH", "asech": "ACOSH",
                  "acsch": "ASINH"}


class _Converter:
    """One conversion: the symbol map, the memo of converted nodes, and the values of named symbols.

    Nodes are made with ``SX.binary``/``SX.unary`` and CasADi's operation codes: the same graph as
    ``x * y`` or ``casadi.sin(x)`` (with the same simplifications, 0·x = 0), without the overload
    resolution of CasADi's Python operators, which costs five times the operation.
    """

    def __init__(self, symbols: Mapping[se.Basic, Any], named: Mapping[se.Basic, se.Basic]) -> None:
        ca = self.ca = casadi()
        self.binary, self.unary = ca.SX.binary, ca.SX.unary
        self.op = {name: getattr(ca, f"OP_{name}") for name in ("ADD", "MUL", "DIV", "SQ", "SQRT", "POW",
                                                               "CONSTPOW", "INV")}
        self.ops = {k: getattr(ca, f"OP_{v}") for k, v in {**_UNARY, **_RECIPROCAL, **_OF_RECIPROCAL}.items()}
        self.done: dict[se.Basic, Any] = {k: v if isinstance(v, ca.SX) else ca.SX(float(v)) for k, v in symbols.items()}
        self.named = named  # symbol → expression (cse's replacements, the caller's intermediates)
        self.numbers: dict[float, Any] = {}

    def __call__(self, root: se.Basic) -> Any:
        """The ``SX`` of ``root``; every node is converted after its arguments (post-order, iterative)."""
        done = self.done
        stack: list[tuple[se.Basic, bool]] = [(root, False)]
        while stack:
            node, ready = stack.pop()
            if node in done:
                continue
            if node.is_Symbol:  # a named subexpression: its value first, then the name stands for it
                value = self.named.get(node)
                if value is None:
                    raise ModelError(f"`{node}` is neither a coordinate, a rate, an input nor a parameter with a "
                                     "value, so it cannot enter the optimization.",
                                     symbol=str(node), fix="give it a value (a parameter) or declare it")
                if value in done:
                    done[node] = done[value]
                else:
                    stack += [(node, False), (value, False)]
                continue
            arguments = self._arguments(node)
            if ready or not arguments:
                done[node] = self._build(node, [done[a] for a in arguments])
            else:
                stack.append((node, True))
                stack.extend((a, False) for a in arguments if a not in done)
        return done[root]

    @staticmethod
    def _arguments(node: se.Basic) -> tuple[se.Basic, ...]:
        if node.is_Number or node == se.pi or node == se.E:
            return ()
        if type(node).__name__ == "Derivative":
            return (settled(node),) if settled(node) != node else ()
        if isinstance(node, se.Pow):
            return (node.args[0],) if node.args[1].is_Number else tuple(node.args)
        return tuple(node.args)

    def _number(self, value: float) -> Any:
        out = self.numbers.get(value)
        if out is None:
            out = self.numbers[value] = self.ca.SX(value)
        return out

    def _fold(self, code: int, args: list[Any]) -> Any:
        out = args[0]
        for a in args[1:]:
            out = self.binary(code, out, a)
        return out

    def _power(self, base: Any, exponent: se.Basic) -> Any:
        """base**exponent, small integer powers as products (exact, and cheaper to differentiate)."""
        op, binary = self.op, self.binary
        if isinstance(exponent, se.Integer) and 1 <= abs(int(exponent)) <= 6:
            k = abs(int(exponent))
            out = self.unary(op["SQ"], base) if k >= 2 else base
            for _ in range(k - 2):
                out = binary(op["MUL"], out, base)
            return out if exponent > 0 else self.unary(op["INV"], out)
        if exponent == se.Rational(1, 2):
            return self.unary(op["SQRT"], base)
        if exponent == se.Rational(-1, 2):
            return self.unary(op["INV"], self.unary(op["SQRT"], base))
        return binary(op["CONSTPOW"], base, self._number(float(exponent)))

    def _build(self, node: se.Basic, args: list[Any]) -> Any:
        if node.is_Number:
            try:
                return self._number(float(node))  # a complex number raises here: it has no place in M or F
            except (TypeError, RuntimeError, OverflowError):
                raise ModelError(f"the equations contain the number `{str(node)[:60]}`, which is not a finite "
                                 "real double.", fix="use smaller numbers in the model") from None
        if node == se.pi:
            return self._number(math.pi)
        if node == se.E:
            return self._number(math.e)
        if isinstance(node, se.Add):
            return self._fold(self.op["ADD"], args)
        if isinstance(node, se.Mul):
            return self._fold(self.op["MUL"], args)
        if isinstance(node, se.Pow):
            if node.args[1].is_Number:
                return self._power(args[0], node.args[1])
            return self.binary(self.op["POW"], args[0], args[1])
        name = type(node).__name__
        if name == "Derivative" and args:  # d|u|/dx, left unevaluated by SymEngine: sign(u) du/dx
            return args[0]
        if name in self.ops and len(args) == 1:
            if name in _RECIPROCAL:
                return self.unary(self.op["INV"], self.unary(self.ops[name], args[0]))
            if name in _OF_RECIPROCAL:
                return self.unary(self.ops[name], self.unary(self.op["INV"], args[0]))
            return self.unary(self.ops[name], args[0])
        known = sorted([*_UNARY, *_RECIPROCAL, *_OF_RECIPROCAL])
        raise ModelError(f"the equations contain `{str(node)[:200]}` ({name}), which cannot be handed to CasADi; "
                         f"it supports {', '.join(known)}, powers and sign.",
                         fix="write the model with these functions")


def casadi_expressions(outputs: Sequence[se.Basic], symbols: Mapping[se.Basic, Any], *,
                       definitions: Sequence[tuple[se.Symbol, se.Basic]] = ()) -> list[Any]:
    """The CasADi ``SX`` of each expression of ``outputs``, common subexpressions shared.

    Parameters
    ----------
    outputs : sequence of SymEngine expressions
        M's entries, F, a cost, a path constraint...
    symbols : mapping of SymEngine expression to object
        Each free symbol → what it stands for: a ``casadi.SX`` (a decision variable, a parameter to
        identify) or a number (a known value, folded into the graph).
    definitions : sequence of (SymEngine Symbol, SymEngine expression), optional
        Named intermediates ``(symbol, expression)``, each expression in the symbols of ``symbols``
        and of other definitions (a recursive form's, `RecursiveForm.needed`).

    Returns
    -------
    list of casadi.SX
        One scalar per output, in order (a Python float for an output free of ``SX`` symbols).

    Raises
    ------
    ModelError
        For a free symbol that is in neither ``symbols`` nor ``definitions``, or a function CasADi
        is not given (the message names it).

    Examples
    --------
    >>> import casadi as ca
    >>> x, m = se.Symbol("x"), se.Symbol("m")
    >>> X = ca.SX.sym("X")
    >>> f, g = casadi_expressions([m * se.sin(x) ** 2, se.cos(se.sin(x))], {x: X, m: 2.0})
    >>> round(float(ca.Function("f", [X], [f])(0.5)), 12)  # 2 sin²(0.5)
    0.459697694132
    """
    exprs = [e if isinstance(e, se.Basic) else se.RealDouble(float(e)) for e in outputs]
    defined = [e for _, e in definitions]
    replacements, reduced = se.cse([*defined, *exprs]) if exprs or defined else ([], [])
    named: dict[se.Basic, se.Basic] = dict(replacements)
    named.update((sym, value) for (sym, _), value in zip(definitions, reduced[:len(definitions)], strict=True))
    convert = _Converter(symbols, named)
    return [convert(e) for e in reduced[len(defined):]]
