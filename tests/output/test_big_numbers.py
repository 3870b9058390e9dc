"""Display simplifications skip numbers past 100 digits (found by `tools/fuzz.py --format urdf`: a link
of mass 1e308, kept exact, made SymPy's factoring hunt for 300-digit primes; `report` took a minute)."""

from __future__ import annotations

from pathlib import Path

import pytest
import symengine as se
import sympy

from lagrangian._big_numbers import has_big_numbers
from lagrangian.cli.main import main

ROOT = Path(__file__).resolve().parents[2]


def test_big_numbers_are_told_from_ordinary_ones() -> None:
    x = sympy.Symbol("x")
    assert has_big_numbers(sympy.Integer(10) ** 308 * x + 1)
    assert has_big_numbers(x / sympy.Integer(10) ** 120)
    assert not has_big_numbers(sympy.Rational(123456789012345, 10**15) ** 4 * x)  # four 15-digit decimals
    assert has_big_numbers(se.Integer(10) ** 308 * se.Symbol("x"))  # SymEngine too
    assert not has_big_numbers(3.5)


@pytest.mark.slow
def test_a_report_with_a_mass_of_1e308_never_factors_its_big_numbers(tmp_path: Path, monkeypatch) -> None:
    # Checked by what is called, not by a clock: SymPy's factor must not meet a 300-digit coefficient.
    factor = sympy.factor

    def guarded(e, *args, **kwargs):  # type: ignore[no-untyped-def]
        assert not has_big_numbers(e), "factor called on a 300-digit coefficient"
        return factor(e, *args, **kwargs)

    monkeypatch.setattr(sympy, "factor", guarded)
    text = (ROOT / "examples" / "rrr_arm.urdf").read_text(encoding="utf-8")
    bad = text.replace('<mass value="2"/>', '<mass value="1e308"/>')
    assert bad != text
    path = tmp_path / "arm.urdf"
    path.write_text(bad, encoding="utf-8")
    assert main(["report", str(path), "--lang", "en", "-o", str(tmp_path / "r.md")]) == 0
    assert (tmp_path / "r.md").read_text(encoding="utf-8").startswith("# ")
