"""Stage 5 — output: the derivation in the course's notation, as text, LaTeX and JSON."""

from ._course import CourseForm as CourseForm
from ._course import course_form as course_form
from ._export import EXPORT_TARGETS as EXPORT_TARGETS
from ..numerics._ensemble import register_backend as _register_backend
from ._ensemble_jax import jax_runner as _jax_runner
from ._export import export as export
from ._json import SCHEMA_ID as SCHEMA_ID
from ._json import SCHEMA_VERSION as SCHEMA_VERSION
from ._json import derive_document as derive_document
from ._latex import render_latex as render_latex
from ._linearize_json import LINEARIZE_SCHEMA_ID as LINEARIZE_SCHEMA_ID
from ._linearize_json import linearize_document as linearize_document
from ._notation import Notation as Notation
from .report import FORMATS as FORMATS
from .report import Report as Report
from .report import ReportFigure as ReportFigure
from .report import format_for as format_for
from .report import report as report
from ._sympy_form import SympyEquations as SympyEquations
from ._sympy_form import sympy_equations as sympy_equations
from ._text import render_text as render_text

_register_backend("jax", _jax_runner)  # `ensemble(..., backend="jax")`: built on the JAX export, so registered here

__all__ = ["CourseForm", "course_form", "EXPORT_TARGETS", "export", "SCHEMA_ID", "SCHEMA_VERSION", "derive_document", "render_latex",
           "LINEARIZE_SCHEMA_ID", "linearize_document",
           "Notation", "render_text", "Report", "ReportFigure", "report", "FORMATS", "format_for",
           "SympyEquations", "sympy_equations"]
