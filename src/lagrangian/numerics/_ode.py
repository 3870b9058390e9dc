"""The compiled ODE route: M q̈ = F integrated in C (DOP853, Gauss–Legendre) or by SciPy's methods.

The run itself happens in compiled C (`codegen/runtime/integrators.c`): Python sets it up, calls it once,
and turns the preallocated output arrays into a `Trajectory`.  Memory is the output grid,
whatever the number of steps.  A progress bar is drawn by a second thread that reads the
time the C loop reached (ctypes releases the GIL during the call), so the run is the same,
bit for bit, with or without it.  The call runs in a worker thread (`_control.interruptible`)
so that Ctrl-C reaches the main thread at once: it then sets the control block's stop
request, the C loop returns at its next step, and `Interrupted` (a `KeyboardInterrupt`)
carries the part computed so far.

Methods
-------
``"dop853"`` (default)
    Adaptive explicit Runge–Kutta 8(5,3) with 7th-order dense output (Hairer, Nørsett &
    Wanner), the algorithm of SciPy's ``DOP853`` run in C.  With ``dt`` it takes fixed steps.
``"gauss-legendre"``
    Fixed-step 2-stage Gauss–Legendre (order 4) on Hamilton's equations in (q, p):
    symplectic, for long conservative runs whose energy must not drift.
``"RK45"``, ``"RK23"``, ``"DOP853"``, ``"Radau"``, ``"BDF"``, ``"LSODA"``
    SciPy's ``solve_ivp`` with that method, driven by the compiled right-hand side (`_scipy_run`).

Inputs (``inputs=``, `_inputs`): numbers, expressions, tables and feedbacks are compiled into
the right-hand side; a table's sample times are breakpoints where every method stops and
starts again (`_input_run`).  The applied inputs are columns of the `Trajectory`.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from pathlib import Path

import numpy as np

from ..dynamics import EquationsOfMotion, derive
from ..errors import Interrupted, SimulationError
from ..model import load_model
from ..model.spec import Model
from ._control import GAUSS_HALVINGS, INTERRUPTED, STATUS, STIFF, control_block, gauss_step, interruptible
from ._input_run import arm_callback, check_callback, input_columns, system_for
from ._mass_spectrum import mass_eigenvalues, mass_eigh
from ._options import BUILTIN, SCIPY, SimulationOptions, default_tolerance
from ._progress import Watch, make_reporter
from ._scipy_run import run_scipy
from ._setup import EventSpec, event_expressions, initial_state, momenta, output_times
from ._system import CompiledSystem, _ptr, known_values
from ._trajectory import Event, Trajectory, conservation

__all__ = ["check_ode_options", "early_stop", "resolve", "run_ode", "singularity", "state_text", "trajectory"]


def state_text(system: CompiledSystem, y: np.ndarray) -> str:
    return ", ".join(f"{name} = {v:.6g}" for name, v in zip(system.coordinates, y[: system.n], strict=True))


def singularity(system: CompiledSystem, t: float, y: np.ndarray, p: np.ndarray, where: str) -> SimulationError:
    """Explain a singular M: which rates its null vector mixes, so the user sees why.

    When M or F is not even finite there (``log(psi)`` at psi = 0, a division by zero), say
    that instead: no eigenvalue of a matrix of nan explains anything.
    """
    M, F = system.mass_forces(t, y, p)
    names = system.coordinates
    bad = ([f"M[{names[i]},{names[j]}]" for i, j in zip(*np.nonzero(~np.isfinite(M)), strict=True)]
           + [f"F[{names[i]}]" for i in np.flatnonzero(~np.isfinite(F))])
    if bad:
        shown = ", ".join(bad[:4]) + (f" and {len(bad) - 4} more" if len(bad) > 4 else "")
        return SimulationError(
            f"M(q, t) q'' = F is not defined {where} (t = {t:.9g}, {state_text(system, y)}): {shown} "
            "not finite; the state is outside the domain of a function of the model (log or sqrt of a "
            "non-positive number, a division by zero) or a value overflows.",
            fix="start from a state where every expression of the model is defined, or correct the expression",
            t=t, state=y.copy())
    w, v = mass_eigh(M)
    null = v[:, 0]
    parts = [f"{c:+.2f} {name}_dot" for c, name in zip(null, system.coordinates, strict=True) if abs(c) > 0.1]
    involved = [name for c, name in zip(null, system.coordinates, strict=True) if abs(c) > 0.1]
    if len(involved) == 1:
        why = f"M has (almost) no inertia along {involved[0]}, so {involved[0]}_ddot is not defined there."
    else:
        why = (f"the motion along ({' '.join(parts)}) has no inertia, so the rates "
               f"{', '.join(n + '_dot' for n in involved)} are not independent there and q'' is not defined. "
               f"The coordinates are singular at this configuration, as Euler angles are when two rotation "
               f"axes align (theta = 0 or pi).")
    return SimulationError(
        f"The mass matrix M is singular {where} (t = {t:.9g}, {state_text(system, y)}; smallest "
        f"eigenvalue {w[0]:.3g}, largest {w[-1]:.3g}): {why}",
        fix="start away from this configuration, or describe the system with coordinates that are regular "
            "there (e.g. rotate the reference frame so the motion stays away from the singular angle); masses or "
            "inertias more than 1e12 apart make M singular in double precision too",
        t=t, state=y.copy())

def resolve(source, events: Sequence[EventSpec], backend: str, inputs=None,
             parameters: Mapping[str, float] | None = None) -> CompiledSystem:
    if isinstance(source, CompiledSystem):
        eom = source.eom
    elif isinstance(source, EquationsOfMotion):
        eom = source
    elif isinstance(source, Model):
        eom = derive(source)
    elif isinstance(source, (str, Path)):
        eom = derive(load_model(source))
    else:
        raise TypeError("simulate() takes a model file, a Model, an EquationsOfMotion or a CompiledSystem")
    compiled = [(e.name, e.expression) for e in event_expressions(eom, events)] if events else []
    return system_for(source, eom, compiled, backend, inputs, parameters)

def check_ode_options(options: SimulationOptions) -> None:
    """Refuse what the plain ODE route cannot do: a stabilization (no constraint is complementary)."""
    if options.stabilization is not None:
        raise SimulationError(f"stabilization={options.stabilization!r} applies to models with complementary "
                              "constraints, and this one keeps none complementary.",
                              fix="leave the stabilization out (its coordinates are all principal)")


def run_ode(source, options: SimulationOptions) -> Trajectory:
    """Integrate M q̈ = F of ``source`` (no complementary constraint) with ``options.method``.

    Raises
    ------
    SimulationError
        A stabilization asked for, a built-in method without a C compiler, a singular M at the
        start or during the run, a failed step; stiff equations or ``max_steps`` reached carry
        the part computed so far (``error.trajectory``).
    """
    check_ode_options(options)
    method, rtol = options.method, options.rtol
    tolerance = default_tolerance(method, rtol) if options.tolerance is None else options.tolerance
    specs = [EventSpec(e, e) if isinstance(e, str) else e for e in options.events]
    system = resolve(source, specs, options.backend, options.inputs, options.parameters)
    if not specs:  # events compiled into the system: both directions, none terminal
        specs = [EventSpec(name, name) for name in system.events]
    if method in BUILTIN and system.backend != "c":
        raise SimulationError(f"The method `{method}` runs in compiled C, and no C compiler was found.",
                              fix="install a C compiler (e.g. gcc), or use a SciPy method such as method='DOP853'")
    p = system.parameter_vector(options.parameters)
    y0 = initial_state(system.eom, options.initial)
    t_start, t_end = options.t_start, options.t_end
    t_out = output_times(float(t_start), float(t_end), options.n_out, options.t_eval,
                         4 * system.n + len(system.monitors) + 1)
    _check_start(system, t_start, y0, p)
    if method in SCIPY:
        arm_callback(system, None)
        t_o, Y, evs, nfev, steps, code = run_scipy(system, p, y0, t_start, t_end, t_out, method, rtol, options.atol,
                                                   options.max_step, specs, options.progress)
        status = "completed" if code == 0 else "stopped by a terminal event"
        conditioning = _pivot(system, t_o, Y, p)
    else:
        t_o, Y, evs, nfev, steps, status, conditioning = _run_builtin(
            system, p, y0, t_start, t_end, t_out, method, rtol, options.atol, options.dt, options.max_step,
            options.max_steps, specs, options.progress, options.stiffness_check)
        if isinstance(status, SimulationError):  # stiff, or max_steps: the part computed so far goes with it
            if len(t_o) > 0:
                status.trajectory = trajectory(system, p, t_o, Y, evs, method, steps, nfev, tolerance,
                                               f"stopped at t = {status.t:.9g} (partial): {status.reason}",
                                               conditioning)
            raise status
    if isinstance(status, Interrupted):
        if len(t_o) > 0:
            status.trajectory = trajectory(system, p, t_o, Y, evs, method, steps, nfev, tolerance,
                                           f"interrupted at t = {status.t:.9g} (partial)", conditioning)
        raise status
    return trajectory(system, p, t_o, Y, evs, method, steps, nfev, tolerance, status, conditioning)


def _check_start(system: CompiledSystem, t_start: float, y0: np.ndarray, p: np.ndarray) -> None:
    """A singular M (or M, F not finite) at the start is reported before anything runs."""
    M, F0 = system.mass_forces(t_start, y0, p)
    check_callback(system)  # a Python input function that fails at the start says so itself
    if not (np.isfinite(M).all() and np.isfinite(F0).all()):  # nan: no eigenvalue (LinAlgError), say why
        raise singularity(system, t_start, y0, p, "at the initial state")
    w = mass_eigenvalues(M)
    if not w[0] > 1e-12 * max(abs(w[-1]), 1e-300):
        raise singularity(system, t_start, y0, p, "at the initial state")


def _pivot(system, t, Y, p) -> float:
    """Smallest relative Cholesky pivot of M over the given states (as the C code tracks it)."""
    M, _ = system.mass_forces(t, Y, p)
    M = np.atleast_3d(M) if M.ndim == 2 else M
    diag = np.abs(np.diagonal(M, axis1=-2, axis2=-1))
    if not np.isfinite(M).all():
        return 0.0
    try:
        L = np.linalg.cholesky(M)
    except np.linalg.LinAlgError:  # M not positive definite at some output state: no pivot, not a crash
        return 0.0
    return float(np.min(np.diagonal(L, axis1=-2, axis2=-1) ** 2 / diag)) if len(M) else 1.0


def _run_builtin(system, p, y0, t_start, t_end, t_out, method, rtol, atol, dt, max_step, max_steps, specs,
                 progress, stiffness_check=True):
    if dt is not None and not dt > 0:
        raise SimulationError(f"dt = {dt} must be positive.", fix="give a positive step, e.g. dt=1e-3")
    given = dt is not None
    h = gauss_step(t_start, t_end, t_out, dt) if method == "gauss-legendre" else None
    reporter = make_reporter(progress, t_start, t_end)
    halvings = 0
    while True:
        code, ctl, y, Y, i_out, ev_out, capacity = _attempt(system, p, y0, t_start, t_end, t_out, method, rtol, atol,
                                                            dt, h, max_step, max_steps, specs, reporter,
                                                            stiffness_check)
        # The default step failed (stages not converging, or a blow-up): the same fixed-step run with
        # half the step, from the start, so that every step of the result has the same length.
        if method != "gauss-legendre" or given or code not in (2, 6) or halvings == GAUSS_HALVINGS:
            break
        halvings += 1
        h /= 2
    if reporter:
        reporter.finish(float(ctl[0]), code in (0, 4))
    n_ev = int(min(ctl[10], capacity))
    evs = [(specs[int(r[0])].name, r[1], r[2:]) for r in ev_out[:n_ev]]
    if code == INTERRUPTED:
        m = int(i_out[0])
        return t_out[:m], Y[:m], evs, int(ctl[5]), int(ctl[6]), Interrupted(float(ctl[0])), float(ctl[12])
    if code in (0, 4):
        m = int(i_out[0])
        return t_out[:m], Y[:m], evs, int(ctl[5]), int(ctl[6]), "completed" if code == 0 else \
            "stopped by a terminal event", float(ctl[12])
    t_fail = float(ctl[0])
    if code in (STIFF, 5):  # stopped early, not failed: what was computed so far is returned with the error
        m = int(i_out[0])
        return t_out[:m], Y[:m], evs, int(ctl[5]), int(ctl[6]), early_stop(system, code, ctl, y), float(ctl[12])
    if code == 1 or (code in (2, 3) and _collapsed(system, t_start, y0, t_fail, y, p)):
        raise singularity(system, t_fail, y, p, "during the integration")
    fixes = {3: "the equations may be stiff or singular there: try method='Radau', or check the model"}
    if method == "gauss-legendre" and code in (2, 6):
        if given:  # the user's step is too long for the fastest motion (a stiff spring, a fast spin)
            fixes[code] = (f"reduce the step: dt = {h:.3g} is too long for the fastest motion of the model "
                           f"(a stiff spring, a fast spin); try dt={h / 10:.3g} (--dt {h / 10:.3g} on the command line)")
        else:
            fixes[code] = (f"the default step was halved {GAUSS_HALVINGS} times, down to dt = {h:.3g}: the equations "
                           "are stiff there; give a smaller dt (--dt), or use method='Radau' (SciPy)")
    elif code == 6:
        fixes[6] = "use a smaller dt"
    raise SimulationError(
        f"The integration stopped at t = {t_fail:.9g} ({state_text(system, y)}): {STATUS[code]}.",
        fix=fixes.get(code, "check the model and the initial state"), t=t_fail, state=y.copy())


def early_stop(system, code: int, ctl: np.ndarray, y: np.ndarray) -> SimulationError:
    """The error of a run that dop853's stiffness test (code 8) or ``max_steps`` (code 5) stopped."""
    t = float(ctl[0])
    if code == STIFF:
        reason = "the equations are stiff"
        err = SimulationError(
            f"The integration stopped at t = {t:.9g} ({state_text(system, y)}): the equations are stiff there. "
            f"dop853's stiffness test (Hairer) found the step limited by stability, not by accuracy: "
            f"h|λ| ≈ {ctl[17]:.3g} > 6.1 for 15 steps in a row (step h = {ctl[1]:.3g}), so an explicit method "
            f"would crawl at that step to the end.",
            fix="use an implicit method: --method Radau (or BDF, LSODA; method='Radau'), or make the stiff part "
                "softer (a smaller stiffness or damping coefficient); --no-stiffness-check (stiffness_check=False) "
                "goes on with dop853 all the same", t=t, state=y.copy())
    elif ctl[21] > 0:  # the pace check: max_steps could not be enough, said at once rather than at the end
        reason = "the maximum number of steps would be reached"
        err = SimulationError(
            f"The integration stopped at t = {t:.9g} ({state_text(system, y)}): at its step size "
            f"(h ≈ {ctl[1]:.3g} now) the run would need about {ctl[21]:.3g} steps, more than max_steps ({int(ctl[9])}). The model moves much "
            f"faster than the time span: its fastest motion (a very stiff spring, a fast spin) lasts a few steps.",
            fix="shorten the time span, soften the fast part (a smaller stiffness), or raise max_steps",
            t=t, state=y.copy())
    else:
        reason = "the maximum number of steps was reached"
        err = SimulationError(f"The integration stopped at t = {t:.9g} ({state_text(system, y)}): {STATUS[5]} "
                              f"({int(ctl[9])}).", fix="raise max_steps, or shorten the time span",
                              t=t, state=y.copy())
    err.reason = reason  # type: ignore[attr-defined]
    return err


def _attempt(system, p, y0, t_start, t_end, t_out, method, rtol, atol, dt, h, max_step, max_steps, specs, reporter,
             stiffness_check=True):
    """One call of the compiled integrator over the whole span (gauss-legendre with the step ``h``)."""
    n2 = 2 * system.n
    ctl = control_block(method, t_start, t_end, t_out, rtol, atol, dt, max_step, max_steps, h, stiffness_check)
    y = y0.copy()
    Y = np.full((len(t_out), n2), np.nan)
    i_out = np.zeros(1, dtype=np.intc)
    ev_dir = np.array([e.direction for e in specs] or [0], dtype=np.intc)
    ev_term = np.array([int(e.terminal) for e in specs] or [0], dtype=np.intc)
    capacity = 100_000 if specs else 1
    ctl[11] = capacity
    ev_out = np.zeros((capacity, 2 + n2))
    lib = system._lib
    # One call for the whole run, whether or not progress is shown: a chunked run would cut a
    # step at each chunk's end, and the result would depend on the progress bar.
    if method == "dop853":
        def call():
            return lib.lg_dop853(_ptr(ctl), _ptr(y), _ptr(p), _ptr(t_out), len(t_out), _ptr(i_out), _ptr(Y),
                                 float(t_end), _ptr(ev_dir), _ptr(ev_term), _ptr(ev_out))
    else:
        def call():
            return lib.lg_gauss(_ptr(ctl), _ptr(y), _ptr(p), _ptr(t_out), len(t_out), _ptr(i_out), _ptr(Y),
                                float(t_end), _ptr(ev_dir), _ptr(ev_term), _ptr(ev_out), float(t_start))
    arm_callback(system, ctl)
    with Watch(reporter, ctl):
        code = interruptible(call, ctl)
    check_callback(system)  # a Python input function failed: its error, not an interruption
    return code, ctl, y, Y, i_out, ev_out, capacity

def _collapsed(system, t0, y0, t, y, p) -> bool:
    """Whether M lost (almost) all its inertia in some direction since the start: then a
    step-size underflow or an overflow is the singularity showing, and is reported as one."""
    M0, M = system.mass_forces(t0, y0, p)[0], system.mass_forces(t, y, p)[0]
    if not (np.isfinite(M0).all() and np.isfinite(M).all()):
        return True  # M undefined there: `_singularity` says which entries
    w0 = mass_eigenvalues(M0)
    w = mass_eigenvalues(M)
    return bool(w[0] < 1e-8 * w0[-1])

def trajectory(system, p, t, Y, evs, method, steps, nfev, tolerance, status, conditioning) -> Trajectory:
    n = system.n
    Y = np.ascontiguousarray(Y)
    columns = input_columns(system, t, Y, p)
    qdd = system.rhs(t, Y, p)[:, n:] if len(t) else np.zeros((0, n))
    values = system.monitor_values(t, Y, p) if len(t) else np.zeros((0, len(system.monitors)))
    monitors = {name: values[:, k].copy() for k, name in enumerate(system.monitors)}
    M = system.mass_forces(t, Y, p)[0].reshape(len(t), n, n) if len(t) else None
    drift, scales = conservation(monitors, system.integrals, momenta=momenta(system.eom, system.integrals), M=M,
                                 qd=Y[:, n:])
    warnings = tuple(
        f"{name} drifted by {drift[name]:.2e} (relative), more than the tolerance {tolerance:.1e}"
        for name in system.integrals if tolerance is not None and drift[name] > tolerance)
    if conditioning < 1e-6:
        warnings += ((f"the motion passed close to a singular configuration of the coordinates (M's smallest "
                      f"relative pivot fell to {conditioning:.1e}): accuracy may be lost there; check the drift "
                      f"of the first integrals, or choose coordinates that are regular along this motion"),)
    events = tuple(Event(name, float(te), np.array(ye[:n]), np.array(ye[n:])) for name, te, ye in evs)
    parameters = {k: v for k, v in known_values(system.parameters, p).items() if k not in system.inputs}
    return Trajectory(
        model_name=system.eom.model.name,
        coordinates=tuple(system.coordinates),
        parameters=parameters,
        t=np.asarray(t, dtype=float), q=Y[:, :n].copy(), qd=Y[:, n:].copy(), qdd=qdd,
        monitors=monitors, integrals=tuple(system.integrals), drift=drift, method=method, steps=steps,
        rhs_calls=nfev, tolerance=tolerance, warnings=warnings, events=events, status=status,
        conditioning=conditioning, scales=scales, extra=columns,
    )
