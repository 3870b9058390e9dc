"""Stage 7 — output: the derivation in the course's notation, as text, LaTeX and JSON.

``export`` and ``EXPORT_TARGETS`` are the code-generation stage's (`lagrangian.codegen`), re-exported here.
"""

from ..codegen import EXPORT_TARGETS as EXPORT_TARGETS
from ..codegen import export as export
from ._course import CourseForm as CourseForm
from ._course import course_form as course_form

# Shared with the command line: the course's forms, the intermediates, what derive prints besides.
from ._course import reference_label as reference_label
from ._course import to_sympy as to_sympy
from ._display import jupyter_repr as jupyter_repr
from ._equilibria_text import bifurcation_text as bifurcation_text
from ._equilibria_text import equilibria_text as equilibria_text
from ._feedback_text import feedback_text as feedback_text
from ._intermediates import needed_intermediates as needed_intermediates
from ._intermediates import render_intermediates as render_intermediates
from ._json import SCHEMA_ID as SCHEMA_ID
from ._json import SCHEMA_VERSION as SCHEMA_VERSION
from ._json import derive_document as derive_document
from ._latex import render_latex as render_latex
from ._linear_text import linear_text as linear_text
from ._linear_text import modes_text as modes_text
from ._linear_text import sweep_text as sweep_text
from ._linearize_json import LINEARIZE_SCHEMA_ID as LINEARIZE_SCHEMA_ID
from ._linearize_json import linearize_document as linearize_document
from ._notation import Notation as Notation
from ._report import FORMATS as FORMATS
from ._report import Report as Report
from ._report import ReportFigure as ReportFigure
from ._report import format_for as format_for
from ._report import report as report
from ._report.size import SizeGate as SizeGate
from ._sympy_equations import sympy_equations as sympy_equations
from ._text import Supplement as Supplement
from ._text import render_text as render_text
from ._text import supplement as supplement
from ._top_text import simulation_check_text as simulation_check_text
from ._top_text import top_analysis_text as top_analysis_text
from ._verification_text import verification_failure as verification_failure
from ._verification_text import verification_text as verification_text

__all__ = ["CourseForm", "course_form", "EXPORT_TARGETS", "export", "SCHEMA_ID", "SCHEMA_VERSION", "derive_document", "render_latex",
           "LINEARIZE_SCHEMA_ID", "linearize_document",
           "Notation", "render_text", "Report", "ReportFigure", "report", "FORMATS", "format_for",
           "sympy_equations", "bifurcation_text", "equilibria_text", "feedback_text", "linear_text", "modes_text",
           "sweep_text", "simulation_check_text", "top_analysis_text", "verification_text", "verification_failure",
           "reference_label", "to_sympy", "needed_intermediates", "render_intermediates", "Supplement", "supplement", "SizeGate",
           "jupyter_repr"]
