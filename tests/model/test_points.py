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
