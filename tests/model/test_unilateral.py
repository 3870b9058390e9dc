"""Unilateral constraints in model files: what is read, and the clear errors for what cannot be a contact."""

from __future__ import annotations

import pytest

import lagrangian
from lagrangian import ModelError

BALL = """
[parameters]
m = 1.0
g = 9.81
e = {e}
mu = 0.5
[coordinates]
x = {{ initial = 0.0, rate = 1.0 }}
z = {{ initial = 1.0, rate = 0.0 }}
[particles.P]
mass = "m"
position = "x*R0.x + z*R0.z"
[loads]
weight = {{ gravity = "-g*R0.z" }}
[constraints]
floor = {{ {contact} }}
"""


def ball(contact: str = 'unilateral = "z", restitution = "e"', e: float = 0.5) -> lagrangian.Model:
    return lagrangian.parse_model(BALL.format(contact=contact, e=e), source="ball.toml")


def test_a_contact_is_read_with_its_gap_coefficients_and_sliding_velocity() -> None:
    model = ball('unilateral = "z", restitution = "e", friction = "mu", slip = "x_dot"')
    [c] = model.constraints
    assert c.unilateral and c.form == "unilateral" and c.kind == "holonomic"
    assert (str(c.expression), str(c.restitution), str(c.friction), str(c.slip)) == ("z", "e", "mu", "x_dot")
    eom = lagrangian.derive(model)  # the closed contact: its gap's row, and the sliding row while it sticks
    assert [r.name for r in eom.constraints] == ["floor", "floor_t"]
    assert [str(r.multiplier) for r in eom.constraints] == ["lambda_floor", "lambda_floor_t"]


def test_the_builder_declares_a_contact() -> None:
    b = lagrangian.ModelBuilder("ball")
    b.parameter("m", 1.0)
    b.coordinate("z", 1.0, 0.0)
    b.particle("P", mass="m", position="z*R0.z")
    b.constraint("floor", "unilateral", "z", restitution="1/2")
    [c] = b.build().constraints
    assert c.unilateral and str(c.restitution) == "1/2" and c.friction is None


@pytest.mark.parametrize(("contact", "e", "message", "line"), [
    ('unilateral = "z", restitution = "e"', 1.5, "e = 1.5, outside [0, 1]", 16),
    ('unilateral = "z", restitution = "e"', -0.1, "e = -0.1, outside [0, 1]", 16),
    ('unilateral = "z"', 0.5, "does not say how it bounces", 16),
    ('unilateral = "z", restitution = "x"', 0.5, "depends on `x`", 16),
    ('unilateral = "z", restitution = "e", friction = "-mu", slip = "x_dot"', 0.5, "μ = -0.5, negative", 16),
    ('unilateral = "z", restitution = "e", friction = "mu"', 0.5, "has friction but no sliding velocity", 16),
    ('unilateral = "z", restitution = "e", slip = "x_dot"', 0.5, "no friction coefficient", 16),
    ('unilateral = "z", restitution = "e", friction = "mu", slip = "x"', 0.5, "holds no rate", 16),
    ('unilateral = "z", restitution = "e", friction = "mu", slip = "x_dot^2"', 0.5, "not linear in the rates", 16),
    ('unilateral = "z_dot", restitution = "e"', 0.5, "depends on the rate `z_dot`", 16),
    ('unilateral = "z*R0.z", restitution = "e"', 0.5, "must be a scalar", 16),
    ('unilateral = "z", restitution = "e", principal = true', 0.5, "cannot be principal", 16),
    ('unilateral = "z", restitution = "e", bounce = 1', 0.5, "unknown key `bounce`", 16),
    ('unilateral = "y", restitution = "e"', 0.5, "unknown symbol `y`", 16),
])
def test_what_cannot_be_a_contact_is_refused_at_its_line(contact: str, e: float, message: str, line: int) -> None:
    with pytest.raises(ModelError) as info:
        ball(contact, e)
    assert message in info.value.message and info.value.line == line and info.value.fix


def test_a_contact_with_friction_may_not_repeat_a_constraint_name() -> None:
    text = BALL.format(contact='unilateral = "z", restitution = "e", friction = "mu", slip = "x_dot"', e=0.5)
    text += 'floor_t = { holonomic = "x - 1" }\n'
    with pytest.raises(ModelError, match="two constraint rows are named `floor_t`"):
        lagrangian.derive(lagrangian.parse_model(text, source="ball.toml"))


def test_dependent_contacts_are_a_model_not_an_error() -> None:
    # A ball between two walls: the rows x and L − x are dependent, and the derivation accepts them.
    text = BALL.format(contact='unilateral = "x", restitution = "e"', e=0.5) + \
        'right = { unilateral = "2 - x", restitution = "e" }\n'
    eom = lagrangian.derive(lagrangian.parse_model(text, source="box.toml"))
    assert [r.name for r in eom.constraints] == ["floor", "right"]
