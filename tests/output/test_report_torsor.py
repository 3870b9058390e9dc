"""Step 3's virtual kinematic torsor {V*(S/R0)} = {Ω*(S/R0) ; V*(A ∈ S/R0)}_A of each rigid body.

The torsor is checked against a direct differentiation: for points P fixed in the body,
V*(A) + Ω* ∧ AP must equal Σ_i ∂OP/∂q_i q_i*, with OP written in R0 and differentiated here
(and, at the centre of mass, the engine's own V*(G)), at random values of every symbol.
"""

from __future__ import annotations

import random

import pytest
import symengine as se

from lagrangian.model import Vector
from lagrangian.output import report
from lagrangian.output.report.build import Context
from lagrangian.output.report.document import math_of
from lagrangian.output.report.steps.kinematics import torsor_point, virtual_torsor
from lagrangian_test_support import eom_of

EXAMPLES = ["lagrange_top.toml", "double_pendulum.toml", "rolling_coin.toml"]
#: Points fixed in each body, by their components in the body's frame (from A).
OFFSETS = [(0.3, -0.7, 1.1), (-1.3, 0.4, 0.2)]


def _r0(c: Context, v: Vector) -> tuple[se.Basic, ...]:
    return tuple(c.kin.frames.express(v, "R0"))


def _direct(c: Context, OP: Vector) -> tuple[se.Basic, ...]:
    """Σ_i ∂OP/∂q_i q_i*, OP in R0's components, differentiated here."""
    comps = _r0(c, OP)
    return tuple(sum((se.diff(x, q) * s for q, s in zip(c.kin.q, c.kin.q_star)), se.Integer(0)) for x in comps)


def _equal_at_random(a: tuple[se.Basic, ...], b: tuple[se.Basic, ...], seed: int) -> bool:
    rng = random.Random(seed)
    exprs = [x - y for x, y in zip(a, b)]
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
