"""Small motions: the equations of motion linearized about an equilibrium or a steady motion.

About a point (q0, q̇0) where the motion is steady — q̈0 = 0, every coordinate that moves
(q̇0_j ≠ 0) absent from the equations (an *ignorable* coordinate: the top's ψ and φ, the
bicycle's x, y and wheel angles) — a perturbation q = q0 + δq, q̇ = q̇0 + δq̇ obeys, to first
order, the linearization of

    M(q) q̈ = F(q, q̇, u) + Aᵀ(q) λ,        A(q) q̇ + b(q) = 0        (`dynamics._constraints`)

namely, with q̈0 = 0 and λ0 the multipliers of the steady motion (F0 + A0ᵀ λ0 = 0),

    M0 δq̈ + D_f δq̇ + K_f δq = A0ᵀ δλ + B_f δu,     D_f = −∂F/∂q̇,  K_f = −∂F/∂q − Σ_k λ0_k ∂A_k/∂q,
    A0 δq̇ + W δq = 0,                               W = ∂(A q̇ + b)/∂q at the point.

**Reduction to independent coordinates and speeds** (the seed's "paramètres principaux" when
some constraints are kept complementary).  The holonomic rows f(q) = 0 fix the dependent
coordinates: δq = P δq_i with P = [I; −Φ_d⁻¹ Φ_i] (implicit-function theorem).  The velocity
rows fix the dependent speeds: δq̇ = C δu + J δq, with C = [I; −A_d⁻¹ A_i] and J the rows
−A_d⁻¹ W of the dependent speeds (zero on the independent ones).  Projecting the dynamics on
the admissible velocities (Cᵀ A0ᵀ = 0 removes δλ: the principle of virtual power with
q* = C u*, as in Kane's and Maggi's equations),

    M_r δu̇ + C_r δu + K_r δq_i = B_r δu_in,     M_r = Cᵀ M0 C,  C_r = Cᵀ (M0 J + D_f) C,
                                                 K_r = Cᵀ [K_f + (M0 J + D_f) J] P,  B_r = Cᵀ B_f,
    δq̇_i = (C δu + J P δq_i) restricted to the independent coordinates,

so the state x = (δq_i, δu) obeys ẋ = A x + B u.  Without complementary constraints P = C = I
and J = 0: the usual M0 δq̈ + (D + G) δq̇ + (K + N) δq = B u, with D, K the symmetric and G, N
the skew-symmetric parts of D_f and K_f (damping, gyroscopic, stiffness, circulatory).

`linearize` runs the work as named steps, each a function: `_setting` reads the point and gives the
parameters their values (steps 1-2), `_dependent_coordinates` (3), `_dependent_speeds` (4), `_rates`
(5), `_check_steady` (6), `_forces_at` and `_residual` check the point and find λ0 (7); the
reduction (Jacobians, P, the reduced matrices, A and B) is `_linear_reduction`'s.

References: Meirovitch, *Methods of Analytical Dynamics* (1970), ch. 6; Meijaard et al.,
Proc. R. Soc. A 463 (2007) 1955–1982, §4 (the bicycle, reduced the same way).
"""

from __future__ import annotations

import math
import random
from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import numpy as np
import symengine as se

from .._identity import are_zero
from ..dynamics import EquationsOfMotion
from ..model import ExpressionError, parse_expression
from ._linear_algebra import RANK_RTOL
from ._linear_algebra import choose as _choose
from ._linear_algebra import jacobian as _jacobian
from ._linear_algebra import solve as _solve
from ._linear_algebra import sub as _sub
from ._linear_algebra import tidy as _tidy
from ._linear_model import LinearizationError, LinearModel, SecondOrderForm, _is_structural_zero
from ._linear_model import to_numpy as _to_numpy
from ._linear_reduction import coordinate_map as _coordinate_map
from ._linear_reduction import ignorable as _ignorable
from ._linear_reduction import jacobians as _jacobians
from ._linear_reduction import multipliers as _multipliers
from ._linear_reduction import reduced_matrices as _reduced_matrices
from ._linear_reduction import second_order as _second_order
from ._linear_reduction import state_matrices as _state_matrices
from ._linear_reduction import velocity_maps as _velocity_maps

__all__ = ["POINT_RTOL", "LinearModel", "LinearizationError", "SecondOrderForm", "holding_inputs", "linearize"]

#: A point is an equilibrium (steady motion) when its residual force is below this fraction
#: of the forces' scale: `--at theta=3.14159` is the inverted pendulum, within 3e-6.
POINT_RTOL = 1e-5

_ZERO = se.Integer(0)


# -- the point -----------------------------------------------------------------------------

def _value(name: str, value: object, names: Mapping[str, se.Basic]) -> se.Basic:
    if isinstance(value, se.Basic):
        return value
    if isinstance(value, bool):
        raise LinearizationError(f"the value of `{name}` must be a number, not {value!r}.")
    if isinstance(value, int):
        return se.Integer(value)
    if isinstance(value, float):
        if not math.isfinite(value):
            raise LinearizationError(f"the value of `{name}` is not finite.", fix=f"give `{name}` a finite value")
        return se.RealDouble(value)
    if isinstance(value, str):  # read by the model's safe grammar: numbers, pi, parameters
        try:
            out = parse_expression(value, names)
        except ExpressionError as exc:
            raise LinearizationError(f"the value `{value}` of `{name}` cannot be read: {exc}",
                                     fix="write a number, `pi`, or an expression in the parameters") from None
        if not isinstance(out, se.Basic):
            raise LinearizationError(f"the value of `{name}` must be a scalar.")
        return out
    raise LinearizationError(f"the value of `{name}` must be a number, not {type(value).__name__}.")


def _number(v: float) -> se.Basic:
    """A parameter value as a SymEngine number: exact when it is an integer (1.0 → 1)."""
    v = float(v)
    return se.Integer(int(v)) if v.is_integer() and abs(v) < 2**53 else se.RealDouble(v)


def _generic(symbols: Sequence[se.Basic], known: Mapping[se.Basic, float]) -> dict[se.Basic, float]:
    """Numbers for the symbols: their values when known, else fixed random ones in [0.3, 1.7]."""
    rng = random.Random(20261124)
    return {s: known.get(s, rng.uniform(0.3, 1.7)) for s in sorted(symbols, key=str)}


def linearize(eom: EquationsOfMotion, at: Mapping[str, object] | None = None, *,
              parameters: Mapping[str, float] | None = None, symbolic: Sequence[str] = (),
              inputs: Sequence[str] | None = None, independent_speeds: Sequence[str] | None = None,
              dependent_coordinates: Sequence[str] | None = None) -> LinearModel:
    """Linearize the equations of motion about an equilibrium or a steady motion.

    Parameters
    ----------
    eom : EquationsOfMotion
        From `lagrangian.derive`.
    at : mapping of str to object, optional
        The point: every coordinate ``q`` a value, rates ``q_dot`` optional (0 by default; dependent
        speeds are solved from the constraints), inputs optional (0 by default: a robot held still by
        its joint torques is ``{"q1": 0.3, "tau_q1": 4.2}``; see `holding_inputs`).  Values are
        numbers, SymEngine expressions in the parameters, or text in the model grammar (``"pi"``,
        ``"-v/rR"``).  None: the model's ``[operating_point]`` table.
    parameters : mapping of str to float, optional
        Parameter values overriding the model's.
    symbolic : sequence of str, optional
        Parameters kept as symbols although they have a value (A(v) for a sweep).
    inputs : sequence of str, optional
        The inputs u, columns of B: parameters or declared ``[inputs]`` (default: the model's
        declared inputs).  Their values at the point u0 come from ``at`` (0 when not given), and A, B
        are the Jacobians at (q0, q̇0, u0).
    independent_speeds : sequence of str, optional
        The independent speeds of the reduction, when the model keeps constraints complementary
        (default: the model's, else chosen by rank).
    dependent_coordinates : sequence of str, optional
        The dependent coordinates of the reduction, likewise.

    Returns
    -------
    LinearModel
        A, B, the second-order form and the point.

    Raises
    ------
    LinearizationError
        An unknown name, a coordinate without a value, a model that depends on t, a point that
        is not an equilibrium or steady motion (with the residual and the nearest equilibrium),
        or a singular mass matrix or constraint Jacobian at the point.

    Examples
    --------
    >>> import lagrangian
    >>> eom = lagrangian.derive(lagrangian.load_model("examples/simple_pendulum.toml"))  # doctest: +SKIP
    >>> lagrangian.linearize(eom, {"theta": 0}).second_order.K                          # doctest: +SKIP
    [g*l*m]
    """
    pnames = {p.name: p for p in eom.model.parameters}
    declared_inputs = tuple(getattr(eom.model, "inputs", ()) or ())
    inputs = tuple(declared_inputs if inputs is None else inputs)
    for name in list(symbolic) + list(inputs) + list(parameters or {}):
        if name not in pnames:
            raise LinearizationError(f"`{name}` is not a parameter of the model ({', '.join(pnames) or 'none'}).",
                                     fix="check its spelling, or declare it under [parameters] or [inputs]")
    if at is None:
        at, independent_speeds, dependent_coordinates = _operating_point(eom, independent_speeds,
                                                                         dependent_coordinates)
    s = _setting(eom, at, inputs, parameters, symbolic)
    A_at, A_num, dep_c = _dependent_coordinates(s, dependent_coordinates)
    dep_s, choice = _dependent_speeds(s, A_num, dep_c, independent_speeds)
    ind_s = [i for i in range(s.n) if i not in dep_s]
    ind_c = [i for i in range(s.n) if i not in dep_c]
    qd0 = _rates(s, A_at, ind_s, dep_s)
    point_subs = {**s.at_q, **qd0}
    _check_steady(s, qd0)
    F_p, M0, zero_u = _forces_at(s, point_subs)
    at_all = {**point_subs, **zero_u}
    Csym, S = _velocity_maps(A_at, ind_s, dep_s, s.n)
    residual, dF_dq, lam0 = _residual(s, F_p, zero_u, at_all, Csym, A_at, point_subs, ind_c, dep_c, ind_s)

    # The reduction to independent coordinates and speeds (`_linear_reduction`, steps 2 to 6).
    Kf, Df, Bf, W = _jacobians(eom, F_p, dF_dq, s.u_syms, lam0, s.psubs, at_all)
    P = _coordinate_map(A_at, s.holo, dep_c, ind_c, s.n)
    reduced = _reduced_matrices(M0, Kf, Df, Bf, W, Csym, S, P, ind_c)
    A, B = _state_matrices(reduced, len(s.u_syms))
    ignorable = _ignorable(_to_numpy(A, s.generic), len(ind_c), [s.coords[i] for i in ind_c])
    second, why = _second_order(s.coords, ind_c, ind_s, reduced, ignorable)
    return _linear_model(s, A, B, P, second, why, ignorable, residual, lam0, qd0, zero_u, ind_c, dep_c, ind_s, dep_s,
                         choice)


@dataclass(frozen=True, slots=True)
class _Setting:
    """The equations and the point, the parameters given their values: what every step reads.

    ``q0``, ``given_rates`` (coordinate index → q̇0) and ``given_inputs`` (name → u0) are the point
    as given, in the parameters left symbolic; ``psubs`` maps the other parameters to their values;
    ``everything`` lists the entries of M, F and the constraint rows (to find what appears in the
    equations); ``generic`` gives the symbols left numbers, to choose columns by rank; ``at_q``
    is ``psubs`` and ``q0`` together.
    """

    eom: EquationsOfMotion
    inputs: tuple[str, ...]
    values: dict[str, float]
    keep: set[str]
    psubs: dict[se.Basic, se.Basic]
    u_syms: list[se.Symbol]
    everything: list[se.Basic]
    q0: dict[se.Basic, se.Basic]
    given_rates: dict[int, se.Basic]
    given_inputs: dict[str, se.Basic]
    sym_left: list[se.Basic]
    generic: dict[se.Basic, float]
    at_q: dict[se.Basic, se.Basic]

    @property
    def coords(self) -> tuple[str, ...]:
        return self.eom.coordinates

    @property
    def n(self) -> int:
        return len(self.eom.coordinates)

    @property
    def rate_names(self) -> list[str]:
        return [c + "_dot" for c in self.eom.coordinates]

    @property
    def holo(self) -> list[int]:
        """The holonomic rows among the complementary constraints."""
        return [k for k, r in enumerate(self.eom.constraints) if r.kind == "holonomic"]


def _operating_point(eom: EquationsOfMotion, independent_speeds: Sequence[str] | None,
                     dependent_coordinates: Sequence[str] | None,
                     ) -> tuple[dict[str, object], Sequence[str] | None, Sequence[str] | None]:
    """The model's ``[operating_point]`` and its choice of independent speeds and dependent coordinates."""
    model = eom.model
    at = dict(getattr(model, "operating_point", ()) or ())
    if not at:
        raise LinearizationError("no point was given and the model has no [operating_point].",
                                 fix="give every coordinate a value, e.g. `at={'theta': 0}` (`--at theta=0`)")
    independent_speeds = independent_speeds or tuple(getattr(model, "independent_speeds", ()) or ()) or None
    dependent_coordinates = dependent_coordinates or tuple(getattr(model, "dependent_coordinates", ()) or ()) or None
    return at, independent_speeds, dependent_coordinates


def _setting(eom: EquationsOfMotion, at: Mapping[str, object], inputs: tuple[str, ...],
             parameters: Mapping[str, float] | None, symbolic: Sequence[str]) -> _Setting:
    """Steps 1 and 2: the point read (every coordinate a value, rates 0 unless given, inputs u0
    0 unless given), the parameters given their values except those kept symbolic and the inputs;
    the equations checked free of t and using every input."""
    coords, q, t = eom.coordinates, eom.q, eom.t
    n = len(coords)
    pnames = {p.name: p for p in eom.model.parameters}
    names = {p: se.Symbol(p) for p in pnames}
    rate_names = [c + "_dot" for c in coords]
    for key in at:
        if key not in coords and key not in rate_names and key not in inputs:
            also = f"; inputs: {', '.join(inputs)}" if inputs else ""
            raise LinearizationError(f"`{key}` is neither a coordinate, a rate nor an input of the linearization "
                                     f"(coordinates: {', '.join(coords)}{also}).",
                                     fix="name a coordinate (`theta`), its rate (`theta_dot`) or an input")
    missing = [c for c in coords if c not in at]
    if missing:
        raise LinearizationError(f"the coordinate{'s' if len(missing) > 1 else ''} {', '.join(f'`{c}`' for c in missing)} "
                                 "of the point have no value.",
                                 fix="give every coordinate a value (rates default to 0), e.g. "
                                     f"`--at {missing[0]}=0`")
    q0 = {q[i]: _value(c, at[c], names) for i, c in enumerate(coords)}
    given_rates = {i: _value(rate_names[i], at[rate_names[i]], names) for i in range(n) if rate_names[i] in at}
    given_inputs = {k: _value(k, at[k], names) for k in inputs if k in at}  # u0

    # Parameter values: the model's, overridden; inputs are 0 at the point.
    values: dict[str, float] = {k: p.value for k, p in pnames.items() if p.value is not None}
    values.update({k: float(v) for k, v in (parameters or {}).items()})
    keep = set(symbolic) | set(inputs)
    psubs = {names[k]: _number(v) for k, v in values.items() if k not in keep}
    u_syms = [names[k] for k in inputs]

    everything = [e for row in eom.M for e in row] + list(eom.F)
    for r in eom.constraints:
        everything += list(r.coefficients) + [r.b]
    # Checked once the parameters have their values: F0 cos(ω t) with F0 = 0 leaves no t.
    if any(t in e.subs(psubs).free_symbols for e in everything if t in e.free_symbols):
        raise LinearizationError("the equations depend on the time t explicitly (a prescribed motion or a "
                                 "time-dependent load): there is no equilibrium or steady motion to linearize about.",
                                 fix="linearize a model whose equations do not depend on t, or give the parameters "
                                     "that switch the time dependence off their value (e.g. --set F0=0)")
    for u in u_syms:
        if not any(u in e.free_symbols for e in eom.F):
            raise LinearizationError(f"no load uses the input `{u}`: its column of B would be zero.",
                                     fix=f"use `{u}` in a load's magnitude, or drop it from the inputs")

    # The point in the parameters left symbolic, and numbers for choosing columns.
    q0 = {k: v.subs(psubs) for k, v in q0.items()}
    given_rates = {i: v.subs(psubs) for i, v in given_rates.items()}
    leftover = set()
    given_inputs = {k: v.subs(psubs) for k, v in given_inputs.items()}
    for v in list(q0.values()) + list(given_rates.values()) + list(given_inputs.values()):
        leftover |= v.free_symbols
    sym_left = sorted({s for e in everything for s in e.free_symbols if str(s) in pnames and s not in psubs} | leftover,
                      key=str)
    return _Setting(eom=eom, inputs=inputs, values=values, keep=keep, psubs=psubs, u_syms=u_syms,
                    everything=everything, q0=q0, given_rates=given_rates, given_inputs=given_inputs,
                    sym_left=sym_left, generic=_generic(sym_left, {}), at_q={**psubs, **q0})


def _dependent_coordinates(s: _Setting, dependent_coordinates: Sequence[str] | None,
                           ) -> tuple[se.DenseMatrix, np.ndarray, list[int]]:
    """Step 3: the holonomic rows f(q0) = 0 checked, and the dependent coordinates q_d whose block
    Φ_d = ∂f/∂q_d is regular at the point (given, else chosen by rank, moving coordinates last).

    Returns A0 (the constraint rows' coefficients at the point), its numbers, and q_d's indices.
    """
    coords, n, rows, holo, generic, at_q = s.coords, s.n, s.eom.constraints, s.holo, s.generic, s.at_q
    m, h = len(rows), len(holo)
    for k in holo:
        res = complex(rows[k].expression.subs(at_q).subs(generic))
        if abs(res) > POINT_RTOL * max(1.0, _scale_of(rows[k].expression, at_q, generic)):
            raise LinearizationError(f"the point does not satisfy the holonomic constraint `{rows[k].name}` "
                                     f"(residual {abs(res):.3g}).",
                                     fix="give the dependent coordinates values that satisfy the constraint")
    A_at = se.DenseMatrix([[e.subs(at_q) for e in r.coefficients] for r in rows]) if m else se.zeros(0, n)
    A_num = _to_numpy(A_at, generic) if m else np.zeros((0, n))
    given_nonzero = {i for i, v in s.given_rates.items() if not _is_structural_zero(v)}
    if dependent_coordinates:
        dep_c = [coords.index(c) if c in coords else _bad_name(c, "coordinate") for c in dependent_coordinates]
    else:
        order = [i for i in range(n) if i not in given_nonzero] + sorted(given_nonzero)
        dep_c = _choose(A_num[holo], h, order) if h else []
    if h and (len(dep_c) != h or np.linalg.matrix_rank(A_num[np.ix_(holo, dep_c)]) < h):
        raise LinearizationError("the holonomic constraints' Jacobian is singular at the point for the dependent "
                                 f"coordinates {', '.join(coords[i] for i in dep_c) or '(none)'}.",
                                 fix="choose other dependent coordinates, or a regular point")
    return A_at, A_num, dep_c


def _dependent_speeds(s: _Setting, A_num: np.ndarray, dep_c: list[int],
                      independent_speeds: Sequence[str] | None) -> tuple[list[int], str]:
    """Step 4: the dependent speeds q̇_d whose block A_d of the velocity rows A q̇ + b = 0 is regular
    at the point: the complement of the independent speeds given, else chosen by rank, preferring
    the rates of dependent coordinates, of coordinates absent from the equations, of rates not
    given.  Returns their indices and a sentence saying how they were chosen."""
    n, m, rate_names = s.n, len(s.eom.constraints), s.rate_names
    if independent_speeds:
        names_ind = list(independent_speeds)
        bad = [r for r in names_ind if r not in rate_names]
        if bad:
            _bad_name(bad[0], "rate (`<coordinate>_dot`)")
        dep_s = [i for i in range(n) if rate_names[i] not in names_ind]
        if len(dep_s) != m or (m and np.linalg.matrix_rank(A_num[:, dep_s]) < m):
            raise LinearizationError(f"with {', '.join(names_ind)} independent, the {m} constraint rows do not fix "
                                     "the other speeds at the point.",
                                     fix=f"name {n - m} independent speeds whose complement is fixed by the rows")
        return dep_s, "independent speeds given by the user: " + ", ".join(names_ind)
    appears = {x for e in s.everything for x in e.free_symbols}
    ignorable_like = [i for i in range(n) if s.eom.q[i] not in appears]
    rest = [i for i in range(n) if i not in dep_c]
    free_first = sorted((i for i in rest if i not in s.given_rates), key=lambda i: (i not in ignorable_like, i))
    order = dep_c + free_first + [i for i in rest if i in s.given_rates]
    dep_s = _choose(A_num, m, order)
    if len(dep_s) != m:  # pragma: no cover - the rows are independent at a generic state (derive checks)
        raise LinearizationError("the constraint rows are dependent at the point.", fix="choose another point")
    return dep_s, ("dependent speeds chosen by rank at the point, preferring the rates of dependent coordinates, "
                   "of coordinates absent from the equations and of rates not given")


def _rates(s: _Setting, A_at: se.DenseMatrix, ind_s: list[int], dep_s: list[int]) -> dict[se.Basic, se.Basic]:
    """Step 5: the rates at the point, q̇0: the independent ones given (or 0), the dependent ones
    solved from the velocity rows, q̇0_d = −A_d⁻¹ (A_i q̇0_i + b); a dependent rate given must agree."""
    qd, rows, generic, rate_names = s.eom.qd, s.eom.constraints, s.generic, s.rate_names
    m = len(rows)
    qd0: dict[se.Basic, se.Basic] = {qd[i]: _snap(s.given_rates.get(i, _ZERO)) for i in ind_s}
    if m:
        b_at = se.DenseMatrix([[r.b.subs(s.at_q)] for r in rows])
        Ai = _sub(A_at, list(range(m)), ind_s) if ind_s else se.zeros(m, 0)
        Ad = _sub(A_at, list(range(m)), dep_s)
        ui0 = se.DenseMatrix([[qd0[qd[i]]] for i in ind_s]) if ind_s else se.zeros(0, 1)
        rhs = -(Ai * ui0 if ind_s else se.zeros(m, 1)) - b_at
        ud0 = _solve(Ad, rhs)
        for k, i in enumerate(dep_s):
            solved = se.expand(ud0[k, 0])
            if i in s.given_rates:
                diff = complex(se.expand(s.given_rates[i] - solved).subs(generic))
                if abs(diff) > POINT_RTOL * max(1.0, abs(complex(solved.subs(generic)))):
                    raise LinearizationError(f"the rate `{rate_names[i]}` given at the point contradicts the constraints "
                                             f"(they fix it at {float(complex(solved.subs(generic)).real):.6g}).",
                                             fix=f"leave `{rate_names[i]}` out: it is solved from the constraints")
            qd0[qd[i]] = _snap(solved)
    return qd0


def _check_steady(s: _Setting, qd0: Mapping[se.Basic, se.Basic]) -> None:
    """Step 6: a steady motion moves only coordinates absent from the equations (q̇0_j ≠ 0 ⇒
    ∂M/∂q_j = ∂F/∂q_j = 0): else the point moves and there is nothing fixed to linearize about."""
    q, qd, coords, rate_names, everything = s.eom.q, s.eom.qd, s.coords, s.rate_names, s.everything
    appears = {x for e in everything for x in e.free_symbols}
    moving = [i for i in range(s.n) if not _is_structural_zero(qd0[qd[i]]) and q[i] in appears]
    held = {i for i in moving  # present in the expressions, but only through identities (sin² + cos²)
            if not all(are_zero([e.diff(q[i]) for e in everything if q[i] in e.free_symbols]))}
    for i in moving:
        if i in held:
            raise LinearizationError(f"`{coords[i]}` moves at the point ({rate_names[i]} = {qd0[qd[i]]}) but the "
                                     "equations depend on it: the motion is not steady, there is no fixed point to "
                                     "linearize about.",
                                     fix=f"set `{rate_names[i]}=0`, or move only coordinates absent from the equations")


def _forces_at(s: _Setting, point_subs: Mapping[se.Basic, se.Basic],
               ) -> tuple[list[se.Basic], se.DenseMatrix, dict[se.Basic, se.Basic]]:
    """Step 7: F with the parameters' values, M0 = M(q0) checked finite and regular, and the
    inputs' values u0 (0 unless given)."""
    F_p = [f.subs(s.psubs) for f in s.eom.F]
    M0 = se.DenseMatrix([[e.subs(s.psubs).subs(point_subs) for e in row] for row in s.eom.M])
    zero_u = {u: s.given_inputs.get(str(u), _ZERO) for u in s.u_syms}  # u0, 0 unless given
    Mn = _to_numpy(M0, s.generic)
    if not np.all(np.isfinite(Mn)):
        raise LinearizationError("the mass matrix M is not finite at the point (a number of the model overflows, or an "
                                 "entry is undefined there).",
                                 fix="check the masses and inertias (e.g. a denormal 5e-324 mass) and the point")
    if np.linalg.matrix_rank(Mn, tol=RANK_RTOL * max(1.0, np.abs(Mn).max(initial=0.0))) < s.n:
        raise LinearizationError("the mass matrix M is singular at the point (the coordinates are singular there, "
                                 "e.g. Euler angles at θ = 0).",
                                 fix="linearize about another point, or describe the system with regular coordinates")
    return F_p, M0, zero_u


def _residual(s: _Setting, F_p: list[se.Basic], zero_u: Mapping[se.Basic, se.Basic],
              at_all: Mapping[se.Basic, se.Basic], Csym: se.DenseMatrix, A_at: se.DenseMatrix,
              point_subs: Mapping[se.Basic, se.Basic], ind_c: list[int], dep_c: list[int], ind_s: list[int],
              ) -> tuple[float, se.DenseMatrix, se.DenseMatrix]:
    """Step 7 continued: the point is steady when the force along the admissible velocities vanishes,
    Cᵀ F0 = 0 (relative to the forces' scale, within `POINT_RTOL`); then λ0 solves F0 + A0ᵀ λ0 = 0.

    Returns the relative residual, ∂F/∂q at the point (reused by the Jacobians) and λ0.
    """
    F0 = se.DenseMatrix([[f.subs(point_subs)] for f in F_p])
    F0 = F0.subs(zero_u) if s.u_syms else F0
    generic = s.generic
    res_sym = Csym.T * F0
    dF_dq = _jacobian(F_p, list(s.eom.q), at_all)
    scale = max(max((_scale_of(f, at_all, generic) for f in F_p), default=0.0),
                float(np.abs(_to_numpy(dF_dq, generic)).max(initial=0.0))) or 1.0
    residual = float(np.abs(_to_numpy(res_sym, generic)).max(initial=0.0)) / scale if res_sym.rows else 0.0
    if residual > POINT_RTOL:
        raise LinearizationError(
            f"the point is not an equilibrium or a steady motion: the residual force is "
            f"{_format_residual(res_sym, generic, ind_s, s.rate_names)} ({residual:.2g} of the forces' scale)."
            + _nearest(s.eom, s.at_q, point_subs, generic, ind_c, dep_c, s.psubs),
            fix="linearize about an equilibrium (lagrangian equilibria MODEL) or a steady motion"
                + (", or hold the point with the inputs' values (--hold; `holding_inputs`)" if s.u_syms else ""))
    lam0 = _multipliers(A_at, F0) if s.eom.constraints else se.zeros(0, 1)
    return residual, dF_dq, lam0


def _linear_model(s: _Setting, A: se.DenseMatrix, B: se.DenseMatrix, P: se.DenseMatrix,
                  second: SecondOrderForm | None, why: str, ignorable: tuple[str, ...], residual: float,
                  lam0: se.DenseMatrix, qd0: Mapping[se.Basic, se.Basic], zero_u: Mapping[se.Basic, se.Basic],
                  ind_c: list[int], dep_c: list[int], ind_s: list[int], dep_s: list[int], choice: str) -> LinearModel:
    """The result: the point with every rate (dependent ones solved) and the inputs given, the
    names of the state, and the symbols left in A and B."""
    coords, rate_names, q, qd, rows = s.coords, s.rate_names, s.eom.q, s.eom.qd, s.eom.constraints
    m = len(rows)
    point = {c: se.expand(s.q0[q[i]]) for i, c in enumerate(coords)}
    point.update({rate_names[i]: qd0[qd[i]] for i in range(s.n)})
    point.update({str(u): zero_u[u] for u in s.u_syms if str(u) in s.given_inputs})
    return LinearModel(
        eom=s.eom, point=point, coordinates=tuple(coords[i] for i in ind_c), speeds=tuple(rate_names[i] for i in ind_s),
        dependent_coordinates=tuple(coords[i] for i in dep_c), dependent_speeds=tuple(rate_names[i] for i in dep_s),
        choice=choice if m else "no complementary constraint: every coordinate and rate is independent",
        inputs=tuple(s.inputs), A=A, B=B,
        symbols=tuple(x for x in s.sym_left if str(x) not in s.inputs and (any(x in e.free_symbols for e in A)
                                                                          or any(x in e.free_symbols for e in B))),
        values={k: v for k, v in s.values.items() if k not in s.keep}, second_order=second, second_order_reason=why,
        ignorable=ignorable, residual=residual,
        multipliers={rows[k].multiplier.name: lam0[k, 0] for k in range(m)}, coordinate_map=_tidy(P))


def _snap(e: se.Basic) -> se.Basic:
    """A numeric rate within rounding of zero is zero (dependent speeds solved in floating point)."""
    if not e.free_symbols and abs(complex(e)) < 1e-13:
        return _ZERO
    return e


def _bad_name(name: str, kind: str) -> int:
    raise LinearizationError(f"`{name}` is not a {kind} of the model.", fix="check its spelling")



def _scale_of(expr: se.Basic, subs: Mapping, generic: Mapping) -> float:
    terms = expr.args if isinstance(expr, se.Add) else (expr,)
    total = 0.0
    for term in terms:
        try:
            total += abs(complex(term.subs(subs).subs(generic)))
        except (RuntimeError, TypeError):
            pass
    return total


def _format_residual(res: se.DenseMatrix, generic: Mapping, ind_s: Sequence[int], rate_names: Sequence[str]) -> str:
    vals = _to_numpy(res, generic)[:, 0]
    return ", ".join(f"{rate_names[i][:-4]}: {v:.6g}" for i, v in zip(ind_s, vals, strict=True))


def _nearest(eom: EquationsOfMotion, at_q: Mapping, point_subs: Mapping, generic: Mapping, ind_c: Sequence[int],
             dep_c: Sequence[int], psubs: Mapping) -> str:
    """' The nearest equilibrium found: θ = 3.14159265.' (unconstrained models at rest), or ''."""
    if eom.constraints or any(not _is_structural_zero(point_subs[s]) for s in eom.qd):
        return ""
    from scipy import optimize
    q = list(eom.q)
    rest = {**{s: _ZERO for s in eom.qd}}
    F = [f.subs(psubs).subs(rest).subs(generic) for f in eom.F]
    try:
        fn = se.Lambdify(q, F)
        x0 = np.array([complex(at_q[s].subs(generic)).real for s in q])
        sol = optimize.root(lambda x: np.asarray(fn(x), dtype=float).ravel(), x0)
    except (RuntimeError, TypeError, ValueError):  # pragma: no cover - defensive: no hint then
        return ""
    if not sol.success:
        return ""
    return " The nearest equilibrium found: " + ", ".join(f"{s} = {v:.10g}" for s, v in zip(q, sol.x, strict=True)) + "."


def holding_inputs(eom: EquationsOfMotion, at: Mapping[str, object], *,
                   parameters: Mapping[str, float] | None = None,
                   inputs: Sequence[str] | None = None) -> dict[str, float]:
    """The inputs u0 that hold the system at rest at ``at``: F(q0, 0, u0) = 0, for `linearize`.

    For a robot these are the gravity-compensating joint torques τ0 = g(q0) (Pinocchio's
    ``computeGeneralizedGravity``).  F is affine in the inputs of a load's magnitude (Q_j = τ_j),
    so u0 solves F(q0, q̇0, 0) + (∂F/∂u) u0 = 0 by least squares; the inputs given in ``at`` keep
    their values.  Every parameter needs a value.

    Parameters
    ----------
    eom : EquationsOfMotion
        The equations.
    at : mapping of str to object
        The point, as for `linearize`.
    parameters : mapping of str to float, optional
        Parameter values overriding the model's.
    inputs : sequence of str, optional
        The inputs to solve for (default: the model's declared inputs).

    Returns
    -------
    dict of str to float
        The inputs u0, by input name.

    Raises
    ------
    LinearizationError
        A coordinate without a value, or a point that no input values hold (an under-actuated
        system away from its equilibria): with the residual force.
    """
    model = eom.model
    pnames = {p.name: p for p in model.parameters}
    names = {p: se.Symbol(p) for p in pnames}
    inputs = tuple(model.inputs if inputs is None else inputs)
    coords = eom.coordinates
    missing = [c for c in coords if c not in at]
    if missing:
        raise LinearizationError(f"the coordinate `{missing[0]}` of the point has no value.",
                                 fix=f"give every coordinate a value, e.g. `--at {missing[0]}=0`")
    values = {k: p.value for k, p in pnames.items() if p.value is not None}
    values.update({k: float(v) for k, v in (parameters or {}).items()})
    free = [k for k in inputs if k not in at]
    subs: dict[se.Basic, se.Basic] = {names[k]: _number(v) for k, v in values.items() if k not in free}
    for k in inputs:
        if k in at:
            subs[names[k]] = _value(k, at[k], names).subs(subs)
    for i, c in enumerate(coords):
        subs[eom.q[i]] = _value(c, at[c], names).subs(subs)
        subs[eom.qd[i]] = _value(c + "_dot", at.get(c + "_dot", 0), names).subs(subs)
    u = [names[k] for k in free]
    F = [f.subs(subs) for f in eom.F]
    try:
        F0 = np.array([float(f.subs({s: 0 for s in u})) for f in F])
        Bf = np.array([[float(f.diff(s).subs({x: 0 for x in u})) for s in u] for f in F]).reshape(len(F), len(u))
    except (RuntimeError, TypeError) as exc:
        raise LinearizationError(f"the holding inputs need every parameter's value ({exc}).",
                                 fix="give the parameters values (`--set NAME=VALUE`)") from None
    u0 = np.linalg.lstsq(Bf, -F0, rcond=None)[0] if u else np.zeros(0)
    residual = F0 + Bf @ u0
    scale = max(float(np.abs(F0).max(initial=0.0)), 1.0)
    if np.abs(residual).max(initial=0.0) > POINT_RTOL * scale:
        worst = int(np.argmax(np.abs(residual)))
        raise LinearizationError(f"no values of the inputs {', '.join(free) or '(none)'} hold the point: the force "
                                 f"along `{coords[worst]}` stays {residual[worst]:.6g}.",
                                 fix="choose an equilibrium of the coordinates the inputs do not drive "
                                     "(lagrangian equilibria MODEL), or more inputs")
    return {k: float(v) for k, v in zip(free, u0, strict=True)}
