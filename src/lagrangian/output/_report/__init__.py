"""The step-by-step derivation report: `report(model)` → a `Report` in HTML, LaTeX or Markdown.

The report follows the seed's "Démarche d'application" for any model, in French (the
course's words and notation) or in English:

1. the principal constraints, classified (holonomic, time-dependent, perfect and why,
   principal or complementary);
2. the n principal parameters and the n Lagrange equations (Remarque 1);
3. the rotation chain, the inertia matrices, Ω of each body and the virtual velocity field
   V*(P) = Σ ∂OP/∂q_i q_i* at the loaded points;
4. T(Σ/R0) and U_P(Σ/R0) with the formulas they come from;
5. the generalized forces Q_i, load by load, by virtual power;
6. ∂T/∂q̇_i, ∂T/∂q_i, ∂U_P/∂q_i, Q_i and L(q_i) for each coordinate (L = T − U_P when
   the system is conservative);
7. the complementary equations;

then the first integrals, the theorem of percussions for a model with unilateral contacts (with
the contact events of a simulation, ``events``), the small motions about an equilibrium (opt-in: ``small_motions``),
the Newton–Euler cross-check (``verification``), the simulation's
figures (``figures``) and the matrix form M q̈ = F.  Everything is computed by the engine;
this module only arranges and writes it.
"""

from __future__ import annotations

import io
import os
import sys
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from ... import _atomic
from ...analysis import FirstIntegral, Verification, first_integrals, verify
from ...dynamics import EquationsOfMotion, derive
from ...errors import OutputError
from ...model import Model, in_language, load_model
from .build import Context
from .document import Document, Scene3D, Section, french_typography, map_math, map_text, pictures
from .render.html import render_html
from .render.markdown import display_math, render_markdown
from .render.pdf import compile_pdf
from .render.tex import render_tex
from .steps.equations import integrals_section, pin_reaction, step6, step7
from .steps.extras import ReportFigure, check_section, matrix_section, notes_section, simulation_section
from .steps.forces import step5
from .steps.impacts import has_contacts, impacts_section
from .steps.kinematics import step3, step4
from .steps.small_motions import as_linear_model, small_motions_section
from .steps.statement import step1, step2, system_section

__all__ = ["Report", "ReportFigure", "report", "FORMATS", "format_for"]

#: The formats, by name, and the file suffixes that select them.
FORMATS = {"html": (".html", ".htm"), "tex": (".tex", ".latex"), "md": (".md", ".markdown"), "pdf": (".pdf",)}


def format_for(path: str | os.PathLike[str], default: str = "md") -> str:
    """The format a file name asks for by its suffix (``default`` when it says nothing).

    Parameters
    ----------
    path : str or PathLike
        The file name.
    default : str, optional
        The format when the suffix says nothing.

    Returns
    -------
    str
        ``"html"``, ``"tex"``, ``"md"`` or ``"pdf"``.
    """
    suffix = Path(path).suffix.lower()
    for name, suffixes in FORMATS.items():
        if suffix in suffixes:
            return name
    return default


def _footer() -> str:
    from ... import __version__

    return f"lagrangian {__version__}"


@dataclass(frozen=True)
class Report:
    """A derivation report: ``document`` holds its content; `html`, `latex` and `markdown` write it.

    In Jupyter the report displays itself (``_repr_html_``).

    Parameters
    ----------
    document : Document
        The report's content.
    eom : EquationsOfMotion
        The equations it reports.
    """

    document: Document
    eom: EquationsOfMotion = field(repr=False)

    def html(self) -> str:
        """One self-contained HTML page (MathML, images inline): opens offline in any browser.

        Returns
        -------
        str
            The page.
        """
        return render_html(self.document, footer=_footer())

    def latex(self, figure_files: Sequence[str] | None = None) -> str:
        """A LaTeX document; ``figure_files`` name the PNG files of the figures (see `save`).

        Parameters
        ----------
        figure_files : sequence of str, optional
            The PNG files of the figures (see `save`).

        Returns
        -------
        str
            The document.
        """
        return render_tex(self.document, footer=_footer(), figures=figure_files)

    def markdown(self, figure_files: Sequence[str] | None = None) -> str:
        """Markdown with GitHub's math syntax.

        Parameters
        ----------
        figure_files : sequence of str, optional
            The PNG files of the figures (see `save`); else they are data: URIs.

        Returns
        -------
        str
            The document.
        """
        return render_markdown(self.document, footer=_footer(), figures=figure_files)

    def pdf(self) -> bytes:
        """The PDF of the LaTeX report, compiled by pdflatex (or lualatex) installed on this machine.

        Returns
        -------
        bytes
            The PDF.
        """
        images = pictures(self.document)
        names = [f"report-figure-{k}.png" for k in range(1, len(images) + 1)]
        return compile_pdf(self.latex(names), {name: image.png for name, image in zip(names, images, strict=True)})

    def render(self, format: str) -> str:
        """The report in ``format``: ``"html"``, ``"tex"`` or ``"md"`` (a PDF is bytes: `pdf` or `save`).

        Parameters
        ----------
        format : {"html", "tex", "md"}
            The format.

        Returns
        -------
        str
            The report.
        """
        if format == "pdf":
            raise OutputError("A PDF is not text: it is written to a file.", fix="give the file: -o report.pdf")
        if format == "html":
            return self.html()
        if format == "tex":
            return self.latex()
        if format == "md":
            return self.markdown()
        raise OutputError(f"Unknown report format `{format}`.", fix="use html, tex or md")

    def save(self, path: str | os.PathLike[str], format: str | None = None) -> Path:
        """Write the report to ``path`` atomically (format from the suffix unless given).

        A LaTeX or Markdown report with figures also writes them, each atomically, as
        ``<name>-figure-<k>.png`` beside it, and refers to them by those relative names
        (``\\includegraphics``, ``![...](name-figure-1.png)``); HTML keeps them inline.
        A PDF is compiled from the LaTeX (`pdf`). A failure leaves any older file at ``path`` as it was.

        Parameters
        ----------
        path : str or PathLike
            The file to write.
        format : {"html", "tex", "md", "pdf"}, optional
            The format; None: from the suffix.

        Returns
        -------
        Path
            The path written.
        """
        path = Path(path)
        fmt = format or format_for(path)
        text: str | bytes
        try:
            if fmt in ("tex", "md"):
                images = pictures(self.document, scenes=fmt == "tex")  # Markdown leaves the 3-D figures out
                names = [f"{path.stem}-figure-{k}.png" for k in range(1, len(images) + 1)]
                for name, image in zip(names, images, strict=True):
                    _atomic.write_atomic(path.with_name(name), image.png)
                text = self.latex(names) if fmt == "tex" else self.markdown(names)
            elif fmt == "pdf":
                text = self.pdf()  # compiled in a temporary folder: nothing is written beside the PDF
            else:
                text = self.render(fmt)
            _atomic.write_atomic(path, text)
        except OSError as exc:
            raise OutputError(f"Cannot write `{path}`: {exc.strerror or exc}.",
                              fix="check that the folder exists and is writable; the old file, if any, is "
                                  "unchanged") from exc
        return path

    # -- Jupyter --------------------------------------------------------------------------------
    def _repr_html_(self) -> str:
        return render_html(self.document, footer=_footer(), fragment=True)

    def _repr_markdown_(self) -> str:
        return self.markdown()

    def _repr_latex_(self) -> str:
        """The Lagrange equations alone, as display math (what a LaTeX-only front end can show)."""
        from .document import Display

        blocks = self.document.section("step6").blocks
        return "\n".join(display_math(eq) for b in blocks if isinstance(b, Display) for eq in b.equations)


def _figure(item: Any) -> ReportFigure:
    """A `ReportFigure` from one, from PNG bytes, from a matplotlib figure, or from (caption, one of those)."""
    if isinstance(item, ReportFigure):
        return item
    if isinstance(item, tuple) and len(item) == 2 and isinstance(item[0], str):
        inner = _figure(item[1])
        return ReportFigure(inner.png, item[0])
    if isinstance(item, (bytes, bytearray)):
        return ReportFigure(bytes(item), "")
    mpl = sys.modules.get("matplotlib.figure")
    if mpl is not None and isinstance(item, mpl.Figure):
        buffer = io.BytesIO()
        item.savefig(buffer, format="png", dpi=110)
        suptitle = item._suptitle.get_text() if item._suptitle is not None else ""
        return ReportFigure(buffer.getvalue(), suptitle)
    raise TypeError(f"a report figure is a ReportFigure, PNG bytes, a matplotlib Figure or (caption, figure), "
                    f"not {type(item).__name__}")


def _scene_block(eom: EquationsOfMotion, lang: str, motion: Any = None) -> Scene3D | None:
    """The system in 3-D (at rest, or moving along ``motion``), or None where it cannot be drawn (a parameter
    without a value): the report goes on without it."""
    from ...errors import LagrangianError
    from ...view3d import view
    from .words import Words

    w = Words(lang)
    try:
        shown = view(motion, eom, lang=lang) if motion is not None else view(eom.model, lang=lang)
    except LagrangianError:
        return None
    key = "scene motion" if motion is not None else "scene statement"
    return Scene3D(shown.scene, (w.text(key),), w.text(key))


def report(model: Model | EquationsOfMotion | str | os.PathLike[str], *, lang: str = "fr",
           verification: Verification | bool | None = None, figures: Sequence[Any] = (),
           integrals: Sequence[FirstIntegral] | None = None, source: str | None = None,
           small_motions: Any = None, view: bool = True, motion: Any = None,
           events: Sequence[Any] = ()) -> Report:
    r"""The step-by-step derivation of ``model`` in the course's order, ready to write as HTML, LaTeX or Markdown.

    Parameters
    ----------
    model : Model or EquationsOfMotion or str or PathLike
        A model file, a `Model`, or its derivation (`lagrangian.derive`).
    lang : {"fr", "en"}, optional
        ``"fr"`` (the course's French) or ``"en"``.
    verification : Verification or bool, optional
        The Newton–Euler cross-check to include: a `Verification` (`lagrangian.analysis.verify`),
        ``True`` to compute it, or None to leave it out.
    figures : sequence, optional
        Figures to include (a simulation's plots): `ReportFigure`, PNG bytes, matplotlib figures, or
        ``(caption, figure)`` pairs.
    integrals : sequence of FirstIntegral, optional
        The first integrals (default: `lagrangian.first_integrals`).
    source : str, optional
        How ``lagrangian derive`` names the model (a file, ``zoo:planar_chain:40``, ``""`` for the
        seed's top), for the note on the equations too long to print in full (default: the model's
        file).
    small_motions : LinearModel or mapping of str to float or bool, optional
        Adds the section "Petits mouvements au voisinage d'une position d'équilibre" / "Small motions
        about an equilibrium": a `LinearModel` (`lagrangian.linearize`), a point ``{"theta": 0}``, or
        True for the model's ``[operating_point]``; None (default) leaves it out.
    view : bool, optional
        The statement shows the system in 3-D in its initial configuration, frames, points and angles
        labelled (`lagrangian.view3d`): interactive in HTML, a still picture in LaTeX and PDF
        (headless Chromium's, else matplotlib's); left out of Markdown.  ``False`` leaves it out.
    motion : Trajectory, optional
        A simulated motion of the model, shown in 3-D at the head of the simulation's figures.
    events : sequence of Event, optional
        The events of a simulated motion (``trajectory.events``): for a model with unilateral
        contacts, its impacts, lift-offs and rests are listed in the section on the theorem of
        percussions (which every model with contacts has).

    Returns
    -------
    Report
        With ``html()``, ``latex()``, ``markdown()`` and ``save(path)``.

    Examples
    --------
    >>> import lagrangian
    >>> r = report(lagrangian.lagrange_top())
    >>> "\\frac{d}{dt}" in r.markdown() and "K" in r.markdown()
    True
    """
    if isinstance(model, EquationsOfMotion):
        eom = model
    else:
        eom = derive(load_model(model) if isinstance(model, (str, os.PathLike)) else model)
    found = tuple(integrals) if integrals is not None else first_integrals(eom)
    c = Context(eom, found, lang, source=source)
    checked = verify(eom) if verification is True else (verification or None)
    figures_in = [_figure(f) for f in figures]
    statement = system_section(c)
    still = _scene_block(eom, lang) if view else None
    if still is not None:
        statement = Section(statement.key, statement.title, statement.blocks + (still,))
    sections = [statement, step1(c), step2(c), step3(c), step4(c), step5(c), step6(c), step7(c),
                integrals_section(c)]
    if has_contacts(c):  # unilateral constraints: what an impact does (theorem of percussions), the events
        sections.append(impacts_section(c, events))
    if checked is not None:  # the reaction of a fixed point, after step 7
        extra = pin_reaction(c, checked)
        if extra:
            sections[7] = Section(sections[7].key, sections[7].title, sections[7].blocks + tuple(extra))
    if small_motions is not None and small_motions is not False:
        sections.append(small_motions_section(c, as_linear_model(eom, small_motions)))
    if checked is not None:
        sections.append(check_section(c, checked))
    moving = _scene_block(eom, lang, motion) if motion is not None and view else None
    if figures_in or moving is not None:
        section = simulation_section(c, figures_in)
        if moving is not None:
            section = Section(section.key, section.title, (moving, *section.blocks))
        sections.append(section)
    sections.append(matrix_section(c))
    notes = notes_section(c)
    if notes is not None:
        sections.insert(1, notes)
    if lang == "en":
        # The cross product: ∧ in French (the course's), × in English.
        sections = [map_math(s, lambda latex: latex.replace(r"\wedge", r"\times")) for s in sections]
    # The model's own title in the report's language ("Mouvement de Lagrange"), else one made from its name.
    title = in_language(eom.model.title, lang) or c.w.text("title", name=eom.model.name)
    subtitle = in_language(eom.model.description, lang) or ""
    if lang == "fr":  # non-breaking spaces before : ; ! ? and inside « », typographic apostrophes
        sections = [map_text(s, french_typography) for s in sections]
        title, subtitle = french_typography(title), french_typography(subtitle)
    return Report(Document(lang, title, subtitle, tuple(sections)), eom)
