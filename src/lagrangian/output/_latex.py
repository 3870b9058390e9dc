r"""LaTeX of a derivation: a complete document (``pdflatex`` compiles it) in the course's notation.

Time derivatives are dots (\dot{\theta}, \ddot{\theta}), angles are Greek letters
(φ is \varphi as in the seed), vectors carry arrows.
"""

from __future__ import annotations

import re

from ._course import CourseForm
from ._notation import Notation, _axis_latex
from ._text import Supplement, as_declared, kind_words, notation, power_label

__all__ = ["render_latex"]

_FORMULA = {
    "fixed point": r"\tfrac{1}{2}\,\vec{\Omega}\cdot\Pi\,\vec{\Omega}",
    "König": r"\tfrac{1}{2} m \vec{V}(G)^2 + \tfrac{1}{2}\,\vec{\Omega}\cdot\Pi_G\,\vec{\Omega}",
    "particle": r"\tfrac{1}{2} m \vec{V}(P)^2",
}


#: Each special character of LaTeX's text mode and what writes it.  One pass over the text (a
#: translation table): replacing one character after another escaped the braces of
#: ``\textbackslash{}`` a second time (``\textbackslash\{\}`` printed a brace pair).
_ESCAPES = str.maketrans({"\\": r"\textbackslash{}", "&": r"\&", "%": r"\%", "$": r"\$", "#": r"\#", "_": r"\_",
                          "{": r"\{", "}": r"\}", "~": r"\textasciitilde{}", "^": r"\^{}"})


def _escape(text: str) -> str:
    r"""``text`` for LaTeX's text mode.

    >>> print(_escape(r"a\b_c {x} 50%"))
    a\textbackslash{}b\_c \{x\} 50\%
    """
    return text.translate(_ESCAPES)


def _frame(name: str) -> str:
    """R0 → R_0; other frame names as written (R1, R0(A))."""
    return "R_0" if name == "R0" else _escape(name)


def _constraints_latex(n, extra: Supplement) -> list[str]:
    out = [r"\subsection*{Constraints (step 1)}", r"\begin{itemize}"]
    declared = as_declared(n)  # the relations as the user wrote them, not rewritten
    for c in extra.constraints:
        if c.axes is None:
            statement = f"${declared.latex(c.statement[0])} = 0$"
        else:
            statement = ", ".join(f"${declared.latex(x)} = 0$ (${_axis_latex(a)}$)" for x, a in zip(c.statement, c.axes, strict=True)
                                  if x != 0) or "$0 = 0$"
        mult = (": multipliers $" + ", ".join(n.latex(_lam(row[1])) for row in c.rows) + "$") if c.rows else ""
        out.append(rf"\item \texttt{{{_escape(c.name)}}} ({c.role}, {_escape(c.form.replace('_', ' '))}): "
                   f"{statement}{mult}")
    out.append(r"\end{itemize}")
    return out


def _lam(name: str):
    import sympy

    return sympy.Symbol(name)


def _step7_latex(n, form: CourseForm, extra: Supplement) -> list[str]:
    q = [n.symbol(c, latex=True) for c in form.coordinates]
    out = [r"\subsection*{Complementary equations (step 7), multipliers and reactions}", r"\begin{align*}"]
    rows = [rf"{n.latex(eq)} &= 0 && \text{{{_escape(row)}}}" for c in extra.constraints for row, _, eq in c.rows]
    for name, formula in extra.multipliers:
        value = n.latex(formula) if formula is not None else r"\text{(solved along a motion)}"
        rows.append(rf"{n.latex(_lam(name))} &= {value}")
    for r in extra.reactions:
        label = rf"&& \text{{reaction of {_escape(r.constraint)}}}"
        if r.force is not None:
            force = n.vector(r.force.terms, latex=True) if r.force.terms else "0"
            rows.append(rf"\vec{{R}}({r.point}) &= {force} {label}")
        if r.moment is not None:
            rows.append(rf"\vec{{C}}({_escape(r.body or '')}) &= "
                        rf"{n.vector(r.moment.terms, latex=True) if r.moment.terms else '0'} {label}")
        if r.force is None and r.moment is None:
            rows.append("& " + r",\quad ".join(rf"Q_{{{qn}}} = {n.latex(g)}" for qn, g in zip(q, r.generalized, strict=True))
                        + label)
    out.append(r" \\".join(rows))
    out.append(r"\end{align*}")
    return out


def _power_label(t) -> str:
    """The label of a term of the balance in LaTeX (no Unicode: ∂U/∂t and λ are written as math)."""
    inner = re.search(r"\((.*)\)$", t.name)
    of = _escape(inner.group(1)) if inner else _escape(t.name)
    if t.kind == "explicit time":
        return rf"\frac{{\partial U}}{{\partial t}}\ (\text{{{of}}})"
    if t.kind == "constraint":
        return rf"\text{{reaction of {of}}}"
    return rf"\text{{{_escape(power_label(t))}}}"


def _balance_latex(n, extra: Supplement) -> list[str]:
    assert extra.balance is not None and extra.power is not None
    out = [r"\subsection*{Energy balance}",
           r"No energy integral: with $E = T + U_P$, $\frac{dE}{dt} = P(\text{non-conservative})$, term by term:",
           r"\begin{align*}"]
    rows = [rf"&{_power_label(t)}: & {n.latex(t.power)}" for t in extra.balance]
    rows.append(rf"&\frac{{dE}}{{dt}} = & {n.latex(extra.power)}")
    out.append(r" \\".join(rows))
    out.append(r"\end{align*}")
    return out


def render_latex(form: CourseForm, extra: Supplement | None = None) -> str:
    """A standalone LaTeX document of the derivation; ``extra`` adds steps 1 and 7 and the energy balance.

    The sections, in the course's order, as in `render_text`: the statement (`_statement_latex`), the frames
    and their angular velocities (`_frames_latex`), the virtual velocities, T and U (`_energies_latex`), the
    generalized forces by virtual power (`_forces_latex`), the Lagrange equations (`_equations_latex`), the
    first integrals (`_integrals_latex`) and the matrix form M q̈ = F (`_matrix_latex`).

    Parameters
    ----------
    form : CourseForm
        The derivation.
    extra : Supplement, optional
        Adds steps 1 and 7 and the energy balance.

    Returns
    -------
    str
        The LaTeX document.
    """
    n = notation(form)
    out = _statement_latex(n, form, extra)
    if form.frames:
        out += _frames_latex(n, form, extra)
    if form.virtual_velocities:
        out.append(r"\subsection*{Virtual velocity field}")
        out.append(r"\begin{align*}")
        out.append(r" \\".join(rf"\vec{{V}}^*({p}) &= {n.vector(row.terms, latex=True)}" for p, row in form.virtual_velocities))
        out.append(r"\end{align*}")
    out += _energies_latex(n, form)
    out += _forces_latex(n, form)
    out += _equations_latex(n, form, extra)
    out += _integrals_latex(n, form)
    if extra is not None and extra.balance is not None:
        out += _balance_latex(n, extra)
    out += _matrix_latex(n, form)
    out.append(r"\end{document}")
    return "\n".join(out) + "\n"


def _coordinates_latex(n: Notation, form: CourseForm) -> list[str]:
    return [n.symbol(c, latex=True) for c in form.coordinates]


def _statement_latex(n: Notation, form: CourseForm, extra: Supplement | None) -> list[str]:
    """The preamble, the title, the principal parameters, a non-Galilean reference and the constraints (step 1)."""
    ref = _frame(form.reference)
    out = [r"\documentclass[a4paper]{article}", r"\usepackage[utf8]{inputenc}", r"\usepackage{amsmath,amssymb}",
           r"\usepackage[margin=2cm]{geometry}", r"\allowdisplaybreaks", r"\begin{document}",
           rf"\section*{{{_escape(form.title)}}}"]
    if form.description:
        out.append(_escape(form.description) + r"\par")
    q = _coordinates_latex(n, form)
    out.append(rf"Principal parameters ($n = {len(q)}$, hence ${len(q)}$ Lagrange equations): $" + ", ".join(q) + "$.")
    if form.reference != "R0":
        out.append(rf"The equations are written relative to ${ref}$, which is not Galilean (Remarque 3): "
                   rf"$T(\Sigma/{ref})$, and the Coriolis and entrainment inertial forces among the loads.")
    if extra is not None and extra.constraints:
        out += _constraints_latex(n, extra)
    return out


def _frames_latex(n: Notation, form: CourseForm, extra: Supplement | None) -> list[str]:
    """Each frame from its parent (angle, axis) and its angular velocity Ω(R_i/ref)."""
    ref = _frame(form.reference)
    out = [r"\subsection*{Frames and angular velocities}", r"\begin{align*}"]
    rows = []
    for f in form.frames:
        axis = _axis_latex(f.axis) if f.axis_vector is None else n.vector(f.axis_vector.terms, latex=True)
        note = r"\quad\text{(the axis given, divided by its norm)}" if f.normalized else ""
        rows.append(rf"&{f.parent} \xrightarrow{{{n.latex(f.angle)},\ {axis}}} {f.name}"
                    rf"({', '.join(_axis_latex(a) for a in f.axes)}){note}")
    for f in form.frames:
        if f.name == form.reference and extra is not None and extra.reference_omega is not None:
            rows.append(rf"\vec{{\Omega}}({f.name}/R_0) &= {n.vector(extra.reference_omega.terms, latex=True)}"
                        r" \quad\text{(prescribed)}")
            continue
        text = rf"\vec{{\Omega}}({f.name}/{ref}) &= {n.vector(f.omega_chain.terms, latex=True)}"
        if f.omega_components is not None and n.vector(f.omega_components.terms, latex=True) != n.vector(f.omega_chain.terms, latex=True):
            text += rf" \\ &= {n.vector(f.omega_components.terms, latex=True)}"
        rows.append(text)
    out.append(r" \\".join(rows))
    out.append(r"\end{align*}")
    return out


def _energies_latex(n: Notation, form: CourseForm) -> list[str]:
    """T(Σ/ref) body by body with the formula used (König, fixed point, particle), and U_P (+ cste)."""
    ref = _frame(form.reference)
    out = [r"\subsection*{Kinetic and potential energies}", r"\begin{align*}"]
    rows = [rf"T({row.name}/{ref}) &= {_FORMULA.get(row.formula, '')} = {n.latex(row.expression)}" for row in form.T]
    rows += [rf"U_P(\text{{{_escape(row.name)}}}) &= {n.latex(row.expression)} + \text{{cste}}" for row in form.U]
    out.append(r" \\".join(rows))
    out.append(r"\end{align*}")
    return out


def _forces_latex(n: Notation, form: CourseForm) -> list[str]:
    """Each load's Q_i by virtual power, conservative or not."""
    q = _coordinates_latex(n, form)
    out = [r"\subsection*{Generalized forces (virtual power)}"]
    if form.loads:
        out.append(r"\begin{align*}")
        rows = []
        for load in form.loads:
            comps = r",\quad ".join(rf"Q_{{{qn}}} = {n.latex(Q)}" for qn, Q in zip(q, load.Q, strict=True))
            tag = "conservative" if load.conservative else "non-conservative"
            rows.append(rf"&\text{{{_escape(load.name)} ({_escape(kind_words(load.kind))}, {tag})}}: & {comps}")
        out.append(r" \\".join(rows))
        out.append(r"\end{align*}")
    return out


def _equations_latex(n: Notation, form: CourseForm, extra: Supplement | None) -> list[str]:
    """L(q_i) with its pieces ∂T/∂q̇_i, ∂T/∂q_i, ∂U_P/∂q_i, Q_i, a cyclic coordinate's first integral,
    L = T − U_P when conservative, and the multipliers (step 7)."""
    out = [r"\subsection*{Lagrange equations}", r"\begin{align*}"]
    rows = []
    for eq in form.equations:
        qn, qd = n.symbol(eq.coordinate, latex=True), n.symbol(eq.coordinate + "_dot", latex=True)
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
        constrained = extra is not None and bool(extra.multipliers)
        out.append(r"The system is conservative (Remarque 2"
                   + (r"; its complementary constraints are perfect and time-independent" if constrained else "")
                   + r"): $L = T - U_P$ and $\frac{d}{dt}\frac{\partial L}{\partial \dot q_i} - "
                   r"\frac{\partial L}{\partial q_i} = " + (r"\sum_k \lambda_k a_{k,i}" if constrained else "0") + "$.")
    if extra is not None and extra.multipliers:
        out += _step7_latex(n, form, extra)
    return out


def _integrals_latex(n: Notation, form: CourseForm) -> list[str]:
    out = [r"\subsection*{First integrals}"]
    if form.integrals:
        out.append(r"\begin{align*}")
        out.append(r" \\".join(rf"{n.sum(i.parts, latex=True)} &= {n.symbol(i.name, latex=True)}" for i in form.integrals))
        out.append(r"\end{align*}")
    else:
        out.append("None found.")
    return out


def _matrix_latex(n: Notation, form: CourseForm) -> list[str]:
    """M's nonzero entries on and above the diagonal (M is symmetric), then F."""
    q = _coordinates_latex(n, form)
    out = [r"\subsection*{Matrix form $M(q,t)\,\ddot q = F(q,\dot q,t)$}", r"\begin{align*}"]
    rows = []
    for a, row in enumerate(form.M):
        for b, entry in enumerate(row):
            if b >= a and entry != 0:
                rows.append(rf"M_{{{q[a]}{q[b]}}} &= {n.latex(entry)}")
    rows += [rf"F_{{{q[a]}}} &= {n.latex(f)}" for a, f in enumerate(form.F)]
    out.append(r" \\".join(rows))
    out.append(r"\end{align*}")
    return out
