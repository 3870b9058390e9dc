"""Terminal text of a derivation, in the order of the course's "démarche d'application"."""

from __future__ import annotations

import re


from ._course import CourseForm
from ._notation import Notation

__all__ = ["render_text"]

_FORMULA = {
    "fixed point": "½ Ω·Π_{P}·Ω",
    "König": "½ m V(G)² + ½ Ω·Π_G·Ω  (König)",
    "particle": "½ m V(P)²",
}


def notation(form: CourseForm) -> Notation:
    """The notation of a derivation; first-integral constants (K, H) order like parameters."""
    return Notation(form.coordinates, form.parameters + tuple(i.name for i in form.integrals))


def greek(n: Notation, form: CourseForm, sentence: str) -> str:
    """Write the coordinate names of a sentence in the course's letters (psi → ψ)."""
    for name in form.coordinates:
        sentence = re.sub(rf"(?<![A-Za-z0-9]){re.escape(name)}(?![A-Za-z0-9])", n.symbol(name), sentence)
    return sentence


def render_text(form: CourseForm) -> str:
    """The derivation as plain Unicode text (ψ̇, θ̈, sin²θ...)."""
    n = notation(form)
    q = [n.symbol(c) for c in form.coordinates]
    lines = [form.title]
    if form.description:
        lines.append(form.description)
    lines.append("")
    count = len(form.coordinates)
    lines.append(f"Principal parameters (n = {count}, hence {count} Lagrange equation{'s' * (count > 1)}): "
                 + ", ".join(q))
    if form.frames:
        lines.append("")
        lines.append("Frames (R0 is Galilean) and angular velocities:")
        for f in form.frames:
            lines.append(f"  {f.parent} --({n.text(f.angle)}, {f.axis})--> {f.name}({', '.join(f.axes)})")
        for f in form.frames:
            text = f"  Ω({f.name}/R0) = {n.vector(f.omega_chain.terms)}"
            if f.omega_components is not None:
                alt = n.vector(f.omega_components.terms)
                if alt != n.vector(f.omega_chain.terms):
                    text += f" = {alt}"
            lines.append(text)
    if form.virtual_velocities:
        lines.append("")
        lines.append("Virtual velocity field compatible with the principal constraints, V*(P) = Σ ∂OP/∂q_i q_i*:")
        for point, row in form.virtual_velocities:
            lines.append(f"  V*({point}) = {n.vector(row.terms)}")
    lines.append("")
    lines.append("Kinetic energy T(Σ/R0):")
    for row in form.T:
        lines.append(f"  T({row.name}/R0) = {n.text(row.expression)}    [{row.formula}]")
    lines.append("Potential energy U_P(Σ/R0) (+ cste):")
    if form.U:
        for row in form.U:
            lines.append(f"  {row.name}: {n.text(row.expression)}")
    else:
        lines.append("  none: no given effort derives from a potential")
    lines.append("")
    lines.append("Generalized forces, by virtual power:")
    for load in form.loads:
        tag = "conservative, Q_i = −∂U/∂q_i" if load.conservative else "non-conservative"
        comps = ";  ".join(f"Q_{qn} = {n.text(Q)}" for qn, Q in zip(q, load.Q))
        lines.append(f"  {load.name} ({load.kind}, {tag}): {comps}")
    if not form.loads:
        lines.append("  none")
    lines.append("")
    lines.append("Lagrange equations  d/dt(∂T/∂q̇_i) − ∂T/∂q_i = −∂U/∂q_i + Q_i(nc):")
    for eq in form.equations:
        qn = n.symbol(eq.coordinate)
        qd = n.symbol(eq.coordinate + "_dot")
        lines.append(f"  L({qn})  ∂T/∂{qd} = {n.text(eq.dT_dqd)};  ∂T/∂{qn} = {n.text(eq.dT_dq)};  "
                     f"∂U/∂{qn} = {n.text(eq.dU_dq)};  Q_{qn}(nc) = {n.text(eq.Q_nc)}")
        if eq.integral is not None:
            p = n.text(eq.dT_dqd)
            lines.append(f"        d/dt[{p}] = 0   ⇒   {p} = {eq.integral}")
        else:
            lines.append(f"        {n.text(eq.lhs)} = {n.text(eq.rhs)}")
            if eq.using_integrals is not None:
                lines.append(f"        or, with the first integrals: {n.text(eq.using_integrals)} = {n.text(eq.rhs)}")
    if form.conservative and form.L is not None:
        lines.append(f"  The system is conservative (Remarque 2): L = T − U_P = {n.sum((form.T_total, -form.U_total))}")
    lines.append("")
    lines.append("First integrals:")
    if not form.integrals:
        lines.append("  none found")
    for i in form.integrals:
        lines.append(f"  {n.sum(i.parts)} = {i.name}    ({greek(n, form, i.reason)})")
    lines.append("")
    lines.append("Matrix form M(q, t) q̈ = F(q, q̇, t):")
    for a, row in enumerate(form.M):
        for b, entry in enumerate(row):
            if b >= a and entry != 0:
                lines.append(f"  M[{q[a]},{q[b]}] = {n.text(entry)}")
    for a, f in enumerate(form.F):
        lines.append(f"  F[{q[a]}] = {n.text(f)}")
    return "\n".join(lines) + "\n"
