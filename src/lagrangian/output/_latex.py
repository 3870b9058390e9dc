r"""LaTeX of a derivation: a complete document (``pdflatex`` compiles it) in the course's notation.

Time derivatives are dots (\dot{\theta}, \ddot{\theta}), angles are Greek letters
(φ is \varphi as in the seed), vectors carry arrows.
"""

from __future__ import annotations


from ._course import CourseForm
from ._notation import _axis_latex
from ._text import notation

__all__ = ["render_latex"]

_FORMULA = {
    "fixed point": r"\tfrac{1}{2}\,\vec{\Omega}\cdot\Pi\,\vec{\Omega}",
    "König": r"\tfrac{1}{2} m \vec{V}(G)^2 + \tfrac{1}{2}\,\vec{\Omega}\cdot\Pi_G\,\vec{\Omega}",
    "particle": r"\tfrac{1}{2} m \vec{V}(P)^2",
}


def _escape(text: str) -> str:
    for a, b in (("\\", r"\textbackslash{}"), ("&", r"\&"), ("%", r"\%"), ("$", r"\$"), ("#", r"\#"),
                 ("_", r"\_"), ("{", r"\{"), ("}", r"\}"), ("~", r"\textasciitilde{}"), ("^", r"\^{}")):
        text = text.replace(a, b)
    return text


def render_latex(form: CourseForm) -> str:
    """A standalone LaTeX document of the derivation."""
    n = notation(form)
    sym = lambda name: n.symbol(name, latex=True)  # noqa: E731
    out = [r"\documentclass[a4paper]{article}", r"\usepackage[utf8]{inputenc}", r"\usepackage{amsmath,amssymb}",
           r"\usepackage[margin=2cm]{geometry}", r"\allowdisplaybreaks", r"\begin{document}",
           rf"\section*{{{_escape(form.title)}}}"]
    if form.description:
        out.append(_escape(form.description) + r"\par")
    q = [sym(c) for c in form.coordinates]
    out.append(rf"Principal parameters ($n = {len(q)}$, hence ${len(q)}$ Lagrange equations): $" + ", ".join(q) + "$.")
    if form.frames:
        out.append(r"\subsection*{Frames and angular velocities}")
        out.append(r"\begin{align*}")
        rows = []
        for f in form.frames:
            rows.append(rf"&{f.parent} \xrightarrow{{{n.latex(f.angle)},\ {_axis_latex(f.axis)}}} {f.name}"
                        rf"({', '.join(_axis_latex(a) for a in f.axes)})")
        for f in form.frames:
            text = rf"\vec{{\Omega}}({f.name}/R_0) &= {n.vector(f.omega_chain.terms, latex=True)}"
            if f.omega_components is not None and n.vector(f.omega_components.terms, latex=True) != n.vector(f.omega_chain.terms, latex=True):
                text += rf" \\ &= {n.vector(f.omega_components.terms, latex=True)}"
            rows.append(text)
        out.append(r" \\".join(rows))
        out.append(r"\end{align*}")
    if form.virtual_velocities:
        out.append(r"\subsection*{Virtual velocity field}")
        out.append(r"\begin{align*}")
        out.append(r" \\".join(rf"\vec{{V}}^*({p}) &= {n.vector(row.terms, latex=True)}" for p, row in form.virtual_velocities))
        out.append(r"\end{align*}")
    out.append(r"\subsection*{Kinetic and potential energies}")
    out.append(r"\begin{align*}")
    rows = [rf"T({row.name}/R_0) &= {_FORMULA.get(row.formula, '')} = {n.latex(row.expression)}" for row in form.T]
    rows += [rf"U_P(\text{{{_escape(row.name)}}}) &= {n.latex(row.expression)} + \text{{cste}}" for row in form.U]
    out.append(r" \\".join(rows))
    out.append(r"\end{align*}")
    out.append(r"\subsection*{Generalized forces (virtual power)}")
    if form.loads:
        out.append(r"\begin{align*}")
        rows = []
        for load in form.loads:
            comps = r",\quad ".join(rf"Q_{{{qn}}} = {n.latex(Q)}" for qn, Q in zip(q, load.Q))
            tag = "conservative" if load.conservative else "non-conservative"
            rows.append(rf"&\text{{{_escape(load.name)} ({tag})}}: & {comps}")
        out.append(r" \\".join(rows))
        out.append(r"\end{align*}")
    out.append(r"\subsection*{Lagrange equations}")
    out.append(r"\begin{align*}")
    rows = []
    for eq in form.equations:
        qn, qd = sym(eq.coordinate), sym(eq.coordinate + "_dot")
        rows.append(rf"L({qn}):\quad & \frac{{\partial T}}{{\partial {qd}}} = {n.latex(eq.dT_dqd)};\quad "
                    rf"\frac{{\partial T}}{{\partial {qn}}} = {n.latex(eq.dT_dq)};\quad "
                    rf"\frac{{\partial U_P}}{{\partial {qn}}} = {n.latex(eq.dU_dq)};\quad Q_{{{qn}}} = {n.latex(eq.Q_nc)}")
        if eq.integral is not None:
            p = n.latex(eq.dT_dqd)
            rows.append(rf"& \frac{{d}}{{dt}}\left[{p}\right] = 0 \;\Rightarrow\; {p} = {eq.integral}")
        else:
            rows.append(rf"& {n.latex(eq.lhs)} = {n.latex(eq.rhs)}")
            if eq.using_integrals is not None:
                rows.append(rf"& {n.latex(eq.using_integrals)} = {n.latex(eq.rhs)}")
    out.append(r" \\".join(rows))
    out.append(r"\end{align*}")
    if form.conservative and form.L is not None:
        out.append(r"The system is conservative (Remarque 2): $L = T - U_P$ and "
                   r"$\frac{d}{dt}\frac{\partial L}{\partial \dot q_i} - \frac{\partial L}{\partial q_i} = 0$.")
    out.append(r"\subsection*{First integrals}")
    if form.integrals:
        out.append(r"\begin{align*}")
        out.append(r" \\".join(rf"{n.sum(i.parts, latex=True)} &= {i.name}" for i in form.integrals))
        out.append(r"\end{align*}")
    else:
        out.append("None found.")
    out.append(r"\subsection*{Matrix form $M(q,t)\,\ddot q = F(q,\dot q,t)$}")
    out.append(r"\begin{align*}")
    rows = []
    for a, row in enumerate(form.M):
        for b, entry in enumerate(row):
            if b >= a and entry != 0:
                rows.append(rf"M_{{{q[a]}{q[b]}}} &= {n.latex(entry)}")
    rows += [rf"F_{{{q[a]}}} &= {n.latex(f)}" for a, f in enumerate(form.F)]
    out.append(r" \\".join(rows))
    out.append(r"\end{align*}")
    out.append(r"\end{document}")
    return "\n".join(out) + "\n"
