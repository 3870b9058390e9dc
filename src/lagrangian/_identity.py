"""Is an expression identically zero?  A randomized identity test that does not miss
zeros hidden behind trigonometric identities.

A coordinate is cyclic when ∂L/∂q is zero *as a function*; SymPy's Lagrangian of the
top has a ∂L/∂φ made of sin φ cos φ terms that cancel only after simplification, and
`simplify` is slow and may still miss.  Instead, the expression is evaluated at
random points with 330-bit (about 100-digit) MPFR arithmetic: an analytic function
that is not identically zero vanishes on a set of measure zero, so a non-zero
function gives a value far above the rounding noise (~1e-95) with probability one,
while an identically zero one gives only that noise (the Schwartz–Zippel idea,
applied to analytic functions).  Two points, drawn from a fixed seed so results are
reproducible, are used; a point where the expression is undefined is redrawn.
"""

from __future__ import annotations

import random
from collections.abc import Iterable, Sequence

import symengine as se

__all__ = ["is_zero", "are_zero"]

#: Working precision in bits for the evaluation (about 100 decimal digits).
PRECISION_BITS = 330
#: Values below this (relative to the size of the terms) are rounding noise.
ZERO_THRESHOLD = 1e-60
#: Number of random points an expression must vanish at.
SAMPLES = 2
_SEED = 20261122
_ZERO_TYPE = type(se.Integer(0))


def _points(symbols: Sequence[se.Symbol], count: int, rng: random.Random) -> list[dict[se.Basic, se.Basic]]:
    out = []
    for _ in range(count):
        # Values in [0.3, 1.7]: positive (lengths, masses, sqrt arguments) and away from
        # the special angles 0, π/2, π where Euler-angle expressions degenerate.
        out.append({s: se.RealMPFR(repr(rng.uniform(0.3, 1.7)), PRECISION_BITS) for s in symbols})
    return out


def _magnitude(value: se.Basic) -> float | None:
    try:
        c = complex(value)
    except (TypeError, RuntimeError, ValueError):
        return None
    if c != c or abs(c) == float("inf"):
        return None
    return abs(c)


def are_zero(exprs: Iterable[se.Basic]) -> list[bool]:
    """For each expression, whether it is identically zero (see the module docstring)."""
    exprs = list(exprs)
    # A structural zero first: SymEngine's 0 is a singleton of its own class (a type test
    # is some 40 times cheaper than `e == 0`, which converts the 0 on each call).
    result = [type(e) is _ZERO_TYPE or (not isinstance(e, se.Basic) and e == 0) for e in exprs]
    pending = [i for i, done in enumerate(result) if not done]
    if not pending:
        return result
    symbols = sorted({s for i in pending for s in exprs[i].free_symbols}, key=str)
    if not symbols:
        return [r or _evaluated(se.expand(exprs[i]), False) == 0 if i in pending else r
                for i, r in enumerate(result)]
    rng = random.Random(_SEED)
    verdict = {i: True for i in pending}
    attempts = 0
    good = 0
    while good < SAMPLES and attempts < 4 * SAMPLES:
        attempts += 1
        point = _points(symbols, 1, rng)[0]
        values = {}
        for i in pending:
            if not verdict[i]:
                continue
            v = _evaluated(exprs[i].subs(point), True)
            if v is _UNKNOWN:  # SymEngine cannot evaluate it (the derivative of abs): not claimed zero
                verdict[i] = False
                continue
            values[i] = v
        if any(v is None for v in values.values()):
            continue  # undefined here (e.g. 1/0): draw another point
        good += 1
        for i, v in values.items():
            if v is not None and v > ZERO_THRESHOLD:
                verdict[i] = False
    for i in pending:
        result[i] = verdict[i]
    return result


_UNKNOWN = object()


def _evaluated(expr: se.Basic, complex_: bool):
    """`_magnitude` of ``expr`` in MPFR, or `_UNKNOWN` when SymEngine cannot evaluate it
    (``RuntimeError: Not Implemented`` for ``Derivative(abs(theta), theta)``)."""
    try:
        return _magnitude(expr.n(PRECISION_BITS, real=False) if complex_ else expr.n(PRECISION_BITS))
    except RuntimeError:
        return _UNKNOWN


def is_zero(expr: se.Basic) -> bool:
    """True when ``expr`` is identically zero as a function of its symbols.

    Examples
    --------
    >>> x = se.Symbol("x")
    >>> is_zero(se.sin(x)**2 + se.cos(x)**2 - 1), is_zero(se.sin(x) - x)
    (True, False)
    """
    return are_zero([expr])[0]
