"""What `simulate` does differently when inputs vary: which compiled system, the breakpoints, the columns.

* `system_for` picks the compiled system of a run: the one given when its law has the same
  structure (only numbers differ: a copy with the new law shares its library), else a new one;
  the first integrals monitored follow the inputs' regime (`first_integrals`' ``inputs``), so an
  input held at a value other than 0 by ``parameters=`` gets the integrals of a constant input.
* `solve_in_segments` runs SciPy's ``solve_ivp`` from breakpoint to breakpoint of the inputs'
  tables, as the compiled integrators do in C (`codegen/runtime/integrators.c`, ``lg_run``), with the tables
  reading the piece of the current interval (the hint).
* `input_columns` gives the applied inputs along the output grid, for the `Trajectory`.
* `InputsAt` computes the law in Python for the constrained (DAE) path, which steps in Python.
"""

from __future__ import annotations

import copy
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from itertools import pairwise

import numpy as np

from ..dynamics import EquationsOfMotion
from ..errors import SimulationError
from ..model.spec import Model
from ._inputs import InputLaw, resolve_inputs
from ._system import CompiledSystem

__all__ = [
    "InputsAt",
    "arm_callback",
    "check_callback",
    "constant_inputs_only",
    "input_columns",
    "rowwise",
    "solve_in_segments",
    "system_for",
]


def _constant_inputs(eom, law: InputLaw, parameters: Mapping[str, float] | None) -> tuple[str, ...]:
    driven = {s.name for s in law.driven}
    return tuple(u for u in eom.model.inputs if u not in driven and (parameters or {}).get(u))


def system_for(source, eom, events: Sequence[tuple[str, object]], backend: str, inputs,
               parameters: Mapping[str, float] | None) -> CompiledSystem:
    """The compiled system of a run with ``inputs`` (None: the model's ``[controls]``) and ``parameters``."""
    law = source.law if isinstance(source, CompiledSystem) and inputs is None else resolve_inputs(eom, inputs)
    constant = _constant_inputs(eom, law, parameters)
    if isinstance(source, CompiledSystem) and not events:
        regime = law.regime({**law.constants, **dict.fromkeys(constant, 1.0)}, tuple(eom.model.inputs))
        if regime == source.regime and law.structure() == source.law.structure():
            if law is source.law:
                return source
            twin = copy.copy(source)  # the same library: only the law's numbers differ
            twin.law = law
            if twin._lib is None:  # the SymEngine fallback computes the law in Python: this law, its own hint
                twin._law_python = law.evaluator(eom, twin.parameters) if law.driven else None
                twin._hint = np.full(1, np.nan)
            return twin
    return CompiledSystem(eom, events=events, backend=backend, inputs=law, constant_inputs=constant)


def check_callback(system: CompiledSystem) -> None:
    """Raise the error of a Python input function that failed during the run (the C side stopped)."""
    callback = system.law._callback
    if callback is not None and callback.error is not None:
        error, callback.error = callback.error, None
        raise error


def arm_callback(system: CompiledSystem, ctl: np.ndarray | None) -> None:
    """Before a run: a failing Python input function asks the compiled loop to stop (ctl's stop request)."""
    callback = system.law._callback
    if callback is not None:
        callback.error = None
        callback.stop = None if ctl is None else ctl[13:14]


def input_columns(system: CompiledSystem, t: np.ndarray, Y: np.ndarray, p: np.ndarray) -> dict[str, np.ndarray]:
    """The applied inputs at the output times: the driven ones from the law, the constant ones as given."""
    out: dict[str, np.ndarray] = {}
    if len(t) and system.inputs:
        values = system.input_values(t, Y, p)
        check_callback(system)
        out = {name: values[:, k].copy() for k, name in enumerate(system.inputs)}
    for name, value in system.law.constants.items():
        out[name] = np.full(len(t), value)
    order = [u for u in system.eom.model.inputs if u in out]
    return {name: out[name] for name in order}


@dataclass
class SegmentedSolution:
    """What `solve_in_segments` returns: the fields of ``solve_ivp``'s result that `simulate` reads."""

    t: np.ndarray
    y: np.ndarray
    t_events: list = field(default_factory=list)
    y_events: list = field(default_factory=list)
    nfev: int = 0
    status: int = 0
    message: str = ""


def solve_in_segments(solve: Callable, t_start: float, t_end: float, t_out: np.ndarray, y0: np.ndarray,
                      breakpoints: np.ndarray, hint: np.ndarray | None, n_events: int):
    """``solve(a, b, y, t_eval)`` (SciPy's ``solve_ivp`` on [a, b]) from breakpoint to breakpoint.

    ``hint`` is the law's hint (a view into p), set to the middle of each interval and back to
    NaN at the end.  Without breakpoints inside the span this is one call.
    """
    inside = [float(b) for b in breakpoints if t_start < b < t_end]
    if not inside:
        return solve(t_start, t_end, y0, t_out)
    edges = [float(t_start), *inside, float(t_end)]
    times, states = [], []
    t_events: list[list] = [[] for _ in range(n_events)]
    y_events: list[list] = [[] for _ in range(n_events)]
    nfev, status, message, y = 0, 0, "", np.asarray(y0, dtype=float)
    try:
        for k, (a, b) in enumerate(pairwise(edges)):
            keep = (t_out <= b) & ((t_out > a) if k else (t_out >= a))
            grid = t_out[keep]
            wanted = np.append(grid, b) if not len(grid) or grid[-1] < b else grid
            if hint is not None:
                hint[0] = 0.5 * (a + b)
            sol = solve(a, b, y, wanted)
            nfev += int(sol.nfev)
            message = sol.message
            got = len(sol.t) if len(grid) == len(wanted) else min(len(sol.t), len(grid))
            times.append(sol.t[:got])
            states.append(sol.y[:, :got])
            for j in range(n_events):
                t_events[j].extend(sol.t_events[j] if sol.t_events is not None else [])
                y_events[j].extend(sol.y_events[j] if sol.y_events is not None else [])
            status = sol.status
            if sol.status != 0:
                break
            y = sol.y[:, -1]
    finally:
        if hint is not None:
            hint[0] = np.nan
    return SegmentedSolution(np.concatenate(times), np.concatenate(states, axis=1),
                             [np.array(v) for v in t_events], [np.array(v) for v in y_events], nfev, status,
                             message)


#: The paths that run constant inputs only, and the way out each offers.
_CONSTANT_ONLY = {
    "friction": ("exact Coulomb friction (stick and slip by events)",
                 "give the inputs constant values, or a regularized friction (regularization > 0)"),
    "free": ("the free bodies' quaternion route",
             "give the inputs constant values (parameters={'tau': 1.0}, --set tau=1)"),
    "contact": ("the unilateral contacts' route (smooth phases between impacts)",
                "give the inputs constant values (parameters={'F': 1.0}, --set F=1)"),
}


def _refuse_varying(what: str, route: str = "friction") -> None:
    path, fix = _CONSTANT_ONLY[route]
    raise SimulationError(f"The input {what} varies, and {path} runs with constant inputs only.", fix=fix)


def constant_inputs_only(source, inputs, parameters, route: str = "friction"):
    """The parameters of a path that runs constant inputs only (``route``: exact friction's stick/slip
    phases, or free bodies): the inputs' numbers join them; an input that varies (or a ``[controls]``
    law) is refused."""
    model = source if isinstance(source, Model) else getattr(getattr(source, "eom", source), "model", None)
    if inputs is not None and not isinstance(inputs, Mapping):
        _refuse_varying("a feedback", route)
    given = {**dict(getattr(model, "controls", ()) or ()), **dict(inputs or {})}
    for name, value in given.items():
        if isinstance(value, bool) or not isinstance(value, (int, float, np.integer, np.floating)):
            _refuse_varying(f"`{name}`", route)
    return {**(parameters or {}), **{k: float(v) for k, v in (given or {}).items()}}


class InputsAt:
    """p with the driven inputs written in at (t, y), computed by the law in Python (`InputLaw.evaluator`);
    ``window`` is a time inside the current interval between the tables' breakpoints (None: none)."""

    def __init__(self, law, eom: EquationsOfMotion, parameters: tuple[str, ...], p: np.ndarray) -> None:
        self.law, self.p = law, p
        self.names = tuple(s.name for s in law.driven)
        self.slots = [parameters.index(u) for u in self.names]
        self.evaluate = law.evaluator(eom, parameters) if self.names else None
        self.window: float | None = None

    def __call__(self, t: float, y: np.ndarray) -> np.ndarray:
        if self.evaluate is None:
            return self.p
        pu = self.p.copy()
        pu[self.slots] = self.evaluate(t, y, self.p, self.window)[0]
        return pu

    def columns(self, t: np.ndarray, Y: np.ndarray) -> dict[str, np.ndarray]:
        """The applied inputs at the output times (driven and constant), for the trajectory."""
        out: dict[str, np.ndarray] = {}
        if self.evaluate is not None and len(t):
            values = self.evaluate(t, Y, self.p)
            out = {name: values[:, k].copy() for k, name in enumerate(self.names)}
        out.update({name: np.full(len(t), v) for name, v in self.law.constants.items()})
        return out


def rowwise(fn, t: np.ndarray, Y: np.ndarray, applied: InputsAt | None):
    """``fn(t, Y, p)`` with each row's own p when inputs vary (one call otherwise)."""
    if applied is None or applied.evaluate is None or not len(t):
        return fn(t, Y, applied.p if applied is not None else None)
    rows = [fn(t[k:k + 1], Y[k:k + 1], applied(float(t[k]), Y[k])) for k in range(len(t))]
    if isinstance(rows[0], tuple):
        return tuple(np.concatenate([r[j] for r in rows]) for j in range(len(rows[0])))
    return np.concatenate(rows)
