"""Step 1: the principal constraints read back from the parameterization of each model.

Each expectation is the physics of the example (its file's header says which constraints
it has): the top's fixed point, the double pendulum's two hinges, the cart's rail and rod...
and the count 6 N_S + 3 N_P − (equations) = n of the course.
"""

from __future__ import annotations

import pytest
import symengine as se

import lagrangian
from lagrangian.model.zoo import planar_chain
from lagrangian.output._report_constraints import degrees_of_freedom, joints
from lagrangian_test_support import eom_of


def _summary(name: str) -> list[tuple]:
    return [(j.kind, j.element, j.support, j.point, j.axis, j.normals, j.equations, j.time_dependent)
            for j in joints(eom_of(name))]


def test_the_top_has_the_fixed_point_O():
    assert _summary("lagrange_top.toml") == [("fixed point", "S", None, "O", None, (), 3, False)]
    assert degrees_of_freedom(eom_of("lagrange_top.toml"), joints(eom_of("lagrange_top.toml"))) == (6, 3, 3)


def test_the_double_pendulum_has_two_hinges_about_x0():
    eom = eom_of("double_pendulum.toml")
    assert _summary("double_pendulum.toml") == [("pivot", "S1", None, "O", "x0", (), 5, False),
                                                ("pivot", "S2", "S1", "A", "x0", (), 5, False)]
    second = joints(eom)[1]
    # Its virtual rotation relative to S1 is θ2* x0.
    assert second.rotation == lagrangian.model.Vector({"R2": (se.Symbol("theta2_star"), 0, 0)})
    assert degrees_of_freedom(eom, joints(eom)) == (12, 10, 2)


def test_pendulums_hang_from_rods():
    (simple,) = joints(eom_of("simple_pendulum.toml"))
    assert (simple.kind, simple.point, simple.normals, simple.length) == ("rod", "O", ("x0",), se.Symbol("l"))
    (spherical,) = joints(eom_of("spherical_pendulum.toml"))
    assert (spherical.kind, spherical.normals, spherical.equations) == ("rod", (), 1)


def test_the_cart_slides_on_its_rail_and_carries_the_pendulum():
    assert _summary("cart_pendulum.toml") == [("line", "C", None, "O", "x0", ("y0", "z0"), 2, False),
                                              ("rod", "P", "C", "C", None, ("y0",), 2, False)]


def test_a_prescribed_pivot_makes_the_constraint_time_dependent():
    (kapitza,) = joints(eom_of("kapitza_pendulum.toml"))
    assert (kapitza.kind, kapitza.point, kapitza.time_dependent) == ("rod", "A", True)


def test_constraints_are_stated_in_the_frame_of_the_equations():
    # The Foucault pendulum is written relative to the Earth frame E: its rod does not move with t there.
    (rod,) = joints(eom_of("foucault_pendulum.toml"))
    assert (rod.kind, rod.time_dependent) == ("rod", False)


def test_a_free_body_has_no_placement_constraint():
    # top_reaction keeps six coordinates for S: only its declared (complementary) constraint remains.
    assert joints(eom_of("top_reaction.toml")) == ()


def test_a_chain_hangs_link_by_link():
    eom = lagrangian.derive(planar_chain(5))
    found = joints(eom)
    assert [(j.kind, j.support, j.point, j.normals) for j in found] == \
        [("rod", None, "O", ("z0",))] + [("rod", f"P{k}", f"P{k}", ("z0",)) for k in range(1, 5)]
    assert [j.length for j in found] == [se.Symbol(f"l{k}") for k in range(1, 6)]
    assert degrees_of_freedom(eom, found) == (15, 10, 5)


@pytest.mark.parametrize("name", ["lagrange_top.toml", "double_pendulum.toml", "cart_pendulum.toml",
                                  "simple_pendulum.toml", "spherical_pendulum.toml"])
def test_every_constraint_is_holonomic_principal_and_perfect(name):
    for j in joints(eom_of(name)):
        assert j.holonomic and j.principal and j.perfect
