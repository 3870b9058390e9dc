"""The optional ``constraints`` keys of ``derive --json`` (schema lagrangian.derive/1, additions only)."""

from __future__ import annotations

import json
from pathlib import Path

import jsonschema
import pytest
import sympy

import lagrangian
from lagrangian.cli.main import main

ROOT = Path(__file__).resolve().parents[2]
SCHEMA = json.loads((ROOT / "src/lagrangian/output/derive.schema.json").read_text())


def document(capsys, name: str) -> dict:
    assert main(["derive", str(ROOT / "examples" / name), "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    jsonschema.validate(doc, SCHEMA)
    return doc


@pytest.mark.slow
def test_models_without_constraints_keep_the_version_1_document(capsys) -> None:
    doc = document(capsys, "lagrange_top.toml")
    assert not {"constraints", "multipliers", "multiplier_terms"} & set(doc)


@pytest.mark.slow
def test_pendulum_constraint_rows_multiplier_and_reaction(capsys) -> None:
    doc = document(capsys, "pendulum_tension.toml")
    (c,) = doc["constraints"]
    assert (c["name"], c["role"], c["form"], c["kind"], c["frame"]) == (
        "length", "complementary", "holonomic", "holonomic", None)
    x, y, l, lam = sympy.symbols("x y l lambda_length")
    assert sympy.simplify(sympy.sympify(c["statement"]) - (x**2 + y**2 - l**2)) == 0
    (row,) = c["rows"]
    assert row["multiplier"] == "lambda_length" and doc["multipliers"] == ["lambda_length"]
    assert {k: sympy.sympify(v) for k, v in row["coefficients"].items()} == {"x": 2 * x, "y": 2 * y}
    force = [sympy.sympify(e) for e in c["reaction"]["force"]]
    assert force == [2 * lam * x, 2 * lam * y, 0] and c["reaction"]["point"] == "P"
    # The equations' right-hand sides hold the multiplier terms (Γ_i = −∂U/∂q_i + Q_i + Σ λ A).
    terms = [sympy.sympify(e) for e in doc["multiplier_terms"]]
    assert terms == [2 * lam * x, 2 * lam * y]
    rhs_y = sympy.sympify(doc["equations"][1]["rhs"])
    assert sympy.simplify(rhs_y - (-sympy.Symbol("g") * sympy.Symbol("m") + 2 * lam * y)) == 0


@pytest.mark.slow
@pytest.mark.parametrize("name", ["rolling_coin.toml", "top_reaction.toml", "rolling_disk_incline.toml"])
def test_vector_constraints_list_their_components_in_their_frame(capsys, name: str) -> None:
    doc = document(capsys, name)
    eom = lagrangian.derive(lagrangian.load_model(ROOT / "examples" / name))
    (c,) = doc["constraints"]
    assert isinstance(c["statement"], list) and len(c["statement"]) == 3 and c["frame"]
    assert [r["name"] for r in c["rows"]] == [r.name for r in eom.constraints]
    assert doc["multipliers"] == [m.name for m in eom.multipliers]
    for r, ours in zip(c["rows"], eom.constraints, strict=True):
        assert sympy.simplify(sympy.sympify(r["equation"]) - ours.expression._sympy_()) == 0


def test_principal_constraints_are_listed_without_rows(capsys, tmp_path) -> None:
    text = (ROOT / "examples" / "simple_pendulum.toml").read_text()
    text += '\n[constraints]\nrod = { holonomic = "(l*sin(theta))^2 + (l*cos(theta))^2 - l^2", principal = true }\n'
    path = tmp_path / "model.toml"
    path.write_text(text)
    assert main(["derive", str(path), "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    jsonschema.validate(doc, SCHEMA)
    (c,) = doc["constraints"]
    assert (c["role"], c["rows"], c["reaction"], doc["multipliers"]) == ("principal", [], None, [])


@pytest.mark.slow
def test_rows_chosen_by_the_engine_are_said(capsys, tmp_path) -> None:
    # Rolling written in the coin's own frame R2: three rows of rank two, kept as the two rows of R1.
    text = (ROOT / "examples" / "rolling_coin.toml").read_text()
    path = tmp_path / "coin.toml"
    path.write_text(text.replace('frame = "R1", description', 'frame = "R2", description'))
    assert main(["derive", str(path), "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    jsonschema.validate(doc, SCHEMA)
    (c,) = doc["constraints"]
    assert c["frame"] == "R2" and [r["name"] for r in c["rows"]] == ["rolling_x1", "rolling_y1"]
    choice = c["row_choice"]
    assert (choice["declared_frame"], choice["rank"], choice["frame"], choice["kept"]) == (
        "R2", 2, "R1", ["rolling_x1", "rolling_y1"])
    assert choice["declared_rows"] == ["rolling_x2", "rolling_y1", "rolling_z2"]
    assert c["reaction"]["frame"] == "R1" and choice["note"] in c["reaction"]["note"]
    assert main(["derive", str(path)]) == 0
    assert "rolling: rows chosen by the engine: written in R2" in capsys.readouterr().out
