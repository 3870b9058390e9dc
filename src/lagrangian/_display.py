"""IPython's display protocol for the values of the early stages, drawn by the output stage.

Jupyter asks a value for its display (``_repr_latex_``, ``_repr_markdown_``, ``_repr_html_``).
The values live in early stages (`EquationsOfMotion` and `LagrangeEquation` in dynamics,
`FirstIntegral` and `LinearModel` in analysis, `Trajectory` in numerics), but drawing them in the
course's notation, bounded in size, is the output stage's work (``lagrangian/output/_display.py``,
whose `RENDERERS` table maps each value type and form to its renderer).

Each display method is one line, ``return render(self, "latex")``: the early stages import only
this module, and `render` imports output's table on first display.  That import is the one that
goes up the stages, in one place, listed with its reason among the import contract's exceptions
(tests/test_import_contract.py).  Nothing is registered at import time: a display works whichever
of the package's modules were imported before.
"""

from __future__ import annotations

__all__ = ["render"]


def render(value: object, form: str) -> str:
    """``value`` drawn for Jupyter as ``form`` (``"latex"``, ``"markdown"`` or ``"html"``) by the output stage.

    A subclass is drawn as its nearest base in the table (an `OptimalTrajectory` as a `Trajectory`).
    Raises `KeyError` for a type or form that output does not draw (a programming error: each
    display method names a form that `RENDERERS` has for its type).
    """
    from .output._display import RENDERERS  # up the stages, on first display (module docstring)

    for cls in type(value).__mro__:
        renderer = RENDERERS.get((cls, form))
        if renderer is not None:
            return renderer(value)
    raise KeyError((type(value).__name__, form))
