"""`lagrangian verify`, called in-process: the report, the exit codes, a failing check."""

from __future__ import annotations

import dataclasses
from pathlib import Path

import pytest

import lagrangian
from lagrangian.cli import _verify
from lagrangian.cli.main import main

ROOT = Path(__file__).resolve().parents[2]
EXAMPLES = sorted((ROOT / "examples").glob("*.toml"))


def test_the_top_in_the_courses_notation(capsys) -> None:
    assert main(["verify", str(ROOT / "examples/lagrange_top.toml")]) == 0
    out = capsys.readouterr().out
    assert "L(ψ) ⇔ moment theorem at O projected on z0:" in out
    assert "L(θ) ⇔ moment theorem at O projected on u:" in out
    assert "L(φ) ⇔ moment theorem at O projected on z:" in out
    assert "A θ̈ − A ψ̇² sinθ cosθ + C ψ̇ sinθ (φ̇ + ψ̇ cosθ) = m g a sinθ ✓" in out
    assert "σ_O(S/R0) = Π_O·Ω = A θ̇ u + A ψ̇ sinθ w + C (φ̇ + ψ̇ cosθ) z" in out
    assert "R_O = m γ(G/R0) − (weight)" in out and "(in R2: u, w, z)" in out
    assert "drop out of every projection" in out
    assert "All 3 Lagrange equations agree" in out


def test_default_model_is_the_top(capsys) -> None:
    assert main(["verify"]) == 0
    assert "Lagrange top" in capsys.readouterr().out


@pytest.mark.slow
@pytest.mark.parametrize("example", EXAMPLES, ids=lambda p: p.stem)
def test_every_example_verifies(example: Path, capsys) -> None:
    assert main(["verify", str(example)]) == 0
    out = capsys.readouterr().out
    assert "✗" not in out and out.count("✓") >= 2


def test_along_a_simulated_motion(capsys) -> None:
    code = main(["verify", str(ROOT / "examples/lagrange_top.toml"), "--simulate", "0.5", "--n-out", "51",
                 "--set", "theta=0.8", "--set", "m=2"])
    out = capsys.readouterr().out
    assert code == 0, out
    assert "L(ψ) projected:" in out and "R_O(t) in R0" in out and "all within 1e-09 ✓" in out


def test_a_wrong_equation_fails_with_exit_code_5(monkeypatch, capsys) -> None:
    def wrong_derive(model):  # noqa: ANN001, ANN202 - L(θ) with the weight's sign flipped
        eom = lagrangian.derive(model)
        eqs = tuple(dataclasses.replace(eq, rhs=-eq.rhs) if eq.coordinate == "theta" else eq for eq in eom.equations)
        return dataclasses.replace(eom, equations=eqs)

    monkeypatch.setattr(_verify, "derive", wrong_derive)
    assert main(["verify"]) == 5
    captured = capsys.readouterr()
    assert captured.out == ""
    assert "L(theta) does not agree with the moment theorem at O projected on u" in captured.err
    assert "right side" in captured.err and "tip:" in captured.err


def test_set_without_simulate_is_refused(capsys) -> None:
    assert main(["verify", "--set", "theta=0.3"]) == 2
    assert "--simulate" in capsys.readouterr().err


def test_an_unknown_setting_is_refused(capsys) -> None:
    assert main(["verify", "--simulate", "0.1", "--set", "nope=1"]) == 2
    assert "`nope`" in capsys.readouterr().err


def test_report_to_a_file(tmp_path: Path, capsys) -> None:
    target = tmp_path / "report.txt"
    assert main(["verify", str(ROOT / "examples/simple_pendulum.toml"), "-o", str(target)]) == 0
    assert capsys.readouterr().out == ""
    assert "L(θ) ⇔ moment theorem at O projected on x0" in target.read_text(encoding="utf-8")


def test_labels_in_a_rotating_reference_frame(capsys) -> None:
    """With inertial loads the theorems are written relative to R: γ(P/R), not γ(P/R0)."""
    assert main(["verify", str(ROOT / "examples/bead_rotating_hoop.toml")]) == 0
    out = capsys.readouterr().out
    assert "m γ(P/R1) = weight + Coriolis + entrainment + R" in out
    assert "R(→P) = m γ(P/R1) − (Coriolis + entrainment + weight)" in out
    assert "γ(P/R0)" not in out and "(R0 Galilean)" not in out and "relative to R1, not Galilean" in out
