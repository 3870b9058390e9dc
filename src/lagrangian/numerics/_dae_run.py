"""The DAE route of `simulate`: models with complementary constraints, with the drift controlled.

The state is y = (q, q̇) as for any model; the multipliers λ are not integrated but
solved at each evaluation from the augmented equations (see `codegen._codegen_dae`): the
constraints are differentiated (index reduction) so that they hold at acceleration
level, A q̈ + c = 0.  The exact solution then stays on the constraint manifold, but the
numerical one drifts from it (f(q, t) grows like t² for holonomic rows), so the drift is
controlled in one of two ways, or both (``stabilization``):

``"projection"`` (default)
    Coordinate projection after every accepted step and at every output time (Hairer,
    Lubich & Wanner, *Geometric Numerical Integration*, IV.4; Hairer & Wanner, *Solving
    ODEs II*, VII.2): q is moved back onto f(q, t) = 0 by Newton steps, then q̇ onto
    A q̇ + b = 0, both along the kinetic-energy metric:

        Δq = −M⁻¹A_hᵀ (A_h M⁻¹ A_hᵀ)⁻¹ f,        Δq̇ = −M⁻¹Aᵀ (A M⁻¹ Aᵀ)⁻¹ (A q̇ + b).

    It needs an explicit Runge–Kutta method (``dop853``, ``RK45``, ``RK23``), whose state
    can be replaced between steps.
``"baumgarte"``
    A q̈ + c + 2α g + β² f = 0 (g = A q̇ + b, f the holonomic residuals): a drift decays
    instead of growing; ``baumgarte=(α, β)`` in 1/time units.  Works with every method.
``"both"``, ``"none"``
    The two together, or neither (to see the drift).

The drift is reported: the monitors ``drift_<row>`` (f_k, holonomic rows) and
``drift_<row>_dot`` (A_k q̇ + b_k, every row) along the output grid, and their largest
absolute values in ``Trajectory.drift``.  The multipliers ``lambda_<row>`` and the
reactions they stand for (``R_<constraint>_<axis>`` force components, ``M_...`` moment
components, ``Q_<constraint>_<coordinate>`` generalized forces) are ``extra`` columns.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from typing import Any

import numpy as np
import symengine as se

from ..dynamics import EquationsOfMotion
from ..errors import SimulationError
from ._dae import ConstrainedSystem, constrained_source
from ._input_run import InputsAt, rowwise
from ._inputs import resolve_inputs
from ._options import STABILIZATIONS, SimulationOptions, default_tolerance
from ._progress import progress_bar
from ._projection import check_initial, project, project_many
from ._setup import EventSpec, event_expressions, initial_state, momenta, output_times
from ._system import known_values
from ._trajectory import Event, Trajectory, conservation

__all__ = ["EXPLICIT", "IMPLICIT", "check_dae_options", "run_dae", "simulate_dae"]

#: Methods whose state may be replaced between steps (the projection needs it).
EXPLICIT = {"dop853": "DOP853", "DOP853": "DOP853", "RK45": "RK45", "RK23": "RK23"}
IMPLICIT = ("Radau", "BDF", "LSODA")


def simulate_dae(source, t_end: float, **options: Any) -> Trajectory:
    """`run_dae` with `simulate`'s keywords: ``simulate_dae(model, 3.0, method="Radau")``."""
    return run_dae(source, SimulationOptions(t_end, **options))


def check_dae_options(options: SimulationOptions) -> str:
    """The stabilization of a constrained run (module docstring); refuses what this route cannot do.

    Raises
    ------
    SimulationError
        Fixed steps, ``gauss-legendre``, or the projection with an implicit method.
    """
    method, stabilization = options.method, options.stabilization
    if options.dt is not None:
        raise SimulationError("Fixed steps (dt) are not available for a model with complementary constraints.",
                              fix="leave dt out (the steps adapt to rtol/atol), or bound them with max_step")
    if method == "gauss-legendre":
        raise SimulationError("The Gauss-Legendre method integrates Hamilton's equations without constraints.",
                              fix="use method='dop853' for a model with complementary constraints")
    if method not in EXPLICIT and method not in IMPLICIT:
        raise SimulationError(f"Unknown method `{method}`.", fix="use dop853, RK45, RK23, Radau, BDF or LSODA")
    if stabilization is None:
        stabilization = "projection" if method in EXPLICIT else "baumgarte"
    if stabilization not in STABILIZATIONS:
        raise SimulationError(f"Unknown stabilization `{stabilization}`.", fix="use " + ", ".join(STABILIZATIONS))
    if stabilization in ("projection", "both") and method not in EXPLICIT:
        raise SimulationError(f"The projection onto the constraints needs an explicit method, not `{method}`.",
                              fix="use method='dop853', or stabilization='baumgarte' with this method")
    return stabilization


def run_dae(source, options: SimulationOptions) -> Trajectory:
    """Integrate a model with complementary constraints (module docstring) with `simulate`'s options.

    ``options.stabilization``: ``"projection"`` (default with explicit methods), ``"baumgarte"``
    (default with ``Radau``, ``BDF``, ``LSODA``), ``"both"`` or ``"none"``; ``options.baumgarte``:
    (α, β), the rates of Baumgarte's stabilisation.

    Returns
    -------
    Trajectory
        With q̈ and the multipliers from the augmented equations, the reactions, and the
        drift of the constraints (``drift_<row>`` monitors and their maxima in ``drift``).

    Raises
    ------
    SimulationError
        A state that violates a constraint at t_start (with the residual and the nearest state
        that satisfies it), constraints redundant there, singular M, a method that cannot do
        what is asked, or a failed step.
    """
    source, eom = constrained_source(source)
    if eom is None:
        raise SimulationError("This model keeps no constraint complementary.", fix="use lagrangian.simulate")
    stabilization = check_dae_options(options)
    # The default tolerance applies to the first integrals; the constraint residuals are
    # checked only against a tolerance asked for.
    tolerance = default_tolerance(options.method, options.rtol) if options.tolerance is None else options.tolerance
    stab = np.array(options.baumgarte if stabilization in ("baumgarte", "both") else (0.0, 0.0), dtype=float)
    system, law, p, applied = _system_and_inputs(source, eom, options)
    y0 = initial_state(eom, options.initial)
    t_out = output_times(float(options.t_start), float(options.t_end), options.n_out, options.t_eval,
                         4 * system.n + 3 * system.m + len(system.monitors) + len(system.reactions) + 1)
    check_initial(system, float(options.t_start), y0, p)
    stepper = _Stepper(system, p, applied, stab, stabilization in ("projection", "both"), options)
    t, Y, evs, status = stepper.run(y0, t_out, _event_function(eom, system, options.events, applied),
                                    law.breakpoints)
    return _trajectory(system, p, t, Y, stab, evs, options.method, stabilization, stepper.steps, stepper.calls,
                       tolerance, status, residual_tolerance=options.tolerance, applied=applied)


def _system_and_inputs(source, eom: EquationsOfMotion, options: SimulationOptions):
    """(system, the inputs' law, p, the inputs applied at (t, y)) of a constrained run."""
    law = resolve_inputs(eom, options.inputs)
    given = {**(options.parameters or {})}
    twice = sorted(set(given) & {s.name for s in law.sources})
    if twice:
        raise SimulationError(f"The input `{twice[0]}` is given both as a parameter value and by the inputs' law.",
                              fix="give it once: in inputs= (--input) or in parameters= (--set)")
    given.update(law.constants)
    regime = law.regime(given, tuple(eom.model.inputs))
    # A system given is used when its integrals are those of this run's regime (and its backend the one asked).
    backend = options.backend
    if isinstance(source, ConstrainedSystem) and source.regime == regime and backend in ("auto", source.backend):
        system = source
    else:
        system = ConstrainedSystem(eom, backend=backend, inputs=regime)
    p = system.parameter_vector(given)
    # Inputs that vary are computed here, in Python, at each evaluation: this path steps in Python
    # anyway (SciPy's solver, the projection), and a table's interval is the current segment's.
    return system, law, p, InputsAt(law, eom, system.parameters, p)


def _event_function(eom: EquationsOfMotion, system: ConstrainedSystem, events: Sequence,
                    applied: InputsAt) -> tuple[list[EventSpec], Callable | None]:
    """(the events read, g(t, y) of all of them at once), or ([], None) without events."""
    specs = event_expressions(eom, list(events))
    if not specs:
        return specs, None
    args = [eom.t, *eom.q, *eom.qd, *(se.Symbol(k) for k in system.parameters)]
    lam = se.Lambdify(args, [s.expression for s in specs])

    def event_fn(t: float, y: np.ndarray) -> np.ndarray:
        return np.asarray(lam(np.concatenate([[t], y, applied(t, y)])), dtype=float).ravel()

    return specs, event_fn


class _Stepper:
    """SciPy's solver driven step by step: projection after each step, events, the output grid."""

    def __init__(self, system: ConstrainedSystem, p: np.ndarray, applied: InputsAt, stab: np.ndarray,
                 projecting: bool, options: SimulationOptions) -> None:
        self.system, self.p, self.applied, self.stab = system, p, applied, stab
        self.projecting, self.options = projecting, options
        from scipy import integrate  # late: SciPy's import is slow, and only this route (of `simulate`'s) needs it

        self.solver_class = getattr(integrate, EXPLICIT.get(options.method, options.method))
        self.tol = max(1e-3 * options.atol, 1e-15)
        self.steps = self.calls = 0

    def fun(self, t: float, y: np.ndarray) -> np.ndarray:
        """ẏ with the stabilization's rates, the inputs at (t, y)."""
        self.calls += 1
        try:
            return self.system.rhs(t, y, self.applied(t, y), self.stab)[0]
        except SimulationError as exc:
            raise SimulationError(f"At t = {t:.9g}: {exc.message}", fix=exc.fix, t=t, state=y.copy()) from None

    def solver(self, a: float, y: np.ndarray, b: float):
        """A new SciPy solver from (a, y) towards b (at the start, and at each breakpoint of the inputs)."""
        max_step = self.options.max_step
        return self.solver_class(self.fun, a, y, b, rtol=self.options.rtol, atol=self.options.atol,
                                 max_step=np.inf if max_step is None else max_step)

    def project(self, t: float, y: np.ndarray) -> np.ndarray:
        return project(self.system, t, y, self.p, self.tol)[0] if self.projecting else y

    def step(self, solver) -> tuple[float, float, Callable, Callable]:
        """One accepted step, projected: (t_old, t_new, projected state(t), raw state(t)) on it."""
        message = solver.step()
        if solver.status == "failed":
            raise SimulationError(f"The integration stopped at t = {solver.t:.9g}: {message}.",
                                  fix="the equations may be stiff there: try method='Radau' with "
                                      "stabilization='baumgarte', or check the model", t=solver.t, state=solver.y)
        self.steps += 1
        if self.steps > self.options.max_steps:
            raise SimulationError(f"The maximum number of steps ({self.options.max_steps}) was reached at "
                                  f"t = {solver.t:.9g}.", fix="raise max_steps, or shorten the time span",
                                  t=solver.t, state=solver.y)
        t_old, t_new = solver.t_old, solver.t
        dense = solver.dense_output()
        if self.projecting:
            y_new, changed = project(self.system, t_new, solver.y, self.p, self.tol)
            if changed:
                solver.y = y_new
                solver.f = self.fun(t_new, y_new)  # the first stage of the next step (FSAL)

        def raw_state(t: float) -> np.ndarray:  # projected with all the outputs at the end
            return dense(t) if t < t_new else solver.y.copy()

        def state(t: float) -> np.ndarray:
            return self.project(t, raw_state(t))

        return t_old, t_new, state, raw_state

    def run(self, y0: np.ndarray, t_out: np.ndarray, events: tuple[list[EventSpec], Callable | None],
            breakpoints) -> tuple[np.ndarray, np.ndarray, list, str]:
        """(t, Y, events, status) on the output grid ``t_out`` from y0 at t_start."""
        specs, event_fn = events
        t_start, t_end = float(self.options.t_start), float(self.options.t_end)
        # A table's samples are breakpoints: the solver starts again at each (`_input_run`).
        edges = [t_start, *(float(b) for b in breakpoints if t_start < b < t_end), t_end]
        segment = 0
        self.applied.window = 0.5 * (edges[0] + edges[1])
        solver = self.solver(t_start, y0, edges[1])
        N = len(t_out)
        Y = np.full((N, 2 * self.system.n), np.nan)
        i_out = 0
        while i_out < N and t_out[i_out] <= t_start:
            Y[i_out] = y0
            i_out += 1
        progress = self.options.progress
        report = progress_bar if progress is True else (progress or None)
        status = "completed"
        evs: list[tuple[str, float, np.ndarray]] = []
        g_old = event_fn(t_start, y0) if event_fn else None
        while solver.status == "running" or (solver.status == "finished" and segment + 2 < len(edges)):
            if solver.status == "finished":  # the next interval between two breakpoints of the inputs
                segment += 1
                self.applied.window = 0.5 * (edges[segment] + edges[segment + 1])
                solver = self.solver(edges[segment], solver.y.copy(), edges[segment + 1])
            t_old, t_new, state, raw_state = self.step(solver)
            t_stop = None
            if event_fn is not None:
                g_new = event_fn(t_new, solver.y)
                t_stop = _crossings(specs, event_fn, g_old, g_new, t_old, t_new, state, evs)
                g_old = g_new
            while i_out < N and t_out[i_out] <= t_new and (t_stop is None or t_out[i_out] <= t_stop):
                Y[i_out] = raw_state(t_out[i_out])
                i_out += 1
            if report:
                report(min(1.0, (t_new - t_start) / (t_end - t_start)), t_new)
            if t_stop is not None:
                status = "stopped by a terminal event"
                evs = [e for e in evs if e[1] <= t_stop]
                break
        evs.sort(key=lambda e: e[1])
        if self.projecting and i_out:
            Y[:i_out] = project_many(self.system, t_out[:i_out], Y[:i_out], self.p, self.tol)[0]
        self.applied.window = None
        return t_out[:i_out], Y[:i_out], evs, status


def _crossings(specs: list[EventSpec], event_fn: Callable, g_old, g_new, t_old: float, t_new: float,
               state: Callable, evs: list) -> float | None:
    """The events crossed in one step, located by Brent's method on the projected dense output and
    added to ``evs``; the earliest terminal one's time (None: none)."""
    from scipy.optimize import brentq

    t_stop = None
    for k, spec in enumerate(specs):
        a, b = g_old[k], g_new[k]
        crossed = (a < 0 <= b and spec.direction >= 0) or (a > 0 >= b and spec.direction <= 0)
        if not crossed or a == 0:
            continue
        te = brentq(lambda s, k=k: event_fn(s, state(s))[k], t_old, t_new, xtol=4e-16 * max(1.0, abs(t_new)))
        evs.append((spec.name, float(te), state(te)))
        if spec.terminal:
            t_stop = te if t_stop is None else min(t_stop, te)
    return t_stop


def _trajectory(system: ConstrainedSystem, p, t, Y, stab, evs, method, stabilization, steps, nfev,
                tolerance, status, *, residual_tolerance: float | None = None,
                applied: InputsAt | None = None) -> Trajectory:
    """The `Trajectory` of a run; ``tolerance`` for the first integrals, ``residual_tolerance``
    (default ``tolerance``) for the constraint residuals."""
    if residual_tolerance is None:
        residual_tolerance = tolerance
    n = system.n
    Y = np.ascontiguousarray(Y)
    M = None
    if len(t):
        if applied is None:
            applied = InputsAt(resolve_inputs(system.eom, {}), system.eom, system.parameters, p)
        dY, LAM = rowwise(lambda t_, Y_, p_: system.rhs(t_, Y_, p_, stab), t, Y, applied)
        M, _, _, _, g, f = system.parts(t, Y, p)
        values = rowwise(system.monitor_values, t, Y, applied)
        reactions = np.concatenate([system.reaction_values(t[k:k + 1], Y[k:k + 1], LAM[k:k + 1], applied(t[k], Y[k]))
                                    for k in range(len(t))]) if applied.evaluate is not None else \
            system.reaction_values(t, Y, LAM, p)
    else:
        dY, LAM = np.zeros((0, 2 * n)), np.zeros((0, system.m))
        g = f = np.zeros((0, system.m))
        values, reactions = np.zeros((0, len(system.monitors))), np.zeros((0, len(system.reactions)))
    monitors = {name: values[:, k].copy() for k, name in enumerate(system.monitors)}
    drift, scales = conservation(monitors, system.integrals, momenta=momenta(system.eom, system.integrals),
                                 M=None if M is None else np.asarray(M).reshape(len(t), n, n), qd=Y[:, n:])
    constraint_drift = {}
    for k, row in enumerate(system.rows):
        if system.holonomic[k]:
            constraint_drift[f"drift_{row}"] = f[:, k].copy()
        constraint_drift[f"drift_{row}_dot"] = g[:, k].copy()
    monitors.update(constraint_drift)
    drift.update({name: float(np.max(np.abs(s), initial=0.0)) for name, s in constraint_drift.items()})
    warnings = tuple(
        f"{name} drifted by {drift[name]:.2e} (relative), more than the tolerance {tolerance:.1e}"
        for name in system.integrals if tolerance is not None and drift[name] > tolerance)
    warnings += tuple(
        f"the constraint residual {name} reached {drift[name]:.2e}, more than the tolerance "
        f"{residual_tolerance:.1e}"
        for name in constraint_drift if residual_tolerance is not None and drift[name] > residual_tolerance)
    extra = {f"lambda_{row}": LAM[:, k].copy() for k, row in enumerate(system.rows)}
    if applied is not None:
        extra.update(applied.columns(t, Y))
    extra.update({name: reactions[:, k].copy() for k, name in enumerate(system.reactions)})
    events = tuple(Event(name, te, np.array(ye[:n]), np.array(ye[n:])) for name, te, ye in evs)
    label = EXPLICIT.get(method, method).lower() if method in EXPLICIT else method
    return Trajectory(
        model_name=system.eom.model.name, coordinates=tuple(system.coordinates),
        parameters={k: v for k, v in known_values(system.parameters, p).items()
                    if applied is None or k not in applied.names},
        t=np.asarray(t, dtype=float), q=Y[:, :n].copy(), qd=Y[:, n:].copy(), qdd=dY[:, n:].copy(),
        monitors=monitors, integrals=tuple(system.integrals), drift=drift,
        method=f"{label} + {stabilization}", steps=steps, rhs_calls=nfev, tolerance=tolerance, warnings=warnings,
        events=events, status=status, conditioning=system.worst_pivot, extra=extra, scales=scales,
    )
