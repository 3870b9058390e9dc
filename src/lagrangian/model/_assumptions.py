"""Sign assumptions on parameters and ranges of coordinates.

A statement says "a spring of natural length L, fixed to a wall at x = −L": the distance
from the wall is then x + L > 0, and its force is −k x.  Nothing in the expressions says so:
the length √((x + L)²) reads |x + L| and the force −k sgn(x + L)(|x + L| − L).  A model may
declare what the statement knows::

    [parameters]
    L = { value = 1, positive = true }        # or nonnegative, negative, nonpositive
    [coordinates]
    x = { initial = 0.1, range = ["-L", "L"] }  # numbers or constant expressions; inf for an open side

and the derivation simplifies with it (`Assumptions.refine`): √(u²)^p → (±u)^p, |u| → ±u
and sgn(u) → ±1 wherever u ≥ 0 (or u ≤ 0) is *proved*:

1. for every value allowed by the declared signs: SymPy's assumptions on u with the
   parameters' signs, or, u being linear in each ranged coordinate with a coefficient of
   known sign, on its smallest (largest) value over the ranges — x + L with x ≥ −L is ≥ 0;
2. otherwise at the declared values of the parameters (x + L with x ∈ [−0.5, 0.5] and L = 1),
   by the same bound or by interval arithmetic over the ranges (SymPy's `AccumBounds`).

Every fact used is recorded (`SignFact`: u, its sign, how it was proved), shown by
`derive` and the JSON, and checked along a simulation with the run's values, as are the
ranges themselves (`lagrangian.numerics._ranges`).  A parameter value that breaks its
declared sign is refused (`check_sign`), in the file and on the command line.  Without any
declared sign or range nothing is touched: `refine` returns its argument.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from fractions import Fraction
from typing import TYPE_CHECKING, Any

import symengine as se

from ..errors import ModelError
from .vectors import as_expr

if TYPE_CHECKING:  # pragma: no cover
    import sympy

    from ._assemble import Assembler, Raw
    from .spec import Model

__all__ = [
    "SIGNS",
    "SIGN_RELATIONS",
    "Assumptions",
    "SignFact",
    "check_sign",
    "range_text",
    "read_range",
    "read_sign",
    "sign_problem",
]

#: The sign assumptions a parameter may declare (each is also the SymPy assumption of its symbol).
SIGNS = ("positive", "nonnegative", "negative", "nonpositive")
_TEST = {"positive": lambda v: v > 0, "nonnegative": lambda v: v >= 0, "negative": lambda v: v < 0,
         "nonpositive": lambda v: v <= 0}
#: Each sign as a relation, for messages.
SIGN_RELATIONS = {"positive": "> 0", "nonnegative": "≥ 0", "negative": "< 0", "nonpositive": "≤ 0"}
#: Largest expression (SymPy operation count) whose sign is sought; beyond, nothing is simplified.
MAX_OPS = 200


def sign_problem(name: str, sign: str | None, value: float | None) -> str | None:
    """The message when ``value`` breaks the declared ``sign`` of parameter ``name`` (else None).

    Parameters
    ----------
    name : str
        The parameter's name.
    sign : str or None
        Its declared sign (``"positive"``...), or None.
    value : float or None
        The value given, or None.

    Returns
    -------
    str or None
        The message, or None when the value keeps the sign (or either is unknown).
    """
    if sign is None or value is None or _TEST[sign](value):
        return None
    return f"parameter `{name}` is declared {sign} ({name} {SIGN_RELATIONS[sign]}), but its value is {value:g}"


def check_sign(model: Model, values: Mapping[str, float]) -> None:
    """Refuse values (``--set``, `simulate(parameters=...)`) that break a declared sign.

    Parameters
    ----------
    model : Model
        The model whose parameters declare signs.
    values : mapping of str to float
        Parameter values by name.

    Raises
    ------
    ModelError
        Naming the parameter, its declared sign, the value and where the sign is declared.
    """
    for p in model.parameters:
        if p.name in values and p.sign is not None:
            problem = sign_problem(p.name, p.sign, float(values[p.name]))
            if problem is not None:
                where = model.where("parameter", p.name)
                raise ModelError(problem, symbol=p.name, file=where.file, line=where.line,
                                 fix=f"give `{p.name}` a value {SIGN_RELATIONS[p.sign]}, or change its declared sign "
                                     "(the equations were simplified with it)")


def read_sign(asm: Assembler, raw: Raw, value: float | None) -> str | None:
    """The one sign declared for parameter ``raw`` (``positive = true``...), or None; ``value`` must obey it."""
    given = [(k, v) for k, v in raw.data.get("signs", {}).items() if v is not None]
    for key, v in given:
        if v is not True:
            raise asm.error(raw, f"`{key}` of parameter `{raw.name}` must be true, not `{v}`", symbol=raw.name,
                            key=key, fix=f"write `{key} = true`, or leave it out (no assumption)")
    if len(given) > 1:
        raise asm.error(raw, f"parameter `{raw.name}` declares {' and '.join(k for k, _ in given)}: one sign at most",
                        symbol=raw.name, key=given[1][0], fix="keep the one that the statement says")
    sign = given[0][0] if given else None
    problem = sign_problem(raw.name, sign, value)
    if problem is not None:
        raise asm.error(raw, problem, symbol=raw.name, key="value",
                        fix=f"give `{raw.name}` a value {SIGN_RELATIONS[sign]}, "  # type: ignore[index]
                            "or correct its declared sign")
    return sign


def read_range(asm: Assembler, raw: Raw, initial: float | None) -> tuple[se.Basic | None, se.Basic | None] | None:
    """The declared ``range = [lower, upper]`` of coordinate ``raw``, checked (None when not given).

    Each side is a number, ±inf (open) or a constant expression in the parameters; the lower
    side must be below the upper one and the initial value within, where their values are known.
    """
    value = raw.data.get("range")
    if value is None:
        return None
    example = 'e.g. range = [-0.5, 0.5], range = ["-L", "L"] or range = [0, inf]'
    if isinstance(value, (str, bytes)) or not isinstance(value, Sequence) or len(value) != 2:
        raise asm.error(raw, f"`range` of coordinate `{raw.name}` must be a list of two bounds, not `{value}`",
                        symbol=raw.name, key="range", fix=example)
    sides: list[se.Basic | None] = []
    for k, side in enumerate(value):
        if isinstance(side, str) and side.strip() in ("inf", "+inf", "-inf"):  # as text too: "-inf"
            side = float(side.strip())
        if isinstance(side, float) and math.isinf(side) and (side < 0) == (k == 0):
            sides.append(None)
            continue
        if isinstance(side, bool) or not isinstance(side, (int, float, str)):
            raise asm.error(raw, f"a bound of the range of coordinate `{raw.name}` must be a number or an "
                            f"expression in the parameters, not `{side}`", symbol=raw.name, key="range", fix=example)
        if isinstance(side, float) and math.isinf(side):
            raise asm.error(raw, f"the {'lower' if k == 0 else 'upper'} bound of the range of coordinate "
                            f"`{raw.name}` is {side}", symbol=raw.name, key="range",
                            fix="write -inf for an open lower side and inf for an open upper side")
        if isinstance(side, str):
            expr = asm.expr(raw, "the range", side, key="range")
        else:  # a number, exact as written (0.5 is 1/2, as in expressions)
            number = asm.number(raw, side, f"a bound of the range of `{raw.name}`", "range")
            expr = as_expr(side if isinstance(side, int) else Fraction(repr(number)))
        moving = sorted(str(s) for s in expr.free_symbols if s not in asm.constants)
        if moving:
            raise asm.error(raw, f"the range of coordinate `{raw.name}` depends on `{moving[0]}`: a bound is "
                            "constant (numbers and parameters only)", symbol=moving[0], key="range",
                            fix="write the bounds with numbers and parameters, e.g. range = [\"-L\", \"L\"]")
        sides.append(expr)
    lower, upper = sides
    known = {s: v for s, v in asm.constants.items() if v is not None}
    numbers = [None if b is None or not b.free_symbols <= set(known) else float(b.subs(known)) for b in sides]
    if numbers[0] is not None and numbers[1] is not None and not numbers[0] < numbers[1]:
        raise asm.error(raw, f"the range of coordinate `{raw.name}` is empty: its lower bound {numbers[0]:g} is not "
                        f"below its upper bound {numbers[1]:g}", symbol=raw.name, key="range",
                        fix="write range = [lower, upper] with lower < upper")
    if initial is not None and ((numbers[0] is not None and initial < numbers[0])
                                or (numbers[1] is not None and initial > numbers[1])):
        raise asm.error(raw, f"the initial value {initial:g} of coordinate `{raw.name}` is outside its range "
                        f"{range_text((lower, upper))}", symbol=raw.name, key="initial",
                        fix="start within the range, or widen it")
    return (lower, upper)


def range_text(bounds: tuple[se.Basic | None, se.Basic | None]) -> str:
    """Format a range as ``[-0.5, 0.5]``, ``[-L, L]``, ``[0, inf)``.

    Parameters
    ----------
    bounds : tuple of (SymEngine expression or None, SymEngine expression or None)
        The lower and upper bounds, None for an open side.

    Returns
    -------
    str
        The range in interval notation.
    """
    lower, upper = (None if b is None else f"{float(b):g}" if not b.free_symbols else str(b) for b in bounds)
    return (f"[{lower}" if lower is not None else "(-inf") + ", " + (f"{upper}]" if upper is not None else "inf)")


@dataclass(frozen=True, slots=True)
class SignFact:
    """A sign the derivation proved and used: u = ``expression`` ≥ 0 (``sign`` +1) or u ≤ 0 (−1).

    That is what ``|u| = ±u`` and ``√(u²) = ±u`` need; sgn(u) = ±1 holds where u ≠ 0, and is taken
    by continuity from inside where u = 0 on the edge of a range (a spring of zero length).

    ``general`` is True when it holds for every value allowed by the declared signs and ranges,
    False when it was proved at the declared parameter values only; ``reason`` says how.

    Parameters
    ----------
    expression : SymEngine expression
        The expression u.
    sign : int
        +1 for u ≥ 0, −1 for u ≤ 0.
    general : bool
        True when it holds for every value allowed by the declared signs and ranges, False when it
        was proved at the declared parameter values only.
    reason : str
        How it was proved.
    """

    expression: se.Basic
    sign: int
    general: bool
    reason: str

    @property
    def relation(self) -> str:
        """``≥`` or ``≤``."""
        return "≥" if self.sign > 0 else "≤"

    @property
    def text(self) -> str:
        """``L + x ≥ 0 (x ∈ [-L, L], L > 0)``."""
        return f"{self.expression} {self.relation} 0 ({self.reason})"

    def holds(self, value: float) -> bool:
        """Whether a value of the expression obeys the fact.

        Parameters
        ----------
        value : float
            A value of ``expression``.

        Returns
        -------
        bool
            True when the value has the proved sign (0 included).
        """
        return self.sign * value >= 0


class Assumptions:
    """The declared signs and ranges of a model, and the simplifications they allow.

    ``facts`` lists, in order of first use, the `SignFact` each simplification relied on.

    Parameters
    ----------
    model : Model
        The model whose declared signs and ranges are used.
    """

    def __init__(self, model: Model) -> None:
        self.model = model
        self.signs = {p.symbol: p.sign for p in model.parameters if p.sign is not None}
        self.ranges = {c.symbol: c.range for c in model.coordinates if c.range is not None}
        self.values = {p.symbol: p.value for p in model.parameters if p.value is not None and not p.input}
        self.coordinates = {c.symbol for c in model.coordinates}
        self.active = bool(self.signs or self.ranges)
        self.facts: list[SignFact] = []
        self._proofs: dict[se.Basic, SignFact | None] = {}
        self._refined: dict[se.Basic, se.Basic] = {}
        # SymPy symbols that carry the declared signs (the others are real); none needed when inactive,
        # and SymPy (most of a second to load) is then not loaded at all.
        self._sympy = {}
        if self.active:
            import sympy

            for p in model.parameters:
                self._sympy[p.symbol] = sympy.Symbol(p.name, **{p.sign or "real": True})
            for c in model.coordinates:
                self._sympy[c.symbol] = sympy.Symbol(c.name, real=True)

    # -- simplification --------------------------------------------------------------------------
    def refine(self, e: se.Basic) -> se.Basic:
        """Simplify ``√(u²)^p``, ``|u|`` and ``sgn(u)`` wherever the sign of u is proved (module docstring).

        Parameters
        ----------
        e : SymEngine expression
            The expression to simplify.

        Returns
        -------
        SymEngine expression
            ``e`` with those resolved.
        """
        if not self.active or not isinstance(e, se.Basic) or not e.free_symbols:
            return e
        return self._walk(e)

    def _walk(self, e: se.Basic) -> se.Basic:
        hit = self._refined.get(e)
        if hit is not None:
            return hit
        args = e.args
        out = e
        if args:
            new = [self._walk(a) for a in args]
            if any(a != b for a, b in zip(new, args, strict=True)):
                out = e.func(*new)
            out = self._resolve(out)
        self._refined[e] = out
        return out

    def _resolve(self, e: se.Basic) -> se.Basic:
        if isinstance(e, se.Pow):
            base, exp = e.args
            # (u^(2k))^p = |u|^(2k p): √(u²) = |u|, 1/√(u²) = 1/|u|.
            if isinstance(base, se.Pow) and base.args[1].is_Integer and int(base.args[1]) % 2 == 0 \
                    and not exp.is_Integer:
                s = self.sign(base.args[0])
                if s is not None:
                    return (s * base.args[0]) ** (base.args[1] * exp)
            return e
        if isinstance(e, se.Abs):
            s = self.sign(e.args[0])
            return s * e.args[0] if s is not None else e
        if isinstance(e, se.sign):
            s = self.sign(e.args[0])  # sgn(u) = 1 for u ≥ 0: by continuity at u = 0 (`SignFact`)
            return se.Integer(s) if s is not None else e
        return e

    # -- signs -----------------------------------------------------------------------------------
    def sign(self, u: se.Basic) -> int | None:
        """The proved sign of u, if any (module docstring).

        Parameters
        ----------
        u : SymEngine expression
            The expression whose sign is asked.

        Returns
        -------
        int or None
            +1 when u ≥ 0 is proved, −1 when u ≤ 0, None when unknown.
        """
        if u not in self._proofs:
            found = self._prove(u)
            fact = None if found is None else SignFact(u, *found)
            self._proofs[u] = fact
            if fact is not None:
                self.facts.append(fact)
        fact = self._proofs[u]
        return None if fact is None else fact.sign

    def _prove(self, u: se.Basic) -> tuple[int, bool, str] | None:
        """(sign, general, reason), or None (module docstring)."""
        import sympy

        symbols = u.free_symbols
        if not symbols or not symbols <= set(self._sympy):
            return None  # a number (SymEngine decides its sign itself), or rates, time...: not here
        su = self._to_sympy(u)
        if sympy.count_ops(su) > MAX_OPS:
            return None
        declared = ", ".join(f"{s} {SIGN_RELATIONS[self.signs[s]]}"
                             for s in sorted(symbols & set(self.signs), key=str))
        if su.is_nonnegative:
            return 1, True, declared or "always"
        if su.is_nonpositive:
            return -1, True, declared or "always"
        ranged = sorted(symbols & set(self.ranges), key=str)
        if not ranged or any(s not in self.ranges for s in symbols & self.coordinates):
            return None  # a coordinate with no declared range can take any value
        ranges = ", ".join(f"{s} ∈ {range_text(self.ranges[s])}" for s in ranged)
        bounds = self._linear_bounds(su, ranged)
        if bounds is not None:
            low, high = bounds
            general = ", ".join(x for x in (ranges, declared) if x)
            if low is not None and low.is_nonnegative:
                return 1, True, general
            if high is not None and high.is_nonpositive:
                return -1, True, general
        # At the declared values of the parameters.
        values = {self._sympy[s]: sympy.Float(v) for s, v in self.values.items()}
        if any(self._sympy[s] not in values for s in symbols - self.coordinates):
            return None
        used = sorted(symbols - self.coordinates, key=str)
        at = ", ".join(f"{s} = {self.values[s]:g}" for s in used)
        reason = ", ".join(x for x in (ranges, at) if x) + ": at the declared values"
        if bounds is not None:
            low, high = (None if b is None else b.xreplace(values) for b in bounds)
        else:
            interval = self._interval(su.xreplace(values), ranged, values)
            if interval is None:
                return None
            low, high = interval.min, interval.max
        if low is not None and low.is_number and low >= 0:
            return 1, False, reason
        if high is not None and high.is_number and high <= 0:
            return -1, False, reason
        return None

    def _linear_bounds(self, su: sympy.Basic, ranged: list[se.Basic]) -> tuple[Any, Any] | None:
        """(smallest, largest) of ``su`` over the ranges when it is linear in each ranged coordinate
        with a coefficient free of coordinates and of known sign; None otherwise (an open side: None)."""
        import sympy

        coordinates = {self._sympy[s] for s in self.coordinates}
        low, high = su, su
        for s in ranged:
            x = self._sympy[s]
            c = sympy.diff(su, x)
            if c.free_symbols & coordinates:
                return None
            lower, upper = (None if b is None else self._to_sympy(b) for b in self.ranges[s])
            if c.is_zero:
                continue
            if c.is_positive:
                low = None if low is None or lower is None else low.subs(x, lower)
                high = None if high is None or upper is None else high.subs(x, upper)
            elif c.is_negative:
                low = None if low is None or upper is None else low.subs(x, upper)
                high = None if high is None or lower is None else high.subs(x, lower)
            else:
                return None
        return low, high

    def _interval(self, su: sympy.Basic, ranged: list[se.Basic], values: dict) -> Any:
        """Interval arithmetic (SymPy's `AccumBounds`) over the ranges, all of them closed and numeric."""
        import sympy

        bounds = {}
        for s in ranged:
            lower, upper = self.ranges[s]
            if lower is None or upper is None:
                return None
            lo, hi = self._to_sympy(lower).xreplace(values), self._to_sympy(upper).xreplace(values)
            if not (lo.is_number and hi.is_number):
                return None
            bounds[self._sympy[s]] = sympy.AccumBounds(lo, hi)
        try:
            out = su.subs(bounds)
        except (TypeError, ValueError, NotImplementedError):  # pragma: no cover - AccumBounds' gaps
            return None
        return out if isinstance(out, sympy.AccumBounds) and out.min.is_number and out.max.is_number else None

    def _to_sympy(self, e: se.Basic) -> sympy.Basic:
        """``e`` in SymPy (by structure, `_sympy_`: no text), its symbols carrying the declared signs."""
        import sympy

        return e._sympy_().xreplace({sympy.Symbol(str(k)): v for k, v in self._sympy.items()})
