"""IPython's display protocol for the values of the early stages, drawn by the output stage.

Jupyter asks a value for its display (``_repr_latex_``, ``_repr_markdown_``, ``_repr_html_``).
The values live in early stages (`EquationsOfMotion` and `LagrangeEquation` in dynamics,
`FirstIntegral` and `LinearModel` in analysis, `Trajectory` in numerics), but drawing them in the
course's notation, bounded in size, is the output stage's work (`lagrangian.output.jupyter_repr`),
and an early stage never imports a later one (the import contract, tests/test_import_contract.py).

So the dependency is turned around: each display method is one line, ``return render(self, "latex")``,
and `render` hands the value to the *drawer* that the package's face installs (`install`).  The face,
``lagrangian/__init__.py``, stands above every stage and runs before any module of the package: its
drawer imports output on the first display, not before, so a display works whichever of the package's
modules were imported, and importing the package loads nothing more.
"""

from __future__ import annotations

from collections.abc import Callable

__all__ = ["install", "render"]

#: Draws a value as a form (``"latex"``, ``"markdown"``, ``"html"``): installed by the package's face.
Drawer = Callable[[object, str], str]

_drawer: Drawer | None = None


def install(drawer: Drawer) -> None:
    """Make ``drawer`` the one that `render` calls (the package's face does, on import)."""
    global _drawer
    _drawer = drawer


def render(value: object, form: str) -> str:
    """``value`` drawn for Jupyter as ``form`` (``"latex"``, ``"markdown"`` or ``"html"``) by the installed drawer.

    Raises `KeyError` for a type or form that is not drawn (a programming error: each display
    method names a form that output draws for its type).
    """
    if _drawer is None:  # a module of the package loaded without its face: not through `import`
        raise RuntimeError("no drawer for Jupyter's display: import lagrangian")
    return _drawer(value, form)
