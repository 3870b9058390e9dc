"""Step 6 (the n Lagrange equations in the seed's layout), step 7 (complementary equations), first integrals.

Seed, worked example:

    L(ψ)  ∂T(Σ/R)/∂ψ̇ = A ψ̇ sin²θ + C cosθ (φ̇ + ψ̇ cosθ) ; ∂T(Σ/R)/∂ψ = 0 ; ∂U_P(Σ/R)/∂ψ = 0 et Q_ψ = 0
          d/dt[A ψ̇ sin²θ + C cosθ (φ̇ + ψ̇ cosθ)] = 0 ⇒ A ψ̇ sin²θ + C cosθ (φ̇ + ψ̇ cosθ) = K constante
          intégrale première du mouvement, dans laquelle K = [...] à t = 0
    L(θ)  ... ⇒ A θ̈ − A ψ̇² sinθ cosθ + C ψ̇ sinθ (φ̇ + ψ̇ cosθ) = m g a sinθ
          ou encore, en tenant compte de L(φ) : A θ̈ − A ψ̇² sinθ cosθ + H ψ̇ sinθ = m g a sinθ

The equations whose coordinate has a momentum integral come first, as in the seed (ψ, φ,
then θ), since the others are then written with those integrals.
"""

from __future__ import annotations

import symengine as se
import sympy

from .._identity import are_zero
from ._course import EquationRow, IntegralRow
from ._report_build import Context
from ._report_doc import Block, Display, Equation, Math, Para, Runs, Section
from ._report_size import visible_width, wrap_many

__all__ = ["step6", "step7", "integrals_section", "ordered_equations"]


def ordered_equations(c: Context) -> list[EquationRow]:
    rows = list(c.form.equations)
    return [r for r in rows if r.integral is not None] + [r for r in rows if r.integral is None]


def _dT(c: Context, q: str, deco: str = "", U: bool = False) -> str:
    what = rf"U_P(\Sigma/{c.R})" if U else rf"T(\Sigma/{c.R})"
    return rf"\frac{{\partial {what}}}{{\partial {c.sym(q, deco)}}}"


def _value(c: Context, name: str, expr_engine: se.Basic) -> Runs:
    """`` (K ≈ 0,4388 avec les valeurs initiales du modèle)``, when the model gives every value."""
    value = c.initial_value(expr_engine)
    if value is None:
        return ()
    return (" (",) + c.w("with values", value=(Math(name), f" ≈ {c.w.number(value)}")) + (")",)


def _partials(c: Context, row: EquationRow) -> list[Equation]:
    """The seed's first line of L(q_i): ∂T/∂q̇_i = … ; ∂T/∂q_i = … ; ∂U_P/∂q_i = … et Q_i = …"""
    q = row.coordinate
    label = rf"L({c.sym(q)})\quad "
    parts = [(_dT(c, q, "dot") + " = ", row.dT_dqd), (_dT(c, q) + " = ", row.dT_dq),
             (_dT(c, q, U=True) + " = ", row.dU_dq), (rf"Q_{{{c.sym(q)}}} = ", row.Q_nc)]
    multiplier = c.eom.equation(q).multiplier_terms
    if multiplier != 0:
        parts.append((rf"\sum_{{k}} \lambda_{{k}} A_{{k{c.sym(q)}}} = ", c.ex(multiplier)))
    pieces = [head + c.n.latex(e) for head, e in parts]
    # The seed's layout: "… ; ∂U_P/∂q_i = … et Q_i = …", cut into lines (inside a piece if need be).
    last = pieces.pop()
    pieces[-1] += rf"\quad\text{{{c.w.text('et')}}}\quad " + last
    return [wrap_many(label, pieces, r";\quad ")]


def _lagrange(c: Context, row: EquationRow) -> list[Block]:
    w = c.w
    q = row.coordinate
    blocks: list[Block] = c.show(_partials(c, row), f"L({q})")
    if row.integral is not None:
        K = c.n.symbol(row.integral, latex=True)
        p = c.n.latex(row.dT_dqd)
        if visible_width(p) > 50:
            p = _dT(c, q, "dot")
        constant = rf"\quad\text{{{w.text('constant')}}}"
        blocks.append(Display((Equation((rf"\frac{{d}}{{dt}}\left[{p}\right] = 0 \quad\Rightarrow\quad {p} = "
                                         rf"{K}{constant}",)),)))
        blocks.append(Para(w("first integral K", K=Math(rf"{K} = \left[{p}\right]_{{t = 0}}"))[:-1]
                           + _value(c, K, c.eom.equation(q).dT_dqd) + (".",)))
        return blocks
    blocks += c.show([c.relation(r"\Rightarrow\quad ", row.lhs, row.rhs)], f"L({q})")
    if row.using_integrals is not None:
        used = {str(s) for s in row.using_integrals.free_symbols}
        eqs = [Math(rf"L({c.sym(r.coordinate)})") for r in c.form.equations if r.integral in used]
        blocks.append(Para(w("using integrals", eqs=w.join(eqs) if eqs else Math(r"\dots"))))
        blocks += c.show([c.relation("", row.using_integrals, row.rhs)], f"L({q})")
    return blocks


def step6(c: Context) -> Section:
    w = c.w
    lam = r" + \sum_{k} \lambda_{k} A_{ki}" if c.eom.constraints else ""
    general = (rf"L(q_i)\quad \frac{{d}}{{dt}}\left[\frac{{\partial T(\Sigma/{c.R})}}{{\partial \dot{{q}}_i}}\right] - "
               rf"\frac{{\partial T(\Sigma/{c.R})}}{{\partial q_i}} = -\frac{{\partial U_P(\Sigma/{c.R})}}{{\partial q_i}}"
               rf" + Q_i{lam} \qquad i = 1, \dots, n")
    n = len(c.form.equations)
    blocks: list[Block] = [Display((Equation((general,)),))]
    blocks.append(Para(w("lagrange n", n=Math(str(n))) if n > 1 else w("lagrange one")))
    for row in ordered_equations(c):
        blocks += _lagrange(c, row)
    if c.eom.constraints:
        blocks.append(Para(w("with multipliers", sum=Math(r"\sum_{k} \lambda_{k} A_{ki}"))))
    if c.form.conservative and c.form.L is not None:
        L = Math(rf"L(\Sigma/{c.R}) = T(\Sigma/{c.R}) - U_P(\Sigma/{c.R})")
        blocks.append(Para(w("conservative", R=Math(c.R), L=L)))
        parts = (c.form.T_total, -c.form.U_total) if c.form.U_total != 0 else (c.form.T_total,)
        blocks += c.show([_sum_equation(c, rf"L(\Sigma/{c.R}) = ", parts, "")], "L")
        blocks.append(Display((Equation((r"L(q_i)\quad \frac{d}{dt}\left[\frac{\partial L}{\partial \dot{q}_i}\right]"
                                         r" - \frac{\partial L}{\partial q_i} = 0 \qquad i = 1, \dots, n",)),)))
    else:
        names = [f"« {f.name} »" if c.lang == "fr" else f"“{f.name}”" for f in c.eom.loads if f.potential is None]
        if names:
            key = "not conservative system" if len(names) == 1 else "not conservative systems"
            blocks.append(Para(w(key, names=w.join(names))))
    return Section("step6", w.text("step6"), tuple(blocks))


def step7(c: Context) -> Section:
    w = c.w
    n = len(c.eom.coordinates)
    rows = c.eom.constraints
    if not rows:
        return Section("step7", w.text("step7"), (Para(w("no complementary", n=Math(str(n)))),))
    lams = Math(", ".join(c.tex(r.multiplier) for r in rows))
    if len(rows) == 1:
        blocks: list[Block] = [Para(w("complementary row", n=Math(str(n)), lams=lams))]
    else:
        blocks = [Para(w("complementary rows", n=Math(str(n)), m=Math(str(len(rows))), lams=lams))]
    blocks += c.show([c.equation("", c.ex(r.expression), " = 0") for r in rows], "7")
    for reaction in c.eom.reactions:
        if not reaction.physical:
            continue
        where = reaction.point or reaction.body or ""
        blocks.append(Para(w("reaction of", name=reaction.constraint, E=Math(c.point_label(where)))))
        eqs = []
        if not reaction.force.is_zero():
            eqs.append(c.vector_equation(r"\vec{R} = ", c.terms(reaction.force)))
        if not reaction.moment.is_zero():
            eqs.append(c.vector_equation(r"\vec{M} = ", c.terms(reaction.moment)))
        if eqs:
            blocks.append(Display(tuple(eqs)))
    return Section("step7", w.text("step7"), tuple(blocks))


# -- first integrals --------------------------------------------------------------------------------
def _sum_equation(c: Context, head: str, parts: tuple[sympy.Basic, ...], tail: str) -> Equation:
    """``head`` then the parts one after the other (T then U_P, as the seed writes the energy)."""
    pieces: list[str] = []
    for part in parts:
        terms = c.n.terms(part, latex=True)
        if pieces and not terms[0].startswith("-"):
            terms[0] = "+ " + terms[0]
        elif pieces:
            terms[0] = "- " + terms[0][1:].lstrip()
        pieces += terms
    eq = wrap_many(head, pieces or ["0"], " ")
    return Equation(eq.lines[:-1] + (eq.lines[-1] + tail,))


def _momentum(c: Context, row: IntegralRow) -> list[Block]:
    w = c.w
    q = row.coordinate or ""
    eq = c.eom.equation(q)
    cyclic = are_zero([eq.dT_dq - eq.dU_dq])[0]
    Lq = Math(rf"L({c.sym(q)})")
    if cyclic:
        why = w.join([Math(rf"\frac{{\partial L}}{{\partial {c.sym(q)}}} = 0"), Math(rf"Q_{{{c.sym(q)}}} = 0")])
        head = w("cyclic", q=Math(c.sym(q)), why=why, eq=Lq)
    else:
        why = (Math(rf"\frac{{\partial T}}{{\partial {c.sym(q)}}} - \frac{{\partial U_P}}{{\partial {c.sym(q)}}}"
                    rf" + Q_{{{c.sym(q)}}} = 0"),)
        head = w("momentum", why=why, eq=Lq)
    name = c.n.symbol(row.name, latex=True)
    return [Para(head)] + c.show([c.equation("", row.expression, f" = {name}")], row.name)


def _energy(c: Context, row: IntegralRow) -> list[Block]:
    w = c.w
    cond = w.text("cond conservative" if c.form.conservative else "cond no work")
    key = "energy integral" if row.kind == "energy" else "jacobi integral"
    blocks: list[Block] = [Para(w(key, L=Math("L"), cond=cond, T=Math(rf"T(\Sigma/{c.R})")))]
    name = c.n.symbol(row.name, latex=True)
    if row.kind == "energy":
        head = rf"T(\Sigma/{c.R}) + U_P(\Sigma/{c.R}) = "
        blocks += c.show([_sum_equation(c, head, row.parts, f" = {name}")], row.name)
    else:
        blocks += c.show([c.equation(r"T_2 - T_0 + U_P = ", row.expression, f" = {name}")], row.name)
    source = next((i.expression for i in c.integrals if i.name == row.name), None)
    if source is not None:
        value = _value(c, name, source)
        if value:
            blocks.append(Para(value[1:-1] + (".",)))
    others = [r.coordinate for r in c.form.equations if r.integral is None]
    if len(others) == 1:
        blocks.append(Para(w("replace", q=Math(c.sym(others[0])))))
    elif len(others) > 1:
        blocks.append(Para(w("replace one", eqs=w.join([Math(rf"L({c.sym(q)})") for q in others]))))
    return blocks


def integrals_section(c: Context) -> Section:
    w = c.w
    blocks: list[Block] = []
    for row in c.form.integrals:
        blocks += _momentum(c, row) if row.kind == "momentum" else _energy(c, row)
    if not blocks:
        kin = c.kin
        L = c.eom.T - c.eom.U
        power = se.Add(*(q * qd for q, qd in zip(c.eom.Q_nc, kin.qd)))
        timed, no_work = are_zero([L.diff(kin.t), power])
        why = [w.text("why time")] if not timed else []
        if not no_work:
            why.append(w.text("why work"))
        if timed and no_work and c.eom.constraints:
            why.append(w.text("why constraints"))
        blocks.append(Para(w("no integral", why=" ; ".join(why) if c.lang == "fr" else "; ".join(why))))
    return Section("integrals", w.text("integrals"), tuple(blocks))
