"""Equilibria in closed form: the static equations solved by SymPy, with each branch's condition of existence.

Each equation is factored (sinθ (R Ω² cosθ − g) = 0) and every choice of one factor per
equation is solved by SymPy; our SymEngine expressions are converted structurally
(``_sympy_()``), no text is ever parsed.  Parameters are assumed positive when their value is
positive or missing, negative when negative, real when zero.  A branch holding acos(a) or
asin(a) exists for −1 ≤ a ≤ 1, one with √a for a ≥ 0; where the boundary makes the branch
coincide with another branch (cosθ = g/(R Ω²) at R Ω² = g is θ = 0, a double root) the
inequality is strict, so the double root is listed once, as the other branch.  The condition
is tidied: g/(R Ω²) < 1 becomes R Ω² > g.
"""

from __future__ import annotations

import itertools
import threading
from collections.abc import Mapping, Sequence

import symengine as se
import sympy

__all__ = ["SOLVE_TIMEOUT", "closed_form", "condition", "principal", "tidy"]

#: Seconds SymPy may take before the numeric search takes over (SymPy cannot be interrupted:
#: the slow solve is left to finish in a daemon thread).
SOLVE_TIMEOUT = 5.0


def _sympy_symbols(unknowns: Sequence[se.Symbol], values: Mapping[str, float | None]) -> dict[se.Basic, sympy.Symbol]:
    """SymPy symbols with assumptions: parameters positive (negative) when their value is, else real."""
    out = {}
    for name, v in values.items():
        kw = {"positive": True} if (v is None or v > 0) and v != 0 else {"negative": True} if v < 0 else {"real": True}
        out[se.Symbol(name)] = sympy.Symbol(name, **kw)
    for s in unknowns:
        out[s] = sympy.Symbol(str(s), real=True)
    return out


def closed_form(equations: Sequence[se.Basic], q: Sequence[se.Symbol], active: Sequence[str],
                multipliers: Sequence[se.Symbol], values: Mapping[str, float | None]) -> list[dict] | None:
    """Every branch SymPy finds of ``equations`` = 0 in the ``active`` coordinates and the multipliers.

    Returns dicts coordinate name → SymPy expression in the parameters (a coordinate left out
    is free), or None when SymPy fails or takes longer than `SOLVE_TIMEOUT`.
    """
    if not active:
        return [{}]
    symbols = _sympy_symbols([*q, *multipliers], values)
    subs = {sympy.Symbol(str(k)): v for k, v in symbols.items()}
    eqs = [e._sympy_().xreplace(subs) for e in equations]  # structural conversion of our expressions
    eqs = [e for e in eqs if e != 0]
    unknowns = [symbols[s] for s in q if str(s) in active]
    unknowns += [symbols[s] for s in multipliers]
    if any(_mixed(e, u) for e in eqs for u in unknowns):
        return None  # θ and sinθ together (k θ = sinθ): no SymPy solver knows it, don't wait for one
    result: list = []

    def factors(e: sympy.Basic) -> list[sympy.Basic]:
        try:
            return [f for f, _ in sympy.factor_list(sympy.together(e))[1] if f.free_symbols & set(unknowns)] or [e]
        except sympy.PolynomialError:
            return [e]

    def work() -> None:
        try:
            combos = list(itertools.product(*[factors(e) for e in eqs]))
            if len(combos) > 64:
                combos = [tuple(eqs)]
            sols = []
            for combo in combos:
                sols += sympy.solve(list(combo), unknowns, dict=True)
            result.append(sols)
        except Exception:  # noqa: BLE001 - any SymPy failure means: no closed form, search numerically
            result.append(None)

    # SymPy cannot be interrupted: a slow solve is left to finish in a daemon thread.
    th = threading.Thread(target=work, daemon=True)
    th.start()
    th.join(SOLVE_TIMEOUT)
    if not result or result[0] is None:
        return None
    names = {symbols[s]: str(s) for s in q}
    out = []
    for sol in result[0]:
        branch = {names[k]: v for k, v in sol.items() if k in names}
        if any(v.has(sympy.I) for v in branch.values()):
            continue  # complex roots (or not known to be real): left to the numeric search
        if any(any(x in unknowns for x in v.free_symbols) for v in branch.values()):
            continue
        out.append(branch)
    return out


_TRANSCENDENTAL = (sympy.sin, sympy.cos, sympy.tan, sympy.exp, sympy.log, sympy.sinh, sympy.cosh, sympy.tanh)


def _mixed(e: sympy.Basic, u: sympy.Symbol) -> bool:
    """Whether ``u`` appears both inside a transcendental function and outside every such function."""
    inside = [f for f in e.atoms(*_TRANSCENDENTAL) if u in f.free_symbols]
    if not inside:
        return False
    bare = e.xreplace({f: sympy.Dummy() for f in inside})
    return u in bare.free_symbols


def condition(expr: sympy.Basic, branch: Mapping[str, sympy.Basic], others: Sequence[Mapping[str, sympy.Basic]],
               name: str) -> list[sympy.Basic]:
    """Where ``expr`` (q*_name) is real: −1 ≤ a ≤ 1 in acos(a), asin(a); a ≥ 0 under √."""
    conds = []
    for f in expr.atoms(sympy.acos, sympy.asin):
        a = f.args[0]
        for bound, edge in ((1, sympy.acos(1) if f.func is sympy.acos else sympy.pi / 2),
                            (-1, sympy.pi if f.func is sympy.acos else -sympy.pi / 2)):
            at_edge = expr.xreplace({f: edge})
            double = any(_equal_mod_2pi(at_edge, o.get(name)) for o in others if o is not branch)
            rel = (sympy.Lt if double else sympy.Le) if bound == 1 else (sympy.Gt if double else sympy.Ge)
            conds.append(tidy(rel(a, bound)))
    for p in expr.atoms(sympy.Pow):
        if p.exp.is_Rational and p.exp.q % 2 == 0:
            conds.append(tidy(sympy.Ge(p.base, 0)))
    return conds


def _equal_mod_2pi(a: sympy.Basic, b: sympy.Basic | None) -> bool:
    if b is None:
        return False
    d = sympy.simplify((a - b) / (2 * sympy.pi))
    return bool(d.is_integer)


def tidy(rel: sympy.Basic) -> sympy.Basic:
    """``g/(R Ω²) < 1`` → ``R Ω² > g``: clear a positive denominator, positive terms on each side."""
    if rel in (sympy.true, sympy.false):
        return rel
    num, den = sympy.fraction(sympy.together(rel.lhs - rel.rhs))
    if den.is_positive:
        terms = sympy.Add.make_args(sympy.expand(num))
        left = sympy.Add(*[t for t in terms if not t.could_extract_minus_sign()])
        right = sympy.Add(*[-t for t in terms if t.could_extract_minus_sign()])
        rel = rel.func(left, right)
        if rel.func in (sympy.Lt, sympy.Le):
            rel = rel.reversed
    return rel


def principal(v: sympy.Basic) -> sympy.Basic:
    """2π − acos(a) → −acos(a): drop a constant 2kπ when what is left is ±acos, ±asin, ±atan (in [−π, π])."""
    terms = sympy.Add.make_args(v)
    const = sympy.Add(*[t for t in terms if t.is_number])
    rest = v - const
    k = const / (2 * sympy.pi)
    inverse = (sympy.acos, sympy.asin, sympy.atan)
    if const != 0 and k.is_integer and (isinstance(rest, inverse) or isinstance(-rest, inverse)):
        return rest
    return v
