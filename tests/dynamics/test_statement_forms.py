"""A model written as its statement says gives the equations of the longer formulation (issue 16).

Each short form is compared with the formulation that worked before it: the same M and F
(simplified difference zero, and the same numbers at random states).
"""

from __future__ import annotations

import random
import textwrap

import pytest
import sympy as sp

import lagrangian
from lagrangian.errors import ModelError


def parse(toml: str) -> lagrangian.Model:
    return lagrangian.parse_model(textwrap.dedent(toml), source="<test>")


def derive(toml: str) -> lagrangian.EquationsOfMotion:
    return lagrangian.derive(parse(toml))


def sym(expr) -> sp.Expr:  # noqa: ANN001 - a SymEngine expression
    return sp.sympify(expr._sympy_())


def mass_and_forces(eom: lagrangian.EquationsOfMotion, subs: dict | None = None) -> tuple[sp.Matrix, sp.Matrix]:
    M = sp.Matrix([[sym(e) for e in row] for row in eom.M]).subs(subs or {})
    F = sp.Matrix([sym(e) for e in eom.F]).subs(subs or {})
    return M, F


def assert_same_equations(a: lagrangian.EquationsOfMotion, b: lagrangian.EquationsOfMotion,
                          subs_b: dict | None = None, *, states: int = 3) -> None:
    """The same M and F: symbolically (simplified difference zero) and numerically at random states."""
    assert a.coordinates == b.coordinates
    Ma, Fa = mass_and_forces(a)
    Mb, Fb = mass_and_forces(b, subs_b)
    for x, y in zip(list(Ma) + list(Fa), list(Mb) + list(Fb)):
        d = sp.expand(x - y)
        assert d == 0 or sp.simplify(sp.trigsimp(d)) == 0, (x, y)
    symbols = sorted((Ma.free_symbols | Fa.free_symbols | Mb.free_symbols | Fb.free_symbols), key=str)
    rng = random.Random(16)
    for _ in range(states):
        point = {s: rng.uniform(0.3, 1.7) for s in symbols}
        for x, y in zip(list(Ma) + list(Fa), list(Mb) + list(Fb)):
            assert abs(complex(x.subs(point)) - complex(y.subs(point))) < 1e-9 * (1 + abs(complex(x.subs(point))))


# -- item 2: a couple on a massless link --------------------------------------------------------
DOUBLE_PENDULUM = """
    [parameters]
    m1 = 1.0
    m2 = 0.5
    l1 = 1.0
    l2 = 0.8
    g = 9.81
    Gamma1 = {{}}
    Gamma2 = {{}}
    {extra_parameters}
    [coordinates]
    theta1 = {{ initial = 0.3 }}
    theta2 = {{ initial = -0.2 }}
    [frames]
    R1 = {{ from = "R0", rotation = ["theta1", "x"] }}
    R2 = {{ from = "R1", rotation = ["theta2", "x"] }}
    [points]
    A = "-l1*R1.z"
    [particles.P1]
    mass = "m1"
    position = "-l1*R1.z"
    [particles.P2]
    mass = "m2"
    position = "-l1*R1.z - l2*R2.z"
    {bodies}
    [loads]
    weight = {{ gravity = "-g*R0.z" }}
    shoulder = {{ torque = "Gamma1*R0.x", on = "{link1}" }}
    elbow = {{ torque = "Gamma2*R1.x", on = "{link2}", reaction_on = "{link1}" }}
"""

INVENTED_BODIES = """
    [bodies.L1]
    frame = "R1"
    mass = "mu"
    center = "-l1/2*R1.z"
    inertia = { diagonal = ["J", "J", "J"] }
    [bodies.L2]
    frame = "R2"
    mass = "mu"
    center_from = "A"
    center = "-l2/2*R2.z"
    inertia = { diagonal = ["J", "J", "J"] }
"""


def test_couple_on_massless_links_is_that_on_invented_zero_mass_bodies() -> None:
    """Motors at the shoulder and the elbow of a double pendulum of massless rods: a couple on a
    frame (virtual power C·Ω*(frame)) gives the equations of the old form, where the rods had to
    be bodies of mass mu and inertia J, set to zero afterwards."""
    on_frames = derive(DOUBLE_PENDULUM.format(extra_parameters="", bodies="", link1="R1", link2="R2"))
    on_bodies = derive(DOUBLE_PENDULUM.format(extra_parameters="mu = {}\n    J = {}", bodies=INVENTED_BODIES,
                                              link1="L1", link2="L2"))
    mu, J = sp.symbols("mu J")
    assert_same_equations(on_frames, on_bodies, {mu: 0, J: 0})
    # and independently: the elbow couple's generalized forces are (0, Γ2), the shoulder's (Γ1, 0)
    Q = {f.name: [sym(x) for x in f.Q] for f in on_frames.loads}
    assert Q["shoulder"] == [sp.Symbol("Gamma1"), 0]
    assert Q["elbow"] == [0, sp.Symbol("Gamma2")]


def test_couple_on_an_unknown_name_names_bodies_and_frames() -> None:
    with pytest.raises(ModelError, match="unknown body or frame `R9`"):
        parse(DOUBLE_PENDULUM.format(extra_parameters="", bodies="", link1="R9", link2="R2"))
