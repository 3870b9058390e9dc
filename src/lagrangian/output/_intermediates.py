"""A robot's equations over the named intermediates of its recursive form, as terminal text.

``lagrangian derive --intermediates``: T, U, the entries of M and F of M q̈ = F, each a short
expression of named intermediates w_k, then every intermediate with its formula, in the
order the compiled code computes them (`dynamics._recursive`: the link velocities and
accelerations, the Newton–Euler forces and moments, the composite inertias of
Featherstone's RNEA and CRBA, *Rigid Body Dynamics Algorithms*, 2008, ch. 5–6).  The
listing grows about linearly with the joints for F and quadratically for M, where the
expanded course entries grow several-fold per joint.
"""

from __future__ import annotations

import symengine as se

from ..dynamics import EquationsOfMotion, RecursiveForm
from ..model.vectors import as_expr
from ._course import to_sympy
from ._notation import Notation

__all__ = ["needed_intermediates", "render_intermediates"]


def needed_intermediates(rec: RecursiveForm) -> list[tuple[se.Symbol, se.Basic]]:
    """The intermediates T, U, M and F need, in computing order (the gradient's are left out).

    Parameters
    ----------
    rec : RecursiveForm
        The recursive form.

    Returns
    -------
    list of (SymEngine Symbol, SymEngine expression)
        The intermediates, in computing order.
    """
    return rec.needed([rec.T, rec.U, *(e for row in rec.M for e in row), *rec.F])


def render_intermediates(eom: EquationsOfMotion) -> str:
    """T, U, M and F over the intermediates of ``eom.recursive``, then the intermediates (module docstring).

    Parameters
    ----------
    eom : EquationsOfMotion
        Equations with a recursive form.

    Returns
    -------
    str
        The text.
    """
    rec = eom.recursive
    assert rec is not None, "a recursive form is needed"
    model = eom.model
    n = Notation(tuple(eom.coordinates), tuple(p.name for p in model.parameters))
    taken = {c for c in eom.coordinates} | {p.name for p in model.parameters}
    prefix = next(p for p in ("w", "W", "w_", "W_", "aux") if not any(
        name.startswith(p) and name[len(p):].isdigit() for name in taken))  # never a model's own name
    names = {s: se.Symbol(f"{prefix}{k}") for k, (s, _) in enumerate(rec.intermediates)}  # k: computing order

    def text(e: se.Basic) -> str:
        return n.text(to_sympy(as_expr(e).xreplace(names)))

    coordinates = [n.symbol(c) for c in eom.coordinates]
    needed = needed_intermediates(rec)
    lines = [model.name]
    if model.description:
        lines.append(model.description)
    lines += ["", f"Principal parameters (n = {len(coordinates)}): " + ", ".join(coordinates)]
    if model.inputs:
        lines.append("Inputs: " + ", ".join(model.inputs))
    lines += ["", f"Recursive form (symbolic recursive Newton–Euler and composite-rigid-body algorithms, "
                  f"docs/robots.md): {len(needed)} named intermediates {prefix}k, listed below, each an expression of "
                  "q, q̇, the parameters and earlier names.", ""]
    lines.append(f"T = {text(rec.T)}")
    lines.append(f"U = {text(rec.U)}" + ("" if rec.conservative else
                                        "    (the loads without a potential enter F, not U)"))
    lines += ["", "M(q) q̈ = F(q, q̇):"]
    for i, row in enumerate(rec.M):
        for j in range(i, len(row)):
            lines.append(f"  M[{coordinates[i]},{coordinates[j]}] = {text(row[j])}")
    for i, f in enumerate(rec.F):
        lines.append(f"  F[{coordinates[i]}] = {text(f)}")
    lines += ["", "where"]
    lines += [f"  {text(s)} = {text(e)}" for s, e in needed]
    return "\n".join(lines) + "\n"
