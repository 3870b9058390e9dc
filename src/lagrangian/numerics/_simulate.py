"""`simulate`: integrate M q̈ = F from the model's initial state, with conservation monitors.

The run itself happens in compiled C (`_integrators.c`): Python sets it up, calls it once,
and turns the preallocated output arrays into a `Trajectory`.  Memory is the output grid,
whatever the number of steps.  A progress bar is drawn by a second thread that reads the
time the C loop reached (ctypes releases the GIL during the call), so the run is the same,
bit for bit, with or without it.  The call runs in a worker thread so that Ctrl-C reaches the
main thread at once: it then sets the control block's stop request, the C loop returns at its
next step, and `Interrupted` (a `KeyboardInterrupt`) carries the part computed so far.

Methods
-------
``"dop853"`` (default)
    Adaptive explicit Runge–Kutta 8(5,3) with 7th-order dense output (Hairer, Nørsett &
    Wanner), the algorithm of SciPy's ``DOP853`` run in C.  With ``dt`` it takes fixed steps.
``"gauss-legendre"``
    Fixed-step 2-stage Gauss–Legendre (order 4) on Hamilton's equations in (q, p):
    symplectic, for long conservative runs whose energy must not drift.
``"RK45"``, ``"RK23"``, ``"DOP853"``, ``"Radau"``, ``"BDF"``, ``"LSODA"``
    SciPy's ``solve_ivp`` with that method, driven by the compiled right-hand side.

Inputs (``inputs=``, `_inputs`): numbers, expressions, tables and feedbacks are compiled into
the right-hand side; a table's sample times are breakpoints where every method stops and
starts again (`_input_run`).  The applied inputs are columns of the `Trajectory`.
"""

from __future__ import annotations

import math
import os
import threading
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np
import symengine as se

from ..dynamics import EquationsOfMotion, derive
from ..errors import Interrupted, ModelError, SimulationError
from ..model import load_model
from ..model._assumptions import check_sign
from ..model._expr import ExpressionError, parse_expression
from ..model.spec import Model
from ._dae import BAUMGARTE, ConstrainedSystem, constrained_source, simulate_dae
from ._input_run import arm_callback, check_callback, constant_inputs_only, input_columns, solve_in_segments, system_for
from ._mass_spectrum import mass_eigenvalues, mass_eigh
from ._progress import Reporter, Watch, make_reporter
from ._ranges import watch_ranges
from ._system import CompiledSystem, _ptr, known_values
from ._trajectory import Event, Trajectory, conservation

if TYPE_CHECKING:
    from ._sensitivity import Sensitivities

__all__ = ["METHODS", "EventSpec", "control_block", "default_tolerance", "initial_state", "simulate"]

BUILTIN = ("dop853", "gauss-legendre")
SCIPY = ("RK45", "RK23", "DOP853", "Radau", "BDF", "LSODA")
METHODS = BUILTIN + SCIPY

#: Smallest rtol, about 50 machine epsilons: a tighter local tolerance than this cannot be met by
#: a step in double precision (SciPy clips rtol at 100 epsilons; the built-in DOP853 still
#: converges at 1e-14).
RTOL_MIN = 1e-14
#: The drift tolerance when none is given: adaptive methods warn above min(1e3 rtol, 1e-6);
#: the symplectic method (no rtol) above 1e-6.
DEFAULT_TOLERANCE_FACTOR, DEFAULT_TOLERANCE_CAP = 1e3, 1e-6
#: Largest output the arrays of a run may take (bytes): at most this, or a quarter of the memory.
OUTPUT_MEMORY_CAP = 8 * 2**30

_STATUS = {
    1: "the mass matrix M became singular",
    2: "the state stopped being finite (overflow)",
    3: "the step size fell below the resolution of t, or below 1e-14 of the time span (step size underflow)",
    5: "the maximum number of steps was reached",
    6: "the implicit stages of the Gauss-Legendre step did not converge",
}
_STIFF = 8  # LG_STIFF: dop853's stiffness test fired (`_integrators.c`, lg_dop_stiff)
#: dop853's NSTIFF: the stiffness test runs every this many accepted steps (then at every step while
#: the problem looks stiff), as in Hairer's dop853.f.
STIFFNESS_TEST_PERIOD = 1000
#: Doubles in the control block, C_SIZE in `_integrators.c` (`lg_batch` copies that many from it).
CONTROL_SIZE = 22
_INTERRUPTED = 7  # LG_INTERRUPTED: the stop request ctl[_C_STOP] was seen
_C_STOP = 13


@dataclass(frozen=True)
class EventSpec:
    """An event: the times where ``expression`` g(t, q, q̇) crosses zero.

    ``expression`` is text in the model's grammar (``"theta_dot"``, ``"theta - 0.3"``) or
    a SymEngine expression.  ``direction``: +1 only rising crossings, −1 only falling,
    0 both.  A ``terminal`` event stops the run at its first occurrence.
    """

    name: str
    expression: str | se.Basic
    direction: int = 0
    terminal: bool = False


def _names(eom: EquationsOfMotion) -> dict[str, se.Basic]:
    names: dict[str, se.Basic] = {"t": eom.t}
    for c, q, qd in zip(eom.model.coordinates, eom.q, eom.qd, strict=True):
        names[c.name] = q
        names[c.name + "_dot"] = qd
    for p in eom.model.parameters:
        names[p.name] = se.Symbol(p.name)
    return names


def _event_expressions(eom: EquationsOfMotion, events: Sequence[EventSpec | str]) -> list[EventSpec]:
    specs = []
    names = _names(eom)
    for ev in events:
        spec = EventSpec(ev, ev) if isinstance(ev, str) else ev
        expr = spec.expression
        if isinstance(expr, str):
            try:
                # The frames are known so that `R0.x` reads as the vector it is, refused below as not a
                # scalar, rather than as an "unknown frame R0".
                expr = parse_expression(expr, names, [f.name for f in eom.model.frames])
            except ExpressionError as exc:
                raise ModelError(f"In the event `{spec.name}`: {exc.message}", fix=exc.fix,
                                 symbol=exc.symbol) from None
            if not isinstance(expr, se.Basic) or hasattr(expr, "components"):
                raise ModelError(f"The event `{spec.name}` must be a scalar expression: `{spec.name}` is a vector.",
                                 fix="write a scalar of the coordinates, their rates and t, such as `theta_dot` or "
                                     "`theta - 0.3` (an event is where it crosses zero)")
        if spec.direction not in (-1, 0, 1):
            raise ValueError("EventSpec.direction must be -1, 0 or 1")
        specs.append(EventSpec(spec.name, expr, spec.direction, spec.terminal))
    return specs


def initial_state(eom: EquationsOfMotion, initial: Mapping[str, float] | None = None) -> np.ndarray:
    """y(t0) = (q(t0), q̇(t0)) from the model's ``initial``/``rate`` values and the overrides.

    ``initial`` maps a coordinate name to q_i(t0) and ``<name>_dot`` to q̇_i(t0).

    Raises
    ------
    SimulationError
        For an unknown name, a missing value or a value that is not finite.
    """
    initial = dict(initial or {})
    coords = eom.model.coordinates
    known = [c.name for c in coords] + [c.name + "_dot" for c in coords]
    unknown = sorted(set(initial) - set(known))
    if unknown:
        raise SimulationError(f"`{unknown[0]}` is neither a coordinate nor a coordinate's rate.",
                              fix="initial values can be given for " + ", ".join(known))
    y = np.empty(2 * len(coords))
    for i, c in enumerate(coords):
        for k, (key, value, what) in enumerate(((c.name, c.initial, "initial"), (c.name + "_dot", c.rate, "rate"))):
            v = initial.get(key, value)
            if v is None:
                raise SimulationError(
                    f"The coordinate `{c.name}` has no initial {'value' if k == 0 else 'rate'}.",
                    fix=f"give it in the model file (`{c.name} = {{ {what} = ... }}` under [coordinates]) "
                        f"or on the command line (`--set {key}=...`)")
            v = float(v)
            if not np.isfinite(v):
                raise SimulationError(f"The initial value of `{key}` is {v}, not a finite number.",
                                      fix=f"give `{key}` a finite value")
            y[i + k * len(coords)] = v
    return y


def _state_text(system: CompiledSystem, y: np.ndarray) -> str:
    return ", ".join(f"{name} = {v:.6g}" for name, v in zip(system.coordinates, y[: system.n], strict=True))


def _singularity(system: CompiledSystem, t: float, y: np.ndarray, p: np.ndarray, where: str) -> SimulationError:
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
            f"M(q, t) q'' = F is not defined {where} (t = {t:.9g}, {_state_text(system, y)}): {shown} "
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
        f"The mass matrix M is singular {where} (t = {t:.9g}, {_state_text(system, y)}; smallest "
        f"eigenvalue {w[0]:.3g}, largest {w[-1]:.3g}): {why}",
        fix="start away from this configuration, or describe the system with coordinates that are regular "
            "there (e.g. rotate the reference frame so the motion stays away from the singular angle); masses or "
            "inertias more than 1e12 apart make M singular in double precision too",
        t=t, state=y.copy())


def default_tolerance(method: str, rtol: float) -> float:
    """The drift above which a first integral gets a warning when no ``tolerance`` is given.

    min(1e3 rtol, 1e-6) for the adaptive methods (a drift a thousand times the local
    tolerance, or above a millionth, is accuracy lost, not round-off); 1e-6 for
    ``gauss-legendre``, whose energy error depends on dt, not on rtol.
    """
    if method == "gauss-legendre":
        return DEFAULT_TOLERANCE_CAP
    return min(DEFAULT_TOLERANCE_FACTOR * rtol, DEFAULT_TOLERANCE_CAP)


def check_options(rtol: float, atol: float, tolerance: float | None) -> None:
    """Refuse tolerances that cannot work, before anything is compiled or run."""
    if not (rtol > 0 and atol > 0) or not (math.isfinite(rtol) and math.isfinite(atol)):
        raise SimulationError(f"rtol = {rtol:g} and atol = {atol:g}: both must be positive finite numbers.",
                              fix="e.g. rtol=1e-10, atol=1e-10")
    if rtol < RTOL_MIN:
        raise SimulationError(f"rtol = {rtol:g} is below {RTOL_MIN:.0e}, about 50 machine epsilons: no step of a "
                              f"double-precision integrator can be that accurate, so the step size would shrink "
                              f"to nothing.", fix=f"use rtol >= {RTOL_MIN:.0e} (e.g. 1e-13)")
    if tolerance is not None and not (tolerance > 0 and not math.isnan(tolerance)):
        raise SimulationError(f"The drift tolerance {tolerance:g} must be a positive number.",
                              fix="e.g. tolerance=1e-9 (--tolerance 1e-9), or leave it out for the default")


def _memory_limit() -> float:
    try:
        physical = os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_PHYS_PAGES")
    except (ValueError, OSError, AttributeError):
        physical = 4 * OUTPUT_MEMORY_CAP
    return min(OUTPUT_MEMORY_CAP, physical / 4)


def _output_times(t_start: float, t_end: float, n_out: int | None, t_eval, width: int = 16) -> np.ndarray:
    """The output grid; ``width``: numbers stored per output time (to refuse a grid too big for memory)."""
    for name, value in (("start", t_start), ("end", t_end)):
        if not np.isfinite(value):
            raise SimulationError(f"The {name} time {value} is not finite.",
                                  fix=f"give a finite {name} time (e.g. --t-{name} {0 if name == 'start' else 10})")
    if not t_end > t_start:
        raise SimulationError(f"The time span [{t_start}, {t_end}] is not increasing.",
                              fix="give an end time greater than the start time (e.g. --t-end 10)")
    if t_eval is not None:
        t_out = np.ascontiguousarray(t_eval, dtype=float)
        if t_out.ndim != 1 or len(t_out) == 0 or np.any(np.diff(t_out) <= 0) or t_out[0] < t_start \
                or t_out[-1] > t_end:
            raise SimulationError("The output times must be increasing and lie within [t_start, t_end].",
                                  fix="pass a sorted t_eval inside the time span")
        return t_out
    n_out = 1001 if n_out is None else int(n_out)
    if n_out < 2:
        raise SimulationError(f"n_out = {n_out}: at least 2 output times are needed.", fix="use n_out >= 2")
    # The state, q'', the monitors and the columns, each as float64, and a copy of them for the output.
    need = 2 * 8 * n_out * max(int(width), 1)
    limit = _memory_limit()
    if need > limit:
        most = int(limit // (2 * 8 * max(int(width), 1)))
        raise SimulationError(f"n_out = {n_out} output times would take about {need / 2**30:.1f} GiB of memory "
                              f"(more than the {limit / 2**30:.1f} GiB allowed).",
                              fix=f"use fewer output times (at most about {most}); the steps are not limited "
                                  f"by n_out, only what is stored")
    return np.linspace(t_start, t_end, n_out)


def _resolve(source, events: Sequence[EventSpec], backend: str, inputs=None,
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
    compiled = [(e.name, e.expression) for e in _event_expressions(eom, events)] if events else []
    return system_for(source, eom, compiled, backend, inputs, parameters)


def simulate(
    source,
    t_end: float,
    *,
    t_start: float = 0.0,
    initial: Mapping[str, float] | None = None,
    parameters: Mapping[str, float] | None = None,
    method: str = "dop853",
    rtol: float = 1e-10,
    atol: float = 1e-10,
    dt: float | None = None,
    max_step: float | None = None,
    n_out: int | None = None,
    t_eval=None,
    events: Sequence[EventSpec | str] = (),
    tolerance: float | None = None,
    max_steps: int = 100_000_000,
    progress: bool | Callable[[float, float], None] = False,
    backend: str = "auto",
    stabilization: str | None = None,
    baumgarte: tuple[float, float] = BAUMGARTE,
    stiffness_check: bool = True,
    sensitivities: Sequence[str] | Sensitivities | None = None,
    inputs=None,
) -> Trajectory:
    """Integrate the equations of motion from t_start to t_end.

    Parameters
    ----------
    source : a model file path, a `Model`, an `EquationsOfMotion` or a `CompiledSystem`.
    t_end, t_start : the time span (must increase).
    initial : overrides of q_i(t0) (``"theta": 0.3``) and q̇_i(t0) (``"phi_dot": 80``).
    parameters : overrides of the parameter values (``"g": 1.62``).
    method : ``"dop853"``, ``"gauss-legendre"`` or a SciPy method name (module docstring).
    rtol, atol : local error tolerances of the adaptive methods.
    dt : fixed step. ``"gauss-legendre"``: default 1/10 of the output spacing, halved (at most
        `GAUSS_HALVINGS` times, the run restarted) while its implicit stages do not converge; a dt smaller
        than the spacing is rounded down so that a whole number of steps fills it, a larger
        one is used as it is (the outputs are interpolated between steps). With ``"dop853"``
        it switches to fixed steps.
    n_out, t_eval : the output grid (default 1001 evenly spaced times).
    events : `EventSpec` items or expression strings; each crossing is recorded.
    tolerance : drift tolerance of the first integrals; a larger drift adds a warning.
        Default: `default_tolerance` (min(1e3 rtol, 1e-6); 1e-6 for ``gauss-legendre``).
    progress : True for a progress bar on standard error, or a callable(fraction, t),
        called at most every 0.1 s (from a second thread for the built-in methods) and
        once at the end. The result does not depend on it.
    stabilization, baumgarte : for models with complementary constraints only, how the
        drift from the constraints is controlled (``"projection"``, ``"baumgarte"``,
        ``"both"``, ``"none"``) and Baumgarte's rates (α, β); see `numerics._dae`.
    stiffness_check : ``"dop853"`` only: Hairer's stiffness test (as in dop853.f), which stops
        the run with a `SimulationError` once the step is limited by stability rather than
        accuracy (h|λ| > 6.1 for 15 steps in a row), where an implicit method (``"Radau"``)
        is the tool. False integrates a knowingly stiff problem explicitly all the same.
    inputs : what the declared inputs do (`lagrangian.numerics._inputs`): a dict by input name of
        numbers, expressions (``"2*sin(3*t)"``, ``"-k1*x - k2*x_dot"``), `InputTable` values, or
        Python functions ``u(t, y)`` (the slow path); or a `Feedback` (``lagrangian.lqr``), the
        closed loop compiled in.  Inputs not named follow the model's ``[controls]``, else stay
        at their value (0).  The applied inputs are columns of the result (``traj.column("F")``).
    sensitivities : parameter names and initial values (``["l", "m", "theta(t0)"]``, or a
        `lagrangian.numerics.Sensitivities`): ∂y(t)/∂x for each, integrated with the state
        (``dop853`` only; `numerics._sensitivity`), as the columns ``d(theta)/d(l)``...;
        ``trajectory.sensitivity("l")`` has shape (N, 2n).

    Returns
    -------
    Trajectory
        With the drift of every first integral (``trajectory.drift_summary()``).

    Raises
    ------
    SimulationError
        Missing or non-finite values, a time span that does not increase or is not finite,
        tolerances that cannot be met, an output grid too large for memory, a singular mass
        matrix (before or during the run: never a silent NaN), step-size underflow, overflow,
        stiff equations (``stiffness_check``) or ``max_steps`` reached; for the last two its
        ``trajectory`` is the part computed so far (status ``"... (partial)"``), or None.
    """
    check_options(rtol, atol, tolerance)
    from ._stickslip import exact_contact_model  # late: `_stickslip` imports this module

    # Declared signs and ranges (`model._assumptions`): values that break a sign are refused, and the
    # motion is checked against the ranges and the signs the derivation used (`_ranges`).
    if isinstance(source, (str, Path)):
        source = load_model(source)  # read once
    model = source if isinstance(source, Model) else getattr(getattr(source, "eom", source), "model", None)
    watched = model is not None and (any(c.range is not None for c in model.coordinates)
                                     or any(p.sign is not None for p in model.parameters))
    if watched:
        check_sign(model, parameters or {})  # type: ignore[arg-type]
        if isinstance(source, Model) and exact_contact_model(source) is None:
            source = derive(source)  # derived here once, for the signs it used
    if sensitivities is not None:
        from ._sensitivity import simulate_sensitivities

        if inputs is not None:
            raise SimulationError("Sensitivities are integrated with the inputs at their values: `inputs=` cannot "
                                  "be given with `sensitivities=`.",
                                  fix="give constant inputs as parameters (parameters={'F': 1.0}), or run the "
                                      "sensitivities without the inputs")

        traj = simulate_sensitivities(source, t_end, sensitivities, t_start=t_start, initial=initial,
                                      parameters=parameters, method=method, rtol=rtol, atol=atol, dt=dt,
                                      max_step=max_step, n_out=n_out, t_eval=t_eval, events=events,
                                      tolerance=tolerance, max_steps=max_steps, progress=progress, backend=backend,
                                      stabilization=stabilization, stiffness_check=stiffness_check)
    else:
        traj = _simulate(source, t_end, t_start=t_start, initial=initial, parameters=parameters, method=method,
                         rtol=rtol, atol=atol, dt=dt, max_step=max_step, n_out=n_out, t_eval=t_eval, events=events,
                         tolerance=tolerance, max_steps=max_steps, progress=progress, backend=backend,
                         stabilization=stabilization, baumgarte=baumgarte, stiffness_check=stiffness_check,
                         inputs=inputs)
    if not watched:
        return traj
    eom = source if isinstance(source, EquationsOfMotion) else getattr(source, "eom", None)
    return watch_ranges(model, traj, eom.assumptions if isinstance(eom, EquationsOfMotion) else ())  # type: ignore[arg-type]


def _simulate(source, t_end, *, t_start, initial, parameters, method, rtol, atol, dt, max_step, n_out, t_eval,
              events, tolerance, max_steps, progress, backend, stabilization, baumgarte,
              stiffness_check, inputs=None) -> Trajectory:
    """`simulate` once the source is read: the free-body, contact, stick-slip, constrained or plain run."""
    from ._contact import contact_model, simulate_contact  # late: `_contact` imports this module
    from ._free_simulate import free_source, simulate_free  # late: both import this module
    from ._stickslip import exact_contact_model, simulate_stick_slip

    free = free_source(source)
    if free is not None:  # free bodies: integrated on unit quaternions, reported in the model's angles
        parameters = constant_inputs_only(source, inputs, parameters, route="free")
        return simulate_free(free, t_end, t_start=t_start, initial=initial, parameters=parameters, method=method,
                             rtol=rtol, atol=atol, dt=dt, max_step=max_step, n_out=n_out, t_eval=t_eval,
                             events=events, tolerance=tolerance, max_steps=max_steps, progress=progress,
                             backend=backend, stabilization=stabilization, stiffness_check=stiffness_check)
    contacts = contact_model(source)
    if contacts is not None:  # unilateral contacts: smooth phases between impacts and lift-offs
        parameters = constant_inputs_only(source, inputs, parameters, route="contact")
        return simulate_contact(contacts, t_end, t_start=t_start, initial=initial, parameters=parameters,
                                method=method, rtol=rtol, atol=atol, dt=dt, max_step=max_step, n_out=n_out,
                                t_eval=t_eval, events=events, tolerance=tolerance, max_steps=max_steps,
                                progress=progress, backend=backend, stabilization=stabilization,
                                stiffness_check=stiffness_check)
    exact = exact_contact_model(source)
    if exact is not None:  # an exact Coulomb contact (regularization = 0): stick/slip phases by events
        parameters = constant_inputs_only(source, inputs, parameters)
        return simulate_stick_slip(exact, t_end, t_start=t_start, initial=initial, parameters=parameters,
                                   method=method, rtol=rtol, atol=atol, dt=dt, max_step=max_step, n_out=n_out,
                                   t_eval=t_eval, events=events, tolerance=tolerance, max_steps=max_steps,
                                   progress=progress, backend=backend, stabilization=stabilization,
                                   baumgarte=baumgarte, stiffness_check=stiffness_check)
    # Complementary constraints make it a differential-algebraic system: `_dae` integrates it.
    source, constrained = constrained_source(source)
    if constrained is not None:
        return simulate_dae(source if isinstance(source, ConstrainedSystem) else constrained, t_end,
                            t_start=t_start, initial=initial, parameters=parameters, method=method, rtol=rtol,
                            atol=atol, dt=dt, max_step=max_step, n_out=n_out, t_eval=t_eval, events=events,
                            tolerance=tolerance, max_steps=max_steps, progress=progress, backend=backend,
                            stabilization=stabilization, baumgarte=baumgarte, inputs=inputs)
    if stabilization is not None:
        raise SimulationError(f"stabilization={stabilization!r} applies to models with complementary constraints, "
                              "and this one keeps none complementary.",
                              fix="leave the stabilization out (its coordinates are all principal)")
    if method not in METHODS:
        raise SimulationError(f"Unknown method `{method}`.", fix="use one of " + ", ".join(METHODS))
    if tolerance is None:
        tolerance = default_tolerance(method, rtol)
    specs = [EventSpec(e, e) if isinstance(e, str) else e for e in events]
    system = _resolve(source, specs, backend, inputs, parameters)
    if not specs:  # events compiled into the system: both directions, none terminal
        specs = [EventSpec(name, name) for name in system.events]
    if method in BUILTIN and system.backend != "c":
        raise SimulationError(f"The method `{method}` runs in compiled C, and no C compiler was found.",
                              fix="install a C compiler (e.g. gcc), or use a SciPy method such as method='DOP853'")
    p = system.parameter_vector(parameters)
    y0 = initial_state(system.eom, initial)
    t_out = _output_times(float(t_start), float(t_end), n_out, t_eval, 4 * system.n + len(system.monitors) + 1)

    # A singular M at the start is reported before anything runs.
    M, F0 = system.mass_forces(t_start, y0, p)
    check_callback(system)  # a Python input function that fails at the start says so itself
    if not (np.isfinite(M).all() and np.isfinite(F0).all()):  # nan: no eigenvalue (LinAlgError), say why
        raise _singularity(system, t_start, y0, p, "at the initial state")
    w = mass_eigenvalues(M)
    if not w[0] > 1e-12 * max(abs(w[-1]), 1e-300):
        raise _singularity(system, t_start, y0, p, "at the initial state")

    if method in SCIPY:
        arm_callback(system, None)
        t_o, Y, evs, nfev, steps, code = _run_scipy(system, p, y0, t_start, t_end, t_out, method, rtol, atol,
                                                    max_step, specs, progress)
        status = "completed" if code == 0 else "stopped by a terminal event"
        conditioning = _pivot(system, t_o, Y, p)
    else:
        t_o, Y, evs, nfev, steps, status, conditioning = _run_builtin(
            system, p, y0, t_start, t_end, t_out, method, rtol, atol, dt, max_step, max_steps, specs, progress,
            stiffness_check)
        if isinstance(status, SimulationError):  # stiff, or max_steps: the part computed so far goes with it
            if len(t_o) > 0:
                status.trajectory = _trajectory(system, p, t_o, Y, evs, method, steps, nfev, tolerance,
                                                f"stopped at t = {status.t:.9g} (partial): {status.reason}",
                                                conditioning)
            raise status
    if isinstance(status, Interrupted):
        if len(t_o) > 0:
            status.trajectory = _trajectory(system, p, t_o, Y, evs, method, steps, nfev, tolerance,
                                            f"interrupted at t = {status.t:.9g} (partial)", conditioning)
        raise status
    return _trajectory(system, p, t_o, Y, evs, method, steps, nfev, tolerance, status, conditioning)


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


#: How many times gauss-legendre's default step is halved when its implicit stages do not converge
#: (or the state overflows): 1/10 of the output spacing is too long for a fast spin or a stiff spring.
GAUSS_HALVINGS = 10


def _gauss_step(t_start: float, t_end: float, t_out: np.ndarray, dt: float | None) -> float:
    """gauss-legendre's fixed step: ``dt``, or 1/10 of the output spacing; rounded to fill the spacing."""
    spacing = np.min(np.diff(t_out)) if len(t_out) > 1 else t_end - t_start
    if dt is None:
        dt = spacing / 10
    uniform = len(t_out) > 1 and np.allclose(np.diff(t_out), spacing, rtol=1e-12, atol=0)
    # A dt below the output spacing is rounded down so that whole steps fill it (the outputs
    # fall on steps); a larger one is honoured, the outputs interpolated between steps.
    return spacing / np.ceil(spacing / dt - 1e-9) \
        if uniform and abs(t_out[0] - t_start) < 1e-15 and dt <= spacing else dt


def control_block(method: str, t_start: float, t_end: float, t_out: np.ndarray, rtol: float, atol: float,
                  dt: float | None, max_step: float | None, max_steps: int, h: float | None = None,
                  stiffness_check: bool = True) -> np.ndarray:
    """The C integrators' control block (``_integrators.c``) at the start of a run.

    One place for it, so that `ensemble` starts each member exactly as `simulate` starts
    its run (same first step, same fixed step of ``gauss-legendre``; ``h`` overrides that
    step when `simulate` halves it).
    """
    if dt is not None and not dt > 0:
        raise SimulationError(f"dt = {dt} must be positive.", fix="give a positive step, e.g. dt=1e-3")
    ctl = np.zeros(CONTROL_SIZE)
    ctl[0] = t_start
    ctl[14] = STIFFNESS_TEST_PERIOD if stiffness_check else 0.0
    ctl[2], ctl[3] = rtol, atol
    ctl[4] = np.inf if max_step is None else float(max_step)
    ctl[9] = float(max_steps)
    ctl[12] = 1.0
    if method == "gauss-legendre":
        ctl[1] = _gauss_step(t_start, t_end, t_out, dt) if h is None else h
        ctl[2] = 1e-14  # stage iteration tolerance: converged to round-off, so symplecticity holds
    elif dt is not None:
        ctl[1], ctl[8] = float(dt), 1.0
    return ctl


def _run_builtin(system, p, y0, t_start, t_end, t_out, method, rtol, atol, dt, max_step, max_steps, specs,
                 progress, stiffness_check=True):
    if dt is not None and not dt > 0:
        raise SimulationError(f"dt = {dt} must be positive.", fix="give a positive step, e.g. dt=1e-3")
    given = dt is not None
    h = _gauss_step(t_start, t_end, t_out, dt) if method == "gauss-legendre" else None
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
    if code == _INTERRUPTED:
        m = int(i_out[0])
        return t_out[:m], Y[:m], evs, int(ctl[5]), int(ctl[6]), Interrupted(float(ctl[0])), float(ctl[12])
    if code in (0, 4):
        m = int(i_out[0])
        return t_out[:m], Y[:m], evs, int(ctl[5]), int(ctl[6]), "completed" if code == 0 else \
            "stopped by a terminal event", float(ctl[12])
    t_fail = float(ctl[0])
    if code in (_STIFF, 5):  # stopped early, not failed: what was computed so far is returned with the error
        m = int(i_out[0])
        return t_out[:m], Y[:m], evs, int(ctl[5]), int(ctl[6]), _early_stop(system, code, ctl, y), float(ctl[12])
    if code == 1 or (code in (2, 3) and _collapsed(system, t_start, y0, t_fail, y, p)):
        raise _singularity(system, t_fail, y, p, "during the integration")
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
        f"The integration stopped at t = {t_fail:.9g} ({_state_text(system, y)}): {_STATUS[code]}.",
        fix=fixes.get(code, "check the model and the initial state"), t=t_fail, state=y.copy())


def _early_stop(system, code: int, ctl: np.ndarray, y: np.ndarray) -> SimulationError:
    """The error of a run that dop853's stiffness test (code 8) or ``max_steps`` (code 5) stopped."""
    t = float(ctl[0])
    if code == _STIFF:
        reason = "the equations are stiff"
        err = SimulationError(
            f"The integration stopped at t = {t:.9g} ({_state_text(system, y)}): the equations are stiff there. "
            f"dop853's stiffness test (Hairer) found the step limited by stability, not by accuracy: "
            f"h|λ| ≈ {ctl[17]:.3g} > 6.1 for 15 steps in a row (step h = {ctl[1]:.3g}), so an explicit method "
            f"would crawl at that step to the end.",
            fix="use an implicit method: --method Radau (or BDF, LSODA; method='Radau'), or make the stiff part "
                "softer (a smaller stiffness or damping coefficient); --no-stiffness-check (stiffness_check=False) "
                "goes on with dop853 all the same", t=t, state=y.copy())
    elif ctl[21] > 0:  # the pace check: max_steps could not be enough, said at once rather than at the end
        reason = "the maximum number of steps would be reached"
        err = SimulationError(
            f"The integration stopped at t = {t:.9g} ({_state_text(system, y)}): at its step size "
            f"(h ≈ {ctl[1]:.3g} now) the run would need about {ctl[21]:.3g} steps, more than max_steps ({int(ctl[9])}). The model moves much "
            f"faster than the time span: its fastest motion (a very stiff spring, a fast spin) lasts a few steps.",
            fix="shorten the time span, soften the fast part (a smaller stiffness), or raise max_steps",
            t=t, state=y.copy())
    else:
        reason = "the maximum number of steps was reached"
        err = SimulationError(f"The integration stopped at t = {t:.9g} ({_state_text(system, y)}): {_STATUS[5]} "
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
        code = _interruptible(call, ctl)
    check_callback(system)  # a Python input function failed: its error, not an interruption
    return code, ctl, y, Y, i_out, ev_out, capacity


def _interruptible(call: Callable[[], int], ctl: np.ndarray) -> int:
    """``call()`` (a compiled run) in a worker thread; Ctrl-C meanwhile asks it to stop at its next step.

    The main thread only waits: a signal's Python handler runs in the main thread, and not
    before a C call made there returns, so the run itself must not be made there.
    """
    result: list = []
    done = threading.Event()

    def run() -> None:
        try:
            result.append(call())
        finally:
            done.set()

    # Waiting on an Event, not on `Thread.join`: before Python 3.13 an interrupted join marks
    # the thread finished, and a second join would return while the run still writes.
    threading.Thread(target=run, name="lagrangian-run", daemon=True).start()
    try:
        done.wait()  # interruptible: KeyboardInterrupt arrives here within milliseconds
    except KeyboardInterrupt:
        ctl[_C_STOP] = 1.0
        done.wait()
    return result[0]


def _collapsed(system, t0, y0, t, y, p) -> bool:
    """Whether M lost (almost) all its inertia in some direction since the start: then a
    step-size underflow or an overflow is the singularity showing, and is reported as one."""
    M0, M = system.mass_forces(t0, y0, p)[0], system.mass_forces(t, y, p)[0]
    if not (np.isfinite(M0).all() and np.isfinite(M).all()):
        return True  # M undefined there: `_singularity` says which entries
    w0 = mass_eigenvalues(M0)
    w = mass_eigenvalues(M)
    return bool(w[0] < 1e-8 * w0[-1])


def _counting_solver(method: str, count: dict, reporter: Reporter | None) -> type:
    """SciPy's solver class for ``method``, counting its accepted steps (and reporting progress)."""
    import scipy.integrate

    base = getattr(scipy.integrate, method)

    class Counted(base):  # type: ignore[misc, valid-type]
        def __init__(self, *args, **kwargs) -> None:
            super().__init__(*args, **kwargs)
            count["solver"] = self

        def _step_impl(self):  # type: ignore[no-untyped-def]
            success, message = super()._step_impl()
            if success:
                count["steps"] += 1
                if reporter is not None:
                    reporter.update(self.t)
            return success, message

    Counted.__name__ = Counted.__qualname__ = base.__name__
    return Counted


def _run_scipy(system, p, y0, t_start, t_end, t_out, method, rtol, atol, max_step, specs, progress=False):
    from scipy.integrate import solve_ivp

    def fun(t, y):
        try:
            return system.rhs(t, y, p)
        except SimulationError:
            check_callback(system)  # a Python input function's error first: it caused this one
            raise

    def make_event(k, spec):
        def g(t, y):
            return float(system.event_values(t, y, p)[k])
        g.direction = spec.direction
        g.terminal = spec.terminal
        return g

    count: dict = {"steps": 0, "solver": None}
    reporter = make_reporter(progress, t_start, t_end)

    def reached() -> float:
        return float(count["solver"].t) if count["solver"] is not None else float(t_start)

    try:
        # A failure is raised as a SimulationError below; NumPy's floating-point warnings on the way add nothing.
        with np.errstate(over="ignore", invalid="ignore", divide="ignore"):
            def solve(a: float, b: float, y: np.ndarray, grid: np.ndarray):  # type: ignore[no-untyped-def]
                return solve_ivp(fun, (a, b), y, method=_counting_solver(method, count, reporter),
                                 t_eval=grid, rtol=rtol, atol=atol, max_step=np.inf if max_step is None else max_step,
                                 events=[make_event(k, s) for k, s in enumerate(specs)] or None)

            # A table's samples and a switch's times are breakpoints: one solve_ivp per interval (`_input_run`).
            law = system.law_block(p) if len(system.law.breakpoints) else None
            sol = solve_in_segments(solve, t_start, t_end, t_out, y0, system.law.breakpoints, law, len(specs))
    except KeyboardInterrupt:
        # SciPy's loop runs in Python, so Ctrl-C stops it at once; what it had is inside
        # solve_ivp and lost, so the Interrupted carries no trajectory.
        if reporter:
            reporter.finish(reached(), False)
        raise Interrupted(reached()) from None
    except SimulationError as exc:
        if reporter:
            reporter.finish(reached(), False)
        raise SimulationError(f"{exc.message} (during SciPy's {method} integration)", fix=exc.fix, t=exc.t,
                              state=exc.state) from None
    except (ValueError, ArithmeticError, np.linalg.LinAlgError) as exc:
        # e.g. "array must not contain infs or NaNs" from the linear algebra of an implicit method
        # whose error weights atol + rtol |y| underflow, or a blow-up of the state.
        if reporter:
            reporter.finish(reached(), False)
        t_fail = reached()
        raise SimulationError(
            f"SciPy's {method} failed at t = {t_fail:.9g}: {exc} (rtol = {rtol:g}, atol = {atol:g}).",
            fix="use tolerances the method can meet (atol no smaller than about 1e-15 times the size of the state, "
                "rtol >= 1e-13), or try method='dop853'; if the state grows without bound, check the model",
            t=t_fail) from None
    if reporter:
        reporter.finish(reached(), sol.status >= 0)
    if sol.status < 0:
        raise SimulationError(f"SciPy's {method} stopped at t = {sol.t[-1] if len(sol.t) else t_start:.9g}: "
                              f"{sol.message}", fix="loosen the tolerances or try another method")
    evs = []
    for k, spec in enumerate(specs):
        for te, ye in zip(sol.t_events[k], sol.y_events[k], strict=True):
            evs.append((spec.name, float(te), ye))
    evs.sort(key=lambda e: e[1])
    return sol.t, np.ascontiguousarray(sol.y.T), evs, int(sol.nfev), int(count["steps"]), sol.status


def _trajectory(system, p, t, Y, evs, method, steps, nfev, tolerance, status, conditioning) -> Trajectory:
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


def momenta(eom: EquationsOfMotion, integrals: Sequence[str]) -> dict[str, int]:
    """Integral name → index of the coordinate whose momentum ∂T/∂q̇_k it is (the others are energy-like)."""
    names = {(c.momentum or f"p_{c.name}"): k for k, c in enumerate(eom.model.coordinates)}
    return {name: names[name] for name in integrals if name in names}
