"""What ``lagrangian derive`` prints beyond the course form: steps 1 and 7 (constraints, λ_k, reactions),
the energy balance, load notes, and labels in a non-Galilean reference frame (text and LaTeX)."""

from __future__ import annotations

from pathlib import Path

import pytest

from lagrangian.cli.main import main

ROOT = Path(__file__).resolve().parents[2]
EXAMPLES = ROOT / "examples"

#: The double pendulum with a viscous hinge and a horizontal push: a joint damper and a point force.
DAMPED = (EXAMPLES / "double_pendulum.toml").read_text().replace("[parameters]", "[parameters]\nc = 0.05\nF = 0.2") + (
    '\n[loads.hinge]\njoint_damper = ["R0", "S1"]\ncoefficient = "c"\n'
    '\n[loads.push]\nforce = "F*sin(t)*R0.y"\nat = "S1"\n')

#: The simple pendulum with its rod's length declared principal: satisfied by the coordinates.
PRINCIPAL = (EXAMPLES / "simple_pendulum.toml").read_text() + (
    '\n[constraints]\nrod = { holonomic = "(l*sin(theta))^2 + (l*cos(theta))^2 - l^2", principal = true }\n')


def derive(capsys, path: Path, *options: str) -> str:
    assert main(["derive", str(path), *options]) == 0
    return capsys.readouterr().out


def written(tmp_path: Path, text: str) -> Path:
    path = tmp_path / "model.toml"
    path.write_text(text, encoding="utf-8")
    return path


def test_pendulum_tension_prints_step_7_the_multiplier_and_the_reaction(capsys) -> None:
    out = derive(capsys, EXAMPLES / "pendulum_tension.toml")
    assert "length (complementary, holonomic): x² + y² − l² = 0" in out
    assert "Complementary equations (step 7)" in out and "x² + y² − l² = 0    [length]" in out
    # T = −2 l λ = m (g cos θ + l θ̇²) with x = l sin θ, y = −l cos θ (docs/constraints.md).
    assert "λ_length = m (g y − x\u0307² − y\u0307²)/(2 (x² + y²))" in out
    assert "reaction of length: force at P: R = 2 x λ_length x0 + 2 y λ_length y0" in out
    assert "m x\u0308 = 2 x λ_length" in out and "lambda_length" not in out


def test_incline_friction_multiplier_is_printed(capsys) -> None:
    out = derive(capsys, EXAMPLES / "rolling_disk_incline.toml")
    assert "λ_rolling_x1 = −⅓ m g sinα" in out
    assert "reaction of rolling: force at I: R = λ_rolling_x1 x1" in out


def test_labels_in_a_rotating_reference_frame(capsys) -> None:
    out = derive(capsys, EXAMPLES / "bead_rotating_hoop.toml")
    assert "Ω(R1/R0) = Ω z0    (prescribed)" in out and "Ω(R2/R1) = θ̇ y1" in out
    assert "Ω(R1/R0) = 0" not in out and "Ω(R2/R0)" not in out
    assert "T(P/R1) = ½ m R² θ̇²" in out and "Kinetic energy T(Σ/R1)" in out and "U_P(Σ/R1)" in out
    assert "/R0) = ½" not in out and "U_P(Σ/R0)" not in out
    tex = derive(capsys, EXAMPLES / "bead_rotating_hoop.toml", "--latex")
    assert r"T(P/R1)" in tex and r"\vec{\Omega}(R2/R1)" in tex and r"T(P/R_0)" not in tex


def test_the_coriolis_note_is_printed(capsys) -> None:
    out = derive(capsys, EXAMPLES / "foucault_pendulum.toml")
    assert "Σ Q_i q̇_i ≡ 0; virtual power Σ Q_i q_i* not zero" in out
    assert "Ω(R_T/R0) = Ω z0    (prescribed)" in out and "T(P/R_T)" in out


@pytest.mark.slow
def test_energy_balance_kinds_and_notes_of_a_damped_driven_pendulum(capsys, tmp_path) -> None:
    out = derive(capsys, written(tmp_path, DAMPED))
    assert "hinge (joint damper, non-conservative)" in out and "push (point force, non-conservative)" in out
    assert "jointdamper" not in out and "pointforce" not in out
    assert "dE/dt = P(non-conservative)" in out
    balance = out.split("Energy balance", 1)[1]
    assert "  hinge (joint damper): −c θ̇1²" in balance and "  push (point force): " in balance
    tex = derive(capsys, written(tmp_path, DAMPED), "--latex")
    assert r"\subsection*{Energy balance}" in tex and "joint damper" in tex
    assert tex.count(r"\begin{align*}") == tex.count(r"\end{align*}")
    assert tex.isascii()  # pdflatex with inputenc: ∂U/∂t and λ are written as math, not as characters


@pytest.mark.parametrize("name", ["simple_pendulum.toml", "lagrange_top.toml", "pendulum_tension.toml"])
def test_no_balance_where_the_energy_is_a_first_integral(capsys, name) -> None:
    assert "Energy balance" not in derive(capsys, EXAMPLES / name)


def test_a_principal_constraint_prints_as_declared_not_0_equals_0(capsys, tmp_path) -> None:
    out = derive(capsys, written(tmp_path, PRINCIPAL))
    assert "rod (principal, holonomic): l² sin²θ + l² cos²θ − l² = 0" in out
    assert "0 = 0" not in out


def test_rolling_on_an_incline_is_shown_holonomic_and_integrated(capsys) -> None:
    out = derive(capsys, EXAMPLES / "rolling_disk_incline.toml")
    assert "rolling (complementary, no slip; holonomic, integrable: " in out
    coin = derive(capsys, EXAMPLES / "rolling_coin.toml")
    assert "rolling (complementary, no slip; nonholonomic): " in coin


def test_kapitza_lagrange_equation_is_printed_expanded(capsys) -> None:
    # 56 operations as derived (beyond the SymPy tidying), 13 once SymEngine has expanded it.
    out = derive(capsys, EXAMPLES / "kapitza_pendulum.toml")
    assert "m l² θ̈ − m l a ν² sinθ cos(ν t) = −m l g sinθ" in out


def test_exact_coulomb_friction_is_printed_with_the_sign_function(capsys) -> None:
    out = derive(capsys, EXAMPLES / "block_on_incline.toml")
    assert "Q_x = −m g f cosα sgn(x\u0307)" in out and "√(x\u0307²)" not in out
    assert "dE/dt = P(non-conservative) = −m g f cosα |x\u0307|" in out
    assert "T = −f N v_s/‖v_s‖ (exact; sticking handled by the simulation with |T| ≤ f_s N)" in out


def test_a_time_dependent_balance_is_not_called_non_conservative(capsys) -> None:
    """Kapitza's dE/dt is ∂U/∂t and the power imposing the pivot's motion: no non-conservative effort."""
    out = derive(capsys, EXAMPLES / "kapitza_pendulum.toml")
    assert "dE/dt = P = " in out and "P(non-conservative)" not in out
    assert "∂U/∂t (weight)" in out and "prescribed motion" in out
    assert "dE/dt = P(non-conservative) = " in derive(capsys, EXAMPLES / "block_on_belt.toml")
