"""The precession of the plane of small oscillations (Foucault's pendulum), by Larmor's theorem.

Two coordinates whose linearized equations read, with M = μ I isotropic and gyroscopic terms only,

    μ δq̈ + G δq̇ + K δq = 0,     G = [[0, γ], [−γ, 0]],

change to coordinates p turned by the angle ω_p t in the plane (δq₁, δq₂), δq = R(ω_p t) p, with
R(θ) the rotation from δq₁ towards δq₂.  Then δq̇ = R (ṗ + ω_p E p), E = [[0, −1], [1, 0]], G = −γ E
commutes with R, and

    μ p̈ + (2 μ ω_p − γ) E ṗ + (K + (γ ω_p − μ ω_p²) I) p = 0         (K = κ I),

so ω_p = γ / (2 μ) removes the gyroscopic term: p oscillates in a fixed plane, δq's plane turns at
ω_p.  When K is isotropic only up to terms of second order in a parameter s whose zero makes γ
vanish (Ω for the Foucault pendulum, whose K = m l (g I + O(Ω²))), the rate holds to first order
in s: −Ω sin λ for Foucault's pendulum (γ = −2 m l² Ω sin λ).
"""

from __future__ import annotations

from typing import Any

import symengine as se
import sympy

from ...._identity import are_zero
from ..build import Context
from ..document import Block, Display, Equation, Math, Para

__all__ = ["precession_blocks", "precession_rate"]


def _second_order_small(e: se.Basic, s: se.Symbol) -> bool:
    """``e`` and ∂e/∂s vanish at s = 0: e = O(s²)."""
    zero = {s: se.Integer(0)}
    return all(are_zero([e.xreplace(zero), e.diff(s).xreplace(zero)]))


def precession_rate(so: Any) -> tuple[se.Basic, se.Symbol | None] | None:
    """(ω_p = G₁₂ / (2 M₁₁), the parameter s to whose first order it holds, or None when K is isotropic), for a
    two-coordinate second-order form with M isotropic, no damping nor circulatory term, and G ≠ 0; else None."""
    if so is None or len(so.coordinates) != 2:
        return None
    M, G, K, D, N = so.M, so.G, so.K, so.D, so.N
    checks = [M[0, 1], M[1, 0], M[0, 0] - M[1, 1], G[0, 0], G[1, 1], G[0, 1] + G[1, 0],
              *(D[i, j] for i in range(2) for j in range(2)), *(N[i, j] for i in range(2) for j in range(2))]
    if not all(are_zero(checks)) or are_zero([G[0, 1]])[0]:
        return None
    rate = se.expand(G[0, 1] / (2 * M[0, 0]))
    anisotropy = [K[0, 1], K[1, 0], K[0, 0] - K[1, 1]]
    if all(are_zero(anisotropy)):
        return rate, None
    for s in sorted(G[0, 1].free_symbols - M[0, 0].free_symbols, key=str):
        if are_zero([G[0, 1].xreplace({s: se.Integer(0)})])[0] and all(_second_order_small(e, s) for e in anisotropy):
            return rate, s
    return None


def _value(c: Context, e: se.Basic) -> float | None:
    values = {p.symbol: se.Float(p.value) for p in c.model.parameters if p.value is not None}
    try:
        return float(e.xreplace(values))
    except (TypeError, RuntimeError, ValueError):
        return None


def precession_blocks(c: Context, so: Any) -> list[Block]:
    """The sentence on the oscillation plane's precession, with ω_p as a formula and its value, when it applies."""
    found = precession_rate(so)
    if found is None:
        return []
    rate, order = found
    w = c.w
    q1, q2 = (rf"\delta {c.sym(q)}" for q in so.coordinates)
    shown = sympy.simplify(rate._sympy_())
    blocks: list[Block] = [Para(w("precession" if order is None else "precession first order",
                                  plane=Math(rf"({q1},\ {q2})"), q1=Math(q1), q2=Math(q2),
                                  change=Math(r"\delta q = R(\omega_p t)\, p"), angle=Math(r"\omega_p t"),
                                  wp=Math(r"\omega_p"),
                                  s=Math(c.sym(str(order))) if order is not None else ""))]
    formula = rf"\omega_p = \frac{{G_{{12}}}}{{2\, M_{{11}}}} = {c.n.latex(shown)}"
    value = _value(c, rate)
    if value is not None:
        si = all(p.unit for p in c.model.parameters if p.value is not None)  # then t is in seconds
        formula += rf" \approx {w.number(value, 4)}" + (r"\ \mathrm{rad/s}" if si else "")
    blocks.append(Display((Equation((formula,)),)))
    return blocks
