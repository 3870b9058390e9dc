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
from ._settings import add_set_option, number_argument, parse_settings
from ._source import MODEL_HELP, load_source

__all__ = ["register", "run"]

SUMMARY = "the 3-D view of a model at rest or of a saved trajectory: one offline HTML page\n" \
          "(play, time slider, orbit, frames, labels, traces, vectors), or a PNG still"


def register(sub: argparse._SubParsersAction) -> None:
    v = sub.add_parser(
        "view", help="write the 3-D view of a model or a trajectory (offline HTML, or PNG)",
        description="Write the 3-D view of a model at rest (its initial configuration, frames, points and angles "
                    "labelled) or of a trajectory saved by `lagrangian simulate -o traj.csv|.npz`: one HTML file "
                    "with three.js inline that opens offline, with play/pause, a time slider, the playback speed, "
                    "orbit/pan/zoom, and toggles for frames, labels, traces and vectors.")
    v.add_argument("model", nargs="?", help=MODEL_HELP)
    v.add_argument("trajectory", nargs="?", help="a trajectory file (.csv or .npz) of this model; default: the "
                                                 "model at rest")
    v.add_argument("--beside", metavar="TRAJ", help="a second trajectory drawn beside the first (an optimal "
                                                    "trajectory beside its replay)")
    v.add_argument("--ghost", metavar="TRAJ", action="append", default=[],
                   help="a trajectory drawn over the first, translucent (an ensemble member); repeatable")
    v.add_argument("--trace", metavar="POINT", action="append", default=None,
                   help="draw the path of POINT (a point, a body's name for its G, tip:BODY); repeatable; default: "
                        "the particles and the tips of the bodies turning about a point")
    v.add_argument("--vector", metavar="NAME", action="append", default=None,
                   help="show the vector NAME at first: V(P) (a velocity), R_O (a reaction column), a force's name; "
                        "repeatable")
    add_set_option(v)
    v.add_argument("--lang", choices=("fr", "en"), default="en", help="language of the title (default: en)")
    v.add_argument("--time", type=number_argument, default=None, metavar="T",
                   help="for a PNG: the time shown (default: the start)")
    v.add_argument("-o", "--output", metavar="FILE", help="write to FILE (.html, or .png for a still), atomically")
    v.set_defaults(run=run)


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
