"""Exact rewritings of M and F that make the generated code cheaper: the package's C form of them.

Every rewriting is an identity, so the code evaluates the derivation's M q̈ = F, only with fewer
operations: sin/cos of sums of coordinates by the addition formulas (`expand_angle_sums`), the
terms of M grouped by their function of q (`collect_by_state`), each body's bias γ⁰(G) and
dσ⁰/dt named once in F (`mass_forces_form`, from `dynamics.mass_matrix_and_bias`), and the
parameter-only coefficients lifted out of the per-state code (`Hoist`).  The in-package library
(`_codegen`) and ``export --to c`` (`targets.c`) print this form; the other export targets use
the first two rewritings.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import symengine as se

from ..dynamics import EquationsOfMotion

__all__ = ["Hoist", "MassForcesForm", "collect_by_state", "expand_angle_sums", "mass_forces_form", "smaller"]


def expand_angle_sums(exprs: Sequence[se.Basic], angles: Sequence[se.Symbol]) -> list[se.Basic]:
    """Rewrite sin/cos of sums of coordinates by the addition formulas.

    cos(θ_i − θ_j) = cos θ_i cos θ_j + sin θ_i sin θ_j, and so on recursively: an n-link
    chain's M then needs 2n trigonometric calls instead of one per pair (i, j), and
    ``cse`` shares the products.  Only arguments that are sums of ±coordinates (at most
    six terms) are rewritten; anything else (2θ, θ + Ω t) is left as it is.
    """
    angle_set = set(angles)
    memo: dict[se.Basic, se.Basic] = {}

    def split(arg: se.Basic):
        if not isinstance(arg, se.Add):
            return None
        terms = []
        for term in arg.args:
            if term in angle_set:
                terms.append((1, term))
            elif isinstance(term, se.Mul) and len(term.args) == 2 and term.args[0] == -1 \
                    and term.args[1] in angle_set:
                terms.append((-1, term.args[1]))
            else:
                return None
        return sorted(terms, key=lambda t: angles.index(t[1])) if 2 <= len(terms) <= 6 else None

    def sc(sign: int, angle: se.Basic, rest: list) -> tuple[se.Basic, se.Basic]:
        s1, c1 = sign * se.sin(angle), se.cos(angle)
        if not rest:
            return s1, c1
        s2, c2 = sc(rest[0][0], rest[0][1], rest[1:])
        key = (sign, angle) + tuple(rest)
        if key not in memo:
            memo[key] = (s1 * c2 + c1 * s2, c1 * c2 - s1 * s2)
        return memo[key]

    mapping = {}
    for expr in exprs:
        for atom in expr.atoms(se.sin, se.cos):
            terms = split(atom.args[0])
            if terms is None:
                continue
            sin_sum, cos_sum = sc(terms[0][0], terms[0][1], terms[1:])
            mapping[atom] = sin_sum if isinstance(atom, se.sin) else cos_sum
    return [e.xreplace(mapping) if mapping else e for e in exprs]


def smaller(a: se.Basic, b: se.Basic) -> se.Basic:
    """Whichever of two equal expressions has fewer operations (``a`` on a tie)."""
    return b if se.count_ops(b) < se.count_ops(a) else a


def collect_by_state(exprs: Sequence[se.Basic], state: Sequence[se.Symbol]) -> list[se.Basic]:
    """Group each sum's terms by their state-dependent factor, summing the constant coefficients.

    M of an n-link chain comes out of the virtual-power route as Σ over bodies of
    m_k (∂V_k/∂q̇_i · ∂V_k/∂q̇_j): O(n³) terms sharing O(n²) distinct functions of q.
    Writing it Σ_g (Σ_k m_k l_i l_j) g(q) makes the per-state cost O(n²): the coefficient
    sums hold only parameters, and `cse` computes each once.
    """
    state_set = set(state)
    out = []
    for expr in exprs:
        if not isinstance(expr, se.Add):
            out.append(expr)
            continue
        groups: dict[se.Basic, list[se.Basic]] = {}
        for term in expr.args:
            factors = term.args if isinstance(term, se.Mul) else (term,)
            const = [f for f in factors if not (f.free_symbols & state_set)]
            var = [f for f in factors if f.free_symbols & state_set]
            key = se.Mul(*var) if var else se.Integer(1)
            groups.setdefault(key, []).append(se.Mul(*const) if const else se.Integer(1))
        if len(groups) == len(expr.args):
            out.append(expr)
        else:
            out.append(se.Add(*(se.Add(*coeffs) * key for key, coeffs in groups.items())))
    return out


class Hoist:
    """Lift the parameter-only parts of expressions out of the per-state code.

    ``(m2 + m3 + m4) l1 l2 cos(θ1 − θ2)`` becomes ``_k7 cos(θ1 − θ2)`` with ``_k7`` computed
    once per parameter set (`lg_constants`), not at every state: for an n-link chain this
    removes the O(n³) coefficient arithmetic from M.
    """

    def __init__(self, parameters: Sequence[se.Symbol]) -> None:
        self.parameters = set(parameters)
        self.constants: dict[se.Basic, se.Symbol] = {}

    def _const(self, expr: se.Basic) -> se.Basic:
        if expr.is_Number or expr.is_Symbol:
            return expr
        if expr not in self.constants:
            self.constants[expr] = se.Symbol(f"_k{len(self.constants)}")
        return self.constants[expr]

    def __call__(self, expr: se.Basic) -> se.Basic:
        free = expr.free_symbols
        if free <= self.parameters:
            return self._const(expr)
        if isinstance(expr, (se.Add, se.Mul)):
            fixed = [a for a in expr.args if a.free_symbols <= self.parameters]
            varying = [self(a) for a in expr.args if not a.free_symbols <= self.parameters]
            op = se.Add if isinstance(expr, se.Add) else se.Mul
            if len(fixed) >= 2 or (fixed and not (fixed[0].is_Number or fixed[0].is_Symbol)):
                fixed = [self._const(op(*fixed))]
            return op(*fixed, *varying)
        if expr.args:
            return expr.func(*(self(a) for a in expr.args))
        return expr


def _shared_bias(eom: EquationsOfMotion) -> tuple[list[tuple[se.Symbol, se.Basic]], list[se.Basic]]:
    """F = Q − Γ⁰ with each body's γ⁰(G) and dσ⁰/dt named once (see `mass_matrix_and_bias`).

    Returns the named components (symbol, expression) and F written with them; falls back
    to ``eom.F`` when the equations carry more than that (e.g. terms the loads do not hold).
    """
    from ..dynamics import mass_matrix_and_bias

    shared: list[tuple[se.Symbol, se.Basic]] = []

    def share(components):
        out = []
        for c in components:
            if c == 0 or c.is_Number or c.is_Symbol or se.count_ops(c) < 4:
                out.append(c)
            else:
                # A named Symbol, not a Dummy: a Dummy's hash holds a per-process counter, so
                # SymEngine would order the sums that use it differently at every compile (a new
                # source, a cache miss, results a few ulp apart).  The leading underscore keeps it
                # apart from model names, which cannot start with one.
                sym = se.Symbol(f"_shared{len(shared)}")
                shared.append((sym, c))
                out.append(sym)
        return tuple(out)

    n = len(eom.q)
    _, gamma0 = mass_matrix_and_bias(eom.kinematics, eom.inertias, share=share)
    Q = [se.Add(*(load.Q[i] for load in eom.loads)) for i in range(n)]
    F = [q - g for q, g in zip(Q, gamma0, strict=True)]
    return shared, F


@dataclass(frozen=True)
class MassForcesForm:
    """M and F as the C code evaluates them: exact rewritings that make them cheaper.

    The fields are expressions over the model's own symbols, plus the names below.  Every sin/cos of
    a sum of coordinates is expanded (`expand_angle_sums`).

    Parameters
    ----------
    shared : tuple of (SymEngine Symbol, SymEngine expression)
        (symbol, expression) of each body's γ⁰(G) and dσ⁰/dt components (`_shared_bias`), to be
        computed first; M and F refer to the symbols.
    M : tuple of SymEngine expressions
        The n*n entries row by row, grouped by their function of q (`collect_by_state`).
    F : tuple of SymEngine expressions
        Q − Γ⁰, written with ``shared``.
    constants : tuple of (SymEngine Symbol, SymEngine expression)
        (``_k<j>``, expression of the parameters only) lifted out of all the above (`Hoist`):
        computed once per parameter set, not per state.
    """

    shared: tuple[tuple[se.Symbol, se.Basic], ...]
    M: tuple[se.Basic, ...]
    F: tuple[se.Basic, ...]
    constants: tuple[tuple[se.Symbol, se.Basic], ...]


def mass_forces_form(eom: EquationsOfMotion) -> MassForcesForm:
    """The package's C form of M and F: the in-package library and ``export --to c``.

    Parameters
    ----------
    eom : EquationsOfMotion
        The equations.

    Returns
    -------
    MassForcesForm
        M and F rewritten for C.
    """
    n = len(eom.q)
    state = (*eom.q, *eom.qd)
    # M's entries are sums over bodies of one function of q each: collect them.  F keeps
    # the nested form of the derivation, which shares more than its expansion would.
    M_flat = [smaller(e, collect_by_state([se.expand(e)], state)[0])
              for e in [eom.M[i][j] for i in range(n) for j in range(n)]]
    shared, F = _shared_bias(eom)
    flat = expand_angle_sums(M_flat + list(F) + [e for _, e in shared], eom.q)
    # Inputs are not hoisted: an input law (`numerics._input_code`) overwrites them state by state.
    hoist = Hoist([se.Symbol(p.name) for p in eom.model.parameters if not p.input])
    flat = [hoist(e) for e in flat]
    return MassForcesForm(
        shared=tuple((sym, e) for (sym, _), e in zip(shared, flat[n * n + n:], strict=True)),
        M=tuple(flat[: n * n]), F=tuple(flat[n * n: n * n + n]),
        constants=tuple((sym, expr) for expr, sym in hoist.constants.items()))
