"""The optional keys of ``derive --json`` added within version 1: ``energy_balance``,
``multiplier_formulas``, ``reference``, ``generalized_forces[].note``; a principal constraint's
``statement`` is the declared f, not 0."""

from __future__ import annotations

import json
from pathlib import Path

import jsonschema
import pytest
import sympy

from lagrangian.cli.main import main

ROOT = Path(__file__).resolve().parents[2]
EXAMPLES = ROOT / "examples"
SCHEMA = json.loads((ROOT / "src/lagrangian/output/derive.schema.json").read_text())


def document(capsys, path: Path) -> dict:
    assert main(["derive", str(path), "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    jsonschema.validate(doc, SCHEMA)
    return doc


@pytest.mark.slow
def test_energy_balance_where_no_energy_integral_holds(capsys) -> None:
    doc = document(capsys, EXAMPLES / "kapitza_pendulum.toml")
    balance = doc["energy_balance"]
    assert [t["kind"] for t in balance["terms"]] == ["explicit time", "prescribed motion"]
    assert balance["conserved"] is False
    total = sum((sympy.sympify(t["power"]) for t in balance["terms"]), sympy.Integer(0))
    assert sympy.simplify(total - sympy.sympify(balance["power"])) == 0
    assert "energy_balance" not in document(capsys, EXAMPLES / "lagrange_top.toml")


@pytest.mark.slow
def test_multiplier_formulas_give_the_tension(capsys) -> None:
    doc = document(capsys, EXAMPLES / "pendulum_tension.toml")
    lam = sympy.sympify(doc["multiplier_formulas"]["lambda_length"])
    m, g, l, th, thd = sympy.symbols("m g l theta theta_dot")
    x, y, xd, yd = sympy.symbols("x y x_dot y_dot")
    on_circle = {x: l * sympy.sin(th), y: -l * sympy.cos(th), xd: l * sympy.cos(th) * thd, yd: l * sympy.sin(th) * thd}
    assert sympy.simplify(-2 * l * lam.subs(on_circle) - m * (g * sympy.cos(th) + l * thd**2)) == 0


@pytest.mark.slow
def test_reference_frame_and_load_notes(capsys) -> None:
    doc = document(capsys, EXAMPLES / "foucault_pendulum.toml")
    assert doc["reference"] == {"frame": "R_T", "origin": "O"}
    notes = {f["load"]: f["note"] for f in doc["generalized_forces"]}
    assert "virtual power Σ Q_i q_i* not zero" in notes["Coriolis"]
    assert "reference" not in document(capsys, EXAMPLES / "simple_pendulum.toml")


@pytest.mark.slow
def test_a_principal_constraint_statement_is_the_declared_relation(capsys, tmp_path) -> None:
    text = (EXAMPLES / "simple_pendulum.toml").read_text()
    text += '\n[constraints]\nrod = { holonomic = "(l*sin(theta))^2 + (l*cos(theta))^2 - l^2", principal = true }\n'
    path = tmp_path / "model.toml"
    path.write_text(text)
    (c,) = document(capsys, path)["constraints"]
    statement = sympy.sympify(c["statement"])
    assert statement != 0 and sympy.simplify(statement) == 0


@pytest.mark.slow
def test_an_integrable_velocity_row_has_its_integral_in_the_json(capsys) -> None:
    """The rolling disk's ẋ − r φ̇ = 0 is holonomic (x − r φ = cste); the coin's rows are not."""
    [disk] = document(capsys, EXAMPLES / "rolling_disk_incline.toml")["constraints"]
    assert disk["kind"] == "holonomic"
    x, r, phi = sympy.symbols("x r phi")
    [integral] = disk["integrals"]
    assert sympy.simplify(sympy.sympify(integral) - (x - r * phi)) == 0
    coin = document(capsys, EXAMPLES / "rolling_coin.toml")["constraints"]
    assert any(c["kind"] == "nonholonomic" and "integrals" not in c for c in coin)
