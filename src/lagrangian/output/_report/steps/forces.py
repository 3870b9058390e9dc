"""Step 5: the generalized forces Q_i of every given effort, by virtual power, load by load.

Seed, section II: P*(effort) = Σ_i Q_i q_i* in the virtual velocity field compatible with
the principal constraints.  Every component is shown, the vanishing ones with the reason
they vanish (the point does not move with q_i, or the force is orthogonal to ∂OP/∂q_i);
a conservative effort is then taken through U_P (Q_i = −∂U_P/∂q_i, checked by the engine),
and the perfect constraints contribute nothing.
"""

from __future__ import annotations

from ...._identity import are_zero
from ....dynamics import LoadForces
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
from ..build import Context
from ..document import Block, Display, Equation, Items, Math, Para, Runs, Section
from ..size import wrap_many

__all__ = ["step5"]


#: Most coordinates for which each vanishing Q_i is explained (beyond, the list would drown the rest).
ZERO_REASONS_MAX = 12


def _elements(c: Context, load: Gravity) -> tuple[str, ...]:
    return load.on or tuple(b.name for b in c.model.bodies) + tuple(p.name for p in c.model.particles)


def _mass(c: Context, name: str) -> str:
    return c.mass_tex(name)


def _formula(c: Context, f: LoadForces, load: object) -> tuple[str, str]:
    """(P* as the course writes it, what the title adds: the effort itself)."""
    R = c.R
    if isinstance(load, Gravity):
        names = _elements(c, load)
        g = c.field_tex(load)
        extra = rf"{g} = {c.vector(load.field)}"
        if len(names) <= 3:
            return " + ".join(rf"{_mass(c, x)}\,{g}\cdot\vec{{V}}^{{*}}({c.point_label(x)})" for x in names), extra
        return rf"\sum_{{k}} m_{{k}}\,{g}\cdot\vec{{V}}^{{*}}(G_{{k}})", extra
    if isinstance(load, PointForce):
        return rf"\vec{{F}}\cdot\vec{{V}}^{{*}}({c.point_label(load.at)})", rf"\vec{{F}} = {c.vector(load.force)}"
    if isinstance(load, Torque):
        on = rf"\vec{{\Omega}}^{{*}}({c.element(load.on)}/{R})"
        extra = rf"\vec{{C}} = {c.vector(load.torque)}"
        if load.reaction_on is None:
            return rf"\vec{{C}}\cdot{on}", extra
        return rf"\vec{{C}}\cdot\left({on} - \vec{{\Omega}}^{{*}}({c.element(load.reaction_on)}/{R})\right)", extra
    if isinstance(load, (Spring, Damper)):
        a, b = (c.point_label(p) for p in load.ends)
        rel = rf"\vec{{u}}_{{{a}{b}}}\cdot\left(\vec{{V}}^{{*}}({b}) - \vec{{V}}^{{*}}({a})\right)"
        ell = rf"\ell = \left\|\overrightarrow{{{a}{b}}}\right\|"
        if isinstance(load, Spring):
            if load.rest_length == 0:
                return rf"-{c.tex(load.stiffness)}\,\ell\, {rel}", ell
            return rf"-{c.tex(load.stiffness)} \left(\ell - {c.tex(load.rest_length)}\right) {rel}", ell
        return rf"-{c.tex(load.coefficient)}\,\dot{{\ell}}\,{rel}", ell
    if isinstance(load, Potential) and f.generalized is not None:  # Q_i = d/dt(∂U/∂q̇_i) − ∂U/∂q_i
        return (r"\sum_{i} \left(\frac{d}{dt}\frac{\partial U}{\partial \dot{q}_i} - \frac{\partial U}{\partial q_i}"
                r"\right) q_i^{*}", rf"U = {c.tex(load.energy)}")
    if isinstance(load, Potential):
        return r"-\sum_{i} \frac{\partial U}{\partial q_i}\, q_i^{*}", rf"U = {c.tex(load.energy)}"
    if isinstance(load, Dissipation):
        return r"-\sum_{i} \frac{\partial D}{\partial \dot{q}_i}\, q_i^{*}", rf"D = {c.tex(load.function)}"
    if isinstance(load, JointDamper):
        s1, s2 = (c.element(x) for x in load.bodies)
        return (rf"-{c.tex(load.coefficient)}\,\vec{{\Omega}}({s2}/{s1})\cdot\left(\vec{{\Omega}}^{{*}}({s2}/{R}) - "
                rf"\vec{{\Omega}}^{{*}}({s1}/{R})\right)", "")
    if isinstance(load, CoulombFriction):
        # R_t, the tangential part of the support's action (T is the kinetic energy), N its normal part (step 7).
        P = c.point_label(load.at)
        power = rf"\vec{{R}}_t\cdot\vec{{V}}^{{*}}({P})"
        mu, N = c.tex(load.coefficient), c.tex(load.normal_force)
        # v_s, the sliding velocity: V(P) less the surface's own (a belt's v_b x0)
        surface = "" if load.surface_velocity.is_zero() else f" - {c.vector(load.surface_velocity)}"
        slide = rf",\ \vec{{v}}_s = \vec{{V}}({P}/{R}){surface}"
        if load.exact:
            return power, rf"\vec{{R}}_t = -{mu} N\,\vec{{v}}_s / \|\vec{{v}}_s\|{slide},\ N = {N}"
        return power, (rf"\vec{{R}}_t = -{mu} N\,\vec{{v}}_s / \sqrt{{\|\vec{{v}}_s\|^{{2}} + "
                       rf"{c.tex(load.regularization)}^{{2}}}}{slide},\ N = {N}")
    if isinstance(load, GeneralizedForce):
        return r"\sum_{i} Q_i\, q_i^{*}", ""
    if f.kind == "inertial: Coriolis":
        return (rf"-\int_{{\Sigma}} 2\,\left(\vec{{\Omega}}({R}/R_{{0}})\wedge\vec{{V}}(P/{R})\right)\cdot\vec{{V}}^{{*}}(P)"
                r"\,dm", "")
    if f.kind == "inertial: entrainment":
        return r"-\int_{\Sigma} \vec{\gamma}_{e}(P)\cdot\vec{V}^{*}(P)\,dm", ""
    return "", ""


def _partial(q: str, of: str) -> str:
    return rf"\frac{{\partial {of}}}{{\partial {q}}}"


def _why_zero(c: Context, f: LoadForces, load: object, i: int) -> Runs:
    """Why Q_i of this load is zero."""
    w, kin = c.w, c.kin
    name = c.eom.coordinates[i]
    q = c.sym(name)
    O = c.name(c.origin)
    points: tuple[str, ...] = ()
    if isinstance(load, Gravity):
        points = _elements(c, load)
    elif isinstance(load, PointForce):
        points = (load.at,)
    elif isinstance(load, CoulombFriction):
        points = (load.at,)
    if points:
        still = [p for p in points if kin.partial_velocities(p)[i].is_zero()]
        if len(still) == len(points):
            labels = w.join([Math(c.point_label(p)) for p in points])
            d = w.join([Math(_partial(q, rf"\overrightarrow{{{O}{c.point_label(p)}}}") + r" = \vec{0}")
                        for p in points])
            return w("point still" if len(points) == 1 else "points still", P=labels, q=Math(q), d=d)
        moving = [p for p in points if p not in still]
        force = load.field if isinstance(load, Gravity) else load.force if isinstance(load, PointForce) else None
        if force is not None and all(are_zero([kin.frames.dot(force, kin.partial_velocities(p)[i]) for p in moving])):
            return w("orthogonal", d=w.join([Math(_partial(q, rf"\overrightarrow{{{O}{c.point_label(p)}}}"))
                                             for p in moving]))
        return (w.text("cancel"),)
    if isinstance(load, (Spring, Damper)):
        a, b = load.ends
        AB = rf"\overrightarrow{{{c.point_label(a)}{c.point_label(b)}}}"
        if (kin.partial_velocities(b)[i] - kin.partial_velocities(a)[i]).is_zero():
            return w("length still", AB=Math(rf"\left\|{AB}\right\|"), q=Math(q))
        return w("orthogonal", d=Math(_partial(q, AB)))
    if isinstance(load, (Torque, JointDamper)):
        bodies = (load.on, load.reaction_on) if isinstance(load, Torque) else load.bodies
        frames = [c.model.body(x).frame if x in c.bodies else x for x in bodies if x is not None]
        moving = [x for x in frames if not kin.partial_omegas(x)[i].is_zero()]
        if not moving:
            return w("no rotation", S=w.join([Math(c.element(x)) for x in bodies if x is not None]), q=Math(q))
        return w("couple orthogonal", d=Math(rf"\frac{{\partial \vec{{\Omega}}}}{{\partial {c.sym(name, 'dot')}}}"))
    if isinstance(load, Potential):
        return w("U still", U=Math("U"), q=Math(q))
    if isinstance(load, Dissipation):
        return w("U still", U=Math("D"), q=Math(c.sym(name, "dot")))
    if isinstance(load, GeneralizedForce):
        return w("not given", q=Math(q))
    if f.kind.startswith("inertial"):
        return _why_inertial(c, f, i)
    return (w.text("cancel"),)


def _why_inertial(c: Context, f: LoadForces, i: int) -> Runs:
    """Q_i of an inertial load is zero: its force on each element is orthogonal to ∂OP/∂q_i (Coriolis on a hoop)."""
    from ....dynamics import inertial_torsors

    w, kin = c.w, c.kin
    q = c.sym(c.eom.coordinates[i])
    O = c.name(c.origin)
    mine = [t for t in inertial_torsors(kin) if t.load == f.name]  # type: ignore[arg-type]
    if not mine:
        return (w.text("cancel"),)
    frames = {b.name: b.frame for b in c.model.bodies}
    still = [t for t in mine if kin.partial_velocities(t.element)[i].is_zero()
             and (t.element not in frames or kin.partial_omegas(frames[t.element])[i].is_zero())]
    if len(still) == len(mine):
        labels = w.join([Math(c.point_label(t.element)) for t in mine])
        d = w.join([Math(_partial(q, rf"\overrightarrow{{{O}{c.point_label(t.element)}}}") + r" = \vec{0}")
                    for t in mine])
        return w("point still" if len(mine) == 1 else "points still", P=labels, q=Math(q), d=d)
    tests = [kin.frames.dot(t.force, kin.partial_velocities(t.element)[i]) for t in mine]
    tests += [kin.frames.dot(t.moment, kin.partial_omegas(frames[t.element])[i]) for t in mine if t.element in frames]
    if all(are_zero(tests)):
        d = w.join([Math(_partial(q, rf"\overrightarrow{{{O}{c.point_label(t.element)}}}")) for t in mine])
        return w("orthogonal", d=d)
    return (w.text("cancel"),)


def _q_list(c: Context, values: list[str], load: str | None = None) -> list[str]:
    """``Q_q(load) = …`` for one load, ``Q_{q, nc} = …`` for the non-conservative total."""
    return [(c.Q_of(q, load) if load is not None else c.Q_nc(q)) + f" = {v}"
            for q, v in zip(c.eom.coordinates, values, strict=True)]


_RELATION = {"positive": ">", "nonnegative": r"\geq", "negative": "<", "nonpositive": r"\leq"}


def _interval(c: Context, bounds: tuple) -> str:
    """[a, b] in LaTeX (numbers as decimals, as the file wrote them), an open side as ∞; in French [a ; b] with
    decimal commas."""
    def number(b) -> str:
        text = f"{float(b):g}"
        return text.replace(".", "{,}") if c.lang == "fr" else text

    lower, upper = (None if b is None else number(b) if not b.free_symbols else c.tex(b) for b in bounds)
    sep = r"\,;\, " if c.lang == "fr" else ", "
    return ((rf"\left[{lower}{sep}" if lower is not None else rf"\left]-\infty{sep}")
            + (rf"{upper}\right]" if upper is not None else r"+\infty\right["))


#: The loads whose magnitude a model gives as a value: constant when it holds no q, q̇, t, nor input.
_GIVEN = (Torque, GeneralizedForce, PointForce)


def _conservative_or_not(c: Context, f: LoadForces, load: object, name: str) -> Para:
    """Whether the load derives from U_P, and why: a constant couple or force does (its magnitude is a constant
    of the problem), a load driven by an input u(t) does not (−u q is a potential only for a constant u); a
    generalized potential U(q, q̇, t) gives Q_i = d/dt(∂U/∂q̇_i) − ∂U/∂q_i, a force apart from U_P."""
    w = c.w
    i_math, UP = Math("i"), Math(rf"U_P(\Sigma/{c.R})")
    Q = Math(rf"Q_i({c.load_tex(f.name)}) = -\frac{{\partial U_P({c.load_tex(f.name)})}}{{\partial q_i}}")
    if f.potential is not None:
        constants = sorted({s for x in f.Q for s in x.free_symbols}, key=str)
        if isinstance(load, _GIVEN) and constants:
            names = w.join([Math(c.tex(s)) for s in constants])
            why = w("constant because", names=names, verb=w.text("is one" if len(constants) == 1 else "are one"))
            return Para(w("derives constant", name=name, why=why, Q=Q, i=i_math, UP=UP))
        return Para(w("derives", name=name, Q=Q, i=i_math, UP=UP))
    if f.generalized is not None:  # U(q, q̇, t) affine in the rates: −∂U/∂q alone would drop d/dt ∂U/∂q̇
        return Para(w("generalized potential", name=name, U=Math("U"),
                      Q=Math(r"Q_i = \frac{d}{dt}\frac{\partial U}{\partial \dot{q}_i} - \frac{\partial U}{\partial q_i}"),
                      Q0=Math(r"-\frac{\partial U}{\partial q_i}"), UP=UP, Qnc=Math(r"Q_{i,\,\mathrm{nc}}")))
    inputs = {p.symbol for p in c.model.parameters if p.input}
    used = {s for x in f.Q for s in x.free_symbols} & inputs
    driving = [p.symbol for p in c.model.parameters if p.symbol in used]  # in the model's order
    nc = Math(r"Q_{i,\,\mathrm{nc}}")
    if driving:
        u = w.join([Math(c.tex(s)) for s in driving])
        what = w.text("driven one" if len(driving) == 1 else "driven many")
        why = w("driven why", U=Math(r"-u\, q"), u=Math("u"))
        return Para(w("driven", name=name, u=u, what=what, why=why, Q=nc), style="note")
    return Para(w("not conservative", name=name, Q=nc), style="note")


def _perfect_constraints(c: Context) -> list[Block]:
    """The principal constraints' actions: none works when all are perfect; in those that are not, only their
    friction works (the Coulomb or viscous loads above), their other actions still do no virtual work."""
    w = c.w
    lossy = [j for j in c.joints if not j.perfect]
    if not lossy:
        return [Para(w("perfect no Q"))]
    if len(lossy) < len(c.joints):
        return [Para(w("perfect no Q but"))]
    names = list(dict.fromkeys(name for j in lossy for name, _ in j.losses))
    quoted = w.join([w("quoted", name=w.load(n)) for n in names])
    return [Para(w("perfect no Q none one" if len(lossy) == 1 else "perfect no Q none", names=quoted))]


def step5(c: Context) -> Section:
    w = c.w
    blocks: list[Block] = [Para(w("virtual power intro", P=Math(r"P^{*} = \sum_{i=1}^{n} Q_i\, q_i^{*}"),
                                  Q=Math("Q_i")))]
    if not c.eom.loads:
        blocks.append(Para(w("no loads")))
    if c.eom.assumptions:  # the signs the derivation proved from the declared ones, and used
        declared = [Math(rf"{c.tex(p.symbol)} {_RELATION[p.sign]} 0") for p in c.model.parameters if p.sign]
        declared += [Math(rf"{c.tex(q.symbol)} \in " + _interval(c, q.range)) for q in c.model.coordinates if q.range]
        facts = [(Math(rf"{c.tex(f.expression)} {_RELATION['nonnegative' if f.sign > 0 else 'nonpositive']} 0"),
                  " (", w.text("sign general" if f.general else "sign at values"), ")") for f in c.eom.assumptions]
        blocks.append(Para(w("signs used", declared=w.join(declared), facts=w.join(facts))))
    spec = {x.name: x for x in c.model.loads}
    for f, row in zip(c.eom.loads, c.form.loads, strict=True):
        load = spec.get(f.name)
        formula, extra = _formula(c, f, load)
        kind = w.text(f"kind {f.kind}") if w.has(f"kind {f.kind}") else f.kind
        if isinstance(load, Gravity) and c.field_tex(load) != r"\vec{g}":
            kind = w.text("kind field")  # an attraction that is not the weight ± g along an axis
        name = c.load_name(f.name)
        blocks.append(Para(w("load title", name=name, kind=kind, extra=(", ", Math(extra)) if extra else "")))
        head = rf"P^{{*}}({c.load_tex(f.name)}) = " + (f"{formula} = " if formula else "")
        equations = [c.equation(head, c.ex(f.virtual_power))]
        equations.append(wrap_many(r"\Rightarrow\quad ", _q_list(c, [c.n.latex(x) for x in row.Q], f.name),
                                   r",\quad "))
        blocks += c.show(equations, name)
        if isinstance(load, CoulombFriction) and load.exact:
            fs = load.static_coefficient if load.static_coefficient is not None else load.coefficient
            blocks.append(Para(w("coulomb exact", v=Math(r"\vec{v}_s \neq \vec{0}"),
                                 stick=Math(rf"\|\vec{{R}}_t\| \le {c.tex(fs)}\, N"), v0=Math(r"\vec{v}_s = \vec{0}"))))
        zeros = [i for i, x in enumerate(row.Q) if x == 0]
        if zeros and len(row.Q) <= ZERO_REASONS_MAX:
            items = tuple(w("zero because", Q=Math(f"{c.Q_of(c.eom.coordinates[i], f.name)} = 0"),
                            why=_why_zero(c, f, load, i)) for i in zeros)
            blocks += c.many([Items(items)], len(items), f.name)
        blocks.append(_conservative_or_not(c, f, load, name))
    blocks += _perfect_constraints(c)
    if c.eom.constraints:
        one = len(c.eom.constraints) == 1
        k = "" if one else "k"
        blocks.append(Para(w("complementary Q one" if one else "complementary Q", Q=Math(c.multiplier_sum()),
                             lam=Math(c.lam if one else rf"{c.lam}_{{k}}"), a=Math(f"a_{{{k + ',' if k else ''}i}}"),
                             f=Math(rf"\frac{{\partial f{'_{k}' if k else ''}}}{{\partial q_i}}"),
                             qd=Math(r"\dot{q}_i"), fk=Math(f"f{'_{k}' if k else ''} = 0"))))
    blocks.append(Para(w("nc total")))
    values = [c.n.latex(eq.Q_nc) for eq in c.form.equations]
    if all(v == "0" for v in values) and len(values) > ZERO_REASONS_MAX:
        blocks.append(Display((Equation((r"Q_{i,\,\mathrm{nc}} = 0 \qquad i = 1, \dots, n",)),)))
    elif all(v == "0" for v in values):
        line = " = ".join(c.Q_nc(q) for q in c.eom.coordinates) + " = 0"
        blocks.append(Display((Equation((line,)),)))
    else:
        blocks += c.show([wrap_many("", _q_list(c, values), r",\quad ")], "Q")
    return Section("step5", w.text("step5"), tuple(blocks))
