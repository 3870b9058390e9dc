"""The model's equations at one collocation point, as CasADi functions of z = (q, q̇, q̈, u, λ) and t.

The dynamics enter the optimization implicitly, as the rows

    M(q, t) q̈ − F(q, q̇, u, t) − Aᵀ(q, t) λ = 0        (n rows; the course's M q̈ = F, seed step 7)
    A(q, t) q̈ + c(q, q̇, t) = 0                          (m rows, complementary constraints only)

with q̈ and λ decision variables: neither M nor A M⁻¹ Aᵀ is ever inverted, and CasADi differentiates
the rows exactly.  The constraints are kept at acceleration level (the index-1 form the simulator
integrates, `numerics._dae`); their position and velocity levels,

    f_k(q, t) = 0 (holonomic rows),      A q̇ + b = 0,

are `PointFunctions.manifold`, imposed where the motion starts (Bordalba, Porta & Ros, *Direct
collocation methods for trajectory optimization in constrained robotic systems*, IEEE T-RO 39,
2023: imposing all three levels at every point over-determines the problem).

A kinematic tree derived in recursive form (`dynamics._recursive`) gives its M and F over named
intermediates, which are converted once each (`_casadi.casadi_expressions`).
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import symengine as se

from ..dynamics import EquationsOfMotion
from ._casadi import casadi, casadi_expressions
from ._layout import Layout

__all__ = ["PointFunctions", "point_functions", "symbol_map"]


@dataclass(frozen=True)
class PointFunctions:
    """CasADi functions of (z, t) at one collocation point (module docstring).

    Attributes
    ----------
    z, t : the ``SX`` symbols they are functions of (z as `Layout` orders it).
    symbols : SymEngine symbol → its ``SX`` (or its value, for a parameter), for further expressions.
    dynamics : (z, t) → the n + m implicit rows.
    energies : (z, t) → (T, U).
    manifold : (z, t) → (f of the holonomic rows, A q̇ + b of every row); None without constraints.
    """

    z: Any
    t: Any
    symbols: Mapping[se.Basic, Any]
    dynamics: Any
    energies: Any
    manifold: Any | None


def symbol_map(layout: Layout, z: Any, t: Any, values: Mapping[str, float]) -> dict[se.Basic, Any]:
    """SymEngine symbol → the entry of ``z``, ``t``, or the parameter's value (folded as a constant)."""
    out: dict[se.Basic, Any] = {s: z[k] for k, s in enumerate(layout.symbols)}
    out[layout.t] = t
    for name, symbol in layout.parameters.items():
        if name in values:
            out[symbol] = values[name]
    return out


def point_functions(eom: EquationsOfMotion, layout: Layout, values: Mapping[str, float]) -> PointFunctions:
    """The `PointFunctions` of ``eom`` with the parameter values ``values`` folded in."""
    ca = casadi()
    n, m = layout.n, len(layout.multipliers)
    z = ca.SX.sym("z", layout.width)
    t = ca.SX.sym("t")
    symbols = symbol_map(layout, z, t, values)
    rec = eom.recursive
    if rec is not None:  # M, F, T, U over the recursive form's intermediates
        M_rows, F_list, T, U = rec.M, rec.F, rec.T, rec.U
    else:
        M_rows, F_list, T, U = eom.M, eom.F, eom.T, eom.U
    rows = eom.constraints
    outputs = [*(M_rows[i][j] for i in range(n) for j in range(n)), *F_list,
               *(a for row in rows for a in row.coefficients), *(row.bias for row in rows), T, U]
    manifold_exprs = [*(row.expression for row in rows if row.kind == "holonomic"),
                      *(row.velocity for row in rows)]
    outputs += manifold_exprs
    definitions = rec.needed(outputs) if rec is not None else ()
    sx = casadi_expressions(outputs, symbols, definitions=definitions)
    k = 0

    def take(count: int) -> list[Any]:
        nonlocal k
        part = sx[k:k + count]
        k += count
        return part

    M = ca.reshape(ca.vertcat(*take(n * n)), n, n).T  # row by row
    F = ca.vertcat(*take(n))
    A = ca.reshape(ca.vertcat(*take(m * n)), n, m).T if m else ca.SX(0, n)
    c = ca.vertcat(*take(m)) if m else ca.SX(0, 1)
    energy = take(2)
    manifold_sx = take(len(manifold_exprs))
    qdd = z[layout.slice("qdd")]
    lam = z[layout.slice("lambda")]
    residual = ca.mtimes(M, qdd) - F
    if m:
        residual = ca.vertcat(residual - ca.mtimes(A.T, lam), ca.mtimes(A, qdd) + c)
    dynamics = ca.Function("dynamics", [z, t], [residual], ["z", "t"], ["residual"])
    energies = ca.Function("energies", [z, t], [ca.vertcat(*energy)], ["z", "t"], ["TU"])
    manifold = ca.Function("manifold", [z, t], [ca.vertcat(*manifold_sx)], ["z", "t"], ["fg"]) if m else None
    return PointFunctions(z, t, symbols, dynamics, energies, manifold)
