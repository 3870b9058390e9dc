"""Step 3 (frames, Ω, inertia, the virtual velocity field) and step 4 (T and U_P with their formulas).

Seed, worked example:

    R0(O; x0, y0, z0) fixe →(ψ, Oz0) R1(O; u, v, z0) →(θ, Ou) R2(O; u, w, z) →(φ, Oz) R(O; x, y, z) lié à (S)
    Ω(S/R0) = ψ̇ z0 + θ̇ u + φ̇ z = θ̇ u + ψ̇ sinθ w + (φ̇ + ψ̇ cosθ) z
    T(S/R0) = ½ Ω(S/R0)·[Π_O(S)·Ω(S/R0)] = ½ A [θ̇² + ψ̇² sin²θ] + ½ C (φ̇ + ψ̇ cosθ)²
    U_P(S/R0) = + m g OG·z0 + cste = m g a cosθ + cste
"""

from __future__ import annotations

import symengine as se

from ....model import Gravity, PointForce, Potential, Spring, Vector
from ..build import Context
from ..document import Block, Display, Equation, Math, Para, Run, Runs, Section
from ..size import visible_width, wrap_many
from .statement import _frame_with_axes

#: The seed writes Ω(S/R0) = ψ̇ z0 + θ̇ u + φ̇ z = θ̇ u + ψ̇ sinθ w + (φ̇ + ψ̇ cosθ) z on one line; so do we up to this width.
LINE_WIDTH_OMEGA = 80

__all__ = ["step3", "step4"]


# -- step 3 ---------------------------------------------------------------------------------------
def _origins(c: Context) -> dict[str, str]:
    """The origin of each frame when the constraints fix it: O for R0 and the top's R1, R2, R; A for a hinge at A."""
    frames = {f.name: f for f in c.model.frames}
    out = {"R0": "O", c.ref: c.origin}
    for j in c.joints:
        if j.kind not in ("fixed point", "pivot", "ball joint") or j.point is None:
            continue
        stop = c.ref if j.support is None else c.model.body(j.support).frame
        f = c.model.body(j.element).frame
        while f != stop and f in frames and frames[f].parent is not None:
            out.setdefault(f, j.point)
            f = frames[f].parent  # type: ignore[assignment]
    return out


def _chains(c: Context) -> list[Equation]:
    frames = c.model.frames
    children: dict[str, list[str]] = {}
    for f in frames:
        if f.parent is not None:
            children.setdefault(f.parent, []).append(f.name)
    by_name = {f.name: f for f in frames}
    origins = _origins(c)
    owner = {b.frame: b.name for b in c.model.bodies}
    w = c.w

    def label(name: str) -> str:
        text = _frame_with_axes(c, name, origins.get(name))
        if name == "R0":
            return text + rf"\ \text{{{w.text('fixed')}}}"
        if name in owner:
            return text + rf"\ \text{{{w.text('attached')}}}\ ({c.element(owner[name])})"
        return text

    def arrow(name: str) -> str:
        frame = by_name[name]
        rot = frame.rotation
        origin = origins.get(name)
        if rot.elementary:  # type: ignore[union-attr]
            axis = c.axis(frame.axes["xyz".index(rot.axis)])  # type: ignore[union-attr]
        else:  # about a constant vector n of the parent, written in its basis
            axis = r"\left(" + c.vector(Vector({frame.parent: rot.direction})) + r"\right)"  # type: ignore
        where = (c.name(origin) if origin else "") + axis
        return rf"\xrightarrow{{{c.tex(rot.angle)},\ {where}}}"  # type: ignore[union-attr]

    lines: list[Equation] = []

    def walk(start: str, pieces: list[str]) -> None:
        kids = children.get(start, [])
        if not kids:
            lines.append(wrap_many("", pieces, " "))
            return
        for k, child in enumerate(kids):
            head = pieces if k == 0 else [label(start)]
            walk(child, head + [arrow(child), label(child)])

    walk("R0", [label("R0")])
    return [eq for eq in lines if len(eq.lines[0]) > len(label("R0"))] if len(lines) > 0 else []


def _inertia(c: Context) -> list[Block]:
    w = c.w
    out: list[Block] = []
    origins = _origins(c)
    for b in c.model.bodies:
        used = c.eom.inertias[b.name]
        S = Math(c.element(b.name))
        P = c.point_label(b.name) if used.point == "G" else c.point_label(used.point)
        matrix = used.matrix
        diagonal = all(matrix[i][j] == 0 for i in range(3) for j in range(3) if i != j)
        F = Math(_frame_with_axes(c, used.frame, origins.get(used.frame)))
        huygens: tuple = ()
        if b.inertia.at != used.point:
            given = c.point_label(b.name) if b.inertia.at == "G" else c.point_label(b.inertia.at)
            huygens = w("huygens", A=Math(given), P=Math(P))
        if diagonal:
            runs = w("principal frame", F=F, S=S, P=Math(P), huygens=huygens)
        else:
            runs = w("inertia frame", P=Math(P), S=S, basis=Math(c.basis(used.frame)), F=Math(c.name(used.frame)),
                     huygens=huygens)
        rows = r" \\ ".join(" & ".join(c.tex(x) for x in row) for row in matrix)
        out.append(Para(runs))
        out.append(Display((Equation((rf"\Pi_{{{P}}}({c.element(b.name)}) = \begin{{bmatrix}} {rows} \end{{bmatrix}}",)),)))
    return out


def _omegas(c: Context) -> list[Equation]:
    steps = {f.name: f for f in c.form.frames}
    out = []
    for b in c.model.bodies:
        f = steps.get(b.frame)
        if f is None:
            continue
        chain = c.n.vector(f.omega_chain.terms, latex=True)
        text = rf"\vec{{\Omega}}({c.element(b.name)}/{c.R}) = {chain}"
        if f.omega_components is not None:
            alt = c.n.vector(f.omega_components.terms, latex=True)
            if alt != chain:
                joined = f"{text} = {alt}"
                out.append(Equation((joined,)) if visible_width(joined) <= LINE_WIDTH_OMEGA else Equation((text, f"= {alt}")))
                continue
        out.append(Equation((text,)))
    return out


def torsor_point(c: Context, name: str) -> str:
    """The point A where the virtual torsor of a body is written: its fixed point (O for the top), else its centre G."""
    body = c.model.body(name)
    return body.fixed_point if body.fixed_point is not None else name


def virtual_torsor(c: Context, name: str) -> tuple[Vector, Vector]:
    """(Ω*(S/R), V*(A ∈ S/R)) of body ``name`` at `torsor_point`: Ω* = Σ ∂Ω/∂q̇_i q_i*, V*(A) = Σ ∂OA/∂q_i q_i*.

    Course, step 3: the virtual velocity field of a rigid body is a torsor (« champ équiprojectif »),
    V*(P) = V*(A) + Ω* ∧ AP for every point P of (S).
    """
    body = c.model.body(name)
    omega = Vector.zero()
    for part, star in zip(c.kin.partial_omegas(body.frame), c.kin.q_star, strict=True):
        omega = omega + part * star
    return omega, c.kin.virtual_velocity(torsor_point(c, name))


def _virtual_torsors(c: Context) -> list[Block]:
    """{V*(S/R)} = {Ω*(S/R) ; V*(A ∈ S/R)}_A for every rigid body (the course's torseur cinématique virtuel)."""
    out: list[Block] = []
    R = c.R
    for b in c.model.bodies:
        S = c.element(b.name)
        A = c.point_label(torsor_point(c, b.name))
        omega, v = virtual_torsor(c, b.name)
        head = (rf"\left\{{\mathcal{{V}}^{{*}}({S}/{R})\right\}} = \left\{{\begin{{matrix}} \vec{{\Omega}}^{{*}}({S}/{R})"
                rf" \\ \vec{{V}}^{{*}}({A}\in {S}/{R}) \end{{matrix}}\right\}}_{{{A}}}")
        eqs = [Equation((head,)),
               c.vector_equation(rf"\vec{{\Omega}}^{{*}}({S}/{R}) = ", c.terms(omega)),
               c.vector_equation(rf"\vec{{V}}^{{*}}({A}\in {S}/{R}) = ", c.terms(v))]
        out.append(Display(tuple(eqs)))
    return out


def comoment_conditions(c: Context, j) -> list[se.Basic] | None:
    """The scalars whose vanishing makes the comoment of a perfect principal constraint's action torsor with the
    virtual kinematic torsor zero, as step 3 states it; None for a constraint it does not argue.

    Comoment at the joint's point X: P* = R·V*(X ∈ S/S₁) + M_X·Ω*(S/S₁) (S₁ the support, R0 if none).
    fixed point, ball joint: V*(X ∈ S/S₁) = 0 and M_X = 0; pivot of axis e: V*(X ∈ S/S₁) = 0 and
    Ω*(S/S₁) ∧ e = 0 (M_X·e = 0); rod XP: XP·V*(P) = 0 (R along XP) and n·V*(P) = 0 for each plane normal;
    plane of normal n: n·V*(P) = 0 (R = N n); line e: V*(P) ∧ e = 0 (R ⟂ e); body plane: n·V*(G) = 0 (R = N n)
    and Ω* along the allowed rotations (M_G orthogonal to them).
    """
    kin, frames = c.kin, c.kin.frames

    def vstar_on(body: str | None, point: str) -> Vector:
        # V*(X ∈ S) = V*(A) + Ω*(S) ∧ AX with A the torsor's point of S (V*(X) for R0 or a particle).
        if body is None or body not in c.bodies:
            return kin.virtual_velocity(point) if body is not None else Vector.zero()
        omega, v = virtual_torsor(c, body)
        A = torsor_point(c, body)
        return v + frames.cross(omega, kin.position(point) - kin.position(A))

    def omega_star(body: str | None) -> Vector:
        return virtual_torsor(c, body)[0] if body is not None and body in c.bodies else Vector.zero()

    def comps(v: Vector) -> list[se.Basic]:
        return list(frames.express(v, c.ref))

    def axis_vector(name: str) -> Vector:
        frame = next(f for f in frames.frames if name in frames.axes(f))
        k = frames.axes(frame).index(name)
        return Vector({frame: tuple(se.Integer(int(i == k)) for i in range(3))})

    if not j.perfect or j.point is None and j.kind != "body plane":
        return None
    if j.kind in ("fixed point", "ball joint", "pivot"):
        relative = vstar_on(j.element, j.point) - vstar_on(j.support, j.point)
        out = comps(relative)
        if j.kind == "pivot":
            if j.axis is None:
                return None
            rotation = omega_star(j.element) - omega_star(j.support)
            out += comps(frames.cross(rotation, axis_vector(j.axis)))
        return out
    v = kin.virtual_velocity(j.element)
    if j.kind == "rod":
        d = kin.position(j.element) - kin.position(j.point)
        rel = v - kin.virtual_velocity(j.point)
        return [frames.dot(d, rel)] + [frames.dot(axis_vector(a), rel) for a in j.normals]
    if j.kind == "plane":
        return [frames.dot(axis_vector(a), v) for a in j.normals]
    if j.kind == "line" and j.axis is not None:
        return comps(frames.cross(v, axis_vector(j.axis)))
    if j.kind == "body plane":
        out = [frames.dot(axis_vector(a), v) for a in j.normals]
        turns = [axis_vector(a) for a in j.turns]
        omega = omega_star(j.element)
        if len(turns) == 1:
            out += comps(frames.cross(omega, turns[0]))
        elif len(turns) == 2:
            out.append(frames.dot(omega, frames.cross(turns[0], turns[1])))
        return out
    return None


def _comoments(c: Context) -> list[Block]:
    """Step 3: why each perfect principal constraint does no virtual work — the comoment of its action torsor
    {R ; M_X}_X with the virtual kinematic torsor is zero (stated only where `comoment_conditions` vanish)."""
    from ...._identity import are_zero

    w, R = c.w, c.R
    because = rf"\text{{{w.text('because')}}}\quad"
    et = rf"\quad\text{{{w.text('et')}}}\quad"
    out: list[Block] = []
    for j in c.joints:
        conditions = comoment_conditions(c, j)
        if conditions is None or not all(are_zero(conditions)):
            continue
        S = c.element(j.element)
        X = c.point_label(j.point) if j.point else ""
        if j.kind in ("fixed point", "ball joint", "pivot"):
            S1 = c.element(j.support) if j.support is not None else R
            rel = rf"{S}/{S1}"
            eq = rf"P^{{*}} = \vec{{R}}_{{{X}}}\cdot\vec{{V}}^{{*}}({X}\in {rel}) + \vec{{M}}_{{{X}}}\cdot\vec{{\Omega}}^{{*}}({rel}) = 0"
            if j.kind == "pivot":
                e = c.axis(j.axis)  # type: ignore[arg-type]
                rotation = c.vector(j.rotation) if j.rotation is not None else ""
                why = (rf"{because} \vec{{V}}^{{*}}({X}\in {rel}) = \vec{{0}},\quad "
                       rf"\vec{{\Omega}}^{{*}}({rel}) = {rotation} {et} \vec{{M}}_{{{X}}}\cdot{e} = 0")
                key = "comoment pivot"
            else:
                why = rf"{because} \vec{{V}}^{{*}}({X}\in {rel}) = \vec{{0}} {et} \vec{{M}}_{{{X}}} = \vec{{0}}"
                key = "comoment fixed point" if j.kind == "fixed point" else "comoment ball"
            support = ("(", Math(S1), ")") if j.support is not None else (Math(S1),)
            out += [Para(w(key, S=Math(S), X=Math(X), S1=support)), Display((Equation((eq, why)),))]
        elif j.kind in ("rod", "plane", "line"):
            along: Run | Runs
            P = c.element(j.element)
            V = rf"\vec{{V}}^{{*}}({P})"
            if j.kind == "rod":
                XP = rf"\overrightarrow{{{X}{P}}}"
                dirs = [XP] + [c.axis(a) for a in j.normals]
                why = rf"{because} " + r",\ ".join(rf"{d}\cdot{V} = 0" for d in dirs)
                if not c.kin.is_fixed(j.point):  # type: ignore[arg-type]
                    V = rf"\left({V} - \vec{{V}}^{{*}}({X})\right)"
                    why = rf"{because} " + r",\ ".join(rf"{d}\cdot{V} = 0" for d in dirs)
                key, along = "comoment rod", w.join([Math(d) for d in dirs])
            elif j.kind == "plane":
                normal = c.axis(j.normals[0])
                why, key, along = rf"{because} {normal}\cdot{V} = 0", "comoment plane", Math(normal)
            else:
                e = c.axis(j.axis)  # type: ignore[arg-type]
                why, key, along = rf"{because} {V}\wedge{e} = \vec{{0}}", "comoment line", Math(e)
            eq = rf"P^{{*}} = \vec{{R}}\cdot{V} = 0"
            out += [Para(w(key, P=Math(P), dirs=along)), Display((Equation((eq, why)),))]
        elif j.kind == "body plane":
            G = c.point_label(j.element)
            n = w.join([Math(c.axis(a)) for a in j.normals])
            allowed = w.join([Math(c.axis(a)) for a in j.turns])
            eq = (rf"P^{{*}} = \vec{{R}}\cdot\vec{{V}}^{{*}}({G}\in {S}/{R}) + \vec{{M}}_{{{G}}}\cdot"
                  rf"\vec{{\Omega}}^{{*}}({S}/{R}) = 0")
            why = (rf"{because} " + r",\ ".join(rf"{c.axis(a)}\cdot\vec{{V}}^{{*}}({G}) = 0" for a in j.normals)
                   + rf" {et} \vec{{\Omega}}^{{*}}({S}/{R}) \in \mathrm{{vect}}("
                   + ", ".join(c.axis(a) for a in j.turns) + ")")
            out += [Para(w("comoment body plane", S=Math(S), G=Math(G), n=n, turns=allowed)),
                    Display((Equation((eq, why)),))]
    if out:
        comoment = Math(r"P^{*} = \vec{R}\cdot\vec{V}^{*}(X) + \vec{M}_{X}\cdot\vec{\Omega}^{*}")
        out.insert(0, Para(w("comoment intro", P=comoment,
                             torsor=Math(r"\left\{\vec{R} \,;\, \vec{M}_{X}\right\}_{X}"))))
    return out


def step3(c: Context) -> Section:
    w = c.w
    blocks: list[Block] = []
    chains = _chains(c)
    if chains:
        blocks.append(Para(w("frames")))
        blocks += c.many([Display(tuple(chains))], len(chains), w.text("frames").rstrip(" :"))
    blocks += c.many(_inertia(c), len(c.model.bodies), "Π", limit=6)
    omegas = _omegas(c)
    if omegas:
        blocks += c.many([Display(tuple(omegas))], len(omegas), w.text("angular velocities").rstrip(" :"))
    field = Math(r"\vec{V}^{*}(P) = \sum_{i=1}^{n} \frac{\partial \overrightarrow{OP}}{\partial q_i}\, q_i^{*}")
    rows = [c.vector_equation(rf"\vec{{V}}^{{*}}({c.name(p)}) = ", v.terms) for p, v in c.form.virtual_velocities]
    blocks.append(Para(w("virtual field", field=field)))
    if rows:
        blocks += c.many(c.show(rows, r"V*"), len(rows), "V*")
    torsors = _virtual_torsors(c)
    if torsors:
        A, P = c.free_letter("A", "B", "D", "J"), c.free_letter("P", "M", "Y")  # not the top's A, the bob P
        AP = (rf"\vec{{V}}^{{*}}({P}\in S/{c.R}) = \vec{{V}}^{{*}}({A}\in S/{c.R}) + \vec{{\Omega}}^{{*}}(S/{c.R})"
              rf"\wedge\overrightarrow{{{A}{P}}}")
        blocks.append(Para(w("virtual torsor", field=Math(AP), A=Math(A))))
        blocks += c.many(torsors, len(c.model.bodies), w.text("virtual torsor short"), limit=6)
    comoments = _comoments(c)
    blocks += c.many(comoments, len(c.joints), w.text("comoment short"), limit=8)
    return Section("step3", w.text("step3"), tuple(blocks))


# -- step 4 ---------------------------------------------------------------------------------------
_T_FORMULA = {
    "fixed point": r"\frac{{1}}{{2}}\,\vec{{\Omega}}({S}/{R})\cdot\left[\Pi_{{{P}}}({S})\cdot\vec{{\Omega}}({S}/{R})\right]",
    "König": (r"\frac{{1}}{{2}} {m}\,\vec{{V}}^{{2}}({G}/{R}) + \frac{{1}}{{2}}\,\vec{{\Omega}}({S}/{R})\cdot"
              r"\left[\Pi_{{{G}}}({S})\cdot\vec{{\Omega}}({S}/{R})\right]"),
    "particle": r"\frac{{1}}{{2}} {m}\,\vec{{V}}^{{2}}({S}/{R})",
}


def _kinetic(c: Context) -> list[Block]:
    # One element: its T is T(Σ/R), whose full form (when summarized) goes under it; numbered before it is written.
    single = c.full([(rf"T(\Sigma/{c.R}) = ", c.form.T[0].expression)], f"T(Σ/{c.ref})") if len(c.form.T) == 1 else []
    rows = []
    for term, shown in zip(c.eom.T_terms, c.form.T, strict=True):
        S = c.element(term.name)
        mass = next((b.mass for b in c.model.bodies if b.name == term.name),
                    next((p.mass for p in c.model.particles if p.name == term.name), None))
        P = c.point_label(term.inertia.point) if term.inertia is not None and term.inertia.point != "G" else ""
        formula = _T_FORMULA.get(term.formula, "").format(S=S, R=c.R, P=P, G=c.point_label(term.name),
                                                          m=c.mass_tex(term.name) if mass is not None else "m")
        head = rf"T({S}/{c.R}) = " + (f"{formula} = " if formula else "")
        rows.append(c.equation(head, shown.expression))
    blocks = c.many(c.show(rows, "T"), len(rows), "T") + single
    blocks += c.many(_inertia_operators(c), len(c.model.bodies), "Π", limit=6)
    if len(rows) > 1:
        head = rf"T(\Sigma/{c.R}) = "
        names = [rf"T({c.element(t.name)}/{c.R})" for t in c.eom.T_terms]
        total = " + ".join(names) if len(names) <= 4 else rf"\sum_{{k}} T(S_{{k}}/{c.R})"
        full = c.full([(head, c.form.T_total)], f"T(Σ/{c.ref})")
        blocks += c.show([c.equation(rf"{head}{total} = ", c.form.T_total)], "T") + full
    return blocks


def _inertia_operators(c: Context) -> list[Block]:
    """Where T first uses Π_P(S) (½ Ω·[Π_O(S)·Ω] for the top): what it is — the inertia operator of (S) at P,
    whose matrix in the basis of step 3 gives T = ½ Ωᵀ [Π_P(S)] Ω with Ω's components in that basis."""
    out: list[Block] = []
    for term in c.eom.T_terms:
        if term.inertia is None or term.formula not in ("fixed point", "König"):
            continue
        S = c.element(term.name)
        P = c.point_label(term.name) if term.inertia.point == "G" else c.point_label(term.inertia.point)
        Pi = rf"\Pi_{{{P}}}({S})"
        # Π_P(S)·Ω = σ_P(S/R) = ∫ PM ∧ (Ω ∧ PM) dm, P fixed in S and R (the top's O) or the centre of mass G.
        Omega = rf"\vec{{\Omega}}({S}/{c.R})"
        v = (rf"\Pi_{{{P}}}({S})\cdot{Omega} = \int_{{M\in {S}}} \overrightarrow{{{P}M}}\wedge\left({Omega}"
             rf"\wedge\overrightarrow{{{P}M}}\right) dm = \vec{{\sigma}}_{{{P}}}({S}/{c.R})")
        out.append(Para(c.w("inertia operator", Pi=Math(Pi), S=Math(S), P=Math(P), op=Math(v),
                            basis=Math(c.basis(term.inertia.frame)))))
    return out


def _gravity_formula(c: Context, load: Gravity) -> str:
    names = load.on or tuple(b.name for b in c.model.bodies) + tuple(p.name for p in c.model.particles)
    masses = {b.name: b.mass for b in c.model.bodies} | {p.name: p.mass for p in c.model.particles}
    pieces = [(f, k, x) for f, comps in c.kin.frames.lift(load.field) for k, x in enumerate(comps) if x != 0]
    O = c.name(c.origin)
    if len(pieces) == 1 and len(names) <= 3:
        frame, k, comp = pieces[0]
        axis = c.axis(c.kin.frames.axes(frame)[k])
        terms = []
        for name in names:
            mass = masses[name]
            # a number (a URDF's 8 kg) is written m_S: m_S g OG·z0, not 8 g OG·z0
            coeff = c.tex(-comp * mass) if mass.free_symbols else f"{c.mass_tex(name)}\\,{c.tex(-comp)}"
            terms.append(rf"{coeff}\,\overrightarrow{{{O}{c.point_label(name)}}}\cdot{axis}")
        text = terms[0]
        for t in terms[1:]:
            text += f" - {t[1:]}" if t.startswith("-") else f" + {t}"
        return text
    if len(names) == 1:
        return rf"-{c.mass_tex(names[0])}\,{c.field_tex(load)}\cdot\overrightarrow{{{O}{c.point_label(names[0])}}}"
    return rf"-\sum_{{k}} m_{{k}}\,{c.field_tex(load)}\cdot\overrightarrow{{{O}G_{{k}}}}"


def _potential_formula(c: Context, kind: str, name: str) -> str:
    load = next((x for x in c.model.loads if x.name == name), None)
    if isinstance(load, Gravity):
        return _gravity_formula(c, load)
    if isinstance(load, Spring):
        a, b = (c.point_label(p) for p in load.ends)
        ell = rf"\left\|\overrightarrow{{{a}{b}}}\right\|"
        if load.rest_length == 0:
            return rf"\frac{{1}}{{2}} {c.tex(load.stiffness)}\,{ell}^{{2}}"
        return rf"\frac{{1}}{{2}} {c.tex(load.stiffness)} \left({ell} - {c.tex(load.rest_length)}\right)^{{2}}"
    if isinstance(load, PointForce):
        return rf"-\vec{{F}}\cdot\overrightarrow{{{c.name(c.origin)}{c.point_label(load.at)}}}"
    if isinstance(load, Potential):
        return ""
    if kind == "inertial: entrainment":
        # Remarque 3, written with this model's frame R, its origin O and its elements.
        O, R, G = c.name(c.origin), c.R, _inertia_centre(c)
        Omega = rf"\vec{{\Omega}}({R}/R_{{0}})"
        m = "m" if G != "G" else r"\sum m"
        return (rf"{m}\,\vec{{\gamma}}({O}/R_{{0}})\cdot\overrightarrow{{{O}{G}}} - \frac{{1}}{{2}}\,{Omega}\cdot"
                rf"\Pi_{{{O}}}(\Sigma)\cdot{Omega}")
    return ""


def _inertia_centre(c: Context) -> str:
    """G in the entrainment potential: the element's own point when there is one, else G (each element's)."""
    elements = [b.name for b in c.model.bodies] + [p.name for p in c.model.particles]
    return c.point_label(elements[0]) if len(elements) == 1 else "G"


def entrainment_conditions(c: Context) -> tuple[bool, bool]:
    """(dΩ(R/R0)/dt = 0, γ(O/R0) = 0) for the frame R of the equations: the two terms of the entrainment force that
    decide whether it derives from a potential (Remarque 3)."""
    from ...._identity import are_zero
    from ....dynamics import RelativeKinematics

    kin = c.kin
    if not isinstance(kin, RelativeKinematics):
        return True, True

    def comps(v: Vector) -> list[se.Basic]:
        return list(kin.frames.absolute.express(v, "R0")) if not v.is_zero() else []

    constant = all(are_zero(comps(kin.frame_omega_rate))) if comps(kin.frame_omega_rate) else True
    fixed = all(are_zero(comps(kin.origin_acceleration))) if comps(kin.origin_acceleration) else True
    return constant, fixed


def _entrainment_terms(c: Context) -> list[Block]:
    """What the entrainment potential's symbols are (Remarque 3), and why it exists: Ω(R/R0) constant, so the term
    dΩ/dt ∧ OP (which derives from no potential) vanishes; with O fixed in R0, the γ(O/R0) term vanishes too."""
    w = c.w
    O, G = c.name(c.origin), _inertia_centre(c)
    Omega = rf"\vec{{\Omega}}({c.R}/R_{{0}})"
    out: list[Block] = [Para(w("entrainment terms", gamma=Math(rf"\vec{{\gamma}}({O}/R_{{0}})"), O=Math(O), R=Math(c.R),
                               R0=Math("R_{0}"), G=Math(G), Omega=Math(Omega),
                               Pi=Math(rf"\Pi_{{{O}}}(\Sigma)"), many="" if G != "G" else w.text("each element")))]
    constant, fixed = entrainment_conditions(c)
    if constant:
        rate = Math(rf"\frac{{d{Omega}}}{{dt}} = \vec{{0}}")
        term = Math(rf"\frac{{d{Omega}}}{{dt}}\wedge\overrightarrow{{{O}P}}")
        if fixed:
            out.append(Para(w("entrainment potential fixed", rate=rate, term=term, O=Math(O), R0=Math("R_{0}"),
                              Omega=Math(Omega),
                              gamma=Math(rf"\vec{{\gamma}}({O}/R_{{0}}) = \vec{{0}}"))))
        else:
            out.append(Para(w("entrainment potential moving", rate=rate, term=term, O=Math(O), Omega=Math(Omega),
                              gamma=Math(rf"\vec{{\gamma}}({O}/R_{{0}})"))))
    return out


def _potential(c: Context) -> list[Block]:
    w = c.w
    cste = rf" + \text{{{w.text('cste')}}}"
    loads = [(f, row) for f, row in zip((f for f in c.eom.loads if f.potential is not None), c.form.U, strict=True)]
    if not loads:
        return [Para(w("no potential", U=Math(rf"U_P(\Sigma/{c.R}) = 0")))]
    head = rf"U_P(\Sigma/{c.R}) = "
    alone = c.full([(head, loads[0][1].expression)], f"U_P(Σ/{c.ref})") if len(loads) == 1 else []
    elements = len(c.model.bodies) + len(c.model.particles)
    single = len(loads) == 1 and elements == 1
    rows = []
    for f, row in loads:
        if single:
            only = (c.model.bodies[0].name if c.model.bodies else c.model.particles[0].name)
            label = rf"U_P({c.element(only)}/{c.R})"
        else:
            label = rf"U_P({c.load_tex(f.name)})"
        formula = _potential_formula(c, f.kind, f.name)
        head = f"{label} = " + (f"{formula}{cste} = " if formula else "")
        if row.expression == 0 and formula:  # m g OG·z0 + cste with OG·z0 = r: a constant, « = cste », not « 0 + cste »
            rows.append(Equation((head + cste.removeprefix(" + "),)))
            continue
        rows.append(c.equation(head, row.expression, cste))
    blocks: list[Block] = []
    if not single:
        blocks.append(Para(w("potential of")))
    blocks += c.show(rows, "U_P") + alone
    if any(f.kind == "inertial: entrainment" for f, _ in loads):
        blocks += _entrainment_terms(c)
    # The total U_P(Σ/R), under its own name, when it sums at least two terms that are not zero.
    if sum(1 for _, row in loads if row.expression != 0) > 1:
        total = rf"U_P(\Sigma/{c.R}) = "
        full = c.full([(total, c.form.U_total)], f"U_P(Σ/{c.ref})")
        blocks += c.show([c.equation(total, c.form.U_total, cste)], "U_P") + full
    return blocks


def step4(c: Context) -> Section:
    blocks: list[Block] = [Para(c.w("energies", R=Math(c.R)))]
    blocks += _kinetic(c)
    blocks += _potential(c)
    return Section("step4", c.w.text("step4"), tuple(blocks))

