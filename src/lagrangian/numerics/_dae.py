"""Models with complementary constraints: their numeric evaluators (parts, q̈ and λ, monitors, reactions).

The state is y = (q, q̇) as for any model; the multipliers λ are not integrated but
solved at each evaluation from the augmented equations (see `codegen._codegen_dae`): the
constraints are differentiated (index reduction) so that they hold at acceleration
level, A q̈ + c = 0, and M q̈ = F + Aᵀλ.  `ConstrainedSystem` evaluates these in C (or
SymEngine); `constrained_source` says whether a source keeps constraints complementary.
The run itself, with the drift control, is the DAE route (`_dae_run`).
"""

from __future__ import annotations

import ctypes
from collections.abc import Mapping, Sequence
from pathlib import Path

import numpy as np
import symengine as se

from ..analysis import first_integrals
from ..codegen import generate_dae_c, monitor_expressions
from ..dynamics import EquationsOfMotion, derive
from ..errors import SimulationError
from ..model import load_model
from ..model.spec import Model
from ._compile import compile_library, compiler
from ._system import CompiledSystem, unused_parameters

__all__ = ["ConstrainedSystem", "constrained_source", "reaction_columns"]


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

    Parameters
    ----------
    eom : EquationsOfMotion
        The equations (with ``eom.constraints``).
    backend : {"auto", "c", "symengine"}, optional
        Compiled C (when a compiler exists, "auto") or SymEngine's evaluation.
    inputs : mapping of str to str, optional
        Each declared input's regime (``"off"``, ``"constant"``, ``"varying"``) the integrals are
        found for; off where not given.

    Attributes
    ----------
    eom : EquationsOfMotion
        The equations.
    n, m : int
        The numbers of coordinates and of complementary rows.
    rows : tuple of str
        The row names.
    holonomic : ndarray of bool
        The mask of the holonomic rows.
    monitors, reactions : tuple of str
        The names of the monitor and reaction columns.
    integrals : tuple of FirstIntegral
        The first integrals among the monitors.
    backend : str
        ``"c"`` or ``"symengine"``.
    regime : dict of str to str
        Each declared input's regime.
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
        """The ``p`` array: the model's values overridden by ``values`` (errors as `CompiledSystem`'s).

        Parameters
        ----------
        values : mapping of str to float, optional
            Parameter values by name.

        Returns
        -------
        ndarray
            The parameter vector.
        """
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
    def _batch(self, t, y) -> tuple[np.ndarray, np.ndarray, bool]:
        Y = np.ascontiguousarray(y, dtype=float)
        single = Y.ndim == 1
        Y = Y.reshape(-1, 2 * self.n)
        T = np.ascontiguousarray(np.broadcast_to(np.asarray(t, dtype=float), (len(Y),)))
        return T, Y, single

    def parts(self, t, y, p: np.ndarray) -> tuple[np.ndarray, ...]:
        """The parts (M, F, A, c, g, f) at each state.

        M q̈ = F + Aᵀλ, A q̈ + c = 0, g = A q̇ + b, f = the holonomic residuals.

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
        tuple of ndarray
            M, F, A, c, g, f.
        """
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

    def rhs(self, t, y, p: np.ndarray, stab: Sequence[float] = (0.0, 0.0)) -> tuple[np.ndarray, np.ndarray]:
        """The derivative ẏ and the multipliers λ at each state, with Baumgarte rates ``stab`` = (α, β).

        Parameters
        ----------
        t : float or ndarray of shape (N,)
            The time(s).
        y : ndarray of shape (2n,) or (N, 2n)
            The state(s) (q, q̇).
        p : ndarray
            The parameter vector.
        stab : sequence of two float, optional
            Baumgarte's rates (α, β).

        Returns
        -------
        ydot : ndarray
            The derivative ẏ = (q̇, q̈).
        lam : ndarray
            The multipliers λ.

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

    def monitor_values(self, t, y, p: np.ndarray) -> np.ndarray:
        """First integrals, T, U at each state: shape (N, len(monitors)).

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
            The first integrals, T and U.
        """
        T, Y, _ = self._batch(t, y)
        k = len(self.monitors)
        if self._lib is not None:
            out = np.zeros((len(Y), max(k, 1)))
            self._lib.lgd_eval_monitors(len(Y), _ptr(T), _ptr(Y), _ptr(p), _ptr(out))
            return out[:, :k]
        return np.asarray(self._se_mon(np.column_stack([T, Y, np.broadcast_to(p, (len(Y), len(p)))]))
                          ).reshape(len(Y), k)

    def reaction_values(self, t, y, lam, p: np.ndarray) -> np.ndarray:
        """Reaction components (`reaction_columns`) at each state and multipliers: shape (N, len(reactions)).

        Parameters
        ----------
        t : float or ndarray of shape (N,)
            The time(s).
        y : ndarray of shape (2n,) or (N, 2n)
            The state(s) (q, q̇).
        lam : ndarray
            The multipliers at those states.
        p : ndarray
            The parameter vector.

        Returns
        -------
        ndarray of shape (N, len(reactions))
            The reaction components.
        """
        T, Y, _ = self._batch(t, y)
        LAM = np.ascontiguousarray(np.asarray(lam, dtype=float).reshape(len(Y), self.m))
        k = len(self.reactions)
        if self._lib is not None:
            out = np.zeros((len(Y), max(k, 1)))
            self._lib.lgd_eval_reactions(len(Y), _ptr(T), _ptr(Y), _ptr(LAM), _ptr(p), _ptr(out))
            return out[:, :k]
        args = np.column_stack([T, Y, LAM, np.broadcast_to(p, (len(Y), len(p)))])
        return np.asarray(self._se_reac(args)).reshape(len(Y), k)

    def _lambdify(self, monitor_items, reaction_items) -> None:
        eom = self.eom
        params = [se.Symbol(name) for name in self.parameters]
        args = [eom.t, *eom.q, *eom.qd, *params]
        rows = eom.constraints
        n = self.n
        parts = [eom.M[i][j] for i in range(n) for j in range(n)] + list(eom.F)
        parts += [x for r in rows for x in r.coefficients] + [r.bias for r in rows] + [r.velocity for r in rows]
        parts += [r.expression if r.kind == "holonomic" else se.Integer(0) for r in rows]

        def make(arguments, exprs):
            return se.Lambdify(arguments, list(exprs) or [se.Integer(0)], cse=True)

        self._se_parts = make(args, parts)
        self._se_mon = make(args, [e for _, e in monitor_items])
        self._se_reac = make([eom.t, *eom.q, *eom.qd, *eom.multipliers, *params], [e for _, e in reaction_items])


# -- which sources keep constraints complementary ----------------------------------------------------------
def constrained_source(source):
    """(source, eom): the equations when ``source`` keeps constraints complementary, else (source, None).

    A file path is read once and handed back as its `Model`, so `simulate` does not read it again.
    """
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
