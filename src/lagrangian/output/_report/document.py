"""The report as a document: sections of paragraphs, equations, lists, tables, folds and images.

The report's content is built once, in one language, as these frozen values (math as
LaTeX strings written by `Notation`); the HTML, LaTeX and Markdown renderers only lay
them out.  So the three formats always say the same thing, and tests can read the
content without parsing any output.
"""

from __future__ import annotations

import re
from collections.abc import Callable, Iterator
from dataclasses import dataclass, field
from typing import Any

__all__ = ["Math", "Run", "Runs", "Para", "Equation", "Display", "Items", "Table", "Fold", "FullForms", "Image",
           "Scene3D", "Block", "Section", "Document", "walk", "math_of", "map_math", "map_text", "pictures",
           "french_typography"]


@dataclass(frozen=True, slots=True)
class Math:
    """A piece of mathematics, in LaTeX (``\\dot{\\theta}``); inline in a paragraph."""

    latex: str


#: A paragraph is a sequence of runs: plain text and inline mathematics.
Run = str | Math
Runs = tuple[Run, ...]


@dataclass(frozen=True, slots=True)
class Para:
    """A paragraph; ``style`` is ``""``, ``"remark"`` (Remarque 1, 2...) or ``"note"``."""

    runs: Runs
    style: str = ""


@dataclass(frozen=True, slots=True)
class Equation:
    """One displayed equation, written on one line or, when long, on several.

    ``lines[0]`` holds the left-hand side and the start of the right-hand side; each
    further line continues it (it starts with ``+``, ``-`` or ``=``).
    """

    lines: tuple[str, ...]


@dataclass(frozen=True, slots=True)
class Display:
    """Equations displayed one under the other."""

    equations: tuple[Equation, ...]


@dataclass(frozen=True, slots=True)
class Items:
    """A bulleted list."""

    items: tuple[Runs, ...]


@dataclass(frozen=True, slots=True)
class Table:
    """A table with a header row; every cell is a sequence of runs."""

    header: tuple[Runs, ...]
    rows: tuple[tuple[Runs, ...], ...]


@dataclass(frozen=True, slots=True)
class Fold:
    """Content shown on demand (``<details>`` in HTML and Markdown; printed in full in LaTeX)."""

    summary: str
    blocks: tuple[Block, ...]


@dataclass(frozen=True, slots=True)
class FullForms:
    """Expressions summarized above as ⟨41 terms (see A.3)⟩, written in full: ``forms`` are (``"A.3"``, equation).

    Folded under their equation in HTML and Markdown (``summary`` is the fold's label); gathered in an
    appendix in LaTeX under ``title``, where the summaries refer to them by number.
    """

    title: str
    summary: str
    forms: tuple[tuple[str, Equation], ...]


@dataclass(frozen=True, slots=True)
class Image:
    """A PNG image with its caption."""

    png: bytes
    caption: Runs
    alt: str


@dataclass(frozen=True)
class Scene3D:
    """A 3-D figure: the scene of `lagrangian.view3d`, drawn by the page (HTML) or as a still picture (LaTeX, PDF).

    ``png`` is made on first use (headless Chromium's screenshot of the page, else matplotlib's
    drawing of the same scene: `lagrangian.view3d._still`) and kept.
    """

    scene: Any
    caption: Runs
    alt: str
    _still: dict = field(default_factory=dict, compare=False, repr=False)

    @property
    def png(self) -> bytes:
        if "png" not in self._still:
            from ...view3d import still_png

            self._still["png"] = still_png(self.scene, width=900, height=600)
        return self._still["png"]


Block = Para | Display | Items | Table | Fold | FullForms | Image | Scene3D


@dataclass(frozen=True, slots=True)
class Section:
    """A numbered step of the démarche (``key`` ``"step1"``...) or another part of the report."""

    key: str
    title: str
    blocks: tuple[Block, ...]


@dataclass(frozen=True, slots=True)
class Document:
    """The whole report: ``lang`` is ``"fr"`` or ``"en"``."""

    lang: str
    title: str
    subtitle: str
    sections: tuple[Section, ...]

    def section(self, key: str) -> Section:
        for s in self.sections:
            if s.key == key:
                return s
        raise KeyError(key)


def walk(blocks: tuple[Block, ...]) -> Iterator[Block]:
    """Every block, the contents of folds included, in order."""
    for b in blocks:
        yield b
        if isinstance(b, Fold):
            yield from walk(b.blocks)


def math_of(blocks: tuple[Block, ...]) -> list[str]:
    """The LaTeX of every piece of mathematics in ``blocks`` (inline and displayed, folds included)."""
    out: list[str] = []

    def runs(rs: Runs) -> None:
        out.extend(r.latex for r in rs if isinstance(r, Math))

    for b in walk(blocks):
        if isinstance(b, Para):
            runs(b.runs)
        elif isinstance(b, Display):
            for eq in b.equations:
                out.extend(eq.lines)
        elif isinstance(b, FullForms):
            for _, eq in b.forms:
                out.extend(eq.lines)
        elif isinstance(b, Items):
            for item in b.items:
                runs(item)
        elif isinstance(b, Table):
            for row in (b.header, *b.rows):
                for cell in row:
                    runs(cell)
        elif isinstance(b, (Image, Scene3D)):
            runs(b.caption)
    return out


def pictures(doc: Document, *, scenes: bool = True) -> list[Image | Scene3D]:
    """The figures of ``doc`` in order: images and (with ``scenes``) 3-D figures, whose ``png`` each has."""
    kinds = (Image, Scene3D) if scenes else (Image,)
    return [b for s in doc.sections for b in walk(s.blocks) if isinstance(b, kinds)]


def map_math(section: Section, fn: Callable[[str], str]) -> Section:
    """``section`` with ``fn`` applied to the LaTeX of every piece of mathematics (folds and tables included)."""

    def runs(rs: Runs) -> Runs:
        return tuple(Math(fn(r.latex)) if isinstance(r, Math) else r for r in rs)

    def eq(e: Equation) -> Equation:
        return Equation(tuple(fn(line) for line in e.lines))

    def block(b: Block) -> Block:
        if isinstance(b, Para):
            return Para(runs(b.runs), b.style)
        if isinstance(b, Display):
            return Display(tuple(eq(e) for e in b.equations))
        if isinstance(b, Items):
            return Items(tuple(runs(i) for i in b.items))
        if isinstance(b, Table):
            return Table(tuple(runs(c) for c in b.header), tuple(tuple(runs(c) for c in row) for row in b.rows))
        if isinstance(b, Fold):
            return Fold(b.summary, tuple(block(x) for x in b.blocks))
        if isinstance(b, FullForms):
            return FullForms(b.title, b.summary, tuple((ref, eq(e)) for ref, e in b.forms))
        if isinstance(b, Image):
            return Image(b.png, runs(b.caption), b.alt)
        if isinstance(b, Scene3D):
            return Scene3D(b.scene, runs(b.caption), b.alt, b._still)
        raise TypeError(f"unknown block {type(b).__name__}")  # pragma: no cover

    return Section(section.key, section.title, tuple(block(b) for b in section.blocks))


def map_text(section: Section, fn: Callable[[str], str]) -> Section:
    """``section`` with ``fn`` applied to every piece of text (titles, paragraphs, cells, fold summaries, captions),
    never to mathematics."""

    def runs(rs: Runs) -> Runs:
        return tuple(r if isinstance(r, Math) else fn(r) for r in rs)

    def block(b: Block) -> Block:
        if isinstance(b, Para):
            return Para(runs(b.runs), b.style)
        if isinstance(b, Items):
            return Items(tuple(runs(i) for i in b.items))
        if isinstance(b, Table):
            return Table(tuple(runs(c) for c in b.header), tuple(tuple(runs(c) for c in row) for row in b.rows))
        if isinstance(b, Fold):
            return Fold(fn(b.summary), tuple(block(x) for x in b.blocks))
        if isinstance(b, FullForms):
            return FullForms(fn(b.title), fn(b.summary), b.forms)
        if isinstance(b, Image):
            return Image(b.png, runs(b.caption), fn(b.alt))
        return b  # Display: mathematics only

    return Section(section.key, fn(section.title), tuple(block(b) for b in section.blocks))


#: Non-breaking space before « : » and after « (and before »); a narrow one before ; ! ? (French typography).
NBSP, NNBSP = "\u00a0", "\u202f"
_BEFORE = re.compile(r"[ \u00a0\u202f]([:;!?»])")


def french_typography(text: str) -> str:
    """French typography on plain text: no line break before : ; ! ? », nor after «; typographic apostrophes.

    « a : b » → «\u00a0a\u00a0: b\u00a0» (U+00A0 before : and inside the guillemets, the narrow U+202F
    before ; ! ?), and l'énergie → l’énergie.  A colon or mark with no space before it (a time, a URL) is left.
    """
    text = _BEFORE.sub(lambda m: (NBSP if m.group(1) in ":»" else NNBSP) + m.group(1), text)
    text = re.sub(r"«[ \u00a0]?", "«" + NBSP, text)
    return text.replace("'", "\u2019")
