"""``lagrangian report --format pdf``: the LaTeX report compiled by a real TeX engine, written atomically.

Compiled where pdflatex (or lualatex) is installed (``make test`` installs Debian's TeX Live as root) and
read back with pdftotext and pdfinfo (poppler-utils); skipped, with the reason, elsewhere.  The refusals
(no engine, a failing engine, no file to write to) are checked everywhere.
"""

from __future__ import annotations

import os
import shutil
import stat
import subprocess

import pytest
from lagrangian_test_support import EXAMPLES_DIR

from lagrangian.cli.main import main
from lagrangian.errors import OutputError
from lagrangian.output import report
from lagrangian.output._report.render import pdf as _report_pdf

needs_tex = pytest.mark.skipif(_report_pdf.tex_engine() is None or shutil.which("pdftotext") is None
                               or shutil.which("pdfinfo") is None,
                               reason="no pdflatex/lualatex or poppler-utils here (`make test` installs them as root)")


@pytest.mark.tex
@needs_tex
def test_pdf_of_the_double_pendulum_in_french(tmp_path):
    out = tmp_path / "pendule.pdf"
    assert main(["report", str(EXAMPLES_DIR / "double_pendulum.toml"), "--lang", "fr", "-o", str(out)]) == 0
    data = out.read_bytes()
    assert data.startswith(b"%PDF-") and data.rstrip().endswith(b"%%EOF")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["pendule.pdf"]  # no .aux, .log or temporary left
    pages = int(next(line.split()[-1] for line in subprocess.run(["pdfinfo", str(out)], capture_output=True,
                     text=True, check=True).stdout.splitlines() if line.startswith("Pages:")))
    assert 3 <= pages <= 20, pages
    text = subprocess.run(["pdftotext", "-layout", str(out), "-"], capture_output=True, text=True, check=True).stdout
    # The title, the steps of the démarche and the model's French texts, in order.
    order = [text.find(s) for s in ("Pendule double", "masse de la tige (S1)", "1. Choix des liaisons principales",
                                    "2. Paramètres principaux", "6. Équations de Lagrange", "Annexe")]
    assert -1 not in order and order == sorted(order), order
    assert "mass of rod" not in text


@pytest.mark.tex
@needs_tex
def test_a_failed_pdf_leaves_the_old_file(tmp_path, monkeypatch):
    """An engine that fails: an OutputError with the engine's first error, and the old PDF unchanged."""
    fake = tmp_path / "bin" / "pdflatex"
    fake.parent.mkdir()
    fake.write_text("#!/bin/sh\necho '! Undefined control sequence.' > report.log\necho 'l.7 \\\\oops' >> report.log\n"
                    "exit 1\n")
    fake.chmod(fake.stat().st_mode | stat.S_IXUSR)
    monkeypatch.setenv("PATH", f"{fake.parent}{os.pathsep}{os.environ['PATH']}")
    out = tmp_path / "old.pdf"
    out.write_bytes(b"%PDF-old")
    r = report(EXAMPLES_DIR / "simple_pendulum.toml", lang="en")
    with pytest.raises(OutputError) as info:
        r.save(out)
    assert "Undefined control sequence" in str(info.value) and info.value.fix
    assert out.read_bytes() == b"%PDF-old"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["bin", "old.pdf"]


@pytest.mark.slow
def test_no_engine_says_how_to_install_one(tmp_path, monkeypatch):
    monkeypatch.setattr(_report_pdf, "ENGINES", ("no-such-tex-engine",))
    with pytest.raises(OutputError) as info:
        report(EXAMPLES_DIR / "simple_pendulum.toml", lang="en").save(tmp_path / "x.pdf")
    assert "no TeX engine" in str(info.value) and "texlive-latex-base" in info.value.fix
    assert not (tmp_path / "x.pdf").exists()


def test_a_pdf_goes_to_a_file_not_the_terminal(capsys):
    assert main(["report", str(EXAMPLES_DIR / "simple_pendulum.toml"), "--format", "pdf"]) != 0
    assert "-o report.pdf" in capsys.readouterr().err


needs_fonts = pytest.mark.skipif(_report_pdf.tex_engine() is None or shutil.which("pdffonts") is None
                                 or shutil.which("kpsewhich") is None
                                 or subprocess.run(["kpsewhich", "lmodern.sty"], capture_output=True,
                                                   check=False).returncode != 0,
                                 reason="no TeX engine, pdffonts or the lmodern package here (`make test` installs them)")


@pytest.mark.tex
@needs_fonts
def test_pdf_text_is_in_vector_fonts_and_the_tables_have_settled(tmp_path):
    """Every font of the PDF is Type 1 (Latin Modern), none a bitmap Type 3; the engine ran until longtable's
    column widths settled (its log no longer asks for a rerun), which takes a second run for a report's tables."""
    latex = report(EXAMPLES_DIR / "rolling_coin.toml", lang="fr").latex()
    assert r"\begin{longtable}" in latex
    data, log, runs = _report_pdf.compile_pdf_and_log(latex)
    assert runs >= 2 and not _report_pdf.needs_rerun(log)  # one run leaves "Table widths have changed"
    out = tmp_path / "coin.pdf"
    out.write_bytes(data)
    fonts = subprocess.run(["pdffonts", str(out)], capture_output=True, text=True, check=True).stdout.splitlines()[2:]
    kinds = {line.split()[1] if line.split()[1] != "Type" else " ".join(line.split()[1:3]) for line in fonts}
    assert fonts and "Type 3" not in kinds, fonts
    assert any("LMRoman" in line for line in fonts), fonts
    text = subprocess.run(["pdftotext", str(out), "-"], capture_output=True, text=True, check=True).stdout
    assert "Pièce roulant debout" in text and "d’une énergie potentielle" in text  # text, with its apostrophes


def test_rerun_is_asked_by_longtable_and_references_only():
    assert _report_pdf.needs_rerun("Package longtable Warning: Table widths have changed. Rerun LaTeX.")
    assert _report_pdf.needs_rerun("LaTeX Warning: Label(s) may have changed. Rerun to get cross-references right.")
    assert not _report_pdf.needs_rerun("Output written on report.pdf (4 pages, 120000 bytes).")
