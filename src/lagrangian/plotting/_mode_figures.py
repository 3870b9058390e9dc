"""Figures of the small motions: the eigenvalues against a parameter, and the mode shapes.

`plot_eigenvalue_sweep` is the figure of Meijaard, Papadopoulos, Ruina & Schwab (2007),
Proc. R. Soc. A 463, fig. 3, for any model: Re λ (solid dots) and Im λ (small dots) of the
essential eigenvalues against the swept parameter, the zero line, and the values where
stability changes marked by vertical lines.  `plot_mode_shapes` draws each mode's shape over
the coordinates (the real part of the eigenvector scaled so its largest coordinate is 1, as
`lagrangian.analysis.modes` normalises it), or the conservative φ_k of K φ = ω² M φ.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from ..dynamics import EquationsOfMotion
from ._labels import symbol
from ._mpl import new_figure, suptitle

__all__ = ["plot_eigenvalue_sweep", "plot_mode_shapes", "plot_bifurcation"]

_WORDS = {
    "en": {"eigenvalues": "eigenvalues against {p}", "re": r"Re $\lambda$", "im": r"Im $\lambda$",
           "lambda": r"$\lambda$ (1/s)", "shapes": "mode shapes", "mode": "mode {k}",
           "bifurcation": "equilibria against {p}", "stable": "stable", "unstable": "unstable",
           "marginal": "undecided"},
    "fr": {"eigenvalues": "valeurs propres en fonction de {p}", "re": r"Re $\lambda$", "im": r"Im $\lambda$",
           "lambda": r"$\lambda$ (1/s)", "shapes": "déformées modales", "mode": "mode {k}",
           "bifurcation": "positions d'équilibre en fonction de {p}", "stable": "stable", "unstable": "instable",
           "marginal": "non décidé"},
}


def _title(model: str, what: str, lang: str) -> str:
    return f"{model} : {what}" if lang == "fr" else f"{model}: {what}"


def _parameter_label(eom: EquationsOfMotion, name: str) -> str:
    unit = next((p.unit for p in eom.model.parameters if p.name == name and p.unit), "")
    return symbol(eom, name) + (f" ({unit})" if unit else "")


def plot_eigenvalue_sweep(sweep: Any, eom: EquationsOfMotion, *, fig: Any = None, lang: str = "en") -> Any:
    """Draw Re λ and Im λ of the essential eigenvalues against ``sweep.parameter``.

    Parameters
    ----------
    sweep : Sweep
        A `lagrangian.analysis.Sweep`.
    eom : EquationsOfMotion
        The equations (their notation).
    fig : matplotlib.figure.Figure, optional
        A figure to draw in; None: a new one.
    lang : {"en", "fr"}, optional
        The language of the titles and labels.

    Returns
    -------
    matplotlib.figure.Figure
        One axes; the changes of stability are dotted vertical lines.
    """
    w = _WORDS.get(lang, _WORDS["en"])
    fig = fig or new_figure(8.0, 5.0, margins=(0.85, 0.2, 0.6, 0.55))
    ax = fig.add_subplot(1, 1, 1)
    x = np.asarray(sweep.values, dtype=float)
    lam = np.asarray(sweep.eigenvalues)
    if lam.ndim == 2 and lam.shape[1]:
        xs = np.repeat(x, lam.shape[1])
        ax.plot(xs, lam.real.ravel(), ".", ms=2.5, color="C0", label=w["re"])
        im = lam.imag.ravel()
        keep = im != 0
        ax.plot(xs[keep], np.abs(im[keep]), ".", ms=1.0, color="C1", label=w["im"])
    ax.axhline(0.0, color="k", lw=0.8)
    for change in sweep.changes:
        ax.axvline(change.value, color="0.4", lw=0.8, ls=":")
    ax.set_xlim(x[0], x[-1] if x[-1] > x[0] else x[0] + 1.0)
    ax.set_xlabel(_parameter_label(eom, sweep.parameter))
    ax.set_ylabel(w["lambda"])
    ax.grid(True, alpha=0.3)
    if ax.get_legend_handles_labels()[0]:
        ax.legend(loc="best", markerscale=4)
    suptitle(fig, _title(eom.model.name, w["eigenvalues"].format(p=symbol(eom, sweep.parameter)), lang))
    return fig


def _shapes(modes: Any) -> list[tuple[str, dict[str, float]]]:
    """(legend, shape over the coordinates) of each mode: the conservative φ_k when known, else each
    eigenvalue with Im λ ≥ 0 (a conjugate pair drawn once)."""
    if modes.pulsations and modes.shapes:
        out = []
        for k, (om, phi) in enumerate(zip(modes.pulsations, modes.shapes, strict=True), 1):
            big = max(phi.values(), key=abs, default=1.0) or 1.0  # the largest component becomes +1
            out.append((f"{k}: ω = {om:.4g} rad/s", {c: v / big for c, v in phi.items()}))
        return out
    out = []
    for k, m in enumerate((m for m in modes.modes if m.eigenvalue.imag >= 0), 1):
        shape = {c: float(np.real(v)) for c, v in m.shape.items() if not c.endswith("_dot")}
        z = m.eigenvalue
        lam = f"{z.real:.4g}" if z.imag == 0 else f"{z.real:.3g} ± {abs(z.imag):.4g} i"
        out.append((f"{k}: λ = {lam}", shape))
    return out


def plot_mode_shapes(modes: Any, eom: EquationsOfMotion, *, fig: Any = None, lang: str = "en") -> Any:
    """A bar chart per mode of its shape over the coordinates (a `lagrangian.analysis.Modes`).

    Parameters
    ----------
    modes : Modes
        A `lagrangian.analysis.Modes`.
    eom : EquationsOfMotion
        The equations (their notation).
    fig : matplotlib.figure.Figure, optional
        A figure to draw in; None: a new one.
    lang : {"en", "fr"}, optional
        The language of the titles and labels.

    Returns
    -------
    matplotlib.figure.Figure
        One axes per mode (at most 12).
    """
    w = _WORDS.get(lang, _WORDS["en"])
    shapes = _shapes(modes)[:12]
    k = max(len(shapes), 1)
    cols = min(k, 3)
    rows = (k + cols - 1) // cols
    fig = fig or new_figure(3.2 * cols + 0.6, 2.4 * rows + 0.8, margins=(0.6, 0.2, 0.55, 0.6), hspace=0.6)
    axes = fig.subplots(rows, cols, squeeze=False)
    for ax in axes.ravel()[len(shapes):]:
        ax.set_visible(False)
    for ax, (legend, shape) in zip(axes.ravel(), shapes, strict=True):
        names = list(shape)
        ax.bar(range(len(names)), [shape[c] for c in names], color=[f"C{i}" for i in range(len(names))])
        ax.set_xticks(range(len(names)))
        ax.set_xticklabels([symbol(eom, c) for c in names])
        ax.axhline(0.0, color="k", lw=0.8)
        ax.set_ylim(-1.15, 1.15)
        ax.set_title(w["mode"].format(k=legend), fontsize=9)
        ax.grid(True, axis="y", alpha=0.3)
    suptitle(fig, _title(eom.model.name, w["shapes"], lang))
    return fig


def plot_bifurcation(diagram: Any, eom: EquationsOfMotion, coordinate: str | None = None, *, fig: Any = None,
                     lang: str = "en") -> Any:
    """Draw q* of each branch of equilibria against the parameter (a `lagrangian.analysis.BifurcationDiagram`).

    Solid where stable, dashed where unstable, dotted where the linearization does not decide; the
    values where a branch appears or changes stability are dotted vertical lines (the bead on the
    rotating hoop: the pitchfork at Ω² = g/R).

    Parameters
    ----------
    diagram : BifurcationDiagram
        The diagram.
    eom : EquationsOfMotion
        The equations (their notation).
    coordinate : str, optional
        The coordinate drawn (default: the first).
    fig : matplotlib.figure.Figure, optional
        A figure to draw in; None: a new one.
    lang : {"en", "fr"}, optional
        The language of the titles and labels.

    Returns
    -------
    matplotlib.figure.Figure
        One axes.
    """
    w = _WORDS.get(lang, _WORDS["en"])
    coordinate = coordinate or diagram.coordinates[0]
    j = diagram.coordinates.index(coordinate)
    fig = fig or new_figure(7.0, 4.5, margins=(0.85, 0.2, 0.6, 0.55))
    ax = fig.add_subplot(1, 1, 1)
    x = np.asarray(diagram.values, dtype=float)
    for k, branch in enumerate(diagram.branches):
        y = branch.q[:, j]
        for value, ls in ((1.0, "-"), (0.0, "--")):
            ax.plot(x, np.where(branch.stable == value, y, np.nan), ls, color=f"C{k % 10}", lw=1.8)
        ax.plot(x, np.where(np.isnan(branch.stable), y, np.nan), ":", color=f"C{k % 10}", lw=1.2)
    for ls, label in (("-", w["stable"]), ("--", w["unstable"]), (":", w["marginal"])):
        ax.plot([], [], ls, color="k", lw=1.5, label=label)  # the legend explains the line styles only
    for branch in diagram.branches:
        for value, _ in branch.changes:
            ax.axvline(value, color="0.4", lw=0.8, ls=":")
    ax.set_xlabel(_parameter_label(eom, diagram.parameter))
    ax.set_ylabel(symbol(eom, coordinate) + "*")
    ax.grid(True, alpha=0.3)
    ax.legend(loc="best")
    suptitle(fig, _title(eom.model.name, w["bifurcation"].format(p=symbol(eom, diagram.parameter)), lang))
    return fig
