"""``lagrangian view [MODEL] [TRAJ] [-o FILE.html|FILE.png] [--beside TRAJ] [--ghost TRAJ ...] [--set k=v]``.

The 3-D view (`lagrangian.view3d`) of a model at rest in its initial configuration, or of a
trajectory saved by ``lagrangian simulate -o traj.csv|.npz``: one offline HTML page (three.js
inline, nothing requested when it opens), or a still PNG (``-o view.png``: Chromium's picture
of the page, else matplotlib's drawing of the same scene).  Without ``-o`` the page goes to
standard output.
"""

from __future__ import annotations

import argparse
from pathlib import Path

from ..errors import OutputError
from ._settings import parse_settings
from ._source import load_source

__all__ = ["run"]


def run(args: argparse.Namespace) -> str | bytes:
    from ..numerics import load_trajectory
    from ..view3d import view

    model = load_source(args.model)
    suffix = Path(args.output).suffix.lower() if args.output else ".html"
    if suffix not in (".html", ".htm", ".png"):
        raise OutputError(f"`{args.output}`: the view is written as .html (the page) or .png (a still).",
                          fix="name the file view.html or view.png")
    parameters, initial = parse_settings(args.set, model)
    if args.trajectory is None:
        if args.beside or args.ghost:
            raise OutputError("--beside and --ghost are drawn with a trajectory; none is given.",
                              fix="give the main trajectory after the model: lagrangian view MODEL TRAJ --ghost T2")
        shown = view(model, parameters=parameters, initial=initial, traces=args.trace, vectors=args.vector,
                     lang=args.lang)
    else:
        shown = view(load_trajectory(args.trajectory), model,
                     ghosts=[load_trajectory(g) for g in args.ghost],
                     beside=load_trajectory(args.beside) if args.beside else None,
                     parameters=parameters or None, traces=args.trace, vectors=args.vector, lang=args.lang)
    if suffix == ".png":
        return shown.png(time=args.time)
    return shown.html()
