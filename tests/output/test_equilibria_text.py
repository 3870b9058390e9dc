"""The equilibria as text from the library: what ``lagrangian equilibria`` prints.

The bead on a hoop turning at Ω (R = 0.5, g = 9.81): rests at θ = 0 and θ = π, and off the axis at
cos θ0 = g/(R Ω²) when R Ω² > g (at Ω = 6: θ0 = acos(9.81/18) = 0.994407212059).
"""

from __future__ import annotations

from lagrangian_test_support import EXAMPLES_DIR

import lagrangian
from lagrangian.cli.main import main
from lagrangian.output import equilibria_text


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
