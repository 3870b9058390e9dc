"""The nonlinear program of a `Problem`: decision variables, constraints, objective and their bounds.

The decision variables are the columns z_j of every collocation point (`_layout`), side by side in
a matrix Z of shape (width, P), and the duration T when it is free:  w = (vec Z, T).  The
constraints are

* the implicit dynamics at every point, ``dynamics.map(P)(Z, t)`` (`_dynamics`): one CasADi
  function of a single point mapped over all of them, so that CasADi differentiates one small
  graph and evaluates it P times (exact, sparse Jacobian and Hessian of the Lagrangian);
* the scheme's defects between points (`_schemes`), with h = T/(N − 1);
* the path constraints at every point, mapped the same way;
* for complementary constraints, their position and velocity levels at the first point, unless the
  initial conditions fix every coordinate and rate (they are then checked instead);
* the boundary conditions and the bounds, as bounds on the entries of w (IPOPT takes a variable
  whose bounds are equal as fixed).

The objective is T Σ_j w_j L(z_j, t_j) + w_T T + Φ(z_{P−1}, t_f), w_j the scheme's quadrature.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np
import symengine as se

from ..dynamics import EquationsOfMotion
from ..errors import ProblemError
from ..numerics import Trajectory
from ._casadi import casadi, casadi_expressions
from ._dynamics import PointFunctions, point_functions
from ._layout import (
    T_END,
    Layout,
    at,
    layout_of,
    parameter_values,
    resolve_bound,
    resolve_expression,
    resolve_path,
    resolve_value,
)
from ._problem import Objective, Problem, objective_of
from ._schemes import Scheme, scheme

__all__ = ["Transcription", "transcribe"]

#: Lower bound of a free duration when none is given: T must stay positive.
MIN_DURATION = 1e-6
#: Largest residual (relative to the state's size) of the complementary constraints at a fully given
#: initial state: values typed with 8 or more significant digits (`l*sin(1)`, 0.4207355) pass.
CONSISTENT = 1e-8


@dataclass
class Transcription:
    """The NLP of a problem (module docstring) and how to read its variables.

    Attributes
    ----------
    problem, eom, layout, scheme : what it was made from.
    values : the parameter values used (inputs excluded).
    N, tau : the number of nodes, and the collocation points τ_j in [0, 1] (t_j = t0 + τ_j T).
    nlp : ``{"x", "f", "g"}`` for `casadi.nlpsol`.
    lbx, ubx, lbg, ubg : the bounds.
    functions : the point functions (for the result's energies).
    fixed_start : the complementary constraints' levels were checked at t0 rather than imposed.
    """

    problem: Problem
    eom: EquationsOfMotion
    layout: Layout
    scheme: Scheme
    values: dict[str, float]
    N: int
    tau: np.ndarray
    nlp: dict[str, Any]
    lbx: np.ndarray
    ubx: np.ndarray
    lbg: np.ndarray
    ubg: np.ndarray
    functions: PointFunctions
    t0: float

    @property
    def P(self) -> int:
        return len(self.tau)

    @property
    def free_time(self) -> bool:
        return self.problem.free_time

    def unpack(self, w: np.ndarray) -> tuple[np.ndarray, float]:
        """(Z of shape (width, P), T) from the vector of decision variables."""
        w = np.asarray(w, dtype=float).ravel()
        W, P = self.layout.width, self.P
        Z = w[: W * P].reshape(P, W).T
        T = float(w[-1]) if self.free_time else float(self.problem.t_end) - self.t0
        return Z, T

    def pack(self, Z: np.ndarray, T: float) -> np.ndarray:
        w = np.asarray(Z, dtype=float).T.ravel()
        return np.append(w, T) if self.free_time else w


def transcribe(problem: Problem, eom: EquationsOfMotion) -> Transcription:
    """The `Transcription` of ``problem`` for the equations ``eom``.

    Raises
    ------
    ProblemError
        An unknown name, reversed bounds, a boundary value outside its bounds, a reference that
        cannot be sampled, an expression that cannot be read.
    """
    ca = casadi()
    layout = layout_of(eom)
    values = parameter_values(eom, problem.parameters)
    method = scheme(problem.method)
    N = problem.nodes
    tau = method.points(N)
    P, W = len(tau), layout.width
    t0 = float(problem.t_start)
    functions = point_functions(eom, layout, values)
    objective = objective_of(problem.objective)

    Z = ca.MX.sym("Z", W, P)
    T = ca.MX.sym("T") if problem.free_time else float(problem.t_end) - t0
    t = t0 + ca.DM(tau).T * T  # 1 × P
    h = T / (N - 1)
    q, qd, qdd = Z[layout.slice("q"), :], Z[layout.slice("qd"), :], Z[layout.slice("qdd"), :]
    blocks: list[tuple[Any, Any, Any]] = [(functions.dynamics.map(P)(Z, t), 0.0, 0.0),
                                          (method.defects(ca, ca.vertcat(q, qd), ca.vertcat(qd, qdd), h), 0.0, 0.0)]

    path = resolve_path(problem.path, layout, values)
    if path:
        g = casadi_expressions([g for g, *_ in path], functions.symbols)
        fn = ca.Function("path", [functions.z, functions.t], [ca.vertcat(*g)])
        low = np.repeat([[lo] for _, lo, _, _ in path], P, axis=1)
        high = np.repeat([[hi] for _, _, hi, _ in path], P, axis=1)
        blocks.append((fn.map(P)(Z, t), low, high))

    lbx, ubx = _box(problem, layout, values, P)
    if functions.manifold is not None:
        blocks += _manifold_at_start(ca, problem, layout, functions, lbx, t0, Z, t)

    cost = _objective(ca, objective, problem, layout, functions, method, N, tau, t0, Z, t, T)
    g = ca.vertcat(*(ca.vec(b) for b, _, _ in blocks))
    lbg = np.concatenate([np.broadcast_to(lo, b.shape).ravel(order="F") for b, lo, _ in blocks])
    ubg = np.concatenate([np.broadcast_to(hi, b.shape).ravel(order="F") for b, _, hi in blocks])
    w = ca.vec(Z)
    if problem.free_time:
        w = ca.vertcat(w, T)
        t_low = resolve_bound(problem.bounds.get(T_END, (None, None))[0], layout, values, "the bound of t_end",
                              MIN_DURATION)
        t_high = resolve_bound(problem.bounds.get(T_END, (None, None))[1], layout, values, "the bound of t_end",
                               math.inf)
        if t_low > t_high:
            raise ProblemError(f"The bounds of `t_end` are reversed: {t_low:g} > {t_high:g}.", symbol=T_END,
                               fix="give them as [low, high]")
        lbx, ubx = np.append(lbx, max(t_low, MIN_DURATION)), np.append(ubx, t_high)
    elif T_END in problem.bounds:
        raise ProblemError("`t_end` has bounds, but the final time is fixed.", symbol=T_END,
                           fix="write t_end = \"free\" to let the duration be chosen, or drop its bounds")
    return Transcription(problem, eom, layout, method, values, N, tau, {"x": w, "f": cost, "g": g},
                         lbx, ubx, lbg, ubg, functions, t0)


def _manifold_at_start(ca: Any, problem: Problem, layout: Layout, functions: PointFunctions, lbx: np.ndarray,
                       t0: float, Z: Any, t: Any) -> list[tuple[Any, float, float]]:
    """The complementary constraints' position and velocity levels where the motion starts.

    Imposed on the first point, unless the initial conditions fix every coordinate and rate: those
    are then checked to lie on the constraints (imposing both would repeat equations, which IPOPT
    cannot tell from a contradiction).  Final conditions on every coordinate and rate are refused:
    the motion reaches them only to the scheme's order, so they would over-determine it.
    """
    manifold = functions.manifold
    if manifold is None:  # no complementary constraint: nothing to impose
        return []
    state = layout.names[: 2 * layout.n]
    if all(name in problem.final for name in state):
        raise ProblemError("The final conditions fix every coordinate and rate of a model with complementary "
                           "constraints, which the constraints already tie together.",
                           fix="give the final values of the independent coordinates and rates only")
    if not all(name in problem.initial for name in state):
        return [(manifold(Z[:, 0], t[0]), 0.0, 0.0)]
    z0 = np.where(np.isfinite(lbx[: layout.width]), lbx[: layout.width], 0.0)
    residual = np.asarray(manifold(z0, t0)).ravel()
    scale = max(1.0, float(np.max(np.abs(z0[: 2 * layout.n]))))
    if np.max(np.abs(residual), initial=0.0) > CONSISTENT * scale:
        raise ProblemError("The initial conditions break the complementary constraints (largest residual "
                           f"{np.max(np.abs(residual)):.2e}).",
                           fix="give initial values on the constraints, or give the independent coordinates "
                               "and rates only (the others then follow)")
    return []


def _box(problem: Problem, layout: Layout, values: Mapping[str, float], P: int) -> tuple[np.ndarray, np.ndarray]:
    """The bounds of Z (flattened column by column): the problem's bounds, then the boundary conditions."""
    W = layout.width
    low, high = np.full(W, -math.inf), np.full(W, math.inf)
    for name, (lo, hi) in problem.bounds.items():
        if name == T_END:
            continue
        with at("bounds", name):
            k = layout.index(name, "`bounds`")
            low[k] = resolve_bound(lo, layout, values, f"the low bound of `{name}`", -math.inf)
            high[k] = resolve_bound(hi, layout, values, f"the high bound of `{name}`", math.inf)
            if low[k] > high[k]:
                raise ProblemError(f"The bounds of `{name}` are reversed: low {low[k]:g} > high {high[k]:g}.",
                                   fix=f"write {name} = [{high[k]:g}, {low[k]:g}]")
    lbx, ubx = np.tile(low, (P, 1)).T.copy(), np.tile(high, (P, 1)).T.copy()
    for what, conditions, column in (("initial", problem.initial, 0), ("final", problem.final, P - 1)):
        for name, value in conditions.items():
            with at(what, name):
                k = layout.index(name, f"`{what}`")
                v = resolve_value(value, layout, values, f"the {what} value of `{name}`")
                if not low[k] <= v <= high[k]:
                    raise ProblemError(f"The {what} value {name} = {v:g} is outside its bounds "
                                       f"[{low[k]:g}, {high[k]:g}]: no motion can meet both.",
                                       fix=f"widen the bounds of `{name}` or change its {what} value")
            lbx[k, column] = ubx[k, column] = v
    return lbx.T.ravel(), ubx.T.ravel()


def _objective(ca: Any, objective: Objective, problem: Problem, layout: Layout, functions: PointFunctions,
               method: Scheme, N: int, tau: np.ndarray, t0: float, Z: Any, t: Any, T: Any) -> Any:
    """J = T Σ_j w_j L(z_j, t_j, r_j) + w_T T + Φ(z_last, t_f) (module docstring)."""
    if objective.time and not problem.free_time:
        raise ProblemError("The objective weighs the duration, but the final time is fixed.",
                           fix="write t_end = \"free\" (with bounds = { t_end = [low, high] }), or drop the time term")
    z, ts = functions.z, functions.t
    terms: list[Any] = []
    effort = objective.effort
    if isinstance(effort, Mapping):
        for name in effort:
            if name not in layout.inputs:
                raise ProblemError(f"The effort weighs `{name}`, which is not an input.", symbol=str(name),
                                   fix="the inputs are " + ", ".join(layout.inputs))
        weights = [float(effort.get(name, 0.0)) for name in layout.inputs]
    else:
        weights = [float(effort)] * len(layout.inputs)
    quadrature = ca.DM(method.weights(N))
    cost: Any = 0.0
    if any(weights):
        # Σ_i w_i Σ_j ω_j u_ij² on the input rows of Z directly: the effort alone (the usual objective)
        # needs no mapped function, whose evaluation would cost more than the sum
        U = Z[layout.slice("u"), :]
        cost = T * ca.dot(ca.DM(weights), ca.mtimes(U * U, quadrature))
    exprs = []
    if objective.running is not None:
        exprs.append(resolve_expression(objective.running, layout, "the running cost"))
    sampled: list[np.ndarray] = []
    r = ca.SX.sym("r", sum(1 for ref in objective.track.values() if not _is_expression(ref)))
    for name, ref in objective.track.items():
        k = layout.index(name, "`track`")
        weight = float(objective.track_weights.get(name, 1.0))
        if _is_expression(ref):
            target = resolve_expression(ref, layout, f"the reference of `{name}`")
            exprs.append(se.RealDouble(weight) * (layout.symbols[k] - target) ** 2)
        else:
            if problem.free_time:
                raise ProblemError(f"The reference of `{name}` is sampled in time, and the final time is free.",
                                   symbol=str(name), fix="give the reference as an expression of t, or fix t_end")
            terms.append(weight * (z[k] - r[len(sampled)]) ** 2)
            sampled.append(_sample(ref, name, t0 + tau * float(T)))
    terms += casadi_expressions(exprs, functions.symbols) if exprs else []
    if terms:  # the other running terms: one function of a point, mapped
        running = ca.Function("running", [z, ts, r], [sum(terms[1:], terms[0])])
        R = np.vstack(sampled) if sampled else np.zeros((0, len(tau)))
        cost = cost + T * ca.mtimes(running.map(len(tau))(Z, t, R), quadrature)
    if objective.time:
        cost = cost + objective.time * T
    if objective.terminal is not None:
        phi = casadi_expressions([resolve_expression(objective.terminal, layout, "the terminal cost")],
                                 functions.symbols)[0]
        cost = cost + ca.Function("terminal", [z, ts], [phi])(Z[:, -1], t[-1])
    return cost


def _is_expression(ref: Any) -> bool:
    return isinstance(ref, (str, se.Basic, int, float)) and not isinstance(ref, bool)


def _sample(ref: Any, name: str, times: np.ndarray) -> np.ndarray:
    """A sampled reference (``(times, values)`` or a `Trajectory`) at the collocation times, linearly."""
    if isinstance(ref, Trajectory):
        tr, values = np.asarray(ref.t, dtype=float), np.asarray(ref.column(name), dtype=float)
    else:
        try:
            tr, values = (np.asarray(a, dtype=float).ravel() for a in ref)
        except (TypeError, ValueError):
            raise ProblemError(f"The reference of `{name}` is neither an expression, a pair (times, values) nor a "
                               "Trajectory.", symbol=str(name), fix="e.g. track = {\"x\": (t, x_ref)}") from None
    if len(tr) != len(values) or len(tr) < 2 or np.any(np.diff(tr) <= 0) or not np.all(np.isfinite(values)):
        raise ProblemError(f"The reference of `{name}` needs at least two increasing times and as many finite "
                           "values.", symbol=str(name), fix="check the arrays of the reference")
    return np.interp(times, tr, values)
