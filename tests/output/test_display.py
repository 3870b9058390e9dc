"""Jupyter display: rendered math in the course's notation, bounded for large models."""

from __future__ import annotations

import subprocess
import sys

import numpy as np
import pytest
from lagrangian_test_support import eom_of

import lagrangian
from lagrangian.output._report.size import FOLD_LINES


def test_equations_of_motion_display_the_seeds_equations() -> None:
    eom = lagrangian.derive(lagrangian.lagrange_top())
    latex = eom._repr_latex_()
    assert latex.startswith("$$") and latex.rstrip().endswith("$$")
    # L(θ): A θ̈ − A ψ̇² sinθ cosθ + C ψ̇ sinθ (φ̇ + ψ̇ cosθ) = m g a sinθ, in the model's parameter order.
    row = next(line for line in latex.splitlines() if r"L(\theta)" in line)
    assert r"A \ddot{\theta} - A \dot{\psi}^{2} \sin\theta \cos\theta" in row
    assert r"C \dot{\psi} \sin\theta \left(\dot{\varphi} + \dot{\psi} \cos\theta\right)" in row
    assert row.rstrip(" \\").endswith(r"= m g a \sin\theta")
    assert latex.count("L(") == 3 and r"L(\varphi)" in latex and r"L(\psi)" in latex
    md = eom._repr_markdown_()
    assert md.startswith("**Lagrange top**: 3 Lagrange equations") and r"\ddot{\theta}" in md


def test_a_value_displays_itself_with_only_its_stage_imported() -> None:
    """Output, a later stage, is loaded by the first display (through the package's face), not before."""
    code = ("import sys\n"
            "from lagrangian.dynamics import derive\n"
            "from lagrangian.model.zoo import lagrange_top\n"
            "eom = derive(lagrange_top())\n"
            "before = 'lagrangian.output' in sys.modules\n"
            "latex = eom._repr_latex_()\n"
            "print(before, 'lagrangian.output' in sys.modules, latex.startswith('$$'))\n")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.split() == ["False", "True", "True"], out.stderr


def test_one_lagrange_equation_and_first_integrals() -> None:
    eom = lagrangian.derive(lagrangian.lagrange_top())
    latex = eom.equation("theta")._repr_latex_()
    assert r"L(\theta):\quad A \ddot{\theta}" in latex and r"\sin\theta" in latex
    integrals = {fi.name: fi for fi in lagrangian.first_integrals(eom)}
    assert r"C \left(\dot{\varphi} + \dot{\psi} \cos\theta\right) = H" in integrals["H"]._repr_latex_()
    assert r"\dot{\theta}^{2}" in integrals["E"]._repr_latex_() and "= E" in integrals["E"]._repr_latex_()
    md = integrals["K"]._repr_markdown_()
    assert "= K" in md and "psi is cyclic" in md


def test_constraint_rows_are_displayed() -> None:
    latex = eom_of("pendulum_tension.toml")._repr_latex_()
    assert r"\lambda_{\mathrm{length}}" in latex and r"= 0 \quad \text{(length)}" in latex


def test_trajectory_summary_table() -> None:
    eom = lagrangian.derive(lagrangian.lagrange_top())
    tr = lagrangian.simulate(eom, 0.5)
    html = tr._repr_html_()
    assert html.startswith("<table>") and "dop853" in html and "theta" in html and "relative drift" in html
    assert f"0 → {tr.t[-1]:.6g} ({len(tr.t)} points)" in html
    md = tr._repr_markdown_()
    assert md.splitlines()[1] == "|---|---|" and f"| theta | {tr.q[0, 1]:.6g} → {tr.q[-1, 1]:.6g} |" in md
    latex = tr._repr_latex_()
    assert r"\theta: & 0.5 \to" in latex and r"H: & \text{relative drift}" in latex


def test_a_subclass_is_displayed_as_its_base() -> None:
    import dataclasses

    from lagrangian.numerics import Trajectory

    @dataclasses.dataclass(frozen=True)
    class Replayed(Trajectory):  # as `OptimalTrajectory` is
        note: str = ""

    tr = lagrangian.simulate(lagrangian.derive(lagrangian.lagrange_top()), 0.2)
    replayed = Replayed(**{f.name: getattr(tr, f.name) for f in dataclasses.fields(Trajectory)})
    assert replayed._repr_html_() == tr._repr_html_() and replayed._repr_latex_() == tr._repr_latex_()


def test_linear_model_writes_A_out() -> None:
    eom = eom_of("inverted_pendulum_cart.toml")
    lm = lagrangian.linearize(eom)
    A, B = lm.numeric()
    latex = lm._repr_latex_()
    assert r"\frac{d}{dt}\begin{bmatrix}x \\ \theta \\ \dot{x} \\ \dot{\theta}\end{bmatrix}" in latex
    assert f"{A[3, 1]:.4g}" in latex and f"{B[3, 0]:.4g}" in latex and r"\begin{bmatrix}F\end{bmatrix}" in latex
    assert r"about $x = 0, \theta = 0" in latex


@pytest.mark.slow
def test_large_models_stay_bounded() -> None:
    """The Whipple bicycle: long sides summarized as ⟨n terms⟩, no equation past FOLD_LINES lines."""
    eom = eom_of("whipple_bicycle.toml")
    latex = eom._repr_latex_()
    assert r"\langle" in latex and r"\text{terms} \rangle" in latex
    assert len(latex) < 20_000
    rows = latex.split(r"\begin{aligned}")[1].split(r"\end{aligned}")[0].split(" \\\\\n")
    starts = [k for k, r in enumerate(rows) if not r.lstrip().startswith(r"& \quad")]
    assert sum(rows[k].lstrip().startswith("& L(") for k in starts) == len(eom.coordinates)
    assert len(starts) == len(eom.coordinates) + len(eom.constraints)
    assert np.diff(starts + [len(rows)]).max() <= FOLD_LINES
    assert len(lagrangian.linearize(eom)._repr_latex_()) < 20_000


def test_an_equation_past_FOLD_LINES_lines_is_cut() -> None:
    from lagrangian.output._display import _bounded
    from lagrangian.output._report.document import Equation

    lines = _bounded(Equation(tuple(f"+ x_{k}" for k in range(20))))
    assert len(lines) == FOLD_LINES and lines[-1].startswith(r"\ldots")
    assert f"{20 - FOLD_LINES + 1} more lines" in lines[-1]
