"""An optimum checked by replay: its inputs run through the compiled integrator, as `simulate` runs any input.

A collocated motion obeys the dynamics only at its collocation points, to the order of its scheme.
Whether the inputs really produce it is found by integrating the equations of motion with those
inputs from the optimum's states: ``simulate(..., inputs={u: InputTable(...)})``, each input the table
of what the scheme stands for between its points (`_schemes.Scheme.input_table`: Hermite–Simpson's
parabola through u_k, u_c, u_{k+1}, the trapezoidal rule's line, backward Euler's u_{k+1} held over
(t_k, t_{k+1}]), integrated by the compiled DOP853 at rtol = atol = 1e-10, which stops and starts again
at every knot of the table (no step straddles a kink of u).  A model with complementary constraints runs
`simulate`'s constrained path (SciPy's DOP853 on the compiled q̈ and λ, projected onto the constraints),
each run from the optimum's state projected onto the constraints first: the collocation holds them at
the acceleration level, so its states leave the manifold by about IPOPT's tolerance, which `simulate`
refuses at a start (above 1e-8) and which is far below the replay's tolerance.

Two measures: the motion replayed from the initial state through the whole span (``final_error``:
where the inputs really lead, open loop), and each interval replayed from the optimum's state at its
first node (``local_error``: the scheme's own error, which an unstable motion — an inverted pendulum
reaching upright — does not amplify).
"""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np

from ..dynamics import EquationsOfMotion
from ..errors import SimulationError
from ..numerics import CompiledSystem, ConstrainedSystem, InputTable, project, simulate
from ._result import REPLAY_TOLERANCE, Replay

__all__ = ["RTOL", "replay_check", "replay_inputs"]

#: The replay's tolerances (relative and absolute).
RTOL = 1e-10


class _Runner:
    """`simulate` of one model under fixed input tables, from any state over any span of the tables.

    The compiled system (the tables' law in its C, no first integral: the replay reads the states only)
    is built once and serves every run; a constrained model's `ConstrainedSystem` likewise.
    """

    def __init__(self, eom: EquationsOfMotion, values: Mapping[str, float], tables: Mapping[str, InputTable]) -> None:
        self.eom = eom
        self.tables = dict(tables)
        self.parameters = {k: v for k, v in values.items() if k not in self.tables}
        if eom.constraints:
            regime = {u: "varying" if u in self.tables else "off" for u in eom.model.inputs}
            self.system: CompiledSystem | ConstrainedSystem = ConstrainedSystem(eom, inputs=regime)
            self.inputs: Mapping[str, InputTable] | None = self.tables
        else:
            self.system = CompiledSystem(eom, integrals=(), inputs=self.tables)
            self.inputs = None  # the system's own law

    def states(self, y0: np.ndarray, t: np.ndarray) -> np.ndarray:
        """(q, q̇) at the times ``t`` of the motion from ``y0`` at ``t[0]``, shape (len(t), 2n)."""
        n = len(self.eom.q)
        if isinstance(self.system, ConstrainedSystem):
            p = self.system.parameter_vector(self.parameters)
            y0 = project(self.system, float(t[0]), np.asarray(y0, dtype=float), p, tol=1e-14)[0]
        initial = {name: float(v) for name, v in zip(self.eom.coordinates, y0[:n], strict=True)}
        initial.update({name + "_dot": float(v) for name, v in zip(self.eom.coordinates, y0[n:], strict=True)})
        # the compiled DOP853, or SciPy's where no C compiler was found (the same method)
        method = "dop853" if getattr(self.system, "backend", "c") == "c" or self.inputs is not None else "DOP853"
        try:
            traj = simulate(self.system, float(t[-1]), t_start=float(t[0]), t_eval=t, initial=initial,
                            parameters=self.parameters, inputs=self.inputs, method=method, rtol=RTOL, atol=RTOL,
                            stiffness_check=False)
        except SimulationError as exc:
            raise SimulationError(f"The replay of the optimized inputs failed: {exc.message}",
                                  fix=exc.fix or "the inputs drive the model somewhere it cannot be integrated"
                                  ) from None
        return np.hstack([traj.q, traj.qd])


def replay_inputs(eom: EquationsOfMotion, values: Mapping[str, float], tables: Mapping[str, InputTable],
                  y0: np.ndarray, t_eval: np.ndarray) -> np.ndarray:
    """The states (q, q̇) at ``t_eval`` of the motion from ``y0`` (at ``t_eval[0]``) under the input
    ``tables`` (the other parameters at ``values``), shape (len(t_eval), 2n).

    Raises
    ------
    SimulationError
        When the integration fails (a singular M, a blow-up): the message says where.
    """
    return _Runner(eom, values, tables).states(np.asarray(y0, dtype=float), np.asarray(t_eval, dtype=float))


def replay_check(eom: EquationsOfMotion, values: Mapping[str, float], tables: Mapping[str, InputTable],
                 t_nodes: np.ndarray, y_nodes: np.ndarray, how: str,
                 tolerance: float = REPLAY_TOLERANCE) -> Replay:
    """`Replay` of an optimum: its input ``tables`` replayed from ``y_nodes[0]`` through all the nodes
    ``t_nodes``, and from each node to the next (the local error, which an unstable motion does not amplify)."""
    runner = _Runner(eom, values, tables)
    t_nodes = np.asarray(t_nodes, dtype=float)
    y = runner.states(y_nodes[0], t_nodes)
    ends = np.empty_like(y_nodes)
    ends[0] = y_nodes[0]
    for k in range(len(t_nodes) - 1):
        ends[k + 1] = runner.states(y_nodes[k], t_nodes[k:k + 2])[-1]
    scale = np.maximum(1.0, np.max(np.abs(y_nodes), axis=1))
    errors = np.max(np.abs(y - y_nodes), axis=1)
    local = np.max(np.abs(ends - y_nodes), axis=1) / scale
    integrator = "DOP853 in C" if isinstance(runner.system, CompiledSystem) and runner.system.backend == "c" else \
        "DOP853 (SciPy)"
    return Replay(t_nodes, y, float(np.max(errors / scale)), float(errors[-1]), float(np.max(local)), tolerance,
                  f"simulate: {integrator}, rtol = atol = {RTOL:.0e}; {how}")
