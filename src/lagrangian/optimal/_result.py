"""The result of an optimization: an optimal motion as a `Trajectory`, with how it was found and checked.

`OptimalTrajectory` is a `Trajectory` whose rows are the collocation points (the mesh nodes, and the
midpoints for Hermite–Simpson; ``node_rows`` says which rows are nodes): q, q̇, q̈ as always, the
inputs and the multipliers as further columns (``result.column("F")``, ``"lambda_<row>"``), and T,
U as monitors.  So it is saved, plotted and animated like a simulated motion.  Beside it: the
objective, the solver's status and iterations, and the `Replay` — the optimized inputs run through
an accurate integrator, and how far that motion ends from the collocated one.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ..numerics import InputTable, Trajectory
from ._schemes import scheme

__all__ = ["REPLAY_TOLERANCE", "OptimalTrajectory", "Replay"]

#: The largest replay error (state units, max-norm, relative to max(1, |x|)) of a verified optimum: for
#: every motion its local error (one interval from the optimum's state), and for a stable motion its
#: whole replay.  Hermite–Simpson's cart-pole swing-up at N = 100 replays to about 1e-4 end to end;
#: backward Euler's to 7.9 (the rod does not end upright): its optimum is not the motion its inputs make.
REPLAY_TOLERANCE = 1e-3


@dataclass(frozen=True)
class Replay:
    """The optimized inputs replayed through an integrator, from the optimum's initial state.

    Parameters
    ----------
    t : ndarray of shape (N,)
        The mesh nodes' times.
    y : ndarray of shape (N, 2n)
        The replayed state (q, q̇) there.
    max_error : float
        Max over the nodes of ``|y_replayed − y_collocated|∞ / max(1, |y_collocated|∞)``, the whole
        span replayed from the initial state (open loop: an unstable motion amplifies any error).
    final_error : float
        ``|y_replayed(t_f) − y_collocated(t_f)|∞`` (state units): where the inputs really lead.
    local_error : float
        The same measure with each interval replayed from the optimum's state at its first node: the
        scheme's own error, not amplified by an instability.
    tolerance : float
        `REPLAY_TOLERANCE` or the one asked for; ``within`` says whether local_error ≤ tolerance.
    integrator : str
        What ran it (``"simulate: DOP853 in C, rtol = atol = 1e-10"``) and how the inputs were read
        between the points (the scheme's `InputTable` kind).
    """

    t: np.ndarray
    y: np.ndarray
    max_error: float
    final_error: float
    local_error: float
    tolerance: float
    integrator: str

    @property
    def within(self) -> bool:
        return self.local_error <= self.tolerance

    @property
    def amplified(self) -> bool:
        """The whole replay departs far more than each interval does: the motion is unstable (open loop)."""
        return self.within and self.max_error > self.tolerance

    def summary(self) -> str:
        verdict = "within" if self.within else "ABOVE"
        text = (f"replay ({self.integrator}): local error {self.local_error:.1e} ({verdict} the tolerance "
                f"{self.tolerance:.0e}); from t0 through the whole span: largest error {self.max_error:.1e}, "
                f"final state {self.final_error:.1e}")
        if self.amplified:
            text += " — the motion is unstable: open loop, the small local errors grow (a feedback holds it)"
        return text


@dataclass(frozen=True)
class OptimalTrajectory(Trajectory):
    """An optimal motion (module docstring): a `Trajectory` with the optimization's own fields.

    Parameters
    ----------
    model_name, coordinates, parameters, t, q, qd, qdd, monitors, integrals, drift, method, steps, rhs_calls, tolerance, warnings, events, status, conditioning, extra, scales, range_exits, sensitivity_names, quaternion_drift : as in Trajectory
        `Trajectory`'s fields; ``status`` is ours (``optimal``, ``acceptable``, ``infeasible``,
        ``interrupted``, ``max_iterations``, ``failed``).
    inputs : tuple of str
        The input names (each a column).
    objective : float
        J at the optimum.
    success : bool
        IPOPT converged (``status == "optimal"``).
    solver_status : str
        IPOPT's return status.
    message : str
        What ``status`` means.
    iterations : int
        IPOPT's iterations.
    violation : float
        The largest violation of a constraint or a bound (≤ the tolerance at an optimum).
    nodes : int
        The mesh's N nodes.
    t_end : float
        The final time (chosen when free).
    free_time : bool
        Whether the final time was free.
    node_rows : ndarray of int
        The indices of the rows that are mesh nodes.
    hessian : str
        The Hessian mode.
    solver : str
        The IPOPT build.
    seconds : mapping of str to float
        ``{"transcribe", "setup", "solve", "replay"}`` wall times.
    replay : Replay, optional
        The `Replay`, or None when it was not run (``verify=False``, or no optimum).
    solution : mapping of str to object
        The raw solution (primal, multipliers) and the layout it belongs to, for a warm start.
    """

    inputs: tuple[str, ...] = ()
    objective: float = float("nan")
    success: bool = False
    solver_status: str = ""
    message: str = ""
    iterations: int = 0
    violation: float = float("nan")
    nodes: int = 0
    t_end: float = float("nan")
    free_time: bool = False
    node_rows: np.ndarray = field(default_factory=lambda: np.zeros(0, dtype=int))
    hessian: str = "exact"
    solver: str = ""
    seconds: Mapping[str, float] = field(default_factory=dict)
    replay: Replay | None = None
    solution: Mapping[str, Any] = field(default_factory=dict, repr=False, compare=False)

    def input(self, name: str) -> np.ndarray:
        """The input u(t) of the input ``name`` at every row (the same as ``column(name)``).

        Parameters
        ----------
        name : str
            An input.

        Returns
        -------
        ndarray of shape (N,)
            Its values.
        """
        return self.column(name)

    def input_table(self, name: str) -> InputTable:
        """The input ``name`` between the collocation points as the scheme stands for it: what the replay runs.

        An `InputTable` that `simulate` reads (``"quadratic"`` for Hermite–Simpson, ``"linear"`` for
        trapezoidal, a ``"zoh"`` of the right values for backward Euler).

        >>> # simulate(eom, 6.0, initial=..., inputs={"F": Switch(best.input_table("F"), feedback, at=2.0)})

        Parameters
        ----------
        name : str
            An input.

        Returns
        -------
        InputTable
            The table.
        """
        if name not in self.inputs:
            raise KeyError(f"`{name}` is not an input of this optimum (its inputs: {', '.join(self.inputs)})")
        return scheme(self.method).input_table(self.t, self.column(name))

    def summary(self) -> str:
        """A few lines: status, objective, iterations, violation, replay.

        Returns
        -------
        str
            The lines.
        """
        lines = [f"{self.model_name}: {self.method}, {self.nodes} nodes, t from {self.t[0]:g} to {self.t[-1]:g}"
                 + (" (free final time)" if self.free_time else ""),
                 f"status: {self.status} — {self.message}",
                 (f"objective J = {self.objective:.10g}, {self.iterations} IPOPT iterations, constraint violation "
                  f"{self.violation:.1e} ({self.hessian} Hessian, {self.solver})"),
                 "times: " + ", ".join(f"{k} {v * 1e3:.1f} ms" for k, v in self.seconds.items())]
        if self.drift:
            lines.append("constraint drift (max residual): "
                         + ", ".join(f"{name[len('drift_'):]} {value:.1e}" for name, value in self.drift.items()))
        if self.replay is not None:
            lines.append(self.replay.summary())
        lines += [f"warning: {w}" for w in self.warnings if w not in self.message]  # the status said it
        return "\n".join(lines)
