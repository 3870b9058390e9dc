"""The system, step 1 (the principal constraints, classified) and step 2 (the principal parameters).

Seed, "Démarche d'application", steps 1 and 2, and the worked example: « La seule liaison
est la liaison "O point fixe" … Elle est holonome, indépendante du temps et principale.
Elle est parfaite car la puissance virtuelle de la réaction R_O en O est nulle … On a donc
3 paramètres principaux qui sont les angles d'Euler ψ, θ et φ de (S). »
"""

from __future__ import annotations

import re

from ....dynamics import describe_constraints
from ....model import Constraint, Vector, in_language
from ..build import Context
from ..document import Block, Display, Equation, Fold, Items, Math, Para, Runs, Section, Table
from ..joints import Joint, constraint_counts, degrees_of_freedom, planar_normal

__all__ = ["system_section", "step1", "step2"]

#: Constraints written out in step 1 before the others are folded (a chain has one per link).
SHOWN_CONSTRAINTS = 4



_SUPERSCRIPTS = str.maketrans("0123456789-", "⁰¹²³⁴⁵⁶⁷⁸⁹⁻")


def _unit(unit: str | None) -> str:
    """A unit as printed: ``m/s^2`` → m/s², ``kg m^2`` → kg·m² (the file keeps plain ASCII)."""
    if not unit:
        return ""
    text = re.sub(r"\^\(?(-?\d+)\)?", lambda m: m.group(1).translate(_SUPERSCRIPTS), unit.replace("**", "^"))
    return re.sub(r"(?<=\w|[⁰¹²³⁴⁵⁶⁷⁸⁹])\s*\*\s*|(?<=\w|[⁰¹²³⁴⁵⁶⁷⁸⁹]) +(?=\w)", "·", text)

def _frame_with_axes(c: Context, frame: str, origin: str | None) -> str:
    axes = ", ".join(c.axis(a) for a in c.kin.frames.axes(frame))
    return f"{c.name(frame)}({c.name(origin)};\\ {axes})" if origin else f"{c.name(frame)}({axes})"


def _mass_given(c: Context, name: str, mass) -> str:
    """m, or m_S = 8 kg for a number (so that later formulas can write m_S)."""
    if mass.free_symbols:
        return c.tex(mass)
    return f"{c.mass_tex(name)} = {c.quantity(mass, 'kg')}"


def _inertia_given(c: Context, body) -> Runs:
    """The inertia of a body as the model gives it: principal moments, or the matrix, at a point in a basis."""
    i = body.inertia
    P = Math(c.point_label(body.name) if i.at == "G" else c.point_label(i.at))
    basis = Math(c.basis(i.frame))
    m = i.matrix
    numbers = c.si and not any(x.free_symbols for row in m for x in row)
    unit = r"\ \mathrm{kg\cdot m^{2}}" if numbers else ""  # a URDF's inertias: numbers in kg·m²
    if all(m[r][k] == 0 for r in range(3) for k in range(3) if r != k):
        return c.w("inertia principal given", P=P, basis=basis,
                   values=Math(r",\ ".join(c.tex(m[k][k]) for k in range(3)) + unit))
    rows = r" \\ ".join(" & ".join(c.tex(x) for x in row) for row in m)
    return c.w("inertia matrix given", P=P, basis=basis,
               matrix=Math(rf"\begin{{bmatrix}} {rows} \end{{bmatrix}}" + unit))


def _load_given(c: Context, load: object) -> Runs | None:  # noqa: PLR0911 - one phrase per kind of load
    """A load as the model declares it, in words and formulas (``pesanteur g = −g z0``)."""
    from ....model import (
        CoulombFriction,
        Damper,
        Dissipation,
        GeneralizedForce,
        Gravity,
        JointDamper,
        PointForce,
        Potential,
        Spring,
        Torque,
    )

    w = c.w
    if isinstance(load, Gravity):
        g = Math(rf"{c.field_tex(load)} = {c.vector(load.field)}")
        weight = c.field_tex(load) == r"\vec{g}"  # else a uniform field that is not ± g along an axis
        if load.on:
            return w("load on" if weight else "load field on", g=g, on=w.join([Math(c.element(x)) for x in load.on]))
        return w("load gravity" if weight else "load field", g=g)
    if isinstance(load, PointForce):
        return w("load force", F=Math(rf"\vec{{F}} = {c.vector(load.force)}"), P=Math(c.point_label(load.at)))
    if isinstance(load, Torque):
        C = Math(rf"\vec{{C}} = {c.vector(load.torque)}")
        if load.reaction_on is None:
            return w("load torque", C=C, S=Math(c.element(load.on)))
        return w("load torque reaction", C=C, S=Math(c.element(load.on)), S2=Math(c.element(load.reaction_on)))
    if isinstance(load, Spring):
        A, B = (Math(c.point_label(p)) for p in load.ends)
        return w("load spring", A=A, B=B, k=Math(c.tex(load.stiffness)), l0=Math(c.tex(load.rest_length)))
    if isinstance(load, Damper):
        A, B = (Math(c.point_label(p)) for p in load.ends)
        return w("load damper", A=A, B=B, c=Math(c.tex(load.coefficient)))
    if isinstance(load, Potential):
        rates = any(s in load.energy.free_symbols for s in c.kin.qd)  # a generalized potential U(q, q̇, t)
        return w("load generalized potential" if rates else "load potential", U=Math(rf"U = {c.tex(load.energy)}"))
    if isinstance(load, Dissipation):
        return w("load dissipation", D=Math(rf"D = {c.tex(load.function)}"))
    if isinstance(load, JointDamper):
        S1, S2 = (Math(c.element(x)) for x in load.bodies)
        return w("load joint damper", S1=S1, S2=S2, c=Math(c.tex(load.coefficient)))
    if isinstance(load, CoulombFriction):
        return w("load coulomb", P=Math(c.point_label(load.at)), f=Math(c.tex(load.coefficient)))
    if isinstance(load, GeneralizedForce):
        Q = r",\ ".join(rf"Q_{{{c.sym(q)}}} = {c.tex(v)}" for q, v in load.components)
        return w("load generalized", Q=Math(Q))
    return None


def _constraint_given(c: Context, con: Constraint) -> Runs:
    """A declared constraint: its description in the report's language (else its name) and its equation."""
    w = c.w
    if con.form == "no_slip":
        I, S = c.point_label(con.points[0]), c.element(con.body or "")
        equation = rf"\vec{{V}}({I}\in {S}/{c.R}) = \vec{{0}}"
    elif con.form == "coincide":
        P, Q = c.point_label(con.points[0]), c.point_label(con.points[1])
        equation = rf"\overrightarrow{{{Q}{P}}} = \vec{{0}}"
    else:
        rows = [r for r in c.eom.constraints if r.constraint == con.name]
        parts = [rf"{c.tex(r.expression)} " + (r"\geq 0" if con.unilateral and r.name == con.name else "= 0")
                 for r in rows]  # a contact: its gap g ≥ 0
        if not parts and con.expression is not None and not isinstance(con.expression, Vector):
            parts = [rf"{c.tex(con.expression)} = 0"]
        equation = r",\quad ".join(parts)
    label: Runs = (c.constraint_label(con.name),)
    return w("constraint item", label=label, equation=Math(equation) if equation else "")


def _vertical(c: Context) -> Runs | None:
    """« O z0 est la verticale ascendante » (or descendante: the bicycle's z0 points down), when the weight is along
    one axis of R0; its sign is read at the model's values (g > 0), else from the expression."""
    from ....model import Gravity

    fields = [load.field for load in c.model.loads if isinstance(load, Gravity)]
    if len(fields) != 1:
        return None
    frames = c.kin.frames.absolute if hasattr(c.kin.frames, "absolute") else c.kin.frames
    comps = list(frames.express(fields[0], "R0"))
    nonzero = [k for k, x in enumerate(comps) if x != 0]
    if len(nonzero) != 1:
        return None
    k = nonzero[0]
    value = c.initial_value(comps[k])
    down = value > 0 if value is not None else not comps[k]._sympy_().could_extract_minus_sign()
    axis = Math(rf"O{c.axis(c.kin.frames.axes('R0')[k])}")
    g = Math(rf"\vec{{g}} = {c.vector(fields[0])}")
    return c.w("vertical down" if down else "vertical up", axis=axis, g=g)


def system_section(c: Context) -> Section:
    """The statement (« Énoncé ») a teacher hands out: the system, R0, the bodies, the constants, the loads, the
    constraints, all as the model declares them (before any step of the démarche)."""
    w, model = c.w, c.model
    blocks: list[Block] = []
    what = in_language(model.description, c.lang)
    if what:
        what = what.rstrip(". ")
        if len(what) > 1 and what[1].islower():  # « … suivant : toupie symétrique … » (not an acronym)
            what = what[0].lower() + what[1:]
        blocks.append(Para(w("statement intro", what=what)))
    blocks.append(Para(w("galilean", R0=Math(_frame_with_axes(c, "R0", "O")))))
    vertical = _vertical(c)
    if vertical is not None:
        blocks.append(Para(vertical))
    if c.ref != "R0":
        blocks.append(Para(w("reference", R=Math(_frame_with_axes(c, c.ref, c.origin)))))
    items: list[Runs] = []
    origin = c.name(c.origin)
    for b in model.bodies:
        G = c.point_label(b.name)
        OG = Math(rf"\overrightarrow{{{origin}{G}}} = {c.short_vector(c.kin.position(b.name))}")
        if b.mass_given:
            item = w("body item", S=Math(c.element(b.name)), m=Math(_mass_given(c, b.name, b.mass)), G=Math(G), OG=OG)
        else:
            item = w("body item no mass", S=Math(c.element(b.name)), G=Math(G), OG=OG)
        items.append(item + (", ",) + _inertia_given(c, b))
    for p in model.particles:
        OP = Math(rf"\overrightarrow{{{origin}{c.element(p.name)}}} = {c.short_vector(c.kin.position(p.name))}")
        items.append(w("particle item", P=Math(c.element(p.name)), m=Math(_mass_given(c, p.name, p.mass)), OP=OP))
    if items:
        blocks.append(Para(w("constituents")))
        blocks += c.many([Items(tuple(items))], len(items), w.text("constituents").rstrip(" :"))
    # The points the constraints and loads name (A of a hinge, the contact point I): where they are.
    points = [p.name for p in model.points if p.name not in ("O", c.origin) and not p.name.startswith("_")]
    if points:
        rows = tuple((Math(rf"\overrightarrow{{{origin}{c.point_label(p)}}} = {c.short_vector(c.kin.position(p))}"),)
                     for p in points)
        blocks.append(Para(w("points given")))
        blocks += c.many([Items(rows)], len(rows), w.text("points given").rstrip(" :"))
    constants = [p for p in model.parameters if not p.input]
    if constants:
        constant_rows = tuple(((Math(c.sym(p.name)),), ("" if p.value is None else w.number(p.value),),
                               (_unit(p.unit),), (in_language(p.description, c.lang) or "",)) for p in constants)
        header = tuple((w.text(k),) for k in ("col symbol", "col value", "col unit", "col description"))
        blocks.append(Para(w("parameters")))
        blocks += c.many([Table(header, constant_rows)], len(constant_rows), w.text("parameters").rstrip(" :"))
    inputs = [p for p in model.parameters if p.input]
    if inputs:  # a motor's τ(t), a push F(t): given functions of time, not constants
        input_rows = tuple(((Math(c.sym(p.name)),), (_unit(p.unit),), (in_language(p.description, c.lang) or "",))
                           for p in inputs)
        header = tuple((w.text(k),) for k in ("col symbol", "col unit", "col description"))
        blocks.append(Para(w("inputs")))
        blocks += c.many([Table(header, input_rows)], len(input_rows), w.text("inputs").rstrip(" :"))
    loads = [(load, _load_given(c, load)) for load in model.loads]
    load_items = tuple(w("load item", name=w.load(load.name), what=what) for load, what in loads
                       if what is not None)
    if load_items:
        blocks.append(Para(w("loads given")))
        blocks += c.many([Items(load_items)], len(load_items), w.text("loads given").rstrip(" :"))
    links = tuple(_joint_name(c, j) for j in c.joints) + tuple(_constraint_given(c, con) for con in model.constraints)
    if links:
        blocks.append(Para(w("constraints given")))
        blocks += c.many([Items(tuple(_capitalize(x) for x in links))], len(links),
                         w.text("constraints given").rstrip(" :"))
    return Section("system", w.text("system"), tuple(blocks))


# -- step 1 ---------------------------------------------------------------------------------------
def _count(c: Context, k: int) -> str:
    return c.w.text("equation count") if k == 1 else c.w.text("equations count", k=str(k))


def _length(c: Context, j: Joint) -> str:
    return c.tex(j.length)


def _vstar(c: Context, point: str, anchor: str | None) -> str:
    """V*(P), or V*(P) − V*(X) when the anchor X moves."""
    own = rf"\vec{{V}}^{{*}}({c.point_label(point)})"
    if anchor is None or c.kin.is_fixed(anchor):
        return own
    return rf"\left({own} - \vec{{V}}^{{*}}({c.point_label(anchor)})\right)"


def _joint_name(c: Context, j: Joint) -> Runs:
    w = c.w
    S = Math(c.element(j.element))
    X = Math(c.point_label(j.point)) if j.point else None
    if j.kind == "fixed point":
        # Seed: « la liaison "O point fixe" : x = y = z = 0 » (the coordinates of the point of (S) at O).
        return w("fixed point", X=X, S=S, xyz=Math("x = y = z = 0"))  # type: ignore[arg-type]
    if j.kind == "pivot":
        axis = Math(rf"({c.point_label(j.point)},\ {c.axis(j.axis)})")  # type: ignore[arg-type]
        if j.support is None:
            return w("pivot R0", axis=axis, S=S, R0=Math(c.R))
        return w("pivot", axis=axis, S=S, S2=Math(c.element(j.support)))
    if j.kind == "ball joint":
        other = Math(c.R) if j.support is None else Math(f"({c.element(j.support)})")
        return w("ball joint", X=X, S=S, other=other)  # type: ignore[arg-type]
    if j.kind == "rod":
        XP = Math(rf"\left\|\overrightarrow{{{c.point_label(j.point)}{c.element(j.element)}}}\right\| = "  # type: ignore[arg-type]
                  + _length(c, j))
        if j.normals:  # a circle: a pendulum's rod as well as a bead's hoop, so no word on what realizes it
            return w("rod plane", XP=XP, what="", P=S, X=X, n=Math(c.axis(j.normals[0])))  # type: ignore[arg-type]
        return w("rod", XP=XP, what=w.text("rod what"))
    if j.kind == "line":
        line = Math(rf"({c.point_label(j.point)},\ {c.axis(j.axis)})")  # type: ignore[arg-type]
        return w("line", P=S, line=line)
    if j.kind == "plane":
        return w("plane", P=S, X=X, n=Math(c.axis(j.normals[0])))  # type: ignore[arg-type]
    if j.kind == "body plane":
        return w("body plane", cond=_offsets(c, j), S=S, rot=_turns(c, j))
    return w("placement", E=S)


def _offsets(c: Context, j: Joint) -> Runs:
    """``OG·z0 = r`` (and ``OG·y0 = 0``): the constant components of a "body plane"."""
    OG = rf"\overrightarrow{{{c.name(c.origin)}{c.point_label(j.element)}}}"
    return c.w.join([Math(rf"{OG}\cdot{c.axis(a)} = {c.tex(v)}") for a, v in zip(j.normals, j.offsets, strict=True)])


def _turns(c: Context, j: Joint) -> Runs:
    axes = c.w.join([Math(c.axis(a)) for a in j.turns])
    return c.w("rotation about" if len(j.turns) == 1 else "rotations about", axes=axes)


def _losses(c: Context, j: Joint) -> list[Block]:
    """Why a constraint with friction is not perfect (its virtual power is not zero)."""
    w = c.w
    why = []
    for name, kind in j.losses:
        if kind == "coulomb":
            why.append(w("why coulomb", name=w.load(name), P=Math(c.point_label(j.element))))
        else:
            why.append(w("why damper", name=w.load(name)))
    Q = Math(r"Q_{i,\,\mathrm{nc}}")
    return [Para(w("not perfect", why=w.join(why), Q=Q))]


def _perfect(c: Context, j: Joint) -> list[Block]:
    """Why the constraint is perfect: its virtual power is zero (seed: « Elle est parfaite car … »)."""
    w, R = c.w, c.R
    if not j.perfect:
        return _losses(c, j)
    X = c.point_label(j.point) if j.point else ""
    since, because, et = (rf"\quad\text{{{w.text(k)}}}\quad" for k in ("since", "because", "et"))
    if j.kind == "fixed point":
        axes = c.kin.frames.axes(c.ref)
        RX = rf"\vec{{R}}_{{{X}}}"
        comps = " + ".join(rf"R_{{n{k + 1}}}\,{c.axis(a)}" for k, a in enumerate(axes))
        eq = Equation((rf"{RX} = {comps} \;\Rightarrow\; P^{{*}}_{{{RX}}} = {RX}\cdot\vec{{V}}^{{*}}({X}) = 0",
                       rf"{because} \vec{{V}}^{{*}}({X}) = \vec{{0}} {since} \vec{{V}}({X}/{R}) = \vec{{0}}"))
        return [Para(w("perfect fixed point", R=Math(RX), X=Math(X))), Display((eq,))]
    if j.kind in ("pivot", "ball joint"):
        S = c.element(j.element)
        rotation = c.vector(j.rotation) if j.rotation is not None else ""
        MX = rf"\vec{{M}}_{{{X}}}"
        if j.kind == "ball joint":
            return [Para(w("perfect ball", X=Math(X)))]
        friction = Math(rf"{MX}\cdot{c.axis(j.axis)} = 0")  # type: ignore[arg-type]
        if j.support is None:
            eq = Equation((rf"P^{{*}} = \vec{{R}}_{{{X}}}\cdot\vec{{V}}^{{*}}({X}) + {MX}\cdot\vec{{\Omega}}^{{*}}({S}/{R})"
                           rf" = 0 {because} \vec{{V}}^{{*}}({X}) = \vec{{0}} {et} "
                           rf"\vec{{\Omega}}^{{*}}({S}/{R}) = {rotation}",))
            return [Para(w("perfect pivot", MX=friction)), Display((eq,))]
        S1 = c.element(j.support)
        eq = Equation((rf"P^{{*}} = \vec{{R}}\cdot\left(\vec{{V}}^{{*}}({X}\in {S}) - \vec{{V}}^{{*}}({X}\in {S1})\right)"
                       rf" + {MX}\cdot\left(\vec{{\Omega}}^{{*}}({S}/{R}) - \vec{{\Omega}}^{{*}}({S1}/{R})\right)",
                       rf"= {MX}\cdot {rotation} = 0"))
        return [Para(w("perfect joint", MX=friction, X=Math(X))), Display((eq,))]
    if j.kind == "rod":
        P = c.element(j.element)
        XP = rf"\overrightarrow{{{X}{P}}}"
        v = _vstar(c, j.element, j.point)
        dirs = [Math(XP)] + [Math(c.axis(a)) for a in j.normals]
        conditions = [rf"{XP}\cdot{v} = 0"] + [rf"{c.axis(a)}\cdot{v} = 0" for a in j.normals]
        orth = w.text("orth one" if len(dirs) == 1 else "orth many")
        plane = w("rod in plane", P=Math(P), n=Math(c.axis(j.normals[0]))) if j.normals else ""
        return [Para(w("perfect rod", P=Math(P), dirs=w.join(dirs), orth=orth, XP2=Math(rf"{XP}^{{2}}"), plane=plane)),
                Display((Equation((r",\qquad ".join(conditions),)),))]
    if j.kind in ("line", "plane"):
        where = w.text("the line") if j.kind == "line" else w.text("the plane")
        return [Para(w("perfect smooth", where=where, V=Math(_vstar(c, j.element, j.point))))]
    if j.kind == "body plane":
        G = c.point_label(j.element)
        n = w.join([Math(c.axis(a)) for a in j.normals])
        cond = w.join([Math(rf"{c.axis(a)}\cdot\vec{{V}}^{{*}}({G}) = 0") for a in j.normals])
        rot = Math(rf"\vec{{\Omega}}^{{*}}({c.element(j.element)}/{c.R}) \in \mathrm{{vect}}("
                   + ", ".join(c.axis(a) for a in j.turns) + ")")
        blocks: list[Block] = [Para(w("perfect body plane", n=n, cond=cond, rot=rot))]
        rolling = next((con for con in c.model.constraints if con.form == "no_slip" and con.body == j.element), None)
        if rolling is not None:  # the contact's tangential action is the rolling constraint's reaction, not zero
            blocks.append(Para(w("adherence", S=Math(c.element(j.element)), I=Math(c.point_label(rolling.points[0])))))
        return blocks
    return [Para(w("perfect assumed"))]


def _classify(c: Context, holonomic: bool, timed: bool, principal: Runs, one: bool) -> Runs:
    w = c.w
    a = w.text("holonomic" if holonomic else "nonholonomic")
    b = w.text("rheonomic" if timed else "scleronomic")
    if one:
        return w("classified one", a=a, b=b, c=principal)
    return w("classified", a=a, b=b, c=principal)


def _declared(c: Context, con: Constraint, one: bool) -> list[Block]:
    """A constraint of the model's [constraints] table: its equation, its kind, principal or complementary."""
    w, kin = c.w, c.kin
    rows = [r for r in c.eom.constraints if r.constraint == con.name]
    # A contact: its gap g ≥ 0 (and, with friction, its sliding velocity w = 0 while it sticks).
    shown = [Equation((rf"{c.tex(r.expression)} " + (r"\geq 0" if con.unilateral and r.name == con.name else "= 0"),))
             for r in rows]
    if not shown and con.expression is not None and not isinstance(con.expression, Vector):
        shown = [Equation((rf"{c.tex(con.expression)} = 0",))]
    equation = Math(r"\quad".join(e.lines[0] for e in shown)) if len(shown) == 1 else ""
    if con.form == "no_slip":
        head = w("no slip", S=Math(c.element(con.body or "")), I=Math(c.point_label(con.points[0])),
                 equation=Math(rf"\vec{{V}}({c.point_label(con.points[0])}\in {c.element(con.body or '')}/{c.R})"
                               r" = \vec{0}"))
    elif con.form == "coincide":
        head = w("coincide", P=Math(c.point_label(con.points[0])), Q=Math(c.point_label(con.points[1])),
                 equation=Math(rf"\overrightarrow{{{c.point_label(con.points[1])}{c.point_label(con.points[0])}}}"
                               r" = \vec{0}"))
    else:
        head = w("declared", label=c.constraint_label(con.name), equation=equation)
    timed = any(r.b != 0 for r in rows) or any(kin.t in r.expression.free_symbols for r in rows)
    if con.principal:
        status: Runs = (w.text("principal declared"),)
    else:
        key = "complementary" if len(rows) == 1 else "complementary many"
        status = w(key, lam=Math(", ".join(c.tex(r.multiplier) for r in rows)))
    blocks: list[Block] = [Para(_capitalize(head) + (".",))]
    if len(shown) > 1 or (con.form in ("no_slip", "coincide") and shown):
        blocks.append(Display(tuple(shown)))
    info = next((i for i in describe_constraints(c.eom) if i.name == con.name), None)
    holonomic = info.kind == "holonomic" if info is not None else con.kind == "holonomic"
    blocks.append(Para(_classify(c, holonomic, timed, status, True)))
    if info is not None and con.kind != "holonomic" and info.integrals:
        # A velocity row that integrates (rolling on a line: ẋ − r φ̇ = 0 gives x − r φ = cste).
        phi = r",\quad ".join(rf"{c.tex(f)} = \text{{cste}}" for f in info.integrals)
        blocks.append(Para(_capitalize(w("integrable", phi=Math(phi))) + (".",)))
    if con.unilateral:
        from .impacts import contact_note

        blocks += contact_note(c, con)
    if not con.principal:
        Q = ", ".join(rf"Q_{{{c.sym(q)}}} = {c.tex(sum(r.multiplier * r.coefficients[i] for r in rows))}"
                      for i, q in enumerate(c.eom.coordinates)
                      if any(r.coefficients[i] != 0 for r in rows))
        if con.form == "no_slip":
            I, S = c.point_label(con.points[0]), c.element(con.body or "")
            P = Math(rf"P^{{*}} = \vec{{R}}_{{{I}}}\cdot\vec{{V}}^{{*}}({I}\in {S}) = 0"
                     rf"\quad\text{{{w.text('because')}}}\quad \vec{{V}}^{{*}}({I}\in {S}) = \vec{{0}}")
            blocks.append(Para(w("perfect no slip", I=Math(I), P=P, Q=Math(Q or "0"))))
        else:
            blocks.append(Para(w("perfect complementary", Q=Math(Q or "0"))))
        for reaction in c.eom.reactions:
            if reaction.constraint == con.name and reaction.point is not None and not reaction.force.is_zero():
                R = Math(rf"{c.reaction_tex(con.name)} = {c.vector(reaction.force)}")
                body = reaction.body or getattr(con, "body", None)
                if body is not None and body != reaction.point and body in c.bodies:
                    runs = w("reaction on at", S=Math(c.element(body)), E=Math(c.point_label(reaction.point)), R=R)
                else:
                    runs = w("reaction is", E=Math(c.point_label(reaction.point)), R=R)
                if con.form == "no_slip":  # the tangential reaction that rolling needs: adherence
                    runs = runs + (" ",) + w("adherence reaction")
                blocks.append(Para(runs))
    else:
        blocks.append(Para(w("perfect assumed")))
    return blocks


def _capitalize(runs: Runs) -> Runs:
    if runs and isinstance(runs[0], str) and runs[0]:
        return (runs[0][0].upper() + runs[0][1:],) + runs[1:]
    return runs


def step1(c: Context) -> Section:
    w = c.w
    declared = list(c.model.constraints)
    total = len(c.joints) + len(declared)
    one = total == 1
    groups: list[list[Block]] = []
    for j in c.joints:
        name = _joint_name(c, j)
        count = _count(c, j.equations)
        classification = _classify(c, j.holonomic, j.time_dependent, (w.text("principal"),), one)
        if one:
            group: list[Block] = [Para(w("only constraint", c=name + (f" ({count})",))), Para(classification)]
        else:
            group = [Para(_capitalize(name) + (f" ({count}) : " if c.lang == "fr" else f" ({count}): ",)
                          + classification + (".",))]
        groups.append(group + _perfect(c, j))
    groups += [_declared(c, con, one) for con in declared]
    head: list[Block] = [Para(w("constraints"))] if total > 1 else []
    blocks: list[Block] = head + [b for g in groups[:SHOWN_CONSTRAINTS] for b in g]
    if len(groups) > SHOWN_CONSTRAINTS:
        rest = [b for g in groups[SHOWN_CONSTRAINTS:] for b in g]
        blocks.append(Fold(w.text("show more", k=str(len(groups) - SHOWN_CONSTRAINTS)), tuple(rest)))
    blocks += _multiplier_table(c)
    blocks += _freedom(c)
    return Section("step1", w.text("step1"), tuple(blocks))


def _multiplier_table(c: Context) -> list[Block]:
    """With several multipliers λ_1 … λ_k, which constraint (its description) and which equation each one goes with."""
    rows = c.eom.constraints
    if len(rows) < 2:
        return []
    w = c.w
    header = tuple((w.text(k),) for k in ("col multiplier", "col constraint", "col row"))
    table = tuple(((Math(c.tex(r.multiplier)),), (c.constraint_label(r.constraint),),
                   (Math(rf"{c.tex(r.expression)} = 0"),)) for r in rows)
    return [Para(w("multiplier table")), *c.many([Table(header, table)], len(table), w.text("col multiplier"))]


def _freedom(c: Context) -> list[Block]:
    """The count of the parameters (principal constraints), then the degrees of freedom n − h − k
    (complementary rows), and whether the motion is planar by construction."""
    w = c.w
    blocks: list[Block] = []
    dof = degrees_of_freedom(c.eom, c.joints)
    if dof is not None and c.joints:
        free, used, n = dof
        parts = []
        if c.model.bodies:
            parts.append(rf"6 \times {len(c.model.bodies)}")
        if c.model.particles:
            parts.append(rf"3 \times {len(c.model.particles)}")
        blocks.append(Para(w("parameter count", count=Math(" + ".join(parts) + rf" - {used} = {n}"))))
    n, h, k = constraint_counts(c.eom)
    if k:
        blocks.append(Para(w("dof", count=Math(rf"n - h - k = {n} - {h} - {k} = {n - h - k}"))))
        blocks.append(Para(w("dof nonholonomic", p=Math(f"n - h = {n - h}"), d=Math(f"n - h - k = {n - h - k}"))))
    elif h:
        blocks.append(Para(w("dof holonomic", count=Math(rf"n - h = {n} - {h} = {n - h}"))))
    else:
        blocks.append(Para(w("dof free", count=Math(f"n = {n}"))))
    normal = planar_normal(c.eom)
    if normal is not None:
        axes = c.kin.frames.axes("R0")
        plane = [c.axis(a) for j, a in enumerate(axes) if j != normal]
        plane_tex = Math(rf"(O;\,{plane[0]},\,{plane[1]})")
        axis_tex = Math(rf"(O, {c.axis(axes[normal])})")
        blocks.append(Para(w("planar bodies", plane=plane_tex, axis=axis_tex) if c.model.bodies
                           else w("planar", plane=plane_tex)))
    return blocks


# -- step 2 ---------------------------------------------------------------------------------------
def _euler_body(c: Context) -> str | None:
    """The body whose three rotations from R0 are the Euler angles (z, x, z) of the three coordinates."""
    q = {s: name for s, name in zip(c.eom.q, c.eom.coordinates, strict=True)}
    if len(q) != 3:
        return None
    frames = {f.name: f for f in c.model.frames}
    for b in c.model.bodies:
        chain, f = [], frames[b.frame]
        while f.parent is not None:
            chain.append(f)
            f = frames[f.parent]
        chain.reverse()
        if [x.rotation.axis for x in chain] == ["z", "x", "z"] and {  # type: ignore[union-attr]
                x.rotation.angle for x in chain} == set(q):  # type: ignore[union-attr]
            return b.name
    return None


def step2(c: Context) -> Section:
    w = c.w
    names = c.eom.coordinates
    symbols = [Math(c.sym(q)) for q in names]
    n = Math(str(len(names)))
    euler = _euler_body(c)
    if len(names) == 1:
        blocks: list[Block] = [Para(w("one param", q=symbols[0]))]
    elif euler is not None:
        blocks = [Para(w("n params euler", n=n, list=w.join(symbols), S=Math(c.element(euler))))]
    else:
        blocks = [Para(w("n params", n=n, list=w.join(symbols)))]
    named = bool(c.coordinate_names)  # q₁, q₂… stand for the joints: their names in a column
    keys = ("col symbol",) + (("col name",) if named else ()) + ("col description", "col initial", "col rate")
    header = tuple((w.text(k),) for k in keys)
    rows = []
    for coord in c.model.coordinates:
        rows.append(((Math(c.sym(coord.name)),),) + (((coord.name,),) if named else ())
                    + ((in_language(coord.description, c.lang) or "",),
                       ("" if coord.initial is None else w.number(coord.initial),),
                       ("" if coord.rate is None else w.number(coord.rate),)))
    blocks += c.many([Table(header, tuple(rows))], len(rows), w.text("step2"))
    m = len(c.eom.constraints)
    if m == 1:
        blocks.append(Para(w("remark 1 lambda one", n=Math(str(len(names)))), style="remark"))
    elif m:
        blocks.append(Para(w("remark 1 lambda", n=Math(str(len(names))), m=Math(str(m))), style="remark"))
    else:
        blocks.append(Para(w("remark 1", n=Math(str(len(names)))), style="remark"))
    return Section("step2", w.text("step2"), tuple(blocks))
