"""The report as a LaTeX document that ``pdflatex`` compiles (packages of a basic TeX Live only).

Long equations are ``align*`` blocks that may break across pages (``\\allowdisplaybreaks``);
folded content is printed in full, except the full forms of summarized expressions
(⟨41 termes (voir A.3)⟩), gathered in an appendix at the end; figures are ``\\includegraphics`` of PNG files written
beside the ``.tex`` file (`Report.save`), or a note when there are none.
"""

from __future__ import annotations

import re
from collections.abc import Sequence

from ..document import (
    Block,
    Display,
    Document,
    Equation,
    Fold,
    FullForms,
    Image,
    Items,
    Math,
    Para,
    Runs,
    Scene3D,
    Section,
    Table,
    walk,
)

__all__ = ["render_tex"]

_PREAMBLE = r"""\documentclass[a4paper,11pt]{article}
\usepackage[T1]{fontenc}
\usepackage[utf8]{inputenc}
\IfFileExists{lmodern.sty}{\usepackage{lmodern}}{}
\usepackage{amsmath,amssymb}
\usepackage[margin=2cm]{geometry}
\usepackage{graphicx}
\usepackage{longtable}
\usepackage{array}
\allowdisplaybreaks
\setlength{\parindent}{0pt}
\setlength{\parskip}{0.5em}
"""
#: French: babel's French where it is installed (texlive-lang-french), else French spacing only.
_FRENCH = r"""\IfFileExists{french.ldf}{\usepackage[french]{babel}}{\frenchspacing}
"""
#: A table whose cells hold more characters than this in a row gets wrapping p{} columns.
TABLE_CHARS = 70
#: Narrowest p{} column, in characters (a header word such as « symbole » and the column's padding).
MIN_COLUMN = 12

_ESCAPES = {"\\": r"\textbackslash{}", "&": r"\&", "%": r"\%", "$": r"\$", "#": r"\#", "_": r"\_", "{": r"\{",
            "}": r"\}", "~": r"\textasciitilde{}", "^": r"\^{}"}
# Characters that T1 + utf8 do not know, written as LaTeX (what a model's description may hold).
_UNICODE = {"Σ": r"\ensuremath{\Sigma}", "Ω": r"\ensuremath{\Omega}", "Π": r"\ensuremath{\Pi}", "·": r"\ensuremath{\cdot}",
            "−": r"\ensuremath{-}", "\u00a0": "~", "\u202f": r"\,", "→": r"\ensuremath{\to}", "⇒": r"\ensuremath{\Rightarrow}", "≤": r"\ensuremath{\le}",
            "≥": r"\ensuremath{\ge}", "≈": r"\ensuremath{\approx}", "²": r"\textsuperscript{2}", "³": r"\textsuperscript{3}",
            "½": r"\ensuremath{\tfrac{1}{2}}", "×": r"\ensuremath{\times}", "∂": r"\ensuremath{\partial}",
            "⟨": r"\ensuremath{\langle}", "⟩": r"\ensuremath{\rangle}", "—": "---", "–": "--", "…": r"\dots{}",
            "✓": r"\ensuremath{\checkmark}", "\u0307": "", "\u0308": "",
            **{s: rf"\textsuperscript{{{d}}}" for s, d in zip("⁰¹⁴⁵⁶⁷⁸⁹⁻", "01456789-", strict=True)}}
_GREEK = {"α": "alpha", "β": "beta", "γ": "gamma", "δ": "delta", "ε": "varepsilon", "ζ": "zeta", "η": "eta",
          "θ": "theta", "ι": "iota", "κ": "kappa", "λ": "lambda", "μ": "mu", "ν": "nu", "ξ": "xi", "π": "pi",
          "ρ": "rho", "σ": "sigma", "τ": "tau", "φ": "varphi", "χ": "chi", "ψ": "psi", "ω": "omega",
          "Γ": "Gamma", "Δ": "Delta", "Θ": "Theta", "Λ": "Lambda", "Ξ": "Xi", "Φ": "Phi", "Ψ": "Psi"}
#: Highest code point written as is (Latin-1 and Latin Extended-A, which T1 covers, with the quotes below).
_LATIN = 0x17F
_QUOTES = "‘’“”«»"


def _char(ch: str) -> str:
    if ch in _ESCAPES:
        return _ESCAPES[ch]
    if ch in _UNICODE:
        return _UNICODE[ch]
    if ch in _GREEK:
        return rf"\ensuremath{{\{_GREEK[ch]}}}"
    if ord(ch) <= _LATIN or ch in _QUOTES:
        return ch
    return "?"


def escape(text: str) -> str:
    # French spacing: babel's french puts its own non-breaking space before : ; ! ? (a space typed there is
    # replaced by it); elsewhere a non-breaking space is a tie, the narrow one a thin space.
    text = re.sub("[\u00a0\u202f]([:;!?])", r" \1", text)
    return "".join(_char(ch) for ch in text)


def _runs(runs: Runs) -> str:
    return "".join(rf"\({r.latex}\)" if isinstance(r, Math) else escape(r) for r in runs)


def _columns(t: Table) -> str:
    """``lll`` for a narrow table; p{} columns sharing the line, by their widest cell, for a wide one."""
    rows = (t.header, *t.rows)
    widest = [max(_visible(row[k]) for row in rows if k < len(row)) for k in range(len(t.header))]
    if sum(widest) <= TABLE_CHARS:
        return "l" * len(widest)
    shares = [max(w, MIN_COLUMN) for w in widest]
    total = sum(shares)
    return "".join(rf">{{\raggedright\arraybackslash}}p{{\dimexpr {share / total:.3f}\linewidth - 2\tabcolsep\relax}}"
                   for share in shares)


def _visible(runs: Runs) -> int:
    """About how many characters a cell prints."""
    from ..size import visible_width

    return sum(visible_width(r.latex) if isinstance(r, Math) else len(r) for r in runs)


def _block(b: Block, figures: Sequence[str] | None, counter: list[int]) -> str:
    if isinstance(b, Para):
        text = _runs(b.runs)
        if b.style == "remark":
            return rf"\textit{{{text}}}" + "\n"
        if b.style == "note":
            return rf"{{\small {text}}}" + "\n"
        return text + "\n"
    if isinstance(b, Display):
        return "\n".join(_align(eq) for eq in b.equations) + "\n"
    if isinstance(b, Items):
        return "\\begin{itemize}\n" + "\n".join(rf"\item {_runs(i)}" for i in b.items) + "\n\\end{itemize}\n"
    if isinstance(b, Table):
        cols = _columns(b)
        head = " & ".join(_runs(c) for c in b.header) + r" \\ \hline"
        body = "\n".join(" & ".join(_runs(c) for c in row) + r" \\" for row in b.rows)
        return f"\\begin{{longtable}}{{{cols}}}\n\\hline\n{head}\n\\endhead\n{body}\n\\hline\n\\end{{longtable}}\n"
    if isinstance(b, Fold):
        return "".join(_block(x, figures, counter) for x in b.blocks)
    if isinstance(b, FullForms):
        return ""  # in the appendix (`_appendix`)
    if isinstance(b, (Image, Scene3D)):
        counter[0] += 1
        caption = _runs(b.caption)
        if figures is not None and counter[0] <= len(figures):
            return ("\\begin{figure}[htbp]\\centering\n"
                    rf"\includegraphics[width=\linewidth]{{{figures[counter[0] - 1]}}}" "\n"
                    rf"\par{{\small {caption}}}" "\n\\end{figure}\n")
        return rf"\fbox{{\parbox{{0.9\linewidth}}{{{caption}}}}}" + "\n"
    raise TypeError(f"unknown block {type(b).__name__}")  # pragma: no cover


def _align(eq: Equation) -> str:
    if len(eq.lines) == 1:
        return rf"\[ {eq.lines[0]} \]"
    rows = [f"& {eq.lines[0]}"] + [rf"&\quad {line}" for line in eq.lines[1:]]
    return "\\begin{align*}\n" + " \\\\\n".join(rows) + "\n\\end{align*}"


def _appendix(doc: Document) -> str:
    """The full forms of the summarized expressions, by number (A.1, A.2...), as breakable ``align*`` blocks."""
    from ..words import Words

    found = [b for s in doc.sections for b in walk(s.blocks) if isinstance(b, FullForms)]
    if not found:
        return ""
    out = [rf"\section*{{{escape(Words(doc.lang).text('appendix full'))}}}"]
    for b in found:
        out.append(rf"\subsection*{{{escape(b.title)}}}")
        for ref, eq in b.forms:
            out.append(rf"\textbf{{{escape(ref)}}}" + "\n" + _align(eq))
    return "\n".join(out) + "\n"


def _section(s: Section, figures: Sequence[str] | None, counter: list[int]) -> str:
    return rf"\section*{{{escape(s.title)}}}" + "\n" + "\n".join(_block(b, figures, counter) for b in s.blocks)


def render_tex(doc: Document, *, footer: str = "", figures: Sequence[str] | None = None) -> str:
    """A standalone LaTeX document; ``figures`` are the file names of the report's images, in order."""
    counter = [0]
    parts = [_PREAMBLE + (_FRENCH if doc.lang == "fr" else ""), r"\begin{document}", rf"\begin{{center}}{{\LARGE {escape(doc.title)}}}\end{{center}}"]
    if doc.subtitle:
        parts.append(rf"\begin{{center}}\textit{{{escape(doc.subtitle)}}}\end{{center}}")
    parts += [_section(s, figures, counter) for s in doc.sections]
    appendix = _appendix(doc)
    if appendix:
        parts.append(appendix)
    if footer:
        parts.append(rf"\vfill{{\footnotesize {escape(footer)}}}")
    parts.append(r"\end{document}")
    return "\n".join(parts) + "\n"
