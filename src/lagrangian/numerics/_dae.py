"""Simulation of systems with complementary constraints: a differential-algebraic system.

The state is y = (q, q̇) as for any model; the multipliers λ are not integrated but
solved at each evaluation from the augmented equations (see `_codegen_dae`): the
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

import ctypes
from collections.abc import Callable, Mapping, Sequence
from pathlib import Path

import numpy as np
import symengine as se

from ..analysis import first_integrals
from ..dynamics import EquationsOfMotion, derive
from ..errors import SimulationError
from ..model import load_model
from ..model.spec import Model
from ._codegen import monitor_expressions
from ._codegen_dae import generate_dae_c
from ._compile import compile_library, compiler
from ._input_run import InputsAt, rowwise
from ._inputs import resolve_inputs
from ._progress import progress_bar
from ._projection import check_initial, project, project_many
from ._system import known_values, unused_parameters
from ._trajectory import Event, Trajectory, conservation

__all__ = ["STABILIZATIONS", "ConstrainedSystem", "constrained_source", "reaction_columns", "simulate_dae"]

STABILIZATIONS = ("projection", "baumgarte", "both", "none")
#: Methods whose state may be replaced between steps (the projection needs it).
EXPLICIT = {"dop853": "DOP853", "DOP853": "DOP853", "RK45": "RK45", "RK23": "RK23"}
IMPLICIT = ("Radau", "BDF", "LSODA")
#: Default Baumgarte rates (α, β), in 1/time.
BAUMGARTE = (5.0, 5.0)

_P = ctypes.c_void_p
_SIGNATURES = {
    "lgd_eval_rhs": (ctypes.c_int, [ctypes.c_int, _P, _P, _P, _P, _P, _P, _P]),
    "lgd_eval_parts": (None, [ctypes.c_int, _P, _P, _P, _P, _P, _P, _P, _P, _P]),
    "lgd_eval_monitors": (None, [ctypes.c_int, _P, _P, _P, _P]),
    "lgd_eval_reactions": (None, [ctypes.c_int, _P, _P, _P, _P, _P]),
    "lgd_dimensions": (ctypes.c_int, [_P]),
}
_FAILURES = {1: "the mass matrix M became singular",
             2: "the constraint rows became dependent (A M⁻¹ Aᵀ singular): the multipliers are not determined",
             3: "the state stopped being finite (overflow)"}


def _ptr(a: np.ndarray) -> int:
    return a.ctypes.data


def reaction_columns(eom: EquationsOfMotion) -> list[tuple[str, se.Basic]]:
    """(column name, expression in q, q̇, λ, t) of every reaction component (module docstring)."""
    out: list[tuple[str, se.Basic]] = []
    frames = eom.kinematics.frames
    for r in eom.reactions:
        if r.physical:
            axes = frames.axes(r.frame)
            if r.point is not None:
                out += [(f"R_{r.constraint}_{a}", c) for a, c in zip(axes, r.force_components, strict=True)]
            if r.body is not None:
                out += [(f"M_{r.constraint}_{a}", c) for a, c in zip(axes, r.moment_components, strict=True)]
        else:
            out += [(f"Q_{r.constraint}_{name}", g) for name, g in zip(eom.coordinates, r.generalized, strict=True)]
    return out


class ConstrainedSystem:
    """Numeric evaluators of a constrained model: parts, q̈ and λ, monitors, reactions.

    Attributes
    ----------
    eom : the equations (with ``eom.constraints``).
    n, m : coordinates and complementary rows.
    rows : row names; ``holonomic`` : boolean mask of the holonomic rows.
    monitors, reactions : names of the monitor and reaction columns.
    integrals : the first integrals among the monitors.
    backend : ``"c"`` or ``"symengine"``.
    regime : each declared input's regime (``"off"``, ``"constant"``, ``"varying"``) the integrals were
        found for (``inputs``; off where not given).
    """

    def __init__(self, eom: EquationsOfMotion, *, backend: str = "auto", inputs: Mapping[str, str] | None = None
                 ) -> None:
        if not eom.constraints:
            raise ValueError("ConstrainedSystem needs a model with complementary constraints")
        if backend not in ("auto", "c", "symengine"):
            raise ValueError(f"backend must be 'auto', 'c' or 'symengine', not {backend!r}")
        self.eom = eom
        self.n, self.m = len(eom.q), len(eom.constraints)
        self.coordinates = eom.coordinates
        self.parameters = tuple(p.name for p in eom.model.parameters)
        self.rows = tuple(r.name for r in eom.constraints)
        self.holonomic = np.array([r.kind == "holonomic" for r in eom.constraints])
        self.regime = {u: (inputs or {}).get(u, "off") for u in eom.model.inputs}
        integrals = first_integrals(eom, inputs=inputs)  # inputs: each input's regime (off by default)
        self.integrals = tuple(fi.name for fi in integrals)
        monitor_items = monitor_expressions(eom, integrals)
        self.monitors = tuple(name for name, _ in monitor_items)
        reaction_items = reaction_columns(eom)
        self.reactions = tuple(name for name, _ in reaction_items)
        rows = eom.constraints
        self._unused = unused_parameters(self.parameters, [
            *(e for row in eom.M for e in row), *eom.F, *(a for r in rows for a in r.coefficients),
            *(r.b for r in rows), *(r.bias for r in rows), *(e for _, e in monitor_items),
            *(e for _, e in reaction_items)])
        if backend == "auto":
            backend = "c" if compiler() is not None else "symengine"
        self.backend = backend
        if backend == "c":
            generated = generate_dae_c(eom, [e for _, e in monitor_items], [e for _, e in reaction_items])
            self.source = generated.source
            self._lib = compile_library(generated.source, generated.key)
            for name, (restype, argtypes) in _SIGNATURES.items():
                fn = getattr(self._lib, name)
                fn.restype, fn.argtypes = restype, argtypes
            dims = np.zeros(4, dtype=np.intc)
            self._lib.lgd_dimensions(_ptr(dims))
            assert tuple(dims) == (self.n, self.m, len(self.monitors), len(self.reactions)), "stale library"
        else:
            self.source, self._lib = None, None
            self._lambdify(monitor_items, reaction_items)
        self.worst_pivot = 1.0

    # -- values of the parameters -------------------------------------------------------------
    def parameter_vector(self, values: Mapping[str, float] | None = None) -> np.ndarray:
        """The ``p`` array: the model's values overridden by ``values`` (errors as `CompiledSystem`'s)."""
        values = dict(values or {})
        unknown = sorted(set(values) - set(self.parameters))
        if unknown:
            raise SimulationError(f"`{unknown[0]}` is not a parameter of `{self.eom.model.name}`.",
                                  fix="the parameters are " + (", ".join(self.parameters) or "(none)"))
        model_values = self.eom.model.parameter_values
        out = np.empty(len(self.parameters))
        for k, name in enumerate(self.parameters):
            value = values.get(name, model_values[name])
            if value is None and name in self._unused:
                out[k] = np.nan  # nothing computed reads it (`_system.unused_parameters`)
                continue
            if value is None:
                raise SimulationError(f"The parameter `{name}` has no value, so the motion cannot be computed.",
                                      fix=f"give it one in the model file (`{name} = {{ value = ... }}`) or with "
                                          f"`--set {name}=...`")
            if not np.isfinite(float(value)):
                raise SimulationError(f"The parameter `{name}` = {value} is not a finite number.",
                                      fix=f"give `{name}` a finite value")
            out[k] = float(value)
        return out

    # -- evaluators ---------------------------------------------------------------------------------
    def _batch(self, t, y) -> tuple[np.ndarray, np.ndarray, bool]:  # type: ignore[no-untyped-def]
        Y = np.ascontiguousarray(y, dtype=float)
        single = Y.ndim == 1
        Y = Y.reshape(-1, 2 * self.n)
        T = np.ascontiguousarray(np.broadcast_to(np.asarray(t, dtype=float), (len(Y),)))
        return T, Y, single

    def parts(self, t, y, p: np.ndarray) -> tuple[np.ndarray, ...]:  # type: ignore[no-untyped-def]
        """(M, F, A, c, g, f) at each state: M q̈ = F + Aᵀλ, A q̈ + c = 0, g = A q̇ + b, f = holonomic residuals."""
        T, Y, single = self._batch(t, y)
        N, n, m = len(Y), self.n, self.m
        if self._lib is not None:
            M, F, A = np.empty((N, n, n)), np.empty((N, n)), np.empty((N, m, n))
            c, g, f = np.empty((N, m)), np.empty((N, m)), np.empty((N, m))
            self._lib.lgd_eval_parts(N, _ptr(T), _ptr(Y), _ptr(p), _ptr(M), _ptr(F), _ptr(A), _ptr(c), _ptr(g),
                                     _ptr(f))
        else:
            out = np.asarray(self._se_parts(np.column_stack([T, Y, np.broadcast_to(p, (N, len(p)))])))
            out = out.reshape(N, -1)
            sizes = [n * n, n, m * n, m, m, m]
            pieces = np.split(out, np.cumsum(sizes)[:-1], axis=1)
            M, F, A = pieces[0].reshape(N, n, n), pieces[1], pieces[2].reshape(N, m, n)
            c, g, f = pieces[3], pieces[4], pieces[5]
        result = (M, F, A, c, g, f)
        return tuple(a[0] for a in result) if single else result

    def rhs(self, t, y, p: np.ndarray, stab: Sequence[float] = (0.0, 0.0)) -> tuple[np.ndarray, np.ndarray]:  # type: ignore[no-untyped-def]
        """(ẏ, λ) at each state, with Baumgarte rates ``stab`` = (α, β).

        Raises
        ------
        SimulationError
            When M or A M⁻¹ Aᵀ is singular at one of the states, or the result is not finite.
        """
        T, Y, single = self._batch(t, y)
        N = len(Y)
        stab_a = np.ascontiguousarray(stab, dtype=float)
        if self._lib is not None:
            dY, LAM, worst = np.empty_like(Y), np.empty((N, self.m)), np.ones(1)
            status = self._lib.lgd_eval_rhs(N, _ptr(T), _ptr(Y), _ptr(p), _ptr(stab_a), _ptr(dY), _ptr(LAM),
                                            _ptr(worst))
            self.worst_pivot = min(self.worst_pivot, float(worst[0]))
            if status:
                raise SimulationError(f"At one of the given states {_FAILURES[status]}.",
                                      fix="check the state, and that no two constraints repeat each other there")
        else:
            M, F, A, c, g, f = self.parts(T, Y, p)
            try:
                X = np.linalg.solve(M, np.concatenate([np.swapaxes(A, 1, 2), F[..., None]], axis=2))
                XA, XF = X[..., :-1], X[..., -1]
                S = A @ XA
                r = -c - 2 * stab_a[0] * g - stab_a[1] ** 2 * f - np.einsum("nki,ni->nk", A, XF)
                LAM = np.linalg.solve(S, r[..., None])[..., 0]
            except np.linalg.LinAlgError:
                raise SimulationError("At one of the given states M or A M⁻¹ Aᵀ is singular.",
                                      fix="check the state, and that no two constraints repeat each other") from None
            dY = np.concatenate([Y[:, self.n:], XF + np.einsum("nik,nk->ni", XA, LAM)], axis=1)
        return (dY[0], LAM[0]) if single else (dY, LAM)

    def monitor_values(self, t, y, p: np.ndarray) -> np.ndarray:  # type: ignore[no-untyped-def]
        """First integrals, T, U at each state: shape (N, len(monitors))."""
        T, Y, _ = self._batch(t, y)
        k = len(self.monitors)
        if self._lib is not None:
            out = np.zeros((len(Y), max(k, 1)))
            self._lib.lgd_eval_monitors(len(Y), _ptr(T), _ptr(Y), _ptr(p), _ptr(out))
            return out[:, :k]
        return np.asarray(self._se_mon(np.column_stack([T, Y, np.broadcast_to(p, (len(Y), len(p)))]))
                          ).reshape(len(Y), k)

    def reaction_values(self, t, y, lam, p: np.ndarray) -> np.ndarray:  # type: ignore[no-untyped-def]
        """Reaction components (`reaction_columns`) at each state and multipliers: shape (N, len(reactions))."""
        T, Y, _ = self._batch(t, y)
        LAM = np.ascontiguousarray(np.asarray(lam, dtype=float).reshape(len(Y), self.m))
        k = len(self.reactions)
        if self._lib is not None:
            out = np.zeros((len(Y), max(k, 1)))
            self._lib.lgd_eval_reactions(len(Y), _ptr(T), _ptr(Y), _ptr(LAM), _ptr(p), _ptr(out))
            return out[:, :k]
        args = np.column_stack([T, Y, LAM, np.broadcast_to(p, (len(Y), len(p)))])
        return np.asarray(self._se_reac(args)).reshape(len(Y), k)

    def _lambdify(self, monitor_items, reaction_items) -> None:  # type: ignore[no-untyped-def]
        eom = self.eom
        params = [se.Symbol(name) for name in self.parameters]
        args = [eom.t, *eom.q, *eom.qd, *params]
        rows = eom.constraints
        n = self.n
        parts = [eom.M[i][j] for i in range(n) for j in range(n)] + list(eom.F)
        parts += [x for r in rows for x in r.coefficients] + [r.bias for r in rows] + [r.velocity for r in rows]
        parts += [r.expression if r.kind == "holonomic" else se.Integer(0) for r in rows]

        def make(arguments, exprs):  # type: ignore[no-untyped-def]
            return se.Lambdify(arguments, list(exprs) or [se.Integer(0)], cse=True)

        self._se_parts = make(args, parts)
        self._se_mon = make(args, [e for _, e in monitor_items])
        self._se_reac = make([eom.t, *eom.q, *eom.qd, *eom.multipliers, *params], [e for _, e in reaction_items])


# -- the run ---------------------------------------------------------------------------------------------
def constrained_source(source):  # type: ignore[no-untyped-def]
    """(source, eom): the equations when ``source`` keeps constraints complementary, else (source, None).

    A file path is read once and handed back as its `Model`, so `simulate` does not read it again.
    """
    from ._system import CompiledSystem

    if isinstance(source, (CompiledSystem, ConstrainedSystem)):
        eom = source.eom
    elif isinstance(source, EquationsOfMotion):
        eom = source
    elif isinstance(source, Model):
        if not any(not c.principal for c in source.constraints):
            return source, None
        eom = derive(source)
    elif isinstance(source, (str, Path)):
        model = load_model(source)
        if not any(not c.principal for c in model.constraints):
            return model, None
        eom = derive(model)
    else:
        return source, None
    return (source, eom) if eom.constraints else (source, None)


def simulate_dae(
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
    events: Sequence = (),
    tolerance: float | None = None,
    max_steps: int = 100_000_000,
    progress: bool | Callable[[float, float], None] = False,
    backend: str = "auto",
    stabilization: str | None = None,
    baumgarte: tuple[float, float] = BAUMGARTE,
    inputs=None,
) -> Trajectory:
    """Integrate a model with complementary constraints (module docstring); `simulate`'s options, plus:

    Parameters
    ----------
    stabilization : ``"projection"`` (default with explicit methods), ``"baumgarte"`` (default with
        ``Radau``, ``BDF``, ``LSODA``), ``"both"`` or ``"none"``.
    baumgarte : (α, β), the rates of Baumgarte's stabilisation.

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
    from scipy import integrate

    from ._simulate import _event_expressions, _output_times, check_options, default_tolerance, initial_state

    source, eom = constrained_source(source)
    if eom is None:
        raise SimulationError("This model keeps no constraint complementary.", fix="use lagrangian.simulate")
    if dt is not None:
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
    projecting = stabilization in ("projection", "both")
    if projecting and method not in EXPLICIT:
        raise SimulationError(f"The projection onto the constraints needs an explicit method, not `{method}`.",
                              fix="use method='dop853', or stabilization='baumgarte' with this method")
    check_options(rtol, atol, tolerance)
    # The default tolerance applies to the first integrals; the constraint residuals are
    # checked only against a tolerance asked for.
    residual_tolerance = tolerance
    if tolerance is None:
        tolerance = default_tolerance(method, rtol)
    stab = np.array(baumgarte if stabilization in ("baumgarte", "both") else (0.0, 0.0), dtype=float)
    law = resolve_inputs(eom, inputs)
    given = {**(parameters or {})}
    twice = sorted(set(given) & {s.name for s in law.sources})
    if twice:
        raise SimulationError(f"The input `{twice[0]}` is given both as a parameter value and by the inputs' law.",
                              fix="give it once: in inputs= (--input) or in parameters= (--set)")
    given.update(law.constants)
    regime = law.regime(given, tuple(eom.model.inputs))
    # A system given is used when its integrals are those of this run's regime (and its backend the one asked).
    if isinstance(source, ConstrainedSystem) and source.regime == regime and backend in ("auto", source.backend):
        system = source
    else:
        system = ConstrainedSystem(eom, backend=backend, inputs=regime)
    p = system.parameter_vector(given)
    # Inputs that vary are computed here, in Python, at each evaluation: this path steps in Python
    # anyway (SciPy's solver, the projection), and a table's interval is the current segment's.
    applied = InputsAt(law, eom, system.parameters, p)
    y0 = initial_state(eom, initial)
    t_out = _output_times(float(t_start), float(t_end), n_out, t_eval,
                          4 * system.n + 3 * system.m + len(system.monitors) + len(system.reactions) + 1)
    check_initial(system, float(t_start), y0, p)
    specs = _event_expressions(eom, [e for e in events])
    event_fn = None
    if specs:
        args = [eom.t, *eom.q, *eom.qd, *(se.Symbol(k) for k in system.parameters)]
        lam = se.Lambdify(args, [s.expression for s in specs])

        def event_fn(t: float, y: np.ndarray) -> np.ndarray:
            return np.asarray(lam(np.concatenate([[t], y, applied(t, y)])), dtype=float).ravel()

    calls = [0]

    def fun(t: float, y: np.ndarray) -> np.ndarray:
        calls[0] += 1
        try:
            return system.rhs(t, y, applied(t, y), stab)[0]
        except SimulationError as exc:
            raise SimulationError(f"At t = {t:.9g}: {exc.message}", fix=exc.fix, t=t, state=y.copy()) from None

    solver_class = getattr(integrate, EXPLICIT.get(method, method))
    tol = max(1e-3 * atol, 1e-15)
    # A table's samples are breakpoints: the solver starts again at each (`_input_run`).
    edges = [float(t_start), *(float(b) for b in law.breakpoints if t_start < b < t_end), float(t_end)]
    segment = 0
    applied.window = 0.5 * (edges[0] + edges[1])
    solver = solver_class(fun, float(t_start), y0, edges[1], rtol=rtol, atol=atol,
                          max_step=np.inf if max_step is None else max_step)
    N = len(t_out)
    Y = np.full((N, 2 * system.n), np.nan)
    i_out = 0
    while i_out < N and t_out[i_out] <= t_start:
        Y[i_out] = y0
        i_out += 1
    report = progress_bar if progress is True else (progress or None)
    steps, status = 0, "completed"
    evs: list[tuple[str, float, np.ndarray]] = []
    g_old = event_fn(t_start, y0) if event_fn else None
    while solver.status == "running" or (solver.status == "finished" and segment + 2 < len(edges)):
        if solver.status == "finished":  # the next interval between two breakpoints of the inputs
            segment += 1
            applied.window = 0.5 * (edges[segment] + edges[segment + 1])
            solver = solver_class(fun, edges[segment], solver.y.copy(), edges[segment + 1], rtol=rtol, atol=atol,
                                  max_step=np.inf if max_step is None else max_step)
        message = solver.step()
        if solver.status == "failed":
            raise SimulationError(f"The integration stopped at t = {solver.t:.9g}: {message}.",
                                  fix="the equations may be stiff there: try method='Radau' with "
                                      "stabilization='baumgarte', or check the model", t=solver.t, state=solver.y)
        steps += 1
        if steps > max_steps:
            raise SimulationError(f"The maximum number of steps ({max_steps}) was reached at t = {solver.t:.9g}.",
                                  fix="raise max_steps, or shorten the time span", t=solver.t, state=solver.y)
        t_old, t_new = solver.t_old, solver.t
        dense = solver.dense_output()
        if projecting:
            y_new, changed = project(system, t_new, solver.y, p, tol)
            if changed:
                solver.y = y_new
                solver.f = fun(t_new, y_new)  # the first stage of the next step (FSAL)

        # This step's dense output, end and solver, bound now (the loop moves on to the next ones).
        def state(t: float, dense=dense, t_new=t_new, solver=solver) -> np.ndarray:  # type: ignore[no-untyped-def]
            y = dense(t) if t < t_new else solver.y.copy()
            return project(system, t, y, p, tol)[0] if projecting else y

        def raw_state(t: float, dense=dense, t_new=t_new, solver=solver) -> np.ndarray:  # type: ignore[no-untyped-def]
            # projected with all the outputs at the end
            return dense(t) if t < t_new else solver.y.copy()

        t_stop = None
        if event_fn is not None:
            g_new = event_fn(t_new, solver.y)
            for k, spec in enumerate(specs):
                a, b = g_old[k], g_new[k]  # type: ignore[index]
                crossed = (a < 0 <= b and spec.direction >= 0) or (a > 0 >= b and spec.direction <= 0)
                if not crossed or a == 0:
                    continue
                from scipy.optimize import brentq

                te = brentq(lambda s, k=k: event_fn(s, state(s))[k], t_old, t_new, xtol=4e-16 * max(1.0, abs(t_new)))
                evs.append((spec.name, float(te), state(te)))
                if spec.terminal:
                    t_stop = te if t_stop is None else min(t_stop, te)
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
    if projecting and i_out:
        Y[:i_out] = project_many(system, t_out[:i_out], Y[:i_out], p, tol)[0]
    applied.window = None
    return _trajectory(system, p, t_out[:i_out], Y[:i_out], stab, evs, method, stabilization, steps, calls[0],
                       tolerance, status, residual_tolerance=residual_tolerance, applied=applied)


def _trajectory(system: ConstrainedSystem, p, t, Y, stab, evs, method, stabilization, steps, nfev,  # type: ignore[no-untyped-def]
                tolerance, status, *, residual_tolerance: float | None = None,
                applied: InputsAt | None = None) -> Trajectory:
    """The `Trajectory` of a run; ``tolerance`` for the first integrals, ``residual_tolerance``
    (default ``tolerance``) for the constraint residuals."""
    from ._simulate import momenta

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
