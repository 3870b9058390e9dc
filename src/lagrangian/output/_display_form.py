r"""Forms a teacher would write on the board: a display simplifier for the report, fast and predictable.

The engine keeps its expressions as derived (M q̈ = F implicit, shared subexpressions); the
report prints them.  Before printing, `display_form` rewrites a sum with three rules, each an
identity, so the value never changes:

1. **sin² + cos² = 1** between two terms equal but for sin²x ↔ cos²x (same coefficient):
   l1² m2 θ̈1 sin²θ2 + l1² m2 θ̈1 cos²θ2 → m2 l1² θ̈1;
2. **angle addition** between two terms equal but for the pair of factors, same coefficient
   up to sign: cos u cos v ∓ sin u sin v → cos(u ± v), sin u cos v ± cos u sin v → sin(u ± v);
   so −l1 cosθ2 cos(θ1 + θ2) − l1 sinθ2 sin(θ1 + θ2) → −l1 cosθ1;
3. **common factors out** (SymPy's ``factor_terms``), then terms that differ only by their
   parameters gathered: θ̇ sinθ (C φ̇ + 2 (C − A) ψ̇ cosθ);
4. **like terms collected**: when the expansion merges terms (the derived form wrote one quantity in
   two places, ½ m2 l2 (l1 θ̇1 cosθ2 + ½ l2 (θ̇1 + θ̇2)) + 1/12 m2 l2² (θ̇1 + θ̇2)), the rewritten form is kept.

Rules 1 and 2 are applied on the expanded sum until none applies.  The rewritten form is kept
when rule 1, 2 or 4 applied, or when it is at most two thirds of the original's size (nodes of the
expression tree) and the expanded sum has at most `FEW_TERMS` terms; otherwise the expression is printed as derived (the seed's
A θ̈ − A ψ̇² sinθ cosθ + C ψ̇ sinθ (φ̇ + ψ̇ cosθ) keeps its conserved spin φ̇ + ψ̇ cosθ).

Cost: one expansion and a dictionary look-up per pair of trigonometric factors of a term.
Expressions past `MAX_OPS` operations, or whose expansion has more than `MAX_TERMS` terms, are
left as they are (the report summarizes them anyway), so the 40-link chain stays cheap.

Reference: the identities are those of any trigonometry table (e.g. Abramowitz & Stegun, 4.3.10, 4.3.16–17).
"""

from __future__ import annotations

import functools
import math
from collections.abc import Collection

import sympy

__all__ = ["display_form", "MAX_OPS", "MAX_TERMS"]

#: Largest expression (nodes of its tree) the simplifier looks at.
MAX_OPS = 240
#: Largest expanded sum a rewrite without identity (rule 3 alone) is tried on.
FEW_TERMS = 8
#: Largest expanded sum it rewrites.
MAX_TERMS = 120
#: A form found without any identity replaces the derived one only when at most this fraction of its size.
SHORTER = 2 / 3

_TRIG = (sympy.sin, sympy.cos)


def display_form(expr: sympy.Basic, parameters: Collection[str] = ()) -> sympy.Basic:
    """``expr`` as a teacher would write it (see the module docstring); its value is unchanged.

    ``parameters`` names the model's constants: terms that differ only by them are gathered
    (2 C ψ̇ cosθ − 2 A ψ̇ cosθ → 2 (C − A) ψ̇ cosθ).
    """
    if not isinstance(expr, sympy.Expr) or expr.is_Atom:
        return expr
    return _display_form(expr, frozenset(parameters))


@functools.lru_cache(maxsize=8192)
def _display_form(expr: sympy.Expr, parameters: frozenset[str]) -> sympy.Expr:
    size = _size(expr, MAX_OPS)
    if size is None:
        return expr
    if _expanded_terms(expr) > MAX_TERMS:
        return expr
    expanded = sympy.expand(expr, power_exp=False, power_base=False, log=False, multinomial=True, mul=True)
    terms = sympy.Add.make_args(expanded)
    if len(terms) > MAX_TERMS or len(terms) < 2:
        return expr
    reduced, fired = _reduce(terms)
    # Like terms met on expanding (½ l2 (θ̇1 + θ̇2) + 1/12 l2 (θ̇1 + θ̇2) is ⅓ l2 (θ̇1 + θ̇2)): the derived form
    # wrote one quantity twice, which a teacher collects; an expansion that merges nothing is no news.
    fired = fired or len(terms) < _expanded_terms(expr)
    if not fired and len(reduced) > FEW_TERMS:
        return expr
    form = _refactor(sympy.Add(*reduced), parameters)
    if fired:
        # The shorter of "common factors out" and "terms with the same constant factor together"
        # (½ m2 l1 l2 θ̇1 cosθ2 + ⅓ m2 l2² (θ̇1 + θ̇2), not ⅙ m2 l2 (3 l1 θ̇1 cosθ2 + 2 l2 θ̇1 + 2 l2 θ̇2)).
        other = _by_constants(reduced, parameters)
        if _terms_shown(other) < _terms_shown(form):
            form = other
    if fired or (_size(form, MAX_OPS) or MAX_OPS) <= SHORTER * size:
        return form
    return expr


def _expanded_terms(e: sympy.Expr) -> int:
    """How many terms ``e`` has once expanded, at most (products multiply, sums add): checked before expanding."""
    if isinstance(e, sympy.Add):
        return sum(_expanded_terms(a) for a in e.args)
    if isinstance(e, sympy.Mul):
        out = 1
        for a in e.args:
            out *= _expanded_terms(a)
        return out
    if isinstance(e, sympy.Pow) and e.exp.is_Integer and e.exp > 0:
        # (a + b)² has 3 monomials, not 4: a power of a sum of n terms has C(n + k − 1, k) distinct ones.
        n, k = _expanded_terms(e.base), int(e.exp)
        return math.comb(n + k - 1, k)
    return 1


def _size(expr: sympy.Expr, limit: int) -> int | None:
    """The number of nodes of ``expr``'s tree; None past ``limit``, without a symbol, or with a summary
    (⟨812 terms⟩).  Walked with an early stop, so that a long expression costs no more than a short one
    (SymPy's ``count_ops`` is 40 times slower)."""
    symbols = False
    k = 0
    for k, node in enumerate(sympy.preorder_traversal(expr), 1):
        if k > limit or type(node).__name__ in ("Summary", "Opaque"):
            return None
        symbols = symbols or node.is_Symbol
    return k if symbols else None


def _split(term: sympy.Expr) -> tuple[sympy.Expr, sympy.Expr]:
    """(numeric coefficient, the rest) of a term: −2 A θ̇ → (−2, A θ̇)."""
    coeff, rest = term.as_coeff_Mul()
    return coeff, rest


def _trig_factors(monomial: sympy.Expr) -> list[tuple[sympy.Expr, int]]:
    """The sin and cos factors of a product, with their powers."""
    out = []
    for f in sympy.Mul.make_args(monomial):
        base, exp = f.as_base_exp()
        if isinstance(base, _TRIG) and exp.is_Integer and exp > 0:
            out.append((base, int(exp)))
    return out


def _reduce(terms: tuple[sympy.Expr, ...]) -> tuple[list[sympy.Expr], bool]:
    """The sum's terms after rules 1 and 2 (until none applies), and whether one applied."""
    table: dict[sympy.Expr, sympy.Expr] = {}
    for t in terms:
        c, m = _split(t)
        table[m] = table.get(m, sympy.Integer(0)) + c
    fired = False
    for _ in range(4 * len(terms)):  # each rewrite removes a term: this bounds the loop
        step = _one_rewrite(table)
        if step is None:
            break
        fired = True
        (m1, m2), (new_c, new_m) = step
        del table[m1], table[m2]
        c, m = _split(new_c * new_m)
        total = table.get(m, sympy.Integer(0)) + c
        if total == 0:
            table.pop(m, None)
        else:
            table[m] = total
    return [c * m for m, c in table.items() if c != 0], fired


def _one_rewrite(table: dict[sympy.Expr, sympy.Expr]) -> tuple[tuple[sympy.Expr, sympy.Expr],
                                                               tuple[sympy.Expr, sympy.Expr]] | None:
    """One application of rule 1 or 2: the two monomials it merges and the (coefficient, monomial) it makes."""
    for m, c in table.items():
        trig = _trig_factors(m)
        for f, p in trig:
            # Rule 1: c R sin²x + c R cos²x = c R.
            if p >= 2 and isinstance(f, sympy.sin):
                partner = m / f**2 * sympy.cos(f.args[0])**2
                if table.get(partner) == c:
                    return (m, partner), (c, m / f**2)
        for i, (f, _) in enumerate(trig):
            for g, _ in trig[i + 1:]:
                u, v = f.args[0], g.args[0]
                rest = m / (f * g)
                if isinstance(f, sympy.cos) and isinstance(g, sympy.cos):
                    # c R cos u cos v ∓ c R sin u sin v = c R cos(u ± v).
                    partner = rest * sympy.sin(u) * sympy.sin(v)
                    pc = table.get(partner)
                    if pc is not None and partner != m and pc in (c, -c):
                        return (m, partner), (c, rest * sympy.cos(u - v if pc == c else u + v))
                elif isinstance(f, sympy.sin) != isinstance(g, sympy.sin):
                    s, k = (u, v) if isinstance(f, sympy.sin) else (v, u)
                    # c R sin s cos k ± c R cos s sin k = c R sin(s ± k).
                    partner = rest * sympy.cos(s) * sympy.sin(k)
                    pc = table.get(partner)
                    if pc is not None and partner != m and pc in (c, -c):
                        return (m, partner), (c, rest * sympy.sin(s + k if pc == c else s - k))
    return None


def _refactor(expr: sympy.Expr, parameters: frozenset[str]) -> sympy.Expr:
    """Common factors out, then the terms that differ by their parameters only gathered (rule 3)."""
    common = sympy.factor_terms(expr, radical=False, clear=False, fraction=False, sign=False)
    factors = sympy.Mul.make_args(common)
    out = []
    for f in factors:
        if isinstance(f, sympy.Add):
            f = _gather(f, parameters)
        out.append(f)
    return sympy.Mul(*out)


def _terms_shown(e: sympy.Expr) -> int:
    """How many terms the eye reads in a sum: a product with a sum in it counts that sum's terms."""
    if isinstance(e, sympy.Add):
        return len(e.args)
    inner = [f for f in sympy.Mul.make_args(e) if isinstance(f, sympy.Add)]
    return max((len(f.args) for f in inner), default=1)


def _constant_part(t: sympy.Expr, parameters: frozenset[str]) -> tuple[sympy.Expr, sympy.Expr]:
    """(numbers and parameters, the rest) of a term: ⅓ m2 l2² θ̇1 → (⅓ m2 l2², θ̇1)."""
    constant: list[sympy.Expr] = []
    moving: list[sympy.Expr] = []
    for f in sympy.Mul.make_args(t):
        (constant if f.is_Number or (f.free_symbols and {s.name for s in f.free_symbols} <= parameters)
         else moving).append(f)
    return sympy.Mul(*constant), sympy.Mul(*moving)


def _by_constants(terms: list[sympy.Expr], parameters: frozenset[str]) -> sympy.Expr:
    """Rates (or accelerations) with the same constant factor written once: ⅓ m2 l2² θ̇1 + ⅓ m2 l2² θ̇2 →
    ⅓ m2 l2² (θ̇1 + θ̇2), as in a momentum or the inertia terms of an equation; other terms as they are
    (T keeps its coefficients of θ̇1², θ̇1 θ̇2, θ̇2², which `_gather` makes)."""
    groups: dict[sympy.Expr, list[sympy.Expr]] = {}
    rest = []
    for t in terms:
        constant, moving = _constant_part(t, parameters)
        if moving.is_Symbol:
            groups.setdefault(constant, []).append(moving)
        else:
            rest.append(t)
    return sympy.Add(*(c * sympy.Add(*ms) for c, ms in groups.items()), *rest)


def _gather(total: sympy.Add, parameters: frozenset[str]) -> sympy.Expr:
    """2 C ψ̇ cosθ − 2 A ψ̇ cosθ + C φ̇ → 2 (C − A) ψ̇ cosθ + C φ̇: terms grouped by their part free of parameters."""
    groups: dict[sympy.Expr, list[sympy.Expr]] = {}
    for t in total.args:
        constant: list[sympy.Expr] = []
        moving: list[sympy.Expr] = []
        for f in sympy.Mul.make_args(t):
            (constant if f.free_symbols and {s.name for s in f.free_symbols} <= parameters or f.is_Number
             else moving).append(f)
        groups.setdefault(sympy.Mul(*moving), []).append(sympy.Mul(*constant))
    if len(groups) == len(total.args):
        return total
    return sympy.Add(*(sympy.factor_terms(sympy.Add(*cs), sign=False) * key for key, cs in groups.items()))
