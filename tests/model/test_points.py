"""Points, particles and bodies may be placed from one another."""

import math

import lagrangian
from lagrangian._identity import is_zero

CHAIN = """
[parameters]
m = 1
l = 1
g = 9.81
[coordinates]
a = { initial = 0.1 }
b = { initial = 0.2 }
[frames]
R1 = { from = "R0", rotation = ["a", "z"] }
R2 = { from = "R0", rotation = ["b", "z"] }
[particles.P1]
mass = "m"
position = "l*R1.x"
[particles.P2]
mass = "m"
from = "P1"
position = "l*R2.x"
"""


def test_particle_from_an_earlier_particle():
    eom = lagrangian.derive(lagrangian.parse_model(CHAIN))
    a, b = eom.q
    # Textbook double pendulum of point masses: M = m l² [[2, cos(a−b)], [cos(a−b), 1]].
    import symengine as se

    l, m = se.Symbol("l"), se.Symbol("m")
    assert is_zero(eom.M[0][0] - 2 * m * l**2)
    assert is_zero(eom.M[0][1] - m * l**2 * se.cos(a - b))
    assert is_zero(eom.M[1][1] - m * l**2)
    assert math.isclose(float(eom.M[0][1].subs({a: 0.3, b: 0.1, l: 1, m: 1})), math.cos(0.2))


# -- one spelling for "relative to a point": `from` -------------------------------------------------------------
BODY = """
[parameters]
m = 1
l = 1
A = 0.1
[coordinates]
a = { initial = 0.1 }
[frames]
R1 = { from = "R0", rotation = ["a", "z"] }
[points]
Q = "l*R0.x"
[bodies.S]
frame = "R1"
mass = "m"
FROM
center = "l*R1.x"
inertia = { diagonal = ["A", "A", "A"] }
"""


def test_a_body_center_is_given_from_a_point_with_from_and_the_old_spelling_still_reads():
    new = lagrangian.parse_model(BODY.replace("FROM", 'from = "Q"'))
    old = lagrangian.parse_model(BODY.replace("FROM", 'center_from = "Q"'))
    import symengine as se

    for model in (new, old):
        eom = lagrangian.derive(model)
        # G = Q + l x1: T = ½ m |l ȧ y1|² + ½ A ȧ², so M = m l² + A (a pivot at Q would be the same).
        l, m, A = se.Symbol("l"), se.Symbol("m"), se.Symbol("A")
        assert is_zero(eom.M[0][0] - (m * l**2 + A))
        position = eom.kinematics.position("S")
        x = eom.kinematics.frames.express(position, "R0")[0]
        assert is_zero(x.subs({eom.q[0]: 0}) - 2 * l)  # OQ + QG = 2 l along x0 at a = 0


def test_both_spellings_at_once_are_refused_with_the_line():
    import pytest

    from lagrangian.errors import ModelError

    with pytest.raises(ModelError, match="both `from` and `center_from`") as info:
        lagrangian.parse_model(BODY.replace("FROM", 'from = "Q"\ncenter_from = "Q"'))
    assert "keep `from`" in str(info.value)


def test_a_table_where_an_expression_is_expected_says_how_to_write_from():
    import pytest

    from lagrangian.errors import ModelError

    text = CHAIN.replace('from = "P1"\nposition = "l*R2.x"', 'position = { from = "P1", position = "l*R2.x" }')
    with pytest.raises(ModelError) as info:
        lagrangian.parse_model(text)
    message = str(info.value)
    assert "a table is not an expression" in message and "`from`" in message
    assert 'from = "A" and position = "l*R2.x" as two keys of [particles.NAME]' in message
    assert "cannot use a dict" not in message
    point = CHAIN.replace("[particles.P1]", '[points]\nB = { position = { from = "O", position = "l*R1.x" } }\n'
                                            '[particles.P1]')
    with pytest.raises(ModelError, match=r'B = \{ from = "A", position = "l\*R2.x" \}'):
        lagrangian.parse_model(point)


def test_the_reserved_names_of_the_docs_are_the_engines():
    from pathlib import Path

    from lagrangian.model._assemble import RESERVED

    docs = (Path(__file__).parents[2] / "docs" / "model-format.md").read_text(encoding="utf-8")
    section = docs[docs.index("**Reserved names.**"):].split("\n\n")[0]
    for name in RESERVED:
        assert f"`{name}`" in section or f" {name} " in section or f"`{name} " in section or f" {name}`" in section, name
