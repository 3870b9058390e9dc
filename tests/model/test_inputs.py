"""`[inputs]` and `[operating_point]`: parsed, built in Python, and bad tables refused with file and line.

The expected lines are found by searching the model text for the offending key, so each
test says which declaration is meant.
"""

from __future__ import annotations

import pytest
import symengine as se

import lagrangian
from lagrangian import ModelError
from lagrangian.model import ModelBuilder

#: A cart (x) carrying a pendulum (theta) driven by a hip torque tau and a push u.
CART = """\
[model]
name = "driven cart-pendulum"

[parameters]
m = 1.0
M = 2.0
l = 0.5
g = 9.81
v = 2.0

[inputs]
tau = { description = "hip torque", unit = "N*m" }
u = {}

[coordinates]
x = {}
theta = {}

[frames]
R1 = { from = "R0", rotation = ["theta", "z"] }

[points]
C = "x*R0.x"

[particles.cart]
mass = "M"
position = "x*R0.x"

[bodies.S]
frame = "R1"
mass = "m"
center = "l*R1.x"
center_from = "C"
inertia = { diagonal = ["0", "m*l^2/3", "m*l^2/3"] }

[loads]
weight = { gravity = "g*R0.x" }
motor = { torque = "tau*R1.z", on = "S" }
push = { force = "u*R0.x", at = "cart" }

[operating_point]
theta = "pi"
x = 0
x_dot = "v/2"
independent = ["x_dot", "theta_dot"]
dependent = ["x"]
"""


def line_of(text: str, needle: str) -> int:
    lines = [k for k, line in enumerate(text.splitlines(), start=1) if needle in line]
    assert len(lines) == 1, f"{needle!r} is on lines {lines}"
    return lines[0]


def edit(text: str, old: str, new: str) -> str:
    assert text.count(old) == 1, f"{old!r} occurs {text.count(old)} times"
    return text.replace(old, new)


def fails(text: str) -> ModelError:
    with pytest.raises(ModelError) as info:
        lagrangian.parse_model(text, source="cart.toml")
    assert info.value.file == "cart.toml"
    return info.value


# -- parsing ---------------------------------------------------------------------------------
def test_inputs_are_parameters_marked_input_with_value_zero() -> None:
    model = lagrangian.parse_model(CART, source="cart.toml")
    assert model.inputs == ("tau", "u")
    tau = next(p for p in model.parameters if p.name == "tau")
    assert (tau.input, tau.value, tau.unit, tau.description) == (True, 0.0, "N*m", "hip torque")
    assert not any(p.input for p in model.parameters if p.name not in ("tau", "u"))
    assert model.where("input", "u").line == line_of(CART, "u = {}")


def test_an_input_is_the_magnitude_of_its_load() -> None:
    # Q_theta of the motor is tau (the couple tau z acts on a body turning by theta about z);
    # Q_x of the push is u: by virtual power, independent of the engine's other loads.
    eom = lagrangian.derive(lagrangian.parse_model(CART))
    tau, u = se.Symbol("tau"), se.Symbol("u")
    q = {name: k for k, name in enumerate(c.name for c in eom.model.coordinates)}
    assert (se.diff(se.sympify(eom.F[q["theta"]]), tau) - 1).expand() == 0
    assert (se.diff(se.sympify(eom.F[q["x"]]), u) - 1).expand() == 0
    assert se.diff(se.sympify(eom.F[q["x"]]), tau) == 0


def test_operating_point_values_and_lists() -> None:
    model = lagrangian.parse_model(CART)
    point = dict(model.operating_point)
    assert list(point) == ["theta", "x", "x_dot"]
    assert point["theta"] == se.pi
    assert point["x"] == 0
    assert (point["x_dot"] - se.Symbol("v") / 2).expand() == 0
    assert model.independent_speeds == ("x_dot", "theta_dot")
    assert model.dependent_coordinates == ("x",)


def test_no_tables_mean_no_inputs_and_no_point() -> None:
    text = CART.split("[inputs]")[0] + "[coordinates]" + CART.split("[coordinates]")[1]
    text = text.split("[operating_point]")[0]
    text = edit(text, 'motor = { torque = "tau*R1.z", on = "S" }\n', "")
    text = edit(text, 'push = { force = "u*R0.x", at = "cart" }\n', "")
    model = lagrangian.parse_model(text)
    assert model.inputs == ()
    assert (model.operating_point, model.independent_speeds, model.dependent_coordinates) == ((), (), ())


def test_builder_declares_inputs_and_the_operating_point() -> None:
    b = ModelBuilder("pendulum")
    for name, value in (("m", 1.0), ("l", 0.5), ("g", 9.81)):
        b.parameter(name, value)
    b.input("tau", description="hip torque", unit="N*m")
    b.coordinate("theta")
    b.frame("R1", "R0", rotation=("theta", "z"))
    b.body("S", frame="R1", mass="m", center="l*R1.x", inertia={"diagonal": [0, "m*l^2", "m*l^2"]})
    b.gravity("weight", "g*R0.x")
    b.torque("motor", "tau*R1.z", on="S")
    b.operating_point({"theta": se.pi, "theta_dot": 0}, independent=["theta_dot"])
    model = b.build()
    assert model.inputs == ("tau",)
    assert dict(model.operating_point) == {"theta": se.pi, "theta_dot": 0}
    assert model.independent_speeds == ("theta_dot",)
    assert model.dependent_coordinates == ()


# -- errors ------------------------------------------------------------------------------------
def test_input_clashing_with_a_parameter() -> None:
    err = fails(edit(CART, "u = {}", "g = {}"))
    assert err.symbol == "g"
    assert "`g` is declared twice" in err.message and "parameter" in err.message
    assert err.line == line_of(CART, "u = {}")


def test_input_clashing_with_a_coordinate() -> None:
    err = fails(edit(CART, "theta = {}", "tau = {}"))
    assert err.symbol == "tau" and "`tau` is declared twice" in err.message


def test_input_no_load_uses() -> None:
    err = fails(edit(CART, 'push = { force = "u*R0.x", at = "cart" }', 'push = { force = "g*R0.x", at = "cart" }'))
    assert err.symbol == "u"
    assert err.message.startswith("input `u` is used by no load")
    assert err.line == line_of(CART, "u = {}")
    assert "remove it from [inputs]" in err.fix and "u*R1.z" in err.fix


def test_input_with_an_unknown_key() -> None:
    err = fails(edit(CART, "u = {}", "u = { value = 1.0 }"))
    assert err.message == "unknown key `value` in input `u`"
    assert "description, unit" in err.fix


def test_input_that_is_not_a_table() -> None:
    err = fails(edit(CART, "u = {}", "u = 3"))
    assert err.message == "input `u` must be a table, not `3`"
    assert err.line == line_of(CART, "u = {}")


def test_operating_point_unknown_name() -> None:
    err = fails(edit(CART, 'x_dot = "v/2"', 'y_dot = "v/2"'))
    assert err.symbol == "y_dot"
    assert err.message == "`y_dot` in the operating point is not a coordinate nor the rate of one"
    assert err.line == line_of(CART, 'x_dot = "v/2"')
    assert "x, theta" in err.fix and "x_dot, theta_dot" in err.fix


@pytest.mark.parametrize(("value", "bad", "what"), [
    ('"x/2"', "x", "a coordinate"),
    ('"v*t"', "t", "the time"),
    ('"theta_dot"', "theta_dot", "a rate"),
    ('"tau"', "tau", "an input"),
])
def test_operating_point_value_must_be_constant(value: str, bad: str, what: str) -> None:
    err = fails(edit(CART, 'x_dot = "v/2"', f"x_dot = {value}"))
    assert err.symbol == bad
    assert err.message == (f"the value of `x_dot` in the operating point uses {what} `{bad}`; "
                           "an operating point is constant")
    assert err.line == line_of(CART, 'x_dot = "v/2"')


def test_operating_point_unknown_symbol_in_a_value() -> None:
    err = fails(edit(CART, 'theta = "pi"', 'theta = "pi + w"'))
    assert err.symbol == "w" and "in the value of operating point `theta`" in err.message
    assert err.line == line_of(CART, 'theta = "pi"')


def test_operating_point_value_of_the_wrong_type() -> None:
    err = fails(edit(CART, "x = 0\n", "x = true\n"))
    assert err.message == ("the value of `x` in the operating point must be a number or an expression in "
                           "quotes, not `True`")


def test_independent_speed_that_is_not_a_rate() -> None:
    err = fails(edit(CART, 'independent = ["x_dot", "theta_dot"]', 'independent = ["x", "theta_dot"]'))
    assert err.symbol == "x"
    assert err.message == "`x` in `independent` of the operating point is not a rate name"
    assert err.line == line_of(CART, "independent =")


def test_dependent_that_is_not_a_list() -> None:
    err = fails(edit(CART, 'dependent = ["x"]', 'dependent = "x"'))
    assert err.message == "`dependent` in the operating point must be a list of names, not `x`"
    assert err.line == line_of(CART, 'dependent = ["x"]')


def test_dependent_listed_twice() -> None:
    err = fails(edit(CART, 'dependent = ["x"]', 'dependent = ["x", "x"]'))
    assert err.message == "`x` is listed twice in `dependent` of the operating point"


def test_dependent_that_is_not_a_coordinate() -> None:
    err = fails(edit(CART, 'dependent = ["x"]', 'dependent = ["x_dot"]'))
    assert err.message == "`x_dot` in `dependent` of the operating point is not a coordinate name"
