"""`Switch`: an input that follows one source, then another from a given time on.

A motion planned open loop and then held by feedback — a swing-up replayed from its table, caught
near upright by an LQR gain — is one input with two sources in turn::

    F = Switch(InputTable(t, u, "quadratic"), feedback, at=2.0)
    simulate(cart, 6.0, inputs={"F": F})

With sources s_0, …, s_m and times a_1 < … < a_m, the input is

    u(t) = s_0(t, x) for t < a_1,   s_k(t, x) for a_k ≤ t < a_{k+1},   s_m(t, x) for t ≥ a_m

(right-continuous, as a zero-order hold).  Each source is anything ``inputs=`` takes for one input
— a number, an expression, an `InputTable`, a `Feedback`, a Python function — but not another
`Switch`.  The law is compiled like the others (`_input_code`): every source is evaluated and the
one of the current phase is kept, the times are numbers of the law's block (changing them recompiles
nothing), and they are breakpoints: the integrators stop and start again there, so no step straddles
the jump, and between two restarts the phase is the one of that interval (its hint), even at its
right end.
"""

from __future__ import annotations

import math
from itertools import pairwise
from typing import Any

from ..errors import SimulationError

__all__ = ["Switch"]


class Switch:
    """Sources of one input in turn (module docstring): ``sources[0]`` before ``at[0]``, and so on.

    ``sources[k]`` applies from ``at[k − 1]`` on.

    Parameters
    ----------
    *sources : object
        Two or more sources, each what ``inputs=`` takes for one input (not a `Switch`).
    at : float or sequence of float
        The switching times (one fewer than the sources; a number for two sources), strictly
        increasing and finite.

    Raises
    ------
    SimulationError
        Fewer than two sources, times that are not as many as the switches, not finite or not
        increasing, a `Switch` among the sources.

    Examples
    --------
    >>> F = Switch(0.0, "-3*x - x_dot", at=1.5)   # off, then a feedback from t = 1.5 on
    >>> F.at
    (1.5,)
    """

    __slots__ = ("at", "sources")

    def __init__(self, *sources: Any, at: float | Any) -> None:
        if len(sources) < 2:
            raise SimulationError(f"A Switch needs two sources or more, not {len(sources)}.",
                                  fix="e.g. Switch(table, feedback, at=2.0): the table, then the feedback")
        if any(isinstance(s, Switch) for s in sources):
            raise SimulationError("A Switch cannot be a source of another Switch.",
                                  fix="give all the sources and times to one: Switch(a, b, c, at=(t1, t2))")
        try:
            times = (float(at),) if isinstance(at, (int, float)) else tuple(float(a) for a in at)
        except (TypeError, ValueError):
            raise SimulationError(f"A Switch's times `at` must be numbers, not {at!r}.",
                                  fix="e.g. at=2.0, or at=(1.0, 2.5) for three sources") from None
        if len(times) != len(sources) - 1:
            raise SimulationError(f"A Switch of {len(sources)} sources needs {len(sources) - 1} switching "
                                  f"time{'s' if len(sources) > 2 else ''}, not {len(times)}.",
                                  fix="give one time per change of source: Switch(a, b, c, at=(t1, t2))")
        if not all(math.isfinite(a) for a in times):
            raise SimulationError(f"A Switch's times must be finite: {times}.", fix="give finite switching times")
        if any(b <= a for a, b in pairwise(times)):
            raise SimulationError(f"A Switch's times must increase strictly: {times}.",
                                  fix="list the switching times in the order they happen")
        self.sources = tuple(sources)
        self.at = times

    def __repr__(self) -> str:
        return f"Switch({', '.join(map(repr, self.sources))}, at={self.at if len(self.at) > 1 else self.at[0]!r})"
