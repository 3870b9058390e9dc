"""The report as one self-contained HTML page: MathML from LaTeX (latex2mathml), images as data: URIs.

Nothing is fetched: no script, no web font, no CDN.  MathML is rendered natively by current
browsers (MathML Core: Chromium 109+, Firefox, Safari), so the page reads offline.
"""

from __future__ import annotations

import base64
import functools
import html
import re

from latex2mathml.converter import convert

from ....errors import OutputError
from ..document import (
    Block,
    Display,
    Document,
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

__all__ = ["render_html"]

_CSS = """
.lagrangian-report { font-family: "Latin Modern Roman", "Cambria", "Georgia", serif; line-height: 1.5;
  max-width: 58em; margin: 0 auto; padding: 1em 1.5em; color: #1d1d1f; background: #fff; }
.lagrangian-report math { font-family: "DejaVu Math TeX Gyre", "STIX Two Math", "Latin Modern Math", "Cambria Math",
  "TeX Gyre Termes Math", "Libertinus Math", math; font-size: 1.05em; }
.lagrangian-report h1 { font-size: 1.7em; margin-bottom: 0.2em; }
.lagrangian-report .subtitle { font-style: italic; margin-top: 0; color: #444; }
.lagrangian-report h2 { font-size: 1.3em; border-bottom: 1px solid #ccc; margin-top: 1.6em; padding-bottom: 0.2em; }
.lagrangian-report nav ul { columns: 2; column-gap: 2.5em; font-size: 0.95em; list-style: none; padding-left: 0; }
.lagrangian-report nav li { break-inside: avoid; margin: 0.2em 0; }
.lagrangian-report .display { margin: 0.6em 0 0.8em 1.5em; overflow-x: auto; }
.lagrangian-report .eq { margin: 0.35em 0; }
.lagrangian-report .eq math[display="block"] { margin: 0.15em 0; }
.lagrangian-report .eq.multi { display: flex; flex-direction: column; align-items: center; }
.lagrangian-report .eq.multi > div { width: 100%; max-width: 50em; }
.lagrangian-report .eq.multi math[display="block"] { width: fit-content; margin-left: 0; }
.lagrangian-report .eq.multi .cont math[display="block"] { margin-left: 3em; }
.lagrangian-report .remark { font-style: italic; }
.lagrangian-report .note { color: #555; font-size: 0.95em; }
.lagrangian-report table { border-collapse: collapse; margin: 0.5em 0 1em 0; }
.lagrangian-report th, .lagrangian-report td { border: 1px solid #ccc; padding: 0.2em 0.6em; text-align: left; }
.lagrangian-report details { margin: 0.4em 0 0.8em 0; }
.lagrangian-report summary { cursor: pointer; color: #1a4f8b; }
.lagrangian-report .full-form .ref { margin: 0.5em 0 0 0; font-weight: bold; }
.lagrangian-report .full-form .display { margin: 0.2em 0 0.6em 0.5em; }
.lagrangian-report .full-form .eq.multi .cont math[display="block"] { margin-left: 1.5em; }
.lagrangian-report figure { margin: 1em 0; }
.lagrangian-report figure img { max-width: 100%; }
.lagrangian-report figcaption { font-size: 0.95em; color: #333; }
.lagrangian-report footer { margin-top: 2em; font-size: 0.85em; color: #777; }
.lagrangian-report mover.vec > mo { color: transparent; }
.lagrangian-report mover.vec { background: __HEAD__ right 0.06em top 0.05em / 0.34em 0.32em no-repeat,
  linear-gradient(#1d1d1f, #1d1d1f) left 0.04em top 0.185em / calc(100% - 0.2em) 0.05em no-repeat; }
"""

#: The head of a vector's arrow (``.vec``): a filled, notched triangle, drawn at the arrow's right end.
_ARROW_HEAD = ("url(\"data:image/svg+xml,%3Csvg xmlns='http://www.w3.org/2000/svg' viewBox='0 0 10 10' "
               "preserveAspectRatio='none'%3E%3Cpath d='M0 0L10 5L0 10L2.5 5Z' fill='%231d1d1f'/%3E%3C/svg%3E\")")
_CSS = _CSS.replace("__HEAD__", _ARROW_HEAD)


@functools.lru_cache(maxsize=4096)
def _mathml(latex: str, display: str) -> str:
    try:
        out = convert(_spaced(_arrows(latex)), display=display)
    except Exception as exc:  # noqa: BLE001 - latex2mathml raises assorted errors on input it does not know
        raise OutputError(f"Cannot convert `{latex[:120]}` to MathML: {exc}.",
                          fix="report this model to the lagrangian developers; --format tex or md still works") from None
    return _function_spacing(_stretchy(out.replace(' xmlns="http://www.w3.org/1998/Math/MathML"', "", 1)))


def _braced(s: str, i: int) -> int:
    """Index after the braced group that opens at ``s[i]`` (``len(s)`` when it is not closed)."""
    depth = 0
    for j in range(i, len(s)):
        if s[j] == "{" and s[j - 1] != "\\":
            depth += 1
        elif s[j] == "}" and s[j - 1] != "\\":
            depth -= 1
            if depth == 0:
                return j + 1
    return len(s)


def _arrows(latex: str) -> str:
    r"""``\xrightarrow{ψ, Oz0}`` → ``\overset{\;ψ, Oz0\;}{\longrightarrow}``.

    latex2mathml writes ``\xrightarrow`` with an ``<mpadded>`` of negative height and offset,
    which Chromium draws over the arrow and the next frame; an arrow under its label
    (`_stretchy` makes it stretch to the label's width) is what LaTeX draws.
    """
    out, start = [], 0
    while (i := latex.find(r"\xrightarrow{", start)) >= 0:
        open_at = i + len(r"\xrightarrow")
        end = _braced(latex, open_at)
        out.append(latex[start:i] + rf"\overset{{\;{latex[open_at + 1:end - 1]}\;}}{{\longrightarrow}}")
        start = end
    return "".join(out) + latex[start:]


#: The long arrow latex2mathml writes as an ``<mi>`` base of ``\\overset``.
_OVERSET_ARROW = "<mover><mrow><mi>&#x027F6;</mi></mrow>"
#: An arrow over letters (``\\overrightarrow{OG}``): its base and the arrow.
_OVER_ARROW = re.compile(r"<mover><mrow>((?:(?!</?mover>).)*?)</mrow><mo>(&#x02192;|&#x02190;|&#x02194;)</mo></mover>")
_DIGITS = re.compile(r"<mn>([^<]*)</mn>")


def _over_arrow(m: re.Match[str]) -> str:
    """The arrow over ``OG`` as wide as ``OG``, with its head: a vector, not an overline (a mesure algébrique).

    Chromium stretches an operator over its base only with an OpenType MATH font that has a horizontal
    construction for it, which most machines lack; a scaled glyph has its head scaled into a line.  So
    the arrow over two symbols or more is drawn by the style sheet (``mover.vec``): a line across the whole
    base and a head of fixed size at its right end.  The ``<mo>`` stays, transparent, for copying and
    screen readers.
    """
    inner, arrow = m.group(1), m.group(2)
    symbols = inner.count("<mi>") + inner.count("<mi ") + sum(len(d) for d in _DIGITS.findall(inner))
    if symbols >= 2 and arrow == "&#x02192;":
        return f'<mover class="vec"><mrow>{inner}</mrow><mo stretchy="false">{arrow}</mo></mover>'
    return f"<mover><mrow>{inner}</mrow><mo>{arrow}</mo></mover>"


def _stretchy(mathml: str) -> str:
    r"""The arrow of ``\overset{label}{\longrightarrow}`` as an operator, and the arrow above ``\overrightarrow{OG}``
    as wide as ``OG``."""
    mathml = mathml.replace(_OVERSET_ARROW, '<mover><mo stretchy="true">&#x027F6;</mo>')
    return _OVER_ARROW.sub(_over_arrow, mathml)


#: A function name (``sin``, or ``sin²``) and what follows it when that is not a bracket, an operator or a space.
_FUNCTION_THEN_ARGUMENT = re.compile(r"(<mi>(?:sin|cos|tan|sinh|cosh|tanh|exp|log|arcsin|arccos|arctan)</mi>"
                                     r"|<msup><mi>(?:sin|cos|tan|sinh|cosh|tanh)</mi><mrow><mn>\d+</mn></mrow></msup>)"
                                     r"(?!<mo[ >]|<mrow><mo[ >]|<mrow><mrow><mo[ >]|<mspace|</mrow>|</math>)")
#: The solidus of ``S/R0`` (S relative to R0) and of a/b inline.
_SOLIDUS = "<mo>&#x0002F;</mo>"


def _function_spacing(mathml: str) -> str:
    """``sin θ`` and ``S/R0`` as LaTeX sets them: a thin space between a function's name and its argument
    (LaTeX's \\mathop; latex2mathml writes two bare ``<mi>``, set touching), and none around the solidus
    (an ordinary symbol in LaTeX, an infix operator with spaces in the MathML operator dictionary)."""
    mathml = _FUNCTION_THEN_ARGUMENT.sub(r'\1<mspace width="0.167em"></mspace>', mathml)
    return mathml.replace(_SOLIDUS, '<mo lspace="0em" rspace="0em">&#x0002F;</mo>')


#: Function names that LaTeX spaces from the factor before them (\\mathop) and latex2mathml does not.
_FUNCTION_AFTER_FACTOR = re.compile(r"([A-Za-z0-9}\)\]])\s+\\(sin|cos|tan|sinh|cosh|tanh|exp|log|arcsin|arccos|arctan)"
                                    r"(?![A-Za-z])")


def _spaced(latex: str) -> str:
    """``a \\sin\\theta`` → ``a\\,\\sin\\theta``: the thin space LaTeX puts before an operator name."""
    return _FUNCTION_AFTER_FACTOR.sub(r"\1\\,\\\2", latex)


def _runs(runs: Runs) -> str:
    return "".join(_mathml(r.latex, "inline") if isinstance(r, Math) else html.escape(r) for r in runs)


def _block(b: Block, scenes: list[int] | None = None) -> str:
    if isinstance(b, Para):
        cls = f' class="{b.style}"' if b.style else ""
        return f"<p{cls}>{_runs(b.runs)}</p>"
    if isinstance(b, Display):
        eqs = []
        for eq in b.equations:
            lines = "".join(f'<div class="{"cont" if k else "first"}">{_mathml(line, "block")}</div>'
                            for k, line in enumerate(eq.lines))
            eqs.append(f'<div class="eq{" multi" if len(eq.lines) > 1 else ""}">{lines}</div>')
        return f'<div class="display">{"".join(eqs)}</div>'
    if isinstance(b, Items):
        return "<ul>" + "".join(f"<li>{_runs(item)}</li>" for item in b.items) + "</ul>"
    if isinstance(b, Table):
        head = "".join(f"<th>{_runs(cell)}</th>" for cell in b.header)
        body = "".join("<tr>" + "".join(f"<td>{_runs(cell)}</td>" for cell in row) + "</tr>" for row in b.rows)
        return f"<table><thead><tr>{head}</tr></thead><tbody>{body}</tbody></table>"
    if isinstance(b, Fold):
        inner = "".join(_block(x, scenes) for x in b.blocks)
        return f"<details><summary>{html.escape(b.summary)}</summary>{inner}</details>"
    if isinstance(b, FullForms):
        forms = "".join(f'<div class="full-form"><p class="ref">{html.escape(ref)}</p>{_block(Display((eq,)))}</div>'
                        for ref, eq in b.forms)
        return f'<details class="full"><summary>{html.escape(b.summary)}</summary>{forms}</details>'
    if isinstance(b, Image):
        data = base64.b64encode(b.png).decode("ascii")
        return (f'<figure><img src="data:image/png;base64,{data}" alt="{html.escape(b.alt, quote=True)}">'
                f"<figcaption>{_runs(b.caption)}</figcaption></figure>")
    if isinstance(b, Scene3D):
        return _scene(b, scenes)
    raise TypeError(f"unknown block {type(b).__name__}")  # pragma: no cover


def _scene(b: Scene3D, scenes: list[int] | None) -> str:
    """A 3-D figure: in a page, the viewer's element and data (the library once, at the end of the page); in a
    notebook (``scenes`` None), the view's own page in an iframe, which needs no script of the notebook's."""
    from ....view3d import View
    from ....view3d.html import fragment

    caption = f'<figcaption>{_runs(b.caption)}</figcaption>'
    if scenes is None:
        return f'<figure class="scene3d">{View(b.scene)._repr_html_()}{caption}</figure>'
    scenes.append(len(scenes) + 1)
    inner = fragment(b.scene, ident=f"lgv-{len(scenes)}", height="460px")
    return inner.replace("</figure>", caption + "</figure>", 1)


def _section(s: Section, scenes: list[int] | None) -> str:
    return (f'<section id="{s.key}"><h2>{html.escape(s.title)}</h2>' + "".join(_block(b, scenes) for b in s.blocks)
            + "</section>")


def _body(doc: Document, footer: str, scenes: list[int] | None = None) -> str:
    # A list without numbers: the titles carry the course's own ("1. Choix des liaisons principales").
    toc = "".join(f'<li><a href="#{s.key}">{html.escape(s.title)}</a></li>' for s in doc.sections)
    subtitle = f'<p class="subtitle">{html.escape(doc.subtitle)}</p>' if doc.subtitle else ""
    return (f'<div class="lagrangian-report"><h1>{html.escape(doc.title)}</h1>{subtitle}'
            f"<nav><ul>{toc}</ul></nav>" + "".join(_section(s, scenes) for s in doc.sections)
            + f"<footer>{html.escape(footer)}</footer></div>")


def render_html(doc: Document, *, footer: str = "", fragment: bool = False) -> str:
    """The report as a complete HTML page, or (``fragment=True``) as a ``<div>`` with its style for a notebook.

    A page with 3-D figures holds the viewer (three.js) once, at its end, and a Content-Security-Policy
    that lets it load nothing but its own inline code, styles and images."""
    if fragment:
        return f"<style>{_CSS}</style>{_body(doc, footer)}"
    scenes: list[int] = []
    body = _body(doc, footer, scenes)
    head, tail = "", ""
    if scenes:
        from ....view3d.html import CSP, library

        head = f'<meta http-equiv="Content-Security-Policy" content="{CSP}">'
        tail = f"<script>\n{library()}\n</script>"
    return ("<!DOCTYPE html>\n"
            f'<html lang="{doc.lang}"><head><meta charset="utf-8">{head}'
            '<meta name="viewport" content="width=device-width, initial-scale=1">'
            f"<title>{html.escape(doc.title)}</title><style>{_CSS}</style></head>"
            f"<body>{body}{tail}</body></html>\n")
