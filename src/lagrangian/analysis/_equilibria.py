"""Static equilibria of an autonomous system: q̇ = 0, q̈ = 0, so F(q, 0) + Aᵀλ = 0.

With M(q) q̈ = F(q, q̇) + Aᵀ(q) λ (seed, section II; the multipliers of the complementary
constraints, step 7), a configuration q* is a position of equilibrium when the system
placed there at rest stays there: q̈ = 0 at q̇ = 0, i.e.

    F(q*, 0) + Aᵀ(q*) λ = 0,    f(q*) = 0 (holonomic rows),    b(q*) = 0 (rate-free part
                                                                 of the velocity rows).

λ is eliminated numerically by projecting F on the complement of the range of Aᵀ.

Closed form first (`_equilibria_closed_form`: SymPy on the factors of each equation, with
each branch's condition of existence, R Ω² > g for the bead's tilted positions).  Then a
numeric multi-start search (``scipy.optimize.least_squares`` from a grid over the ranges)
finds all roots when every parameter has a value; it fills in what the closed form missed
(SymPy's solvers are not complete: ``solve`` alone loses θ = π of the bead) or replaces it
when SymPy fails.  Roots are deduplicated, angles modulo 2π.

Dry friction (an exact Coulomb contact, ``regularization = 0``): at rest the contact sticks,
so its law T = −f N v_s/|v_s| (undefined at v_s = 0) is replaced by the sticking constraint
w = v_s·e = 0 with its own multiplier T, the friction force along e; a rest is an equilibrium
where the force it needs stays in the friction cone, |T| ≤ f_s N (Coulomb's law of
adherence).  For a block on an incline of angle α: T = −m g sin α, so every x is an
equilibrium when |sin α|/cos α = tan α ≤ f_s.

An *angle* is a coordinate in which the static equations are 2π-periodic (checked
numerically); it ranges over (−π, π] — π rather than −π, as the course writes the upper
position.  Other coordinates need a range for the numeric search (``ranges={"x": (a, b)}``).
See docs/equilibria.md.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field, replace

import numpy as np
import symengine as se
import sympy
from symengine.lib.symengine_wrapper import sympy2symengine

from ..dynamics import EquationsOfMotion
from ..dynamics._friction import sliding_direction
from ..model import CoulombFriction
from ._effective_potential import AnalysisError
from ._equilibria_closed_form import SOLVE_TIMEOUT, closed_form, principal
from ._equilibria_closed_form import condition as branch_condition
from ._equilibria_search import STARTS, Region, Search, near_curve, region_of
from ._equilibria_search import angles as _angles
from ._equilibria_search import same as _same
from ._equilibria_search import search as _search
from ._equilibria_search import wrap as _wrap

__all__ = [
    "SOLVE_TIMEOUT",
    "STARTS",
    "Equilibria",
    "Equilibrium",
    "EquilibriumError",
    "Region",
    "Search",
    "equilibria",
]


class EquilibriumError(AnalysisError):
    """Equilibria cannot be sought: a model that depends on t, an unknown parameter, a missing range."""


@dataclass(frozen=True)
class Equilibrium:
    """One position of equilibrium q*.

    Attributes
    ----------
    values : coordinate name → q*_i: a SymEngine expression in the parameters (closed form)
        or a float (numeric); a coordinate in ``free`` maps to its own symbol (any value).
    closed_form : whether ``values`` were found by SymPy.
    condition, condition_text : the condition of existence (a SymPy relational or And of them,
        in the parameters) and its text, or None when the equilibrium always exists.
    exists : the condition at the parameter values (None when some value is missing).
    numeric : q* at the parameter values (angles in (−π, π]), or None without all values.
    residual : max |F(q*, 0) + Aᵀλ|, |f(q*)| at ``numeric`` (None without values).
    free : coordinates along which every value is an equilibrium: absent from the static equations, left
        free by SymPy, or found so by the numeric search (the bead on a turning parabola at Ω² = 2 g a:
        "r any").
    family : the dimension of a curved family of equilibria through ``numeric`` (0: none; the static
        equations' Jacobian is singular there and the rests form a curve, which this one stands for).
    aliases : other values of the coordinates that put every body and particle in the same place
        (the elastic pendulum's r = −0.63, θ = π is its r = 0.63, θ = 0): listed here, not as rests.
    """

    values: Mapping[str, se.Basic | float]
    closed_form: bool
    condition: sympy.Basic | None = None
    condition_text: str | None = None
    exists: bool | None = True
    numeric: Mapping[str, float] | None = None
    residual: float | None = None
    free: tuple[str, ...] = field(default=())
    family: int = 0
    aliases: tuple[Mapping[str, float], ...] = ()


class Equilibria(tuple):  # type: ignore[type-arg]
    """The equilibria found (a tuple of `Equilibrium`), with ``search``: what was searched (`Search`)."""

    search: Search

    def __new__(cls, items: Sequence[Equilibrium], search: Search) -> Equilibria:  # noqa: PYI034
        out = super().__new__(cls, items)
        out.search = search
        return out


def equilibria(eom: EquationsOfMotion, parameters: Mapping[str, float] | None = None,
               ranges: Mapping[str, tuple[float, float]] | None = None, *,
               all_branches: bool = False, numeric: bool = True) -> Equilibria:
    """Every static equilibrium of ``eom`` (q̇ = 0, q̈ = 0), closed form when possible.

    Parameters
    ----------
    eom : `lagrangian.derive`'s result, for an autonomous model.
    parameters : values overriding the model's (name → number).
    ranges : coordinate name → (a, b), where the numeric search looks (and where closed-form
        roots are kept); angles default to (−π, π], other coordinates to their declared ``range``,
        else to starting points over every scale (`lagrangian.analysis._equilibria_search`).
    all_branches : keep closed-form branches whose condition is false at the values.
    numeric : run the numeric search (when every parameter has a value); False: the closed form only.

    Returns
    -------
    Equilibria
        A tuple of `Equilibrium`, whose ``search`` says what was searched: the list holds what was
        found there, and a root beyond the starting points' reach may be missing.

    Raises
    ------
    EquilibriumError
        The model depends on t explicitly (once the parameters have their values), a name in
        ``parameters`` or ``ranges`` is unknown, or the closed form failed and a parameter has no value.
    """
    values = _values(eom, parameters)
    known = all(v is not None for v in values.values())
    numbers = {se.Symbol(k): v for k, v in values.items() if v is not None}
    system = _StaticSystem(eom, numbers)
    ranges = _ranges(eom, ranges)
    angles = system.angles(numbers)
    out: list[Equilibrium] = []
    branches = closed_form(system.equations, system.q, system.active, system.lam, values)
    if branches is not None:
        for sol in branches:
            eq = _from_closed_form(system, sol, branches, numbers, angles, known)
            if eq is not None and system.sticking:
                eq = _within_friction_cone(system, eq, sol, numbers)
            if eq is None or (eq.exists is False and not all_branches):
                continue
            if eq.numeric is not None and not _in_ranges(eq.numeric, ranges, angles):
                continue
            if not any(_duplicate(o, eq, angles) for o in out):
                out.append(eq)
    continuum = any(len(e.free) > len(system.free) for e in out)  # sample points of it are no news
    report = Search(branches is not None, False)
    if known and numeric and not continuum:
        declared = {c.name: c.range for c in eom.model.coordinates}
        regions = [region_of(n, n in angles, ranges.get(n), declared.get(n), numbers) for n in system.active]
        roots, starts = _search(system.active, system.residual_function(numbers), system.size_function(numbers),
                                regions, angles, numbers)
        report = Search(branches is not None, True, tuple(Region(n, kind, bounds, starts) for n, (kind, bounds)
                                                          in zip(system.active, regions)), starts)
        out = _identify(system, _merge(system, out, roots, numbers, angles), numbers, angles)
    elif not known and branches is None:
        missing = sorted(k for k, v in values.items() if v is None)
        raise EquilibriumError(f"no closed form was found, and parameter `{missing[0]}` has no value for a "
                               "numeric search", fix=f"give it one: parameters={{'{missing[0]}': ...}} "
                               f"(CLI: --set {missing[0]}=...)")
    return Equilibria(out, report)


def _configuration(system: _StaticSystem, numbers: Mapping[se.Basic, float]):  # type: ignore[no-untyped-def]
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
    parts = [se.sympify(e).subs(dict(numbers)).subs({kin.t: 0}) for e in parts]
    return _lambdify(list(system.q), parts)


def _identify(system: _StaticSystem, out: list[Equilibrium], numbers: Mapping[se.Basic, float],
              angles: set[str]) -> list[Equilibrium]:
    """Each configuration once: rests whose coordinates put every body in the same place (r and θ against
    −r and θ + π) are one rest, written with lengths ≥ 0 and closed form first; the others become its
    ``aliases``."""
    points = [e for e in out if e.numeric is not None and not e.free]
    if len(points) < 2:
        return out
    try:
        place = _configuration(system, numbers)
    except (RuntimeError, TypeError, ValueError, KeyError, AttributeError):  # pragma: no cover - no kinematics
        return out
    names = system.names
    at = {e_id: np.asarray(place(np.array([e.numeric.get(n, 0.0) for n in names])), dtype=float).ravel()
          for e_id, e in ((id(e), e) for e in points)}
    groups: list[list[Equilibrium]] = []
    for e in points:
        for g in groups:
            a, b = at[id(g[0])], at[id(e)]
            if np.all(np.abs(a - b) <= 1e-9 * (1.0 + np.abs(a))):
                g.append(e)
                break
        else:
            groups.append([e])

    def key(e: Equilibrium) -> tuple:  # type: ignore[type-arg]
        negative = sum(1 for n, v in e.numeric.items() if n not in angles and v < -1e-12)
        return (negative, not e.closed_form, sum(1 for v in e.numeric.values() if v < -1e-12))

    keep: dict[int, Equilibrium] = {}
    for g in groups:
        best = min(g, key=key)
        keep[id(best)] = replace(best, aliases=tuple(dict(x.numeric) for x in g if x is not best))
    return [keep.get(id(e), e) for e in out if id(e) in keep or e.numeric is None or e.free]


def _merge(system: _StaticSystem, out: list[Equilibrium], roots: Sequence, numbers: Mapping[se.Basic, float],
           angles: set[str]) -> list[Equilibrium]:
    """The closed-form equilibria and the numeric roots, each rest once: a numeric family ("r any") takes
    the place of the closed-form points on it; a numeric point already given in closed form is dropped."""
    families = [r for r in roots if r.free]
    kept = []
    curves = {id(r): r for r in roots if r.curve is not None}
    for e in out:
        on_family = e.numeric is not None and not e.free and any(
            _same(f.point, {n: e.numeric[n] for n in f.point}, angles) for f in families)
        if on_family:
            continue
        on_curve = [k for k, r in curves.items() if e.numeric is not None and not e.free
                    and near_curve(r.curve, np.array([e.numeric[n] for n in system.active]))]
        if on_curve:  # a closed-form point of a curved family stands for it, once
            if not any(curves[k].family == -1 for k in on_curve):
                kept.append(replace(e, family=curves[on_curve[0]].family))
            for k in on_curve:
                curves[k] = replace(curves[k], family=-1)  # taken: its numeric point is not listed
            continue
        kept.append(e)
    taken = {k for k, r in curves.items() if r.family == -1}
    roots = [r for r in roots if id(r) not in taken]
    found = [e.numeric for e in kept if e.numeric is not None and e.exists is not False]
    for root in roots:
        point = root.point
        if not root.free and any(_same(f, point, angles) for f in found):
            continue
        full = {**point, **{n: 0.0 for n in root.free}}
        if system.sticking and not system.holds_by_friction(full, numbers):
            continue  # the contacts would need more friction than f_s N: it slides away
        free = tuple(n for n in system.names if n in system.free or n in root.free)
        vals = {n: point[n] if n in point else se.Symbol(n) for n in system.names}
        numeric = point if not root.free else None
        kept.append(Equilibrium(vals, False, numeric=numeric, residual=root.residual, free=free,
                                family=root.family))
        found.append(point)
    return kept


# -- the static system ---------------------------------------------------------------------

def _lambdify(q: list[se.Basic], exprs: list[se.Basic]):  # type: ignore[no-untyped-def]
    """`symengine.Lambdify` of ``exprs`` in ``q``, also when ``q`` is empty (every coordinate fixed
    or free, e.g. a block held on an incline): SymEngine refuses zero arguments, so a dummy one."""
    if q:
        return se.Lambdify(q, exprs)
    f = se.Lambdify([se.Symbol("_unused_")], exprs)
    return lambda x: f(np.zeros(1))


class _StaticSystem:
    """F(q, 0) + Aᵀλ = 0, f(q) = 0, b(q) = 0, with the checks that it is autonomous."""

    def __init__(self, eom: EquationsOfMotion, numbers: Mapping[se.Basic, float] | None = None) -> None:
        t = eom.t
        numbers = dict(numbers or {})
        rest = {qd: 0 for qd in eom.qd}
        self.eom = eom
        self.q = list(eom.q)
        self.names = [str(s) for s in self.q]
        F = [_se(f) for f in eom.F]
        sticking = self._sticking_contacts(eom)
        for load in eom.loads:
            if load.name in sticking:  # its sliding law is undefined at rest: replaced by T (below)
                F = [se.expand(f - q) for f, q in zip(F, load.Q)]
        F = [_autonomous(f.subs(rest), t, f"the generalized force on `{name}` at rest", numbers)
             for name, f in zip(self.names, F)]
        for row in eom.M:
            for m in row:
                _autonomous(_se(m), t, "the mass matrix M", numbers)
        self.A = [[_se(a) for a in r.coefficients] for r in eom.constraints]
        self.lam = [r.multiplier for r in eom.constraints]
        extra = []
        for r in eom.constraints:
            e = _autonomous(_se(r.expression if r.kind == "holonomic" else r.b).subs(rest), t,
                            f"constraint row `{r.name}`", numbers)
            for a in r.coefficients:
                _autonomous(_se(a), t, f"constraint row `{r.name}`", numbers)
            if e != 0:
                extra.append(e)
        #: Per exact contact: (name, multiplier T, f_s, N); T is the friction force along e.
        self.sticking: list[tuple[str, se.Symbol, se.Basic, se.Basic]] = []
        for name, (speed, fs, N) in sticking.items():
            # Sticking: w = a·q̇ + b = 0, a nonholonomic row whose multiplier is T (seed, Q_i = T ∂w/∂q̇_i).
            self.A.append([_se(speed.diff(qd)) for qd in eom.qd])
            T = se.Symbol(f"T_{name}")
            self.lam.append(T)
            self.sticking.append((name, T, fs, N))

        self.F = F
        self.extra = extra
        #: F + Aᵀλ per coordinate, then the holonomic rows and the rate-free parts b.
        self.equations = [f + sum((lam * row[i] for lam, row in zip(self.lam, self.A)), se.Integer(0))
                          for i, f in enumerate(F)] + extra
        used: set[se.Basic] = set()
        for e in self.equations:
            used |= e.free_symbols
        self.free = tuple(n for n, s in zip(self.names, self.q) if s not in used)
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
                if se.expand(_se(sliding_direction(eom.kinematics, load).speed).subs(rest)) != 0:
                    continue
                fs = load.static_coefficient if load.static_coefficient is not None else load.coefficient
                out[load.name] = (sliding_direction(eom.kinematics, load).speed, _se(fs), _se(load.normal_force))
        return out

    def multipliers_at(self, point: Mapping[str, float], numbers: Mapping[se.Basic, float]) -> np.ndarray:
        """λ (then the friction forces T) at a rest point, by least squares on F + Aᵀλ = 0."""
        at = {**numbers, **{s: point.get(n, 0.0) for n, s in zip(self.names, self.q)}}
        f = np.array([float(e.subs(at)) for e in self.F])
        At = np.array([[float(a.subs(at)) for a in row] for row in self.A]).T
        lam, *_ = np.linalg.lstsq(At, -f, rcond=None)
        return lam

    def holds_by_friction(self, point: Mapping[str, float], numbers: Mapping[se.Basic, float]) -> bool:
        """|T| ≤ f_s N at every sticking contact (with a relative margin for rounding)."""
        lam = self.multipliers_at(point, numbers)
        at = {**numbers, **{s: point.get(n, 0.0) for n, s in zip(self.names, self.q)}}
        k0 = len(self.lam) - len(self.sticking)
        for (_, _, fs, N), T in zip(self.sticking, lam[k0:]):
            b = abs(float((fs * N).subs(at)))
            if abs(T) > b * (1 + 1e-12) + 1e-300:
                return False
        return True

    def angles(self, numbers: Mapping[se.Basic, float]) -> set[str]:
        """Coordinates that enter the equations (M, F at any rates, the rows) only through 2π-periodic
        sin, cos, tan (`_equilibria_search.angles`): only those wrap."""
        eom = self.eom
        everything = [_se(m) for row in eom.M for m in row] + [_se(f) for f in eom.F] + self.equations
        for r in eom.constraints:
            everything += [_se(a) for a in r.coefficients] + [_se(r.b)]
        return _angles(everything, self.q, self.names, numbers, self.free)

    def residual_function(self, numbers: Mapping[se.Basic, float]):  # type: ignore[no-untyped-def]
        """r(q_active) with λ eliminated: (I − Aᵀ(Aᵀ)⁺) F, then the holonomic and b rows; q_active one point
        (shape (d,)) or a batch of points (shape (N, d), for the search's Levenberg–Marquardt)."""
        q = [s for n, s in zip(self.names, self.q) if n in self.active]
        zero = {se.Symbol(n): 0.0 for n in self.free}
        F = _lambdify(q, [f.subs(numbers).subs(zero) for f in self.F])
        A = _lambdify(q, [a.subs(numbers).subs(zero) for row in self.A for a in row]) if self.A else None
        X = _lambdify(q, [e.subs(numbers).subs(zero) for e in self.extra]) if self.extra else None
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

    def size_function(self, numbers: Mapping[se.Basic, float]):  # type: ignore[no-untyped-def]
        """s(q_active): per equation of `residual_function`, the sum of the sizes of its terms (F's, then the
        rows'), against which a residual is small."""
        q = [s for n, s in zip(self.names, self.q) if n in self.active]
        zero = {se.Symbol(n): 0.0 for n in self.free}
        terms = [se.Add(*[abs(x) for x in se.Add.make_args(se.expand(e.subs(numbers).subs(zero)))])
                 for e in self.F + self.extra]
        fn = _lambdify(q, terms)

        def size(x: np.ndarray) -> np.ndarray:
            out = np.abs(np.asarray(fn(np.atleast_2d(np.asarray(x, dtype=float))), dtype=float))
            out = out.reshape(len(np.atleast_2d(x)), -1)
            return out if np.ndim(x) == 2 else out[0]

        return size


def _se(x: object) -> se.Basic:
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


def _values(eom: EquationsOfMotion, parameters: Mapping[str, float] | None) -> dict[str, float | None]:
    values: dict[str, float | None] = {p.name: p.value for p in eom.model.parameters}
    for k, v in (parameters or {}).items():
        if k not in values:
            raise EquilibriumError(f"`{k}` is not a parameter of the model", fix="parameters: "
                                   + ", ".join(values))
        values[k] = float(v)
    return values


def _ranges(eom: EquationsOfMotion, ranges: Mapping[str, tuple[float, float]] | None) -> dict[str, tuple[float, float]]:
    out = {}
    for k, (a, b) in (ranges or {}).items():
        if k not in eom.coordinates:
            raise EquilibriumError(f"`{k}` in the ranges is not a coordinate", fix="coordinates: "
                                   + ", ".join(eom.coordinates))
        if not (math.isfinite(a) and math.isfinite(b) and a < b):
            raise EquilibriumError(f"the range of `{k}` must be a < b, finite, not {a}:{b}",
                                   fix=f"e.g. {k}=-1:1")
        out[k] = (float(a), float(b))
    return out


def _from_closed_form(system: _StaticSystem, branch: Mapping[str, sympy.Basic], branches: Sequence[Mapping],
                      numbers: Mapping[se.Basic, float], angles: set[str], known: bool) -> Equilibrium | None:
    conds: list[sympy.Basic] = []
    for name, v in branch.items():
        conds += branch_condition(v, branch, branches, name)
    condition = sympy.And(*conds) if conds else sympy.true
    if condition == sympy.false:
        return None
    free = tuple(n for n in system.names if n in system.free or n not in branch)
    branch = {n: principal(v) if n in angles else v for n, v in branch.items()}
    plain = {s: sympy.Symbol(s.name) for v in branch.values() for s in v.free_symbols}
    values: dict[str, se.Basic | float] = {n: _se(v.xreplace(plain)) for n, v in branch.items()}
    exists: bool | None = True
    if condition != sympy.true:
        at = condition.xreplace({s: numbers[se.Symbol(s.name)] for s in condition.free_symbols
                                 if se.Symbol(s.name) in numbers})
        exists = bool(at) if at in (sympy.true, sympy.false) else None
    at_values: dict[str, float] = {}
    for n, v in values.items():
        try:
            x = float(_se(v).subs(numbers))
        except (RuntimeError, TypeError, ValueError):
            continue  # a parameter without value
        if not math.isfinite(x):  # no real value at these parameters (asin of 2, a division by 0)
            exists = False
            continue
        if n in angles:  # into (−π, π], the expression too (−π is written π)
            k = round((_wrap(x) - x) / (2 * math.pi))
            if k:
                x += 2 * k * math.pi
                values[n] = _se(v) + 2 * k * se.pi
        at_values[n] = x
    numeric = residual = None
    if known and exists is not False and len(free) == len(system.free):
        numeric = at_values
        r = system.residual_function(numbers)
        residual = float(np.max(np.abs(r(np.array([numeric[n] for n in system.active]))), initial=0.0))
    for n in free:
        values[n] = se.Symbol(n)
    values = {n: values[n] for n in system.names}
    return Equilibrium(values, True, None if condition == sympy.true else condition,
                       None if condition == sympy.true else sympy.sstr(condition), exists, numeric, residual, free)


def _within_friction_cone(system: _StaticSystem, eq: Equilibrium, branch: Mapping[str, sympy.Basic],
                          numbers: Mapping[se.Basic, float]) -> Equilibrium:
    """Add |T|/N ≤ f_s, Coulomb's condition of adherence, to a closed-form rest with sticking contacts.

    T comes from F + Aᵀλ = 0 solved for the multipliers at the branch (linear in them); when it
    is not unique (redundant rows) the rest is checked numerically only.
    """
    lam = [sympy.Symbol(str(s), real=True) for s in system.lam]
    positive = {sympy.Symbol(str(k)): sympy.Symbol(str(k), positive=True) for k, v in numbers.items() if v > 0}
    plain = {sympy.Symbol(str(s)): s2 for s, s2 in zip(system.lam, lam)}
    at = {sympy.Symbol(n): v for n, v in branch.items()}
    eqs = [e._sympy_().xreplace(plain).xreplace(at).xreplace(positive) for e in system.equations]
    try:
        sols = sympy.solve([e for e in eqs if e != 0], lam, dict=True)
    except (NotImplementedError, ValueError):
        sols = []
    conds: list[sympy.Basic] = []
    k0 = len(system.lam) - len(system.sticking)
    for (_, T, fs, N), sym in zip(system.sticking, lam[k0:]):
        value = sols[0].get(sym) if len(sols) == 1 else None
        if value is None or any(s in lam for s in value.free_symbols):
            conds = []
            break
        # Coulomb's adherence |T| ≤ f_s N, written as a teacher does: |T|/N ≤ f_s (tan α ≤ f_s).
        ratio = sympy.simplify(sympy.Abs(value) / sympy.Abs(N._sympy_().xreplace(positive)))
        conds.append(sympy.Le(ratio, fs._sympy_().xreplace(positive)))
    if not conds:
        if eq.numeric is not None and not system.holds_by_friction(eq.numeric, numbers):
            return replace(eq, exists=False)
        return eq
    back = {v: sympy.Symbol(str(k)) for k, v in positive.items()}
    cond = sympy.And(*[c.xreplace(back) if c not in (sympy.true, sympy.false) else c for c in conds])
    condition = cond if eq.condition is None else sympy.And(eq.condition, cond)
    if condition == sympy.true:
        return eq
    exists: bool | None = eq.exists
    if condition == sympy.false:
        exists = False
    else:
        at_num = condition.xreplace({s: numbers[se.Symbol(s.name)] for s in condition.free_symbols
                                     if se.Symbol(s.name) in numbers})
        if at_num in (sympy.true, sympy.false):
            exists = bool(at_num) if exists is not False else False
        elif exists is True:
            exists = None
    return replace(eq, condition=condition, condition_text=sympy.sstr(condition), exists=exists)


# -- numeric search -----------------------------------------------------------------------------
def _duplicate(a: Equilibrium, b: Equilibrium, angles: set[str]) -> bool:
    """The same point: equal numbers (angles modulo 2π), or the same expressions and condition."""
    if a.exists is False or b.exists is False:
        return False
    if a.numeric is not None and b.numeric is not None:
        return _same(a.numeric, b.numeric, angles)
    if a.free != b.free or a.condition != b.condition:
        return False
    for n, v in a.values.items():
        d = se.expand(_se(v) - _se(b.values[n]))
        if d != 0 and not (n in angles and d.is_number and abs(math.remainder(float(d), 2 * math.pi)) < 1e-12):
            return False
    return True


def _in_ranges(point: Mapping[str, float], ranges: Mapping[str, tuple[float, float]], angles: set[str]) -> bool:
    for n, x in point.items():
        if n in ranges and n not in angles:
            a, b = ranges[n]
            if not (a - 1e-12 * (1 + abs(a)) <= x <= b + 1e-12 * (1 + abs(b))):
                return False
    return True
