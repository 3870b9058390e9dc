"""Forward sensitivities: ∂y(t)/∂p and ∂y(t)/∂y(t0), integrated with the state in compiled C.

For ẏ = f(t, y, p) with y = (q, q̇) and f = (q̇, q̈), M(q, p) q̈ = F(q, q̇, p), the
sensitivity S = ∂y/∂x to a parameter or an initial value x obeys the variational equations
(Hairer, Nørsett & Wanner, *Solving ODEs I*, §I.14)

    Ṡ = (∂f/∂y) S + ∂f/∂x,        S(t0) = 0 (a parameter) or e_i (the initial value y_i(t0)),

and the rows of ∂f that belong to q̈ come from M q̈ = F differentiated at q̈ held:

    ∂q̈/∂x = M⁻¹ (∂F/∂x − ∂(M a)/∂x |_{a = q̈}).

The Jacobian J = ∂(F − M a)/∂(q, q̇, p_sel), with a a vector of symbols, is generated
symbolically (`_forward.forward_jacobian`, through the recursive form's intermediates where
there is one; never M⁻¹) and compiled after the model's own code, with an augmented DOP853
(the C runtime's ``sensitivity.c``, `codegen.runtime_source`) that integrates y and every column
of S by the same steps.  By default the step-size control looks at y only
(`Sensitivities.in_error_norm`): y is then the plain run's, bit for bit, and S the exact
derivative of that numerical solution (see ``codegen/runtime/sensitivity.c``).
"""

from __future__ import annotations

import ctypes
import dataclasses
import hashlib
import weakref
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
import symengine as se

from ..codegen import c_function, runtime_source
from ..dynamics import EquationsOfMotion, derive
from ..errors import Interrupted, SimulationError
from ..model.spec import Model
from ._compile import compile_library
from ._control import INTERRUPTED, STATUS, STIFF, control_block, interruptible
from ._dae import constrained_source
from ._forward import forward_jacobian
from ._ode import early_stop, resolve, singularity, state_text, trajectory
from ._options import BUILTIN, SimulationOptions, default_tolerance
from ._progress import Watch, make_reporter
from ._setup import initial_state, output_times
from ._stickslip import exact_contact_model
from ._system import CompiledSystem, _ptr

__all__ = [
    "Sensitivities",
    "SensitivityColumn",
    "SensitivityRun",
    "SensitivitySystem",
    "check_sensitivity_options",
    "column_name",
    "inverse_dynamics",
    "parse_sensitivities",
    "run_sensitivities",
    "sensitivity_system",
]

_P = ctypes.c_void_p
#: The suffix that names an initial value among the sensitivities: ``"theta(t0)"``, ``"theta_dot(t0)"``.
INITIAL = "(t0)"


@dataclass(frozen=True)
class Sensitivities:
    """What ``simulate(..., sensitivities=...)`` differentiates the motion with respect to.

    Parameters
    ----------
    names : tuple of str
        Parameters (``"l"``) and initial values (``"theta(t0)"``, ``"theta_dot(t0)"``).
    in_error_norm : bool
        False (default): the step-size control looks at the state only, so the state is the plain
        run's bit for bit and the sensitivities are the exact derivatives of that numerical solution
        (consistent with it, which a Gauss–Newton fit needs); True: the sensitivities must meet
        ``rtol``/``atol`` too (CVODES's default), at the cost of more steps where they grow faster
        than the state.
    """

    names: tuple[str, ...]
    in_error_norm: bool = False

    def __post_init__(self) -> None:
        names = (self.names,) if isinstance(self.names, str) else tuple(self.names)
        object.__setattr__(self, "names", names)


@dataclass(frozen=True)
class SensitivityColumn:
    """One sensitivity: its name, and the parameter (index in ``p``) or state entry it is taken to.

    Parameters
    ----------
    name : str
        Its name.
    parameter : int or None
        The index in the model's parameters, or None for an initial value.
    state : int or None
        The index in y for an initial value.
    """

    name: str
    parameter: int | None  # index in the model's parameters, or None for an initial value
    state: int | None  # index in y for an initial value


def column_name(state: str, name: str) -> str:
    """The trajectory column of ∂state/∂name: ``d(theta)/d(l)``."""
    return f"d({state})/d({name})"


def parse_sensitivities(eom: EquationsOfMotion, names: Sequence[str]) -> list[SensitivityColumn]:
    """The sensitivity columns asked for, checked.

    Raises
    ------
    SimulationError
        For an input (a time function, not a constant to differentiate with respect to), an
        unknown name, or a name given twice.
    """
    model = eom.model
    params = [p for p in model.parameters]
    coords = [c.name for c in model.coordinates]
    states = coords + [c + "_dot" for c in coords]
    out: list[SensitivityColumn] = []
    seen: set[str] = set()
    for name in names:
        if not isinstance(name, str):
            raise SimulationError(f"The sensitivity `{name!r}` is not a name.",
                                  fix="give parameter names, or initial values as `theta(t0)`")
        if name in seen:
            raise SimulationError(f"The sensitivity to `{name}` is asked for twice.", fix="give each name once")
        seen.add(name)
        if name.endswith(INITIAL) and name[: -len(INITIAL)] in states:
            out.append(SensitivityColumn(name, None, states.index(name[: -len(INITIAL)])))
            continue
        match = [k for k, p in enumerate(params) if p.name == name]
        if match and params[match[0]].input:
            raise SimulationError(
                f"`{name}` is an input of `{model.name}`, not a parameter: a sensitivity is taken with respect to "
                "a constant, and an input is a function of time.",
                fix=f"differentiate with respect to the parameters ({_names(params)}); to fit an input, "
                    "declare it as a parameter")
        if match:
            out.append(SensitivityColumn(name, match[0], None))
            continue
        hint = f" (its initial value is `{name}{INITIAL}`)" if name in states else ""
        raise SimulationError(f"`{name}` is neither a parameter of `{model.name}` nor an initial value{hint}.",
                              fix=f"the parameters are {_names(params)}; initial values are written "
                                  f"`{states[0]}{INITIAL}`" if states else "give a parameter name")
    return out


def _names(params: Sequence) -> str:
    names = [p.name for p in params if not p.input]
    return ", ".join(names) or "(none)"


def inverse_dynamics(eom: EquationsOfMotion) -> tuple[list[tuple[se.Symbol, se.Basic]], list[se.Basic]]:
    """The inverse dynamics r = M a − F, with a = q̈ as the symbols ``eom.qdd``.

    Over the recursive form's named intermediates where there is one (nothing expanded).

    Parameters
    ----------
    eom : EquationsOfMotion
        The equations.

    Returns
    -------
    intermediates : list of (SymEngine Symbol, SymEngine expression)
        The named intermediates, in order.
    r : list of SymEngine expressions
        M a − F.
    """
    rec = eom.recursive
    n = len(eom.q)
    M, F = (rec.M, rec.F) if rec is not None else (eom.M, eom.F)
    r = [se.Add(*(M[i][j] * eom.qdd[j] for j in range(n))) - F[i] for i in range(n)]
    return (list(rec.intermediates) if rec is not None else []), r


class SensitivitySystem:
    """A `CompiledSystem` with ∂(F − M a)/∂(y, p_sel) and the augmented DOP853, compiled once.

    ``parameters``: the parameters that may be differentiated with respect to (their order is
    the order of J's last columns); initial values need nothing more.

    Parameters
    ----------
    system : CompiledSystem
        The compiled system.
    parameters : sequence of str
        The parameters that may be differentiated with respect to (their order is the order of J's
        last columns); initial values need nothing more.
    """

    def __init__(self, system: CompiledSystem, parameters: Sequence[str]) -> None:
        if system.backend != "c" or system.generated is None:
            raise SimulationError("Sensitivities are integrated in compiled C, and no C compiler was found.",
                                  fix="install a C compiler (e.g. gcc)")
        eom = system.eom
        self.system = system
        self.n = n = system.n
        self.parameters = tuple(parameters)
        index = {name: k for k, name in enumerate(system.parameters)}
        definitions, r = inverse_dynamics(eom)
        variables = [*eom.q, *eom.qd, *(se.Symbol(name) for name in self.parameters)]
        jac = forward_jacobian(definitions, [-e for e in r], variables)
        width = len(variables)
        reads: dict[se.Basic, str] = {eom.t: "t"}
        reads.update({q: f"y[{i}]" for i, q in enumerate(eom.q)})
        reads.update({qd: f"y[{n + i}]" for i, qd in enumerate(eom.qd)})
        reads.update({a: f"a[{i}]" for i, a in enumerate(eom.qdd)})
        reads.update({se.Symbol(name): f"p[{k}]" for name, k in index.items()})
        outputs = [(f"J[{i * width + j}]", e) for i, row in enumerate(jac.jacobian) for j, e in enumerate(row)]
        function = c_function("static void lg_sens_jacobian(double t, const double *y, const double *p, "
                              "const double *a, double *J)", jac.definitions, outputs, reads,
                              "the derivative of M q'' = F")
        # The model's units (`codegen._cparts`: its long functions in parts), the first with the derivative and
        # the augmented integrator appended.
        units = system.generated.units
        first = "\n".join([units[0], f"#define LG_NV {width}", function,
                           runtime_source("cholesky.c"), runtime_source("sensitivity.c")])
        units = (first, *units[1:])
        key = hashlib.sha256("\n/* ---- unit ---- */\n".join(units).encode("utf-8")).hexdigest()
        self._lib = lib = compile_library(units, key)
        lib.lg_sens_dop853.restype = ctypes.c_int
        lib.lg_sens_dop853.argtypes = [_P, _P, _P, ctypes.c_int, _P, _P, ctypes.c_int, _P, _P, ctypes.c_double,
                                       ctypes.c_int, _P, ctypes.c_int, _P, _P, _P]
        lib.lg_sens_eval_jacobian.restype = None
        lib.lg_sens_eval_jacobian.argtypes = [ctypes.c_int, _P, _P, _P, _P, _P]
        lib.lg_constants.restype = None
        lib.lg_constants.argtypes = [_P, _P]
        self.width = width

    def jacobian(self, t, y: np.ndarray, a: np.ndarray, p: np.ndarray) -> np.ndarray:
        """The Jacobian J = ∂(F − M a)/∂(y, p_sel) at each point.

        Parameters
        ----------
        t : float or ndarray of shape (N,)
            The time(s).
        y : ndarray of shape (2n,) or (N, 2n)
            The state(s).
        a : ndarray of shape (n,) or (N, n)
            The accelerations.
        p : ndarray
            The parameter vector.

        Returns
        -------
        ndarray of shape (N, n, 2n + len(parameters))
            J.
        """
        Y = np.ascontiguousarray(np.atleast_2d(y), dtype=float)
        A = np.ascontiguousarray(np.atleast_2d(a), dtype=float)
        T = np.ascontiguousarray(np.broadcast_to(np.asarray(t, dtype=float), (len(Y),)))
        out = np.empty((len(Y), self.n, self.width))
        self._lib.lg_sens_eval_jacobian(len(Y), _ptr(T), _ptr(Y), _ptr(A), _ptr(p), _ptr(out))
        return out

    def run(self, p: np.ndarray, y0: np.ndarray, columns: Sequence[SensitivityColumn], t_out: np.ndarray, t_end: float, *,
            ctl: np.ndarray, in_error_norm: bool = False, inputs: tuple[Sequence[int], np.ndarray, np.ndarray] | None
            = None, watch=None) -> SensitivityRun:
        """Integrate y and the ``columns`` from ``ctl[0]`` to ``t_end``, output at ``t_out``.

        Parameters
        ----------
        p : ndarray
            The extended parameter vector (`CompiledSystem.parameter_vector`).
        y0 : ndarray of shape (2n,)
            The initial state.
        columns : sequence of SensitivityColumn
            The sensitivities to integrate.
        t_out : ndarray
            The output times.
        t_end : float
            The end of the run.
        ctl : ndarray
            The control block (`_control.control_block`).
        in_error_norm : bool, optional
            Whether the sensitivities enter the step-size control.
        inputs : (sequence of int, ndarray, ndarray), optional
            (parameter indices, times (m,), values (m, k)) of inputs set by linear interpolation at
            every evaluation.
        watch : callable, optional
            Wraps the call (progress, Ctrl-C): a function taking the call and ``ctl``.

        Returns
        -------
        SensitivityRun
            Output times, states, sensitivities and the C status.
        """
        n2 = 2 * self.n
        ns = len(columns)
        nz = n2 * (1 + ns)
        z = np.zeros(nz)
        z[:n2] = y0
        col = np.array([-1 if c.parameter is None else self.parameters.index(self.system.parameters[c.parameter])
                        for c in columns] or [0], dtype=np.intc)
        for k, c in enumerate(columns):
            if c.state is not None:
                z[n2 * (k + 1) + c.state] = 1.0
        ctl[21] = 1.0 if in_error_norm else 0.0
        Z = np.full((len(t_out), nz), np.nan)
        i_out = np.zeros(1, dtype=np.intc)
        work = np.zeros((16 + 8 + 8) * nz)
        pw = np.array(p, dtype=float)
        if inputs is not None:
            index = np.ascontiguousarray(inputs[0], dtype=np.intc)
            times = np.ascontiguousarray(inputs[1], dtype=float)
            values = np.ascontiguousarray(inputs[2], dtype=float)
            n_in, rows = len(index), len(times)
        else:
            index, times, values = np.zeros(1, dtype=np.intc), np.zeros(1), np.zeros(1)
            n_in, rows = 0, 0
        t_out = np.ascontiguousarray(t_out, dtype=float)

        def call() -> int:
            return self._lib.lg_sens_dop853(_ptr(ctl), _ptr(z), _ptr(pw), ns, _ptr(col), _ptr(t_out), len(t_out),
                                            _ptr(i_out), _ptr(Z), float(t_end), n_in, _ptr(index), rows,
                                            _ptr(times), _ptr(values), _ptr(work))

        code = watch(call, ctl) if watch is not None else interruptible(call, ctl)
        m = int(i_out[0])
        Z = Z[:m]
        return SensitivityRun(t_out[:m], Z[:, :n2].copy(), Z[:, n2:].reshape(m, ns, n2).copy(), int(code), ctl, z)


@dataclass(frozen=True)
class SensitivityRun:
    """What one augmented run gives: output times, states (N, 2n), sensitivities (N, ns, 2n), the C status."""

    t: np.ndarray
    y: np.ndarray
    S: np.ndarray
    code: int
    ctl: np.ndarray
    z: np.ndarray  # the augmented state where the run ended

    @property
    def steps(self) -> int:
        return int(self.ctl[6])

    @property
    def rhs_calls(self) -> int:
        return int(self.ctl[5])


_CACHE: weakref.WeakKeyDictionary = weakref.WeakKeyDictionary()


def sensitivity_system(system: CompiledSystem, parameters: Sequence[str]) -> SensitivitySystem:
    """The `SensitivitySystem` of ``system`` for ``parameters``, built once per pair.

    Parameters
    ----------
    system : CompiledSystem
        The compiled system.
    parameters : sequence of str
        The parameters to differentiate with respect to.

    Returns
    -------
    SensitivitySystem
        The system, cached.
    """
    mine = _CACHE.setdefault(system, {})
    key = tuple(parameters)
    if key not in mine:
        mine[key] = SensitivitySystem(system, key)
    return mine[key]


def sensitivity_extra(coordinates: Sequence[str], columns: Sequence[SensitivityColumn], S: np.ndarray
                      ) -> dict[str, np.ndarray]:
    """The trajectory columns ``d(theta)/d(l)``, ``d(theta_dot)/d(l)``... of S (N, ns, 2n)."""
    states = [*coordinates, *(c + "_dot" for c in coordinates)]
    return {column_name(state, c.name): S[:, k, i].copy() for k, c in enumerate(columns)
            for i, state in enumerate(states)}


def with_sensitivities(traj, columns: Sequence[SensitivityColumn], S: np.ndarray):
    """``traj`` with the sensitivity columns added (`Trajectory.sensitivity`)."""
    extra = dict(traj.extra)
    extra.update(sensitivity_extra(traj.coordinates, columns, S))
    return dataclasses.replace(traj, extra=extra, sensitivity_names=tuple(c.name for c in columns))


def check_sensitivity_options(source, options: SimulationOptions) -> None:
    """Refuse what the sensitivities cannot be integrated with: inputs, a method other than dop853, events,
    complementary constraints or exact dry friction."""
    if options.inputs is not None:
        raise SimulationError("Sensitivities are integrated with the inputs at their values: `inputs=` cannot "
                              "be given with `sensitivities=`.",
                              fix="give constant inputs as parameters (parameters={'F': 1.0}), or run the "
                                  "sensitivities without the inputs")
    method = options.method
    if method != "dop853":
        raise SimulationError(f"Sensitivities are integrated by the compiled `dop853`, not `{method}`.",
                              fix="use method='dop853' (the default)" + (
                                  "; its fixed-step mode is dt=..." if method in BUILTIN else ""))
    if options.events:
        raise SimulationError("Sensitivities and events cannot be combined: an event time moves with the "
                              "parameters, and the sensitivities would jump there.",
                              fix="run the events and the sensitivities separately")
    if options.stabilization is not None or exact_contact_model(source) is not None:
        raise SimulationError("Sensitivities are computed for ordinary differential equations M q'' = F only, "
                              "not for complementary constraints or exact dry friction.",
                              fix="leave out the sensitivities, or regularize the contact")


def run_sensitivities(source, options: SimulationOptions):
    """`simulate` with ``options.sensitivities``: the motion and ∂y/∂x for each x asked for (module docstring).

    Raises
    ------
    SimulationError
        Besides `simulate`'s: a method other than ``dop853``, events, a model with complementary
        constraints or exact dry friction, an input or an unknown name among the sensitivities.
    """
    check_sensitivity_options(source, options)
    sensitivities = options.sensitivities
    opts = sensitivities if isinstance(sensitivities, Sensitivities) else Sensitivities(tuple(sensitivities))
    source, constrained = constrained_source(source)
    if constrained is not None:
        raise SimulationError("Sensitivities are computed for ordinary differential equations M q'' = F only, "
                              "and this model keeps complementary constraints (a differential-algebraic system).",
                              fix="choose principal coordinates that satisfy the constraints, or leave out the "
                                  "sensitivities")
    if isinstance(source, Model):
        source = derive(source)
    # the names are checked before anything is compiled
    columns = parse_sensitivities(source.eom if isinstance(source, CompiledSystem) else source, opts.names)
    system = resolve(source, [], options.backend)
    if system.backend != "c":
        raise SimulationError("Sensitivities are integrated in compiled C, and no C compiler was found.",
                              fix="install a C compiler (e.g. gcc)")
    tolerance = default_tolerance(options.method, options.rtol) if options.tolerance is None else options.tolerance
    p = system.parameter_vector(options.parameters)
    y0 = initial_state(system.eom, options.initial)
    n = system.n
    t_start, t_end = float(options.t_start), float(options.t_end)
    width = 4 * n + len(system.monitors) + 1 + 2 * n * len(columns)
    t_out = output_times(t_start, t_end, options.n_out, options.t_eval, width)
    M, F0 = system.mass_forces(options.t_start, y0, p)
    if not (np.isfinite(M).all() and np.isfinite(F0).all()) or \
            not np.linalg.eigvalsh(M)[0] > 1e-12 * max(abs(np.linalg.eigvalsh(M)[-1]), 1e-300):
        raise singularity(system, options.t_start, y0, p, "at the initial state")
    sens = sensitivity_system(system, [system.parameters[c.parameter] for c in columns if c.parameter is not None])
    ctl = control_block("dop853", t_start, t_end, t_out, options.rtol, options.atol, options.dt, options.max_step,
                        options.max_steps, None, options.stiffness_check)
    reporter = make_reporter(options.progress, t_start, t_end)

    def watch(call, ctl):
        with Watch(reporter, ctl):
            return interruptible(call, ctl)

    run = sens.run(p, y0, columns, t_out, t_end, ctl=ctl, in_error_norm=opts.in_error_norm, watch=watch)
    if reporter:
        reporter.finish(float(ctl[0]), run.code == 0)

    def partial(status: str):
        if not len(run.t):
            return None
        traj = trajectory(system, p, run.t, run.y, [], options.method, run.steps, run.rhs_calls, tolerance, status,
                          float(ctl[12]))
        return with_sensitivities(traj, columns, run.S)

    if run.code == 0:
        return partial("completed")
    raise _failure(system, p, run, ctl, partial)


def _failure(system: CompiledSystem, p: np.ndarray, run: SensitivityRun, ctl: np.ndarray,
             partial) -> BaseException:
    """The error of a run that did not complete, with the part computed so far where there is one."""
    code, n = run.code, system.n
    t_fail = float(ctl[0])
    y_fail = run.z[: 2 * n]
    if code == INTERRUPTED:
        return Interrupted(t_fail, partial(f"interrupted at t = {t_fail:.9g} (partial)"))
    if code in (5, STIFF):
        err = early_stop(system, code, ctl, y_fail)
        err.trajectory = partial(f"stopped at t = {t_fail:.9g} (partial): {err.reason}")  # type: ignore[attr-defined]
        return err
    if code == 1:
        return singularity(system, t_fail, y_fail, p, "during the integration")
    return SimulationError(f"The integration stopped at t = {t_fail:.9g} ({state_text(system, y_fail)}): "
                           f"{STATUS.get(code, 'the integration failed')}.",
                           fix="the equations may be stiff or singular there: check the model, or loosen the "
                               "tolerances", t=t_fail, state=y_fail.copy())
