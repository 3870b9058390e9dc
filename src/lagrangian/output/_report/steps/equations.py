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

import re

import symengine as se
import sympy

from ...._big_numbers import has_big_numbers
from ...._identity import are_zero
from ....analysis import Verification
from ....model import ORIGIN
from ..._course import EquationRow, IntegralRow
from ..._notation import Opaque
from ..build import _SI, Context
from ..document import Block, Display, Equation, Math, Para, Runs, Section
from ..joints import _root
from ..size import visible_width, wrap_many
from .contact import contact_blocks
from .impacts import closed_note, has_contacts, integrals_note

__all__ = ["step6", "step7", "integrals_section", "ordered_equations", "left_out_note"]


def ordered_equations(c: Context) -> list[EquationRow]:
    rows = list(c.form.equations)
    return [r for r in rows if r.integral is not None] + [r for r in rows if r.integral is None]


def _dT(c: Context, q: str, deco: str = "", U: bool = False) -> str:
    what = rf"U_P(\Sigma/{c.R})" if U else rf"T(\Sigma/{c.R})"
    return rf"\frac{{\partial {what}}}{{\partial {c.sym(q, deco)}}}"




def _unit(c: Context, kind: str, coordinate: str | None = None) -> str:
    """The SI unit of an integral's value — J for an energy or a Jacobi integral, J·s (kg·m²/s) for the
    momentum of an angle or an angular momentum, kg·m/s for that of a length, rad/s or m/s for a constant
    speed — when every parameter with a value (and every coordinate with a unit) declares an SI unit.
    ``coordinate``: the coordinate of a momentum, or the integral's name (σ_O·z0, φ̇)."""
    declared = [p.unit for p in c.model.parameters if p.value is not None and not getattr(p, "input", False)]
    declared += [q.unit for q in c.model.coordinates if q.unit is not None]
    if not declared or any(u is None or u.strip() not in _SI for u in declared):
        return ""
    if kind in ("energy", "jacobi"):
        return "\u202fJ"
    if kind == "symmetry":  # P·e (a translation) or σ_O·e (a rotation)
        return "\u202fJ·s" if (coordinate or "").startswith("sigma") else "\u202fkg·m/s"
    if kind == "nonholonomic":  # a constant speed q̇ (coordinate: its name q_dot)
        coordinate = (coordinate or "").removesuffix("_dot")
    q = next((q for q in c.model.coordinates if q.name == coordinate), None)
    if q is None:
        return ""
    unit = (q.unit or "").strip()
    if not unit and any(f.rotation is not None and q.symbol in f.rotation.angle.free_symbols for f in c.model.frames):
        unit = "rad"  # an angle of rotation of a frame
    if kind == "nonholonomic":
        return {"rad": "\u202frad/s", "m": "\u202fm/s"}.get(unit, "")
    return {"rad": "\u202fJ·s", "m": "\u202fkg·m/s"}.get(unit, "")


def _value(c: Context, name: str, expr_engine: se.Basic, unit: str = "") -> Runs:
    """`` (K ≈ 0,4388 J·s avec les valeurs initiales du modèle)``, when the model gives every value."""
    value = c.initial_value(expr_engine)
    if value is None:
        return ()
    return (" (",) + c.w("with values", value=(Math(name), f" ≈ {c.w.number(value, 4)}{unit}")) + (")",)


def _partials(c: Context, row: EquationRow) -> tuple[list[Equation], list[Block]]:
    """The seed's first line of L(q_i): ∂T/∂q̇_i = … ; ∂T/∂q_i = … ; ∂U_P/∂q_i = … et Q_i = …, with the
    full forms of its summaries."""
    q = row.coordinate
    label = rf"L({c.sym(q)})\quad "
    parts = [(_dT(c, q, "dot") + " = ", row.dT_dqd), (_dT(c, q) + " = ", row.dT_dq),
             (_dT(c, q, U=True) + " = ", row.dU_dq), (c.Q_nc(q) + " = ", row.Q_nc)]
    multiplier = c.eom.equation(q).multiplier_terms
    if multiplier != 0:
        parts.append((f"{c.multiplier_sum(c.sym(q))} = ", c.ex(multiplier)))
    full = c.full(parts, f"L({c.n.symbol(q)})")
    pieces = [head + c.n.latex(e) for head, e in parts]
    # The seed's layout: "… ; ∂U_P/∂q_i = … et Q_i = …", cut into lines (inside a piece if need be).
    last = pieces.pop()
    pieces[-1] += rf"\quad\text{{{c.w.text('et')}}}\quad " + last
    return [wrap_many(label, pieces, r";\quad ")], full


def _sides(c: Context, q: str) -> list[str]:
    """What the two sides of L(q_i) are, as heads of their full forms: d/dt[∂T/∂q̇] − ∂T/∂q = and −∂U_P/∂q + Q = ."""
    lam = f" + {c.multiplier_sum(c.sym(q))}" if c.eom.equation(q).multiplier_terms != 0 else ""
    return [rf"\frac{{d}}{{dt}}\left[{_dT(c, q, 'dot')}\right] - {_dT(c, q)} = ",
            rf"-{_dT(c, q, U=True)} + {c.Q_nc(q)}{lam} = "]


def _lagrange(c: Context, row: EquationRow) -> list[Block]:
    w = c.w
    q = row.coordinate
    partials, full = _partials(c, row)
    blocks: list[Block] = c.show(partials, f"L({c.n.symbol(q)})") + full
    if row.integral is not None:
        K = c.n.symbol(row.integral, latex=True)
        p = c.n.latex(row.dT_dqd)
        if visible_width(p) > 50:
            p = _dT(c, q, "dot")
        constant = rf"\quad\text{{{w.text('constant')}}}"
        blocks.append(Display((Equation((rf"\frac{{d}}{{dt}}\left[{p}\right] = 0 \quad\Rightarrow\quad {p} = "
                                         rf"{K}{constant}",)),)))
        at = rf"\text{{{w.text('at t0')}}}\ t = 0"
        blocks.append(Para(w("first integral K", K=Math(rf"{K} = \left[{p}\right]_{{{at}}}"))[:-1]
                           + _value(c, K, c.eom.equation(q).dT_dqd, _unit(c, "momentum", q)) + (".",)))
        return blocks
    lhs_head, rhs_head = _sides(c, q)
    full = c.full([(lhs_head, row.lhs), (rhs_head, row.rhs)], f"L({c.n.symbol(q)})")
    blocks += c.show([c.relation(r"\Rightarrow\quad ", row.lhs, row.rhs)], f"L({c.n.symbol(q)})") + full
    if row.using_integrals is not None:
        used = {str(s) for s in row.using_integrals.free_symbols}
        eqs = [Math(rf"L({c.sym(r.coordinate)})") for r in c.form.equations if r.integral in used]
        blocks.append(Para(w("using integrals", eqs=w.join(eqs) if eqs else Math(r"\dots"))))
        full = c.full([(lhs_head, row.using_integrals)], f"L({c.n.symbol(q)})")
        blocks += c.show([c.relation("", row.using_integrals, row.rhs)], f"L({c.n.symbol(q)})") + full
    return blocks


def step6(c: Context) -> Section:
    w = c.w
    lam = f" + {c.multiplier_sum()}" if c.eom.constraints else ""
    general = (rf"L(q_i)\quad \frac{{d}}{{dt}}\left[\frac{{\partial T(\Sigma/{c.R})}}{{\partial \dot{{q}}_i}}\right] - "
               rf"\frac{{\partial T(\Sigma/{c.R})}}{{\partial q_i}} = -\frac{{\partial U_P(\Sigma/{c.R})}}{{\partial q_i}}"
               rf" + Q_{{i,\,\mathrm{{nc}}}}{lam} \qquad i = 1, \dots, n")
    n = len(c.form.equations)
    # The principle of virtual power where it is used [Seed, II]: P*_acc = Σ Γ_i q_i* = Σ Q_i q_i* for every
    # q_i*, so Γ_i = Q_i, with Γ_i = d/dt[∂T/∂q̇_i] − ∂T/∂q_i [Seed, I].
    pvv = (rf"P^{{*}}_{{\mathrm{{acc}}}}(\Sigma/{c.R}) = \sum_{{i=1}}^{{n}} \Gamma_i\, q_i^{{*}} = "
           rf"\sum_{{i=1}}^{{n}} Q_i\, q_i^{{*}} \quad \forall\, q_i^{{*}} \quad\Rightarrow\quad \Gamma_i = Q_i")
    gamma = (rf"\Gamma_i = \frac{{d}}{{dt}}\left[\frac{{\partial T(\Sigma/{c.R})}}{{\partial \dot{{q}}_i}}\right] - "
             rf"\frac{{\partial T(\Sigma/{c.R})}}{{\partial q_i}}")
    blocks: list[Block] = [Para(w("pvv", R=Math(c.R))), Display((Equation((pvv,)),)),
                           Para(w("gamma", gamma=Math(gamma), R=Math(c.R), Q=Math("Q_i"))),
                           Display((Equation((general,)),))]
    if c.eom.constraints:
        blocks.append(Para(w("multiplier def one" if len(c.eom.constraints) == 1 else "multiplier def", sum=Math(c.multiplier_sum()))))
    blocks.append(Para(w("lagrange n", n=Math(str(n))) if n > 1 else w("lagrange one")))
    for row in ordered_equations(c):
        blocks += _lagrange(c, row)
    if c.eom.constraints:
        blocks.append(Para(w("with multiplier" if len(c.eom.constraints) == 1 else "with multipliers", sum=Math(c.multiplier_sum()))))
    left = [s for s in c.book.left_out if s.reference is None]
    if left:
        blocks.append(Para(left_out_note(c, left), style="note"))
    if c.form.conservative and c.form.L is not None:
        L = Math(rf"L(\Sigma/{c.R}) = T(\Sigma/{c.R}) - U_P(\Sigma/{c.R})")
        if c.eom.constraints:  # complementary and scleronomic: their reactions stay on the right
            blocks.append(Para(w("conservative constrained", R=Math(c.R), L=L, sum=Math(c.multiplier_sum()))))
        else:
            blocks.append(Para(w("conservative", R=Math(c.R), L=L)))
        parts = (c.form.T_total, -c.form.U_total) if c.form.U_total != 0 else (c.form.T_total,)
        blocks += c.show([_sum_equation(c, rf"L(\Sigma/{c.R}) = ", parts, "")], "L")
        right = c.multiplier_sum() if c.eom.constraints else "0"
        blocks.append(Display((Equation((r"L(q_i)\quad \frac{d}{dt}\left[\frac{\partial L}{\partial \dot{q}_i}\right]"
                                         rf" - \frac{{\partial L}}{{\partial q_i}} = {right} \qquad i = 1, \dots, n",)),)))
        if not are_zero([(c.eom.T - c.eom.U).diff(c.kin.t)])[0]:
            # Remarque 2 holds with time-dependent constraints; only the energy integral is lost.
            blocks.append(Para(w("conservative timed", L=Math("L"), t=Math("t"),
                                 dL=Math(r"\frac{\partial L}{\partial t} \neq 0"))))
    else:
        names = [f"« {c.load_name(f.name)} »" if c.lang == "fr" else f"“{c.load_name(f.name)}”"
                 for f in c.eom.loads if f.potential is None and f.kind != "inertial: Coriolis"]
        if names:
            key = "not conservative system" if len(names) == 1 else "not conservative systems"
            blocks.append(Para(w(key, names=w.join(names))))
        blocks += _coriolis(c, jacobi=not names)
    return Section("step6", w.text("step6"), tuple(blocks))


def _coriolis(c: Context, jacobi: bool) -> list[Block]:
    """The Coriolis forces: no potential, but no real power either (zero, or gyroscopic, generalized forces)."""
    w = c.w
    force = next((f for f in c.eom.loads if f.kind == "inertial: Coriolis"), None)
    if force is None:
        return []
    Q = Math(rf"Q_i({c.load_tex(force.name)})")
    if all(are_zero(list(force.Q))):
        runs = w("coriolis zero", Q=Math(rf"Q_i({c.load_tex(force.name)}) = 0"), R=Math(c.R))
    else:
        power = se.Add(*(x * qd for x, qd in zip(force.Q, c.kin.qd, strict=True)))
        if not are_zero([power])[0]:  # pragma: no cover - Coriolis forces never work
            return []
        runs = w("coriolis gyroscopic", Q=Q, R=Math(c.R), nc=Math(r"Q_{i,\,\mathrm{nc}}"),
                 P=Math(rf"\sum_{{i}} Q_i({c.load_tex(force.name)})\,\dot{{q}}_i = 0"))
    if jacobi and any(r.kind != "momentum" for r in c.form.integrals):
        # The same h as the integrals section defines: T(Σ/R) + U_P(Σ/R) when T(Σ/R) = T_2 (U_P then holds the
        # entrainment potential, counted once), T_2 − T_0 + U_P(Σ/R) otherwise.
        h = (rf"h = T(\Sigma/{c.R}) + U_P(\Sigma/{c.R})" if _homogeneous(c)
             else rf"h = T_2 - T_0 + U_P(\Sigma/{c.R})")
        runs += w("coriolis jacobi", h=Math(h))
    return [Para(runs)]


def left_out_note(c: Context, left: list) -> Runs:
    """The note on the summaries whose full forms the budget left out, and where to find them."""
    budget = f"{c.book.budget:,}".replace(",", "\u202f" if c.lang == "fr" else ",")  # 300 000: a narrow space
    return c.w("full forms left", budget=budget, k=str(len(left)),
               sample=Math(left[0].plain_latex), cmd=c.derive_command, fn="lagrangian.derive")


def pin_reaction(c: Context, v: Verification) -> list[Block]:
    """After step 7, the reaction of a fixed point as a formula: R_O = m γ(G/R0) − P (the resultant theorem,
    [Seed, Remarque 4]; `lagrangian.analysis.reactions`), where no complementary equation gives it already."""
    from ....analysis import reactions

    if c.eom.constraints or c.ref != "R0":
        return []
    out: list[Block] = []
    for r in reactions(v):
        if r.pinned is None or len(r.elements) != 1 or r.point is None:
            continue
        body = r.elements[0]
        th = next((t for t in v.theorems if t.name == body), None)
        if th is None:
            continue
        P, G, S, R = c.name(r.point), c.point_label(body), c.element(body), c.R
        RO = rf"\vec{{R}}_{{{P}}}"
        given = " - ".join(rf"\vec{{F}}({c.load_tex(e)})" for e in th.efforts)
        head = rf"{RO} = {c.mass_tex(body)}\,\vec{{\gamma}}({G}/{R})" + (f" - {given}" if given else "") + " = "
        axes = c.kin.frames.axes(r.frame)
        terms = tuple((c.ex(x), a) for x, a in zip(r.force_components, axes, strict=True) if not c.is_zero(x))
        out.append(Para(c.w("pin reaction", R=Math(RO), O=Math(P), S=Math(f"({S})"))))
        out.append(Display((c.vector_equation(head, terms),)))
    return out


def step7(c: Context) -> Section:
    w = c.w
    n = len(c.eom.coordinates)
    rows = c.eom.constraints
    if not rows:
        none = [Para(w("no complementary" if n > 1 else "no complementary one", n=Math(str(n))))]
        return Section("step7", w.text("step7"), tuple(none + contact_blocks(c)))
    lams = Math(", ".join(c.tex(r.multiplier) for r in rows))
    if len(rows) == 1:
        blocks: list[Block] = [Para(w("complementary row", n=Math(str(n)), lams=lams))]
    else:
        blocks = [Para(w("complementary rows", n=Math(str(n)), m=Math(str(len(rows))), lams=lams))]
    blocks += c.show([c.equation("", c.ex(r.expression), " = 0") for r in rows], "7")
    if has_contacts(c):  # a contact's row holds while it is closed, its λ ≥ 0
        blocks += closed_note(c)
    for reaction in c.eom.reactions:  # rows the engine chose of a vector constraint, and why
        choice = reaction.row_choice
        if choice is not None:
            # The kept rows by their axes (rolling_x1 → x1): the identifiers stay in the JSON.
            prefix = reaction.constraint + "_"
            kept = w.join([Math(c.axis(r.removeprefix(prefix))) for r in choice.kept])
            blocks.append(Para(w("rows chosen frame" if choice.frame else "rows chosen subset",
                                 declared=choice.declared_frame, name=c.constraint_label(reaction.constraint),
                                 k=str(len(choice.declared_rows)), r=str(choice.rank), frame=choice.frame or "",
                                 kept=kept)))
    formulas = _multipliers(c)
    if formulas is not None:
        if len(rows) > 1:
            blocks.append(Para(w("multipliers are")))
        else:  # a holonomic row f = 0 is differentiated twice (A q̈ + c = 0), a velocity row once
            twice = rows[0].kind == "holonomic"
            times = {"fr": ("deux fois", "une fois"), "en": ("twice", "once")}[c.lang][0 if twice else 1]
            blocks.append(Para(w("multiplier is", times=times)))
        shown = _on_the_constraints(c, [_simple(c, f) for f in formulas])
        blocks += c.show([c.equation(f"{c.tex(r.multiplier)} = ", e) for r, e in zip(rows, shown, strict=True)], "λ")
    for reaction in c.eom.reactions:
        if not reaction.physical:
            continue
        where = reaction.point or reaction.body or ""
        R = c.reaction_tex(reaction.constraint)
        body = reaction.body or next((k.body for k in c.model.constraints if k.name == reaction.constraint), None)
        label, named = c.constraint_label(reaction.constraint), Math(R) if not reaction.force.is_zero() else ""
        if reaction.point is not None and body in c.bodies and body != reaction.point:  # on (S) at I
            blocks.append(Para(w("reaction of at", R=named, name=label, S=Math(c.element(body)),
                                 E=Math(c.point_label(reaction.point)))))
        else:
            blocks.append(Para(w("reaction of", R=named, name=label, E=Math(c.point_label(where)))))
        eqs = []
        if not reaction.force.is_zero():
            eqs.append(c.vector_equation(f"{R} = ", c.terms(reaction.force)))
        if not reaction.moment.is_zero():
            eqs.append(c.vector_equation(r"\vec{M} = ", c.terms(reaction.moment)))
        if eqs:
            blocks.append(Display(tuple(eqs)))
        if formulas is not None:
            blocks += _tension(c, reaction, formulas)
    return Section("step7", w.text("step7"), tuple(blocks + contact_blocks(c)))


def _multipliers(c: Context) -> tuple[se.Basic, ...] | None:
    """λ_k(q, q̇, t) solved from the Lagrange equations and the constraint equations differentiated."""
    from ....dynamics import multiplier_formulas
    from ....errors import DerivationError

    if sum(1 for con in c.model.constraints if con.unilateral) > 1:
        return None  # which contacts are closed changes along the motion: no single formula
    try:
        return multiplier_formulas(c.eom)
    except DerivationError:
        return None


def _on_the_constraints(c: Context, exprs: list[sympy.Basic]) -> list[sympy.Basic]:
    """``exprs`` with each factor of their numerators and denominators reduced modulo the holonomic
    constraints f_k(q, t) = 0, which hold all along the motion, where that shortens the factor.

    The pendulum's λ = m (g y − ẋ² − ẏ²) / (2 (x² + y²)) is written m (g y − ẋ² − ẏ²) / (2 l²), as a
    teacher would (x² + y² − l² = 0).  The reduction is the remainder of the division by the
    constraints' Gröbner basis (Cox, Little & O'Shea, *Ideals, Varieties, and Algorithms*, §2.3),
    tried only where every constraint is a polynomial in the coordinates.
    """
    holonomic = [r.expression for r in c.eom.constraints if r.kind == "holonomic"]
    plain = [e for e in exprs if isinstance(e, sympy.Basic) and not e.atoms(Opaque)]
    if not holonomic or not plain or len(holonomic) > 3:
        return exprs
    try:
        # the same symbols as in the expressions (the printed forms may carry assumptions: x real, l positive)
        own = {s.name: s for e in plain for s in e.free_symbols}
        shown = [c.ex(f) for f in holonomic]  # SymPy objects (never text)
        if not all(isinstance(f, sympy.Basic) and not f.atoms(Opaque) for f in shown):
            return exprs
        fs = [f.xreplace({s: own.get(s.name, s) for s in f.free_symbols}) for f in shown]
        names = set(c.eom.coordinates)
        q = sorted({s for f in fs for s in f.free_symbols if s.name in names}, key=lambda s: s.name)
        if not q or not all(f.is_polynomial(*q) for f in fs):
            return exprs
        basis = list(sympy.groebner(fs, *q, order="grevlex").exprs)  # once for all the multipliers
    except (sympy.PolynomialError, sympy.CoercionFailed, ValueError, TypeError):  # pragma: no cover - kept as is
        return exprs

    def reduced(product: sympy.Basic) -> sympy.Basic:
        out = []
        for factor in sympy.Mul.make_args(product):
            base, power = factor.as_base_exp()
            if base.is_polynomial(*q) and base.free_symbols & set(q):
                try:  # (reduced builds a domain holding the factor's other symbols, rates and parameters)
                    shorter = sympy.factor(sympy.reduced(sympy.expand(base), basis, *q, order="grevlex")[1])
                except (sympy.PolynomialError, sympy.CoercionFailed, ValueError, TypeError):  # pragma: no cover
                    shorter = base
                if sympy.count_ops(shorter) < sympy.count_ops(base):
                    base = shorter
            out.append(base**power)
        return sympy.Mul(*out)

    def on_them(e: sympy.Basic) -> sympy.Basic:
        if not isinstance(e, sympy.Basic) or e.atoms(Opaque):
            return e
        numerator, denominator = sympy.fraction(sympy.factor(e))
        return reduced(numerator) / reduced(denominator)

    return [on_them(e) for e in exprs]


#: Largest expression (operations) that the report simplifies with SymPy before printing it.
SIMPLIFY_MAX_OPS = 120
#: Deepest nesting of functions (sin(sin θ) is 2) that the report simplifies: SymPy's trigonometric
#: rewriting grows with each level, and a power balance with sin∘…∘sin θ eight deep took 25 s
#: (tools/fuzz.py); the course's expressions nest one or two deep (|sin θ|, √(1 − e² sin² φ)).
SIMPLIFY_MAX_NESTING = 2


def _nesting(e: sympy.Basic) -> int:
    """How many functions deep the expression goes (powers and products do not count)."""
    inner = max((_nesting(a) for a in e.args), default=0)
    return inner + 1 if isinstance(e, sympy.Function) else inner


def _simple(c: Context, e: se.Basic, limit: int = SIMPLIFY_MAX_OPS) -> sympy.Basic:
    shown = c.ex(e)
    if isinstance(shown, sympy.Basic) and sympy.count_ops(shown) <= limit and not has_big_numbers(shown) \
            and _nesting(shown) <= SIMPLIFY_MAX_NESTING:
        simple = sympy.factor(sympy.simplify(shown))
        # SymPy rewrites sgn(v) by cases (0 where v = 0, v/|v| elsewhere): the course keeps sgn.
        if simple.has(sympy.Piecewise) and not shown.has(sympy.Piecewise):
            return shown
        return simple
    return shown


def _tension(c: Context, reaction, formulas: tuple[se.Basic, ...]) -> list[Block]:
    """A rod's tension N = −R·XP/|XP| when the constraint is |XP|² − L² = 0 and R is along XP (pendulum_tension).

    With XP in a vertical plane whose coordinates are two of the q_i, it is also written with the
    angle θ of XP from the descending vertical: x = L sin θ, y = −L cos θ (seed's notation).
    """
    from ....model import Gravity

    w, kin = c.w, c.kin
    rows = [r for r in c.eom.constraints if r.constraint == reaction.constraint]
    if reaction.point is None or len(rows) != 1 or rows[0].kind != "holonomic":
        return []
    d = kin.position(reaction.point) - kin.position(ORIGIN)
    squared = kin.frames.dot(d, d)
    L2 = se.expand(squared - rows[0].expression)
    moving = set(kin.q) | set(kin.qd) | {kin.t}
    if L2.free_symbols & moving or L2 == 0:
        return []
    parallel = kin.frames.cross(reaction.force, d)
    if not all(are_zero(list(kin.frames.express(parallel, c.ref)))):
        return []
    values = {r.multiplier: f for r, f in zip(c.eom.constraints, formulas, strict=True)}
    L = _root(L2)
    N = (-kin.frames.dot(reaction.force, d) / L).xreplace(values)
    X, P = c.name(c.origin), c.point_label(reaction.point)
    head = rf"N = -{c.reaction_tex(reaction.constraint)}\cdot\frac{{\overrightarrow{{{X}{P}}}}}{{{c.tex(L)}}} = "
    blocks: list[Block] = [Para(w("tension", P=Math(P), X=Math(X)))]
    blocks += c.show([c.equation(head, _simple(c, N))], "N")
    # The angle of XP from the descending vertical, when XP = x e1 + y e2 with e2 the ascending vertical.
    axes = kin.frames.axes(c.ref)
    comps = list(kin.frames.express(d, c.ref))
    gravity = [x for x in c.model.loads if isinstance(x, Gravity)]
    if len(gravity) != 1:
        return blocks
    g = list(kin.frames.express(gravity[0].field, c.ref))
    up = [k for k in range(3) if g[k] != 0]
    used = [k for k in range(3) if comps[k] != 0]
    q = list(kin.q)
    if len(up) != 1 or len(used) != 2 or up[0] not in used or not all(comps[k] in q for k in used):
        return blocks
    v = up[0]
    h = next(k for k in used if k != v)
    theta, theta_dot = sympy.Symbol("theta"), sympy.Symbol("theta_dot")
    Ls = L._sympy_()  # SymEngine → SymPy by structure (no text is parsed)
    x, y = sympy.Symbol(str(comps[h])), sympy.Symbol(str(comps[v]))
    xd, yd = (sympy.Symbol(str(kin.qd[q.index(comps[k])])) for k in (h, v))
    polar = {x: Ls * sympy.sin(theta), y: -Ls * sympy.cos(theta), xd: Ls * sympy.cos(theta) * theta_dot,
             yd: Ls * sympy.sin(theta) * theta_dot}
    try:
        N_theta = sympy.factor(sympy.trigsimp(N._sympy_().subs(polar)))
    except (TypeError, ValueError):
        return blocks
    if N_theta.free_symbols & {x, y, xd, yd}:
        return blocks
    names = {theta: r"\theta", theta_dot: r"\dot{\theta}"}
    for s in N_theta.free_symbols - {theta, theta_dot}:
        names[s] = c.tex(se.Symbol(str(s)))
    latex = re.sub(r"\\(sin|cos)\{\\left\(\\theta \\right\)\}", r"\\\1\\theta", sympy.latex(N_theta, symbol_names=names))
    sub = rf"{c.tex(comps[h])} = {c.tex(L)} \sin\theta,\quad {c.tex(comps[v])} = -{c.tex(L)} \cos\theta"
    blocks.append(Para(w("tension angle", sub=Math(sub), theta=Math(r"\theta"), XP=Math(rf"\overrightarrow{{{X}{P}}}"),
                         e=Math(c.axis(axes[v])))))
    blocks.append(Display((Equation((f"N = {latex}",)),)))
    return blocks


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
    # An integral found with the inputs off (`first_integrals`) says so: τ's potential −τ φ is then 0.
    off = [u for u in c.eom.model.inputs if se.Symbol(u) in (eq.dU_dq + eq.Q_nc).free_symbols]
    zero = {se.Symbol(u): se.Integer(0) for u in off}
    cyclic = are_zero([(eq.dT_dq - eq.dU_dq).xreplace(zero)])[0]
    Lq = Math(rf"L({c.sym(q)})")
    # With complementary constraints, L(q) also holds Σ λ_k a_{k,q}: it integrates only when no row has q̇ (the
    # coin's x is cyclic and free of given efforts, but λ_1 cos ψ − λ_2 sin ψ drives it).
    rows: Runs = ()
    if c.eom.constraints:
        a = rf"a_{{{c.sym(q)}}} = 0" if len(c.eom.constraints) == 1 else rf"a_{{k,{c.sym(q)}}} = 0"
        rows = w("no row", qd=Math(c.sym(q, "dot")), a=Math(a))
    if cyclic:
        parts = [Math(rf"\frac{{\partial L}}{{\partial {c.sym(q)}}} = 0"), Math(f"{c.Q_nc(q)} = 0")]
        why = w.join(parts + ([rows] if rows else []))
        head = w("cyclic", q=Math(c.sym(q)), why=why, eq=Lq)
    else:
        why = (Math(rf"\frac{{\partial T}}{{\partial {c.sym(q)}}} - \frac{{\partial U_P}}{{\partial {c.sym(q)}}}"
                    rf" + {c.Q_nc(q)} = 0"),)
        why = w.join([why, rows]) if rows else why
        head = w("momentum", why=why, eq=Lq)
    if off:
        head = w("inputs off", zero=Math(", ".join(f"{c.sym(u)} = 0" for u in off))) + head
    name = c.n.symbol(row.name, latex=True)
    return [Para(head)] + c.show([c.equation("", row.expression, f" = {name}")], row.name)


def _homogeneous(c: Context) -> bool:
    """T = T_2: T(Σ/R) is a homogeneous quadratic form of the q̇_i."""
    kin, n = c.kin, len(c.eom.q)
    T2 = se.Rational(1, 2) * se.Add(*(c.eom.M[i][j] * kin.qd[i] * kin.qd[j] for i in range(n) for j in range(n)
                                       if c.eom.M[i][j] != 0))
    return bool(are_zero([c.eom.T - T2])[0])


def _energy(c: Context, row: IntegralRow) -> list[Block]:
    w = c.w
    cond = w.text("cond conservative" if c.form.conservative else "cond no work")
    T, U = Math(rf"T(\Sigma/{c.R})"), Math(rf"U_P(\Sigma/{c.R})")
    cste = rf"\text{{{w.text('cste')}}}"
    if row.kind == "energy":
        blocks: list[Block] = [Para(w("energy integral", L=Math("L"), cond=cond, T=T))]
        head = rf"T(\Sigma/{c.R}) + U_P(\Sigma/{c.R}) = "
        blocks += c.show([_sum_equation(c, head, row.parts, f" = {cste}")], row.name)
    elif _homogeneous(c):
        # Seed, Remarque 3: in the moving frame R, U_P holds the entrainment potential; T(Σ/R) = T_2.
        blocks = [Para(w("jacobi moving", L=Math("L"), cond=cond, T=T, U=U, R=Math(c.R), R0=Math("R_{0}"),
                         E=Math(r"E = T(\Sigma/R_{0}) + U_P(\Sigma/R_{0})"), T2=Math(rf"T(\Sigma/{c.R}) = T_2")))]
        head = rf"h = T(\Sigma/{c.R}) + U_P(\Sigma/{c.R}) = "
        blocks += c.show([_sum_equation(c, head, row.parts, f" = {cste}") if row.parts
                          else c.equation(head, row.expression, f" = {cste}")], row.name)
    else:
        blocks = [Para(w("jacobi integral", L=Math("L"), cond=cond, T=T,
                         parts=Math(rf"T(\Sigma/{c.R}) = T_2 + T_1 + T_0"), qd=Math(r"\dot{q}_i"),
                         T210=Math(r"T_2,\ T_1,\ T_0"), T1=Math("T_1"), T0=Math("T_0"),
                         E=Math(rf"T(\Sigma/{c.R}) + U_P(\Sigma/{c.R})")))]
        blocks += c.show([c.equation(rf"h = T_2 - T_0 + U_P(\Sigma/{c.R}) = ", row.expression, f" = {cste}")],
                         row.name)
    source = next((i.expression for i in c.integrals if i.name == row.name), None)
    if source is not None:
        name = c.n.symbol(row.name, latex=True)
        value = _value(c, cste if row.kind == "energy" else name, source, _unit(c, row.kind, row.name))
        if value:
            blocks.append(Para(value[1:-1] + (".",)))
    others = [r.coordinate for r in c.form.equations if r.integral is None]
    what = w.text("the energy integral" if row.kind == "energy" else "the jacobi integral")
    if len(others) == 1:
        blocks.append(Para(w("replace", q=Math(c.sym(others[0])), what=what)))
    elif len(others) > 1:
        eqs = [Math(rf"L({c.sym(q)})") for q in others]
        blocks.append(Para(w("replace one", what=what[:1].upper() + what[1:],
                             eqs=w.join_or(eqs))))
    return blocks


def _other_integral(c: Context, row: IntegralRow) -> list[Block]:
    """A constant speed of a nonholonomic system (the coin's φ̇, from its reduced equations) or a symmetry's
    integral (σ_O·z0 of a top free to turn about Oz0): neither is an energy nor a Jacobi integral."""
    w = c.w
    name = c.n.symbol(row.name, latex=True)
    if row.kind == "nonholonomic":
        blocks: list[Block] = [Para(w("constant speed", qd=Math(name),
                                      d=Math(rf"\frac{{d{name}}}{{dt}} = 0")))]
        blocks += c.show([c.equation("", row.expression, rf" = \text{{{w.text('cste')}}}")], row.name)
    else:
        blocks = [Para(w("symmetry integral"))]
        blocks += c.show([c.equation("", row.expression, f" = {name}")], row.name)
    source = next((i.expression for i in c.integrals if i.name == row.name), None)
    if source is not None:
        value = _value(c, name, source, _unit(c, row.kind, row.name))
        if value:
            blocks.append(Para(value[1:-1] + (".",)))
    return blocks


#: Longest ∂L/∂q (operations) tested for being identically zero when q appears in T or U.
CYCLIC_MAX_OPS = 400


def _cyclic_but_driven(c: Context) -> tuple[list[str], list[Runs]]:
    """The coordinates with ∂L/∂q = 0 for which that does not suffice to integrate L(q), and why: a non-conservative
    effort works on them (the cart pushed by F), or a complementary row acts on them (the coin's x and y).  (The
    coin's φ̇ is still constant, by its reduced equations: only the cyclic argument fails.)"""
    w = c.w
    integrating = {row.coordinate for row in c.form.integrals if row.kind == "momentum"}
    # Cyclic: ∂L/∂q ≡ 0, tested where q is in T or U only when ∂L/∂q is short (this sentence only adds to the
    # integrals found; an identity test on each of a 40-link chain's long ∂L/∂q would cost a second).
    in_L = set(c.eom.T.free_symbols) | set(c.eom.U.free_symbols)
    candidates = [(q, eq) for q, s, eq in zip(c.eom.coordinates, c.kin.q, c.eom.equations, strict=True)
                  if q not in integrating and (s not in in_L or se.count_ops(eq.dT_dq - eq.dU_dq) <= CYCLIC_MAX_OPS)]
    if not candidates:
        return [], []
    cyclic = are_zero([eq.dT_dq - eq.dU_dq for _, eq in candidates])
    names: list[str] = []
    reasons: list[Runs] = []
    for (q, eq), flat in zip(candidates, cyclic, strict=True):
        if not flat:
            continue
        why: list[Runs] = []
        if not are_zero([eq.Q_nc])[0]:
            why.append((Math(rf"{c.Q_nc(q)} \neq 0"),))
        if eq.multiplier_terms != 0 and not are_zero([eq.multiplier_terms])[0]:
            a = rf"a_{{{c.sym(q)}}}" if len(c.eom.constraints) == 1 else rf"a_{{k,{c.sym(q)}}}"
            why.append(w("row acts", a=Math(rf"{a} \neq 0")))
        if why:
            names.append(q)
            reasons.append(w("cyclic driven", q=Math(c.sym(q)), dL=Math(rf"\frac{{\partial L}}{{\partial {c.sym(q)}}} = 0"),
                             why=w.join(why), eq=Math(rf"L({c.sym(q)})")))
    return names, reasons


def integrals_section(c: Context) -> Section:
    w = c.w
    blocks: list[Block] = []
    for row in c.form.integrals:
        if row.kind in ("nonholonomic", "symmetry"):
            blocks += _other_integral(c, row)
            continue
        blocks += _momentum(c, row) if row.kind == "momentum" else _energy(c, row)
    driven, reasons = _cyclic_but_driven(c)
    found = bool(blocks)
    blocks += [Para(r) for r in reasons]
    if not found:
        kin = c.kin
        L = c.eom.T - c.eom.U
        power = se.Add(*(q * qd for q, qd in zip(c.eom.Q_nc, kin.qd, strict=True)))
        timed, no_work = are_zero([L.diff(kin.t), power])
        why = [w.text("why time")] if not timed else []
        if not no_work:
            why.append(w.text("why work"))
        if timed and no_work and c.eom.constraints:
            why.append(w.text("why constraints"))
        key = "no integral" if not driven else "no integral but cyclic"
        blocks.append(Para(w(key, why=" ; ".join(why) if c.lang == "fr" else "; ".join(why))))
        blocks += _balance(c)
    if has_contacts(c):  # between impacts only: an impact takes energy
        blocks += integrals_note(c)
    return Section("integrals", w.text("integrals"), tuple(blocks))


def _balance(c: Context) -> list[Block]:
    """dE/dt = P_nc term by term, E = T + U_P, when no energy integral holds (friction, driving, prescribed motion)."""
    from ....analysis import energy_balance

    w = c.w
    try:
        balance = energy_balance(c.eom)
    except (ValueError, RuntimeError, ZeroDivisionError):  # pragma: no cover - a singular symbolic solve
        return []
    terms = [t for t in balance.terms if t.power != 0]
    if balance.conserved or not terms:
        return []
    if any(t.kind == "prescribed motion" for t in terms):
        # ∂U_P/∂t + [d/dt(T_1 + 2 T_0) − ∂T/∂t] = −∂L/∂t + d/dt(T_1 + 2 T_0): each term under the name of its value
        # (the course's Painlevé form: d/dt(T_2 − T_0 + U_P) = −∂L/∂t).
        kin = c.kin
        dT_dt = c.eom.T.diff(kin.t)
        timed = [t for t in terms if t.kind in ("explicit time", "prescribed motion")]
        minus_dL = se.Add(*(t.power for t in timed if t.kind == "explicit time")) - dT_dt
        rate = next(t.power for t in timed if t.kind == "prescribed motion") + dT_dt
        from ....analysis import PowerTerm

        merged = [PowerTerm("-dL/dt", "minus dL/dt", minus_dL, ""), PowerTerm("d(T1+2T0)/dt", "T1 T0", rate, "")]
        terms = [t for t in terms if t not in timed] + [t for t in merged if not are_zero([t.power])[0]]
    labels = []
    for t in terms:
        if t.kind == "load":
            labels.append(rf"P({c.load_tex(t.name)})")
        elif t.kind == "minus dL/dt":
            labels.append(r"-\frac{\partial L}{\partial t}")
        elif t.kind == "T1 T0":
            labels.append(r"\frac{d}{dt}\left(T_1 + 2\,T_0\right)")
        elif t.kind == "prescribed motion":  # pragma: no cover - merged above
            labels.append(rf"P(\text{{{w.text('prescribed')}}})")
        elif t.kind == "explicit time":
            labels.append(r"\frac{\partial U_P}{\partial t}")
        else:
            labels.append(rf"P(\text{{{w.text('reaction')}}}\ {c.tex(next((r.multiplier for r in c.eom.constraints if t.name.endswith(f'({r.name})')), se.Symbol('lambda')))})")
    E = rf"E = T(\Sigma/{c.R}) + U_P(\Sigma/{c.R})"
    blocks: list[Block] = [Para(w("balance", E=Math(E)))]
    if any(t.kind == "T1 T0" for t in terms) or any(t.kind == "minus dL/dt" for t in terms):
        blocks.append(Para(w("balance timed", T=Math(rf"T(\Sigma/{c.R}) = T_2 + T_1 + T_0"),
                             h=Math(rf"\frac{{d}}{{dt}}\left(T_2 - T_0 + U_P(\Sigma/{c.R})\right) = "
                                    r"-\frac{\partial L}{\partial t}"),
                             L=Math(rf"L = T(\Sigma/{c.R}) - U_P(\Sigma/{c.R})"))))
    eqs = [Equation((r"\frac{dE}{dt} = " + " + ".join(labels),))]
    eqs += [c.equation(f"{label} = ", _simple(c, t.power, 3 * SIMPLIFY_MAX_OPS)) for label, t in zip(labels, terms, strict=True)]
    blocks += c.show(eqs, "dE/dt")
    return blocks
