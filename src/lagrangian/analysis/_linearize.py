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

References: Meirovitch, *Methods of Analytical Dynamics* (1970), ch. 6; Meijaard et al.,
Proc. R. Soc. A 463 (2007) 1955–1982, §4 (the bicycle, reduced the same way).
"""

from __future__ import annotations

import math
import random
from collections.abc import Mapping, Sequence

import numpy as np
import symengine as se

from .._identity import are_zero
from ..dynamics import EquationsOfMotion
from ..model._expr import ExpressionError, parse_expression
from ._linear_algebra import RANK_RTOL
from ._linear_algebra import choose as _choose
from ._linear_algebra import jacobian as _jacobian
from ._linear_algebra import solve as _solve
from ._linear_algebra import stack as _stack
from ._linear_algebra import sub as _sub
from ._linear_algebra import tidy as _tidy
from ._linear_model import LinearizationError, LinearModel, SecondOrderForm, _is_structural_zero
from ._linear_model import to_numpy as _to_numpy

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
    eom : from `lagrangian.derive`.
    at : the point: every coordinate ``q`` a value, rates ``q_dot`` optional (0 by default;
        dependent speeds are solved from the constraints), inputs optional (0 by default: a
        robot held still by its joint torques is ``{"q1": 0.3, "tau_q1": 4.2}``; see
        `holding_inputs`).  Values are numbers, SymEngine expressions in the parameters, or
        text in the model grammar (``"pi"``, ``"-v/rR"``).  None: the model's
        ``[operating_point]`` table.
    parameters : parameter values overriding the model's.
    symbolic : parameters kept as symbols although they have a value (A(v) for a sweep).
    inputs : the inputs u, columns of B: parameters or declared ``[inputs]`` (default: the
        model's declared inputs).  Their values at the point u0 come from ``at`` (0 when not
        given), and A, B are the Jacobians at (q0, q̇0, u0).
    independent_speeds, dependent_coordinates : the choice of the reduction, when the model
        keeps constraints complementary (default: the model's, else chosen by rank).

    Returns
    -------
    LinearModel

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
    model = eom.model
    coords = eom.coordinates
    n = len(coords)
    q, qd, t = eom.q, eom.qd, eom.t
    pnames = {p.name: p for p in model.parameters}
    declared_inputs = tuple(getattr(model, "inputs", ()) or ())
    inputs = tuple(declared_inputs if inputs is None else inputs)
    for name in list(symbolic) + list(inputs) + list(parameters or {}):
        if name not in pnames:
            raise LinearizationError(f"`{name}` is not a parameter of the model ({', '.join(pnames) or 'none'}).",
                                     fix="check its spelling, or declare it under [parameters] or [inputs]")

    # 1. The point: every coordinate a value; rates 0 unless given.
    if at is None:
        at = dict(getattr(model, "operating_point", ()) or ())
        if not at:
            raise LinearizationError("no point was given and the model has no [operating_point].",
                                     fix="give every coordinate a value, e.g. `at={'theta': 0}` (`--at theta=0`)")
        independent_speeds = independent_speeds or tuple(getattr(model, "independent_speeds", ()) or ()) or None
        dependent_coordinates = dependent_coordinates or tuple(getattr(model, "dependent_coordinates", ()) or ()) or None
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

    # 2. Parameter values: the model's, overridden; inputs are 0 at the point.
    values: dict[str, float] = {k: p.value for k, p in pnames.items() if p.value is not None}
    values.update({k: float(v) for k, v in (parameters or {}).items()})
    keep = set(symbolic) | set(inputs)
    psubs = {names[k]: _number(v) for k, v in values.items() if k not in keep}
    u_syms = [names[k] for k in inputs]

    rows = eom.constraints
    holo = [k for k, r in enumerate(rows) if r.kind == "holonomic"]
    m, h = len(rows), len(holo)
    everything = [e for row in eom.M for e in row] + list(eom.F)
    for r in rows:
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
    generic = _generic(sym_left, {})
    at_q = {**psubs, **q0}

    # 3. Holonomic rows: f(q0) = 0, dependent coordinates by rank.
    for k in holo:
        res = complex(rows[k].expression.subs(at_q).subs(generic))
        if abs(res) > POINT_RTOL * max(1.0, _scale_of(rows[k].expression, at_q, generic)):
            raise LinearizationError(f"the point does not satisfy the holonomic constraint `{rows[k].name}` "
                                     f"(residual {abs(res):.3g}).",
                                     fix="give the dependent coordinates values that satisfy the constraint")
    A_at = se.DenseMatrix([[e.subs(at_q) for e in r.coefficients] for r in rows]) if m else se.zeros(0, n)
    A_num = _to_numpy(A_at, generic) if m else np.zeros((0, n))
    given_nonzero = {i for i, v in given_rates.items() if not _is_structural_zero(v)}
    appears = {s for e in everything for s in e.free_symbols}
    ignorable_like = [i for i in range(n) if q[i] not in appears]
    if dependent_coordinates:
        dep_c = [coords.index(c) if c in coords else _bad_name(c, "coordinate") for c in dependent_coordinates]
    else:
        order = [i for i in range(n) if i not in given_nonzero] + sorted(given_nonzero)
        dep_c = _choose(A_num[holo], h, order) if h else []
    if h and (len(dep_c) != h or np.linalg.matrix_rank(A_num[np.ix_(holo, dep_c)]) < h):
        raise LinearizationError("the holonomic constraints' Jacobian is singular at the point for the dependent "
                                 f"coordinates {', '.join(coords[i] for i in dep_c) or '(none)'}.",
                                 fix="choose other dependent coordinates, or a regular point")
    # 4. Velocity rows: dependent speeds (those of the dependent coordinates first).
    if independent_speeds:
        names_ind = list(independent_speeds)
        bad = [s for s in names_ind if s not in rate_names]
        if bad:
            _bad_name(bad[0], "rate (`<coordinate>_dot`)")
        dep_s = [i for i in range(n) if rate_names[i] not in names_ind]
        if len(dep_s) != m or (m and np.linalg.matrix_rank(A_num[:, dep_s]) < m):
            raise LinearizationError(f"with {', '.join(names_ind)} independent, the {m} constraint rows do not fix "
                                     "the other speeds at the point.",
                                     fix=f"name {n - m} independent speeds whose complement is fixed by the rows")
        choice = "independent speeds given by the user: " + ", ".join(names_ind)
    else:
        rest = [i for i in range(n) if i not in dep_c]
        free_first = sorted((i for i in rest if i not in given_rates), key=lambda i: (i not in ignorable_like, i))
        order = dep_c + free_first + [i for i in rest if i in given_rates]
        dep_s = _choose(A_num, m, order)
        if len(dep_s) != m:  # pragma: no cover - the rows are independent at a generic state (derive checks)
            raise LinearizationError("the constraint rows are dependent at the point.", fix="choose another point")
        choice = ("dependent speeds chosen by rank at the point, preferring the rates of dependent coordinates, "
                  "of coordinates absent from the equations and of rates not given")
    ind_s = [i for i in range(n) if i not in dep_s]
    ind_c = [i for i in range(n) if i not in dep_c]

    # 5. Rates at the point: the independent ones given (or 0), the dependent ones solved.
    qd0: dict[se.Basic, se.Basic] = {qd[i]: _snap(given_rates.get(i, _ZERO)) for i in ind_s}
    if m:
        b_at = se.DenseMatrix([[r.b.subs(at_q)] for r in rows])
        Ai = _sub(A_at, list(range(m)), ind_s) if ind_s else se.zeros(m, 0)
        Ad = _sub(A_at, list(range(m)), dep_s)
        ui0 = se.DenseMatrix([[qd0[qd[i]]] for i in ind_s]) if ind_s else se.zeros(0, 1)
        rhs = -(Ai * ui0 if ind_s else se.zeros(m, 1)) - b_at
        ud0 = _solve(Ad, rhs)
        for k, i in enumerate(dep_s):
            solved = se.expand(ud0[k, 0])
            if i in given_rates:
                diff = complex(se.expand(given_rates[i] - solved).subs(generic))
                if abs(diff) > POINT_RTOL * max(1.0, abs(complex(solved.subs(generic)))):
                    raise LinearizationError(f"the rate `{rate_names[i]}` given at the point contradicts the constraints "
                                             f"(they fix it at {float(complex(solved.subs(generic)).real):.6g}).",
                                             fix=f"leave `{rate_names[i]}` out: it is solved from the constraints")
            qd0[qd[i]] = _snap(solved)
    point_subs = {**at_q, **qd0}

    # 6. Steady: a moving coordinate must be absent from the equations.
    moving = [i for i in range(n) if not _is_structural_zero(qd0[qd[i]]) and q[i] in appears]
    held = {i for i in moving  # present in the expressions, but only through identities (sin² + cos²)
            if not all(are_zero([e.diff(q[i]) for e in everything if q[i] in e.free_symbols]))}
    for i in moving:
        if i in held:
            raise LinearizationError(f"`{coords[i]}` moves at the point ({rate_names[i]} = {qd0[qd[i]]}) but the "
                                     "equations depend on it: the motion is not steady, there is no fixed point to "
                                     "linearize about.",
                                     fix=f"set `{rate_names[i]}=0`, or move only coordinates absent from the equations")

    # 7. The pieces at the point.
    F_p = [f.subs(psubs) for f in eom.F]
    M0 = se.DenseMatrix([[e.subs(psubs).subs(point_subs) for e in row] for row in eom.M])
    F0 = se.DenseMatrix([[f.subs(point_subs)] for f in F_p])
    zero_u = {u: given_inputs.get(str(u), _ZERO) for u in u_syms}  # u0, 0 unless given
    F0 = F0.subs(zero_u) if u_syms else F0
    Mn = _to_numpy(M0, generic)
    if not np.all(np.isfinite(Mn)):
        raise LinearizationError("the mass matrix M is not finite at the point (a number of the model overflows, or an "
                                 "entry is undefined there).",
                                 fix="check the masses and inertias (e.g. a denormal 5e-324 mass) and the point")
    if np.linalg.matrix_rank(Mn, tol=RANK_RTOL * max(1.0, np.abs(Mn).max(initial=0.0))) < n:
        raise LinearizationError("the mass matrix M is singular at the point (the coordinates are singular there, "
                                 "e.g. Euler angles at θ = 0).",
                                 fix="linearize about another point, or describe the system with regular coordinates")
    # C = ∂q̇/∂u and S = the map of the dependent rows, numerically to check the point.
    Csym, S = _velocity_maps(A_at, ind_s, dep_s, n)
    at_all = {**point_subs, **zero_u}
    res_sym = Csym.T * F0
    dF_dq = _jacobian(F_p, list(q), at_all)
    scale = max(max((_scale_of(f, at_all, generic) for f in F_p), default=0.0),
                float(np.abs(_to_numpy(dF_dq, generic)).max(initial=0.0))) or 1.0
    residual = float(np.abs(_to_numpy(res_sym, generic)).max(initial=0.0)) / scale if res_sym.rows else 0.0
    if residual > POINT_RTOL:
        raise LinearizationError(
            f"the point is not an equilibrium or a steady motion: the residual force is "
            f"{_format_residual(res_sym, generic, ind_s, rate_names)} ({residual:.2g} of the forces' scale)."
            + _nearest(eom, at_q, point_subs, generic, ind_c, dep_c, psubs),
            fix="linearize about an equilibrium (lagrangian equilibria MODEL) or a steady motion"
                + (", or hold the point with the inputs' values (--hold; `holding_inputs`)" if u_syms else ""))
    lam0 = _multipliers(A_at, F0) if m else se.zeros(0, 1)

    # 8. Jacobians.
    qs, qds = list(q), list(qd)
    Kf = -dF_dq
    if m:
        lamA = [se.Add(*[lam0[k, 0] * rows[k].coefficients[i].subs(psubs) for k in range(m)]) for i in range(n)]
        Kf = Kf - _jacobian(lamA, qs, at_all)
        vel = [se.Add(*[r.coefficients[i] * qd[i] for i in range(n)], r.b).subs(psubs) for r in rows]
        W = _jacobian(vel, qs, {**at_all})
    Df = -_jacobian(F_p, qds, at_all)
    Bf = _jacobian(F_p, u_syms, at_all) if u_syms else se.zeros(n, 0)
    # P: δq = P δq_i.
    if h:
        Phi = _sub(A_at, holo, list(range(n)))
        Phi_d = _sub(Phi, list(range(h)), dep_c)
        Phi_i = _sub(Phi, list(range(h)), ind_c)
        dq_d = -_solve(Phi_d, Phi_i)
        P = _stack(n, ind_c, se.eye(len(ind_c)), dep_c, dq_d)
    else:
        P = se.eye(n)
    J = S * W if m else se.zeros(n, n)
    MJD = M0 * J + Df
    Mr = Csym.T * M0 * Csym
    Cr = Csym.T * MJD * Csym
    Kr = Csym.T * (Kf + MJD * J) * P
    Br = Csym.T * Bf
    kin_c = (_sub(Csym, ind_c, list(range(Csym.cols))), _sub(J * P, ind_c, list(range(P.cols))))
    ni, nu = len(ind_c), len(ind_s)
    Minv_C = _solve(Mr, Cr)
    Minv_K = _solve(Mr, Kr)
    Minv_B = _solve(Mr, Br) if Br.cols else se.zeros(nu, 0)
    A = se.zeros(ni + nu, ni + nu)
    for r in range(ni):
        for c in range(ni):
            A[r, c] = kin_c[1][r, c]
        for c in range(nu):
            A[r, ni + c] = kin_c[0][r, c]
    for r in range(nu):
        for c in range(ni):
            A[ni + r, c] = -Minv_K[r, c]
        for c in range(nu):
            A[ni + r, ni + c] = -Minv_C[r, c]
    B = se.zeros(ni + nu, len(u_syms))
    for r in range(nu):
        for c in range(len(u_syms)):
            B[ni + r, c] = Minv_B[r, c]
    A, B = _tidy(A), _tidy(B)
    An = _to_numpy(A, generic)
    ignorable = _ignorable(An, ni, [coords[i] for i in ind_c])
    second, why = _second_order(coords, ind_c, ind_s, Mr, Cr, Kr, Br, kin_c, ignorable, generic)
    point = {c: se.expand(q0[q[i]]) for i, c in enumerate(coords)}
    point.update({rate_names[i]: qd0[qd[i]] for i in range(n)})
    point.update({str(u): zero_u[u] for u in u_syms if str(u) in given_inputs})
    return LinearModel(
        eom=eom, point=point, coordinates=tuple(coords[i] for i in ind_c), speeds=tuple(rate_names[i] for i in ind_s),
        dependent_coordinates=tuple(coords[i] for i in dep_c), dependent_speeds=tuple(rate_names[i] for i in dep_s),
        choice=choice if m else "no complementary constraint: every coordinate and rate is independent",
        inputs=tuple(inputs), A=A, B=B,
        symbols=tuple(s for s in sym_left if str(s) not in inputs and (any(s in e.free_symbols for e in A)
                                                                        or any(s in e.free_symbols for e in B))),
        values={k: v for k, v in values.items() if k not in keep}, second_order=second, second_order_reason=why,
        ignorable=ignorable, residual=residual,
        multipliers={rows[k].multiplier.name: lam0[k, 0] for k in range(m)}, coordinate_map=_tidy(P))


def _ignorable(An: np.ndarray, ni: int, names: Sequence[str]) -> tuple[str, ...]:
    """Coordinates nothing depends on, found repeatedly: the bicycle's y first (δẏ = v δψ is its
    only use of ψ), then its heading ψ."""
    keep = list(range(An.shape[0]))
    out: list[int] = []
    changed = True
    while changed:
        changed = False
        for c in range(ni):
            if c in keep and not np.any(An[np.ix_(keep, [c])]):
                keep.remove(c)
                out.append(c)
                changed = True
    return tuple(names[c] for c in sorted(out))


def _snap(e: se.Basic) -> se.Basic:
    """A numeric rate within rounding of zero is zero (dependent speeds solved in floating point)."""
    if not e.free_symbols and abs(complex(e)) < 1e-13:
        return _ZERO
    return e


def _bad_name(name: str, kind: str) -> int:
    raise LinearizationError(f"`{name}` is not a {kind} of the model.", fix="check its spelling")


def _velocity_maps(A_at: se.DenseMatrix, ind_s: list[int], dep_s: list[int], n: int) -> tuple[se.DenseMatrix, se.DenseMatrix]:
    """C = ∂q̇/∂u (n × p) and S (n × m): δq̇_d = −A_d⁻¹ (A_i δu + W δq) placed in the dependent rows."""
    m = A_at.rows
    if not m:
        return se.eye(n), se.zeros(n, 0)
    Ad = _sub(A_at, list(range(m)), dep_s)
    Ai = _sub(A_at, list(range(m)), ind_s) if ind_s else se.zeros(m, 0)
    Ad_inv = _solve(Ad, se.eye(m))
    C = _stack(n, ind_s, se.eye(len(ind_s)), dep_s, -(Ad_inv * Ai)) if ind_s else se.zeros(n, 0)
    S = _stack(n, ind_s, se.zeros(len(ind_s), m), dep_s, -Ad_inv)
    return C, S


def _multipliers(A_at: se.DenseMatrix, F0: se.DenseMatrix) -> se.DenseMatrix:
    """λ0 with F0 + A0ᵀ λ0 = 0 (least squares; exact at a steady point)."""
    AAT = A_at * A_at.T
    return _solve(AAT, -(A_at * F0))


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


def _rounding_to_zero(skew: se.DenseMatrix, whole: se.DenseMatrix) -> se.DenseMatrix:
    """The skew part of a numeric matrix (a point held by computed torques) with its rounding dropped:
    entries below 1e-12 of the matrix's largest are 0, so that a symmetric K does not show N ≈ 1e−16."""
    entries = [whole[i, j] for i in range(whole.rows) for j in range(whole.cols)]
    if any(e.free_symbols for e in entries) or any(skew[i, j].free_symbols for i in range(skew.rows)
                                                   for j in range(skew.cols)):
        return skew
    try:
        scale = max((abs(float(e)) for e in entries), default=0.0)
    except (TypeError, RuntimeError):  # complex or not a number: left as it is
        return skew
    return skew.applyfunc(lambda e: se.Integer(0) if abs(float(e)) <= 1e-12 * scale else e)


def _second_order(coords: Sequence[str], ind_c: Sequence[int], ind_s: Sequence[int], Mr: se.DenseMatrix,
                  Cr: se.DenseMatrix, Kr: se.DenseMatrix, Br: se.DenseMatrix, kin_c, ignorable: Sequence[str],
                  generic: Mapping) -> tuple[SecondOrderForm | None, str]:
    """M δq̈ + (D + G) δq̇ + (K + N) δq = B u on the coordinates whose rates are the independent speeds.

    It exists when every other independent coordinate is ignorable (a zero column of A): then
    δq̇_c = δu_c for the coordinates kept and the reduced equations are second order in them.
    """
    speeds_coord = list(ind_s)  # the coordinate index of each independent speed
    kept = [i for i in speeds_coord if i in ind_c]
    if len(kept) != len(speeds_coord):
        return None, ("an independent speed is the rate of a dependent coordinate: the reduced equations are "
                      "first order only")
    others = [c for c in ind_c if c not in speeds_coord]
    if any(coords[c] not in ignorable for c in others):
        return None, ("an independent coordinate whose rate is not an independent speed acts on the motion: "
                      "the reduced equations are first order only (see A)")
    cols = [list(ind_c).index(i) for i in kept]
    K_full = _sub(Kr, list(range(Kr.rows)), cols)
    Msym = Mr
    Dsym = (Cr + Cr.T) / 2
    Gskew = (Cr - Cr.T) / 2
    Ksym = (K_full + K_full.T) / 2
    Nskew = (K_full - K_full.T) / 2
    Gskew, Nskew = _rounding_to_zero(Gskew, Cr), _rounding_to_zero(Nskew, K_full)
    form = SecondOrderForm(tuple(coords[i] for i in kept), _tidy(Msym), _tidy(Dsym), _tidy(Gskew), _tidy(Ksym),
                           _tidy(Nskew), _tidy(Br))
    return form, ""


def holding_inputs(eom: EquationsOfMotion, at: Mapping[str, object], *,
                   parameters: Mapping[str, float] | None = None,
                   inputs: Sequence[str] | None = None) -> dict[str, float]:
    """The inputs u0 that hold the system at rest at ``at``: F(q0, 0, u0) = 0, for `linearize`.

    For a robot these are the gravity-compensating joint torques τ0 = g(q0) (Pinocchio's
    ``computeGeneralizedGravity``).  F is affine in the inputs of a load's magnitude (Q_j = τ_j),
    so u0 solves F(q0, q̇0, 0) + (∂F/∂u) u0 = 0 by least squares; the inputs given in ``at`` keep
    their values.  Every parameter needs a value.

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
