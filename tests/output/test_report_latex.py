"""The LaTeX report compiles with pdflatex (skipped where pdflatex is not installed)."""

from __future__ import annotations

import re
import shutil
import subprocess
from io import BytesIO

import pytest
from lagrangian_test_support import EXAMPLES_DIR

import lagrangian
from lagrangian.output import ReportFigure, report

needs_pdflatex = pytest.mark.skipif(shutil.which("pdflatex") is None, reason="pdflatex is not installed on this machine")

#: Widest line (pt) the seed's top may overflow the text width by: none of its lines should.
OVERFULL_PT = 1.0


def _compile(tmp_path, name: str) -> str:
    run = subprocess.run(["pdflatex", "-interaction=nonstopmode", "-halt-on-error", f"{name}.tex"], cwd=tmp_path,
                         capture_output=True, text=True, timeout=180)
    assert run.returncode == 0, run.stdout[-3000:]
    assert (tmp_path / f"{name}.pdf").stat().st_size > 5000
    return run.stdout


@pytest.mark.tex
@needs_pdflatex
def test_top_report_compiles_with_its_figure_and_fits_the_page(tmp_path):
    import matplotlib.figure

    fig = matplotlib.figure.Figure(figsize=(3, 2))
    fig.add_subplot().plot([0, 1, 4, 9])
    buffer = BytesIO()
    fig.savefig(buffer, format="png")
    r = report(lagrangian.lagrange_top(), lang="fr", verification=True,
               figures=[ReportFigure(buffer.getvalue(), "θ(t) — nutation")])
    r.save(tmp_path / "top.tex")
    log = _compile(tmp_path, "top")
    widths = [float(x) for x in re.findall(r"Overfull \\hbox \(([\d.]+)pt too wide\)", log)]
    assert all(w < OVERFULL_PT for w in widths), widths


@pytest.mark.tex
@needs_pdflatex
@pytest.mark.parametrize("name, lang", [("double_pendulum.toml", "en"), ("pendulum_tension.toml", "fr"),
                                        ("bead_rotating_hoop.toml", "fr")])
def test_other_reports_compile(name, lang, tmp_path):
    report(EXAMPLES_DIR / name, lang=lang, verification=True).save(tmp_path / "model.tex")
    _compile(tmp_path, "model")


def test_french_uses_babel_where_installed_and_wide_tables_wrap():
    tex = report(EXAMPLES_DIR / "foucault_pendulum.toml", lang="fr").latex()
    assert r"\IfFileExists{french.ldf}{\usepackage[french]{babel}}{\frenchspacing}" in tex
    assert "babel" not in report(EXAMPLES_DIR / "foucault_pendulum.toml", lang="en").latex()
    specs = re.findall(r"\\begin\{longtable\}\{(.*)\}\n", tex)
    assert specs and any("p{" in spec for spec in specs)  # the constants' table, with its long descriptions
    for spec in specs:
        shares = [float(x) for x in re.findall(r"([\d.]+)\\linewidth", spec)]
        assert not shares or abs(sum(shares) - 1) < 0.01


@pytest.mark.tex
@needs_pdflatex
def test_foucault_in_french_fits_the_page(tmp_path):
    """The audit's overfull box: the constants' table of Foucault (38 pt too wide with llll)."""
    report(EXAMPLES_DIR / "foucault_pendulum.toml", lang="fr").save(tmp_path / "foucault.tex")
    log = _compile(tmp_path, "foucault")
    widths = [float(x) for x in re.findall(r"Overfull \\hbox \(([\d.]+)pt too wide\)", log)]
    assert all(w < OVERFULL_PT for w in widths), widths
