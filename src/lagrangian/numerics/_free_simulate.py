"""`simulate` for a model with free bodies: the motion on unit quaternions, reported in the model's angles.

A free body's Euler angles are singular somewhere (θ = 0 for the course's z-x-z angles), and
a tumbling body passes there; its unit quaternion e and its angular velocity ω (in its own
basis) are not.  So the run integrates the state of `dynamics._floating` (r, e, v, ω and the
joints of what the body carries), compiled as any model (`codegen._free_codegen`, `FreeBodySystem`),
with DOP853 in C (or a SciPy method on the same right-hand side), and:

* after each accepted step of DOP853, projects each e back on |e| = 1 (e ← e/|e|, the nearest
  unit quaternion), so that the drift of the norm never accumulates; the largest |1 − |e||
  met before a projection is reported (`Trajectory.quaternion_drift`, and in
  `drift_summary`).  The dynamics does not depend on |e| (R is e's rotation divided by |e|²);
  with a SciPy method nothing projects, and the drift reported is that of the outputs;
* reports the motion in the model's coordinates: the angles from e, continuous from their
  initial values; their rates and accelerations from ω and ω̇ (`_euler`), which are NaN
  where the angles are singular (|det J| < 1e-9), with a warning saying when; the
  quaternions and ω as extra columns (``S_ew``..., ``S_omega_x``...);
* monitors the first integrals of the quaternion form (the energy, the angular momentum σ_G
  about each tree's centre of mass and the momentum P where they are conserved), each drift
  measured against the size of what it adds up (|T| + |U| for E, |σ_G| and |P| for their
  components).

Events may use the positions of the free bodies' origins, the joints, their rates, the
parameters and t, not the Euler angles (they are not integrated).  The symplectic
``gauss-legendre`` method, which integrates Hamilton's equations in the model's coordinates, and
the ensembles do not take free bodies.
"""

from __future__ import annotations

from pathlib import Path
from types import SimpleNamespace

import numpy as np
import symengine as se

from ..errors import Interrupted, SimulationError
from ..model import TIME, Model, load_model
from ._control import control_block, interruptible
from ._free_system import FreeBodySystem, has_free_body
from ._input_run import constant_inputs_only
from ._options import SCIPY, SimulationOptions, default_tolerance
from ._progress import Watch, make_reporter
from ._scipy_run import run_scipy
from ._setup import EventSpec, event_expressions, initial_state, output_times
from ._trajectory import Event, Trajectory, drift_scale, relative_drift

__all__ = ["check_free_options", "free_source", "run_free"]


def free_source(source) -> Model | FreeBodySystem | None:
    """The model (or compiled system) to integrate on quaternions, or None when it has no free body."""
    if isinstance(source, FreeBodySystem):
        return source
    if isinstance(source, (str, Path)):
        source = load_model(source)
    model = source if isinstance(source, Model) else getattr(getattr(source, "eom", source), "model", None)
    return model if isinstance(model, Model) and has_free_body(model) else None


def _state_text(system: FreeBodySystem, y: np.ndarray) -> str:
    q, _, _ = system.coordinates_of(y[None, :], np.zeros((1, system.width)), np.zeros(2 * len(system.coordinates)))
    return ", ".join(f"{name} = {v:.6g}" for name, v in zip(system.coordinates, q[0], strict=True))


def check_free_options(options: SimulationOptions) -> None:
    """Refuse what the quaternion route cannot do: Gauss–Legendre, a stabilization, no compiler."""
    if options.method == "gauss-legendre":
        raise SimulationError("The method `gauss-legendre` integrates Hamilton's equations in the model's "
                              "coordinates, whose Euler angles are singular somewhere; a free body is integrated on "
                              "a unit quaternion instead.", fix="use dop853 (the default) or a SciPy method")
    if options.stabilization is not None:
        raise SimulationError(f"stabilization={options.stabilization!r} applies to models with complementary "
                              "constraints, and this one keeps none complementary.", fix="leave the stabilization out")
    if options.backend == "symengine":
        raise SimulationError("A model with free bodies is integrated in compiled C only.",
                              fix="install a C compiler (e.g. gcc), or use backend='auto'")


def run_free(source, options: SimulationOptions) -> Trajectory:
    """`simulate` of a model with free bodies (module docstring): ``source`` is what `free_source` gives.

    Constant inputs only: their numbers join the parameters (`_input_run.constant_inputs_only`).
    """
    parameters = constant_inputs_only(source, options.inputs, options.parameters, route="free")
    check_free_options(options)
    method, rtol, atol = options.method, options.rtol, options.atol
    t_start, t_end, tolerance = options.t_start, options.t_end, options.tolerance
    system = source if isinstance(source, FreeBodySystem) else None
    model = system.model if system is not None else source
    specs = list(options.events)
    if specs or system is None:  # the events read with the model's names, then in the state's symbols
        names = SimpleNamespace(model=model, t=TIME, q=_symbols(model, ""), qd=_symbols(model, "_dot"))
        specs = event_expressions(names, specs) if specs else []
        system = FreeBodySystem(model, events=[(e.name, e.expression) for e in specs])
    else:
        specs = [EventSpec(name, name) for name in system.events]
    if tolerance is None:
        tolerance = default_tolerance(method, rtol)
    p = system.parameter_vector(parameters)
    start = initial_state(SimpleNamespace(model=model), options.initial)
    y0 = system.state_of(start[None, :])[0]
    t_out = output_times(float(t_start), float(t_end), options.n_out, options.t_eval,
                         3 * system.width + len(system.monitors))
    try:
        system.rhs(t_start, y0, p)
    except SimulationError as exc:
        raise SimulationError(f"{exc.message} (at the initial state: {_state_text(system, y0)})", fix=exc.fix) from None
    if method in SCIPY:
        t, Y, evs, nfev, steps, code = run_scipy(system, p, y0, t_start, t_end, t_out, method, rtol, atol,
                                                 options.max_step, specs, options.progress)
        status, conditioning = ("completed" if code == 0 else "stopped by a terminal event"), 1.0
        return _trajectory(system, p, t, Y, evs, method, steps, nfev, tolerance, status, conditioning, start)
    return _run_compiled(system, p, y0, t_out, specs, options, tolerance, start)


def _run_compiled(system: FreeBodySystem, p: np.ndarray, y0: np.ndarray, t_out: np.ndarray,
                  specs: list[EventSpec], options: SimulationOptions, tolerance: float,
                  start: np.ndarray) -> Trajectory:
    """DOP853 in C with the quaternions projected after each step; failures as `SimulationError`."""
    method, t_start, t_end = options.method, options.t_start, options.t_end
    ctl = control_block(method, t_start, t_end, t_out, options.rtol, options.atol, options.dt, options.max_step,
                        options.max_steps, None, options.stiffness_check)
    y = y0.copy()
    Y = np.full((len(t_out), system.width), np.nan)
    i_out = np.zeros(1, dtype=np.intc)
    ev_dir = np.array([e.direction for e in specs] or [0], dtype=np.intc)
    ev_term = np.array([int(e.terminal) for e in specs] or [0], dtype=np.intc)
    capacity = 100_000 if specs else 1
    ctl[11] = capacity
    ev_out = np.zeros((capacity, 2 + system.width))
    reporter = make_reporter(options.progress, t_start, t_end)
    lib = system._lib

    def call() -> int:
        return lib.lg_dop853(_ptr(ctl), _ptr(y), _ptr(p), _ptr(t_out), len(t_out), _ptr(i_out), _ptr(Y),
                             float(t_end), _ptr(ev_dir), _ptr(ev_term), _ptr(ev_out))

    with Watch(reporter, ctl):
        code = interruptible(call, ctl)
    if reporter:
        reporter.finish(float(ctl[0]), code in (0, 4))
    m = int(i_out[0])
    evs = [(specs[int(r[0])].name, r[1], r[2:]) for r in ev_out[:int(min(ctl[10], capacity))]]
    done = {0: "completed", 4: "stopped by a terminal event"}
    if code in done:
        return _trajectory(system, p, t_out[:m], Y[:m], evs, method, int(ctl[6]), int(ctl[5]), tolerance,
                           done[code], float(ctl[12]), start)
    t_fail = float(ctl[0])
    partial = (_trajectory(system, p, t_out[:m], Y[:m], evs, method, int(ctl[6]), int(ctl[5]), tolerance,
                           f"stopped at t = {t_fail:.9g} (partial)", float(ctl[12]), start) if m else None)
    if code == 7:
        raise Interrupted(t_fail, partial)
    reasons = {1: "the articulated inertia of a free body lost its rank (a mass or moment of inertia too small)",
               2: "the state stopped being finite (overflow, a blow-up)",
               3: "the step size fell below the resolution of t (step size underflow)",
               5: "the maximum number of steps was reached",
               8: "the equations are stiff (dop853's stiffness test)"}
    fixes = {5: "raise max_steps, or shorten the time span", 8: "use method='Radau', or soften the stiff part"}
    error = SimulationError(f"The integration stopped at t = {t_fail:.9g} ({_state_text(system, y)}): "
                            f"{reasons.get(code, f'status {code}')}.", fix=fixes.get(code, "check the model and the "
                                                                                                 "initial state"),
                            t=t_fail, state=y.copy())
    error.trajectory = partial
    raise error


def _ptr(a: np.ndarray) -> int:
    return a.ctypes.data


def _symbols(model: Model, suffix: str) -> tuple[se.Symbol, ...]:
    return tuple(se.Symbol(c.name + suffix) for c in model.coordinates)


def _drift(system: FreeBodySystem, monitors: dict[str, np.ndarray],
           integrals: tuple[str, ...]) -> tuple[dict[str, float], dict[str, float]]:
    """(drift, scale) of each first integral, each against the size of what it adds up (module docstring)."""
    drift, scales = {}, {}
    size = np.abs(monitors["T"]) + np.abs(monitors["U"])
    groups: dict[str, np.ndarray] = {}
    for names in system.form.momentum:
        norm = np.sqrt(sum(monitors[name] ** 2 for name in names))
        groups.update({name: norm for name in names})
    for name in integrals:
        if name.startswith("P"):
            family = [m for m in monitors if m.rsplit("_", 1)[0] == name.rsplit("_", 1)[0]]
            groups[name] = np.sqrt(sum(monitors[m] ** 2 for m in family))
        magnitude = size if name == "E" else groups.get(name)
        scales[name] = drift_scale(monitors[name], magnitude)
        drift[name] = float(np.max(relative_drift(monitors[name], scales[name]), initial=0.0))
    return drift, scales


def _trajectory(system: FreeBodySystem, p, t, Y, evs, method, steps, nfev, tolerance, status, conditioning,
                start) -> Trajectory:
    Y = np.ascontiguousarray(Y)
    dY = system.rhs(t, Y, p) if len(t) else np.zeros((0, system.width))
    q, qd, qdd = system.coordinates_of(Y, dY, start, np.asarray(t, dtype=float))
    values = system.monitor_values(t, Y, p) if len(t) else np.zeros((0, len(system.monitors)))
    monitors = {name: values[:, k].copy() for k, name in enumerate(system.monitors)}
    integrals = system.integrals_for(p)
    drift, scales = _drift(system, monitors, integrals) if len(t) else ({}, {})
    norms = system.quaternion_norms(Y)
    records = system.drift_records(Y) if method == "dop853" else {}
    quaternion = {body: max(records.get(body, 0.0), float(np.max(np.abs(n - 1.0), initial=0.0)))
                  for body, n in norms.items()}
    warnings = tuple(f"{name} drifted by {drift[name]:.2e} (relative), more than the tolerance {tolerance:.1e}"
                     for name in integrals if tolerance is not None and drift.get(name, 0.0) > tolerance)
    if conditioning < 1e-6:
        warnings += ((f"the articulated inertia of a free body came close to losing its rank (smallest relative "
                      f"pivot {conditioning:.1e}): accuracy may be lost there"),)
    for fj, *_ in system.blocks:
        body = fj.body
        bad = ~np.isfinite(qd[:, [system.coordinates.index(a) for a in fj.angles]]).all(axis=1)
        if bad.any():
            k = int(np.argmax(bad))
            warnings += ((f"the Euler angles {', '.join(fj.angles)} of free body `{body}` are singular at "
                         f"{int(bad.sum())} output time(s), first t = {t[k]:.9g}: their rates and accelerations are "
                         f"not defined there (NaN); the motion itself is integrated on a unit quaternion (columns "
                         f"{body}_ew..., {body}_omega_...), which is regular"),)
    n = len(system.coordinates)
    events = []
    for name, te, ye in evs:
        row = int(np.searchsorted(t, te, side="right")) - 1
        ref = np.concatenate([q[row], qd[row]]) if 0 <= row < len(t) else start
        dy = system.rhs(te, ye, p)
        eq, eqd, _ = system.coordinates_of(np.asarray(ye)[None, :], dy[None, :], np.nan_to_num(ref[:n].tolist() + [0] * n))
        events.append(Event(name, float(te), eq[0], eqd[0]))
    return Trajectory(
        model_name=system.model.name, coordinates=system.coordinates,
        parameters={k: float(v) for k, v in zip(system.parameters, p[:len(system.parameters)], strict=True) if not np.isnan(v)},
        t=np.asarray(t, dtype=float), q=q, qd=qd, qdd=qdd, monitors=monitors, integrals=integrals,
        drift=drift, method=method, steps=steps, rhs_calls=nfev, tolerance=tolerance, warnings=warnings,
        events=tuple(events), status=status, conditioning=conditioning, extra=system.extra_columns(Y),
        scales=scales, quaternion_drift=quaternion)
