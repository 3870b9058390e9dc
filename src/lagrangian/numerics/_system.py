"""A model's equations as fast numeric functions: `CompiledSystem`.

`compile_system(eom)` turns M(q, t) q̈ = F(q, q̇, t), the monitors (first integrals, T,
U) and optional event functions into compiled C (see `codegen._codegen`), loaded once.  All
evaluators take the parameter values as an array, so one compiled system serves every
``--set``; all accept a batch of states, which is how the per-state cost falls to a
fraction of a microsecond.

Where no C compiler exists, ``backend="symengine"`` (chosen automatically) evaluates the
same expressions with SymEngine's ``Lambdify`` (LLVM when available); only the built-in
integrators need the C backend.

Inputs that vary (``inputs=``, or the model's ``[controls]``: `_inputs`) are compiled in with
the model (`_input_code`); their numbers (gains, tables) follow the parameters in ``p``, so
`parameter_vector` appends them.  The first integrals monitored are those that hold with the
inputs as the law leaves them (off, constant or varying: `lagrangian.first_integrals`).
"""

from __future__ import annotations

import ctypes
from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np
import symengine as se

from ..analysis import FirstIntegral, first_integrals, tree_integrals
from ..codegen import GeneratedSource, generate_c, monitor_expressions
from ..dynamics import EquationsOfMotion
from ..errors import SimulationError
from ._compile import Compilers, cached_library, compile_library, compiler
from ._fastcall import rhs_caller
from ._input_code import law_code
from ._inputs import InputLaw, resolve_inputs
from ._plans import Plan, plan_key, read_plan, write_plan

__all__ = ["CompiledSystem", "compile_system", "known_values", "unused_parameters"]


def unused_parameters(parameters: Sequence[str], expressions: Sequence[se.Basic]) -> frozenset[str]:
    """The names among ``parameters`` that no expression of ``expressions`` holds.

    Such a parameter needs no value to compute the motion (the mass of a pulley turning about
    its fixed centre: it enters neither M, F nor the first integrals); `parameter_vector`
    then gives it NaN, which nothing reads, rather than refusing the run.
    """
    used: set[se.Basic] = set()
    for e in expressions:
        used |= e.free_symbols
    return frozenset(name for name in parameters if se.Symbol(name) not in used)


def known_values(parameters: Sequence[str], p: np.ndarray) -> dict[str, float]:
    """The values of ``p`` by name, leaving out the NaN of unused parameters without a value."""
    # p may go on with constants precomputed by the C backend: only its first len(parameters) are values
    return {name: float(v) for name, v in zip(parameters, p[:len(parameters)], strict=True) if not np.isnan(v)}

_P = ctypes.c_void_p
_SIGNATURES = {
    "lg_eval_rhs": (ctypes.c_int, [ctypes.c_int, _P, _P, _P, _P]),
    "lg_eval_mass_forces": (None, [ctypes.c_int, _P, _P, _P, _P, _P]),
    "lg_eval_monitors": (None, [ctypes.c_int, _P, _P, _P, _P]),
    "lg_eval_events": (None, [ctypes.c_int, _P, _P, _P, _P]),
    "lg_dimensions": (ctypes.c_int, [_P]),
    "lg_constants": (None, [_P, _P]),
    "lg_dop853": (ctypes.c_int, [_P, _P, _P, _P, ctypes.c_int, _P, _P, ctypes.c_double, _P, _P, _P]),
    "lg_gauss": (ctypes.c_int, [_P, _P, _P, _P, ctypes.c_int, _P, _P, ctypes.c_double, _P, _P, _P,
                                ctypes.c_double]),
}
#: The evaluator of the inputs' law, in a library compiled with one.
_INPUT_SIGNATURE = (ctypes.c_int, [ctypes.c_int, _P, _P, _P, _P])


def _ptr(a: np.ndarray) -> int:
    return a.ctypes.data


class CompiledSystem:
    """Numeric M, F, q̈, monitors and events of one model (see the module docstring).

    Parameters
    ----------
    eom : EquationsOfMotion
        The equations.
    integrals : sequence of FirstIntegral, optional
        The first integrals to monitor; None: those `first_integrals` finds for the inputs' regimes.
    events : sequence of (str, SymEngine expression), optional
        (name, g) pairs; an event occurs where g(t, q, q̇) changes sign.
    backend : {"auto", "c", "symengine"}, optional
        Compiled C (when a compiler exists, "auto") or SymEngine's evaluation.
    inputs : dict or Feedback or InputLaw, optional
        The inputs' law compiled in, as `simulate` takes it; None: the model's ``[controls]``.
    constant_inputs : sequence of str, optional
        Inputs held at a value other than 0 by the parameters (so that their integrals are those of
        a constant input).

    Attributes
    ----------
    eom : EquationsOfMotion
        The equations it was generated from.
    n : int
        The number of coordinates; states are y = (q, q̇), shape (2n,) or (N, 2n).
    coordinates, parameters, monitors, events : tuple of str
        Names, in array order.
    integrals : tuple of FirstIntegral
        The first integrals among the monitors.
    backend : str
        ``"c"`` or ``"symengine"``.
    law : InputLaw
        The inputs' law (`_inputs`).
    inputs : tuple of str
        The names of the inputs it drives, in the order of `input_values`' columns.
    regime : dict of str to str
        Each declared input's regime (``"off"``, ``"constant"``, ``"varying"``) the integrals were
        found for.
    """

    def __init__(self, eom: EquationsOfMotion, *, integrals: Sequence | None = None,
                 events: Sequence[tuple[str, se.Basic]] = (), backend: str = "auto", inputs=None,
                 constant_inputs: Sequence[str] = ()) -> None:
        if backend not in ("auto", "c", "symengine"):
            raise ValueError(f"backend must be 'auto', 'c' or 'symengine', not {backend!r}")
        self.eom = eom
        self.n = len(eom.q)
        self.coordinates = eom.coordinates
        if backend == "auto":
            backend = "c" if compiler() is not None else "symengine"
        self.backend = backend
        self.law = inputs if isinstance(inputs, InputLaw) else resolve_inputs(eom, inputs)
        self.inputs = tuple(s.name for s in self.law.driven)
        # Inputs held at a value other than 0 are parameters like any other; the others are off.
        values = {**{u: v for u, v in eom.model.parameter_values.items() if u in eom.model.inputs},
                  **self.law.constants, **dict.fromkeys(constant_inputs, 1.0)}
        self.regime = self.law.regime(values, tuple(eom.model.inputs))
        # With a recursive form the C code monitors the integrals found from it (`tree_integrals`: the
        # momenta, the energy and Noether's, over its intermediates), T and U; the course's search
        # (`first_integrals`) and its T, U would first make the whole course derivation.
        self._recursive = eom.recursive is not None and backend == "c"
        self._first_integrals = None if integrals is None else tuple(integrals)
        self.parameters = tuple(p.name for p in eom.model.parameters)
        self._unused: frozenset[str] | None = None  # see `unused_parameters`
        self._events = tuple(events)
        self.events = tuple(name for name, _ in self._events)
        self._law_size = 0
        self._generated: GeneratedSource | None = None
        self._lib: Any = None  # the compiled model's ctypes library: its functions are looked up by name
        if backend == "c":
            self._code = law_code(eom, self.law) if self.law.driven else None
            if self._code is not None:
                self._law_size = self._code.size
            # A run that made this system before left its plan (`_plans`): then neither the first
            # integrals nor the C source are needed to load the library it compiled.
            key = None if integrals is not None else plan_key(
                eom, self.regime, None if self._code is None else self._code.prelude + self._code.epilogue,
                self._events)
            plan = read_plan(key) if key else None
            library = cached_library(plan.library, plan.units) if plan else None
            if plan is None or library is None or not self._bind(library, plan.integrals, plan.monitors,
                                                                  plan.constants):
                self._compile(key)
        else:
            self.integrals = tuple(fi.name for fi in self.first_integrals)
            self.monitors = tuple(name for name, _ in monitor_expressions(eom, self.first_integrals))
            self._constants = 0
            self._lambdify()
            self._law_python = self.law.evaluator(eom, self.parameters) if self.law.driven else None
        # Without C the law runs in Python, its numbers in the law itself; its hint (a time inside the
        # current interval between breakpoints, NaN outside a run) is kept here.
        self._hint = np.full(1, np.nan)
        self._t1 = np.zeros(1)

    def _compile(self, key: str | None) -> None:
        """Generate the C source, compile (or find) its library and bind it; store the plan under ``key``.

        The units of the long functions' parts are compiled as they are generated (`Compilers`).
        """
        with Compilers() as compilers:
            # The integrals as a function: sought while M and F's parts compile.
            generated = self._generated = generate_c(self.eom, lambda: self.first_integrals, self._events,
                                                     law=self._code, on_unit=compilers.part)
            library = compile_library(generated.units, generated.key, compilers=compilers)
        integrals = tuple(fi.name for fi in self.first_integrals)
        monitors = tuple(name for name, _ in monitor_expressions(self.eom, self.first_integrals,
                                                                  recursive=self._recursive))
        if not self._bind(library, integrals, monitors, generated.constants):
            raise SimulationError("The compiled library does not have the dimensions of the model it was made for.",
                                  fix="report this as a bug of lagrangian, with the model file")
        if key is not None:
            write_plan(key, Plan(integrals, monitors, generated.constants, generated.key, len(generated.units)))

    def _bind(self, library: ctypes.CDLL, integrals: tuple[str, ...], monitors: tuple[str, ...],
              constants: int) -> bool:
        """Use ``library`` for this system, with these names; False (nothing changed) when its dimensions differ."""
        for name, (restype, argtypes) in _SIGNATURES.items():
            fn = getattr(library, name)
            fn.restype, fn.argtypes = restype, argtypes
        dims = np.zeros(3, dtype=np.intc)
        library.lg_dimensions(_ptr(dims))
        if tuple(dims) != (self.n, len(monitors), len(self.events)):
            return False
        if self._code is not None:
            library.lg_eval_inputs.restype, library.lg_eval_inputs.argtypes = _INPUT_SIGNATURE
        self._lib, self.integrals, self.monitors, self._constants = library, integrals, monitors, constants
        # The one-state call through ctypes costs ~4 µs, mostly Python's; the vectorcall
        # wrapper brings it to the C evaluation plus ~0.1 µs (`_fastcall`).
        caller = rhs_caller(library.lg_eval_rhs, 2 * self.n,
                            len(self.parameters) + self._constants + self._law_size, library)
        if caller is not None:
            self.rhs_c = caller  # type: ignore[method-assign]  # the vectorcall wrapper stands in for the method
        return True

    @property
    def first_integrals(self) -> tuple[FirstIntegral, ...]:
        """The first integrals monitored (found on first use when the system came from its plan, `_plans`)."""
        if self._first_integrals is None:
            self._first_integrals = tuple(
                tree_integrals(self.eom, self.regime) if self._recursive
                else first_integrals(self.eom, inputs=self.regime))
        return self._first_integrals

    @property
    def generated(self) -> GeneratedSource | None:
        """The generated C of the library (`codegen.GeneratedSource`: source, units, key); None with SymEngine.

        When the system came from its plan (`_plans`), the C is generated again on first use, from
        these equations: the same functions as the library's, their subexpressions numbered alike,
        except in a process that had already derived the model once (SymEngine may then number
        them otherwise, and the key differs).
        """
        if self._generated is None and self.backend == "c":
            self._generated = generate_c(self.eom, self.first_integrals, self._events, law=self._code)
        return self._generated

    @property
    def source(self) -> str | None:
        """The C source of the library, as one translation unit (`generated`); None with the SymEngine backend."""
        generated = self.generated
        return None if generated is None else generated.source

    # -- parameter values -------------------------------------------------------------
    def parameter_vector(self, values: Mapping[str, float] | None = None) -> np.ndarray:
        """The ``p`` array: the model's values, overridden by ``values``.

        Parameters
        ----------
        values : mapping of str to float, optional
            Parameter values by name.

        Returns
        -------
        ndarray
            The parameter vector.

        Raises
        ------
        SimulationError
            When a parameter has no value (naming it and how to give one), or ``values``
            names something that is not a parameter.
        """
        values = dict(values or {})
        unknown = sorted(set(values) - set(self.parameters))
        if unknown:
            raise SimulationError(
                f"`{unknown[0]}` is not a parameter of `{self.eom.model.name}`.",
                fix="the parameters are " + (", ".join(self.parameters) or "(none)"))
        twice = sorted(set(values) & ({s.name for s in self.law.sources}))
        if twice:
            raise SimulationError(f"The input `{twice[0]}` is given both as a parameter value and by the inputs' law.",
                                  fix="give it once: in inputs= (--input) or in parameters= (--set)")
        values.update(self.law.constants)
        model_values = self.eom.model.parameter_values
        out = np.empty(len(self.parameters))
        for k, name in enumerate(self.parameters):
            value = values.get(name, model_values[name])
            if value is None and name in self.unused_parameters:
                out[k] = np.nan  # nothing computed reads it
                continue
            if value is None:
                raise SimulationError(
                    f"The parameter `{name}` has no value, so the motion cannot be computed.",
                    fix=f"give it one in the model file (`{name} = {{ value = ... }}` under [parameters]) "
                        f"or on the command line (`--set {name}=...`)")
            value = float(value)
            if not np.isfinite(value):
                raise SimulationError(f"The parameter `{name}` = {value} is not a finite number.",
                                      fix=f"give `{name}` a finite value")
            out[k] = value
        if self._constants or self._law_size:
            # The parameter-only subexpressions of M and F follow the values (`codegen._rewrite.Hoist`),
            # then the numbers of the inputs' law (`_input_code`).
            extended = np.empty(len(out) + self._constants + self._law_size)
            extended[: len(out)] = out
            if self._constants:
                self._lib.lg_constants(_ptr(extended), _ptr(extended[len(out):]))
            if self._law_size:
                extended[len(out) + self._constants:] = self.law.data()
            return extended
        return out

    def law_block(self, p: np.ndarray) -> np.ndarray:
        """The inputs' law's numbers in ``p``.

        Parameters
        ----------
        p : ndarray
            The parameter vector.

        Returns
        -------
        ndarray
            A view: its hint, ``[0]``, may be written; without C, the hint alone (the law's numbers are
            in the law).
        """
        if self._lib is None:
            return self._hint
        start = len(self.parameters) + self._constants
        return p[start:start + self._law_size]

    def _python_law(self, T: np.ndarray, Y: np.ndarray, p: np.ndarray) -> np.ndarray:
        hint = float(self._hint[0])
        return self._law_python(T, Y, p, None if np.isnan(hint) else hint)

    def input_values(self, t, y, p: np.ndarray) -> np.ndarray:
        """The driven inputs (`inputs`) at each state: shape (N, len(inputs)), as the compiled law gives them.

        Parameters
        ----------
        t : float or ndarray of shape (N,)
            The time(s).
        y : ndarray of shape (2n,) or (N, 2n)
            The state(s) (q, q̇).
        p : ndarray
            The parameter vector.

        Returns
        -------
        ndarray of shape (N, len(inputs))
            The driven inputs, as the compiled law gives them.
        """
        T, Y, single = self._batch(t, y, 2 * self.n)
        k = len(self.inputs)
        if not k:
            out = np.zeros((len(Y), 0))
        elif self._lib is not None:
            out = np.empty((len(Y), k))
            self._lib.lg_eval_inputs(len(Y), _ptr(T), _ptr(Y), _ptr(p), _ptr(out))
        else:
            out = self._python_law(T, Y, p)
        return out[0] if single else out

    def _rows(self, T: np.ndarray, Y: np.ndarray, p: np.ndarray) -> np.ndarray:
        """The SymEngine evaluators' argument rows (t, y, parameters), the driven inputs written in."""
        P = np.array(np.broadcast_to(p[: len(self.parameters)], (len(Y), len(self.parameters))))
        if self.inputs:
            P[:, [self.parameters.index(u) for u in self.inputs]] = self._python_law(T, Y, p)
        return np.column_stack([T, Y, P])

    @property
    def unused_parameters(self) -> frozenset[str]:
        """Parameters that M, F, the monitors and the events do not hold (they need no value)."""
        if self._unused is None:
            exprs = [e for row in self.eom.M for e in row] + list(self.eom.F)
            exprs += [e for _, e in monitor_expressions(self.eom, self.first_integrals)] + [e for _, e in self._events]
            self._unused = unused_parameters(self.parameters, exprs)
        return self._unused

    # -- evaluators (single state or batch) ---------------------------------------------
    @staticmethod
    def _batch(t, y, width: int) -> tuple[np.ndarray, np.ndarray, bool]:
        Y = np.ascontiguousarray(y, dtype=float)
        single = Y.ndim == 1
        Y = Y.reshape(-1, width)
        T = np.ascontiguousarray(np.broadcast_to(np.asarray(t, dtype=float), (len(Y),)))
        return T, Y, single

    def rhs(self, t, y, p: np.ndarray) -> np.ndarray:
        """The derivative ẏ = (q̇, q̈) with q̈ solved from M q̈ = F.

        Parameters
        ----------
        t : float or ndarray of shape (N,)
            The time(s).
        y : ndarray of shape (2n,) or (N, 2n)
            The state(s) (q, q̇).
        p : ndarray
            The parameter vector.

        Returns
        -------
        ndarray
            The derivative ẏ, of the shape of ``y``.

        Raises
        ------
        SimulationError
            When M is singular (or not positive definite) at one of the states, or when a
            state or q̈ is not finite (the solution overflowed: a blow-up).
        """
        T, Y, single = self._batch(t, y, 2 * self.n)
        out = np.empty_like(Y)
        if self._lib is not None:
            status = self._lib.lg_eval_rhs(len(Y), _ptr(T), _ptr(Y), _ptr(p), _ptr(out))
            if status:
                raise _rhs_failure(status, T, Y)
        else:
            M, F = self.mass_forces(T, Y, p)
            out[:, : self.n] = Y[:, self.n:]
            if not np.all(np.isfinite(Y)):
                raise _rhs_failure(2, T, Y)
            try:
                out[:, self.n:] = np.linalg.solve(M, F[..., None])[..., 0]
            except np.linalg.LinAlgError as exc:
                raise SimulationError("The mass matrix M is singular at one of the given states.") from exc
        return out[0] if single else out

    def rhs_c(self, t: float, y: np.ndarray, p: np.ndarray, out: np.ndarray) -> int:
        """One state, no allocation: ``out`` ← ẏ.

        For tight loops and benchmarks; arrays must be contiguous float64 and ``p`` the
        `parameter_vector`.  Where the `_fastcall` extension builds (the usual case), this
        method is replaced on the instance by its vectorcall wrapper, which also checks the
        arrays' type and length; this ctypes version is the fallback.

        Parameters
        ----------
        t : float
            The time.
        y : ndarray of shape (2n,)
            The state.
        p : ndarray
            The parameter vector.
        out : ndarray of shape (2n,)
            Receives ẏ.

        Returns
        -------
        int
            The C status: 0 = fine, 1 = M singular.
        """
        self._t1[0] = t
        return self._lib.lg_eval_rhs(1, _ptr(self._t1), _ptr(y), _ptr(p), _ptr(out))

    def rhs_function(self, parameters: Mapping[str, float] | None = None):
        """A plain ``f(t, y)`` for `scipy.integrate.solve_ivp`, with the analytic Jacobian ``f.jac(t, y)``.

        ``solve_ivp(f, (0, 10), y0, method="Radau", jac=f.jac)``; y = (q, q̇) in `coordinates`
        order, ``parameters`` override the model's values.  Each call returns a new array
        (never a reused buffer).  See `lagrangian.numerics._scipy_rhs.RhsFunction`.

        Parameters
        ----------
        parameters : mapping of str to float, optional
            Override the model's values.

        Returns
        -------
        RhsFunction
            ``f(t, y)``, with ``f.jac``.

        Raises
        ------
        SimulationError
            For a model with complementary constraints (a differential-algebraic system), or
            a parameter without a value.
        """
        from ._scipy_rhs import RhsFunction

        return RhsFunction(self, parameters)

    def mass_forces(self, t, y, p: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """M (N, n, n) and F (N, n) at each state (no leading axis for a single state).

        Parameters
        ----------
        t : float or ndarray of shape (N,)
            The time(s).
        y : ndarray of shape (2n,) or (N, 2n)
            The state(s) (q, q̇).
        p : ndarray
            The parameter vector.

        Returns
        -------
        M : ndarray of shape (N, n, n)
            The mass matrix (no leading axis for a single state).
        F : ndarray of shape (N, n)
            The right side.
        """
        T, Y, single = self._batch(t, y, 2 * self.n)
        n = self.n
        if self._lib is not None:
            M = np.empty((len(Y), n, n))
            F = np.empty((len(Y), n))
            self._lib.lg_eval_mass_forces(len(Y), _ptr(T), _ptr(Y), _ptr(p), _ptr(M), _ptr(F))
        else:
            out = self._se_mf(self._rows(T, Y, p))
            out = np.asarray(out).reshape(len(Y), -1)
            M, F = out[:, : n * n].reshape(-1, n, n), out[:, n * n:]
        return (M[0], F[0]) if single else (M, F)

    def monitor_values(self, t, y, p: np.ndarray) -> np.ndarray:
        """The monitors (first integrals, T, U) at each state.

        Parameters
        ----------
        t : float or ndarray of shape (N,)
            The time(s).
        y : ndarray of shape (2n,) or (N, 2n)
            The state(s) (q, q̇).
        p : ndarray
            The parameter vector.

        Returns
        -------
        ndarray of shape (N, len(monitors))
            Their values.
        """
        return self._eval_many(t, y, p, "lg_eval_monitors", len(self.monitors), "_se_mon")

    def event_values(self, t, y, p: np.ndarray) -> np.ndarray:
        """Event functions at each state: shape (N, len(events)).

        Parameters
        ----------
        t : float or ndarray of shape (N,)
            The time(s).
        y : ndarray of shape (2n,) or (N, 2n)
            The state(s) (q, q̇).
        p : ndarray
            The parameter vector.

        Returns
        -------
        ndarray of shape (N, len(events))
            The event functions' values.
        """
        return self._eval_many(t, y, p, "lg_eval_events", len(self.events), "_se_ev")

    def _eval_many(self, t, y, p, c_name: str, width: int, se_name: str) -> np.ndarray:
        T, Y, single = self._batch(t, y, 2 * self.n)
        out = np.zeros((len(Y), max(width, 1)))
        if width:
            if self._lib is not None:
                getattr(self._lib, c_name)(len(Y), _ptr(T), _ptr(Y), _ptr(p), _ptr(out))
            else:
                out = np.asarray(getattr(self, se_name)(self._rows(T, Y, p))).reshape(len(Y), width)
        out = out[:, :width]
        return out[0] if single else out

    # -- SymEngine fallback -----------------------------------------------------------------
    def _lambdify(self) -> None:
        eom = self.eom
        args = [eom.t, *eom.q, *eom.qd, *(se.Symbol(name) for name in self.parameters)]
        backend = "llvm" if "llvm" in getattr(se, "__all__", ()) or hasattr(se, "LLVMDouble") else None
        kw = {"backend": backend} if backend else {}

        def make(exprs):
            return se.Lambdify(args, exprs or [se.Integer(0)], cse=True, **kw)

        n = self.n
        self._se_mf = make([eom.M[i][j] for i in range(n) for j in range(n)] + list(eom.F))
        self._se_mon = make([e for _, e in monitor_expressions(eom, self.first_integrals)])
        self._se_ev = make([e for _, e in self._events])


def _rhs_failure(status: int, T: np.ndarray, Y: np.ndarray) -> SimulationError:
    """The error of a failed q̈: a state that is not finite is a blow-up, not a singular M."""
    bad = ~np.all(np.isfinite(Y), axis=1)
    if bad.any():
        k = int(np.argmax(bad))
        return SimulationError(
            f"The solution overflowed (blow-up) at t = {T[k]:.9g}: the state holds non-finite numbers, so q'' "
            "cannot be computed there.",
            fix="the motion grows without bound: check the parameters and the initial state, shorten the time "
                "span, or tighten the tolerances", t=float(T[k]), state=Y[k].copy())
    if status == 2:
        return SimulationError("q'' is not finite at one of the given states (overflow in M q'' = F).",
                               fix="check the state and the parameters")
    return SimulationError(
        "The mass matrix M is singular at one of the given states, so q'' is not defined there.",
        fix="check the state, or see `CompiledSystem.mass_forces`")


def compile_system(eom: EquationsOfMotion, *, events: Sequence[tuple[str, se.Basic]] = (),
                   backend: str = "auto", inputs=None) -> CompiledSystem:
    """The `CompiledSystem` of ``eom`` (compiled C when a compiler exists, else SymEngine).

    Parameters
    ----------
    eom : EquationsOfMotion
        The equations.
    events : sequence of (str, SymEngine expression), optional
        (name, g) pairs; an event occurs where g(t, q, q̇) changes sign.
    backend : {"auto", "c", "symengine"}, optional
        Compiled C (when a compiler exists, "auto") or SymEngine's evaluation.
    inputs : dict or Feedback, optional
        The inputs' law compiled in (a dict by input name or a `Feedback`, as `simulate` takes it);
        None: the model's ``[controls]``, if any.

    Returns
    -------
    CompiledSystem
        The numeric system.
    """
    return CompiledSystem(eom, events=events, backend=backend, inputs=inputs)
