"""Reduction to one coordinate: the cyclic rates solved from their momenta, the effective potential.

When every coordinate but one (θ) is cyclic, each cyclic momentum is a first integral
(the seed's K for ψ and H for φ).  The momenta are linear in the cyclic rates ċ:

    p = M_cc ċ + M_cθ θ̇ + B        (M the mass matrix, B = ∂T1/∂ċ),

so ċ = M_cc⁻¹ (P − B − M_cθ θ̇) with P the constant values (K, H).  Put in the energy
(or Painlevé–Jacobi) integral T2 − T0 + U, the cross terms in θ̇ cancel and

    E = ½ a(θ) θ̇² + U_eff(θ),   a = M_θθ − M_θc M_cc⁻¹ M_cθ,
    U_eff(θ) = ½ (P − B)ᵀ M_cc⁻¹ (P − B) − T0 + U,

a one-degree-of-freedom problem: θ moves where U_eff(θ) ≤ E, between turning angles
θ1 ≤ θ2 where U_eff(θ) = E.  For the top, ψ̇ = (K − H cosθ)/(A sin²θ) and
U_eff = (K − H cosθ)²/(2A sin²θ) + H²/(2C) + m g a cosθ.

M_cc⁻¹ is written with the adjugate and the (expanded) determinant, adj(M_cc)/det M_cc,
which keeps the expressions short (det = A C sin²θ for the top).  The substitution in
the energy is checked against ½ a θ̇² + U_eff by the randomized identity test.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
import numpy.typing as npt
import symengine as se
from symengine.lib.symengine_wrapper import sympy2symengine

from .._identity import are_zero
from ..dynamics import EquationsOfMotion
from ..errors import AnalysisError
from ..model.spec import GALILEAN_FRAME
from ._integrals import first_integrals

if TYPE_CHECKING:
    import sympy

__all__ = [
    "Curve",
    "CyclicReduction",
    "EffectivePotential",
    "SingularPassage",
    "StructureError",
    "reduce_cyclic",
    "tidy",
    "turning_points",
    "well_integrals",
]


class StructureError(AnalysisError):
    """The model lacks the structure an analysis needs (e.g. cyclic coordinates, an energy integral).

    Parameters
    ----------
    message : str
        What was wrong, a full sentence naming the culprit in backticks.
    fix : str, optional
        How to fix it, printed after the message.
    """


class SingularPassage(AnalysisError):
    """The remaining coordinate runs through a value where the coordinates are singular (θ = 0 or π)."""


@dataclass(frozen=True, slots=True)
class CyclicReduction:
    """The energy integral reduced to the one non-cyclic coordinate θ: E = ½ a(θ) θ̇² + U_eff(θ).

    Parameters
    ----------
    model_name : str
        The model's name.
    coordinate : str
        The remaining coordinate θ.
    symbol : SymEngine Symbol
        Its symbol.
    rate : SymEngine Symbol
        The symbol of θ̇.
    cyclic : tuple of str
        The cyclic coordinates, in model order.
    cyclic_rates : tuple of SymEngine Symbol
        Their rate symbols ċ.
    momenta : tuple of str
        K, H, ... (one per cyclic coordinate).
    momentum_symbols : tuple of SymEngine Symbol
        The constants' symbols.
    momentum_expressions : tuple of SymEngine expressions
        The momenta p_i = ∂T/∂ċ_i.
    energy_name : str
        ``"E"`` (T + U) or ``"h"`` (T2 − T0 + U).
    energy_expression : SymEngine expression
        That integral's expression.
    rates : tuple of SymEngine expressions
        The rates ċ_i(θ, θ̇, K, H) solved from the momenta.
    inertia : SymEngine expression
        The coefficient a(θ).
    effective_potential : SymEngine expression
        U_eff(θ, K, H).
    block : tuple of tuples of SymEngine expressions
        M_cc, the block of M of the cyclic rates.
    determinant : SymEngine expression
        The determinant det M_cc (expanded).
    numerator : SymEngine expression
        N = (P − B)ᵀ adj(M_cc) (P − B), so U_eff = N/(2 det) + W.
    regular_part : SymEngine expression
        W = U − T0.
    offset : tuple of SymEngine expressions
        B = ∂T1/∂ċ at ċ = θ̇ = 0 (zero unless T has terms linear in the rates).
    angle : bool
        True when θ is a rotation angle of a frame (so θ = 0 or π may be a sleeping position).
    precession : str
        The cyclic coordinate of the rotation about an axis fixed in R0 (ψ).
    spin : str or None
        With exactly two cyclic coordinates, the other one (φ); else None.
    """

    model_name: str
    coordinate: str
    symbol: se.Symbol
    rate: se.Symbol
    cyclic: tuple[str, ...]
    cyclic_rates: tuple[se.Symbol, ...]
    momenta: tuple[str, ...]
    momentum_symbols: tuple[se.Symbol, ...]
    momentum_expressions: tuple[se.Basic, ...]
    energy_name: str
    energy_expression: se.Basic
    rates: tuple[se.Basic, ...]
    inertia: se.Basic
    effective_potential: se.Basic
    block: tuple[tuple[se.Basic, ...], ...]
    determinant: se.Basic
    numerator: se.Basic
    regular_part: se.Basic
    offset: tuple[se.Basic, ...]
    angle: bool
    precession: str
    spin: str | None

    def momentum_of(self, coordinate: str) -> se.Symbol:
        """The symbol of the constant momentum of cyclic ``coordinate`` (K for ψ).

        Parameters
        ----------
        coordinate : str
            A cyclic coordinate.

        Returns
        -------
        SymEngine Symbol
            The symbol of its constant momentum.
        """
        return self.momentum_symbols[self.cyclic.index(coordinate)]


def _structure_error(eom: EquationsOfMotion, cyclic: list[str], remaining: list[str]) -> StructureError:
    name = eom.model.name
    found = f"`{name}` has " + (f"{len(cyclic)} cyclic ({', '.join(cyclic)})" if cyclic else "none cyclic")
    found += f" and {len(remaining)} remaining" + (f" ({', '.join(remaining)})" if remaining else "")
    return StructureError(
        f"analyse_top needs one remaining coordinate with every other coordinate cyclic (the heavy symmetric "
        f"top: ψ and φ cyclic, θ remaining); {found}. Each cyclic coordinate gives a constant momentum (K, H) "
        f"that eliminates its rate, which is what leaves the one-coordinate problem E = ½ a(θ) θ̇² + U_eff(θ).",
        fix="analyse a model of this structure (a symmetric top, a spherical pendulum, a central-force "
            "problem); a coordinate is cyclic when L does not depend on it and no non-conservative effort "
            "works on it")


def _determinant(m: list[list[se.Basic]]) -> se.Basic:
    if len(m) == 1:
        return m[0][0]
    if len(m) == 2:
        return m[0][0] * m[1][1] - m[0][1] * m[1][0]
    return se.Matrix(m).det()


def _adjugate(m: list[list[se.Basic]]) -> list[list[se.Basic]]:
    n = len(m)
    if n == 1:
        return [[se.Integer(1)]]
    adj = [[se.Integer(0)] * n for _ in range(n)]
    for i in range(n):
        for j in range(n):
            minor = [[m[r][c] for c in range(n) if c != j] for r in range(n) if r != i]
            adj[j][i] = (-1) ** (i + j) * _determinant(minor)
    return adj


def _quadratic_form(vector: list[se.Basic], matrix: list[list[se.Basic]], other: list[se.Basic]) -> se.Basic:
    return se.Add(*(vector[i] * matrix[i][j] * other[j] for i in range(len(vector)) for j in range(len(other))))


def _precession(eom: EquationsOfMotion, cyclic: list[str]) -> str:
    """The cyclic coordinate whose rotation turns a frame about an axis fixed in R0 (ψ for the top)."""
    symbols = dict(zip(eom.coordinates, eom.q, strict=True))
    for frame in eom.model.frames:
        if frame.parent == GALILEAN_FRAME and frame.rotation is not None:
            for name in cyclic:
                if frame.rotation.angle == symbols[name]:
                    return name
    return cyclic[0]


def reduce_cyclic(eom: EquationsOfMotion) -> CyclicReduction:
    """Eliminate the cyclic rates with their momenta: E = ½ a(θ) θ̇² + U_eff(θ).

    Parameters
    ----------
    eom : EquationsOfMotion
        Equations of motion with one non-cyclic coordinate, the others cyclic, and an energy (or
        Painlevé–Jacobi) integral.

    Returns
    -------
    CyclicReduction
        The rates solved from the momenta, a(θ) and U_eff(θ).

    Raises
    ------
    StructureError
        When the model has no cyclic coordinate, more than one remaining coordinate, no
        energy integral, or cyclic momenta that cannot be solved for the rates.

    Examples
    --------
    >>> import lagrangian
    >>> r = reduce_cyclic(lagrangian.derive(lagrangian.lagrange_top()))
    >>> r.cyclic, r.coordinate, r.momenta, r.inertia
    (('psi', 'phi'), 'theta', ('K', 'H'), A)
    """
    integrals = first_integrals(eom)
    momenta = {f.coordinate: f for f in integrals if f.kind == "momentum"}
    names = list(eom.coordinates)
    cyclic = [n for n in names if n in momenta]
    remaining = [n for n in names if n not in momenta]
    if not cyclic or len(remaining) != 1:
        raise _structure_error(eom, cyclic, remaining)
    energy = next((f for f in integrals if f.kind in ("energy", "jacobi")), None)
    if energy is None:
        raise StructureError(
            f"analyse_top needs the energy integral, and `{eom.model.name}` has none: L depends on t "
            "explicitly or non-conservative efforts do work, so E = ½ a(θ) θ̇² + U_eff(θ) is not constant.",
            fix="analyse a conservative model whose Lagrangian does not depend on time")
    ci = [names.index(n) for n in cyclic]
    r = names.index(remaining[0])
    theta, theta_dot = eom.q[r], eom.qd[r]
    rates = [eom.qd[i] for i in ci]
    P = [se.Symbol(momenta[n].name) for n in cyclic]
    p_expr = [momenta[n].expression for n in cyclic]
    M = eom.M
    block = [[M[i][j] for j in ci] for i in ci]
    coupling = [M[i][r] for i in ci]
    rest = {qd: 0 for qd in eom.qd}
    B = [se.expand(p.subs(rest)) for p in p_expr]
    det = se.expand(_determinant(block))
    if are_zero([det])[0]:
        raise StructureError(
            f"The momenta of {', '.join(cyclic)} cannot be solved for their rates: det M_cc is identically zero.",
            fix="describe the system with independent coordinates")
    adj = _adjugate(block)
    free = [P[i] - B[i] for i in range(len(P))]
    shifted = [free[i] - coupling[i] * theta_dot for i in range(len(P))]
    solved = [se.Add(*(adj[i][j] * shifted[j] for j in range(len(P)))) / det for i in range(len(P))]
    T0 = se.expand(eom.T.subs(rest))
    W = eom.U - T0
    N = se.expand(_quadratic_form(free, adj, free))
    U_eff = N / (2 * det) + W
    if all(are_zero(coupling)):
        a = M[r][r]
    else:
        a = (M[r][r] * det - _quadratic_form(coupling, adj, coupling)) / det
    # The derivation, checked: the momenta give back P, and E(ċ(θ, θ̇)) = ½ a θ̇² + U_eff.
    back = dict(zip(rates, solved, strict=True))
    checks = [p.subs(back) - Pi for p, Pi in zip(p_expr, P, strict=True)]
    checks.append(energy.expression.subs(back) - (a * theta_dot**2 / 2 + U_eff))
    allowed = {theta, *P} | {se.Symbol(p.name) for p in eom.model.parameters}
    if not all(are_zero(checks)) or not (U_eff.free_symbols | a.free_symbols) <= allowed:
        raise StructureError(
            f"The energy of `{eom.model.name}` does not reduce to a function of {remaining[0]} and "
            f"{remaining[0]}_dot alone once the cyclic rates are eliminated.",
            fix="check that the coordinates reported as cyclic really are absent from T and U")
    angle = any(f.rotation is not None and theta in f.rotation.angle.free_symbols for f in eom.model.frames)
    precession = _precession(eom, cyclic)
    spin = next((n for n in cyclic if n != precession), None) if len(cyclic) == 2 else None
    return CyclicReduction(
        model_name=eom.model.name, coordinate=remaining[0], symbol=theta, rate=theta_dot,
        cyclic=tuple(cyclic), cyclic_rates=tuple(rates), momenta=tuple(momenta[n].name for n in cyclic),
        momentum_symbols=tuple(P), momentum_expressions=tuple(p_expr), energy_name=energy.name,
        energy_expression=energy.expression, rates=tuple(solved), inertia=a, effective_potential=U_eff,
        block=tuple(tuple(row) for row in block), determinant=det, numerator=N, regular_part=W,
        offset=tuple(B), angle=angle, precession=precession, spin=spin)


# -- display ---------------------------------------------------------------------------------


def _orient(base: sympy.Expr, order: Sequence[sympy.Symbol]) -> tuple[sympy.Expr, int]:
    """±base, with the sign that makes the term of the earliest symbol in ``order`` positive."""
    import sympy

    terms = sympy.Add.make_args(base)
    for symbol in order:
        for term in terms:
            if term.has(symbol):
                return (-base, -1) if term.could_extract_minus_sign() else (base, 1)
    return base, 1


def _oriented(expr: sympy.Expr, order: Sequence[sympy.Symbol]) -> sympy.Expr:
    """A factored numerator with its sums written K − H cosθ rather than −K + H cosθ."""
    import sympy

    sign = 1
    factors = []
    for f in sympy.Mul.make_args(expr):
        if isinstance(f, sympy.Add):
            f, s = _orient(f, order)
            sign *= s
        elif isinstance(f, sympy.Pow) and isinstance(f.base, sympy.Add) and f.exp.is_Integer:
            base, s = _orient(f.base, order)
            f = base**f.exp
            sign *= s ** int(f.exp)
        factors.append(f)
    return sign * sympy.Mul(*factors)


def tidy(expr: se.Basic, order: Sequence[se.Symbol] = ()) -> se.Basic:
    """The textbook form of a rational expression in sin/cos: terms over a common denominator, factored.

    (K² − 2KH cosθ + H² cos²θ)/(2A sin²θ) becomes (K − H cosθ)²/(2A sin²θ).  Only the
    writing changes (expand, group by denominator, factor); ``order`` lists the symbols
    whose term should come first with a + sign (the momenta K, H).
    """
    import sympy  # late: SymPy takes most of a second to load, and only this needs it

    order_sympy = [s._sympy_() for s in order]
    groups: dict[sympy.Expr, list[sympy.Expr]] = {}
    for term in sympy.Add.make_args(sympy.expand(expr._sympy_())):
        coeff, rest = term.as_coeff_Mul()
        num, den = sympy.fraction(rest)
        groups.setdefault(den, []).append(coeff * num)
    out = sympy.Add(*(_oriented(sympy.factor(sympy.Add(*nums)), order_sympy) / den for den, nums in groups.items()))
    return sympy2symengine(out)


# -- numbers ---------------------------------------------------------------------------------


class Curve:
    """Expressions of θ alone (numbers substituted) as one numeric function; arrays in, arrays out.

    ``curve(x)`` has shape ``x.shape + (len(expressions),)``; ``curve.scalar(x)`` the
    first expression at a float.
    """

    def __init__(self, symbol: se.Symbol, expressions: Sequence[se.Basic]) -> None:
        self.expressions = tuple(expressions)
        self._f = se.Lambdify([symbol], list(self.expressions), cse=True)

    def __call__(self, x: npt.ArrayLike) -> np.ndarray:
        arr = np.asarray(x, dtype=float)
        flat = np.ascontiguousarray(arr.reshape(-1))
        with np.errstate(all="ignore"):
            out = np.asarray(self._f(flat), dtype=float)
        return out.reshape(arr.shape + (len(self.expressions),))

    def scalar(self, x: float) -> float:
        return float(self(np.array([x]))[0, 0])


class EffectivePotential:
    """U_eff(θ) with the parameter and momentum values in it: ``U_eff(0.5)``, ``U_eff(array)``."""

    def __init__(self, symbol: se.Symbol, expression: se.Basic) -> None:
        self.expression = expression
        self._curve = Curve(symbol, [expression])

    def __call__(self, theta: npt.ArrayLike) -> float | np.ndarray:
        out = self._curve(theta)[..., 0]
        return float(out) if out.ndim == 0 else out

    def __repr__(self) -> str:
        return f"EffectivePotential({self.expression})"


Gap = Callable[[npt.ArrayLike], "float | np.ndarray"]

#: Offsets from θ0 scanned for the first sign change of E − U_eff: fine near θ0 (small
#: nutations of a fast top), then every π/2048 up to π, then growing (non-angle coordinates).
_SCAN = np.concatenate([np.geomspace(1e-10, np.pi / 2048, 40, endpoint=False),
                        np.arange(1, 2049) * (np.pi / 2048),
                        np.pi * 1.25 ** np.arange(1, 100)])
#: Bisection steps to locate where E − U_eff stops being finite (a singular θ).
_BISECTIONS = 200


def _turning_point(gap: Gap, start: float, direction: int, angle: bool, name: str) -> float:
    """The first θ from ``start`` in ``direction`` where the kinetic part E − U_eff(θ) reaches 0."""
    offsets = _SCAN[_SCAN <= 2 * np.pi] if angle else _SCAN
    xs = start + direction * offsets
    values = np.asarray(gap(xs), dtype=float)
    bad = np.flatnonzero(~(values > 0))
    if len(bad) == 0:
        raise AnalysisError(
            f"The motion is not bounded: E − U_eff({name}) stays positive for {name} "
            f"{'below' if direction < 0 else 'above'} {start:.6g}, so {name} has no turning point there.",
            fix="analyse an initial state with less energy (a bounded nutation)")
    k = bad[0]
    inner = start if k == 0 else float(xs[k - 1])
    outer = float(xs[k])
    if not np.isfinite(values[k]):  # U_eff singular beyond: find the edge, then the root before it
        for _ in range(_BISECTIONS):
            mid = 0.5 * (inner + outer)
            if mid in (inner, outer):
                break
            if gap(mid) > 0:
                inner = mid
            else:
                outer = mid
            if np.isfinite(gap(outer)):
                break
        if not np.isfinite(gap(outer)):
            raise SingularPassage(
                f"{name} reaches {outer:.9g}, where U_eff is singular, with {name}_dot ≠ 0: the coordinates "
                f"are singular there (for Euler angles, the axis passes through the vertical).",
                fix="analyse an initial state for which the axis does not pass through the singular direction")
    if gap(outer) == 0.0:
        return outer
    from scipy import optimize  # late: SciPy takes tenths of a second to load, and only this needs it

    return float(optimize.brentq(lambda x: float(gap(x)), inner, outer, xtol=1e-15, rtol=4 * np.finfo(float).eps, maxiter=200))


def turning_points(gap: Gap, slope: Callable[[float], float], theta0: float, rate0: float,
                   *, angle: bool, name: str = "theta") -> tuple[float, float]:
    """θ1 ≤ θ2, the roots of E − U_eff(θ) = 0 that bracket θ0 (``gap`` = E − U_eff, ``slope`` = U_eff').

    ``gap`` takes a float or an array (the scan outwards from θ0 evaluates it on a grid).

    With θ̇0 = 0, θ0 is itself a turning angle (exactly, since E = U_eff(θ0) by
    construction); the side the motion goes to is where U_eff decreases.
    """
    if rate0 != 0.0:
        return (_turning_point(gap, theta0, -1, angle, name), _turning_point(gap, theta0, +1, angle, name))
    s = slope(theta0)
    if s == 0.0 or not np.isfinite(s):
        return theta0, theta0
    if s > 0:
        return _turning_point(gap, theta0, -1, angle, name), theta0
    return theta0, _turning_point(gap, theta0, +1, angle, name)


#: Midpoint-rule sizes tried for the well integrals (doubling until two agree).
_NODES = tuple(32 * 2**k for k in range(9))
#: Relative agreement of two successive midpoint sums that ends the doubling.
_QUADRATURE_RTOL = 1e-14


def well_integrals(curve: Curve, energy: float, lo: float, hi: float) -> np.ndarray:
    """2∫ f_k(θ) dθ/θ̇ over θ1..θ2 for f = (1, ċ_1, ċ_2, ...): the period, then each cyclic advance.

    ``curve`` gives (U_eff, a, ċ_1, ...) at θ; θ̇ = sqrt(2(E − U_eff)/a).  With
    θ = θ̄ − Δ cos s (θ̄, Δ the centre and half-width of [θ1, θ2]), dθ = Δ sin s ds and
    E − U_eff = Δ² sin²s h(θ) with h smooth and positive, so the integrand
    sqrt(a/(2h)) f is a smooth, even, 2π-periodic function of s: the midpoint rule on
    [0, π] converges exponentially (the trapezoidal rule on a periodic function).  Its
    nodes stay away from the turning angles, where E − U_eff is the difference of two
    nearly equal numbers; an adaptive rule that crowds nodes there (quad) chases that
    rounding noise and loses about sqrt(eps) — 1e-8 relative.
    """
    mid, half = 0.5 * (lo + hi), 0.5 * (hi - lo)
    previous = change = None
    for n in _NODES:
        s = (np.arange(n) + 0.5) * (np.pi / n)
        values = curve(mid - half * np.cos(s))
        kinetic = np.abs(energy - values[:, 0])
        jacobian = half * np.sin(s) * np.sqrt(values[:, 1] / (2 * kinetic))
        f = np.column_stack([np.ones(n), values[:, 2:]])
        total = 2.0 * (np.pi / n) * (jacobian[:, None] * f).sum(axis=0)
        if not np.all(np.isfinite(total)):
            raise AnalysisError("The nutation integrals are not finite: U_eff is singular between the turning "
                                "angles.", fix="check the model's parameter values and initial state")
        if previous is not None:
            new_change = float(np.abs(total - previous).max() / np.abs(total).max())
            if new_change <= _QUADRATURE_RTOL:
                return total
            if change is not None and new_change > change:  # rounding noise near the ends now dominates
                return previous
            change = new_change
        previous = total
    return total
