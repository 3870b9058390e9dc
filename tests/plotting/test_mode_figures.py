"""The small-motion figures: the eigenvalues against a parameter, and the mode shapes.

The data drawn is compared with the closed form of the bead on the rotating hoop at the
bottom, δθ̈ = (Ω² − g/R) δθ: Im λ = √(g/R − Ω²) below the pitchfork, Re λ = ±√(Ω² − g/R) above.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from lagrangian_test_support import EXAMPLES_DIR

import lagrangian
from lagrangian.plotting import plot_eigenvalue_sweep, plot_mode_shapes

pytest.importorskip("matplotlib")


@pytest.fixture(scope="module")
def hoop():
    eom = lagrangian.derive(lagrangian.load_model(EXAMPLES_DIR / "bead_rotating_hoop.toml"))
    return eom, lagrangian.linearize(eom, {"theta": 0}, symbolic=("Omega",))


@pytest.mark.parametrize("lang, word", [("en", "eigenvalues"), ("fr", "valeurs propres")])
def test_eigenvalue_sweep_draws_the_hoops_closed_form(hoop, lang, word):
    eom, lin = hoop
    g, R = 9.81, 0.5
    values = np.linspace(0.0, 8.0, 81)
    sweep = lagrangian.sweep(lin, "Omega", values)
    fig = plot_eigenvalue_sweep(sweep, eom, lang=lang)
    ax = fig.axes[0]
    re_line, im_line = ax.lines[0], ax.lines[1]
    x, re_ = re_line.get_data()
    expected = [math.sqrt(max(w * w - g / R, 0.0)) for w in x]
    assert np.allclose(np.abs(re_), expected, atol=1e-9)
    xi, im = im_line.get_data()
    assert np.allclose(im, [math.sqrt(g / R - w * w) for w in xi], atol=1e-9)
    # The change of stability is marked where Ω² = g/R.
    marks = [line.get_xdata()[0] for line in ax.lines[2:] if line.get_linestyle() == ":"]
    assert len(marks) >= 1 and all(abs(m - math.sqrt(g / R)) < 1e-8 for m in marks)
    assert word in fig._suptitle.get_text()


def test_mode_shapes_one_panel_per_mode_largest_component_one():
    eom = lagrangian.derive(lagrangian.load_model(EXAMPLES_DIR / "double_pendulum.toml"))
    modes = lagrangian.linearize(eom, {"theta1": 0, "theta2": 0}).modes()
    fig = plot_mode_shapes(modes, eom)
    panels = [ax for ax in fig.axes if ax.get_visible()]
    assert len(panels) == 2
    for ax in panels:
        heights = [p.get_height() for p in ax.patches]
        assert max(heights, key=abs) == pytest.approx(1.0)
