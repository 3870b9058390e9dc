"""The total time derivative d/dt along a motion q(t).

For any f(q, q̇, t):  df/dt = Σ_i (∂f/∂q_i q̇_i + ∂f/∂q̇_i q̈_i) + ∂f/∂t.
q, q̇ and q̈ are plain symbols (``theta``, ``theta_dot``, ``theta_ddot``), which is
much lighter than SymPy's functions of time and gives the same results.

Two ways to compute it, the same function each time:

* ``d_dt(f)`` differentiates f once per coordinate symbol it holds and groups the
  result by q̇_i and q̈_i, as a student collects terms (the form shown to the user);
* ``d_dt.many(fs)`` applies the chain rule node by node, keeping the derivative of
  every subexpression it meets, so expressions that share subexpressions (the ∂T/∂q̇_i
  of a long chain all contain the same velocity components) cost one pass in all,
  where the grouped form costs 2n passes over each; products stay products.
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence
from dataclasses import dataclass

import symengine as se

from ..model.vectors import sum_of

__all__ = ["TimeDerivative"]


@dataclass(frozen=True, slots=True)
class TimeDerivative:
    """The derivative d/dt for expressions in q, q̇ (and q̈ when ``accelerations`` is set) and t.

    Parameters
    ----------
    q : tuple of SymEngine Symbol
        The coordinates q_i.
    qd : tuple of SymEngine Symbol
        Their rates q̇_i.
    qdd : tuple of SymEngine Symbol
        Their accelerations q̈_i.
    t : SymEngine Symbol
        The time.
    """

    q: tuple[se.Symbol, ...]
    qd: tuple[se.Symbol, ...]
    qdd: tuple[se.Symbol, ...]
    t: se.Symbol

    @classmethod
    def of(cls, q: Sequence[se.Symbol], qd: Sequence[se.Symbol], qdd: Sequence[se.Symbol], t: se.Symbol) -> TimeDerivative:
        return cls(tuple(q), tuple(qd), tuple(qdd), t)

    def __call__(self, f: se.Basic, *, accelerations: bool = True) -> se.Basic:
        """df/dt; with ``accelerations=False``, the part of it without q̈ (used for M q̈ = F)."""
        if f.is_Number:
            return _ZERO
        free = f.free_symbols
        if not free:
            return _ZERO
        terms = []
        for q, qd, qdd in zip(self.q, self.qd, self.qdd, strict=True):
            if q in free:
                terms.append(f.diff(q) * qd)
            if accelerations and qd in free:
                terms.append(f.diff(qd) * qdd)
        if self.t in free:
            terms.append(f.diff(self.t))
        return sum_of(terms)

    def many(self, exprs: Iterable[se.Basic], *, accelerations: bool = True) -> tuple[se.Basic, ...]:
        """The derivatives df/dt of each f of ``exprs`` by the chain rule, sharing the work on common subexpressions.

        Sums and products are differentiated term by term and factor by factor (product
        rule), powers with a constant exponent by the power rule, symbols by their rate;
        any other node (sin u, √u is a power, abs u...) goes to ``self`` (grouped form), so
        the result is the same function as ``self(f)``, in a form that keeps the products.

        Parameters
        ----------
        exprs : iterable of SymEngine expressions
            The expressions f.
        accelerations : bool, optional
            False takes the rates' derivatives q̈ as zero.

        Returns
        -------
        tuple of SymEngine expressions
            The derivatives, in order.
        """
        zero, one = _ZERO, se.Integer(1)
        rate: dict[se.Basic, se.Basic] = {self.t: one}
        for q, qd, qdd in zip(self.q, self.qd, self.qdd, strict=True):
            rate[q] = qd
            rate[qd] = qdd if accelerations else zero
        moving = set(rate)
        memo: dict[se.Basic, se.Basic] = {}

        def d(f: se.Basic) -> se.Basic:
            if f.is_Number:
                return zero
            out = memo.get(f)
            if out is not None:
                return out
            if f.is_Symbol:
                out = rate.get(f, zero)
            elif f.is_Add:
                out = sum_of([d(a) for a in f.args])
            elif f.is_Mul:
                args = f.args
                terms = []
                for k, a in enumerate(args):
                    da = d(a)
                    if type(da) is not _ZERO_TYPE:
                        terms.append(se.Mul(*args[:k], *args[k + 1:], da))
                out = sum_of(terms)
            elif f.is_Pow and (f.args[1].is_Number or not (f.args[1].free_symbols & moving)):
                base, exponent = f.args
                db = d(base)
                out = zero if type(db) is _ZERO_TYPE else exponent * base ** (exponent - 1) * db
            else:
                out = self(f, accelerations=accelerations)
            memo[f] = out
            return out

        return tuple(d(f) for f in exprs)


_ZERO = se.Integer(0)
_ZERO_TYPE = type(_ZERO)
