"""`view(motion)`: the 3-D view of a model at rest or of its motion, as one offline HTML page.

The result, a `View`, writes the page (`View.html`, `View.save`), shows itself in Jupyter
(`_repr_html_`: the page in an ``<iframe srcdoc>``, which JupyterLab and VS Code display
without any kernel extension, with no network access), and gives a still picture
(`View.png`: a headless Chromium screenshot of the page, or matplotlib's drawing of the same
scene where no Chromium is installed).
"""

from __future__ import annotations

import html as html_lib
import os
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from .._atomic import write_atomic
from ..dynamics import EquationsOfMotion
from ..errors import OutputError
from ..model import Model, load_model
from ..numerics import Trajectory
from ._build import MAX_FRAMES, Motion, build_scene
from ._scene import Scene

__all__ = ["View", "at_rest", "motion_of", "view"]


@dataclass(frozen=True)
class View:
    """A 3-D view: its `Scene` and how to show it (see the module docstring).

    Parameters
    ----------
    scene : Scene
        What is drawn.
    """

    scene: Scene

    def html(self) -> str:
        """One self-contained HTML page: three.js, the viewer and the scene inline; it requests nothing.

        Returns
        -------
        str
            The page.
        """
        from .html import page

        return page(self.scene)

    def save(self, path: str | os.PathLike[str]) -> Path:
        """Write the page to ``path`` atomically (an older file is replaced only by a complete one).

        Parameters
        ----------
        path : str or PathLike
            The file to write.

        Returns
        -------
        Path
            The path written.
        """
        path = Path(path)
        try:
            write_atomic(path, self.html())
        except OSError as exc:
            raise OutputError(f"Cannot write `{path}`: {exc.strerror or exc}.",
                              fix="check that the folder exists and is writable; the old file, if any, is unchanged") \
                from None
        return path

    def png(self, *, width: int = 800, height: int = 600, time: float | None = None, browser: bool | None = None) -> bytes:
        """A still picture at ``time``: Chromium's screenshot of the page, else matplotlib's drawing of the scene.

        Parameters
        ----------
        width : int, optional
            In pixels.
        height : int, optional
            In pixels.
        time : float, optional
            The time shown (default: the start).
        browser : bool, optional
            ``browser=False`` forces matplotlib, ``True`` Chromium.

        Returns
        -------
        bytes
            The PNG.
        """
        from ._still import still_png

        return still_png(self.scene, width=width, height=height, time=time, browser=browser)

    def _repr_html_(self) -> str:
        """The page in an iframe (``srcdoc``, scripts allowed, no same-origin access): works offline in
        JupyterLab, Jupyter Notebook and VS Code, with no extension to install."""
        return (f'<iframe srcdoc="{html_lib.escape(self.html(), quote=True)}" '
                'style="width: 100%; height: 560px; border: 1px solid #ddd;" sandbox="allow-scripts" '
                f'title="{html_lib.escape(self.scene.title, quote=True)}" loading="eager"></iframe>')


def motion_of(trajectory: Trajectory, model: Model, *, label: str | None = None, ghost: bool = False,
              beside: bool = False) -> Motion:
    """A trajectory as a `Motion` of ``model`` (its coordinates checked against the model's)."""
    names = tuple(c.name for c in model.coordinates)
    if tuple(trajectory.coordinates) != names:
        raise OutputError(f"The trajectory's coordinates ({', '.join(trajectory.coordinates)}) are not those of the "
                          f"model `{model.name}` ({', '.join(names)}).",
                          fix="view a trajectory with the model it was simulated from")
    return Motion(label or trajectory.model_name, np.asarray(trajectory.t, float), np.asarray(trajectory.q, float),
                  np.asarray(trajectory.qd, float), dict(trajectory.extra), ghost, beside)


def at_rest(model: Model, initial: Mapping[str, float] | None = None) -> Motion:
    """The model in its initial configuration (q_i(0), q̇_i(0); 0 where the model gives none)."""
    initial = dict(initial or {})
    q = np.array([[initial.get(c.name, c.initial if c.initial is not None else 0.0) for c in model.coordinates]])
    qd = np.array([[initial.get(c.name + "_dot", c.rate if c.rate is not None else 0.0) for c in model.coordinates]])
    return Motion(model.name, np.zeros(1), q.reshape(1, -1), qd.reshape(1, -1))


def _model(source: Any) -> Model:
    if isinstance(source, Model):
        return source
    if isinstance(source, (str, os.PathLike)):
        return load_model(source)
    if isinstance(source, EquationsOfMotion):
        return source.model
    raise OutputError(f"`{type(source).__name__}` is not a model.",
                      fix="give a Model, an EquationsOfMotion or a model file")


def view(motion: Any, model: Any = None, *, ghosts: Sequence[Trajectory] = (), beside: Trajectory | None = None,
         labels: Sequence[str] | None = None, traces: Sequence[str] | None = None,
         vectors: Sequence[str] | None = None, parameters: Mapping[str, float] | None = None,
         initial: Mapping[str, float] | None = None, title: str | None = None, lang: str = "en",
         max_frames: int = MAX_FRAMES) -> View:
    """The 3-D view of a model at rest, or of a simulated motion.

    Parameters
    ----------
    motion : Trajectory or Model or EquationsOfMotion or str
        A `Trajectory` (then ``model`` is its model), or a model (`Model`, `EquationsOfMotion`, a
        file) to see at rest in its initial configuration.
    model : Model or EquationsOfMotion or str, optional
        With a trajectory, its model: a `Model`, an `EquationsOfMotion` or a model file.
    ghosts : sequence of Trajectory, optional
        More trajectories of the same model drawn over the first, translucent (ensemble members).
    beside : Trajectory, optional
        A trajectory drawn beside the first (an optimal trajectory beside its replay).
    labels : sequence of str, optional
        Names of the runs (default: the model's name; ghosts numbered).
    traces : sequence of str, optional
        The points whose paths are drawn (point names, a body for its G, ``tip:BODY``); default: the
        particles and the tips of the bodies that turn about a point (the top's apex).
    vectors : sequence of str, optional
        The arrows shown at first: ``"V(P)"`` (velocity of P), ``"R_O"`` (a reaction column of the
        trajectory), a force's load name; every one available can be switched on in the page.
    parameters : mapping of str to float, optional
        Parameter values (default: the trajectory's, else the model's).
    initial : mapping of str to float, optional
        At rest: overrides of q_i(0), q̇_i(0).
    title : str, optional
        The page's title (default: the model's name).
    lang : {"en", "fr"}, optional
        The language of the labels.
    max_frames : int, optional
        The most frame times.

    Returns
    -------
    View
        ``html()``, ``save(path)``, ``png()``, and it displays itself in Jupyter.

    Examples
    --------
    >>> import lagrangian
    >>> v = lagrangian.view(lagrangian.lagrange_top())
    >>> v.scene.at_rest, [p.kind for p in v.scene.parts]
    (True, ['disk', 'rod', 'sphere'])
    """
    if isinstance(motion, Trajectory):
        if model is None:
            raise OutputError("A trajectory does not carry its model, and the view needs it.",
                              fix="give the model too: lagrangian.view(traj, eom) (or the model file)")
        found = _model(model)
        values = {p.name: p.value for p in found.parameters if p.value is not None}
        values.update(motion.parameters)
        values.update(parameters or {})
        names = list(labels or [])
        runs = [motion_of(motion, found, label=names[0] if names else None)]
        for k, ghost in enumerate(ghosts):
            label = names[k + 1] if len(names) > k + 1 else f"{found.name} ({k + 2})"
            runs.append(motion_of(ghost, found, label=label, ghost=True))
        if beside is not None:
            runs.append(motion_of(beside, found, label=names[-1] if len(names) > len(ghosts) + 1 else beside.model_name,
                                  beside=True))
    else:
        if ghosts or beside is not None:
            raise OutputError("Ghosts and a run beside are drawn with a motion; here there is only a model.",
                              fix="give the main trajectory first: lagrangian.view(traj, eom, ghosts=[...])")
        found = _model(motion if model is None else model)
        values = {p.name: p.value for p in found.parameters if p.value is not None}
        values.update(parameters or {})
        runs = [at_rest(found, initial)]
    values = {k: float(v) for k, v in values.items() if v is not None}
    return View(build_scene(found, runs, values, title=title or _title(found, lang), lang=lang, traces=traces,
                            vectors=vectors, max_frames=max_frames))


def _title(model: Model, lang: str) -> str:
    from ..model import in_language

    return in_language(model.title, lang) or model.name
