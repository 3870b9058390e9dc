"""``lagrangian view``: its arguments (its work: `lagrangian.cli._view`)."""

from __future__ import annotations

import argparse

from .common import MODEL_HELP, add_set_option, command, number_argument

__all__ = ["SUMMARY", "register"]

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
    v.set_defaults(run=command("view"))
