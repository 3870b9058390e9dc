"""matplotlib, imported only when a figure is made (the optional extra ``lagrangian[plot]``).

Figures are made as `matplotlib.figure.Figure` objects drawn by the Agg canvas: no
pyplot, no window, no global backend switch (a user's interactive session is left as it
was), and nothing to close afterwards.
"""

from __future__ import annotations

from typing import Any

from .._matplotlib import MissingPlotDependency, require_matplotlib

__all__ = ["require_matplotlib", "new_figure", "suptitle", "MissingPlotDependency"]


def new_figure(width: float, height: float, *, margins: tuple[float, float, float, float] = (0.8, 0.2, 0.55, 0.5),
               wspace: float = 0.3, hspace: float = 0.3, dpi: float = 100) -> Any:
    """A `Figure` of ``width`` × ``height`` inches on an Agg canvas.

    ``margins`` (left, right, bottom, top) are in inches, so they hold the tick labels and
    titles whatever the figure's size.  A fixed layout rather than matplotlib's
    constrained layout, which draws the figure several times to find one: that halves the
    time a figure takes to save.

    Parameters
    ----------
    width : float
        In inches.
    height : float
        In inches.
    margins : (float, float, float, float), optional
        (left, right, bottom, top), in inches, so they hold the tick labels and titles whatever the
        figure's size.
    wspace : float, optional
        The horizontal space between axes, relative to their width.
    hspace : float, optional
        The vertical space between axes, relative to their height.
    dpi : float, optional
        The resolution.

    Returns
    -------
    matplotlib.figure.Figure
        The figure.
    """
    require_matplotlib()
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    fig = Figure(figsize=(width, height), dpi=dpi)
    left, right, bottom, top = margins
    fig.subplots_adjust(left=left / width, right=1 - right / width, bottom=bottom / height, top=1 - top / height,
                        wspace=wspace, hspace=hspace)
    FigureCanvasAgg(fig)
    return fig


def suptitle(fig: Any, text: str) -> None:
    """The figure's title, a fixed 0.1 inch below its top edge whatever its height."""
    height = fig.get_figheight()
    fig.suptitle(text, y=1 - 0.1 / height, va="top")
