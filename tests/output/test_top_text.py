"""The top's analysis as text from the library: what ``lagrangian analyse`` prints, in the course's notation."""

from __future__ import annotations

import lagrangian
from lagrangian.cli.main import main
from lagrangian.output import top_analysis_text


def test_top_analysis_text_is_what_lagrangian_analyse_prints(capsys):
    eom = lagrangian.derive(lagrangian.lagrange_top())
    text = top_analysis_text(lagrangian.analyse_top(eom), eom)
    assert main(["analyse"]) == 0
    assert capsys.readouterr().out == text
    # The seed's sleeping-top criterion with its values (C ω)² = 0.25 > 4 A m g a = 0.07848.
    assert "(ψ, φ cyclic; θ remaining)" in text and "C²ω² = 0.25 > 4 A m g a = 0.07848" in text
