"""The small-motion text of ``lagrangian linearize`` and ``lagrangian modes``, from the library: the same text,
with the numbers of the hand derivation (pendulum: K = m g l, λ = ± i sqrt(g/l))."""

from __future__ import annotations

import math

from lagrangian_test_support import EXAMPLES_DIR

import lagrangian
from lagrangian.cli.main import main
from lagrangian.output import linear_text, modes_text, sweep_text
from lagrangian.output._linear_text import number


def _pendulum() -> lagrangian.EquationsOfMotion:
    return lagrangian.derive(lagrangian.load_model(EXAMPLES_DIR / "simple_pendulum.toml"))


def test_linear_text_is_what_lagrangian_linearize_prints(capsys):
    lin = lagrangian.linearize(_pendulum(), {"theta": 0})
    text = linear_text(lin)
    assert main(["linearize", str(EXAMPLES_DIR / "simple_pendulum.toml"), "--at", "theta=0"]) == 0
    assert capsys.readouterr().out == text
    m, l, g = 1.0, 0.5, 9.81  # the example's values
    assert f"K = [ {number(m * g * l)} ]" in text and "B: no input" in text
    assert f"±{number(math.sqrt(g / l))} i" in text and "Stability: stable" in text


def test_modes_text_computes_the_modes_at_the_values_given(capsys):
    eom = lagrangian.derive(lagrangian.load_model(EXAMPLES_DIR / "bead_rotating_hoop.toml"))
    lin = lagrangian.linearize(eom, {"theta": 0}, symbolic=("Omega",))
    text = modes_text(lin, Omega=2.0)
    assert text == modes_text(lin, lin.stability(Omega=2.0), lin.modes(Omega=2.0))
    R, g = 0.5, 9.81  # ω² = g/R − Ω² about the bottom
    assert f"ω₁ = {number(math.sqrt(g / R - 4.0))} rad/s" in text
    # Without values the linearized equations are written, and the text says which to give.
    assert "give values to Omega" in linear_text(lin)
    sweep = lagrangian.sweep(lin, "Omega", [1.0, 5.0, 9.0])
    assert "stability lost" in sweep_text(lin, sweep, "rad/s")
