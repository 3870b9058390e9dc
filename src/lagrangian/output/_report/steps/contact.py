"""Step 7 for a contact with Coulomb friction: its normal force N by the resultant theorem, and the stick condition.

A principal constraint with friction (a block on an incline) is not perfect, but only its
tangential action R_t works; the normal one, N n, does not enter Lagrange's equations.  The
course then finds it from the general theorems (Remarque 4): projected on the contact's unit
normal n, the resultant theorem on the element P gives

    m γ(P/R)·n = Σ F_given·n + N        (R_t ⟂ n),

so N = m γ(P/R)·n − Σ F_given·n: m g cos α for the block (γ·n = 0 since it stays on the
incline).  The model declares N for its friction law; the report derives it and says whether
the two agree.

With the exact law (``regularization = 0``) on a fixed support, the contact sticks once the
sliding stops while the tangential force it needs stays within the cone of static friction:
at rest (q̇ = 0, q̈ = 0) Lagrange's equation of the one coordinate q gives that force,
R_t = −Q_other(q, 0)/|∂OP/∂q| along the sliding direction, and the condition
|R_t| ≤ f_s N, i.e. |Q_other|/(N |∂OP/∂q|) ≤ f_s (|tan α| ≤ f_s for the block).
"""

from __future__ import annotations

import symengine as se
import sympy

from ...._identity import are_zero
from ....model import Body, CoulombFriction, Particle
from ..build import Context
from ..document import Block, Display, Equation, Math, Para

__all__ = ["contact_blocks", "normal_force", "stick_ratio"]


def _element(c: Context, load: CoulombFriction) -> str | None:
    """The particle or body that carries the contact point of ``load``."""
    if load.at in {p.name for p in c.model.particles} | c.bodies:
        return load.at
    for b in c.model.bodies:
        d = c.kin.frames.express(c.kin.position(load.at) - c.kin.position(b.name), b.frame)
        moving = set(c.kin.q) | {c.kin.t}
        if not any(set(x.free_symbols) & moving for x in d):
            return b.name
    return None


def _mass(c: Context, name: str) -> se.Basic:
    elements: tuple[Body | Particle, ...] = (*c.model.bodies, *c.model.particles)
    return next(e.mass for e in elements if e.name == name)


def normal_force(c: Context, load: CoulombFriction) -> tuple[str, se.Basic, se.Basic, se.Basic] | None:
    """(element, m γ(G/R)·n, Σ F_given·n, N) of the contact of ``load``, by the resultant theorem projected on n.

    None when the projection does not isolate N: no unit normal given, the element moves along n, or a
    complementary constraint acts on it (its multiplier would enter the projection too).
    """
    from ....analysis import given_efforts

    if load.normal is None:
        return None
    name = _element(c, load)
    if name is None or any(r.body == name or r.point == name for r in c.eom.reactions):
        return None
    kin, n = c.kin, load.normal
    if not all(are_zero([kin.frames.dot(n, v) for v in kin.partial_velocities(name)])):
        return None  # the element moves along the normal: the contact is no principal constraint
    efforts = {e.element: e for e in given_efforts(c.eom)[0]}
    if name not in efforts:
        return None
    inertia = se.expand(kin.frames.dot(kin.acceleration(name), n) * _mass(c, name))
    given = se.expand(kin.frames.dot(efforts[name].force, n))
    return name, inertia, given, se.expand(inertia - given)


def stick_ratio(c: Context, load: CoulombFriction) -> tuple[sympy.Basic, sympy.Basic] | None:
    """(R_t, |Q_other| / (N |∂OP/∂q|)) at rest, for a one-coordinate model whose exact friction law acts on a
    fixed support: R_t is the tangential force the contact must supply along the unit sliding direction."""
    kin = c.kin
    if not load.exact or len(kin.q) != 1 or not load.surface_velocity.is_zero():
        return None
    found = normal_force(c, load)
    if found is None:
        return None
    N = found[3]._sympy_()
    rest = {kin.qd[0]: se.Integer(0)}
    other = se.Add(*(f.Q[0] for f in c.eom.loads if f.name != load.name)).xreplace(rest)._sympy_()
    tangent = kin.partial_velocities(load.at)[0]
    length = sympy.sqrt(sympy.simplify(kin.frames.dot(tangent, tangent)._sympy_()))
    # Simplified with the constants of positive value taken positive (m, g), then put back as the model's symbols.
    positive = {sympy.Symbol(p.name): sympy.Symbol(p.name, positive=True) for p in c.model.parameters
                if p.value is not None and p.value > 0}
    back = {v: k for k, v in positive.items()}
    R_t = sympy.simplify((-other / length).xreplace(positive)).xreplace(back)
    ratio = sympy.simplify((other / (N * length)).xreplace(positive))
    if ratio.has(sympy.sin, sympy.cos):
        ratio = sympy.simplify(ratio.rewrite(sympy.tan))
    return R_t, sympy.Abs(ratio.xreplace(back), evaluate=False)


def _value(c: Context, e: sympy.Basic) -> float | None:
    values = {sympy.Symbol(p.name): p.value for p in c.model.parameters if p.value is not None}
    try:
        return float(e.subs(values))
    except (TypeError, ValueError):
        return None


def contact_blocks(c: Context) -> list[Block]:
    """For each Coulomb contact: N from the resultant theorem (checked against the model's), then the stick
    condition when the law is exact."""
    w, R = c.w, c.R
    out: list[Block] = []
    for load in c.model.loads:
        if not isinstance(load, CoulombFriction):
            continue
        found = normal_force(c, load)
        if found is None:
            continue
        name, inertia, given, N = found
        n = c.vector(load.normal)  # type: ignore[arg-type]
        P = c.point_label(name)
        m = c.tex(_mass(c, name))
        efforts = [e for e in given_names(c, name) if e != load.name]
        forces = " + ".join(rf"\vec{{F}}({c.load_tex(e)})" for e in efforts) or r"\vec{0}"
        forces = rf"\left({forces}\right)" if len(efforts) > 1 else forces
        lines = (rf"{m}\,\vec{{\gamma}}({P}/{R})\cdot{n} = {forces}\cdot{n} + N",
                 (rf"{m}\,\vec{{\gamma}}({P}/{R})\cdot{n} = {c.tex(inertia)},\qquad {forces}\cdot{n} = "
                  rf"{c.tex(given)}"),
                 rf"\Rightarrow\quad N = {c.tex(N)}")
        out.append(Para(w("normal force", P=Math(P), n=Math(n), name=w("quoted", name=w.load(load.name)))))
        out.append(Display(tuple(Equation((line,)) for line in lines)))
        agrees = are_zero([N - load.normal_force])[0]
        key = "normal agrees" if agrees else "normal differs"
        out.append(Para(w(key, N=Math(rf"N = {c.tex(load.normal_force)}")), style="" if agrees else "note"))
        stick = stick_ratio(c, load)
        if stick is None:
            continue
        R_t, ratio = stick
        fs = load.static_coefficient if load.static_coefficient is not None else load.coefficient
        q = c.sym(c.eom.coordinates[0])
        rest = Math(rf"{c.sym(c.eom.coordinates[0], 'dot')} = 0,\ {c.sym(c.eom.coordinates[0], 'ddot')} = 0")
        e = c.vector(c.kin.partial_velocities(load.at)[0])
        out.append(Para(w("stick", rest=rest, q=Math(rf"L({q})"), Rt=Math(rf"R_t = {c.n.latex(R_t)}"),
                          e=Math(e), cone=Math(rf"|R_t| \le {c.tex(fs)}\, N"))))
        out.append(Display((Equation((rf"{c.n.latex(ratio)} \le {c.tex(fs)}",)),)))
        value, limit = _value(c, ratio), _value(c, fs._sympy_())
        if value is not None and limit is not None:
            key = "stick holds" if value <= limit else "stick fails"
            out.append(Para(w(key, P=Math(P), value=Math(rf"{c.n.latex(ratio)} \approx {w.number(value, 4)}"),
                              limit=Math(rf"{c.tex(fs)} = {w.number(limit, 4)}"))))
    return out


def given_names(c: Context, name: str) -> list[str]:
    """The loads acting on element ``name`` as forces (gravity, forces, springs...), in the model's order."""
    from ....analysis import given_efforts

    efforts = {e.element: e for e in given_efforts(c.eom)[0]}
    return list(efforts[name].loads) if name in efforts else []
