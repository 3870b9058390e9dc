"""An optimum checked by replay: its inputs run through an accurate integrator of the compiled equations.

A collocated motion obeys the dynamics only at its collocation points, to the order of its scheme.
Whether the inputs really produce it is found by integrating the equations of motion with those
inputs — interpolated between the points as the scheme stands for them (`_schemes`) — from the
optimum's initial state, with SciPy's DOP853 at rtol = atol = 1e-10 on the compiled right-hand side
(`CompiledSystem`, or `ConstrainedSystem` with Baumgarte's stabilization for complementary
constraints).  The inputs are parameters of the compiled code (``p``), written at each call.

Two measures: the motion replayed from the initial state through the whole span (``final_error``:
where the inputs really lead, open loop), and each interval replayed from the optimum's state at its
first node (``local_error``: the scheme's own error, which an unstable motion — an inverted pendulum
reaching upright — does not amplify).  Both are computed in one pass, node to node.

`replay_inputs` is the one function that runs inputs through the equations from a state: once
``simulate`` takes time-varying inputs (``simulate(eom, t_end, inputs={"F": InputTable(t, u, "cubic")})``),
its body can become that call.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence

import numpy as np
from scipy.integrate import solve_ivp

from ..dynamics import EquationsOfMotion
from ..errors import SimulationError
from ..numerics import CompiledSystem
from ..numerics._dae import BAUMGARTE, ConstrainedSystem
from ._result import REPLAY_TOLERANCE, Replay

__all__ = ["RTOL", "input_rhs", "replay_check", "replay_inputs"]

#: The replay's tolerances (relative and absolute).
RTOL = 1e-10


def input_rhs(eom: EquationsOfMotion, values: dict[str, float], inputs: Sequence[str],
              u: Callable[[float], np.ndarray]) -> Callable[[float, np.ndarray], np.ndarray]:
    """ẏ = (q̇, q̈)(t, y) of ``eom`` under the inputs ``u(t)`` (the other parameters at ``values``), for SciPy.

    The inputs are parameters of the compiled code: their slots of ``p`` are written at each call.
    """
    constrained = bool(eom.constraints)
    # No first integrals: the replay reads q̈ only, and their search (Noether's) would cost more than it.
    system = ConstrainedSystem(eom) if constrained else CompiledSystem(eom, integrals=())
    base = system.parameter_vector({**values, **dict.fromkeys(inputs, 0.0)})
    slots = [system.parameters.index(name) for name in inputs]
    hoisted = _inputs_hoisted(system, values, inputs, base)
    p = base.copy()

    def parameters(t: float) -> np.ndarray:
        ut = u(t)
        if hoisted:  # the whole vector remade, its parameter-only subexpressions with it
            return system.parameter_vector({**values, **dict(zip(inputs, map(float, ut)))})
        p[slots] = ut
        return p

    if constrained:
        def fun(t: float, y: np.ndarray) -> np.ndarray:
            return system.rhs(t, y, parameters(t), BAUMGARTE)[0]
        return fun
    if system.backend != "c":
        return lambda t, y: system.rhs(t, y, parameters(t))
    out = np.empty(2 * system.n)

    def fun_c(t: float, y: np.ndarray) -> np.ndarray:
        if system.rhs_c(t, np.ascontiguousarray(y), parameters(t), out):
            raise SimulationError(f"The replay met a singular mass matrix at t = {t:.6g}.",
                                  fix="look at the motion there; a coarse mesh may cross a singular configuration")
        return out.copy()
    return fun_c


def _intervals(fun: Callable[[float, np.ndarray], np.ndarray], t_eval: np.ndarray, y0: np.ndarray,
               restarts: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray | None]:
    """Integrate node to node: the motion from ``y0`` at each of ``t_eval`` and, with ``restarts`` (one state
    per node), where each interval's motion from ``restarts[k]`` ends at ``t_eval[k + 1]`` (the two in one run).

    Interval by interval, since the input is smooth inside each (a polynomial) and not across the nodes,
    where one run would have its step rejected at every kink.
    """
    y = np.asarray(y0, dtype=float)
    m = len(y)
    states = np.empty((len(t_eval), m))
    ends = None if restarts is None else np.empty((len(t_eval), m))
    states[0] = y
    both = fun if restarts is None else (lambda t, z: np.concatenate([fun(t, z[:m]), fun(t, z[m:])]))
    for k in range(len(t_eval) - 1):
        z = y if restarts is None else np.concatenate([y, restarts[k]])
        sol = solve_ivp(both, (t_eval[k], t_eval[k + 1]), z, method="DOP853", rtol=RTOL, atol=RTOL)
        if sol.status != 0:
            raise SimulationError(f"The replay of the optimized inputs stopped at t = {sol.t[-1]:.6g}: "
                                  f"{sol.message}", fix="the inputs drive the model somewhere it cannot be integrated")
        y = states[k + 1] = sol.y[:m, -1]
        if ends is not None:
            ends[k + 1] = sol.y[m:, -1]
    if ends is not None:
        ends[0] = restarts[0]
    return states, ends


def replay_inputs(eom: EquationsOfMotion, values: dict[str, float], inputs: Sequence[str],
                  u: Callable[[float], np.ndarray], y0: np.ndarray, t_eval: np.ndarray) -> np.ndarray:
    """The states (q, q̇) at ``t_eval`` of the motion from ``y0`` (at ``t_eval[0]``) under the inputs ``u(t)``,
    shape (len(t_eval), 2n).

    Raises
    ------
    SimulationError
        When the integration fails (a singular M, a blow-up): the message says where.
    """
    return _intervals(input_rhs(eom, values, inputs, u), np.asarray(t_eval, dtype=float), y0)[0]


def _inputs_hoisted(system: CompiledSystem | ConstrainedSystem, values: dict[str, float], inputs: Sequence[str],
                    base: np.ndarray) -> bool:
    """Whether an input enters the parameter-only subexpressions computed once per parameter set
    (`numerics._codegen._Hoist`), which then follow the values in ``p`` and must be remade with it."""
    if len(base) == len(system.parameters):
        return False
    other = system.parameter_vector({**values, **dict.fromkeys(inputs, 0.7390851332151607)})
    return not np.array_equal(other[len(system.parameters):], base[len(system.parameters):])


def replay_check(eom: EquationsOfMotion, values: dict[str, float], inputs: Sequence[str],
                 u: Callable[[float], np.ndarray], t_nodes: np.ndarray, y_nodes: np.ndarray, how: str,
                 tolerance: float = REPLAY_TOLERANCE) -> Replay:
    """`Replay` of an optimum: its inputs ``u`` replayed from ``y_nodes[0]`` through all the nodes ``t_nodes``,
    and from each node to the next (the local error, which an unstable motion does not amplify)."""
    fun = input_rhs(eom, values, inputs, u)
    y, ends = _intervals(fun, np.asarray(t_nodes, dtype=float), y_nodes[0], y_nodes)
    scale = np.maximum(1.0, np.max(np.abs(y_nodes), axis=1))
    errors = np.max(np.abs(y - y_nodes), axis=1)
    local = np.max(np.abs(ends - y_nodes), axis=1) / scale
    return Replay(t_nodes, y, float(np.max(errors / scale)), float(errors[-1]), float(np.max(local)), tolerance,
                  f"DOP853, rtol = atol = {RTOL:.0e}, {how}")
