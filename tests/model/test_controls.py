"""The ``[controls]`` table: a law per declared input, read by the model grammar, errors at file:line."""

from __future__ import annotations

import pytest
import symengine as se
from lagrangian_test_support import example_text

import lagrangian
from lagrangian.errors import ModelError

BASE = example_text("inverted_pendulum_cart.toml").replace(
    'g = { value = 9.81', 'k1 = 2.0\nk2 = 3.0\ng = { value = 9.81')


def _with(table: str) -> str:
    return BASE + "\n[controls]\n" + table + "\n"


def _line(text: str, needle: str) -> int:
    """The last line that starts with ``needle`` (the [controls] table is at the end)."""
    return max(k for k, line in enumerate(text.splitlines(), start=1) if line.startswith(needle))


def test_a_law_is_read_in_the_model_grammar():
    model = lagrangian.parse_model(_with('F = "-k1*x - k2*x_dot + 30*theta"'))
    (name, law), = model.controls
    x, xd, theta, k1, k2 = (se.Symbol(s) for s in ("x", "x_dot", "theta", "k1", "k2"))
    assert name == "F" and se.expand(law - (-k1 * x - k2 * xd + 30 * theta)) == 0


def test_the_builder_takes_the_same_table():
    b = lagrangian.ModelBuilder("cart")
    b.parameter("m", 1.0)
    b.parameter("k", 2.0)
    b.input("F")
    b.coordinate("x", 0.1, 0.0)
    b.particle("P", mass="m", position="x*R0.x")
    b.force("push", "F*R0.x", at="P")
    b.controls({"F": "-k*x"})
    assert b.build().controls == (("F", -se.Symbol("k") * se.Symbol("x")),)


@pytest.mark.parametrize(("table", "message"), [
    ('G = "x"', "`G` in \\[controls\\] is not a declared input"),
    ('m = "x"', "`m` in \\[controls\\] is a parameter"),
    ('F = "F*x"', "uses the input `F`"),
    ('F = "y"', "unknown symbol `y`"),
    ('F = [1, 2]', "must be an expression in quotes or a number"),
    ('F = "R0.x"', "must be a scalar"),
])
def test_a_bad_law_is_refused_at_its_line(table, message):
    text = _with(table)
    with pytest.raises(ModelError, match=message) as info:
        lagrangian.parse_model(text, source="cart.toml")
    assert info.value.file == "cart.toml" and info.value.line == _line(text, table.split()[0] + " =")
