"""Simulation of a model with unilateral contacts: smooth phases, events, impacts, persistent contact.

A contact (``unilateral = "g"`` in ``[constraints]``, `lagrangian.model._unilateral`) is open
(g > 0, no force) or closed (g = 0, a complementary constraint whose multiplier is the normal
reaction λ ≥ 0).  `run_contact` (the contacts' route of `simulate`) integrates phase after phase
(`_contact_phase`), each with a fixed set of closed contacts, and switches at the events that end
them (`_contact_switch`):

* touch-down (g of an open contact falls to 0): an impact — percussions from Lagrange's
  equations in impulsive form with Newton's coefficient e and, with friction, Coulomb's bound
  (`_impact`) — then the closed set of the next phase;
* lift-off (λ of a closed contact falls to 0): the closed set of the next phase;
* an accumulation of impacts (Zeno): summed, and the contacts closed.

The trajectory is on the requested grid, with the extra columns ``gap_<contact>``,
``closed_<contact>`` (1 closed, 0 open), ``lambda_<row>`` (0 where open) and the reactions of the
contacts that declare one (``R_<contact>_<axis>``); its events are `ContactEvent` items
(``impact_<contact>`` with the percussion and the energy before and after, ``liftoff_<contact>``,
``rest_<contact>``) with the user's events.  The drift of each first integral is measured within
each smooth piece (between impacts, where it must hold); what an impact takes is in its event.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from pathlib import Path

import numpy as np
import symengine as se

from ..dynamics import EquationsOfMotion
from ..errors import Interrupted, ModelError, SimulationError
from ..model import load_model
from ..model.spec import Model
from ._contact_phase import FastPhases, Options, Outputs, PhaseEnd, dae_phase
from ._contact_switch import REST, ContactEvent, ContactLaws, accumulation
from ._contact_system import ContactSystem, contacts_of, solve_small
from ._input_run import constant_inputs_only
from ._options import SimulationOptions, default_tolerance
from ._progress import make_reporter
from ._projection import check_initial
from ._setup import event_expressions, initial_state, momenta, output_times
from ._stickslip import exact_contact
from ._system import known_values
from ._trajectory import Event, Trajectory, conservation

__all__ = ["ContactEvent", "check_contact_options", "contact_model", "contact_system", "run_contact"]

#: Consecutive phases shorter than this (relative to max(1, |t|)) before the run is refused as chattering.
CHATTER_LENGTH, CHATTER_COUNT = 1e-12, 50


def contact_model(source) -> Model | None:
    """The `Model` of ``source`` (a path, `Model`, equations or compiled system) when it has unilateral contacts.

    Parameters
    ----------
    source : str or Path or Model or EquationsOfMotion or CompiledSystem
        A path, `Model`, equations or compiled system.

    Returns
    -------
    Model or None
        Its model when it has unilateral contacts, else None.
    """
    if isinstance(source, (str, Path)):
        model = load_model(source)
    elif isinstance(source, Model):
        model = source
    elif isinstance(getattr(source, "eom", None), EquationsOfMotion):
        model = source.eom.model
    elif isinstance(source, (EquationsOfMotion, ContactSystem)):
        model = source.model
    else:
        return None
    return model if contacts_of(model) else None


_SYSTEMS: dict[tuple, tuple[Model, ContactSystem]] = {}


def contact_system(model: Model, backend: str = "auto") -> ContactSystem:
    """One `ContactSystem` per model object and backend (derived and compiled once)."""
    key = (id(model), backend)
    hit = _SYSTEMS.get(key)
    if hit is not None and hit[0] is model:
        return hit[1]
    system = ContactSystem(model, backend=backend)
    if len(_SYSTEMS) > 16:
        _SYSTEMS.clear()
    _SYSTEMS[key] = (model, system)
    return system


def check_contact_options(options: SimulationOptions) -> None:
    """Refuse what the contacts' route cannot do: a method other than dop853, fixed steps, a stabilization
    other than the projection, ``rest`` outside (0, 1)."""
    if options.dt is not None or options.method != "dop853":
        raise SimulationError("A model with unilateral contacts runs with method='dop853' only, adaptive: its phases "
                              "end at events, not on a fixed grid.", fix="leave method and dt out")
    if options.stabilization not in (None, "projection"):
        raise SimulationError(f"stabilization={options.stabilization!r}: the closed contacts are kept by projection.",
                              fix="leave stabilization out")
    rest = REST if options.rest is None else options.rest
    if not 0 < rest < 1:
        raise SimulationError(f"rest = {rest:g} must lie in (0, 1).", fix="e.g. rest=1e-6")


def run_contact(source, options: SimulationOptions) -> Trajectory:
    """Integrate a model with unilateral contacts (module docstring), by phases between impacts.

    ``options.rest``: the last approach speed, relative to the first of a geometric series of
    impacts, at which the accumulation is summed and the contacts closed (default `REST`;
    `_contact_switch`); ``options.max_phases``: the most smooth phases a run may have (default
    1 000 000).  Constant inputs only: their numbers join the parameters.

    Raises
    ------
    ModelError
        No unilateral contact, or an exact Coulomb load beside the contacts.
    SimulationError
        A contact violated at the initial state (g < 0), e outside [0, 1] or μ < 0, simultaneous
        impacts with no solution, a contact that must stay closed while sliding with friction,
        endless chattering; otherwise as `simulate`.
    """
    model = contact_model(source)
    if model is None:
        raise ModelError("The model has no unilateral contact.", fix="use lagrangian.simulate")
    options = options.but(parameters=constant_inputs_only(model, options.inputs, options.parameters,
                                                          route="contact"), inputs=None)
    if exact_contact(model) is not None:
        raise ModelError("Exact Coulomb friction (regularization = 0) and unilateral contacts are not simulated "
                         "together.", symbol=exact_contact(model).name,  # type: ignore[union-attr]
                         fix="give the Coulomb load a positive regularization, or put the friction on the contact "
                             "(friction = \"mu\", slip = \"...\")")
    check_contact_options(options)
    cs = contact_system(model, options.backend)
    specs = event_expressions(cs.eom, options.events) if options.events else []
    fast = cs.fast_system([(s.name, s.expression) for s in specs])
    p, p_fast = cs.parameter_values(options.parameters)
    e, mu = cs.coefficients(p)
    y = initial_state(cs.eom, options.initial)
    t = float(options.t_start)
    grid = output_times(t, float(options.t_end), options.n_out, options.t_eval,
                        4 * cs.n + 4 * len(cs.full.rows) + len(cs.full.monitors))
    out = Outputs(grid, np.full((len(grid), 2 * cs.n), np.nan), np.full(len(grid), -1, dtype=int))
    opts = Options(options.rtol, options.atol, options.max_step, options.max_steps, options.stiffness_check, specs)
    laws = ContactLaws(cs, p, e, mu, options.atol)
    flights = None if fast is None else FastPhases(fast, len(cs.contacts), p_fast, float(options.t_end), out, opts)  # type: ignore[arg-type]
    run = _Run(cs, laws, REST if options.rest is None else options.rest)
    phases, status, t = _phases(run, flights, p, t, y, out, opts, _user_functions(cs, specs, p), options)
    tolerance = options.tolerance
    return _join(cs, p, out, phases, run.events, status, run,
                 tolerance if tolerance is not None else default_tolerance(options.method, options.rtol))


def _phases(run: _Run, flights: FastPhases | None, p: np.ndarray, t: float, y: np.ndarray,
            out: Outputs, opts: Options, user_values: Callable | None,
            options: SimulationOptions) -> tuple[list[np.ndarray], str, float]:
    """The smooth phases one after the other, switching the contacts between them (the run's loop)."""
    cs, laws, t_end = run.cs, run.laws, float(options.t_end)
    max_phases = 1_000_000 if options.max_phases is None else options.max_phases
    phases: list[np.ndarray] = []
    status = "completed"
    reporter = make_reporter(options.progress, float(options.t_start), t_end)
    try:
        y, closed = run.start(t, y)
        short = 0
        while True:
            phases.append(closed.copy())
            index = len(phases) - 1
            h = run.first_step(t, y, closed)
            if not closed.any() and flights is not None:
                end = flights.run(t, y, index, h)
            else:
                end = dae_phase(cs, p, t, y, t_end, closed, laws.mu, laws.eps, out, index, opts, user_values, h,
                                laws.probe, laws.acc_scale)
            run.account(end)
            if reporter:
                reporter.update(end.t)
            if end.reason in ("end", "event"):
                status = "completed" if end.reason == "end" else "stopped by a terminal event"
                break
            short = short + 1 if end.t - t <= CHATTER_LENGTH * max(1.0, abs(t)) else 0
            if short >= CHATTER_COUNT or len(phases) >= max_phases:
                raise SimulationError(f"The contacts switched {len(phases)} times, the last {short} within "
                                      f"{CHATTER_LENGTH:g} s of each other, by t = {end.t:.9g} (chattering).",
                                      fix="check the contacts' gaps and coefficients, or raise max_phases",
                                      t=end.t, state=end.y.copy())
            t = end.t
            y, closed = run.switch(end, closed)
            if t >= t_end:
                break
    except KeyboardInterrupt:
        if reporter:
            reporter.finish(t, False)
        partial = _join(cs, p, out, phases, run.events, f"interrupted at t = {t:.9g} (partial)", run,
                        options.tolerance)
        raise Interrupted(t, partial) from None
    if reporter:
        reporter.finish(t_end if status == "completed" else t, True)
    return phases, status, t


def _user_functions(cs: ContactSystem, specs: Sequence, p: np.ndarray) -> Callable | None:
    if not specs:
        return None
    eom = cs.eom
    args = [eom.t, *eom.q, *eom.qd, *(se.Symbol(k) for k in cs.full.parameters)]
    fn = se.Lambdify(args, [s.expression for s in specs])
    q = p[: len(cs.full.parameters)]
    return lambda t, y: np.asarray(fn(np.concatenate([[t], y, q])), dtype=float).ravel()


class _Run:
    """The events of a run and the switches between its phases."""

    def __init__(self, cs: ContactSystem, laws: ContactLaws, rest: float) -> None:
        self.cs, self.laws, self.rest = cs, laws, rest
        self.events: list[Event] = []
        self.series: tuple[list[float], list[float]] = ([], [])
        self.steps = self.rhs_calls = 0
        self.tol = max(1e-3 * laws.atol, 1e-15)

    def account(self, end: PhaseEnd) -> None:
        self.steps += end.steps
        self.rhs_calls += end.rhs_calls
        self.events += [Event(name, te, ye[: self.cs.n].copy(), ye[self.cs.n:].copy()) for name, te, ye in
                        end.user_events]

    def first_step(self, t: float, y: np.ndarray, closed: np.ndarray) -> float:
        """A first step short enough not to step over the next touch-down of a contact that has just opened.

        The events are sign changes of the gap between the ends of a step: a gap that starts at 0 and
        comes back below 0 within the first step (a tiny bounce) would go unseen.  So the first step is
        at most a quarter of the flight 2 ġ/|g̈| of each contact that starts touching and opening
        (0: the integrator chooses).
        """
        cs, laws = self.cs, self.laws
        M, F, A, c, g, f, gap_tol, _ = laws.parts(t, y)
        opening = [k for k in laws.touching(f, gap_tol) if not closed[k] and g[laws.rows_n[k]] > 0]
        if not opening:
            return 0.0
        if laws.simple and not closed.any():
            qdd = solve_small(M, F)
        else:
            rows = cs.active_rows(closed)
            qdd = cs.solve(M, F, A, c, y, rows, cs.core(A, rows))[0][cs.n:]
        flights = []
        for k in opening:
            r = laws.rows_n[k]
            acc = float(A[r] @ qdd + c[r])
            if acc < 0:
                flights.append(2 * float(g[r]) / -acc)
        return 0.25 * min(flights) if flights else 0.0

    def _closed_state(self, t: float, y: np.ndarray, closed: np.ndarray) -> np.ndarray:
        if not closed.any() and not len(self.cs.bilateral):
            return y  # nothing to project onto
        rows = self.cs.active_rows(closed)
        core = self.cs.core(self.laws.parts(t, y)[2], rows)
        return self.cs.project_active(t, y, self.laws.p, core, self.tol, self.laws.probe)[0]

    def start(self, t: float, y: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """The state and closed contacts at the start: a violated contact is refused, an approaching one impacts."""
        cs = self.cs
        _, _, _, _, g, f, gap_tol, v_tol = self.laws.parts(t, y)
        gaps, speeds = f[cs.normal], g[cs.normal]
        for k in np.flatnonzero(gaps < -gap_tol):
            name = cs.names[k]
            loc = cs.model.where("constraint", name)
            where = f" (declared at {loc.file}:{loc.line})" if loc.file and loc.line else ""
            raise SimulationError(
                f"The contact `{name}`{where} is violated at the initial state: its gap g = {gaps[k]:.6g} < 0 "
                "(the bodies overlap).", fix="start from a state where every gap is ≥ 0 (the contact closed at g = 0)",
                t=t, state=y.copy())
        if len(cs.bilateral):
            from ._contact_system import _Active

            check_initial(_Active(cs.full, cs.bilateral), t, y, self.laws.p)  # type: ignore[arg-type]
        approaching = np.flatnonzero((np.abs(gaps) <= gap_tol) & (speeds < -v_tol))
        if len(approaching):
            y = self._impact(t, y, int(approaching[np.argmin(speeds[approaching])]))
        closed = self.laws.decide(t, y)
        return self._closed_state(t, y, closed), closed

    def _impact(self, t: float, y: np.ndarray, trigger: int) -> np.ndarray:
        y_plus, events = self.laws.impact(t, y, trigger)
        times, speeds = self.series
        times.append(t)
        speeds.append(max(abs(ev.speed) for ev in events))
        found = accumulation(times, speeds, self.rest, float(self.laws.parts(t, y)[6][trigger]))
        if found is not None:  # Zeno: the rest of the series summed, the touching contacts closed at its end
            t_inf, _ = found
            y_plus, touching, (E0, E1) = self.laws.settle(t, y)
            n = self.cs.n
            events = [ContactEvent(f"rest_{self.cs.names[k]}", t_inf, y[:n].copy(), y[n:].copy(), kind="rest",
                                   contact=self.cs.names[k], qd_after=y_plus[n:].copy(), energy_before=E0,
                                   energy_after=E1) for k in touching]
            times.clear()
            speeds.clear()
        self.events += events
        return y_plus

    def switch(self, end: PhaseEnd, closed: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """The state and closed contacts of the next phase, after the event that ended the last one."""
        cs, n = self.cs, self.cs.n
        t, y, k = end.t, end.y, end.contact
        if end.reason == "touchdown":
            y = self._impact(t, y, k)
            closed = self.laws.decide(t, y)
        elif end.reason == "liftoff":
            lam = cs.accelerations(t, y, self.laws.p, cs.active_rows(closed))[1]
            self.events.append(ContactEvent(f"liftoff_{cs.names[k]}", t, y[:n].copy(), y[n:].copy(), kind="liftoff",
                                            contact=cs.names[k], reaction=float(lam[cs.normal[k]])))
            self.series[0].clear()
            self.series[1].clear()
            closed = self.laws.decide(t, y, prefer_open={k})
        else:  # slip: the sticking contact needs more friction than μ λ
            raise SimulationError(
                f"At t = {t:.9g} the contact `{cs.names[k]}` would need more friction than μ λ to stay stuck: it "
                "would slide, and a persistent contact that slides with Coulomb friction is not simulated.",
                fix="raise its friction coefficient so that it sticks, or make it frictionless (leave `friction` out)",
                t=t, state=y.copy())
        return self._closed_state(t, y, closed), closed


def _join(cs: ContactSystem, p: np.ndarray, out: Outputs, phases: list[np.ndarray], events: list[Event], status: str,
          run: _Run, tolerance: float | None) -> Trajectory:
    """One `Trajectory` on the grid from the phases (module docstring)."""

    N, n = out.i, cs.n
    t, Y, which = out.t[:N], np.ascontiguousarray(out.Y[:N]), out.phase[:N]
    rows_all = cs.full.rows
    dY = np.zeros((N, 2 * n))
    lam = np.zeros((N, len(rows_all)))
    closed = np.zeros((N, len(cs.contacts)), dtype=bool)
    sets: dict[bytes, list[int]] = {}  # the phases with the same closed contacts, solved together
    for k in set(which.tolist()) - {-1}:
        sets.setdefault(phases[k].tobytes(), []).append(k)
    for group in sets.values():
        mask = np.isin(which, group)
        dY[mask], lam[mask] = cs.accelerations_many(t[mask], Y[mask], p, cs.active_rows(phases[group[0]]))
        closed[mask] = phases[group[0]]
    monitors_all = cs.full.monitor_values(t, Y, p) if N else np.zeros((0, len(cs.full.monitors)))
    monitors = {name: monitors_all[:, k].copy() for k, name in enumerate(cs.full.monitors)}
    M, _, _, _, g, f = cs.full.parts(t, Y, p) if N else (np.zeros((0, n, n)),) + (np.zeros((0, len(rows_all))),) * 5
    integrals = tuple(cs.full.integrals)
    # The first integrals hold between impacts: their drift is measured piece by piece.
    cuts = sorted({ev.t for ev in events if isinstance(ev, ContactEvent) and ev.kind in ("impact", "rest")})
    piece = np.searchsorted(np.asarray(cuts), t, side="left") if cuts else np.zeros(N, dtype=int)
    # The scale of each integral over the whole run (`conservation`), its drift from the start of each piece.
    drift, scales = conservation(monitors, integrals, momenta=momenta(cs.eom, integrals), M=np.asarray(M), qd=Y[:, n:])
    first = np.searchsorted(piece, piece, side="left")  # the first output of each output's piece
    for name in integrals:
        values = monitors[name]
        drift[name] = float(np.max(np.abs(values - values[first]), initial=0.0)) / scales[name]
    for k in cs.bilateral:
        row = cs.eom.constraints[k]
        drift[f"drift_{row.name}"] = float(np.max(np.abs(f[:, k]), initial=0.0)) if row.kind == "holonomic" else 0.0
        drift[f"drift_{row.name}_dot"] = float(np.max(np.abs(g[:, k]), initial=0.0))
    for i, name in enumerate(cs.names):
        drift[f"drift_{name}"] = float(np.max(np.abs(f[closed[:, i], cs.normal[i]]), initial=0.0))
    warnings = [f"{name} drifted by {drift[name]:.2e} (relative), more than the tolerance {tolerance:.1e}"
                for name in integrals if tolerance is not None and drift[name] > tolerance]
    for ev in events:
        if isinstance(ev, ContactEvent) and ev.kind == "impact" and cs.tangent[cs.names.index(ev.contact)] < 0:
            gain = ev.energy_after - ev.energy_before
            if gain > 1e-9 * max(abs(ev.energy_before), abs(ev.energy_after), 1e-300):
                warnings.append(f"the impact of `{ev.contact}` at t = {ev.t:.9g} increased the energy by {gain:.3g}")
    reactions = cs.full.reaction_values(t, Y, lam, p) if N else np.zeros((0, len(cs.full.reactions)))
    extra: dict[str, np.ndarray] = {}
    for i, name in enumerate(cs.names):
        extra[f"gap_{name}"] = f[:, cs.normal[i]].copy()
        extra[f"closed_{name}"] = closed[:, i].astype(float)
    extra.update({f"lambda_{row}": lam[:, k].copy() for k, row in enumerate(rows_all)})
    extra.update({name: reactions[:, k].copy() for k, name in enumerate(cs.full.reactions)})

    return Trajectory(
        model_name=cs.model.name, coordinates=tuple(cs.full.coordinates), parameters=known_values(cs.full.parameters, p),
        t=np.asarray(t, dtype=float), q=Y[:, :n].copy(), qd=Y[:, n:].copy(), qdd=dY[:, n:].copy(), monitors=monitors,
        integrals=integrals, drift=drift, method="dop853 + contacts", steps=run.steps, rhs_calls=run.rhs_calls,
        tolerance=tolerance, warnings=tuple(warnings), events=tuple(sorted(events, key=lambda ev: ev.t)),
        status=status, conditioning=cs.full.worst_pivot, extra=extra, scales=scales)
