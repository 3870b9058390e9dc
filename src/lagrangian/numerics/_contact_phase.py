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
output to a few ulp (`_integrators.c`).  Any other phase steps SciPy's DOP853 on q̈ solved with the
acting rows (`ContactSystem.solve`), projects every step onto them (positions onto the
closed gaps, velocities onto ġ = 0 and w = 0), and locates its events by Brent's method on the
projected dense output (`dae_phase`), as the DAE route (`_dae_run.run_dae`) does.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass, field

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
    """
    from scipy.integrate import DOP853
    from scipy.optimize import brentq

    probe = probe or Probe(cs.full, p)
    rows = cs.active_rows(closed)
    core = cs.core(probe.parts(t0, y0)[2], rows)  # independent rows: a block flat on the ground has one too many
    tol = max(1e-3 * opts.atol, 1e-15)
    n, m = cs.n, len(cs.contacts)
    calls = [0]

    def fun(t: float, y: np.ndarray) -> np.ndarray:
        calls[0] += 1
        try:
            return cs.solve(*probe.parts(t, y)[:4], y, rows, core)[0]
        except SimulationError as exc:
            raise SimulationError(f"At t = {t:.9g}: {exc.message}", fix=exc.fix, t=t, state=y.copy()) from None

    if cs.autonomous and not opts.user and rest_scale > 0 and np.max(np.abs(y0[n:])) <= 10 * opts.atol \
            and np.max(np.abs(fun(t0, y0)[n:])) <= 1e-9 * rest_scale:
        y_rest = np.array(y0, dtype=float)
        y_rest[n:] = 0.0
        out.fill(t_end, lambda ts: np.broadcast_to(y_rest, (len(ts), 2 * n)), phase)
        return PhaseEnd(float(t_end), y_rest, "end", rhs_calls=calls[0])

    sticking = [k for k in np.flatnonzero(closed) if cs.tangent[k] >= 0]

    def watch(t: float, y: np.ndarray) -> np.ndarray:
        """Every event function at one state: gaps of the open contacts, reactions of the closed ones, slips, user."""
        M, F, A, c, _, f = probe.parts(t, y)
        gaps = f[cs.normal].copy()
        _, lam = cs.solve(M, F, A, c, y, rows, core)
        values = np.where(closed, lam[cs.normal] + eps, gaps)
        slips = [mu[k] * lam[cs.normal[k]] - abs(lam[cs.tangent[k]]) + eps[k] for k in sticking]
        extra = user_values(t, y) if user_values is not None else np.zeros(0)
        return np.concatenate([values, slips, extra])

    directions = [-1] * (m + len(sticking)) + [e.direction for e in opts.user]
    solver = DOP853(fun, t0, np.array(y0, dtype=float), t_end, rtol=opts.rtol, atol=opts.atol,
                    max_step=np.inf if opts.max_step is None else opts.max_step,
                    first_step=min(first_step, t_end - t0) if first_step > 0 else None)
    out.fill(t0, lambda ts: np.broadcast_to(y0, (len(ts), 2 * n)), phase)
    g_old = watch(t0, y0)
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
        dense = solver.dense_output()
        y_new, changed = cs.project_active(t_new, solver.y, p, core, tol, probe)
        if changed:
            solver.y = y_new
            solver.f = fun(t_new, y_new)
        y_end = solver.y.copy()

        def state(s: float, dense=dense, t_new=t_new, y_end=y_end) -> np.ndarray:  # type: ignore[no-untyped-def]
            return cs.project_active(s, dense(s), p, core, tol, probe)[0] if s < t_new else y_end.copy()

        def states(ts: np.ndarray, dense=dense, t_new=t_new, y_end=y_end) -> np.ndarray:  # type: ignore[no-untyped-def]
            Y = np.array(dense(ts).T, dtype=float).reshape(len(ts), 2 * n)
            Y[ts >= t_new] = y_end
            return cs.project_active(ts, Y, p, core, tol)[0]

        g_new = watch(t_new, y_end)
        found = []
        for k, d in enumerate(directions):
            a, b = g_old[k], g_new[k]
            crossed = (a < 0 <= b and d >= 0) or (a > 0 >= b and d <= 0)
            if not crossed or a == 0:
                continue
            te = brentq(lambda s, k=k: watch(s, state(s))[k], t_old, t_new, xtol=4e-16 * max(1.0, abs(t_new)),
                        rtol=4 * np.finfo(float).eps)
            found.append((te, k))
        found.sort()
        stop = None
        for te, k in found:
            if k < m + len(sticking) or opts.user[k - m - len(sticking)].terminal:
                stop = (te, k)
                break
        t_stop = t_new if stop is None else stop[0]
        for te, k in found:
            if k >= m + len(sticking) and te <= t_stop:
                users.append((opts.user[k - m - len(sticking)].name, te, state(te)))
        out.fill(t_stop, states, phase)
        g_old = g_new
        if stop is not None:
            te, k = stop
            y_stop = state(te)
            if k < m:
                return PhaseEnd(te, y_stop, "liftoff" if closed[k] else "touchdown", k, users, steps, calls[0],
                                solver.h_abs)
            if k < m + len(sticking):
                return PhaseEnd(te, y_stop, "slip", int(sticking[k - m]), users, steps, calls[0], solver.h_abs)
            return PhaseEnd(te, y_stop, "event", -1, users, steps, calls[0], solver.h_abs)
    return PhaseEnd(float(solver.t), solver.y.copy(), "end", -1, users, steps, calls[0], solver.h_abs)
