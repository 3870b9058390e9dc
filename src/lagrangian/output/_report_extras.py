"""The parts after step 7: the Newton–Euler cross-check, the simulation's figures, the matrix form, a note.

Seed, last remark of the worked example: « Ces équations de Lagrange peuvent être retrouvées
en appliquant le théorème du moment dynamique en O à (S) par rapport à R … on retrouve
Lψ) par projection de cette équation sur la direction de l'axe de rotation z0 … ».  The
check itself is `lagrangian.analysis.verify`; this module only writes it.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

from ..analysis import Verification
from ._report_build import Context, tex_text
from ._report_doc import Block, Display, Equation, Image, Math, Para, Runs, Section

__all__ = ["ReportFigure", "check_section", "simulation_section", "matrix_section", "notes_section"]


@dataclass(frozen=True, slots=True)
class ReportFigure:
    """A figure for the report: PNG bytes and a caption (plain text)."""

    png: bytes
    caption: str

    def __post_init__(self) -> None:
        if not self.png.startswith(b"\x89PNG\r\n\x1a\n"):
            raise ValueError("a report figure must be a PNG image (its bytes start with the PNG signature)")


def check_section(c: Context, v: Verification) -> Section:
    w = c.w
    blocks: list[Block] = [Para(w("check intro", R0=Math("R_{0}")))]
    liaisons = w.text("constraint actions")
    for th in v.theorems:
        efforts = " + ".join(rf"\vec{{F}}({tex_text(e)})" for e in th.efforts) or r"\vec{0}"
        if th.kind == "particle":
            P = c.element(th.name)
            blocks.append(Para(w("resultant theorem", P=Math(P))))
            blocks.append(Display((Equation((rf"{c.tex(th.mass)}\,\vec{{\gamma}}({P}/R_{{0}}) = {efforts}"
                                             rf" + \vec{{R}}(\text{{{liaisons}}})",)),)))
            continue
        S = c.element(th.name)
        P = _point(c, th.point, th.name)
        moments = " + ".join(rf"\vec{{M}}_{{{P}}}({tex_text(e)})" for e in th.efforts) or r"\vec{0}"
        blocks.append(Para(w("moment theorem", P=Math(P), S=Math(S))))
        sigma = c.vector_equation(rf"\vec{{\sigma}}_{{{P}}}({S}/R_{{0}}) = \Pi_{{{P}}}({S})\cdot\vec{{\Omega}}({S}/R_{{0}}) = ",
                                  c.terms(th.angular_momentum))
        blocks.append(Display((Equation((rf"\vec{{\delta}}_{{{P}}}({S}/R_{{0}}) = \frac{{d}}{{dt}}\left[\vec{{\sigma}}_"
                                         rf"{{{P}}}({S}/R_{{0}})\right]_{{R_{{0}}}} = {moments} + \vec{{M}}_{{{P}}}"
                                         rf"(\text{{{liaisons}}})",)), sigma)))
    blocks.append(Para(w("perfect drop")))
    for check in v.checks:
        q = c.sym(check.coordinate)
        eq = Math(rf"L({q})")
        of: Runs = () if check.whole_system else w("of", names=w.join([Math(c.element(e)) for e in check.elements]))
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
        blocks.append(Para(head))
        mark = r"\quad\checkmark" if check.agrees else r"\quad\times"
        blocks += c.show([c.relation("", c.ex(check.newton_euler), c.ex(check.newton_euler_efforts), mark)],
                         f"L({check.coordinate})")
        if not check.agrees:
            blocks.append(Para(w("check failed", eq=eq), style="note"))
    return Section("check", w.text("check"), tuple(blocks))


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
        blocks.append(Image(fig.png, w("figure", k=str(k), caption=fig.caption), fig.caption))
    return Section("simulation", w.text("simulation"), tuple(blocks))


#: Most coordinates for which the appendix lists the entries of M and F (n(n + 1)/2 + n of them).
MATRIX_MAX = 12


def matrix_section(c: Context) -> Section:
    w = c.w
    q = c.eom.coordinates
    form = Math(r"M(q, t)\,\ddot{q} = F(q, \dot{q}, t)")
    if len(q) > MATRIX_MAX:
        count = sum(1 for a, row in enumerate(c.eom.M) for b, x in enumerate(row) if b >= a and x != 0)
        text = w("matrix large", form=form, n=Math(rf"{len(q)} \times {len(q)}"), k=str(count),
                 cmd="lagrangian derive --json")
        return Section("matrix", w.text("matrix"), (Para(text),))
    rows: list[Equation] = []
    for a, row in enumerate(c.form.M):
        for b, entry in enumerate(row):
            if b >= a and entry != 0:
                rows.append(c.equation(rf"M_{{{c.sym(q[a])}{c.sym(q[b])}}} = ", entry))
    rows += [c.equation(rf"F_{{{c.sym(q[a])}}} = ", f) for a, f in enumerate(c.form.F)]
    blocks: list[Block] = [Para(w("matrix intro", form=form))]
    blocks += c.many(c.show(rows, "M, F"), len(rows), "M, F")
    return Section("matrix", w.text("matrix"), tuple(blocks))


def notes_section(c: Context) -> Section | None:
    """A note on the expressions summarized as ⟨N terms⟩, when there are any."""
    if not c.gate.summaries:
        return None
    sample = Math(c.gate.summaries[0].latex_form)
    text = c.w("summaries", sample=sample, cmd="lagrangian derive --json", fn="lagrangian.derive")
    return Section("notes", c.w.text("notes"), (Para(text, style="note"),))
