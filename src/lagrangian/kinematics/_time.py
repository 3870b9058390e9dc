"""The total time derivative d/dt along a motion q(t).

For any f(q, q̇, t):  df/dt = Σ_i (∂f/∂q_i q̇_i + ∂f/∂q̇_i q̈_i) + ∂f/∂t.
q, q̇ and q̈ are plain symbols (``theta``, ``theta_dot``, ``theta_ddot``), which is
much lighter than SymPy's functions of time and gives the same results.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import symengine as se

__all__ = ["TimeDerivative"]


@dataclass(frozen=True, slots=True)
class TimeDerivative:
    """d/dt for expressions in q, q̇ (and q̈ when ``accelerations`` is set) and t."""

    q: tuple[se.Symbol, ...]
    qd: tuple[se.Symbol, ...]
    qdd: tuple[se.Symbol, ...]
    t: se.Symbol

    @classmethod
    def of(cls, q: Sequence[se.Symbol], qd: Sequence[se.Symbol], qdd: Sequence[se.Symbol], t: se.Symbol) -> TimeDerivative:
        return cls(tuple(q), tuple(qd), tuple(qdd), t)

    def __call__(self, f: se.Basic, *, accelerations: bool = True) -> se.Basic:
        """df/dt; with ``accelerations=False``, the part of it without q̈ (used for M q̈ = F)."""
        free = f.free_symbols
        if not free:
            return se.Integer(0)
        terms = []
        for q, qd, qdd in zip(self.q, self.qd, self.qdd):
            if q in free:
                terms.append(f.diff(q) * qd)
            if accelerations and qd in free:
                terms.append(f.diff(qd) * qdd)
        if self.t in free:
            terms.append(f.diff(self.t))
        return se.Add(*terms) if terms else se.Integer(0)
