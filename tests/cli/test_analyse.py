"""`lagrangian analyse` and the shared `--set NAME=VALUE` parsing, called in-process."""

from __future__ import annotations

import math
import re
from pathlib import Path

import pytest

import lagrangian
from lagrangian.analysis._top import analyse_top
from lagrangian.cli._settings import SettingError, parse_settings
from lagrangian.cli.main import main

ROOT = Path(__file__).resolve().parents[2]


def _number(pattern: str, text: str) -> float:
    match = re.search(pattern, text)
    assert match, f"{pattern!r} not in:\n{text}"
    return float(match.group(1))


def test_default_is_the_seed_top_with_every_result(capsys):
    assert main(["analyse"]) == 0
    out = capsys.readouterr().out
    an = analyse_top(lagrangian.derive(lagrangian.lagrange_top()))
    assert "Lagrange top" in out and "(ψ, φ cyclic; θ remaining)" in out
    assert "ψ̇ = (K − H cosθ)/(A sin²θ)" in out
    assert "U_eff(θ) = H²/(2 C) + (K − H cosθ)²/(2 A sin²θ) + m g a cosθ" in out
    theta1 = _number(r"θ1 = ([0-9.]+) rad", out)
    theta2 = _number(r"θ2 = ([0-9.]+) rad", out)
    assert theta1 == pytest.approx(an.theta1, abs=1e-12) and theta2 == pytest.approx(an.theta2, abs=1e-12)
    degrees = _number(r"θ2 = [0-9.]+ rad = ([0-9.]+)°", out)
    assert degrees == pytest.approx(math.degrees(an.theta2), abs=1e-6)
    assert _number(r"T = 2 ∫ dθ/θ̇ over \[θ1, θ2\] = ([0-9.]+) s", out) == pytest.approx(an.period, rel=1e-8)
    assert _number(r"⟨ψ̇⟩ = ([0-9.]+) rad/s", out) == pytest.approx(an.precession_rate, rel=1e-8)
    assert "Apex curve: cusps" in out
    assert "C²ω² = 0.25 > 4 A m g a = 0.07848" in out and "stable" in out
    assert "u̇² = (2E' − 2 m g a u)(1 − u²)/A − ((K − H u)/A)²" in out


def test_set_changes_the_motion(capsys):
    assert main(["analyse", "--set", "psi_dot=-5", "--set", "theta=0.4", "--set", "C=0.012"]) == 0
    out = capsys.readouterr().out
    assert "Apex curve: loops" in out
    assert "θ = 0.4," in out and "C = 0.012" in out
    an = analyse_top(lagrangian.derive(lagrangian.lagrange_top()), parameters={"C": 0.012},
                     initial={"psi_dot": -5.0, "theta": 0.4})
    assert _number(r"θ2 = ([0-9.]+) rad", out) == pytest.approx(an.theta2, abs=1e-12)


def test_below_the_critical_spin_the_sleeping_top_is_unstable(capsys):
    assert main(["analyse", "--set", "phi_dot=20", "--set", "theta=0.01"]) == 0
    out = capsys.readouterr().out
    assert "C²ω² = 0.04 < 4 A m g a = 0.07848" in out
    assert "U_eff''(0) = H²/(4 A) − m g a = -0.481: unstable" in out
    assert "Applies to this motion" in out


def test_other_model_of_the_same_structure(capsys):
    assert main(["analyse", str(ROOT / "examples" / "spherical_pendulum.toml")]) == 0
    out = capsys.readouterr().out
    assert "Lz/(m l² sin²θ)" in out and "Apex curve: waves" in out
    assert "(2E' + 2 m l g u)" in out  # m g a = −m g l: the bob hangs below O


def test_output_file(tmp_path, capsys):
    target = tmp_path / "top.txt"
    assert main(["analyse", "-o", str(target)]) == 0
    assert capsys.readouterr().out == ""
    assert "Nutation period" in target.read_text(encoding="utf-8")


@pytest.mark.parametrize("argv, message", [
    (["--set", "thta=0.3"], "`thta` in `--set thta=0.3` is not a parameter, a coordinate or a coordinate's rate"),
    (["--set", "theta=abc"], "`abc` is not a number"),
    (["--set", "theta"], "is not of the form NAME=VALUE"),
    (["--set", "theta=nan"], "`nan` is not a number"),
    ([str(ROOT / "examples" / "double_pendulum.toml")], "`Double pendulum` has none cyclic"),
])
def test_errors_are_clear_and_exit_non_zero(argv, message, capsys):
    assert main(["analyse", *argv]) == 2
    err = capsys.readouterr().err
    assert message in err and "tip:" in err


def test_unknown_name_lists_the_known_ones(capsys):
    main(["analyse", "--set", "omega=3"])
    err = capsys.readouterr().err
    assert "parameters m, g, a, A, C; coordinates psi, theta, phi; rates psi_dot, theta_dot, phi_dot" in err


def test_parse_settings_splits_parameters_and_initial_values():
    model = lagrangian.lagrange_top()
    params, initial = parse_settings([" g = 1.62", "theta=0.3", "phi_dot=-8e1"], model)
    assert params == {"g": 1.62} and initial == {"theta": 0.3, "phi_dot": -80.0}
    assert parse_settings([], model) == ({}, {}) and parse_settings(None, model) == ({}, {})
    with pytest.raises(SettingError, match="set twice"):
        parse_settings(["g=1", "g=2"], model)
    with pytest.raises(SettingError, match="not a number"):
        parse_settings(["g=2*pi"], model)  # no expression evaluation
    # What Python's float also reads is not a plain decimal number.
    for text in ("1_0", "\u0663", "infinity", "nan", "0x10", "1e", "--1"):
        with pytest.raises(SettingError, match="not a number"):
            parse_settings([f"theta={text}"], model)
    assert parse_settings(["theta=.5", "g=+1E1", "phi_dot=-3."], model) == ({"g": 10.0}, {"theta": 0.5, "phi_dot": -3.0})


def test_simulate_checks_the_analysis_against_the_motion(capsys):
    """θ1, θ2, T and ⟨ψ̇⟩ read off a simulation (events θ̇ = 0) agree with the analysis to 1e-8."""
    assert main(["analyse", "--set", "phi_dot=80", "--set", "theta_dot=1", "--simulate", "3"]) == 0
    out = capsys.readouterr().out
    assert "Check against a simulation" in out
    rows = re.findall(r"^  (.+?): analysis (\S+) \S+; simulation (.+?)  \(largest difference (\S+)\)$", out, re.M)
    assert [r[0] for r in rows] == ["θ1", "θ2", "nutation period", "mean ⟨ψ̇⟩"]
    for name, _, sims, diff in rows:
        sims = [float(x) for x in sims.split(", ")]
        assert len(sims) >= 2, name
        assert float(diff) < 1e-8, (name, diff)


def test_simulation_check_is_independent_of_the_analysis():
    """A wrong analysis value shows up as a large difference (the check reads the motion only)."""
    from dataclasses import replace

    from lagrangian.numerics import simulation_check

    eom = lagrangian.derive(lagrangian.lagrange_top())
    an = analyse_top(eom)
    good = simulation_check(eom, an, periods=2.5)
    assert max(row[3] for row in good.rows) < 1e-8
    wrong = replace(an, nutation=replace(an.nutation, theta2=an.nutation.theta2 + 1e-3))
    rows = {row[0]: row for row in simulation_check(eom, wrong, periods=2.5).rows}
    assert rows["theta2"][3] == pytest.approx(1e-3, rel=1e-6)


def test_simulate_needs_a_positive_number_of_periods(capsys):
    assert main(["analyse", "--simulate", "-1"]) != 0
    assert "must be positive" in capsys.readouterr().err
