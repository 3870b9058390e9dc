"""Figures over time: q_i(t) and q̇_i(t), phase portraits (q_i, q̇_i), and the drift of the first integrals."""

from __future__ import annotations

from typing import Any

import numpy as np

from ..dynamics import EquationsOfMotion
from ..numerics import Trajectory
from ._labels import label, symbol, words
from ._mpl import new_figure, suptitle

__all__ = ["plot_time_series", "plot_phase", "plot_drift", "relative_drift"]

#: Height of one row of panels, in inches.
ROW_HEIGHT = 1.7


def _title(model: str, what: str, lang: str) -> str:
    """``model: what``, with the space French puts before a colon."""
    return f"{model} : {what}" if lang == "fr" else f"{model}: {what}"


def plot_time_series(trajectory: Trajectory, eom: EquationsOfMotion, *, fig: Any = None, lang: str = "en") -> Any:
    """Draw q_i(t) (left) and q̇_i(t) (right), one row per coordinate.

    Parameters
    ----------
    trajectory : Trajectory
        A simulated motion.
    eom : EquationsOfMotion
        Its equations.
    fig : matplotlib.figure.Figure, optional
        A figure to draw in; None: a new one.
    lang : {"en", "fr"}, optional
        The language of the titles and labels.

    Returns
    -------
    matplotlib.figure.Figure
        With 2n axes, in the order q_1, q̇_1, q_2, q̇_2, ...
    """
    names = trajectory.coordinates
    n = len(names)
    fig = fig or new_figure(9.0, min(1.0 + ROW_HEIGHT * n, 40.0), margins=(0.85, 0.15, 0.5, 0.65), hspace=0.12)
    axes = fig.subplots(n, 2, sharex=True, squeeze=False)
    for i, name in enumerate(names):
        for k, data in enumerate((trajectory.q[:, i], trajectory.qd[:, i])):
            ax = axes[i, k]
            ax.plot(trajectory.t, data, lw=1.2, color=f"C{i}")
            ax.set_ylabel(label(eom, name, k))
            ax.grid(True, alpha=0.3)
    for k in range(2):
        axes[-1, k].set_xlabel("t (s)")
    w = words(lang)
    axes[0, 0].set_title(w["coordinates"])
    axes[0, 1].set_title(w["rates"])
    suptitle(fig, _title(trajectory.model_name, w["time series"], lang))
    return fig


def plot_phase(trajectory: Trajectory, eom: EquationsOfMotion, *, fig: Any = None, lang: str = "en") -> Any:
    """Phase portraits (q_i, q̇_i), one panel per coordinate; the start is marked by a dot.

    Parameters
    ----------
    trajectory : Trajectory
        A simulated motion.
    eom : EquationsOfMotion
        Its equations.
    fig : matplotlib.figure.Figure, optional
        A figure to draw in; None: a new one.
    lang : {"en", "fr"}, optional
        The language of the titles and labels.

    Returns
    -------
    matplotlib.figure.Figure
        With n axes (extra grid cells are hidden).
    """
    names = trajectory.coordinates
    n = len(names)
    cols = min(n, 3)
    rows = -(-n // cols)
    fig = fig or new_figure(3.6 * cols + 0.4, min(3.3 * rows + 0.6, 40.0), margins=(0.75, 0.15, 0.55, 0.45),
                            wspace=0.4, hspace=0.35)
    axes = fig.subplots(rows, cols, squeeze=False)
    for i, name in enumerate(names):
        ax = axes[i // cols, i % cols]
        ax.plot(trajectory.q[:, i], trajectory.qd[:, i], lw=1.0, color=f"C{i}")
        if len(trajectory.t):
            ax.plot(trajectory.q[0, i], trajectory.qd[0, i], "o", color="k", ms=4, label="t = 0")
        ax.set_xlabel(label(eom, name, 0))
        ax.set_ylabel(label(eom, name, 1))
        ax.grid(True, alpha=0.3)
    for j in range(n, rows * cols):
        axes[j // cols, j % cols].set_visible(False)
    axes[0, 0].legend(loc="best", fontsize="small")
    suptitle(fig, _title(trajectory.model_name, words(lang)["phase"], lang))
    return fig


def relative_drift(trajectory: Trajectory, name: str) -> np.ndarray:
    """The relative drift ``|I(t) − I(t0)| / S``, S the physical scale of the integral (`Trajectory.scales`).

    Parameters
    ----------
    trajectory : Trajectory
        A simulated motion.
    name : str
        A first integral.

    Returns
    -------
    ndarray of shape (N,)
        The drift; its maximum is ``trajectory.drift[name]``, the conservation monitor of the run.
    """
    return trajectory.relative_drift(name)


def plot_drift(trajectory: Trajectory, eom: EquationsOfMotion | None = None, *, fig: Any = None,
               lang: str = "en") -> Any:
    """Energy exchange (T, U, E) on top, and the relative drift of every first integral below (log scale).

    A drift that is exactly zero at every sample (a first integral conserved to the last
    bit) cannot be drawn on a log scale; its legend entry says so.

    Parameters
    ----------
    trajectory : Trajectory
        A simulated motion.
    eom : EquationsOfMotion, optional
        Its equations (their notation).
    fig : matplotlib.figure.Figure, optional
        A figure to draw in; None: a new one.
    lang : {"en", "fr"}, optional
        The language of the titles and labels.

    Returns
    -------
    matplotlib.figure.Figure
        Axes 0: the energies; axes 1 (when the model has first integrals): one line per
        integral whose y-data are `relative_drift` (zeros left out).
    """
    w = words(lang)
    integrals = trajectory.integrals
    rows = 2 if integrals else 1
    fig = fig or new_figure(8.0, 2.8 * rows + 0.6, margins=(1.0, 0.15, 0.5, 0.6), hspace=0.3)
    axes = fig.subplots(rows, 1, sharex=True, squeeze=False)[:, 0]
    t = trajectory.t
    ax = axes[0]
    for name in ("T", "U", "E"):
        if name in trajectory.monitors:
            shown = symbol(eom, name) if eom is not None else name
            ax.plot(t, trajectory.monitors[name], lw=1.2, label=shown)
    ax.set_ylabel(w["energy"])
    ax.grid(True, alpha=0.3)
    ax.legend(loc="best", fontsize="small")
    ax.set_title(w["energies"] + (w["energies E"] if "E" in trajectory.monitors else ""))
    if integrals:
        ax = axes[1]
        for name in integrals:
            d = relative_drift(trajectory, name)
            shown = symbol(eom, name) if eom is not None else name
            if np.any(d > 0):
                ax.semilogy(t, np.where(d > 0, d, np.nan), lw=1.0,
                            label=f"{shown}: max {trajectory.drift.get(name, d.max()):.1e}")
            else:
                ax.plot([], [], lw=1.0, label=f"{shown}: {w['exact']}")
        ax.set_yscale("log")
        ax.set_ylabel(r"$|I(t) - I(t_0)| \,/\, |I(t_0)|$")
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(loc="best", fontsize="small")
        tol = trajectory.tolerance
        if tol is not None:
            ax.axhline(tol, color="r", ls="--", lw=0.8)
        ax.set_title(w["drift"].format(method=trajectory.method))
    axes[-1].set_xlabel("t (s)")
    suptitle(fig, _title(trajectory.model_name, w["conservation"], lang))
    return fig
