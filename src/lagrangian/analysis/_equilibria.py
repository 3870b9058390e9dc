"""Static equilibria of an autonomous system: q̇ = 0, q̈ = 0, so F(q, 0) + Aᵀλ = 0.

With M(q) q̈ = F(q, q̇) + Aᵀ(q) λ (seed, section II; the multipliers of the complementary
constraints, step 7), a configuration q* is a position of equilibrium when the system
placed there at rest stays there: q̈ = 0 at q̇ = 0, i.e.

    F(q*, 0) + Aᵀ(q*) λ = 0,    f(q*) = 0 (holonomic rows),    b(q*) = 0 (rate-free part
                                                                 of the velocity rows).

λ is eliminated numerically by projecting F on the complement of the range of Aᵀ.

Closed form first (`_equilibria_closed_form`: SymPy on the factors of each equation, with
each branch's condition of existence, R Ω² > g for the bead's tilted positions).  Then a
numeric multi-start search (`_equilibria_search`: Levenberg–Marquardt from starting points
over each coordinate's region) whenever every parameter has a value; it fills in what the
closed form missed (SymPy's solvers are not complete: ``solve`` alone loses θ = π of the bead,
and the elastic pendulum's upright rest with |r| in its spring) or replaces it when SymPy fails.
Roots are deduplicated, angles modulo 2π; families of rests ("r any", a curve) are given once,
and rests that put every body in the same place (r, θ and −r, θ + π) are one rest with aliases.
What was searched is returned with the list (`EquilibriumSearch`), which is never presented as
complete.

Dry friction (an exact Coulomb contact, ``regularization = 0``): at rest the contact sticks,
so its law T = −f N v_s/|v_s| (undefined at v_s = 0) is replaced by the sticking constraint
w = v_s·e = 0 with its own multiplier T, the friction force along e; a rest is an equilibrium
where the force it needs stays in the friction cone, |T| ≤ f_s N (Coulomb's law of
adherence).  For a block on an incline of angle α: T = −m g sin α, so every x is an
equilibrium when |sin α|/cos α = tan α ≤ f_s.

An *angle* is a coordinate that enters the equations only through 2π-periodic sin, cos, tan;
it ranges over (−π, π] — π rather than −π, as the course writes the upper position.  Other
coordinates are searched over the range given (``ranges={"x": (a, b)}``), else the model's
declared ``range``, else from starting points over every scale.  See docs/equilibria.md.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field, replace

import numpy as np
import symengine as se
import sympy

from ..dynamics import EquationsOfMotion
from ._equilibria_closed_form import SOLVE_TIMEOUT, closed_form, principal
from ._equilibria_closed_form import condition as branch_condition
from ._equilibria_search import STARTS, EquilibriumSearch, SearchRegion, near_curve, region_of
from ._equilibria_search import same as _same
from ._equilibria_search import search as _search
from ._equilibria_search import wrap as _wrap
from ._static_system import EquilibriumError, StaticSystem, configuration, to_symengine

__all__ = [
    "SOLVE_TIMEOUT",
    "STARTS",
    "Equilibria",
    "Equilibrium",
    "EquilibriumError",
    "EquilibriumSearch",
    "SearchRegion",
    "equilibria",
]


@dataclass(frozen=True)
class Equilibrium:
    """One position of equilibrium q*.

    Parameters
    ----------
    values : mapping of str to SymEngine expression or float
        Coordinate name → q*_i: a SymEngine expression in the parameters (closed form) or a float
        (numeric); a coordinate in ``free`` maps to its own symbol (any value).
    closed_form : bool
        Whether ``values`` were found by SymPy.
    condition : SymPy expression, optional
        The condition of existence (a SymPy relational or And of them, in the parameters), or None
        when the equilibrium always exists.
    condition_text : str, optional
        Its text.
    exists : bool or None
        The condition at the parameter values (None when some value is missing).
    numeric : mapping of str to float, optional
        The equilibrium q* at the parameter values (angles in (−π, π]), or None without all values.
    residual : float, optional
        ``max |F(q*, 0) + Aᵀλ|, |f(q*)|`` at ``numeric`` (None without values).
    free : tuple of str
        Coordinates along which every value is an equilibrium: absent from the static equations,
        left free by SymPy, or found so by the numeric search (the bead on a turning parabola at
        Ω² = 2 g a: "r any").
    family : int
        The dimension of a curved family of equilibria through ``numeric`` (0: none; the static
        equations' Jacobian is singular there and the rests form a curve, which this one stands for).
    aliases : tuple of mapping of str to float
        Other values of the coordinates that put every body and particle in the same place (the
        elastic pendulum's r = −0.63, θ = π is its r = 0.63, θ = 0): listed here, not as rests.
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


class Equilibria(tuple):
    """The equilibria found (a tuple of `Equilibrium`), with what was searched.

    Parameters
    ----------
    items : sequence of Equilibrium
        The equilibria.
    search : EquilibriumSearch
        What was searched.
    """

    search: EquilibriumSearch

    def __new__(cls, items: Sequence[Equilibrium], search: EquilibriumSearch) -> Equilibria:  # noqa: PYI034
        out = super().__new__(cls, items)
        out.search = search
        return out


def equilibria(eom: EquationsOfMotion, parameters: Mapping[str, float] | None = None,
               ranges: Mapping[str, tuple[float, float]] | None = None, *,
               all_branches: bool = False, numeric: bool = True) -> Equilibria:
    """Every static equilibrium of ``eom`` (q̇ = 0, q̈ = 0), closed form when possible.

    Parameters
    ----------
    eom : EquationsOfMotion
        `lagrangian.derive`'s result, for an autonomous model.
    parameters : mapping of str to float, optional
        Values overriding the model's (name → number).
    ranges : mapping of str to (float, float), optional
        Coordinate name → (a, b), where the numeric search looks (and where closed-form roots are
        kept); angles default to (−π, π], other coordinates to their declared ``range``, else to
        starting points over every scale (`lagrangian.analysis._equilibria_search`).
    all_branches : bool, optional
        Keep closed-form branches whose condition is false at the values.
    numeric : bool, optional
        Run the numeric search (when every parameter has a value); False: the closed form only.

    Returns
    -------
    Equilibria
        A tuple of `Equilibrium`, whose ``search`` says what was searched: the list holds what was
        found there, and a root beyond the starting points' reach may be missing.

    Raises
    ------
    EquilibriumError
        The model depends on t explicitly (once the parameters have their values), a name in
        ``parameters`` or ``ranges`` is unknown, or the closed form failed and a parameter has no value;
        or it has unilateral contacts (which of them hold at an equilibrium, with λ ≥ 0, is not sought).
    """
    contacts = [c.name for c in eom.model.constraints if c.unilateral]
    if contacts:
        raise EquilibriumError(
            f"the model has unilateral contacts ({', '.join(f'`{n}`' for n in contacts)}): at an equilibrium some "
            "of them are closed with a reaction λ ≥ 0 and the others open, and which is not sought here",
            fix="declare the contacts that hold as bilateral constraints (holonomic = \"...\") and remove the others, "
                "or find the rest states by simulating (lagrangian simulate: an accumulation of impacts ends at rest)")
    values = _values(eom, parameters)
    known = all(v is not None for v in values.values())
    numbers = {se.Symbol(k): v for k, v in values.items() if v is not None}
    system = StaticSystem(eom, numbers)
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
    skipped = "not asked" if not numeric else "values" if not known else "continuum" if continuum else None
    report = EquilibriumSearch(branches is not None, False, skipped=skipped)
    if skipped is None:
        declared = {c.name: c.range for c in eom.model.coordinates}
        regions = [region_of(n, n in angles, ranges.get(n), declared.get(n), numbers) for n in system.active]
        roots, starts = _search(system.active, system.residual_function(numbers), system.size_function(numbers),
                                regions, angles, numbers)
        where = tuple(SearchRegion(n, kind, bounds, starts) for n, (kind, bounds) in zip(system.active, regions, strict=True))
        report = EquilibriumSearch(branches is not None, True, where, starts)
        out = _identify(system, _merge(system, out, roots, numbers, angles), numbers, angles)
    elif not known and branches is None:
        missing = sorted(k for k, v in values.items() if v is None)
        raise EquilibriumError(f"no closed form was found, and parameter `{missing[0]}` has no value for a "
                               "numeric search", fix=f"give it one: parameters={{'{missing[0]}': ...}} "
                               f"(CLI: --set {missing[0]}=...)")
    return Equilibria(out, report)


def _identify(system: StaticSystem, out: list[Equilibrium], numbers: Mapping[se.Basic, float],
              angles: set[str]) -> list[Equilibrium]:
    """Each configuration once: rests whose coordinates put every body in the same place (r and θ against
    −r and θ + π) are one rest, written with lengths ≥ 0 and closed form first; the others become its
    ``aliases``."""
    points = [e for e in out if e.numeric is not None and not e.free]
    if len(points) < 2:
        return out
    try:
        place = configuration(system, numbers)
    except (RuntimeError, TypeError, ValueError, KeyError, AttributeError):  # pragma: no cover - no kinematics
        return out
    names = system.names
    at = {e_id: np.asarray(place(np.array([(e.numeric or {}).get(n, 0.0) for n in names])), dtype=np.float64).ravel()
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

    def key(e: Equilibrium) -> tuple:
        numeric = e.numeric or {}  # the rests grouped have numbers (`points`)
        negative = sum(1 for n, v in numeric.items() if n not in angles and v < -1e-12)
        return (negative, not e.closed_form, sum(1 for v in numeric.values() if v < -1e-12))

    keep: dict[int, Equilibrium] = {}
    for g in groups:
        best = min(g, key=key)
        keep[id(best)] = replace(best, aliases=tuple(dict(x.numeric or {}) for x in g if x is not best))
    return [keep.get(id(e), e) for e in out if id(e) in keep or e.numeric is None or e.free]


def _merge(system: StaticSystem, out: list[Equilibrium], roots: Sequence, numbers: Mapping[se.Basic, float],
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


def _from_closed_form(system: StaticSystem, branch: Mapping[str, sympy.Basic], branches: Sequence[Mapping],
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
    values: dict[str, se.Basic | float] = {n: to_symengine(v.xreplace(plain)) for n, v in branch.items()}
    exists: bool | None = True
    if condition != sympy.true:
        at = condition.xreplace({s: numbers[se.Symbol(s.name)] for s in condition.free_symbols
                                 if se.Symbol(s.name) in numbers})
        exists = bool(at) if at in (sympy.true, sympy.false) else None
    at_values: dict[str, float] = {}
    for n, v in values.items():
        try:
            x = float(to_symengine(v).subs(numbers))
        except (RuntimeError, TypeError, ValueError):
            continue  # a parameter without value
        if not math.isfinite(x):  # no real value at these parameters (asin of 2, a division by 0)
            exists = False
            continue
        if n in angles:  # into (−π, π], the expression too (−π is written π)
            k = round((_wrap(x) - x) / (2 * math.pi))
            if k:
                x += 2 * k * math.pi
                values[n] = to_symengine(v) + 2 * k * se.pi
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


def _within_friction_cone(system: StaticSystem, eq: Equilibrium, branch: Mapping[str, sympy.Basic],
                          numbers: Mapping[se.Basic, float]) -> Equilibrium:
    """Add |T|/N ≤ f_s, Coulomb's condition of adherence, to a closed-form rest with sticking contacts.

    T comes from F + Aᵀλ = 0 solved for the multipliers at the branch (linear in them); when it
    is not unique (redundant rows) the rest is checked numerically only.
    """
    lam = [sympy.Symbol(str(s), real=True) for s in system.lam]
    positive = {sympy.Symbol(str(k)): sympy.Symbol(str(k), positive=True) for k, v in numbers.items() if v > 0}
    plain = {sympy.Symbol(str(s)): s2 for s, s2 in zip(system.lam, lam, strict=True)}
    at = {sympy.Symbol(n): v for n, v in branch.items()}
    eqs = [e._sympy_().xreplace(plain).xreplace(at).xreplace(positive) for e in system.equations]
    try:
        sols = sympy.solve([e for e in eqs if e != 0], lam, dict=True)
    except (NotImplementedError, ValueError):
        sols = []
    conds: list[sympy.Basic] = []
    k0 = len(system.lam) - len(system.sticking)
    for (_, _, fs, N), sym in zip(system.sticking, lam[k0:], strict=True):
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
        d = se.expand(to_symengine(v) - to_symengine(b.values[n]))
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
