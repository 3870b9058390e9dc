r"""The report in Markdown with GitHub's and GitLab's math syntax: inline ``$`...`$``, displayed ```` ```math ````.

``$...$`` would go through the Markdown parser first, which eats the backslash of ``\,``,
``\;``, ``\|``, ``\ `` and ``\\``; the code-span forms reach the math renderer untouched
(GitHub, GitLab; Pandoc reads ``$`...`$`` as code).  A long equation is one ``aligned``
block; folded content is a ``<details>`` element, which those sites render; images are
files beside the ``.md`` (``figures``), referred to by relative paths, else data: URIs.
"""

from __future__ import annotations

import base64
import re
from collections.abc import Sequence
from urllib.parse import quote

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
)

__all__ = ["render_markdown", "display_math", "fenced_math", "inline_math"]

_SPECIAL = re.compile(r"([\\`*_{}\[\]<>#|$])")


def _text(s: str) -> str:
    return _SPECIAL.sub(r"\\\1", s)


def inline_math(latex: str, in_table: bool = False) -> str:
    """``$`latex`$``: a code span, so no Markdown escape touches the LaTeX (``|`` escaped in a table cell)."""
    body = latex.strip()
    if in_table:
        body = body.replace("|", "\\|")
    return f"$`{body}`$"


def _runs(runs: Runs, in_table: bool = False) -> str:
    return "".join(inline_math(r.latex, in_table) if isinstance(r, Math) else _text(r) for r in runs)


def _aligned(eq: Equation) -> str:
    if len(eq.lines) == 1:
        return eq.lines[0]
    lines = [f"& {eq.lines[0]}"] + [rf"& \quad {line}" for line in eq.lines[1:]]
    return "\\begin{aligned}\n" + " \\\\\n".join(lines) + "\n\\end{aligned}"


def fenced_math(eq: Equation) -> str:
    """One displayed equation as a ```` ```math ```` block (several lines: an ``aligned`` block)."""
    return f"```math\n{_aligned(eq)}\n```"


#: Most lines of one ```` ```math ```` block of a full form (a longer one is cut into several: the sites'
#: math renderers refuse very large expressions).
CHUNK_LINES = 24


def _chunks(eq: Equation) -> list[tuple[str, ...]]:
    """A long equation's lines in blocks of at most `CHUNK_LINES` (each further block continues the sum)."""
    return [eq.lines[k:k + CHUNK_LINES] for k in range(0, len(eq.lines), CHUNK_LINES)]


def display_math(eq: Equation) -> str:
    """One displayed equation between ``$$`` (what Jupyter's LaTeX display reads)."""
    return f"$$\n{_aligned(eq)}\n$$"


def _block(b: Block, figures: Sequence[str] | None = None, counter: list[int] | None = None) -> str:
    counter = counter if counter is not None else [0]
    if isinstance(b, Para):
        text = _runs(b.runs)
        return f"*{text}*" if b.style == "remark" and "*" not in text else text
    if isinstance(b, Display):
        return "\n\n".join(fenced_math(eq) for eq in b.equations)
    if isinstance(b, Items):
        return "\n".join(f"- {_runs(item)}" for item in b.items)
    if isinstance(b, Table):
        def row(cells: tuple[Runs, ...]) -> str:
            return "| " + " | ".join(_runs(cell, in_table=True).replace("\n", " ") for cell in cells) + " |"
        return "\n".join([row(b.header), "|" + "---|" * len(b.header)] + [row(r) for r in b.rows])
    if isinstance(b, Fold):
        inner = "\n\n".join(_block(x, figures, counter) for x in b.blocks if not isinstance(x, Scene3D))
        summary = b.summary.replace("<", "&lt;").replace(">", "&gt;")
        return f"<details><summary>{summary}</summary>\n\n{inner}\n\n</details>"
    if isinstance(b, FullForms):
        forms = "\n\n".join(f"**{ref}**\n\n" + "\n\n".join(fenced_math(Equation(part)) for part in _chunks(eq))
                            for ref, eq in b.forms)
        summary = b.summary.replace("<", "&lt;").replace(">", "&gt;")
        return f"<details><summary>{summary}</summary>\n\n{forms}\n\n</details>"
    if isinstance(b, Image):
        counter[0] += 1
        if figures is not None and counter[0] <= len(figures):
            target = quote(figures[counter[0] - 1])
        else:
            target = "data:image/png;base64," + base64.b64encode(b.png).decode("ascii")
        return f"![{_text(b.alt)}]({target})\n\n{_runs(b.caption)}"
    raise TypeError(f"unknown block {type(b).__name__}")  # pragma: no cover


def _section(s: Section, figures: Sequence[str] | None, counter: list[int]) -> str:
    # A 3-D figure has no Markdown form (its still would be a large data: URI): left out, as GitHub shows no page.
    return f"## {s.title}\n\n" + "\n\n".join(_block(b, figures, counter) for b in s.blocks
                                                 if not isinstance(b, Scene3D))


def render_markdown(doc: Document, *, footer: str = "", figures: Sequence[str] | None = None) -> str:
    """The report as Markdown text; ``figures`` are the relative paths of its images' PNG files, in order."""
    counter = [0]
    parts = [f"# {_text(doc.title)}"]
    if doc.subtitle:
        parts.append(f"*{_text(doc.subtitle)}*")
    parts += [_section(s, figures, counter) for s in doc.sections]
    if footer:
        parts.append(f"---\n\n{_text(footer)}")
    return "\n\n".join(parts) + "\n"
