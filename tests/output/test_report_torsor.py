"""Step 3's virtual kinematic torsor {V*(S/R0)} = {Ω*(S/R0) ; V*(A ∈ S/R0)}_A of each rigid body.

The torsor is checked against a direct differentiation: for points P fixed in the body,
V*(A) + Ω* ∧ AP must equal Σ_i ∂OP/∂q_i q_i*, with OP written in R0 and differentiated here
(and, at the centre of mass, the engine's own V*(G)), at random values of every symbol.
"""

from __future__ import annotations

import random

import pytest
import symengine as se
from lagrangian_test_support import eom_of

from lagrangian.model import Vector
from lagrangian.output import report
from lagrangian.output._report.build import Context
from lagrangian.output._report.document import math_of
from lagrangian.output._report.steps.kinematics import torsor_point, virtual_torsor

EXAMPLES = ["lagrange_top.toml", "double_pendulum.toml", "rolling_coin.toml"]
#: Points fixed in each body, by their components in the body's frame (from A).
OFFSETS = [(0.3, -0.7, 1.1), (-1.3, 0.4, 0.2)]


def _r0(c: Context, v: Vector) -> tuple[se.Basic, ...]:
    return tuple(c.kin.frames.express(v, "R0"))


def _direct(c: Context, OP: Vector) -> tuple[se.Basic, ...]:
    """Σ_i ∂OP/∂q_i q_i*, OP in R0's components, differentiated here."""
    comps = _r0(c, OP)
    return tuple(sum((se.diff(x, q) * s for q, s in zip(c.kin.q, c.kin.q_star, strict=True)), se.Integer(0)) for x in comps)


def _equal_at_random(a: tuple[se.Basic, ...], b: tuple[se.Basic, ...], seed: int) -> bool:
    rng = random.Random(seed)
    exprs = [x - y for x, y in zip(a, b, strict=True)]
    symbols = set().union(*(e.free_symbols for e in exprs))
    for _ in range(3):
        values = {s: se.Float(rng.uniform(-2, 2)) for s in symbols}
        if any(abs(float(se.expand(e.subs(values)))) > 1e-9 for e in exprs):
            return False
    return True


@pytest.fixture(scope="module", params=EXAMPLES)
def context(request) -> Context:
    return Context(eom_of(request.param), (), "fr")


def test_the_torsor_gives_the_virtual_velocity_of_every_point_of_the_body(context):
    c = context
    for b in c.model.bodies:
        omega, vA = virtual_torsor(c, b.name)
        OA = c.kin.position(torsor_point(c, b.name))
        for k, offset in enumerate(OFFSETS):
            AP = Vector({b.frame: offset})
            from_torsor = _r0(c, vA + c.kin.frames.cross(omega, AP, "R0"))
            assert _equal_at_random(from_torsor, _direct(c, OA + AP), seed=k), (b.name, offset)
        # At the centre of mass: the engine's own V*(G) = Σ ∂OG/∂q_i q_i*.
        AG = c.kin.position(b.name) - OA
        from_torsor = _r0(c, vA + c.kin.frames.cross(omega, AG, "R0"))
        assert _equal_at_random(from_torsor, _r0(c, c.kin.virtual_velocity(b.name)), seed=7), b.name


def test_a_wrong_rotation_is_caught(context):
    """The check can fail: Ω (the real rates) in place of Ω* does not give V*(P)."""
    c = context
    b = c.model.bodies[-1]
    _, vA = virtual_torsor(c, b.name)
    AP = Vector({b.frame: OFFSETS[0]})
    wrong = _r0(c, vA + c.kin.frames.cross(c.kin.omega(b.frame), AP, "R0"))
    assert not _equal_at_random(wrong, _direct(c, c.kin.position(torsor_point(c, b.name)) + AP), seed=1)


@pytest.mark.parametrize("lang", ["fr", "en"])
def test_step3_writes_the_torsor_of_each_body(lang):
    eom = eom_of("double_pendulum.toml")
    step3 = " ".join(math_of(report(eom, lang=lang).document.section("step3").blocks))
    for name, A in (("S_{1}", "O"), ("S_{2}", "G_{S_{2}}")):
        assert rf"\left\{{\mathcal{{V}}^{{*}}({name}/R_{{0}})\right\}}" in step3
        assert rf"\vec{{V}}^{{*}}({A}\in {name}/R_{{0}})" in step3
    assert r"\vec{V}^{*}(O\in S_{1}/R_{0}) = \vec{0}" in step3  # S1 turns about the fixed O


# -- step 3: the comoment of each perfect principal constraint's action torsor with the virtual torsor -----------
#: Examples and the principal constraints step 3 argues (the report states one comoment per entry).
COMOMENTS = {"lagrange_top.toml": ["fixed point"], "double_pendulum.toml": ["pivot", "pivot"],
             "pendulum_tension.toml": ["plane"], "rolling_coin.toml": ["body plane"],
             "bead_rotating_hoop.toml": ["rod"], "cart_pendulum.toml": ["line", "rod"]}


def _sym(e):  # type: ignore[no-untyped-def]
    import sympy

    return sympy.sympify(e._sympy_() if hasattr(e, "_sympy_") else e)


def _unit(c: Context, name: str):  # type: ignore[no-untyped-def]
    """An axis of the model (x0, u, y1) as R0 components."""
    frames = c.kin.frames
    frame = next(f for f in frames.frames if name in frames.axes(f))
    k = frames.axes(frame).index(name)
    return [_sym(x) for x in _r0(c, Vector({frame: tuple(se.Integer(int(i == k)) for i in range(3))}))]


def _omega_star(c: Context, body: str | None):  # type: ignore[no-untyped-def]
    """Ω*(S/R0) = Σ ∂Ω/∂q̇_i q_i*, Ω in R0 components differentiated here (not the engine's partial ω)."""
    if body is None:
        return [0, 0, 0]
    omega = [_sym(x) for x in _r0(c, c.kin.omega(c.model.body(body).frame))]
    return [sum(x.diff(_sym(qd)) * _sym(s) for qd, s in zip(c.kin.qd, c.kin.q_star, strict=True)) for x in omega]


@pytest.mark.slow
@pytest.mark.parametrize("name", sorted(COMOMENTS))
def test_step3_argues_each_perfect_constraint_by_a_zero_comoment(name):
    """For each principal constraint step 3 argues, a generic action torsor {R ; M_X}_X with the stated
    properties (M_O = 0 at a fixed point, M_X·e = 0 for a hinge, R along the normal of a smooth plane, along XP
    and the plane normals for a rod, R ⟂ e for a slider, R along n and M_G ⟂ the allowed rotations for a body on
    a plane) has a comoment with the virtual field, R·V*(X) + M_X·Ω*, that simplifies to 0 with SymPy."""
    import sympy

    eom = eom_of(name)
    c = Context(eom, (), "fr")
    step3 = " ".join(math_of(report(eom, lang="fr").document.section("step3").blocks))
    assert step3.count(r"P^{*} = \vec{R}") == len(COMOMENTS[name]) + 1  # and the general comoment before them
    assert [j.kind for j in c.joints if j.perfect] == COMOMENTS[name]
    Rg, Mg = sympy.symbols("R1:4"), sympy.symbols("M1:4")
    dot = lambda a, b: sum(x * y for x, y in zip(a, b, strict=True))  # noqa: E731
    cross = lambda a, b: [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]  # noqa: E731
    for j in c.joints:
        if j.kind in ("fixed point", "pivot", "ball joint"):
            # Relative virtual torsor of S to its support, at X (a point of both): Ω*(S) − Ω*(S1), V*(X) − V*(X).
            omega = [a - b for a, b in zip(_omega_star(c, j.element), _omega_star(c, j.support), strict=True)]
            V = [0, 0, 0]
            R = list(Rg)
            if j.kind == "pivot":
                e = _unit(c, j.axis)
                M = [m - dot(Mg, e) * x for m, x in zip(Mg, e, strict=True)]  # the part of a generic moment orthogonal to e
            else:
                M = [0, 0, 0]
        else:
            omega, M = _omega_star(c, j.element if j.is_body else None), [0, 0, 0]
            V = [_sym(x) for x in _direct(c, c.kin.position(j.element))]
            if j.kind == "rod":  # relative to the rod's anchor X
                V = [a - _sym(b) for a, b in zip(V, _direct(c, c.kin.position(j.point)), strict=True)]
            if j.kind == "rod":
                XP = [_sym(x) for x in _r0(c, c.kin.position(j.element) - c.kin.position(j.point))]
                R = [Rg[0] * a + sum(Rg[k + 1] * n for k, n in enumerate(col)) for a, *col in
                     zip(XP, *[_unit(c, a) for a in j.normals], strict=True)]
            elif j.kind == "plane":
                R = [Rg[0] * x for x in _unit(c, j.normals[0])]
            elif j.kind == "line":
                e = _unit(c, j.axis)
                R = [r - dot(Rg, e) * x for r, x in zip(Rg, e, strict=True)]
            else:  # body plane: a force along the normal, a moment orthogonal to the allowed rotations
                R = [Rg[0] * x for x in _unit(c, j.normals[0])]
                t = [_unit(c, a) for a in j.turns]
                M = [Mg[0] * x for x in cross(t[0], t[1])] if len(t) == 2 else [m - dot(Mg, t[0]) * x for m, x in zip(Mg, t[0], strict=True)]
        comoment = dot(R, V) + dot(M, omega)
        assert sympy.simplify(sympy.expand_trig(comoment)) == 0, (name, j.kind, comoment)
        # and the argument is not empty: the virtual field does move (else the check proves nothing).
        assert any(sympy.simplify(x) != 0 for x in V + omega)


# -- step 4: Π_P(S), the inertia operator, introduced where T first uses it ------------------------------------
@pytest.mark.slow
@pytest.mark.parametrize("name", ["lagrange_top.toml", "double_pendulum.toml", "rolling_coin.toml"])
def test_step4_introduces_the_inertia_operator_that_T_uses(name):
    """T(S/R0) = ½ Ω·[Π_P(S)·Ω] (+ ½ m V²(G) by König): with the matrix step 3 prints and Ω's components in its
    basis, ½ Ωᵀ [Π] Ω (+ ½ m V(G)² differentiated here) equals the engine's T term (SymPy); step 4 defines each Π."""
    import sympy

    eom = eom_of(name)
    c = Context(eom, (), "fr")
    step4 = " ".join(math_of(report(eom, lang="fr").document.section("step4").blocks))
    t = sympy.Symbol("t")
    for term in eom.T_terms:
        used = eom.inertias[term.name]
        P = c.point_label(term.name) if used.point == "G" else c.point_label(used.point)
        S = c.element(term.name)
        assert rf"\Pi_{{{P}}}({S})\cdot\vec{{\Omega}}({S}/R_{{0}}) = \int_{{M\in {S}}}" in step4
        Pi = sympy.Matrix([[_sym(x) for x in row] for row in used.matrix])
        w = sympy.Matrix([_sym(x) for x in c.kin.frames.express(c.kin.omega(c.model.body(term.name).frame), used.frame)])
        T = (w.T * Pi * w)[0] / 2
        if term.formula == "König":
            # V(G/R0) by differentiating OG's R0 components along q(t) here.
            q = [_sym(x) for x in c.kin.q]
            funcs = {x: sympy.Function(str(x))(t) for x in q}
            OG = [_sym(x).subs(funcs) for x in _r0(c, c.kin.position(term.name))]
            rates = {sympy.Derivative(funcs[x], t): _sym(qd) for x, qd in zip(q, c.kin.qd, strict=True)}
            V = [sympy.diff(x, t).subs(rates).subs({v: k for k, v in funcs.items()}) for x in OG]
            T += _sym(c.model.body(term.name).mass) * sum(x**2 for x in V) / 2
        else:
            assert term.formula == "fixed point"
        assert sympy.simplify(T - _sym(term.expression)) == 0, (name, term.name)
    if name == "lagrange_top.toml":  # and the seed's closed form
        A, C = sympy.symbols("A C")
        th, ps, ph = (sympy.Symbol(f"{x}_dot") for x in ("theta", "psi", "phi"))
        seed = A * (th**2 + ps**2 * sympy.sin(sympy.Symbol("theta"))**2) / 2 + C * (ph + ps * sympy.cos(sympy.Symbol("theta")))**2 / 2
        assert sympy.simplify(_sym(eom.T_terms[0].expression) - seed) == 0
