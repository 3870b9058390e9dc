"""The static system of a model: F(q, 0) + Aᵀλ = 0, f(q) = 0, b(q) = 0, as expressions and as functions.

What `equilibria` solves (in closed form, by `_equilibria_closed_form`; numerically, by
`_equilibria_search`): the generalized forces at rest, with the multipliers λ of the
complementary rows and, per exact Coulomb contact that sticks at rest, its friction force T as
the multiplier of the sticking row (seed, Q_i = T ∂w/∂q̇_i).  A term in t that vanishes at the
parameters' values (F0 cos ω t with F0 = 0) is dropped; any other t is refused.  Numerically,
λ is eliminated by projecting F on the complement of the range of Aᵀ.
"""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np
import symengine as se
import sympy
from symengine.lib.symengine_wrapper import sympy2symengine

from ..dynamics import EquationsOfMotion, sliding_direction
from ..errors import AnalysisError
from ..model import CoulombFriction
from ._equilibria_search import angles as _angles

__all__ = ["EquilibriumError", "StaticSystem", "configuration", "lambdify", "to_symengine"]


class EquilibriumError(AnalysisError):
    """Equilibria cannot be sought: a model that depends on t, an unknown parameter, a missing range.

    Parameters
    ----------
    message : str
        What was wrong, a full sentence naming the culprit in backticks.
    fix : str, optional
        How to fix it, printed after the message.
    """




def lambdify(q: list[se.Basic], exprs: list[se.Basic]):
    """`symengine.Lambdify` of ``exprs`` in ``q``, also when ``q`` is empty (every coordinate fixed
    or free, e.g. a block held on an incline): SymEngine refuses zero arguments, so a dummy one."""
    if q:
        return se.Lambdify(q, exprs)
    f = se.Lambdify([se.Symbol("_unused_")], exprs)
    return lambda x: f(np.zeros(1))


class StaticSystem:
    """F(q, 0) + Aᵀλ = 0, f(q) = 0, b(q) = 0, with the checks that it is autonomous."""

    def __init__(self, eom: EquationsOfMotion, numbers: Mapping[se.Basic, float] | None = None) -> None:
        t = eom.t
        numbers = dict(numbers or {})
        rest = {qd: 0 for qd in eom.qd}
        self.eom = eom
        self.q = list(eom.q)
        self.names = [str(s) for s in self.q]
        F = [to_symengine(f) for f in eom.F]
        sticking = self._sticking_contacts(eom)
        for load in eom.loads:
            if load.name in sticking:  # its sliding law is undefined at rest: replaced by T (below)
                F = [se.expand(f - q) for f, q in zip(F, load.Q, strict=True)]
        F = [_autonomous(f.subs(rest), t, f"the generalized force on `{name}` at rest", numbers)
             for name, f in zip(self.names, F, strict=True)]
        for row in eom.M:
            for m in row:
                _autonomous(to_symengine(m), t, "the mass matrix M", numbers)
        self.A = [[to_symengine(a) for a in r.coefficients] for r in eom.constraints]
        self.lam = [r.multiplier for r in eom.constraints]
        extra = []
        for r in eom.constraints:
            e = _autonomous(to_symengine(r.expression if r.kind == "holonomic" else r.b).subs(rest), t,
                            f"constraint row `{r.name}`", numbers)
            for a in r.coefficients:
                _autonomous(to_symengine(a), t, f"constraint row `{r.name}`", numbers)
            if e != 0:
                extra.append(e)
        #: Per exact contact: (name, multiplier T, f_s, N); T is the friction force along e.
        self.sticking: list[tuple[str, se.Symbol, se.Basic, se.Basic]] = []
        for name, (speed, fs, N) in sticking.items():
            # Sticking: w = a·q̇ + b = 0, a nonholonomic row whose multiplier is T (seed, Q_i = T ∂w/∂q̇_i).
            self.A.append([to_symengine(speed.diff(qd)) for qd in eom.qd])
            T = se.Symbol(f"T_{name}")
            self.lam.append(T)
            self.sticking.append((name, T, fs, N))

        self.F = F
        self.extra = extra
        #: F + Aᵀλ per coordinate, then the holonomic rows and the rate-free parts b.
        self.equations = [f + sum((lam * row[i] for lam, row in zip(self.lam, self.A, strict=True)), se.Integer(0))
                          for i, f in enumerate(F)] + extra
        used: set[se.Basic] = set()
        for e in self.equations:
            used |= e.free_symbols
        self.free = tuple(n for n, s in zip(self.names, self.q, strict=True) if s not in used)
        self.active = [n for n in self.names if n not in self.free]

    @staticmethod
    def _sticking_contacts(eom: EquationsOfMotion) -> dict[str, tuple[se.Basic, se.Basic, se.Basic]]:
        """Exact Coulomb contacts that can stick at rest: name → (sliding speed w = v_s·e, f_s, N).

        A contact whose surface moves (a belt) still slides when the system is at rest, with a
        friction force that is then well defined: it keeps its sliding law.
        """
        out = {}
        rest = {qd: 0 for qd in eom.qd}
        for load in eom.model.loads:
            if isinstance(load, CoulombFriction) and load.exact:
                if se.expand(to_symengine(sliding_direction(eom.kinematics, load).speed).subs(rest)) != 0:
                    continue
                fs = load.static_coefficient if load.static_coefficient is not None else load.coefficient
                out[load.name] = (sliding_direction(eom.kinematics, load).speed, to_symengine(fs), to_symengine(load.normal_force))
        return out

    def multipliers_at(self, point: Mapping[str, float], numbers: Mapping[se.Basic, float]) -> np.ndarray:
        """λ (then the friction forces T) at a rest point, by least squares on F + Aᵀλ = 0."""
        at = {**numbers, **{s: point.get(n, 0.0) for n, s in zip(self.names, self.q, strict=True)}}
        f = np.array([float(e.subs(at)) for e in self.F])
        At = np.array([[float(a.subs(at)) for a in row] for row in self.A]).T
        lam, *_ = np.linalg.lstsq(At, -f, rcond=None)
        return lam

    def holds_by_friction(self, point: Mapping[str, float], numbers: Mapping[se.Basic, float]) -> bool:
        """|T| ≤ f_s N at every sticking contact (with a relative margin for rounding)."""
        lam = self.multipliers_at(point, numbers)
        at = {**numbers, **{s: point.get(n, 0.0) for n, s in zip(self.names, self.q, strict=True)}}
        k0 = len(self.lam) - len(self.sticking)
        for (_, _, fs, N), T in zip(self.sticking, lam[k0:], strict=True):
            b = abs(float((fs * N).subs(at)))
            if abs(T) > b * (1 + 1e-12) + 1e-300:
                return False
        return True

    def angles(self, numbers: Mapping[se.Basic, float]) -> set[str]:
        """Coordinates that enter the equations (M, F at any rates, the rows) only through 2π-periodic
        sin, cos, tan (`_equilibria_search.angles`): only those wrap."""
        eom = self.eom
        everything = [to_symengine(m) for row in eom.M for m in row] + [to_symengine(f) for f in eom.F] + self.equations
        for r in eom.constraints:
            everything += [to_symengine(a) for a in r.coefficients] + [to_symengine(r.b)]
        return _angles(everything, self.q, self.names, numbers, self.free)

    def residual_function(self, numbers: Mapping[se.Basic, float]):
        """r(q_active) with λ eliminated: (I − Aᵀ(Aᵀ)⁺) F, then the holonomic and b rows; q_active one point
        (shape (d,)) or a batch of points (shape (N, d), for the search's Levenberg–Marquardt)."""
        q = [s for n, s in zip(self.names, self.q, strict=True) if n in self.active]
        zero = {se.Symbol(n): 0.0 for n in self.free}
        F = lambdify(q, [f.subs(numbers).subs(zero) for f in self.F])
        A = lambdify(q, [a.subs(numbers).subs(zero) for row in self.A for a in row]) if self.A else None
        X = lambdify(q, [e.subs(numbers).subs(zero) for e in self.extra]) if self.extra else None
        n, m = len(self.names), len(self.A)

        def r(x: np.ndarray) -> np.ndarray:
            xs = np.atleast_2d(np.asarray(x, dtype=float))
            f = np.asarray(F(xs), dtype=float).reshape(len(xs), n)
            if A is not None:
                At = np.swapaxes(np.asarray(A(xs), dtype=float).reshape(len(xs), m, n), 1, 2)
                with np.errstate(all="ignore"):
                    ok = np.all(np.isfinite(At), axis=(1, 2))
                    lam = np.zeros((len(xs), m))
                    if ok.any():
                        lam[ok] = -np.einsum("kij,kj->ki", np.linalg.pinv(At[ok]), f[ok])
                    lam[~ok] = np.nan
                    f = f + np.einsum("kij,kj->ki", At, lam)
            if X is not None:
                f = np.concatenate([f, np.asarray(X(xs), dtype=float).reshape(len(xs), -1)], axis=1)
            return f if np.ndim(x) == 2 else f[0]

        return r

    def size_function(self, numbers: Mapping[se.Basic, float]):
        """s(q_active): per equation of `residual_function`, the sum of the sizes of its terms (F's, then the
        rows'), against which a residual is small."""
        q = [s for n, s in zip(self.names, self.q, strict=True) if n in self.active]
        zero = {se.Symbol(n): 0.0 for n in self.free}
        terms = [se.Add(*[abs(x) for x in se.Add.make_args(se.expand(e.subs(numbers).subs(zero)))])
                 for e in self.F + self.extra]
        fn = lambdify(q, terms)

        def size(x: np.ndarray) -> np.ndarray:
            out = np.abs(np.asarray(fn(np.atleast_2d(np.asarray(x, dtype=float))), dtype=float))
            out = out.reshape(len(np.atleast_2d(x)), -1)
            return out if np.ndim(x) == 2 else out[0]

        return size


def to_symengine(x: object) -> se.Basic:
    """Our SymEngine or SymPy objects (or numbers) as SymEngine, structurally (no text is parsed)."""
    if isinstance(x, se.Basic):
        return x
    if isinstance(x, sympy.Basic):
        return sympy2symengine(x)
    return se.Integer(x) if isinstance(x, int) else se.RealDouble(float(x))  # type: ignore[arg-type]


def _autonomous(e: se.Basic, t: se.Symbol, where: str, numbers: Mapping[se.Basic, float]) -> se.Basic:
    """``e`` without its terms in t that vanish at the parameters' values (F0 cos ω t with F0 = 0), or
    the refusal when t is still there."""
    if t not in e.free_symbols:
        return e
    kept = []
    for term in se.Add.make_args(se.expand(e)):
        if t in term.free_symbols:
            at = se.expand(term.subs(dict(numbers)))
            if at == 0 or (not at.free_symbols and complex(at) == 0):  # 0.0 (a float value) is not == 0
                continue
            if t in at.free_symbols:
                raise EquilibriumError(
                    f"the model depends on t explicitly ({where} contains t), so it has no static equilibrium in "
                    "the sense q̇ = 0 for all t", fix="write the equations in a frame where the motion is steady "
                    "([reference]), give the parameters that switch the time dependence off their value "
                    "(--set F0=0), or study the motion by simulation")
        kept.append(term)
    return se.Add(*kept)



def configuration(system: StaticSystem, numbers: Mapping[se.Basic, float]):
    """q ↦ the positions of every particle and body centre and the axes of every body, in R0's basis."""
    kin = system.eom.kinematics
    model = system.eom.model
    frame = model.frames[0].name if model.frames else "R0"
    parts: list[se.Basic] = []
    for name in [p.name for p in model.particles] + [b.name for b in model.bodies]:
        parts += list(kin.frames.express(kin.position(name), frame))
    for b in model.bodies:
        for axis in ((1, 0, 0), (0, 1, 0), (0, 0, 1)):
            parts += list(kin.frames.convert(tuple(se.Integer(x) for x in axis), b.frame, frame))
    parts = [to_symengine(e).subs(dict(numbers)).subs({kin.t: 0}) for e in parts]
    return lambdify(list(system.q), parts)
