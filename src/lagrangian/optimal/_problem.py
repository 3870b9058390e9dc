"""The statement of an optimal-control problem, as a value: `Problem` and its `Objective`.

An optimal-control problem asks for the inputs u(t) of a model, and the motion they cause, that

    minimize   J = w_T T + ∫_{t0}^{t0+T} [ Σ_i w_i u_i² + L(q, q̇, q̈, u, t) + Σ_j c_j (y_j − r_j(t))² ] dt
                   + Φ(q(t_f), q̇(t_f), t_f)
    subject to M(q, t) q̈ = F(q, q̇, u, t) (+ Aᵀλ, A q̈ + c = 0 with complementary constraints),
               the boundary conditions y(t0) = y0, y(t_f) = y_f on the columns given,
               the bounds low ≤ y ≤ high on any column, the path constraints low ≤ g(q, q̇, q̈, u, t) ≤ high,
               and, for a free final time, T within its bounds.

Columns y are named as in a `Trajectory`: ``x``, ``x_dot``, ``x_ddot``, the inputs (``F``) and the
multipliers (``lambda_<row>``).  Everything written as text (values such as ``"pi"``, expressions
such as ``"x^2 + y^2"``) is read with the model grammar (`lagrangian.model.parse_expression`),
never evaluated.  This module only holds and checks the plain values; `_layout` resolves the names
against the model.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from ..errors import ProblemError

__all__ = ["DEFAULT_NODES", "FREE", "METHODS", "Objective", "Problem", "objective_of"]

#: The transcriptions (`_schemes`), the default first.
METHODS = ("hermite-simpson", "trapezoidal", "backward-euler")
#: ``t_end = FREE``: the duration T is a decision variable.
FREE = "free"
DEFAULT_NODES = 50
#: IPOPT's convergence tolerance (its ``tol``) unless the problem gives one.
DEFAULT_TOLERANCE = 1e-8
HESSIANS = ("exact", "limited-memory")


@dataclass(frozen=True)
class Objective:
    """The objective J = w_T T + ∫ (Σ w_i u_i² + L + Σ c_j (y_j − r_j(t))²) dt + Φ(final state) (module docstring).

    Parameters
    ----------
    effort : float or mapping of str to float
        The weight w_i of ∫ u_i² dt: one number for every input, or input name → weight.
    time : float
        The weight w_T of the duration T (a free final time).
    running : str or SymEngine expression, optional
        L, an expression of t, the coordinates, their rates and accelerations, the inputs and the
        parameters (text in the model grammar, or a SymEngine expression).
    terminal : str or SymEngine expression, optional
        Φ, an expression of the same names at the final time (t is t_f there).
    track : mapping of str to object
        Column name → the reference r_j(t) it should follow: a number, an expression of t (text), a
        pair ``(times, values)`` of arrays (interpolated linearly) or a `Trajectory` (its column of
        the same name).
    track_weights : mapping of str to float
        Column name → c_j (default 1 for each tracked column).
    """

    effort: float | Mapping[str, float] = 0.0
    time: float = 0.0
    running: Any = None
    terminal: Any = None
    track: Mapping[str, Any] = field(default_factory=dict)
    track_weights: Mapping[str, float] = field(default_factory=dict)

    def __post_init__(self) -> None:
        weights = self.effort.values() if isinstance(self.effort, Mapping) else [self.effort]
        for w in [*weights, self.time, *self.track_weights.values()]:
            if not isinstance(w, (int, float)) or isinstance(w, bool) or not math.isfinite(w) or w < 0:
                raise ProblemError(f"An objective weight must be a finite number ≥ 0, not `{w!r}`.",
                                   fix="give weights such as 1 or 0.5 (a negative weight rewards what it weighs)")
        unknown = set(self.track_weights) - set(self.track)
        if unknown:
            name = min(unknown)
            raise ProblemError(f"`{name}` has a tracking weight but no reference to track.", symbol=name,
                               fix=f"give its reference in track = {{ {name} = ... }}, or drop the weight")

    @property
    def empty(self) -> bool:
        """Nothing to minimize: no effort, no time, no running, terminal or tracking term."""
        effort = any(self.effort.values()) if isinstance(self.effort, Mapping) else bool(self.effort)
        return not (effort or self.time or self.running is not None or self.terminal is not None or self.track)


#: The objectives a word names.
_NAMED = {"effort": Objective(effort=1.0), "time": Objective(time=1.0)}
_KEYS = ("effort", "time", "running", "terminal", "track", "track_weights")


def objective_of(value: str | Objective | Mapping[str, Any]) -> Objective:
    """An `Objective` from a word (``"effort"``: ∫ Σ u² dt; ``"time"``: T), a mapping of its fields, or itself."""
    if isinstance(value, Objective):
        return value
    if isinstance(value, str):
        if value not in _NAMED:
            raise ProblemError(f"Unknown objective `{value}`.",
                               fix="use \"effort\" (∫ Σ u² dt), \"time\" (the duration, with t_end = \"free\"), or "
                                   "a table of effort, time, running, terminal, track")
        return _NAMED[value]
    if isinstance(value, Mapping):
        unknown = [k for k in value if k not in _KEYS]
        if unknown:
            raise ProblemError(f"The objective has no term `{unknown[0]}`.", symbol=str(unknown[0]),
                               fix="its terms are " + ", ".join(_KEYS))
        return Objective(**value)
    raise ProblemError(f"An objective is a word, a table or an Objective, not {type(value).__name__}.",
                       fix="e.g. objective = \"effort\"")


@dataclass(frozen=True)
class Problem:
    """What a user states: the model, the time span, the conditions, the bounds, the objective, the mesh.

    Parameters
    ----------
    model : str or Path or Model or EquationsOfMotion
        A model file path, a `Model` or an `EquationsOfMotion`.
    t_end : float or str
        The final time, or ``"free"`` (then T = t_end − t_start is a decision variable, bounded by
        ``bounds["t_end"]`` and first guessed as ``t_guess``).
    t_start : float
        The initial time t0.
    initial : mapping of str to object
        Column name → its value at t0: a number, or text in the model grammar of the parameters
        (``"pi"``, ``"l/2"``).  A column not named is free there.
    final : mapping of str to object
        Column name → its value at the final time, likewise.
    bounds : mapping of str to (low, high)
        Column name (or ``"t_end"``) → ``(low, high)``; None or ±inf for no bound.
    objective : Objective or str or mapping
        An `Objective`, ``"effort"``, ``"time"`` or a mapping of `Objective`'s fields.
    nodes : int
        N, the number of mesh nodes (N − 1 intervals of equal length), at least 2.
    method : str
        One of `METHODS`.
    path : sequence of str or mapping
        Path constraints, each ``"expr <= high"``, ``"low <= expr <= high"``, ``"expr >= low"`` or
        ``"expr == value"`` (text), or a mapping expression → (low, high).
    parameters : mapping of str to float
        Overrides of the model's parameter values.
    tolerance : float
        IPOPT's ``tol``.
    max_iterations : int
        IPOPT's ``max_iter``.
    hessian : str
        IPOPT's Hessian: ``"exact"``, CasADi's exact second derivatives, or ``"limited-memory"``, a
        quasi-Newton one.
    t_guess : float, optional
        The first guess of T when it is free.
    guess : str
        Where IPOPT starts, ``"interpolate"`` or ``"simulate"`` (`lagrangian.optimize` also takes a
        `Trajectory` or a mapping).
    source : str, optional
        The problem file this came from (messages name it), or None.
    """

    model: Any
    t_end: float | str
    t_start: float = 0.0
    initial: Mapping[str, Any] = field(default_factory=dict)
    final: Mapping[str, Any] = field(default_factory=dict)
    bounds: Mapping[str, Sequence[Any]] = field(default_factory=dict)
    objective: Any = "effort"
    nodes: int = DEFAULT_NODES
    method: str = METHODS[0]
    path: Sequence[str] | Mapping[str, Sequence[Any]] = ()
    parameters: Mapping[str, float] = field(default_factory=dict)
    tolerance: float = DEFAULT_TOLERANCE
    max_iterations: int = 3000
    hessian: str = "exact"
    t_guess: float | None = None
    guess: str = "interpolate"
    source: str | None = None

    def __post_init__(self) -> None:
        where: dict[str, Any] = {"file": self.source} if self.source else {}
        if isinstance(self.model, (str, Path)) and not str(self.model):
            raise ProblemError("The problem names no model.", fix="give the model file", **where)
        if isinstance(self.nodes, bool) or not isinstance(self.nodes, int) or self.nodes < 2:
            raise ProblemError(f"nodes = {self.nodes!r}: a mesh needs at least 2 nodes (one interval).",
                               fix="give nodes = N with N ≥ 2 (e.g. 50; more nodes, a finer motion)", **where)
        if self.method not in METHODS:
            raise ProblemError(f"Unknown method `{self.method}`.", symbol=str(self.method),
                               fix="use " + ", ".join(METHODS) + " (the first is the default: fourth order)",
                               **where)
        if self.hessian not in HESSIANS:
            raise ProblemError(f"Unknown Hessian `{self.hessian}`.", fix="use " + " or ".join(HESSIANS), **where)
        _finite("t_start", self.t_start, where)
        if self.t_end != FREE:
            _finite("t_end", self.t_end, where)
            if float(self.t_end) <= float(self.t_start):
                raise ProblemError(f"t_end = {self.t_end} is not after t_start = {self.t_start}.",
                                   fix="give a final time after the initial one, or t_end = \"free\"", **where)
        if self.t_guess is not None:
            _finite("t_guess", self.t_guess, where)
            if self.t_guess <= 0:
                raise ProblemError(f"t_guess = {self.t_guess} is not a positive duration.", fix="give T > 0",
                                   **where)
        if not (isinstance(self.tolerance, (int, float)) and 0 < self.tolerance < 1):
            raise ProblemError(f"tolerance = {self.tolerance!r} must be a number between 0 and 1.",
                               fix="e.g. 1e-8 (IPOPT's tol)", **where)
        if isinstance(self.max_iterations, bool) or not isinstance(self.max_iterations, int) \
                or self.max_iterations < 1:
            raise ProblemError(f"max_iterations = {self.max_iterations!r} must be a positive whole number.",
                               fix="e.g. 3000", **where)
        for name in ("initial", "final", "bounds", "parameters"):
            if not isinstance(getattr(self, name), Mapping):
                raise ProblemError(f"`{name}` must map names to values, not {type(getattr(self, name)).__name__}.",
                                   fix=f"e.g. {name}={{\"theta\": 0}}" if name != "bounds" else
                                   "e.g. bounds={\"F\": (-20, 20)}", **where)
        for name, pair in self.bounds.items():
            if isinstance(pair, (str, bytes)) or not isinstance(pair, Sequence) or len(pair) != 2:
                raise ProblemError(f"The bounds of `{name}` must be a pair (low, high), not `{pair!r}`.",
                                   symbol=str(name), fix=f"write {name} = [low, high] (None or ±inf: no bound)",
                                   **where)
        objective_of(self.objective)  # checked now, resolved against the model later

    @property
    def free_time(self) -> bool:
        return self.t_end == FREE


def _finite(name: str, value: Any, where: Mapping[str, Any]) -> None:
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
        raise ProblemError(f"{name} = {value!r} is not a finite number.", fix=f"give {name} as a number",
                           symbol=name, **where)
