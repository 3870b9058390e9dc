"""One smooth phase of a motion with contacts: integrate with a fixed set of closed contacts up to an event.

Between two events the closed contacts act as complementary constraints and the open ones
not at all, so the motion is smooth; it ends where

* an open contact touches: its gap g_k falls through 0 (``"touchdown"``);
* a closed contact would pull: its normal reaction λ_k falls through −ε_k (``"liftoff"``; ε_k is
  1e-12 of the scale of the reactions, so that the round-off of a reaction that is exactly zero —
  two pendulums swinging together — is not a lift-off);
* a sticking contact would slide: μ λ_k − |λ_t,k| falls through −ε_k (``"slip"``);
* or at the end of the span, or at a terminal event of the user's.

A phase in which every contact is open, in a model without bilateral rows, runs in the compiled
DOP853 with the gaps as terminal event functions (`FastPhases`), each event located on the dense
output to a few ulp (`codegen/runtime/integrators.c`).  Any other phase steps SciPy's DOP853 on q̈ solved with the
acting rows (`ContactSystem.solve`), projects every step onto them (positions onto the
closed gaps, velocities onto ġ = 0 and w = 0), and locates its events by Brent's method on the
projected dense output (`dae_phase`), as the DAE route (`_dae_run.run_dae`) does.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ..errors import SimulationError
from ._contact_system import ContactSystem, Probe
from ._control import control_block
from ._system import CompiledSystem

__all__ = ["FastPhases", "Options", "Outputs", "PhaseEnd", "dae_phase"]

#: Rows of the compiled integrator's event buffer per phase (user events beyond are dropped, counted).
EVENT_CAPACITY = 10_000
_STATUS = {1: "the mass matrix M became singular", 2: "the state stopped being finite (overflow)",
           3: "the step size fell below the resolution of t (step size underflow)",
           5: "the maximum number of steps was reached", 8: "the equations are stiff (dop853's stiffness test)"}


@dataclass
class Outputs:
    """The output grid, filled phase after phase: ``Y[i]`` at ``t[i]``, produced by phase ``phase[i]``."""

    t: np.ndarray
    Y: np.ndarray
    phase: np.ndarray
    i: int = 0

    def fill(self, until: float, states: Callable[[np.ndarray], np.ndarray], phase: int) -> None:
        """The output times up to ``until`` (included) not yet filled, from ``states(times)`` (k, 2n)."""
        j = int(np.searchsorted(self.t, until, side="right"))
        if j > self.i:
            self.Y[self.i:j] = states(self.t[self.i:j])
            self.phase[self.i:j] = phase
            self.i = j


@dataclass
class PhaseEnd:
    """How a phase ended: ``reason`` ("end", "touchdown", "liftoff", "slip", "event"), at ``t`` in state ``y``;
    ``contact`` the index of the contact concerned (−1 for none); the user's events met on the way."""

    t: float
    y: np.ndarray
    reason: str
    contact: int = -1
    user_events: list[tuple[str, float, np.ndarray]] = field(default_factory=list)
    steps: int = 0
    rhs_calls: int = 0
    h: float = 0.0


@dataclass(frozen=True)
class Options:
    rtol: float
    atol: float
    max_step: float | None
    max_steps: int
    stiffness_check: bool
    user: Sequence  # EventSpec of the user's events (expressions), in the fast system's order after the gaps


class FastPhases:
    """Phases with every contact open in the compiled DOP853 (module docstring), with buffers kept from one
    phase to the next: a bouncing ball's flight then costs the integration and a few µs of Python.

    ``system`` is `ContactSystem.fast_system` (the m gaps, then the user's events, as event functions).
    """

    def __init__(self, system: CompiledSystem, m: int, p_fast: np.ndarray, t_end: float, out: Outputs,
                 opts: Options) -> None:
        self.system, self.m, self.out, self.opts, self.t_end = system, m, out, opts, float(t_end)
        user = opts.user
        self.template = control_block("dop853", float(out.t[0]), t_end, out.t, opts.rtol, opts.atol, None,
                                      opts.max_step, opts.max_steps, None, opts.stiffness_check)
        self.template[11] = EVENT_CAPACITY
        self.ctl = self.template.copy()
        self.y = np.zeros(2 * system.n)
        self.p = np.ascontiguousarray(p_fast, dtype=float)
        self.ev_dir = np.array([-1] * m + [e.direction for e in user], dtype=np.intc)
        self.ev_term = np.array([1] * m + [int(e.terminal) for e in user], dtype=np.intc)
        self.ev_out = np.empty((EVENT_CAPACITY, 2 + 2 * system.n))  # rows written by the C before they are read
        self.i_out = np.zeros(1, dtype=np.intc)
        args = [a.ctypes.data for a in (self.ctl, self.y, self.p, out.t)] + [len(out.t)] + \
            [a.ctypes.data for a in (self.i_out, out.Y)] + [self.t_end] + \
            [a.ctypes.data for a in (self.ev_dir, self.ev_term, self.ev_out)]
        lib = system._lib
        self._call = lambda: lib.lg_dop853(*args)

    def run(self, t0: float, y0: np.ndarray, phase: int, h0: float = 0.0) -> PhaseEnd:
        """Integrate from (t0, y0) to the first gap closing, a terminal event of the user's, or the end."""
        out, ctl, m = self.out, self.ctl, self.m
        ctl[:] = self.template
        ctl[0], ctl[1] = t0, h0
        self.y[:] = y0
        self.i_out[0] = start = out.i
        code = self._call()
        out.i = int(self.i_out[0])
        out.phase[start:out.i] = phase
        t, y = float(ctl[0]), self.y.copy()
        if code not in (0, 4):
            raise SimulationError(f"The integration stopped at t = {t:.9g}: {_STATUS.get(code, f'status {code}')}.",
                                  fix="check the model and the initial state; the equations may be stiff there",
                                  t=t, state=y)
        count = int(min(ctl[10], EVENT_CAPACITY))
        found = [(int(r[0]), float(r[1]), r[2:].copy()) for r in self.ev_out[:count]] if count else []
        user = self.opts.user
        users = [(user[k - m].name, te, ye) for k, te, ye in found if k >= m]
        end = PhaseEnd(t, y, "end", -1, users, int(ctl[6]), int(ctl[5]), float(ctl[1]))
        if code == 4:
            closing = [k for k, te, _ in found if k < m and te == t]
            if closing:
                end.reason, end.contact = "touchdown", closing[0]
            else:
                end.reason = "event"
        return end


def dae_phase(cs: ContactSystem, p: np.ndarray, t0: float, y0: np.ndarray, t_end: float, closed: np.ndarray,
              mu: np.ndarray, eps: np.ndarray, out: Outputs, phase: int, opts: Options,
              user_values: Callable[[float, np.ndarray], np.ndarray] | None = None, first_step: float = 0.0,
              probe: Probe | None = None, rest_scale: float = 0.0) -> PhaseEnd:
    """Closed contacts (or bilateral rows) acting: SciPy's DOP853 with projection, events by Brent (module docstring).

    ``eps`` is the per-contact tolerance ε_k of the reactions (lift-off, slip).  A state at rest in
    equilibrium — q̇ = 0 and q̈ = 0 (below 10 atol and 1e-9 ``rest_scale``) of an autonomous model without
    user events — stays there: the phase ends at t_end without stepping (a ball come to rest).

    Each step: DOP853's step, the state projected on the active rows (`_Phase.project`), the event
    functions watched at its end and their crossings located (`_Phase.crossings`), the dense output
    filled up to the first terminal one, which ends the phase (`_Phase.end`).
    """
    from scipy.integrate import DOP853

    ph = _Phase(cs, p, t0, y0, closed, mu, eps, opts, user_values, probe)
    n = cs.n
    if ph.at_rest(t0, y0, rest_scale):
        y_rest = np.array(y0, dtype=float)
        y_rest[n:] = 0.0
        out.fill(t_end, lambda ts: np.broadcast_to(y_rest, (len(ts), 2 * n)), phase)
        return PhaseEnd(float(t_end), y_rest, "end", rhs_calls=ph.calls)
    solver = DOP853(ph.fun, t0, np.array(y0, dtype=float), t_end, rtol=opts.rtol, atol=opts.atol,
                    max_step=np.inf if opts.max_step is None else opts.max_step,
                    first_step=min(first_step, t_end - t0) if first_step > 0 else None)
    out.fill(t0, lambda ts: np.broadcast_to(y0, (len(ts), 2 * n)), phase)
    g_old = ph.watch(t0, y0)
    steps = 0
    users: list[tuple[str, float, np.ndarray]] = []
    while solver.status == "running":
        message = solver.step()
        if solver.status == "failed":
            raise SimulationError(f"The integration stopped at t = {solver.t:.9g}: {message}.",
                                  fix="check the model; the equations may be stiff or singular there",
                                  t=solver.t, state=solver.y.copy())
        steps += 1
        if steps > opts.max_steps:
            raise SimulationError(f"The maximum number of steps ({opts.max_steps}) was reached at t = {solver.t:.9g}.",
                                  fix="raise max_steps, or shorten the time span", t=solver.t, state=solver.y.copy())
        t_old, t_new = solver.t_old, solver.t
        state, states, y_end = ph.project(solver)
        g_new = ph.watch(t_new, y_end)
        found = ph.crossings(g_old, g_new, t_old, t_new, state)
        stop = ph.first_terminal(found)
        t_stop = t_new if stop is None else stop[0]
        users += ph.user_events(found, t_stop, state)
        out.fill(t_stop, states, phase)
        g_old = g_new
        if stop is not None:
            return ph.end(stop, state, users, steps, solver.h_abs)
    return PhaseEnd(float(solver.t), solver.y.copy(), "end", -1, users, steps, ph.calls, solver.h_abs)


class _Phase:
    """The pieces of one phase with closed contacts: the right-hand side with the active rows (`fun`), the
    event functions (`watch`: gaps of the open contacts, normal reactions of the closed ones, the slip
    margins μ λ_n − |λ_t| of the sticking ones, the user's), their crossings in a step, and the end."""

    def __init__(self, cs: ContactSystem, p: np.ndarray, t0: float, y0: np.ndarray, closed: np.ndarray,
                 mu: np.ndarray, eps: np.ndarray, opts: Options,
                 user_values: Callable[[float, np.ndarray], np.ndarray] | None, probe: Probe | None) -> None:
        self.cs, self.p, self.closed, self.mu, self.eps, self.opts = cs, p, closed, mu, eps, opts
        self.user_values = user_values
        self.probe = probe or Probe(cs.full, p)
        self.rows = cs.active_rows(closed)
        self.core = cs.core(self.probe.parts(t0, y0)[2], self.rows)  # independent rows: a block flat on the ground has one too many
        self.tol = max(1e-3 * opts.atol, 1e-15)
        self.m = len(cs.contacts)
        self.calls = 0
        self.sticking = [k for k in np.flatnonzero(closed) if cs.tangent[k] >= 0]
        self.directions = [-1] * (self.m + len(self.sticking)) + [e.direction for e in opts.user]

    def fun(self, t: float, y: np.ndarray) -> np.ndarray:
        """ẏ with the active rows' multipliers (M q̈ = F + Aᵀ λ, A q̈ = c)."""
        self.calls += 1
        try:
            return self.cs.solve(*self.probe.parts(t, y)[:4], y, self.rows, self.core)[0]
        except SimulationError as exc:
            raise SimulationError(f"At t = {t:.9g}: {exc.message}", fix=exc.fix, t=t, state=y.copy()) from None

    def at_rest(self, t0: float, y0: np.ndarray, rest_scale: float) -> bool:
        """q̇ = 0 and q̈ = 0 (below 10 atol and 1e-9 ``rest_scale``) of an autonomous model without user events."""
        n = self.cs.n
        return bool(self.cs.autonomous and not self.opts.user and rest_scale > 0
                    and np.max(np.abs(y0[n:])) <= 10 * self.opts.atol
                    and np.max(np.abs(self.fun(t0, y0)[n:])) <= 1e-9 * rest_scale)

    def watch(self, t: float, y: np.ndarray) -> np.ndarray:
        """Every event function at one state: gaps of the open contacts, reactions of the closed ones, slips, user."""
        cs, closed = self.cs, self.closed
        M, F, A, c, _, f = self.probe.parts(t, y)
        gaps = f[cs.normal].copy()
        _, lam = cs.solve(M, F, A, c, y, self.rows, self.core)
        values = np.where(closed, lam[cs.normal] + self.eps, gaps)
        slips = [self.mu[k] * lam[cs.normal[k]] - abs(lam[cs.tangent[k]]) + self.eps[k] for k in self.sticking]
        extra = self.user_values(t, y) if self.user_values is not None else np.zeros(0)
        return np.concatenate([values, slips, extra])

    def project(self, solver: Any) -> tuple[Callable[[float], np.ndarray], Callable[[np.ndarray], np.ndarray],
                                            np.ndarray]:
        """The step's end projected on the active rows (the solver continues from it), and the step's dense
        output projected: one state, many states (for the outputs), and the state at its end."""
        cs, p, core, tol, probe, n = self.cs, self.p, self.core, self.tol, self.probe, self.cs.n
        t_new = solver.t
        dense = solver.dense_output()
        y_new, changed = cs.project_active(t_new, solver.y, p, core, tol, probe)
        if changed:
            solver.y = y_new
            solver.f = self.fun(t_new, y_new)
        y_end = solver.y.copy()

        def state(s: float) -> np.ndarray:
            return cs.project_active(s, dense(s), p, core, tol, probe)[0] if s < t_new else y_end.copy()

        def states(ts: np.ndarray) -> np.ndarray:
            Y = np.array(dense(ts).T, dtype=float).reshape(len(ts), 2 * n)
            Y[ts >= t_new] = y_end
            return cs.project_active(ts, Y, p, core, tol)[0]

        return state, states, y_end

    def crossings(self, g_old: np.ndarray, g_new: np.ndarray, t_old: float, t_new: float,
                  state: Callable[[float], np.ndarray]) -> list[tuple[float, int]]:
        """Each event function that crosses zero in its direction during the step, located by Brent's method
        on the projected dense output: (t, index), in time order."""
        from scipy.optimize import brentq

        found = []
        for k, d in enumerate(self.directions):
            a, b = g_old[k], g_new[k]
            crossed = (a < 0 <= b and d >= 0) or (a > 0 >= b and d <= 0)
            if not crossed or a == 0:
                continue
            te = brentq(lambda s, k=k: self.watch(s, state(s))[k], t_old, t_new, xtol=4e-16 * max(1.0, abs(t_new)),
                        rtol=4 * np.finfo(float).eps)
            found.append((te, k))
        found.sort()
        return found

    def first_terminal(self, found: list[tuple[float, int]]) -> tuple[float, int] | None:
        """The first crossing that ends the phase: a contact's, or a terminal user event."""
        for te, k in found:
            if k < self.m + len(self.sticking) or self.opts.user[k - self.m - len(self.sticking)].terminal:
                return te, k
        return None

    def user_events(self, found: list[tuple[float, int]], t_stop: float,
                    state: Callable[[float], np.ndarray]) -> list[tuple[str, float, np.ndarray]]:
        """The user events crossed up to ``t_stop``: (name, t, state)."""
        first = self.m + len(self.sticking)
        return [(self.opts.user[k - first].name, te, state(te)) for te, k in found if k >= first and te <= t_stop]

    def end(self, stop: tuple[float, int], state: Callable[[float], np.ndarray],
            users: list[tuple[str, float, np.ndarray]], steps: int, h_abs: float) -> PhaseEnd:
        """The phase's end at the first terminal crossing: a lift-off or touchdown, a slip, or a user event."""
        te, k = stop
        y_stop = state(te)
        m = self.m
        if k < m:
            return PhaseEnd(te, y_stop, "liftoff" if self.closed[k] else "touchdown", k, users, steps, self.calls,
                            h_abs)
        if k < m + len(self.sticking):
            return PhaseEnd(te, y_stop, "slip", int(self.sticking[k - m]), users, steps, self.calls, h_abs)
        return PhaseEnd(te, y_stop, "event", -1, users, steps, self.calls, h_abs)
