"""`lagrangian equilibria`, called in-process: text, JSON, --set, --range, and the refusals."""

from __future__ import annotations

import json
import math
from pathlib import Path

import pytest

from lagrangian.cli.main import main

ROOT = Path(__file__).resolve().parents[2]
HOOP = str(ROOT / "examples" / "bead_rotating_hoop.toml")
CART = str(ROOT / "examples" / "cart_pendulum.toml")


@pytest.mark.slow
def test_text_gives_each_equilibrium_and_the_condition(capsys):
    assert main(["equilibria", HOOP]) == 0
    out = capsys.readouterr().out
    assert "Equilibria of Bead on a rotating hoop" in out
    assert "1. θ = 0  (closed form" in out and "θ = π = 3.14159265359" in out
    a = math.acos(9.81 / (0.5 * 6.0 ** 2))  # cosθ = g/(R Ω²), R = 0.5, Ω = 6
    assert f"θ = arccos(g/(R Ω²)) = {a:.12g}" in out
    assert out.count("exists if R Ω² > g (holds here)") == 2


def test_set_below_the_critical_rate(capsys):
    assert main(["equilibria", HOOP, "--set", "Omega=2"]) == 0
    out = capsys.readouterr().out
    assert "arccos" not in out and "2. θ = π" in out and "\n  3. " not in out


@pytest.mark.slow
def test_json_document(capsys):
    assert main(["equilibria", CART, "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert (doc["schema"], doc["version"], doc["coordinates"]) == ("lagrangian.equilibria", 1, ["x", "theta"])
    pairs = sorted((e["numeric"]["x"], round(e["numeric"]["theta"], 12)) for e in doc["equilibria"])
    pi = round(math.pi, 12)
    assert pairs == [(-1.0, 0.0), (-1.0, pi), (0.0, 0.0), (0.0, pi)]  # x = 0 or −2 l0, sinθ = 0
    assert {e["values"]["x"] for e in doc["equilibria"]} == {"0", "-2*l0"}
    assert all(e["closed_form"] and e["condition"] is None and e["residual"] < 1e-12 for e in doc["equilibria"])


def test_range_keeps_the_roots_inside(capsys, tmp_path):
    out_file = tmp_path / "eq.json"
    assert main(["equilibria", CART, "--range", "x=-0.4:2", "--json", "-o", str(out_file)]) == 0
    assert capsys.readouterr().out == ""
    doc = json.loads(out_file.read_text())
    assert sorted(e["numeric"]["x"] for e in doc["equilibria"]) == [0.0, 0.0]


@pytest.mark.parametrize(("argv", "message"), [
    (["--range", "y=0:1"], "--range y=0:1: `y` is not a coordinate"),
    (["--range", "x=1:0"], "the bounds must be finite with a < b"),
    (["--range", "x=a:b"], "the bounds must be numbers"),
    (["--range", "x"], "expected NAME=a:b"),
    (["--set", "theta=1"], "--set takes parameters only"),
    (["--set", "w=1"], "w"),
])
def test_bad_options_are_refused(capsys, argv, message):
    assert main(["equilibria", CART, *argv]) != 0
    err = capsys.readouterr().err
    assert err.startswith("error:") and message in err


def test_time_dependent_model_is_refused(capsys, tmp_path):
    out_file = tmp_path / "eq.txt"
    code = main(["equilibria", str(ROOT / "examples" / "kapitza_pendulum.toml"), "-o", str(out_file)])
    assert code != 0
    assert "depends on t explicitly" in capsys.readouterr().err
    assert not out_file.exists()


def test_each_equilibrium_comes_with_its_stability(capsys):
    """The bead: θ = 0 stable iff Ω² < g/R (here Ω = 3 < 4.43), θ = π always unstable."""
    import json

    from lagrangian_test_support import EXAMPLES_DIR

    from lagrangian.cli.main import main as cli
    assert cli(["equilibria", str(EXAMPLES_DIR / "bead_rotating_hoop.toml"), "--set", "Omega=3", "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    verdicts = {e["values"]["theta"]: (e["stable"], e["stability_reason"]) for e in doc["equilibria"]}
    assert verdicts["0"][0] is True and "Lagrange–Dirichlet" in verdicts["0"][1]
    assert verdicts["pi"][0] is False


def test_numeric_roots_at_simple_multiples_of_pi_are_named_and_minus_zero_is_zero() -> None:
    import math

    from lagrangian.output._equilibria_text import _numeric

    assert _numeric(-0.0) == "0"
    assert _numeric(-math.pi / 2) == "−π/2 = -1.57079632679"
    assert _numeric(math.pi) == "π = 3.14159265359"
    assert _numeric(2 * math.pi / 3) == "2π/3 = 2.09439510239"
    assert _numeric(0.994407212058699) == "0.994407212059"  # acos(g/(R Ω²)): not a multiple of π
    assert "π" not in _numeric(math.pi / 2 + 1e-9)  # 1e-9 away: a number, not π/2
