"""The command line, called in-process: `main(argv)` returns the exit code."""

import json
from pathlib import Path

import jsonschema
import numpy as np
import pytest
import sympy

import lagrangian
from lagrangian.cli.main import main

ROOT = Path(__file__).resolve().parents[2]
SCHEMA = json.loads((ROOT / "src/lagrangian/output/derive.schema.json").read_text())


def test_help_lists_every_command(capsys):
    assert main([]) == 0
    out = capsys.readouterr().out
    assert "derive" in out
    with pytest.raises(SystemExit) as exc:
        main(["derive", "--help"])
    assert exc.value.code == 0
    assert "--json" in capsys.readouterr().out


def test_default_model_is_the_seed_top(capsys):
    assert main(["derive"]) == 0
    out = capsys.readouterr().out
    assert "Lagrange top" in out and "= K" in out and "= H" in out


@pytest.mark.slow
@pytest.mark.parametrize("example", sorted((ROOT / "examples").glob("*.toml")), ids=lambda p: p.stem)
def test_json_is_valid_and_reads_back_into_sympy(example, capsys):
    assert main(["derive", str(example), "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    jsonschema.validate(doc, SCHEMA)
    # The strings are SymPy-readable and mean the engine's M and F (checked at a random state).
    eom = lagrangian.derive(lagrangian.load_model(example))
    names = doc["coordinates"] + doc["rates"] + list(doc["parameters"]) + ["t"]
    rng = np.random.default_rng(3)
    point = {name: float(rng.uniform(0.3, 1.2)) for name in names}
    locals_ = {name: sympy.Symbol(name) for name in names}
    se_point = {s: point[s.name] for s in (*eom.q, *eom.qd) if s.name in point}
    se_point.update({sympy.Symbol(k): v for k, v in point.items()})
    at = {sympy.Symbol(k): sympy.Float(v) for k, v in point.items()}  # xreplace: subs is slow on long entries
    for i, row in enumerate(doc["mass_matrix"]):
        for j, entry in enumerate(row):
            ours = float(sympy.sympify(entry, locals=locals_).xreplace(at))
            engine = float(eom.M[i][j]._sympy_().xreplace(at))
            assert ours == pytest.approx(engine, rel=1e-12, abs=1e-12)
    for i, entry in enumerate(doc["forcing"]):
        ours = float(sympy.sympify(entry, locals=locals_).xreplace(at))
        assert ours == pytest.approx(float(eom.F[i]._sympy_().xreplace(at)), rel=1e-12, abs=1e-12)
    assert len(doc["equations"]) == len(doc["coordinates"])


def test_top_json_first_integrals(capsys):
    assert main(["derive", "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert set(doc["first_integrals"]) == {"K", "H", "E"}
    assert doc["conservative"] is True
    H = sympy.sympify(doc["first_integrals"]["H"])
    C, phi_dot, psi_dot, theta = sympy.symbols("C phi_dot psi_dot theta")
    assert sympy.simplify(H - C * (phi_dot + psi_dot * sympy.cos(theta))) == 0


def test_output_file_is_written_atomically_and_kept_on_error(tmp_path, capsys):
    out = tmp_path / "top.tex"
    assert main(["derive", "--latex", "-o", str(out)]) == 0
    assert out.read_text().startswith(r"\documentclass")
    bad = tmp_path / "bad.toml"
    bad.write_text('[coordinates]\nx = {}\n[particles.P]\nmass = "m"\nposition = "x*R0.x"\n')
    out.write_text("previous content")
    assert main(["derive", str(bad), "--latex", "-o", str(out)]) == 2
    assert out.read_text() == "previous content"
    assert list(tmp_path.iterdir()) == sorted([bad, out]) or set(tmp_path.iterdir()) == {bad, out}


def test_bad_model_gives_location_and_tip_not_a_traceback(tmp_path, capsys):
    bad = tmp_path / "bad.toml"
    bad.write_text('[parameters]\nm = 1\n[coordinates]\nx = {}\n[particles.P]\nmass = "m"\nposition = "x*R0.x + y*R0.y"\n')
    assert main(["derive", str(bad)]) == 2
    err = capsys.readouterr().err
    assert str(bad) in err and "unknown symbol `y`" in err and "tip:" in err
    assert "Traceback" not in err


def test_missing_file(capsys):
    assert main(["derive", "/nonexistent/model.toml"]) == 2
    assert "does not exist" in capsys.readouterr().err
