"""Models whose equations are not defined at the initial state (issue 15; found by tools/fuzz.py).

``rotation = ["phi^phi", "z"]`` with phi = 0 puts log(0) in M: the eigenvalue check of the
initial state met a matrix of nan and raised NumPy's `LinAlgError`.  Now a `SimulationError`
names the entries that are not finite and the state.
"""

from __future__ import annotations

from pathlib import Path

import pytest

import lagrangian
from lagrangian import SimulationError
from lagrangian.cli.main import main

ROOT = Path(__file__).resolve().parents[2]


def _top(tmp_path: Path, example: str, old: str, new: str) -> Path:
    text = (ROOT / "examples" / example).read_text(encoding="utf-8")
    assert old in text
    path = tmp_path / example
    path.write_text(text.replace(old, new), encoding="utf-8")
    return path


@pytest.mark.parametrize("example", ["lagrange_top.toml", "top_reaction.toml"])
def test_m_not_finite_at_the_start_is_a_simulation_error(tmp_path: Path, example: str) -> None:
    path = _top(tmp_path, example, 'rotation = ["phi", "z"]', 'rotation = ["phi^phi", "z"]')
    eom = lagrangian.derive(lagrangian.load_model(path))
    with pytest.raises(SimulationError) as info:
        lagrangian.simulate(eom, 0.1, n_out=3)
    assert "not finite" in info.value.message and "initial state" in info.value.message
    assert "M[" in info.value.message and info.value.fix


def test_the_command_line_says_it_in_one_message(tmp_path: Path, capsys) -> None:
    path = _top(tmp_path, "lagrange_top.toml", 'rotation = ["phi", "z"]', 'rotation = ["phi^phi", "z"]')
    assert main(["simulate", str(path), "--t-end", "0.1"]) == 4
    err = capsys.readouterr().err
    assert "not finite" in err and "Traceback" not in err
