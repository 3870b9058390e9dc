"""Declared signs and ranges, and the signs the derivation used, in `derive` and its JSON."""

from __future__ import annotations

import json
from pathlib import Path

import jsonschema
import pytest
from lagrangian_test_support import wall_spring

from lagrangian.cli.main import main

ROOT = Path(__file__).resolve().parents[2]
SCHEMA = json.loads((ROOT / "src/lagrangian/output/derive.schema.json").read_text())

SPRING = wall_spring(0.1)


@pytest.mark.slow
def test_json_and_text_say_what_was_assumed_and_used(capsys, tmp_path) -> None:
    path = tmp_path / "spring.toml"
    path.write_text(SPRING)
    assert main(["derive", str(path), "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    jsonschema.validate(doc, SCHEMA)
    assert doc["forcing"] == ["-k*x"]
    a = doc["assumptions"]
    assert a["signs"] == {"L": "positive"} and a["ranges"] == {"x": ["-1/2", "1/2"]}
    (used,) = a["used"]
    assert (used["expression"], used["relation"], used["general"]) == ("L + x", "≥", False)
    assert "L = 1: at the declared values" in used["reason"]
    assert main(["derive", str(path)]) == 0
    text = capsys.readouterr().out
    assert "Declared assumptions: L > 0, x ∈ [-0.5, 0.5]" in text
    assert "used to simplify: x + L ≥ 0" in text and "F[x] = −k x" in text


def test_models_without_assumptions_have_no_key(capsys) -> None:
    assert main(["derive", str(ROOT / "examples" / "simple_pendulum.toml"), "--json"]) == 0
    assert "assumptions" not in json.loads(capsys.readouterr().out)


def test_the_report_says_which_signs_simplified_the_efforts(tmp_path) -> None:
    path = tmp_path / "spring.toml"
    path.write_text(SPRING.replace("range = [-0.5, 0.5]", 'range = ["-L", "L"]'))
    out = tmp_path / "spring.md"
    assert main(["report", str(path), "--format", "md", "--no-verify", "--lang", "en", "-o", str(out)]) == 0
    text = out.read_text()
    assert (r"The declared assumptions ($`L > 0`$ and $`x \in \left[-L, L\right]`$) give $`x + L \geq 0`$ "
            "(for every allowed value)") in text
