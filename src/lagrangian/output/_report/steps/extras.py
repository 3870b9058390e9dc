"""The parts after step 7: the Newton–Euler cross-check, the simulation's figures, the matrix form, a note.

Seed, last remark of the worked example: « Ces équations de Lagrange peuvent être retrouvées
en appliquant le théorème du moment dynamique en O à (S) par rapport à R … on retrouve
Lψ) par projection de cette équation sur la direction de l'axe de rotation z0 … ».  The
check itself is `lagrangian.analysis.verify`; this module only writes it.
"""

from __future__ import annotations

import re
from collections.abc import Sequence
from dataclasses import dataclass

import symengine as se
import sympy

from ...._identity import are_zero
from ....analysis import Verification
from ....model import Vector
from ..._notation import Opaque
from ..build import Context
from ..document import Block, Display, Equation, Image, Math, Para, Runs, Section

__all__ = ["ReportFigure", "check_section", "simulation_section", "matrix_section", "notes_section"]


@dataclass(frozen=True, slots=True)
class ReportFigure:
    """A figure for the report: PNG bytes and a caption (plain text).

    Parameters
    ----------
    png : bytes
        The PNG image.
    caption : str
        Its caption (plain text).
    """

    png: bytes
    caption: str

    def __post_init__(self) -> None:
        if not self.png.startswith(b"\x89PNG\r\n\x1a\n"):
            raise ValueError("a report figure must be a PNG image (its bytes start with the PNG signature)")


def check_section(c: Context, v: Verification) -> Section:
    """Each L(q_i) as the projection of a Newton–Euler theorem, the theorem stated just before its first use.

    The theorems are written in the frame of the equations (R0, or R with the inertial forces);
    a theorem is stated for the very point and elements its projections use.
    """
    w, R = c.w, c.R
    moving = c.ref != "R0"
    blocks: list[Block] = [Para(w("check intro moving" if moving else "check intro", R0=Math(R)))]
    liaisons = w.text("constraint actions")
    stated: set[tuple[str, str, tuple[str, ...]]] = set()
    noted = False  # the note on the efforts given by their generalized forces, once
    theorems = {(th.name, th.point): th for th in v.theorems}
    lambdas = {r.multiplier for r in c.eom.constraints}
    with_lambda = any(set(ch.newton_euler_efforts.free_symbols) & lambdas for ch in v.checks)
    lossy = any(not j.perfect for j in c.joints)
    # A fixed point's reaction drops out of the moment at that point for its own reason (OO ∧ R_O = 0, said there).
    fixed_only = bool(c.joints) and all(j.kind == "fixed point" for j in c.joints) and not c.eom.constraints
    if not fixed_only:
        blocks.append(Para(w("drop not perfect" if lossy else "perfect drop principal" if with_lambda
                             else "perfect drop")))
    for check in v.checks:
        q = c.sym(check.coordinate)
        eq = Math(rf"L({q})")
        names = check.elements or tuple(th.name for th in v.theorems)
        key = (check.theorem, check.point or "", tuple(names))
        if check.theorem in ("moment", "resultant") and key not in stated:
            stated.add(key)
            # The efforts that go by their generalized forces (a potential, given Q_i, a dissipation function) but
            # act on this coordinate are part of the theorem too: the projection uses them.
            i = c.eom.coordinates.index(check.coordinate)
            by_power = [f.name for f in c.eom.loads if f.name in v.virtual_power_loads and f.Q[i] != 0]
            blocks += _theorem(c, check.theorem, check.point, names, theorems, liaisons, by_power,
                               note=not noted and bool(by_power))
            noted = noted or bool(by_power)
        of: Runs = () if check.whole_system else w("of", names=w.join(
            [Math(f"({c.element(e)})" if e in c.bodies else c.element(e)) for e in check.elements]))
        if check.axis is not None:
            direction = Math(c.axis(check.axis))
        elif check.direction is not None:
            direction = Math(c.vector(check.direction))
        else:
            direction = Math(r"\vec{e}")
        if check.theorem == "moment":
            P = _point(c, check.point, check.elements[0] if check.elements else "")
            head = w("by moment", eq=eq, P=Math(P), of=of, e=direction)
        elif check.theorem == "resultant":
            head = w("by resultant", eq=eq, of=of, e=direction)
        else:
            head = w("by power", eq=eq, of=of, q=Math(q))
        blocks += _fixed_axis(c, check, theorems)
        mark = r"\quad\checkmark" if check.agrees else r"\quad\times"
        left, right = c.ex(check.newton_euler), c.ex(check.newton_euler_efforts)
        long_left, long_right = (isinstance(x, sympy.Basic) and bool(x.atoms(Opaque)) for x in (left, right))
        if check.agrees and (long_left or long_right):
            # ⟨24 termes⟩ = … ✓ cannot be checked by a reader: say what was compared, member by member.
            G, Q = rf"\Gamma^{{\mathrm{{NE}}}}_{{{q}}}", rf"Q^{{\mathrm{{NE}}}}_{{{q}}}"
            summary = "check summarized" if long_right else "check summarized left"
            blocks.append(Para(head + (" ",) + w(summary, eq=eq, k=str(_terms(check.newton_euler)),
                                                 k2=str(_terms(check.newton_euler_efforts)), G=Math(G), Q=Math(Q))))
            gamma, forces = _identity_line(c, check.coordinate)
            lines = [gamma, forces] if long_right else [gamma]
            blocks.append(Display(tuple(Equation((line,)) for line in lines)))
            if not long_right:
                blocks += c.show([c.equation(f"{Q} = ", right, mark)], f"L({check.coordinate})")
        else:
            blocks.append(Para(head))
            blocks += c.show([c.relation("", left, right, mark)], f"L({check.coordinate})")
        if not check.agrees:
            blocks.append(Para(w("check failed", eq=eq), style="note"))
    return Section("check", w.text("check"), tuple(blocks))


def _terms(e: se.Basic) -> int:
    return len(e.args) if isinstance(e, se.Add) else 1


def _identity_line(c: Context, q: str) -> tuple[str, str]:
    """Γ_q^NE − Γ_q = 0 ✓ and Q_q^NE − Q_q = 0 ✓, Γ_q and Q_q the two members of L(q) at step 6."""
    qs, qd = c.sym(q), c.sym(q, "dot")
    R = c.R
    gamma = (rf"\frac{{d}}{{dt}}\left[\frac{{\partial T(\Sigma/{R})}}{{\partial {qd}}}\right] - "
             rf"\frac{{\partial T(\Sigma/{R})}}{{\partial {qs}}}")
    lam = f" + {c.multiplier_sum(qs)}" if c.eom.equation(q).multiplier_terms != 0 else ""
    forces = rf"-\frac{{\partial U_P(\Sigma/{R})}}{{\partial {qs}}} + {c.Q_nc(q)}{lam}"
    return (rf"\Gamma^{{\mathrm{{NE}}}}_{{{qs}}} - \left({gamma}\right) = 0\quad\checkmark",
            rf"Q^{{\mathrm{{NE}}}}_{{{qs}}} - \left({forces}\right) = 0\quad\checkmark")


def _fixed_axis(c: Context, check, theorems: dict) -> list[Block]:
    """δ_O·z0 = d/dt(σ_O·z0) = d/dt(∂T/∂ψ̇) (= dK/dt): the moment at a fixed point projected on an axis fixed
    in R0 is the derivative of the projected angular momentum, and that is ∂T/∂q̇ — shown only where the
    engine finds σ_O·e − ∂T/∂q̇ identically zero, so that a student recognises L(q) in it."""
    if (check.theorem != "moment" or c.ref != "R0" or check.axis is None or check.direction is None
            or len(check.elements) != 1 or check.point is None
            or (check.point.startswith("G_") and check.point[2:] in c.bodies)  # a centre of mass: not a fixed point
            or not c.kin.is_fixed(check.point)):
        return []
    (frame, _), = list(check.direction)
    th = theorems.get((check.elements[0], check.point))
    if frame != "R0" or th is None or getattr(th, "angular_momentum", None) is None:
        return []
    projected = c.kin.frames.dot(th.angular_momentum, check.direction)
    equation = next(e for e in c.eom.equations if e.coordinate == check.coordinate)
    if not are_zero([projected - equation.dT_dqd])[0]:
        return []
    row = next(r for r in c.form.equations if r.coordinate == check.coordinate)
    P, E, R, e = _point(c, check.point, check.elements[0]), c.element(check.elements[0]), c.R, c.axis(check.axis)
    qd = c.sym(check.coordinate, "dot")
    sigma = rf"\vec{{\sigma}}_{{{P}}}({E}/{R})\cdot{e}"
    chain = (rf"\vec{{\delta}}_{{{P}}}({E}/{R})\cdot{e} = \frac{{d}}{{dt}}\left[{sigma}\right] = "
             rf"\frac{{d}}{{dt}}\left[\frac{{\partial T(\Sigma/{R})}}{{\partial {qd}}}\right]")
    if row.integral is not None:
        chain += rf" = \frac{{d{c.n.symbol(row.integral, latex=True)}}}{{dt}}"
    return [Para(c.w("fixed axis", e=Math(e), R0=Math(R), O=Math(P))),
            Display((Equation((chain,)), c.equation(f"{sigma} = ", c.ex(projected))))]


def _theorem(c: Context, kind: str, point: str | None, names: tuple[str, ...], theorems: dict,
             liaisons: str, by_power: list[str] | tuple[str, ...] = (), note: bool = True) -> list[Block]:
    """The statement of the resultant or moment theorem for ``names`` (at ``point``), in the frame R; ``by_power``
    names the efforts given by their generalized forces (actuators, dissipation), which enter it too."""
    out = _theorem_statement(c, kind, point, names, theorems, liaisons, by_power)
    if by_power and note:
        loads = c.w.join([c.w("quoted", name=c.load_name(x)) for x in by_power])
        out.append(Para(c.w("by power note" if len(by_power) > 1 else "by power note one", names=loads)))
    return out


def _theorem_statement(c: Context, kind: str, point: str | None, names: tuple[str, ...], theorems: dict,
                       liaisons: str, by_power: list[str] | tuple[str, ...]) -> list[Block]:
    w, R = c.w, c.R
    elements = w.join([Math(f"({c.element(e)})" if e in c.bodies else c.element(e)) for e in names])
    label = names[0] if len(names) == 1 else r"\Sigma"
    E = c.element(label) if len(names) == 1 else label
    efforts = sorted({e for th in theorems.values() if th.name in names for e in th.efforts})
    if kind == "resultant":
        G = c.point_label(names[0]) if len(names) == 1 else "G"
        m = c.mass_tex(names[0]) if len(names) == 1 else r"\sum m"
        forces = " + ".join([c.reaction_tex(e) if c.is_constraint(e) else rf"\vec{{F}}({c.load_tex(e)})"
                             for e in efforts] + [rf"\vec{{F}}({c.load_tex(e)})" for e in by_power]) or r"\vec{0}"
        return [Para(w("resultant theorem", P=elements)),
                Display((Equation((rf"{m}\,\vec{{\gamma}}({G}/{R}) = {forces} + \vec{{R}}(\text{{{liaisons}}})",)),))]
    P = _point(c, point, names[0])
    moments = " + ".join([rf"\vec{{M}}_{{{P}}}({c.reaction_tex(e) if c.is_constraint(e) else c.load_tex(e)})"
                          for e in efforts] + [rf"\vec{{M}}_{{{P}}}({c.load_tex(e)})" for e in by_power]) or r"\vec{0}"
    fixed = next((j for j in c.joints if j.kind == "fixed point" and j.support is None and names == (j.element,)
                  and j.point is not None and c.point_label(j.point) == P), None)
    th = theorems.get((names[0], point)) if len(names) == 1 else None
    out: list[Block] = []
    if fixed is not None and th is not None and c.ref == "R0":
        # The seed: δ_O = d/dt[σ_O]_{R0} = M_O(P) + M_O(R_O) = OG∧P + OO∧R_O, soit d/dt[σ_O]_{R0} = OG∧P.
        out.append(Para(w("top moment", R0=Math(R), O=Math(P), S=Math(E))))
        arms, named = [], []
        for load in [*efforts, *by_power]:
            spec = next((x for x in c.model.loads if x.name == load), None)
            from ....model import Gravity

            if isinstance(spec, Gravity):
                arms.append(rf"\overrightarrow{{{P}{c.point_label(names[0])}}}\wedge\vec{{P}}")
                named.append(rf"\vec{{M}}_{{{P}}}(\vec{{P}})")
            else:
                arms.append(rf"\vec{{M}}_{{{P}}}({c.load_tex(load)})")
                named.append(arms[-1])
        RO = rf"\vec{{R}}_{{{P}}}"
        dsigma = rf"\frac{{d}}{{dt}}\left[\vec{{\sigma}}_{{{P}}}({E}/{R})\right]_{{{R}}}"
        first = (rf"\vec{{\delta}}_{{{P}}}({E}/{R}) = {dsigma} = " + " + ".join(named + [rf"\vec{{M}}_{{{P}}}({RO})"])
                 + " = " + " + ".join(arms + [rf"\overrightarrow{{{P}{P}}}\wedge{RO}"]))
        sigma = c.vector_equation(rf"\vec{{\sigma}}_{{{P}}}({E}/{R}) = \Pi_{{{P}}}({E})\cdot\vec{{\Omega}}({E}/{R}) = ",
                                  c.terms(th.angular_momentum))
        out.append(Display((Equation((first,)), sigma)))
        out.append(Para(w("fixed point moment", R=Math(RO), O=Math(P), OO=Math(rf"\overrightarrow{{{P}{P}}}\wedge{RO} = \vec{{0}}"))))
        out.append(Display((Equation((rf"{dsigma} = " + (" + ".join(arms) or r"\vec{0}"),)),)))
        return out
    # δ_P = d/dt[σ_P]_R only where P is fixed in R or is the centre of mass; at a moving point A,
    # δ_A = d/dt[σ_A]_R + m V(A/R) ∧ V(G/R) (the double pendulum's joint, the coin's contact point).
    where = point[2:] if point and point.startswith("G_") and point[2:] in c.bodies else point  # G_S: S's centre
    at_centre = where is None or (len(names) == 1 and where == names[0])
    moving = not at_centre and not c.kin.is_fixed(where)  # type: ignore[arg-type]
    drift = ""
    if moving:
        masses = {th.name: th.mass for th in theorems.values() if th.name in names}
        m = c.mass_tex(names[0]) if len(names) == 1 else "m"
        G = c.point_label(names[0]) if len(names) == 1 else "G"
        term = rf"{m}\,\vec{{V}}({P}/{R})\wedge\vec{{V}}({G}/{R})"
        # m V(P) ∧ V(G) = V(P) ∧ Σ m_k V(G_k): it vanishes when P moves with G (the coin's contact point).
        frames, vP = c.kin.frames, c.kin.velocity(where)  # type: ignore[arg-type]
        total = Vector.zero()
        for name in names:
            total = total + frames.cross(vP, c.kin.velocity(name)) * masses[name]
        parallel = total.is_zero() or all(are_zero(list(frames.express(total, "R0"))))
        if parallel:
            out.append(Para(w("moment theorem parallel", P=Math(P), S=elements, R=Math(R), G=Math(G),
                              term=Math(term + r" = \vec{0}"))))
        else:
            drift = " + " + term
            out.append(Para(w("moment theorem moving", P=Math(P), S=elements, R=Math(R), term=Math(term))))
    else:
        out.append(Para(w("moment theorem", P=Math(P), S=elements)))
    rows = [Equation((rf"\vec{{\delta}}_{{{P}}}({E}/{R}) = \frac{{d}}{{dt}}\left[\vec{{\sigma}}_{{{P}}}({E}/{R})\right]_{{{R}}}"
                      rf"{drift} = {moments} + \vec{{M}}_{{{P}}}(\text{{{liaisons}}})",))]
    if th is not None and th.kind == "body":
        rows.append(c.vector_equation(rf"\vec{{\sigma}}_{{{P}}}({E}/{R}) = \Pi_{{{P}}}({E})\cdot\vec{{\Omega}}({E}/{R}) = ",
                                      c.terms(th.angular_momentum)))
    out.append(Display(tuple(rows)))
    return out


def _point(c: Context, point: str | None, body: str) -> str:
    """The moment point of a theorem: a body's name, or ``G_<body>``, stands for its centre of mass."""
    if point is None or point == body:
        return c.point_label(body) if body in c.bodies else "G"
    if point.startswith("G_") and point[2:] in c.bodies:
        return c.point_label(point[2:])
    return c.point_label(point)


def simulation_section(c: Context, figures: Sequence[ReportFigure]) -> Section:
    w = c.w
    blocks: list[Block] = []
    for k, fig in enumerate(figures, start=1):
        blocks.append(Image(fig.png, w("figure", k=str(k), caption=caption_runs(fig.caption)), fig.caption))
    return Section("simulation", w.text("simulation"), tuple(blocks))


#: An indexed symbol of a caption's plain text: q_i(t), q̇_i, U_P, R_O(t).
_INDEXED = re.compile(r"(q\u0307|[A-Za-z])_([A-Za-z0-9]+)(\(t\))?")


def caption_runs(caption: str) -> Runs:
    """A figure's plain-text caption with its indexed symbols as mathematics: "Paramètres q_i(t)" →
    "Paramètres " + q_i(t) set as math (the captions of `lagrangian.plotting` are plain text)."""
    out: list[str | Math] = []
    start = 0
    for m in _INDEXED.finditer(caption):
        base = r"\dot{q}" if m.group(1) == "q\u0307" else m.group(1)
        out += [caption[start:m.start()], Math(f"{base}_{{{m.group(2)}}}" + (m.group(3) or ""))]
        start = m.end()
    out.append(caption[start:])
    return tuple(r for r in out if r != "")


#: Most coordinates for which the appendix lists the entries of M and F (n(n + 1)/2 + n of them).
MATRIX_MAX = 12


def matrix_section(c: Context) -> Section:
    w = c.w
    q = c.eom.coordinates
    form = Math(r"M(q, t)\,\ddot{q} = F(q, \dot{q}, t)")
    if len(q) > MATRIX_MAX:
        count = sum(1 for a, row in enumerate(c.eom.M) for b, x in enumerate(row) if b >= a and x != 0)
        text = w("matrix large", form=form, n=Math(rf"{len(q)} \times {len(q)}"), k=str(count),
                 cmd=c.derive_command)
        return Section("matrix", w.text("matrix"), (Para(text),))
    rows: list[Equation] = []
    for a, row in enumerate(c.form.M):
        for b, entry in enumerate(row):
            if b >= a and entry != 0:
                rows.append(c.equation(rf"M_{{{c.sym(q[a])}{c.sym(q[b])}}} = ", entry))
    rows += [c.equation(rf"F_{{{c.sym(q[a])}}} = ", f) for a, f in enumerate(c.form.F)]
    # With complementary constraints F holds the given efforts only; their reactions are the rows of Aᵀλ.
    lams = [(name, c.eom.equation(name).multiplier_terms) for name in q] if c.eom.constraints else []
    lams = [(name, t) for name, t in lams if t != 0]
    if lams:
        L = c.lam
        form = Math(rf"M(q, t)\,\ddot{{q}} = F(q, \dot{{q}}, t) + A^{{\mathsf{{T}}}}{L}")
        rows += [c.equation(rf"\left(A^{{\mathsf{{T}}}}{L}\right)_{{{c.sym(name)}}} = {c.multiplier_sum(c.sym(name))} = ",
                            c.ex(t)) for name, t in lams]
        A = "A = (a_{i})" if len(c.eom.constraints) == 1 else "A = (a_{k,i})"
        intro = w("matrix intro multiplier" if len(c.eom.constraints) == 1 else "matrix intro multipliers", form=form, A=Math(A), lam=Math(L))
    else:
        intro = w("matrix intro", form=form)
    blocks: list[Block] = [Para(intro)]
    blocks += c.many(c.show(rows, "M, F"), len(rows), "M, F")
    return Section("matrix", w.text("matrix"), tuple(blocks))


def notes_section(c: Context) -> Section | None:
    """A note on the expressions summarized as ⟨N terms⟩, when there are any."""
    if not c.gate.summaries:
        return None
    from .equations import left_out_note

    blocks: list[Block] = []
    numbered = c.book.numbered
    if numbered:
        refs = numbered[0].reference if len(numbered) == 1 else \
            c.w.text("refs", first=numbered[0].reference, last=numbered[-1].reference)
        blocks.append(Para(c.w("full forms note", sample=Math(numbered[0].latex_form), refs=refs), style="note"))
    left = [s for s in c.gate.summaries if s.reference is None]
    if left and c.book.left_out:
        blocks.append(Para(left_out_note(c, left), style="note"))
    elif left:
        blocks.append(Para(c.w("summaries", sample=Math(left[0].plain_latex), cmd=c.derive_command,
                               fn="lagrangian.derive"), style="note"))
    return Section("notes", c.w.text("notes"), tuple(blocks))
