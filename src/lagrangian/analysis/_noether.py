"""First integrals from symmetries (Noether), and the constant speeds of nonholonomic models.

**Noether.**  Move the whole system rigidly — a translation along an axis e of R0, or a rotation
about an axis e through O — and write the motion in the coordinates: the generator ξ(q) with

    Σ_i ∂V(P)/∂q̇_i ξ_i = e  (translation)  or  e ∧ OP  (rotation)     for every centre P,
    Σ_i ∂Ω(S)/∂q̇_i ξ_i = 0  (translation)  or  e                      for every body S.

When such a ξ exists and T, U are invariant (δT = Σ ∂T/∂q_i ξ_i + ∂T/∂q̇_i ξ̇_i ≡ 0,
Σ ∂U/∂q_i ξ_i ≡ 0), the non-conservative efforts do no work on it (Σ Q_i(nc) ξ_i ≡ 0) and the
complementary constraints admit it (Σ_i A_ki ξ_i ≡ 0, so Σ λ_k A_k·ξ = 0), the Lagrange
equations give d/dt(Σ_i p_i ξ_i) = 0 (E. Noether, 1918; Arnold, *Mathematical Methods of
Classical Mechanics*, §20): J = Σ p_i ξ_i = P·e (the momentum) or σ_O·e (the angular momentum
about the axis).  A free rigid body about a fixed point keeps all three components of σ_O, not
only the one a cyclic coordinate gives.

**Nonholonomic speeds.**  With the velocity rows solved for the dependent speeds, q̇ = C(q) u,
the reduced equations (Maggi, the seed's principle of virtual power with q* = C u*)
Cᵀ(M q̈ − F) = 0 give u̇ = M_r⁻¹ Cᵀ(F − M Ċ u), M_r = Cᵀ M C.  An independent speed whose
u̇_j vanishes identically is constant: the upright rolling coin keeps ψ̇ and φ̇.

"≡ 0" is the randomized identity test of `_identity`.  Only integrals that are new — not a
combination with constant coefficients of those already found (K of the top is σ_O·z0) — are
kept.
"""

from __future__ import annotations

import random
from collections.abc import Sequence

import numpy as np
import symengine as se
from symengine.lib.symengine_wrapper import sympy2symengine

from .._identity import are_zero
from ..dynamics import EquationsOfMotion
from ..model.spec import GALILEAN_FRAME
from ._linear_algebra import choose

__all__ = ["MAX_COORDINATES", "nonholonomic_integrals", "symmetry_integrals"]

#: Symmetries are sought up to this many coordinates (the invariance tests differentiate T).
MAX_COORDINATES = 12

_ZERO = se.Integer(0)
_AXES = ("x", "y", "z")


def _cross(e: int, v: Sequence[se.Basic]) -> list[se.Basic]:
    """e_k ∧ v in R0 components."""
    x, y, z = v
    return [[_ZERO, -z, y], [z, _ZERO, -x], [-y, x, _ZERO]][e]


def _numbers(symbols: set, seed: int) -> dict:
    rng = random.Random(seed)
    return {s: rng.uniform(0.3, 1.7) for s in sorted(symbols, key=str)}


#: Longest entry (characters of its text) that `_tidy` simplifies: SymPy's cancel grows fast with
#: the size (a bicycle's entries would take minutes), and the removable singularities it is there
#: for come from short entries (Cardan angles' sin β / sin β).
TIDY_MAX_CHARS = 400


def _tidy(e: se.Basic) -> se.Basic:
    """cancel, trigsimp, cancel (SymPy): the generator's entries are short once simplified."""
    if not e.free_symbols or len(str(e)) > TIDY_MAX_CHARS:
        return e
    import sympy  # late: SymPy takes most of a second to load, and only this needs it

    try:
        return sympy2symengine(sympy.cancel(sympy.trigsimp(sympy.cancel(e._sympy_()))))
    except (TypeError, ValueError, RuntimeError, NotImplementedError, AttributeError):  # pragma: no cover
        return e


def _rows(eom: EquationsOfMotion, kind: str, axis: int) -> tuple[list[list[se.Basic]], list[se.Basic]]:
    """The linear system R ξ = r that the generator of the rigid motion must satisfy (module docstring)."""
    kin, model = eom.kinematics, eom.model
    express = kin.frames.express
    n = kin.n
    rows: list[list[se.Basic]] = []
    rhs: list[se.Basic] = []
    e = [se.Integer(int(k == axis)) for k in range(3)]
    centres = [b.name for b in model.bodies] + [p.name for p in model.particles]
    for name in centres:
        partials = [express(v, GALILEAN_FRAME) for v in kin.partial_velocities(name)]
        target = e if kind == "translation" else _cross(axis, express(kin.position(name), GALILEAN_FRAME))
        for k in range(3):
            rows.append([partials[i][k] for i in range(n)])
            rhs.append(target[k])
    for body in model.bodies:
        partials = [express(w, GALILEAN_FRAME) for w in kin.partial_omegas(body.frame)]
        for k in range(3):
            rows.append([partials[i][k] for i in range(n)])
            rhs.append(_ZERO if kind == "translation" else e[k])
    return rows, rhs


class _NumericGenerator:
    """ξ(q) by least squares on R(q) ξ = r(q), with numbers for the parameters: whether a generator
    exists, and whether the constraints admit it, are settled numerically before any symbolic solve
    (a symbolic LU with an unlucky pivot order swells: the bicycle's coordinates listed backwards)."""

    def __init__(self, eom: EquationsOfMotion, rows: list[list[se.Basic]], rhs: list[se.Basic]) -> None:
        kin = eom.kinematics
        self.q = list(kin.q)
        flat = [x for r in rows for x in r] + list(rhs)
        symbols = set().union(*(x.free_symbols for x in flat)) - set(self.q)
        self.parameters = _numbers(symbols, 11)
        self.shape = (len(rows), kin.n)
        self.fn = se.Lambdify(self.q, [x.subs(self.parameters) for x in flat], cse=True)

    def __call__(self, q: np.ndarray) -> tuple[np.ndarray, float]:
        """(ξ at q, the relative residual of R ξ = r there)."""
        with np.errstate(all="ignore"):
            values = np.asarray(self.fn(np.asarray(q, dtype=float)), dtype=float).ravel()
        if not np.all(np.isfinite(values)):  # outside the coordinates' domain (log ψ at ψ < 0)
            return np.full(self.shape[1], np.nan), float("inf")
        m, n = self.shape
        R, r = values[: m * n].reshape(m, n), values[m * n:]
        xi, *_ = np.linalg.lstsq(R, r, rcond=None)
        scale = max(1.0, float(np.abs(R).max(initial=0.0)), float(np.abs(r).max(initial=0.0)))
        return xi, float(np.abs(R @ xi - r).max(initial=0.0)) / scale

    def exists(self) -> bool:
        """R ξ = r solvable at two random states where the rows are defined (up to eight tried)."""
        rng = np.random.default_rng(13)
        solved = 0
        for _ in range(8):
            residual = self(rng.uniform(-1.0, 1.0, len(self.q)))[1]
            if residual == float("inf"):
                continue
            if residual >= 1e-9:
                return False
            solved += 1
            if solved == 2:
                return True
        return False


def _generator(eom: EquationsOfMotion, kind: str, axis: int) -> tuple[list[se.Basic], _NumericGenerator] | None:
    """ξ(q) of the rigid translation or rotation (and its numeric twin), or None when the
    coordinates cannot follow it or the complementary constraints do not admit it."""
    kin = eom.kinematics
    n = kin.n
    rows, rhs = _rows(eom, kind, axis)
    if not rows:
        return None
    try:
        numeric = _NumericGenerator(eom, rows, rhs)
    except RuntimeError:  # SymEngine cannot compile it (the derivative of abs): no generator shown
        return None
    if not numeric.exists() or not _admissible(eom, numeric):
        return None
    symbols = set().union(*(x.free_symbols for r in rows for x in r)) | set().union(*(x.free_symbols for x in rhs))
    numbers = _numbers(symbols, 11)
    Jn = np.array([[float(complex(x.subs(numbers)).real) for x in r] for r in rows])
    picked_rows = choose(Jn.T, n, range(len(rows)))  # n independent rows fix ξ
    if len(picked_rows) < n:
        return None
    A = se.DenseMatrix([rows[r] for r in picked_rows])
    b = se.DenseMatrix([[rhs[r]] for r in picked_rows])
    try:
        xi = A.LUsolve(b)
    except (RuntimeError, ValueError, ZeroDivisionError):  # pragma: no cover - a singular symbolic pivot
        return None
    xi_list = [xi[i, 0] for i in range(n)]
    residuals = [se.Add(*[r[i] * xi_list[i] for i in range(n)]) - t for r, t in zip(rows, rhs, strict=True)]
    return (xi_list, numeric) if all(are_zero(residuals)) else None


def _admissible(eom: EquationsOfMotion, xi: _NumericGenerator) -> bool:
    """Σ_i A_ki ξ_i = 0 for every complementary row, where the holonomic rows hold (a pivot kept at O
    admits the rotations about O: e ∧ OQ vanishes with OQ).  Tested at random states, or at points
    of the constraint manifold found by least squares from random starts, with ξ found there."""
    rows = eom.constraints
    if not rows:
        return True
    from scipy import optimize
    kin = eom.kinematics
    q = list(kin.q)
    exprs = [c for row in rows for c in row.coefficients]
    holonomic = [row.expression for row in rows if row.kind == "holonomic"]
    symbols = set().union(*(e.free_symbols for e in exprs + holonomic)) - set(q) - set(kin.qd)
    parameters = {**_numbers(symbols, 7), **{s: v for s, v in xi.parameters.items() if s in symbols}}
    A = se.Lambdify(q, [e.subs(parameters) for e in exprs], cse=True)
    f = se.Lambdify(q, [e.subs(parameters) for e in holonomic], cse=True) if holonomic else None
    rng = np.random.default_rng(3)
    for _ in range(3):
        point = rng.uniform(-1.0, 1.0, len(q))
        if f is not None:
            try:
                sol = optimize.least_squares(lambda x: np.asarray(f(x), dtype=float).ravel(), point,
                                             xtol=1e-15, ftol=1e-15, gtol=1e-15)
            except ValueError:  # residuals not finite at the start: outside the coordinates' domain
                return False
            if np.abs(sol.fun).max(initial=0.0) > 1e-10:
                return False  # no point of the manifold found: do not claim the integral
            point = sol.x
        x, residual = xi(point)
        if residual > 1e-9:  # not solvable there, or outside the coordinates' domain: do not claim it
            return False
        value = np.asarray(A(point), dtype=float).reshape(len(rows), len(q)) @ x
        if np.abs(value).max(initial=0.0) > 1e-8 * max(1.0, float(np.abs(x).max(initial=0.0))):
            return False
    return True


def _independent(eom: EquationsOfMotion, found: Sequence[se.Basic], candidate: se.Basic) -> bool:
    """``candidate`` is not a constant-coefficient combination of ``found`` (a rank test at random states)."""
    exprs = list(found) + [candidate]
    symbols = set().union(*(x.free_symbols for x in exprs))
    kin = eom.kinematics
    state = set(kin.q) | set(kin.qd) | {kin.t}
    parameters = _numbers(symbols - state, 99)  # the same parameters at every state: constant coefficients
    values = []
    for seed in range(len(exprs) + 4):
        numbers = {**parameters, **_numbers(symbols & state, 100 + seed)}
        values.append([float(complex(x.subs(numbers)).real) for x in exprs])
    V = np.array(values)
    if not np.isfinite(V).all():  # overflow at a random state: no rank to compare, not shown independent
        return False
    scale = max(1.0, float(np.abs(V).max()))
    rank_before = np.linalg.matrix_rank(V[:, :-1], tol=1e-9 * scale) if found else 0
    return np.linalg.matrix_rank(V, tol=1e-9 * scale) > rank_before


def symmetry_integrals(eom: EquationsOfMotion, known: Sequence[se.Basic] = ()) -> list[tuple[str, se.Basic, str]]:
    """(name, J, reason) for each rigid translation or rotation of the whole system that leaves L,
    the non-conservative efforts and the constraints invariant, J new with respect to ``known``."""
    model = eom.model
    if eom.kinematics.n > MAX_COORDINATES or (model.reference is not None and not model.reference.is_galilean_frame):
        return []
    kin = eom.kinematics
    declared = next((f.axes for f in model.frames if f.name == GALILEAN_FRAME and getattr(f, "axes", None)), None)
    axes_names = tuple(declared) if declared else ("x0", "y0", "z0")
    T, U = eom.T, eom.U
    p = [eq.dT_dqd for eq in eom.equations]
    found = list(known)
    out = []
    for kind in ("translation", "rotation"):
        for axis in range(3):
            found_xi = _generator(eom, kind, axis)
            if found_xi is None or all(are_zero(found_xi[0])):
                continue
            xi = found_xi[0]
            xi_dot = [se.Add(*[x.diff(q) * qd for q, qd in zip(kin.q, kin.qd, strict=True)]) for x in xi]
            dT = se.Add(*[T.diff(q) * x for q, x in zip(kin.q, xi, strict=True)], *[T.diff(qd) * x for qd, x in zip(kin.qd, xi_dot, strict=True)])
            dU = se.Add(*[U.diff(q) * x for q, x in zip(kin.q, xi, strict=True)])
            work = se.Add(*[Q * x for Q, x in zip(eom.Q_nc, xi, strict=True)])
            if not all(are_zero([dT, dU, work])):
                continue
            # The LU leaves removable singularities (sin β/sin β in Cardan angles): simplified once the
            # symmetry holds (SymPy's cancel is slow; most candidates fail the tests above).
            xi = [_tidy(x) for x in xi]
            J = se.Add(*[pi * x for pi, x in zip(p, xi, strict=True)])
            if are_zero([J])[0] or not _independent(eom, found, J):
                continue
            found.append(J)
            axis_name = axes_names[axis]
            if kind == "translation":
                name = f"P_{axis_name}"
                why = (f"Noether: L is invariant under a translation along {axis_name} and no other effort works "
                       f"on it, so the momentum P(Σ/R0)·{axis_name} = Σ p_i ξ_i is constant")
            else:
                name = f"sigma_O_{axis_name}"
                why = (f"Noether: L is invariant under a rotation about O{axis_name} and no other effort works "
                       f"on it, so the angular momentum σ_O(Σ/R0)·{axis_name} = Σ p_i ξ_i is constant")
            out.append((name, J, why))
    return out


def nonholonomic_integrals(eom: EquationsOfMotion, known: Sequence[se.Basic] = ()) -> list[tuple[str, se.Basic, str]]:
    """(name, u_j, reason) for each independent speed that the reduced equations keep constant."""
    rows = eom.constraints
    kin = eom.kinematics
    n, m = kin.n, len(rows)
    if not m or n > 8 or any(r.kind == "holonomic" for r in rows):
        return []
    A = se.DenseMatrix([list(r.coefficients) for r in rows])
    b = [r.b for r in rows]
    if not all(are_zero(b)):
        return []  # rheonomic rows: q̇ = C u + d, left aside
    symbols = set().union(*(x.free_symbols for x in A))
    try:
        An = np.array(A.subs(_numbers(symbols | set(kin.q), 5)).tolist(), dtype=float)
    except (RuntimeError, TypeError, ValueError):  # not real at the sample point (asin(φ) at φ > 1): claim nothing
        return []
    appears = set().union(*(e.free_symbols for row in eom.M for e in row), *(f.free_symbols for f in eom.F))
    order = sorted(range(n), key=lambda i: (kin.q[i] in appears, i))  # dependent: coordinates absent first
    dep = choose(An, m, order)
    if len(dep) < m:
        return []
    ind = [i for i in range(n) if i not in dep]
    Ad = se.DenseMatrix([[A[k, i] for i in dep] for k in range(m)])
    Ai = se.DenseMatrix([[A[k, i] for i in ind] for k in range(m)])
    try:
        solved = Ad.LUsolve(-Ai)
    except (RuntimeError, ValueError, ZeroDivisionError):  # pragma: no cover
        return []
    C = se.zeros(n, len(ind))
    for c, i in enumerate(ind):
        C[i, c] = 1
    for r, i in enumerate(dep):
        for c in range(len(ind)):
            C[i, c] = solved[r, c]
    u = [kin.qd[i] for i in ind]
    qd_of_u = [se.Add(*[C[i, c] * u[c] for c in range(len(ind))]) for i in range(n)]
    on_manifold = dict(zip(kin.qd, qd_of_u, strict=True))
    Cu_dot = [se.Add(*[x.diff(q) * v for q, v in zip(kin.q, qd_of_u, strict=True)]) for x in qd_of_u]
    # u̇ = M_r⁻¹ Cᵀ(F − M Ċ u) is evaluated numerically at random states (the randomized identity test
    # of `_identity`, without forming M_r⁻¹ symbolically: that swelled to seconds on the stuck block).
    flat = [e for r in eom.M for e in r] + [f.subs(on_manifold) for f in eom.F] + list(C) + Cu_dot
    state = list(kin.q) + u + [kin.t]
    symbols = set().union(*(e.free_symbols for e in flat)) - set(state)
    rng = np.random.default_rng(17)
    k = len(ind)
    zero = [True] * k
    for seed in range(3):
        parameters = _numbers(symbols, 50 + seed)
        fn = se.Lambdify(state, [e.subs(parameters) for e in flat], cse=True)
        with np.errstate(all="ignore"):
            values = np.asarray(fn(rng.uniform(0.3, 1.2, len(state))), dtype=float).ravel()
        if not np.all(np.isfinite(values)):
            return []  # outside the domain of the equations: claim nothing
        Mn = values[: n * n].reshape(n, n)
        Fn = values[n * n: n * n + n]
        Cn = values[n * n + n: n * n + n + n * k].reshape(n, k)
        Cun = values[n * n + n + n * k:]
        try:
            u_dot = np.linalg.solve(Cn.T @ Mn @ Cn, Cn.T @ (Fn - Mn @ Cun))
        except np.linalg.LinAlgError:  # pragma: no cover - a singular reduced mass matrix
            return []
        scale = max(1.0, float(np.abs(Fn).max(initial=0.0)), float(np.abs(Mn @ Cun).max(initial=0.0)))
        zero = [z and abs(x) <= 1e-9 * scale for z, x in zip(zero, u_dot, strict=True)]
    out = []
    found = list(known)
    for j, i in enumerate(ind):
        if not zero[j] or not _independent(eom, found, u[j]):
            continue
        found.append(u[j])
        name = f"{kin.model.coordinates[i].name}_dot"
        others = ", ".join(str(kin.qd[d]) for d in dep)
        out.append((name, u[j],
                    f"the reduced equations (dependent speeds {others} eliminated by the constraint rows) give "
                    f"d/dt({name}) = 0: {name} is constant"))
    return out
