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

import itertools
import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field, replace

import numpy as np
import symengine as se
import sympy
from scipy import optimize
from symengine.lib.symengine_wrapper import sympy2symengine

from ..dynamics import EquationsOfMotion
from ..dynamics._friction import sliding_direction
from ..model import CoulombFriction
from ._effective_potential import AnalysisError
from ._equilibria_closed_form import SOLVE_TIMEOUT, closed_form, principal
from ._equilibria_closed_form import condition as branch_condition

__all__ = ["Equilibrium", "EquilibriumError", "equilibria", "SOLVE_TIMEOUT", "STARTS"]

#: About how many starting points the numeric search uses.
STARTS = 240
#: A root is accepted when ‖residual‖ ≤ TOLERANCE × (typical ‖residual‖ over the range).
TOLERANCE = 1e-9


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
    free : coordinates absent from the static equations: any value is an equilibrium.
    """

    values: Mapping[str, se.Basic | float]
    closed_form: bool
    condition: sympy.Basic | None = None
    condition_text: str | None = None
    exists: bool | None = True
    numeric: Mapping[str, float] | None = None
    residual: float | None = None
    free: tuple[str, ...] = field(default=())


def equilibria(eom: EquationsOfMotion, parameters: Mapping[str, float] | None = None,
               ranges: Mapping[str, tuple[float, float]] | None = None, *,
               all_branches: bool = False) -> tuple[Equilibrium, ...]:
    """Every static equilibrium of ``eom`` (q̇ = 0, q̈ = 0), closed form when possible.

    Parameters
    ----------
    eom : `lagrangian.derive`'s result, for an autonomous model.
    parameters : values overriding the model's (name → number).
    ranges : coordinate name → (a, b), where the numeric search looks (and where closed-form
        roots are kept); angles default to (−π, π], other coordinates have no default.
    all_branches : keep closed-form branches whose condition is false at the values.

    Raises
    ------
    EquilibriumError
        The model depends on t explicitly, a name in ``parameters`` or ``ranges`` is unknown,
        or the closed form failed and a coordinate that is not an angle has no range; or it has
        unilateral contacts (which of them hold at an equilibrium, with λ ≥ 0, is not sought).
    """
    contacts = [c.name for c in eom.model.constraints if c.unilateral]
    if contacts:
        raise EquilibriumError(
            f"the model has unilateral contacts ({', '.join(f'`{n}`' for n in contacts)}): at an equilibrium some "
            "of them are closed with a reaction λ ≥ 0 and the others open, and which is not sought here",
            fix="declare the contacts that hold as bilateral constraints (holonomic = \"...\") and remove the others, "
                "or find the rest states by simulating (lagrangian simulate: an accumulation of impacts ends at rest)")
    system = _StaticSystem(eom)
    values = _values(eom, parameters)
    ranges = _ranges(eom, ranges)
    known = all(v is not None for v in values.values())
    numbers = {se.Symbol(k): v for k, v in values.items() if v is not None}
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
    searchable = [n for n in system.active if n in angles or n in ranges]
    continuum = any(len(e.free) > len(system.free) for e in out)  # sample points of it are no news
    if known and not continuum and (branches is None or len(searchable) == len(system.active)):
        missing = [n for n in system.active if n not in searchable]
        if missing:
            raise EquilibriumError(
                f"no closed form was found and coordinate `{missing[0]}` is not an angle, so the numeric search "
                "needs a range for it", fix=f"give one: ranges={{'{missing[0]}': (a, b)}} "
                f"(CLI: --range {missing[0]}=a:b)")
        found = [e.numeric for e in out if e.numeric is not None and e.exists is not False]
        for root, res in _search(system, numbers, ranges, angles):
            if not any(_same(f, root, angles) for f in found):
                found.append(root)
                vals = {n: root[n] if n in root else se.Symbol(n) for n in system.names}
                if system.sticking and not system.holds_by_friction(root, numbers):
                    continue  # the contacts would need more friction than f_s N: it slides away
                out.append(Equilibrium(vals, False, numeric=root, residual=res, free=system.free))
    elif not known and branches is None:
        missing = sorted(k for k, v in values.items() if v is None)
        raise EquilibriumError(f"no closed form was found, and parameter `{missing[0]}` has no value for a "
                               "numeric search", fix=f"give it one: parameters={{'{missing[0]}': ...}} "
                               f"(CLI: --set {missing[0]}=...)")
    return tuple(out)


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

    def __init__(self, eom: EquationsOfMotion) -> None:
        t = eom.t
        rest = {qd: 0 for qd in eom.qd}
        self.eom = eom
        self.q = list(eom.q)
        self.names = [str(s) for s in self.q]
        F = [_se(f) for f in eom.F]
        sticking = self._sticking_contacts(eom)
        for load in eom.loads:
            if load.name in sticking:  # its sliding law is undefined at rest: replaced by T (below)
                F = [se.expand(f - q) for f, q in zip(F, load.Q)]
        F = [f.subs(rest) for f in F]
        for name, f in zip(self.names, F):
            _autonomous(f, t, f"the generalized force on `{name}` at rest")
        for row in eom.M:
            for m in row:
                _autonomous(_se(m), t, "the mass matrix M")
        self.A = [[_se(a) for a in r.coefficients] for r in eom.constraints]
        self.lam = [r.multiplier for r in eom.constraints]
        extra = []
        for r in eom.constraints:
            e = _se(r.expression if r.kind == "holonomic" else r.b).subs(rest)
            _autonomous(e, t, f"constraint row `{r.name}`")
            for a in r.coefficients:
                _autonomous(_se(a), t, f"constraint row `{r.name}`")
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
        """Coordinates in which every static equation is 2π-periodic (at two random points)."""
        rng = np.random.default_rng(1)
        symbols = set().union(*(e.free_symbols for e in self.equations)) if self.equations else set()
        out = set()
        for name, q in zip(self.names, self.q):
            if name in self.free:
                continue
            ok = True
            for _ in range(2):
                point = {s: numbers.get(s, float(rng.uniform(0.5, 2.0))) for s in symbols}
                point.update({s: float(rng.uniform(-3, 3)) for s in symbols if s in self.q or s in self.lam})
                shifted = dict(point)
                shifted[q] = point[q] + 2 * math.pi
                for e in self.equations:
                    a, b = complex(e.subs(point)), complex(e.subs(shifted))
                    if abs(a - b) > 1e-9 * (1 + abs(a)):
                        ok = False
            if ok:
                out.add(name)
        return out

    def residual_function(self, numbers: Mapping[se.Basic, float]):  # type: ignore[no-untyped-def]
        """r(q_active) with λ eliminated: (I − Aᵀ(Aᵀ)⁺) F, then the holonomic and b rows."""
        q = [s for n, s in zip(self.names, self.q) if n in self.active]
        zero = {se.Symbol(n): 0.0 for n in self.free}
        F = _lambdify(q, [f.subs(numbers).subs(zero) for f in self.F])
        A = _lambdify(q, [a.subs(numbers).subs(zero) for row in self.A for a in row]) if self.A else None
        X = _lambdify(q, [e.subs(numbers).subs(zero) for e in self.extra]) if self.extra else None
        n, m = len(self.names), len(self.A)

        def r(x: np.ndarray) -> np.ndarray:
            f = np.asarray(F(x), dtype=float).ravel()
            parts = []
            if A is not None:
                At = np.asarray(A(x), dtype=float).reshape(m, n).T
                lam, *_ = np.linalg.lstsq(At, -f, rcond=None)
                f = f + At @ lam
            parts.append(f)
            if X is not None:
                parts.append(np.asarray(X(x), dtype=float).ravel())
            return np.concatenate(parts)

        return r


def _se(x: object) -> se.Basic:
    """Our SymEngine or SymPy objects (or numbers) as SymEngine, structurally (no text is parsed)."""
    if isinstance(x, se.Basic):
        return x
    if isinstance(x, sympy.Basic):
        return sympy2symengine(x)
    return se.Integer(x) if isinstance(x, int) else se.RealDouble(float(x))  # type: ignore[arg-type]


def _autonomous(e: se.Basic, t: se.Symbol, where: str) -> None:
    if t in e.free_symbols:
        raise EquilibriumError(
            f"the model depends on t explicitly ({where} contains t), so it has no static equilibrium in "
            "the sense q̇ = 0 for all t", fix="write the equations in a frame where the motion is steady "
            "([reference]), or study the motion by simulation")


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


def _wrap(x: float) -> float:
    """x modulo 2π in (−π, π]."""
    y = math.remainder(x, 2 * math.pi)
    return math.pi if y <= -math.pi + 1e-12 else y


def _in_ranges(point: Mapping[str, float], ranges: Mapping[str, tuple[float, float]], angles: set[str]) -> bool:
    for n, x in point.items():
        if n in ranges and n not in angles:
            a, b = ranges[n]
            if not (a - 1e-12 * (1 + abs(a)) <= x <= b + 1e-12 * (1 + abs(b))):
                return False
    return True


def _same(a: Mapping[str, float], b: Mapping[str, float], angles: set[str]) -> bool:
    for n in a:
        d = a[n] - b.get(n, math.nan)
        if n in angles:
            d = math.remainder(d, 2 * math.pi)
        if not abs(d) <= 1e-6 * (1 + abs(a[n])):
            return False
    return True


def _search(system: _StaticSystem, numbers: Mapping[se.Basic, float], ranges: Mapping[str, tuple[float, float]],
            angles: set[str]) -> list[tuple[dict[str, float], float]]:
    """All roots of the static system in the ranges, from a grid of starting points."""
    names = system.active
    if not names:
        return []
    box = [(-math.pi, math.pi) if n in angles and n not in ranges else ranges[n] for n in names]
    d = len(names)
    k = max(2, int(round(STARTS ** (1 / d))))
    rng = np.random.default_rng(0)
    axes = [np.linspace(a, b, k, endpoint=False) + (b - a) / (2 * k) for a, b in box]
    starts = [np.array(p) for p in itertools.product(*axes)] if k ** d <= 4 * STARTS else \
        [np.array([rng.uniform(a, b) for a, b in box]) for _ in range(STARTS)]
    r = system.residual_function(numbers)
    scale = float(np.median([np.linalg.norm(r(x)) for x in starts[:: max(1, len(starts) // 30)]])) or 1.0
    found: list[tuple[dict[str, float], float]] = []
    for x0 in starts:
        try:
            sol = optimize.least_squares(r, x0, method="lm", xtol=1e-15, ftol=1e-15, gtol=1e-15)
        except (ValueError, np.linalg.LinAlgError):
            continue
        res = float(np.max(np.abs(r(sol.x))))
        if not np.isfinite(res) or np.linalg.norm(r(sol.x)) > TOLERANCE * scale:
            continue
        point = {n: (_wrap(x) if n in angles else float(x)) for n, x in zip(names, sol.x)}
        if _in_ranges(point, ranges, angles) and not any(_same(p, point, angles) for p, _ in found):
            found.append((point, res))
    found.sort(key=lambda pr: tuple(pr[0][n] for n in names))
    return found
