"""Limits on what a model expression may cost, and the check of every constant's value.

Model files come from strangers; a 30-character expression such as
``((theta+2)^1000)^1000`` is a polynomial of degree one million once expanded, and
the derivation, the code generation and the integrator would try.  So every
expression read from a file is measured before it is accepted:

- its length, at most `MAX_LENGTH` characters;
- its *effective degree*: nested powers multiply (``(theta^2+1)^20`` has degree 40),
  products add, sums take the largest; a function call such as ``sin(theta)`` counts
  as one new variable (degree 1).  At most `MAX_DEGREE`;
- its *size*: an upper bound of the number of terms once multiplied out
  (``(a+b+c+d)^5`` has 56, ``(a+b)*(c+d)`` 4).  At most `MAX_TERMS`;
- every constant sub-expression (no coordinate, rate, parameter or time in it) must be
  a finite real number as a double: ``sqrt(-1)``, ``log(-1)``, ``exp(exp(1000))`` and
  ``1e400`` are refused, and so is a nonzero number that a double rounds to 0 (``1e-400``).

`real_value` is the one check of a number's value: the parser uses it for constants,
the model's assembly for parameter values and initial conditions.
"""

from __future__ import annotations

import math
import os
import sys
from fractions import Fraction
from numbers import Real

import symengine as se

__all__ = ["MAX_OPS_VARIABLE", "MAX_LENGTH", "MAX_DEGREE", "MAX_TERMS", "MAX_OPS", "NotFinite", "TooLarge", "real_value", "Measure",
           "excerpt", "max_ops", "equations_size"]

#: Longest expression, in characters (the longest in the examples has a few hundred).
MAX_LENGTH = 20_000
#: Largest effective polynomial degree of an expression (nested powers multiply).  The
#: examples reach 7; a position of degree 32 already takes seconds to derive (T squares it).
MAX_DEGREE = 32
#: Largest number of terms an expression may have once multiplied out (an upper bound).
#: The examples reach 15; a position of 128 terms takes about 5 s to derive.
MAX_TERMS = 128

#: Largest size of the derived equations of motion M q̈ = F, in operations (SymEngine's
#: ``count_ops`` over M and F together).  The largest models we ship measure: the Whipple
#: bicycle 4·10^4, the 20-link planar chain 6·10^4, the 10-rod spatial chain 1.1·10^5, the
#: 100-link planar chain 7.4·10^6 and the 50-rod spatial chain 1.4·10^7; past this, code
#: generation, compilation and the cross-checks take minutes and gigabytes.
MAX_OPS = 20_000_000
#: The environment variable that raises (or lowers) `MAX_OPS` for models one trusts.
MAX_OPS_VARIABLE = "LAGRANGIAN_MAX_OPS"

#: Relative size of an imaginary part that is taken as rounding (``acos`` of an exact 1, ...).
_IMAG_TOL = 1e-12


class NotFinite(ValueError):
    """A value that is not a finite real double; the message says what it is instead."""


def real_value(value: object) -> float:
    """Convert ``value`` (a Python number or a constant SymEngine expression) to a finite real float.

    Parameters
    ----------
    value : object
        A Python number or a constant SymEngine expression.

    Returns
    -------
    float
        The value.

    Raises
    ------
    NotFinite
        When the value is infinite, not a number, too large for a double (``1e400``,
        ``10**400``), an exact number too small for one (``1e-400``), or not real (``sqrt(-1)``);
        the message says which.
    """
    if isinstance(value, bool):
        raise NotFinite("a truth value, not a number")
    if isinstance(value, Real):
        try:
            number = float(value)
        except OverflowError:
            raise NotFinite("too large for a double (at most about 1.8e308)") from None
        if math.isnan(number):
            raise NotFinite("not a number (nan)")
        if math.isinf(number):
            raise NotFinite("infinite" if isinstance(value, float)
                            else "too large for a double (at most about 1.8e308)")
        if number == 0.0 and value != 0:
            # 1e-400 is 0 in every computation, while the exact value stays in the symbolic work
            # (x^1e-400 is 1 numerically, its derivative 1e-400 x^-1 is not)
            raise NotFinite("too small for a double: it would be 0 in every computation (the smallest is about "
                            "5e-324); write 0 if that is meant")
        return number
    if not isinstance(value, se.Basic):
        raise NotFinite(f"not a number: `{excerpt(str(value))}`")
    if value.free_symbols:
        raise NotFinite(f"not a constant: it depends on {', '.join(sorted(map(str, value.free_symbols)))}")
    if value.is_Rational:
        return real_value(Fraction(*(int(n) for n in value.get_num_den())))
    if value.has(se.zoo) or value.has(se.nan) or value.has(se.oo):
        raise NotFinite("infinite or undefined")
    try:
        z = complex(value.n(53, real=False))
    except (RuntimeError, ValueError, TypeError, OverflowError) as exc:
        raise NotFinite(f"not computable as a number ({exc})") from None
    if not (math.isfinite(z.real) and math.isfinite(z.imag)):
        raise NotFinite("infinite, or too large for a double (at most about 1.8e308)")
    if abs(z.imag) > _IMAG_TOL * max(1.0, abs(z.real)):
        raise NotFinite(f"not a real number (it is {z.real:.6g}{z.imag:+.6g}i)")
    return z.real


def max_ops() -> int:
    """The largest size of equations allowed: `MAX_OPS`, or the number in ``$LAGRANGIAN_MAX_OPS``.

    Returns
    -------
    int
        `MAX_OPS`, or the whole number in ``$LAGRANGIAN_MAX_OPS`` when it is set (ASCII digits only).
    """
    text = os.environ.get(MAX_OPS_VARIABLE, "").strip()
    return int(text) if text.isascii() and text.isdigit() and len(text) <= 18 else MAX_OPS


def equations_size(named: dict[str, se.Basic], limit: int) -> tuple[int, str, int] | None:
    """Check the size of the expressions of ``named`` against ``limit`` operations in all.

    SymEngine counts in C++ (0.2 s for 10^7 operations), so the check costs little next to
    the derivation it guards.

    Parameters
    ----------
    named : dict of str to SymEngine expression
        The expressions, by name.
    limit : int
        The largest number of operations allowed together.

    Returns
    -------
    tuple of (int, str, int) or None
        None when the expressions have at most ``limit`` operations together, else ``(total,
        largest's name, largest's operations)``.
    """
    total = se.count_ops(*named.values()) if named else 0
    if total <= limit:
        return None
    sizes = {name: se.count_ops(e) for name, e in named.items()}
    largest = max(sizes, key=sizes.__getitem__)
    return total, largest, sizes[largest]


class TooLarge(ValueError):
    """An expression past `MAX_DEGREE` or `MAX_TERMS`; the message says which and by how much."""

    def __init__(self, expr: se.Basic, degree: Fraction, terms: int) -> None:
        if degree > MAX_DEGREE:
            what = f"its degree is {_number(degree)} (nested powers multiply), more than the {MAX_DEGREE} allowed"
        else:
            what = (f"it has {'more than ' if terms >= sys.maxsize else ''}{_number(terms)} terms once "
                    f"multiplied out, more than the {MAX_TERMS} allowed")
        super().__init__(f"`{excerpt(str(expr), width=60)}` is too large: {what}")
        self.expr = expr


def _number(value: Fraction | int) -> str:
    if value >= 10**12:
        return f"about {float(value):.3g}"
    return str(value) if not isinstance(value, Fraction) or value.denominator != 1 else str(value.numerator)


class Measure:
    """The effective degree and the size (terms once expanded) of SymEngine expressions.

    Sub-expressions are shared between the steps of a parse, so each is measured once.
    """

    def __init__(self) -> None:
        self._memo: dict[se.Basic, tuple[Fraction, int]] = {}

    def __call__(self, expr: se.Basic) -> tuple[Fraction, int]:
        """``(degree, terms)`` of ``expr``; each argument of a function is measured as well.

        Raises
        ------
        TooLarge
            For the first sub-expression past `MAX_DEGREE` or `MAX_TERMS`.
        """
        hit = self._memo.get(expr)
        if hit is None:
            hit = self._measure(expr)
            degree, terms = hit
            if degree > MAX_DEGREE or terms > MAX_TERMS:
                raise TooLarge(expr, degree, terms)
            self._memo[expr] = hit
        return hit

    def _measure(self, expr: se.Basic) -> tuple[Fraction, int]:
        if expr.is_Number or not expr.free_symbols:
            return Fraction(0), 1
        if expr.is_Symbol:
            return Fraction(1), 1
        args = expr.args
        if expr.is_Add:
            parts = [self(a) for a in args]
            return max(d for d, _ in parts), sum(n for _, n in parts)
        if expr.is_Mul:
            parts = [self(a) for a in args]
            terms = 1
            for _, n in parts:
                terms = min(terms * n, sys.maxsize)
            return sum((d for d, _ in parts), Fraction(0)), terms
        if expr.is_Pow:
            base, exponent = args
            degree, terms = self(base)
            if exponent.is_Rational:
                power = abs(Fraction(*(int(n) for n in exponent.get_num_den())))
                whole = int(power)
                if terms > 1 and whole > 1:  # the monomials of degree `whole` in `terms` variables
                    terms = _comb_capped(whole + terms - 1, terms - 1)
                return degree * power, terms
            return max(degree, self(exponent)[0]), 1  # a symbolic exponent: kept as it is
        for a in args:  # a function call: its argument is measured (and limited) too
            self(a)
        return Fraction(1), 1


def _comb_capped(n: int, k: int) -> int:
    """``math.comb(n, k)``, or a number past every limit when it would be huge."""
    k = min(k, n - k)
    if k > 64 and n > 10_000:
        return sys.maxsize
    return min(math.comb(n, k), sys.maxsize)


def excerpt(text: str, column: int | None = None, *, width: int = 120) -> str:
    """``text`` whole when short, else its start, the part around ``column`` and its end.

    A 140 KB expression must not make a 140 KB error message.
    """
    if len(text) <= width:
        return text
    part = width // 3
    start, end = text[:part], text[-part:]
    if column is None or column <= part + part // 2 or column > len(text) - part - part // 2:
        return f"{start} … {end}"
    middle = text[max(part, column - 1 - part // 2):column - 1 + part // 2]
    return f"{start} … {middle} … {end}"
