"""A model with free bodies as compiled C on its quaternion state: `FreeBodySystem`.

The state is that of `dynamics._floating` (r, e, q_joints; v, ω, q̇_joints; one drift record per
free body, `codegen._free_codegen`).  This class compiles it once and gives its right-hand side, its
mass matrix in the velocities (v, ω, q̇), its monitors and events for one state or a batch,
and the two conversions with the model's own coordinates: a state from the model's initial
values (Euler angles and their rates: e from R(θ), ω = J(θ) θ̇, regular even where J is not),
and the model's q, q̇, q̈ along a run (the angles from e, continuous; their rates and
accelerations from ω and ω̇ where J is regular, NaN where it is not: `_euler`).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from pathlib import Path
from types import SimpleNamespace

import numpy as np
import symengine as se

from ..dynamics import FloatingForm, floating_form
from ..errors import SimulationError
from ..model import Model, inertia_problem
from ._compile import compile_library
from ._euler import (
    SINGULAR,
    euler_from_matrix,
    euler_matrix,
    matrix_from_quaternion,
    quaternion_from_matrix,
    rate_matrix,
    rate_matrix_derivative,
)
from ._fastcall import rhs_caller
from ._inputs import InputLaw
from ._system import _SIGNATURES as _SYSTEM_SIGNATURES
from ._system import unused_parameters

__all__ = ["FreeBodySystem", "compile_free_system", "has_free_body"]

#: The C functions of `_system`'s compiled runtime but the Gauss-Legendre method (free bodies have no Hamilton form).
_SIGNATURES = {name: signature for name, signature in _SYSTEM_SIGNATURES.items() if name != "lg_gauss"}


def _ptr(a: np.ndarray) -> int:
    return a.ctypes.data


def has_free_body(model: Model | None) -> bool:
    """Whether ``model`` declares a free body (then `simulate` integrates it on quaternions)."""
    return model is not None and any(b.free for b in model.bodies)


class FreeBodySystem:
    """The compiled quaternion-state equations of a model with free bodies (module docstring).

    Parameters
    ----------
    model : Model
        A model with free bodies.
    events : sequence of (str, SymEngine expression), optional
        (name, g) pairs in the state's symbols.

    Attributes
    ----------
    model : Model
        The model.
    form : FloatingForm
        Its quaternion-state equations.
    nq, nv : int
        The lengths of the position and velocity parts of the state; ``width`` = nq + nv + (free
        bodies).
    coordinates, parameters, monitors, integrals, events : tuple of str
        Names, in array order.
    """

    def __init__(self, model: Model, *, events: Sequence[tuple[str, se.Basic]] = ()) -> None:
        from ..codegen import generate_free_c

        self.model = model
        self.form: FloatingForm = floating_form(model)
        self.coordinates = tuple(c.name for c in model.coordinates)
        self.parameters = tuple(p.name for p in model.parameters)
        self.events = tuple(name for name, _ in events)
        self._event_expressions = tuple(self._state_expression(name, e) for name, e in events)
        generated = generate_free_c(self.form, list(zip(self.events, self._event_expressions, strict=True)))
        self.source = generated.source
        self.nq, self.nv = generated.nq, generated.nv
        self.width = self.nq + self.nv + len(self.form.trees)
        self.monitors = generated.monitors
        self.integrals = self.form.integrals
        self._constants = generated.constants
        self._lib = compile_library(generated.source, generated.key)
        for name, (restype, argtypes) in _SIGNATURES.items():
            fn = getattr(self._lib, name)
            fn.restype, fn.argtypes = restype, argtypes
        dims = np.zeros(3, dtype=np.intc)
        self._lib.lg_dimensions(_ptr(dims))
        assert tuple(dims) == (self.nv, len(self.monitors), len(self.events)), "stale compiled library"
        caller = rhs_caller(self._lib.lg_eval_rhs, self.width, len(self.parameters) + self._constants, self._lib)
        if caller is not None:
            self.rhs_c = caller  # type: ignore[method-assign]  # the vectorcall wrapper stands in for the method
        self._layout()
        self._unused: frozenset[str] | None = None
        self._t1 = np.zeros(1)
        #: No input law is compiled in: the route runs constant inputs only.
        #:
        #: They are given as parameters (`_input_run.constant_inputs_only`), so the solvers see no
        #: breakpoints and no law block.
        self.law = InputLaw()

    # -- where each model coordinate is in the state ------------------------------------------------
    def _layout(self) -> None:
        index = {name: k for k, name in enumerate(self.coordinates)}
        self.blocks = []  # per tree: (joint, position offset, velocity offset, translation idx, angle idx, joints idx)
        oq, ov = 0, self.nq
        for tree in self.form.trees:
            fj = tree.joint
            self.blocks.append((fj, oq, ov, [index[c] for c in fj.translation], [index[c] for c in fj.angles],
                                list(tree.joints)))
            oq += 7 + len(tree.joints)
            ov += 6 + len(tree.joints)

    def _state_expression(self, name: str, expr: se.Basic) -> se.Basic:
        """An event's g(t, q, q̇) in the state's symbols: translations and joints only, not the angles."""
        mapping: dict[se.Basic, se.Basic] = {}
        angles = set()
        for tree, base in zip(self.form.trees, self.form.bases, strict=True):
            for c, r, v in zip(tree.joint.translation, base.r, base.v, strict=True):
                mapping[se.Symbol(c)], mapping[se.Symbol(c + "_dot")] = r, v
            angles |= {se.Symbol(a) for a in tree.joint.angles} | {se.Symbol(a + "_dot") for a in tree.joint.angles}
        used = sorted(str(s) for s in expr.free_symbols & angles)
        if used:
            raise SimulationError(f"The event `{name}` uses `{used[0]}`, an Euler angle (or its rate) of a free body: "
                                  "a free body is integrated on a unit quaternion, and its angles are computed "
                                  "afterwards.", fix="write the event with the positions of the free bodies, the "
                                                     "joint coordinates, their rates, parameters and t")
        return expr.xreplace(mapping) if mapping else expr

    # -- parameters ---------------------------------------------------------------------------------
    @property
    def unused_parameters(self) -> frozenset[str]:
        if self._unused is None:
            exprs = [e for _, e in self.form.intermediates] + list(self.form.derivative)
            exprs += [e for _, e in self.form.monitors] + list(self._event_expressions)
            self._unused = unused_parameters(self.parameters, exprs)
        return self._unused

    def integrals_for(self, p: np.ndarray) -> tuple[str, ...]:
        """The first integrals of a run with parameter values ``p``.

        Without E when an input whose load is not conservative has a value other than 0
        (`FloatingForm.energy_inputs`).

        Parameters
        ----------
        p : ndarray
            The parameter vector.

        Returns
        -------
        tuple of str
            Their names.
        """
        values = dict(zip(self.parameters, p[:len(self.parameters)], strict=True))
        if any(values.get(u, 0.0) != 0.0 for u in self.form.energy_inputs):
            return tuple(name for name in self.integrals if name != "E")
        return tuple(self.integrals)

    def parameter_vector(self, values: Mapping[str, float] | None = None) -> np.ndarray:
        """The ``p`` array (as `CompiledSystem.parameter_vector`), the free bodies' inertias checked.

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
            A parameter without a value, an unknown name, or a free body whose mass or a
            principal moment of inertia at G is zero with these values.
        """
        values = dict(values or {})
        unknown = sorted(set(values) - set(self.parameters))
        if unknown:
            raise SimulationError(f"`{unknown[0]}` is not a parameter of `{self.model.name}`.",
                                  fix="the parameters are " + (", ".join(self.parameters) or "(none)"))
        out = np.empty(len(self.parameters))
        for k, parameter in enumerate(self.model.parameters):
            value = values.get(parameter.name, parameter.value)
            if value is None and parameter.name in self.unused_parameters:
                out[k] = np.nan
                continue
            if value is None:
                raise SimulationError(f"The parameter `{parameter.name}` has no value, so the motion cannot be "
                                      "computed.", fix=f"give it one in the model file or with --set "
                                                       f"{parameter.name}=...")
            out[k] = float(value)
            if not np.isfinite(out[k]):
                raise SimulationError(f"The parameter `{parameter.name}` = {value} is not a finite number.",
                                      fix=f"give `{parameter.name}` a finite value")
        self._check_inertias(out)
        extended = np.empty(len(out) + self._constants)
        extended[: len(out)] = out
        if self._constants:
            self._lib.lg_constants(_ptr(extended), _ptr(extended[len(out):]))
        return extended

    def _check_inertias(self, p: np.ndarray) -> None:
        known = {se.Symbol(name): se.RealDouble(float(v)) for name, v in zip(self.parameters, p[:len(self.parameters)], strict=True) if not np.isnan(v)}
        for tree in self.form.trees:
            leaf = next(node for node in tree.nodes if node.name == tree.joint.body)
            try:
                mass = float(leaf.mass.xreplace(known))
                inertia = np.array([[float(x.xreplace(known)) for x in row] for row in leaf.inertia])  # type: ignore[union-attr]
            except (RuntimeError, TypeError):  # pragma: no cover - every value is known by now
                continue
            problem = inertia_problem(mass, inertia)
            if problem:
                raise SimulationError(f"Free body `{tree.joint.body}` cannot move freely: {problem}. A free body "
                                      "translates and turns about every axis, so its mass and each principal moment "
                                      "of inertia at G must be positive.",
                                      fix="give it a positive mass and inertia (--set the parameters they hold)")

    # -- states ---------------------------------------------------------------------------------------
    def initial_state(self, initial: Mapping[str, float] | None = None) -> np.ndarray:
        """The state from the model's initial values and rates (and ``initial``'s overrides).

        Parameters
        ----------
        initial : mapping of str to float, optional
            Overrides of the initial values and rates, by name.

        Returns
        -------
        ndarray of shape (width,)
            The state.
        """
        from ._setup import initial_state  # late: only `state_of` of a model's initial values needs it

        y = initial_state(SimpleNamespace(model=self.model), initial)  # (q, q̇) in the model's coordinates
        return self.state_of(y[None, :])[0]

    def state_of(self, Y: np.ndarray) -> np.ndarray:
        """Convert rows (q, q̇) in the model's coordinates (N, 2n) to states (N, width).

        Parameters
        ----------
        Y : ndarray of shape (N, 2n)
            The rows.

        Returns
        -------
        ndarray of shape (N, width)
            The states.
        """
        Y = np.atleast_2d(np.asarray(Y, dtype=float))
        n = len(self.coordinates)
        q, qd = Y[:, :n], Y[:, n:]
        out = np.zeros((len(Y), self.width))
        for fj, oq, ov, trans, ang, joints in self.blocks:
            angles = q[:, ang]
            out[:, oq:oq + 3] = q[:, trans]
            out[:, oq + 3:oq + 7] = quaternion_from_matrix(euler_matrix(fj.sequence, angles))
            out[:, oq + 7:oq + 7 + len(joints)] = q[:, joints]
            out[:, ov:ov + 3] = qd[:, trans]
            out[:, ov + 3:ov + 6] = np.einsum("nij,nj->ni", rate_matrix(fj.sequence, angles), qd[:, ang])
            out[:, ov + 6:ov + 6 + len(joints)] = qd[:, joints]
        return out

    def coordinates_of(self, Y: np.ndarray, dY: np.ndarray, start: np.ndarray, t: np.ndarray | None = None
                       ) -> tuple[np.ndarray, ...]:
        """The coordinates (q, q̇, q̈) in the model's coordinates along states Y with derivatives dY, at times t.

        Each body's angles come from its quaternion, on the branch ``start`` gives, each turn followed
        from row to row (`_euler.euler_from_matrix`); their rates and accelerations are NaN where
        ``|det J|`` < `SINGULAR` (within about 1e-9 rad of their singularity).

        Parameters
        ----------
        Y : ndarray of shape (N, width)
            The states.
        dY : ndarray of shape (N, width)
            Their derivatives.
        start : ndarray of shape (2n,)
            Gives the branch and turn of the angles at the first row.
        t : ndarray of shape (N,), optional
            The times.

        Returns
        -------
        tuple of ndarray
            The coordinates q, rates q̇ and accelerations q̈, each of shape (N, n).
        """
        n, N = len(self.coordinates), len(Y)
        q, qd, qdd = (np.empty((N, n)) for _ in range(3))
        for fj, oq, ov, trans, ang, joints in self.blocks:
            q[:, trans], qd[:, trans], qdd[:, trans] = Y[:, oq:oq + 3], Y[:, ov:ov + 3], dY[:, ov:ov + 3]
            k = len(joints)
            q[:, joints], qd[:, joints] = Y[:, oq + 7:oq + 7 + k], Y[:, ov + 6:ov + 6 + k]
            qdd[:, joints] = dY[:, ov + 6:ov + 6 + k]
            angles = euler_from_matrix(fj.sequence, matrix_from_quaternion(Y[:, oq + 3:oq + 7]), start[ang],
                                       Y[:, ov + 3:ov + 6], t)
            J = rate_matrix(fj.sequence, angles)
            regular = np.abs(np.linalg.det(J)) >= SINGULAR
            rates = np.full((N, 3), np.nan)
            accel = np.full((N, 3), np.nan)
            if regular.any():
                omega, omega_dot = Y[regular, ov + 3:ov + 6], dY[regular, ov + 3:ov + 6]
                rates[regular] = np.linalg.solve(J[regular], omega[..., None])[..., 0]
                bias = rate_matrix_derivative(fj.sequence, angles[regular], rates[regular])
                accel[regular] = np.linalg.solve(J[regular], (omega_dot - bias)[..., None])[..., 0]
            q[:, ang], qd[:, ang], qdd[:, ang] = angles, rates, accel
        return q, qd, qdd

    def quaternion_norms(self, Y: np.ndarray) -> dict[str, np.ndarray]:
        """The norm ``|e|`` of each free body's quaternion along states Y.

        Parameters
        ----------
        Y : ndarray of shape (N, width)
            The states.

        Returns
        -------
        dict of str to ndarray
            By body.
        """
        return {fj.body: np.linalg.norm(Y[:, oq + 3:oq + 7], axis=1) for fj, oq, *_ in self.blocks}

    def drift_records(self, Y: np.ndarray) -> dict[str, float]:
        """The largest ``|1 − |e||`` before a projection, per free body, recorded in the state up to Y's last row.

        Parameters
        ----------
        Y : ndarray of shape (N, width)
            The states.

        Returns
        -------
        dict of str to float
            By body.
        """
        return {fj.body: float(Y[-1, self.nq + self.nv + t]) if len(Y) else 0.0
                for t, (fj, *_) in enumerate(self.blocks)}

    def extra_columns(self, Y: np.ndarray) -> dict[str, np.ndarray]:
        """Each free body's quaternion (w, x, y, z) and ω (in its basis) along states Y.

        Parameters
        ----------
        Y : ndarray of shape (N, width)
            The states.

        Returns
        -------
        dict of str to ndarray
            The columns, by name.
        """
        out: dict[str, np.ndarray] = {}
        for fj, oq, ov, *_ in self.blocks:
            for k, part in enumerate("wxyz"):
                out[f"{fj.body}_e{part}"] = Y[:, oq + 3 + k].copy()
            for k, axis in enumerate("xyz"):  # along the body frame's x, y, z
                out[f"{fj.body}_omega_{axis}"] = Y[:, ov + 3 + k].copy()
        return out

    # -- evaluators ---------------------------------------------------------------------------------
    def _batch(self, t, y) -> tuple[np.ndarray, np.ndarray, bool]:
        Y = np.ascontiguousarray(y, dtype=float)
        single = Y.ndim == 1
        Y = Y.reshape(-1, self.width)
        T = np.ascontiguousarray(np.broadcast_to(np.asarray(t, dtype=float), (len(Y),)))
        return T, Y, single

    def rhs(self, t, y, p: np.ndarray) -> np.ndarray:
        """The derivative ẏ at each state (the free bodies' v̇ in R0's basis, ω̇ in theirs, the joints' q̈).

        Parameters
        ----------
        t : float or ndarray of shape (N,)
            The time(s).
        y : ndarray of shape (width,) or (N, width)
            The state(s).
        p : ndarray
            The parameter vector.

        Returns
        -------
        ndarray
            The derivative ẏ, of the shape of ``y``.
        """
        T, Y, single = self._batch(t, y)
        out = np.empty_like(Y)
        status = self._lib.lg_eval_rhs(len(Y), _ptr(T), _ptr(Y), _ptr(p), _ptr(out))
        if status:
            what = ("the state is not finite (a blow-up)" if status == 2 or not np.isfinite(Y).all() else
                    "the articulated inertia of a free body lost its rank (a zero mass or moment of inertia)")
            raise SimulationError(f"q'' is not defined at one of the given states: {what}.",
                                  fix="check the masses, the inertias and the state")
        return out[0] if single else out

    def rhs_c(self, t: float, y: np.ndarray, p: np.ndarray, out: np.ndarray) -> int:
        """One state, no allocation (replaced by the `_fastcall` wrapper where it builds).

        Parameters
        ----------
        t : float
            The time.
        y : ndarray of shape (width,)
            The state.
        p : ndarray
            The parameter vector.
        out : ndarray of shape (width,)
            Receives ẏ.

        Returns
        -------
        int
            The C status (0 = fine).
        """
        self._t1[0] = t
        return self._lib.lg_eval_rhs(1, _ptr(self._t1), _ptr(y), _ptr(p), _ptr(out))

    def mass_forces(self, t, y, p: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """The mass matrix M in the velocities (v, ω, q̇) and F = M ẏ_v, the generalized forces that give the motion.

        Parameters
        ----------
        t : float or ndarray of shape (N,)
            The time(s).
        y : ndarray of shape (width,) or (N, width)
            The state(s).
        p : ndarray
            The parameter vector.

        Returns
        -------
        M : ndarray of shape (N, nv, nv)
            The mass matrix.
        F : ndarray of shape (N, nv)
            The forces.
        """
        T, Y, single = self._batch(t, y)
        M = np.empty((len(Y), self.nv, self.nv))
        F = np.empty((len(Y), self.nv))
        self._lib.lg_eval_mass_forces(len(Y), _ptr(T), _ptr(Y), _ptr(p), _ptr(M), _ptr(F))
        return (M[0], F[0]) if single else (M, F)

    def monitor_values(self, t, y, p: np.ndarray) -> np.ndarray:
        return self._evaluate(t, y, p, "lg_eval_monitors", len(self.monitors))

    def event_values(self, t, y, p: np.ndarray) -> np.ndarray:
        return self._evaluate(t, y, p, "lg_eval_events", len(self.events))

    def _evaluate(self, t, y, p, name: str, width: int) -> np.ndarray:
        T, Y, single = self._batch(t, y)
        out = np.zeros((len(Y), max(width, 1)))
        if width:
            getattr(self._lib, name)(len(Y), _ptr(T), _ptr(Y), _ptr(p), _ptr(out))
        out = out[:, :width]
        return out[0] if single else out


def compile_free_system(source, *, events: Sequence[tuple[str, se.Basic]] = ()) -> FreeBodySystem:
    """The `FreeBodySystem` of a model with free bodies.

    ``simulate`` takes it as a source (and builds one by itself from a model with free bodies).
    Its `mass_forces` gives M and the forces in the velocities (v, ω, q̇), MuJoCo's for a free joint.

    Parameters
    ----------
    source : str or Path or Model or EquationsOfMotion
        A path, a `Model` or its `EquationsOfMotion`.
    events : sequence of (str, SymEngine expression), optional
        (name, g) pairs in the state's symbols.

    Returns
    -------
    FreeBodySystem
        The compiled system.

    Raises
    ------
    SimulationError
        When the model has no free body (`compile_system` is its route).
    DerivationError
        When the quaternion route does not apply to it (`dynamics._floating_tree` says why).
    """
    from ..model import load_model

    if isinstance(source, (str, Path)):
        source = load_model(source)
    model = source if isinstance(source, Model) else getattr(source, "model", None)
    if not has_free_body(model):
        raise SimulationError(f"`{getattr(model, 'name', source)}` has no free body: nothing to integrate on "
                              "quaternions.", fix="use compile_system(derive(model)), or declare a body free = true")
    return FreeBodySystem(model, events=events)  # type: ignore[arg-type]
