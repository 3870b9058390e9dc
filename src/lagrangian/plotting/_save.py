"""Every figure of a run in one call: `save_plots` (what ``lagrangian simulate --plot DIR`` runs).

Each file is written atomically (a temporary file beside it, then `os.replace`), so a
failure leaves any older file of that name as it was.
"""

from __future__ import annotations

import re
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Any

import numpy as np

from .._atomic import write_atomic_with
from ..dynamics import EquationsOfMotion
from ..errors import LagrangianError, OutputError
from ..numerics import Trajectory
from ._animation import FORMATS, animate
from ._apex import plot_apex_sphere, plot_nutation
from ._geometry import apex_path
from ._labels import words
from ._reaction import plot_reaction, reaction_stem, reactions_along
from ._series import plot_drift, plot_phase, plot_time_series

__all__ = ["KINDS", "plot_trajectory", "applicable_kinds", "figure_name", "figure_caption", "save_plots",
           "save_figure"]

#: Every kind of figure, in the order `save_plots` writes them.
KINDS = ("time_series", "phase", "apex_sphere", "nutation", "drift", "reaction")
#: Image formats matplotlib's Agg canvas writes without extra software.
IMAGE_FORMATS = ("png", "svg", "pdf", "jpg", "jpeg", "eps", "ps", "webp", "tif", "tiff")
#: Smallest singular value (relative) of the axis tip's positions for the axis to turn in 3D
#: rather than in one plane through O (a great circle: a planar pendulum's rod).
GREAT_CIRCLE = 1e-9

_PLOTTERS: dict[str, Callable[..., Any]] = {
    "time_series": plot_time_series,
    "phase": plot_phase,
    "apex_sphere": plot_apex_sphere,
    "nutation": plot_nutation,
    "drift": plot_drift,
    "reaction": plot_reaction,
}


def plot_trajectory(trajectory: Trajectory, eom: EquationsOfMotion, kind: str = "time_series",
                    **options: Any) -> Any:
    """The figure ``kind`` (one of `KINDS`) of a simulated motion.

    ``options`` go to the figure's function: ``ax=`` (``apex_sphere``, ``reaction``),
    ``fig=`` (the others), ``body=`` and ``axis=`` (``apex_sphere``, ``nutation``), ``lang=``
    (``"en"``, the default, or ``"fr"``: the titles in the course's French).

    Parameters
    ----------
    trajectory : Trajectory
        A simulated motion.
    eom : EquationsOfMotion
        Its equations.
    kind : str, optional
        One of `KINDS`.
    **options
        Go to the figure's function: ``ax=`` (``apex_sphere``, ``reaction``), ``fig=`` (the
        others), ``body=`` and ``axis=`` (``apex_sphere``, ``nutation``), ``lang=`` (``"en"``, the
        default, or ``"fr"``: the titles in the course's French).

    Returns
    -------
    matplotlib.figure.Figure
        The figure.

    Examples
    --------
    >>> import lagrangian
    >>> from lagrangian.numerics import simulate
    >>> eom = lagrangian.derive(lagrangian.lagrange_top())
    >>> fig = plot_trajectory(simulate(eom, 0.5, n_out=51), eom, "nutation")
    >>> len(fig.axes)
    2
    """
    if kind not in _PLOTTERS:
        raise OutputError(f"Unknown figure `{kind}`.", fix="choose one of " + ", ".join(KINDS))
    fig = _PLOTTERS[kind](trajectory, eom, **options)
    if options.get("lang") == "fr":
        french_numbers(fig)
    return fig


#: A decimal point between digits, outside $...$ (mathtext).
_DECIMAL_POINT = re.compile(r"(?<=\d)\.(?=\d)")


def _comma(text: str) -> str:
    """``28.65°`` → ``28,65°`` in the plain parts of a label; in ``$...$`` the comma is braced, ``{,}``, so that
    mathtext does not space it as punctuation."""
    parts = text.split("$")
    return "$".join(_DECIMAL_POINT.sub("," if k % 2 == 0 else "{,}", part) for k, part in enumerate(parts))


def french_numbers(fig: Any) -> None:
    """The numbers of a figure written the French way, with a decimal comma: its tick labels (plain axes) and
    its texts (titles, legends, annotations)."""
    import matplotlib.text
    from matplotlib.ticker import ScalarFormatter

    class CommaFormatter(ScalarFormatter):
        def __call__(self, x: float, pos: int | None = None) -> str:
            return _comma(super().__call__(x, pos))

        def get_offset(self) -> str:
            return _comma(super().get_offset())

    for ax in fig.axes:
        for axis in (ax.xaxis, ax.yaxis):
            if type(axis.get_major_formatter()) is ScalarFormatter:
                axis.set_major_formatter(CommaFormatter())
    for text in fig.findobj(matplotlib.text.Text):
        label = text.get_text()
        if label and _DECIMAL_POINT.search(label):
            text.set_text(_comma(label))
    for ax in fig.axes:
        legend = ax.get_legend()
        if legend is not None:
            for t in legend.get_texts():
                t.set_text(_comma(t.get_text()))


def _turns_in_3d(trajectory: Trajectory, eom: EquationsOfMotion) -> bool:
    tip = apex_path(trajectory, eom)
    s = np.linalg.svd(tip, compute_uv=False)
    return bool(s[0] > 0 and s[-1] > GREAT_CIRCLE * s[0])


def applicable_kinds(trajectory: Trajectory, eom: EquationsOfMotion) -> tuple[str, ...]:
    """The figures that say something for this model and run.

    The apex figures need a rigid body whose axis turns in 3D (the top; not a planar
    pendulum, whose rods stay on a great circle); the reaction needs every load in force
    form (`reactions_along`).

    Parameters
    ----------
    trajectory : Trajectory
        A simulated motion.
    eom : EquationsOfMotion
        Its equations.

    Returns
    -------
    tuple of str
        Figure kinds, in the order of `KINDS`.
    """
    kinds = ["time_series", "phase"]
    if eom.model.bodies and len(trajectory.t) >= 3 and _turns_in_3d(trajectory, eom):
        kinds += ["apex_sphere", "nutation"]
    kinds.append("drift")
    try:
        reactions_along(trajectory, eom)
        kinds.append("reaction")
    except LagrangianError:
        pass
    return tuple(kinds)


def figure_name(kind: str, eom: EquationsOfMotion) -> str:
    """The file stem of a figure: ``time_series``, ..., ``reaction_O`` when held at O."""
    return reaction_stem(eom) if kind == "reaction" else kind


def figure_caption(kind: str, eom: EquationsOfMotion, lang: str = "en") -> str:
    """A caption for the figure ``kind`` in ``lang`` (``"fr"``: the course's words), e.g. "Réaction R_O(t)".

    Parameters
    ----------
    kind : str
        One of `KINDS`.
    eom : EquationsOfMotion
        The equations.
    lang : {"en", "fr"}, optional
        The language.

    Returns
    -------
    str
        The caption.

    Examples
    --------
    >>> import lagrangian
    >>> figure_caption("apex_sphere", lagrangian.derive(lagrangian.lagrange_top()), "fr")
    "Trajectoire de l'apex sur la sphère unité"
    """
    if kind not in _PLOTTERS:
        raise OutputError(f"Unknown figure `{kind}`.", fix="choose one of " + ", ".join(KINDS))
    stem = reaction_stem(eom)
    name = stem[0].upper() + stem[len("reaction"):] if stem.startswith("reaction_") else "R"
    return words(lang)[f"caption {kind}"].format(name=name)


def save_figure(fig: Any, path: str | Path, *, dpi: float = 110) -> Path:
    """Write ``fig`` to ``path`` atomically, in the format of its suffix.

    Parameters
    ----------
    fig : matplotlib.figure.Figure
        The figure.
    path : str or Path
        The file to write.
    dpi : float, optional
        The resolution.

    Returns
    -------
    Path
        The path written.
    """
    path = Path(path)
    fmt = path.suffix.lstrip(".").lower()
    if fmt not in IMAGE_FORMATS:
        raise OutputError(f"`{path.name}`: unknown image format `{fmt}`.", fix="use one of " + ", ".join(IMAGE_FORMATS))
    try:
        write_atomic_with(path, lambda handle: fig.savefig(handle, format=fmt, dpi=dpi))
    except OSError as exc:
        raise OutputError(f"Cannot write the figure `{path}`: {exc.strerror or exc}.",
                          fix="check that the folder exists and is writable; any older file is unchanged") from None
    return path


def save_plots(trajectory: Trajectory, eom: EquationsOfMotion, directory: str | Path, *, animation: bool = True,
               formats: Sequence[str] = ("png",), kinds: Sequence[str] | None = None, frames: int = 100,
               fps: float = 25.0, animation_format: str = "gif", dpi: float = 110) -> list[Path]:
    """Write every applicable figure of a run, and an animation, into ``directory``.

    Parameters
    ----------
    trajectory : Trajectory
        The run (`lagrangian.numerics.simulate`).
    eom : EquationsOfMotion
        Its equations.
    directory : str or Path
        Created when missing.
    animation : bool, optional
        Also write ``animation.gif`` (or ``.mp4``, ``animation_format``).
    formats : sequence of str, optional
        Image formats of each figure (``"png"``, ``"svg"``, ``"pdf"``...).
    kinds : sequence of str, optional
        The figures to write (default: `applicable_kinds`).
    frames : int, optional
        The animation's frame count.
    fps : float, optional
        The animation's frame rate.
    animation_format : {"gif", "mp4"}, optional
        The animation's format.
    dpi : float, optional
        The figures' resolution.

    Returns
    -------
    list of Path
        Files written, in order: ``time_series``, ``phase``, ``apex_sphere``, ``nutation``,
        ``drift``, ``reaction_O`` (each in every format), then ``animation.gif``.

    Raises
    ------
    OutputError
        A folder or file that cannot be written (older files are left intact), an unknown
        format or kind, or matplotlib missing (``pip install 'lagrangian[plot]'``).
    """
    formats = [f.lower().lstrip(".") for f in formats]
    for fmt in formats:
        if fmt not in IMAGE_FORMATS:
            raise OutputError(f"Unknown image format `{fmt}`.", fix="use one of " + ", ".join(IMAGE_FORMATS))
    suffix = "." + animation_format.lower().lstrip(".")
    if animation and suffix not in FORMATS:
        raise OutputError(f"Unknown animation format `{animation_format}`.", fix="use gif (or mp4 with ffmpeg)")
    chosen = tuple(kinds) if kinds is not None else applicable_kinds(trajectory, eom)
    for kind in chosen:
        if kind not in KINDS:
            raise OutputError(f"Unknown figure `{kind}`.", fix="choose among " + ", ".join(KINDS))
    directory = Path(directory)
    try:
        directory.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise OutputError(f"Cannot create the folder `{directory}` for the plots: {exc.strerror or exc}.",
                          fix="choose a folder you can write to") from None
    written: list[Path] = []
    for kind in chosen:
        fig = plot_trajectory(trajectory, eom, kind)
        stem = figure_name(kind, eom)
        for fmt in formats:
            written.append(save_figure(fig, directory / f"{stem}.{fmt}", dpi=dpi))
    if animation:
        written.append(animate(trajectory, eom, directory / f"animation{suffix}", frames=frames, fps=fps))
    return written
