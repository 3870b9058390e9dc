"""Whether an expression holds numbers too big for SymPy's polynomial algorithms to be quick.

SymPy's ``factor`` (and ``simplify``, which calls it) factors over the integers with Wang's
algorithm, which looks for primes past the size of the coefficients: with a coefficient of
300 digits (a mass of ``1e308`` in a model, kept exact) each prime test costs milliseconds and
one report took a minute (found by ``tools/fuzz.py --format urdf``).  Display simplifications
are skipped for such expressions: they are printed as derived, which is still right.
"""

from __future__ import annotations

__all__ = ["BIG_DIGITS", "has_big_numbers"]

#: More digits than this in a numerator or denominator: no factoring.  Products of a few
#: 15-digit decimals stay far below it.
BIG_DIGITS = 100


def has_big_numbers(expr: object, digits: int = BIG_DIGITS) -> bool:
    """Whether a rational number of ``expr`` (SymPy or SymEngine) has more than ``digits`` digits."""
    import sympy  # late: its users need it only when they simplify, and it takes most of a second to load

    e = expr._sympy_() if hasattr(expr, "_sympy_") and not isinstance(expr, sympy.Basic) else expr
    if not isinstance(e, sympy.Basic):
        return False
    bound = 10 ** digits
    return any(abs(r.p) >= bound or r.q >= bound for r in e.atoms(sympy.Rational))
