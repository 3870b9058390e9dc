"""The report in Markdown with ``$...$`` and ``$$...$$`` mathematics (GitHub, GitLab, Jupyter, Pandoc).

A long equation is one ``aligned`` block; folded content is a ``<details>`` element, which
those sites render; images are data: URIs.
"""

from __future__ import annotations

import base64
import re

from ._report_doc import Block, Display, Document, Equation, Fold, Image, Items, Math, Para, Runs, Section, Table

__all__ = ["render_markdown", "display_math"]

_SPECIAL = re.compile(r"([\\`*_{}\[\]<>#|$])")


def _text(s: str) -> str:
    return _SPECIAL.sub(r"\\\1", s)


def _runs(runs: Runs) -> str:
    return "".join(f"${r.latex.strip()}$" if isinstance(r, Math) else _text(r) for r in runs)


def display_math(eq: Equation) -> str:
    """One displayed equation between ``$$`` (several lines: an ``aligned`` block)."""
    if len(eq.lines) == 1:
        return f"$$\n{eq.lines[0]}\n$$"
    lines = [f"& {eq.lines[0]}"] + [rf"& \quad {line}" for line in eq.lines[1:]]
    return "$$\n\\begin{aligned}\n" + " \\\\\n".join(lines) + "\n\\end{aligned}\n$$"


def _block(b: Block) -> str:
    if isinstance(b, Para):
        text = _runs(b.runs)
        return f"*{text}*" if b.style == "remark" and "*" not in text else text
    if isinstance(b, Display):
        return "\n\n".join(display_math(eq) for eq in b.equations)
    if isinstance(b, Items):
        return "\n".join(f"- {_runs(item)}" for item in b.items)
    if isinstance(b, Table):
        def row(cells: tuple[Runs, ...]) -> str:
            return "| " + " | ".join(_runs(cell).replace("\n", " ") for cell in cells) + " |"
        return "\n".join([row(b.header), "|" + "---|" * len(b.header)] + [row(r) for r in b.rows])
    if isinstance(b, Fold):
        inner = "\n\n".join(_block(x) for x in b.blocks)
        summary = b.summary.replace("<", "&lt;").replace(">", "&gt;")
        return f"<details><summary>{summary}</summary>\n\n{inner}\n\n</details>"
    if isinstance(b, Image):
        data = base64.b64encode(b.png).decode("ascii")
        return f"![{_text(b.alt)}](data:image/png;base64,{data})\n\n{_runs(b.caption)}"
    raise TypeError(f"unknown block {type(b).__name__}")  # pragma: no cover


def _section(s: Section) -> str:
    return f"## {s.title}\n\n" + "\n\n".join(_block(b) for b in s.blocks)


def render_markdown(doc: Document, *, footer: str = "") -> str:
    """The report as Markdown text."""
    parts = [f"# {_text(doc.title)}"]
    if doc.subtitle:
        parts.append(f"*{_text(doc.subtitle)}*")
    parts += [_section(s) for s in doc.sections]
    if footer:
        parts.append(f"---\n\n{_text(footer)}")
    return "\n\n".join(parts) + "\n"
