"""The equilibria as text from the library: what ``lagrangian equilibria`` prints.

The bead on a hoop turning at Ω (R = 0.5, g = 9.81): rests at θ = 0 and θ = π, and off the axis at
cos θ0 = g/(R Ω²) when R Ω² > g (at Ω = 6: θ0 = acos(9.81/18) = 0.994407212059).
"""

from __future__ import annotations

import math

import numpy as np
from lagrangian_test_support import EXAMPLES_DIR

import lagrangian
from lagrangian.analysis import bifurcation
from lagrangian.cli.main import main
from lagrangian.output import bifurcation_text, equilibria_text


def test_equilibria_text_is_what_lagrangian_equilibria_prints(capsys):
    eom = lagrangian.derive(lagrangian.load_model(EXAMPLES_DIR / "bead_rotating_hoop.toml"))
    found = lagrangian.equilibria(eom, parameters={"Omega": 6.0})
    text = equilibria_text(eom, found)
    assert "θ = 0" in text and "θ = π" in text and "0.994407212059" in text and "Searched:" in text
    assert main(["equilibria", str(EXAMPLES_DIR / "bead_rotating_hoop.toml"), "--set", "Omega=6"]) == 0
    # The CLI gives each rest its verdict from the linearization there.
    stabilities = [lagrangian.linearize(eom, {"theta": e.numeric["theta"]}, parameters={"Omega": 6.0}).stability()
                   for e in found]
    with_verdicts = equilibria_text(eom, found, [(st.stable, st.verdict, st.reason) for st in stabilities])
    assert capsys.readouterr().out == with_verdicts
    assert with_verdicts.count("Lagrange–Dirichlet") >= 1 and "Lagrange–Dirichlet" not in text


def test_the_bifurcation_text_gives_the_hoops_pitchfork_at_the_hand_value():
    """The bead on a hoop turning at Ω: θ = 0 loses its stability and θ = ±arccos(g/(R Ω²)) appear where
    R Ω² = g (U_P = −m g R cosθ − ½ m R² Ω² sin²θ, ∂²U_P/∂θ² at 0 = m R (g − R Ω²))."""
    eom = lagrangian.derive(lagrangian.load_model(EXAMPLES_DIR / "bead_rotating_hoop.toml"))
    values = eom.model.parameter_values
    critical = math.sqrt(float(values["g"]) / float(values["R"]))
    lines = bifurcation_text(eom, bifurcation(eom, "Omega", np.arange(1.0, 8.01, 0.5))).splitlines()
    assert lines[:2] == ["Equilibria of Bead on a rotating hoop against Ω from 1 to 8 (15 values)", ""]
    assert lines[2] == "  1. θ = 0" and lines[4:6] == ["  2. θ = π", "     unstable over the whole range"]
    changes = {line.split(": ")[1]: float(line.split("=")[1].split(":")[0]) for line in lines if "Ω = " in line}
    assert set(changes) == {"becomes unstable", "appears"}
    assert all(abs(x - critical) < 1e-9 * critical for x in changes.values())
