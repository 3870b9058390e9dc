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

    Attributes
    ----------
    t : the mesh nodes' times; ``y`` the replayed state (q, q̇) there, shape (N, 2n).
    max_error : max over the nodes of ``|y_replayed − y_collocated|∞ / max(1, |y_collocated|∞)``, the whole
        span replayed from the initial state (open loop: an unstable motion amplifies any error).
    final_error : ``|y_replayed(t_f) − y_collocated(t_f)|∞`` (state units): where the inputs really lead.
    local_error : the same measure with each interval replayed from the optimum's state at its first
        node: the scheme's own error, not amplified by an instability.
    tolerance : `REPLAY_TOLERANCE` or the one asked for; ``within`` says whether local_error ≤ tolerance.
    integrator : what ran it (``"simulate: DOP853 in C, rtol = atol = 1e-10"``) and how the inputs were read
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
    """An optimal motion (module docstring).  Beyond `Trajectory`'s fields:

    Attributes
    ----------
    inputs : the input names (each a column).
    objective : J at the optimum.
    success : IPOPT converged (``status == "optimal"``).
    solver_status : IPOPT's return status; ``status`` is ours (``optimal``, ``acceptable``, ``infeasible``,
        ``interrupted``, ``max_iterations``, ``failed``) and ``message`` says what it means.
    iterations : IPOPT's iterations.
    violation : the largest violation of a constraint or a bound (≤ the tolerance at an optimum).
    nodes, t_end, free_time : the mesh (N nodes), the final time (chosen when free).
    node_rows : the indices of the rows that are mesh nodes.
    hessian, solver : the Hessian mode and the IPOPT build.
    seconds : ``{"transcribe", "setup", "solve", "replay"}`` wall times.
    replay : the `Replay`, or None when it was not run (``verify=False``, or no optimum).
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
    #: The raw solution (primal, multipliers) and the layout it belongs to, for a warm start.
    solution: Mapping[str, Any] = field(default_factory=dict, repr=False, compare=False)

    def input(self, name: str) -> np.ndarray:
        """u(t) of the input ``name`` at every row (the same as ``column(name)``)."""
        return self.column(name)

    def input_table(self, name: str) -> InputTable:
        """The input ``name`` between the collocation points as the scheme stands for it, an `InputTable`
        that `simulate` reads (``"quadratic"`` for Hermite–Simpson, ``"linear"`` for trapezoidal, a
        ``"zoh"`` of the right values for backward Euler): what the replay runs.

        >>> # simulate(eom, 6.0, initial=..., inputs={"F": Switch(best.input_table("F"), feedback, at=2.0)})
        """
        if name not in self.inputs:
            raise KeyError(f"`{name}` is not an input of this optimum (its inputs: {', '.join(self.inputs)})")
        return scheme(self.method).input_table(self.t, self.column(name))

    def summary(self) -> str:
        """A few lines: status, objective, iterations, violation, replay."""
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
