"""The report as a PDF: its LaTeX compiled by a TeX engine installed on the machine (pdflatex, else lualatex).

The LaTeX of `render_tex` is written with its figures into a private temporary folder and compiled
there with shell escape off (``-no-shell-escape``: the texts of a model file come from strangers and
are escaped by the renderer; nothing they say can run a program), in batch mode, with a time limit.
The engine runs until the document settles (longtable's columns need a second run).  The fonts are the
Latin Modern Type 1 fonts (the TeX package ``lmodern``, which ``make test`` installs), so that the text
is not in bitmap Type 3 fonts.  The PDF's bytes are returned; `Report.save` writes them atomically.  No TeX engine: an `OutputError`
saying how to install one (Debian: ``texlive-latex-base``, ``texlive-latex-recommended``,
``texlive-lang-french``; ``make test`` installs them) or to write ``--format tex`` instead.
"""

from __future__ import annotations

import os
import shutil
import subprocess
import tempfile
from collections.abc import Mapping
from pathlib import Path

from ....errors import OutputError

__all__ = ["ENGINES", "MAX_RUNS", "compile_pdf", "compile_pdf_and_log", "needs_rerun", "tex_engine"]

#: The engines tried, in order: the report's preamble (inputenc, T1 fonts) is written for pdflatex;
#: lualatex compiles it too.
ENGINES = ("pdflatex", "lualatex")
#: Seconds one compilation may take (a 6-link chain's report: about 3 s).
TIME_LIMIT = 300
_INSTALL = ("install TeX Live (Debian: apt-get install texlive-latex-base texlive-latex-recommended "
            "texlive-lang-french), or write the LaTeX with --format tex and compile it elsewhere")


def tex_engine() -> str | None:
    """The path of the first TeX engine of `ENGINES` found on the PATH, or None."""
    return next((p for p in map(shutil.which, ENGINES) if p), None)


#: Most runs of the engine: longtable needs two to settle its column widths ("Table widths have changed.
#: Rerun LaTeX."), and a third when a page break moves a table; beyond, the document does not settle.
MAX_RUNS = 4


def needs_rerun(log: str) -> bool:
    """Whether TeX's log asks for another run (longtable's column widths, labels, references)."""
    return "Rerun LaTeX" in log or "Rerun to get" in log or "Table widths have changed" in log


def compile_pdf(latex: str, figures: Mapping[str, bytes] = {}) -> bytes:
    """The PDF of the LaTeX document ``latex``; ``figures`` are the files it includes, by name."""
    return compile_pdf_and_log(latex, figures)[0]


def compile_pdf_and_log(latex: str, figures: Mapping[str, bytes] = {}) -> tuple[bytes, str, int]:
    """(PDF, the last run's log, number of runs): the engine runs until the document settles (`needs_rerun`),
    `MAX_RUNS` times at most, so that every longtable's header sits on its columns."""
    engine = tex_engine()
    if engine is None:
        raise OutputError("Cannot write a PDF: no TeX engine (pdflatex or lualatex) is installed.", fix=_INSTALL)
    with tempfile.TemporaryDirectory(prefix="lagrangian-pdf-") as folder:
        work = Path(folder)
        (work / "report.tex").write_text(latex, encoding="utf-8")
        for name, data in figures.items():
            (work / Path(name).name).write_bytes(data)
        command = [engine, "-interaction=batchmode", "-halt-on-error", "-no-shell-escape", "report.tex"]
        # TEXMFOUTPUT and openout_any: TeX writes only in its folder; HOME there too (font caches).
        env = {**os.environ, "TEXMFOUTPUT": folder, "openout_any": "p", "HOME": folder}
        pdf, log = work / "report.pdf", ""
        for runs in range(1, MAX_RUNS + 1):  # noqa: B007 (the number of runs is returned after the loop)
            try:
                run = subprocess.run(command, cwd=work, capture_output=True, timeout=TIME_LIMIT, env=env,
                                     stdin=subprocess.DEVNULL, check=False)
            except subprocess.TimeoutExpired:
                raise OutputError(f"Cannot write a PDF: {Path(engine).name} took more than {TIME_LIMIT} s.",
                                  fix="write the LaTeX with --format tex and compile it by hand") from None
            if run.returncode != 0 or not pdf.exists():
                raise OutputError(f"Cannot write a PDF: {Path(engine).name} failed: "
                                  f"{_first_error(work / 'report.log')}",
                                  fix="report this model to the lagrangian developers; --format tex writes the LaTeX "
                                      "to compile by hand (a LaTeX package may be missing: " + _INSTALL + ")")
            log = (work / "report.log").read_text(encoding="utf-8", errors="replace")
            if not needs_rerun(log):
                break
        return pdf.read_bytes(), log, runs


def _first_error(log: Path) -> str:
    """The first error of a TeX log (``! Undefined control sequence.`` and the line after), or a summary."""
    try:
        lines = log.read_text(encoding="utf-8", errors="replace").splitlines()
    except OSError:
        return "no log was written."
    for k, line in enumerate(lines):
        if line.startswith("!"):
            return " ".join(x.strip() for x in lines[k:k + 3])[:300]
    return "see its log (no error line found)."
