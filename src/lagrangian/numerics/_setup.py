"""What every route reads before it runs: the initial state, the output grid, the events.

`initial_state` is y(t0) = (q(t0), q̇(t0)) from the model and the overrides; `output_times`
the grid the trajectory is reported on (refused when it would not fit in memory);
`event_expressions` reads the events (text in the model's grammar) as expressions; `momenta`
says which first integrals are momenta ∂T/∂q̇_k, for the drift's scale (`_trajectory`).
"""

from __future__ import annotations

import os
from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import numpy as np
import symengine as se

from ..dynamics import EquationsOfMotion
from ..errors import ModelError, SimulationError
from ..model import ExpressionError, parse_expression

__all__ = ["OUTPUT_MEMORY_CAP", "EventSpec", "event_expressions", "initial_state", "memory_limit", "momenta",
           "output_times"]

#: Largest output the arrays of a run may take (bytes): at most this, or a quarter of the memory.
OUTPUT_MEMORY_CAP = 8 * 2**30



@dataclass(frozen=True)
class EventSpec:
    """An event: the times where ``expression`` g(t, q, q̇) crosses zero.

    ``expression`` is text in the model's grammar (``"theta_dot"``, ``"theta - 0.3"``) or
    a SymEngine expression.  ``direction``: +1 only rising crossings, −1 only falling,
    0 both.  A ``terminal`` event stops the run at its first occurrence.

    Parameters
    ----------
    name : str
        The event's name.
    expression : str or SymEngine expression
        Text in the model's grammar (``"theta_dot"``, ``"theta - 0.3"``) or a SymEngine expression.
    direction : int
        +1 only rising crossings, −1 only falling, 0 both.
    terminal : bool
        A terminal event stops the run at its first occurrence.
    """

    name: str
    expression: str | se.Basic
    direction: int = 0
    terminal: bool = False


def _names(eom: EquationsOfMotion) -> dict[str, se.Basic]:
    names: dict[str, se.Basic] = {"t": eom.t}
    for c, q, qd in zip(eom.model.coordinates, eom.q, eom.qd, strict=True):
        names[c.name] = q
        names[c.name + "_dot"] = qd
    for p in eom.model.parameters:
        names[p.name] = se.Symbol(p.name)
    return names


def event_expressions(eom: EquationsOfMotion, events: Sequence[EventSpec | str]) -> list[EventSpec]:
    specs = []
    names = _names(eom)
    for ev in events:
        spec = EventSpec(ev, ev) if isinstance(ev, str) else ev
        expr = spec.expression
        if isinstance(expr, str):
            try:
                # The frames are known so that `R0.x` reads as the vector it is, refused below as not a
                # scalar, rather than as an "unknown frame R0".
                expr = parse_expression(expr, names, [f.name for f in eom.model.frames])
            except ExpressionError as exc:
                raise ModelError(f"In the event `{spec.name}`: {exc.message}", fix=exc.fix,
                                 symbol=exc.symbol) from None
            if not isinstance(expr, se.Basic) or hasattr(expr, "components"):
                raise ModelError(f"The event `{spec.name}` must be a scalar expression: `{spec.name}` is a vector.",
                                 fix="write a scalar of the coordinates, their rates and t, such as `theta_dot` or "
                                     "`theta - 0.3` (an event is where it crosses zero)")
        if spec.direction not in (-1, 0, 1):
            raise ValueError("EventSpec.direction must be -1, 0 or 1")
        specs.append(EventSpec(spec.name, expr, spec.direction, spec.terminal))
    return specs


def initial_state(eom: EquationsOfMotion, initial: Mapping[str, float] | None = None) -> np.ndarray:
    """The initial state y(t0) = (q(t0), q̇(t0)) from the model's ``initial``/``rate`` values and the overrides.

    Parameters
    ----------
    eom : EquationsOfMotion
        The equations.
    initial : mapping of str to float, optional
        Maps a coordinate name to q_i(t0) and ``<name>_dot`` to q̇_i(t0).

    Returns
    -------
    ndarray of shape (2n,)
        The state y(t0).

    Raises
    ------
    SimulationError
        For an unknown name, a missing value or a value that is not finite.
    """
    initial = dict(initial or {})
    coords = eom.model.coordinates
    known = [c.name for c in coords] + [c.name + "_dot" for c in coords]
    unknown = sorted(set(initial) - set(known))
    if unknown:
        raise SimulationError(f"`{unknown[0]}` is neither a coordinate nor a coordinate's rate.",
                              fix="initial values can be given for " + ", ".join(known))
    y = np.empty(2 * len(coords))
    for i, c in enumerate(coords):
        for k, (key, value, what) in enumerate(((c.name, c.initial, "initial"), (c.name + "_dot", c.rate, "rate"))):
            v = initial.get(key, value)
            if v is None:
                raise SimulationError(
                    f"The coordinate `{c.name}` has no initial {'value' if k == 0 else 'rate'}.",
                    fix=f"give it in the model file (`{c.name} = {{ {what} = ... }}` under [coordinates]) "
                        f"or on the command line (`--set {key}=...`)")
            v = float(v)
            if not np.isfinite(v):
                raise SimulationError(f"The initial value of `{key}` is {v}, not a finite number.",
                                      fix=f"give `{key}` a finite value")
            y[i + k * len(coords)] = v
    return y

def memory_limit() -> float:
    try:
        physical = os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_PHYS_PAGES")
    except (ValueError, OSError, AttributeError):
        physical = 4 * OUTPUT_MEMORY_CAP
    return min(OUTPUT_MEMORY_CAP, physical / 4)


def output_times(t_start: float, t_end: float, n_out: int | None, t_eval, width: int = 16) -> np.ndarray:
    """The output grid; ``width``: numbers stored per output time (to refuse a grid too big for memory)."""
    for name, value in (("start", t_start), ("end", t_end)):
        if not np.isfinite(value):
            raise SimulationError(f"The {name} time {value} is not finite.",
                                  fix=f"give a finite {name} time (e.g. --t-{name} {0 if name == 'start' else 10})")
    if not t_end > t_start:
        raise SimulationError(f"The time span [{t_start}, {t_end}] is not increasing.",
                              fix="give an end time greater than the start time (e.g. --t-end 10)")
    if t_eval is not None:
        t_out = np.ascontiguousarray(t_eval, dtype=float)
        if t_out.ndim != 1 or len(t_out) == 0 or np.any(np.diff(t_out) <= 0) or t_out[0] < t_start \
                or t_out[-1] > t_end:
            raise SimulationError("The output times must be increasing and lie within [t_start, t_end].",
                                  fix="pass a sorted t_eval inside the time span")
        return t_out
    n_out = 1001 if n_out is None else int(n_out)
    if n_out < 2:
        raise SimulationError(f"n_out = {n_out}: at least 2 output times are needed.", fix="use n_out >= 2")
    # The state, q'', the monitors and the columns, each as float64, and a copy of them for the output.
    need = 2 * 8 * n_out * max(int(width), 1)
    limit = memory_limit()
    if need > limit:
        most = int(limit // (2 * 8 * max(int(width), 1)))
        raise SimulationError(f"n_out = {n_out} output times would take about {need / 2**30:.1f} GiB of memory "
                              f"(more than the {limit / 2**30:.1f} GiB allowed).",
                              fix=f"use fewer output times (at most about {most}); the steps are not limited "
                                  f"by n_out, only what is stored")
    return np.linspace(t_start, t_end, n_out)

def momenta(eom: EquationsOfMotion, integrals: Sequence[str]) -> dict[str, int]:
    """Integral name → index of the coordinate whose momentum ∂T/∂q̇_k it is (the others are energy-like)."""
    names = {(c.momentum or f"p_{c.name}"): k for k, c in enumerate(eom.model.coordinates)}
    return {name: names[name] for name in integrals if name in names}
