"""Declaring sign assumptions and coordinate ranges: reading and errors."""

from __future__ import annotations

import pytest
import symengine as se
from lagrangian_test_support import wall_spring

import lagrangian
from lagrangian import ModelBuilder, ModelError


def parse(L: str = 'L = { value = 1.0, positive = true }', x: str = 'x = { initial = 0.1, range = [-0.5, 0.5] }'):
    return lagrangian.parse_model(wall_spring(L=L, x=x), source="model.toml")


def test_signs_and_ranges_are_read() -> None:
    model = parse()
    L = next(p for p in model.parameters if p.name == "L")
    assert L.sign == "positive" and L.value == 1.0
    assert next(p for p in model.parameters if p.name == "k").sign is None
    (x,) = model.coordinates
    assert x.range == (se.Rational(-1, 2), se.Rational(1, 2))  # decimals are exact, as in expressions
    for sign in ("nonnegative", "negative", "nonpositive"):
        value = "-1.0" if "neg" in sign and sign != "nonnegative" or sign == "nonpositive" else "1.0"
        model = parse(L=f"L = {{ value = {value}, {sign} = true }}", x="x = 0.1")
        assert next(p for p in model.parameters if p.name == "L").sign == sign
    model = parse(x='x = { initial = 0.1, range = ["-L", inf] }')
    assert model.coordinates[0].range == (-se.Symbol("L"), None)
    model = parse(x='x = { initial = 0.1, range = [-inf, "L"] }')
    assert model.coordinates[0].range == (None, se.Symbol("L"))


def test_the_builder_declares_the_same() -> None:
    b = ModelBuilder("model")
    b.parameter("m", 1.0)
    b.parameter("k", 2.0)
    b.parameter("L", 1.0, positive=True)
    b.coordinate("x", 0.1, range=[-0.5, 0.5])
    b.point("W", "-L*R0.x")
    b.particle("P", mass="m", position="x*R0.x")
    b.spring("spring", ["W", "P"], stiffness="k", rest_length="L")
    built, read = b.build(), parse()
    assert built.parameters == read.parameters and built.coordinates == read.coordinates
    assert lagrangian.derive(built).F == lagrangian.derive(read).F


@pytest.mark.parametrize(("L", "x", "words", "line_of"), [
    ("L = { value = -1.0, positive = true }", "x = 0.1",
     "parameter `L` is declared positive (L > 0), but its value is -1", "L ="),
    ("L = { value = 0.0, positive = true }", "x = 0.1", "declared positive (L > 0), but its value is 0", "L ="),
    ("L = { value = 1.0, negative = true }", "x = 0.1", "declared negative (L < 0)", "L ="),
    ("L = { value = 1.0, positive = false }", "x = 0.1", "`positive` of parameter `L` must be true", "L ="),
    ("L = { value = 1.0, positive = true, nonnegative = true }", "x = 0.1", "one sign at most", "L ="),
    ("L = { value = 1.0, sign = true }", "x = 0.1", "unknown key `sign`", "L ="),
    ("L = 1.0", "x = { initial = 0.1, range = [0.5] }", "must be a list of two bounds", "x ="),
    ("L = 1.0", 'x = { initial = 0.1, range = "0, 1" }', "must be a list of two bounds", "x ="),
    ("L = 1.0", "x = { initial = 0.1, range = [0.5, -0.5] }", "is empty: its lower bound 0.5", "x ="),
    ("L = 1.0", "x = { initial = 0.7, range = [-0.5, 0.5] }", "initial value 0.7 of coordinate `x` is outside",
     "x ="),
    ("L = 1.0", 'x = { initial = 0.1, range = ["-x", 1] }', "depends on `x`", "x ="),
    ("L = 1.0", 'x = { initial = 0.1, range = ["-t", 1] }', "depends on `t`", "x ="),
    ("L = 1.0", "x = { initial = 0.1, range = [inf, 1] }", "lower bound of the range of coordinate `x` is inf",
     "x ="),
    ("L = 1.0", "x = { initial = 0.1, range = [true, 1] }", "must be a number or an expression", "x ="),
    ("L = 1.0", 'x = { initial = 0.1, range = ["-q", 1] }', "unknown symbol `q`", "x ="),
])
def test_bad_declarations_name_the_file_line_and_fix(L: str, x: str, words: str, line_of: str) -> None:
    text = wall_spring(L=L, x=x)
    with pytest.raises(ModelError) as exc:
        lagrangian.parse_model(text, source="model.toml")
    err = exc.value
    assert words in err.message, err.message
    assert err.file == "model.toml" and err.fix
    assert err.line == next(n for n, line in enumerate(text.splitlines(), 1) if line.startswith(line_of))


def test_a_value_set_later_must_keep_the_declared_sign() -> None:
    from lagrangian.model._assumptions import check_sign

    model = parse()
    check_sign(model, {"L": 2.0, "k": -1.0})  # k declares no sign
    with pytest.raises(ModelError, match=r"parameter `L` is declared positive \(L > 0\), but its value is -0.5") as e:
        check_sign(model, {"L": -0.5})
    assert e.value.line == 5 and "change its declared sign" in e.value.fix
