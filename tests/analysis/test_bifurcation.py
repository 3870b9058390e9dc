"""Equilibria followed along a parameter: the bead on the rotating hoop's pitchfork at Ω² = g/R."""

from __future__ import annotations

import math

import numpy as np
import pytest
from lagrangian_test_support import EXAMPLES_DIR

import lagrangian
from lagrangian.analysis import EquilibriumError, bifurcation
from lagrangian.cli.main import main


def _hoop():
    return lagrangian.derive(lagrangian.load_model(EXAMPLES_DIR / "bead_rotating_hoop.toml"))


@pytest.mark.slow
def test_pitchfork_of_the_bead_on_the_rotating_hoop():
    g, R = 9.81, 0.5
    critical = math.sqrt(g / R)
    values = np.linspace(1.0, 8.0, 36)
    d = bifurcation(_hoop(), "Omega", values)
    by_value = {str(b.equilibrium.values["theta"]): b for b in d.branches}
    bottom, top = by_value["0"], by_value["pi"]
    assert [w for _, w in bottom.changes] == ["becomes unstable"]
    assert bottom.changes[0][0] == pytest.approx(critical, rel=1e-9)
    np.testing.assert_array_equal(bottom.stable, np.where(values < critical, 1.0, 0.0))
    assert not top.changes and np.all(top.stable == 0.0)
    side = [b for b in d.branches if b not in (bottom, top)]
    assert len(side) == 2
    for b in side:
        assert [w for _, w in b.changes] == ["appears"] and b.changes[0][0] == pytest.approx(critical, rel=1e-9)
        exists = values > critical
        np.testing.assert_allclose(np.abs(b.q[exists, 0]), np.arccos(g / (R * values[exists] ** 2)), rtol=1e-12)
        assert np.all(np.isnan(b.q[~exists, 0])) and np.all(b.stable[exists] == 1.0)


def test_bifurcation_errors():
    with pytest.raises(EquilibriumError, match="`k` is not a parameter"):
        bifurcation(_hoop(), "k", [1.0, 2.0])
    with pytest.raises(EquilibriumError, match="no point"):
        bifurcation(_hoop(), "Omega", [])


@pytest.mark.slow
def test_cli_equilibria_sweep_draws_the_pitchfork(tmp_path, capsys):
    out = tmp_path / "figs"
    assert main(["equilibria", str(EXAMPLES_DIR / "bead_rotating_hoop.toml"), "--sweep", "Omega=1:8:0.5",
                 "--plot", str(out)]) == 0
    text = capsys.readouterr().out
    assert "becomes unstable" in text and "appears" in text and "4.4294469" in text
    assert (out / "bifurcation.png").stat().st_size > 0
    assert main(["equilibria", str(EXAMPLES_DIR / "bead_rotating_hoop.toml"), "--plot", str(tmp_path / "x")]) == 2
    assert not (tmp_path / "x").exists()
