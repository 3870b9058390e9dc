"""matplotlib, imported only when something is drawn with it (the optional extra ``lagrangian[plot]``).

Shared by the figures (`lagrangian.plotting`) and the 3-D view's still and animation drawing
(`lagrangian.view3d`): without matplotlib, `MissingPlotDependency` says how to install it.
"""

from __future__ import annotations

from types import ModuleType

from .errors import OutputError

__all__ = ["MissingPlotDependency", "require_matplotlib"]


class MissingPlotDependency(OutputError):
    """The plotting library matplotlib (the ``plot`` extra) is not installed.

    Parameters
    ----------
    message : str
        What was wrong, a full sentence naming the culprit in backticks.
    fix : str, optional
        How to fix it, printed after the message.
    """


def require_matplotlib() -> ModuleType:
    """The ``matplotlib`` module, or a `MissingPlotDependency` that says how to install it.

    Returns
    -------
    module
        ``matplotlib``.
    """
    try:
        import matplotlib
        import matplotlib.figure
        from matplotlib.backends import backend_agg  # noqa: F401  (the Agg canvas)
    except ImportError as exc:
        raise MissingPlotDependency(
            f"Plots need matplotlib, which cannot be imported ({exc}).",
            fix="install the plot extra: pip install 'lagrangian[plot]'") from None
    return matplotlib
