"""The size limit on the derived equations of motion M q̈ = F.

Equations past `MAX_OPS` operations are refused by `derive` with a `ModelError` that names
the size, the limit, the largest entry and the fix, before code generation, compilation or
a cross-check spends minutes and gigabytes on them; the largest models we ship stay well
inside it.
"""

from __future__ import annotations

from pathlib import Path

import pytest
import symengine as se

import lagrangian
from lagrangian import ModelError
from lagrangian.cli.main import main
from lagrangian.model import _limits
from lagrangian.model.zoo import planar_chain, spatial_chain

ROOT = Path(__file__).resolve().parents[2]


def _ops(eom) -> int:
    return se.count_ops(*[e for row in eom.M for e in row], *eom.F)


@pytest.mark.slow
@pytest.mark.parametrize("make", [lambda: lagrangian.load_model(ROOT / "examples" / "whipple_bicycle.toml"),
                                  lambda: planar_chain(20), lambda: spatial_chain(10)],
                         ids=["whipple", "planar-20", "spatial-10"])
def test_the_largest_shipped_models_are_well_inside_the_limit(make) -> None:
    eom = lagrangian.derive(make())
    assert _ops(eom) < _limits.MAX_OPS / 100


def test_equations_past_the_limit_are_refused_with_the_limit_and_the_fix(monkeypatch) -> None:
    model = lagrangian.load_model(ROOT / "examples" / "double_pendulum.toml")
    size = _ops(lagrangian.derive(model))
    monkeypatch.setattr(_limits, "MAX_OPS", size - 1)
    with pytest.raises(ModelError) as info:
        lagrangian.derive(model)
    err = info.value
    assert f"{size:,} operations" in err.message and f"{size - 1:,} allowed" in err.message
    assert "largest entry, F[" in err.message or "largest entry, M[" in err.message
    assert "LAGRANGIAN_MAX_OPS" in err.fix and err.file == str(ROOT / "examples" / "double_pendulum.toml")
    # For a model one trusts, the environment raises the limit.
    monkeypatch.setenv("LAGRANGIAN_MAX_OPS", str(size))
    assert lagrangian.derive(model).F


def test_the_command_line_says_why_in_one_message(monkeypatch, capsys) -> None:
    monkeypatch.setenv("LAGRANGIAN_MAX_OPS", "3")
    assert main(["derive", str(ROOT / "examples" / "simple_pendulum.toml")]) == 2
    err = capsys.readouterr().err
    assert "too large" in err and "3 allowed" in err and "tip:" in err and "Traceback" not in err


@pytest.mark.parametrize("text", ["", "x", "1e9", "٣", "-5"])
def test_a_malformed_environment_value_keeps_the_default(monkeypatch, text: str) -> None:
    monkeypatch.setenv("LAGRANGIAN_MAX_OPS", text)
    assert _limits.max_ops() == _limits.MAX_OPS
