"""``lagrangian simulate``: its arguments (its work: `lagrangian.cli._simulate`)."""

from __future__ import annotations

import argparse

from .common import MODEL_HELP, add_input_options, add_set_option, command, number_argument

__all__ = ["METHODS", "STABILIZATIONS", "SUMMARY", "register"]

#: `lagrangian.numerics.METHODS` and `STABILIZATIONS`, written out so that parsing needs no numerics
#: (a test holds them equal).
METHODS = ("dop853", "gauss-legendre", "RK45", "RK23", "DOP853", "Radau", "BDF", "LSODA")
STABILIZATIONS = ("projection", "baumgarte", "both", "none")

SUMMARY = "simulate a model from its initial state; report the drift of every first integral\n" \
          "(CSV or NPZ output, plots and an animation with --plot [DIR])"


def register(sub: argparse._SubParsersAction) -> None:
    s = sub.add_parser(
        "simulate", help="integrate the equations of motion",
        description="Integrate M q'' = F from the model's initial state (compiled C, no Python per step) and "
                    "report the conservation of every first integral. The trajectory (t, q, q', q'', the first "
                    "integrals, T, U) goes to --out, or as CSV to standard output.",
    )
    s.add_argument("model", nargs="?", help=MODEL_HELP)
    s.add_argument("--t-end", type=number_argument, default=10.0, metavar="T", help="end time (default 10)")
    s.add_argument("--t-start", type=number_argument, default=0.0, metavar="T0", help="start time (default 0)")
    add_set_option(s)
    add_input_options(s)
    s.add_argument("--method", choices=METHODS, default="dop853",
                   help="dop853 (adaptive, default), gauss-legendre (fixed step, symplectic) or a SciPy method")
    s.add_argument("--rtol", type=number_argument, default=1e-10, help="relative tolerance (default 1e-10)")
    s.add_argument("--atol", type=number_argument, default=1e-10, help="absolute tolerance (default 1e-10)")
    s.add_argument("--dt", type=number_argument, default=None,
                   help="fixed step (gauss-legendre: default 1/10 of the output spacing, halved while too long for "
                        "the motion; rounded down to divide the spacing when smaller, used as given when larger; "
                        "dop853: fixed steps)")
    s.add_argument("--n-out", type=int, default=1001, metavar="N",
                   help="number of output times (default 1001; refused when it would not fit in memory)")
    s.add_argument("--event", action="append", default=[], metavar="EXPR",
                   help="record the times where EXPR crosses zero, e.g. --event theta_dot (repeatable)")
    s.add_argument("--stop-when", action="append", default=[], metavar="EXPR",
                   help="stop at the first zero crossing of EXPR, e.g. --stop-when 'theta - 1.2'")
    s.add_argument("--stiffness-check", action=argparse.BooleanOptionalAction, default=True,
                   help="dop853: stop with an error when the equations turn out stiff (Hairer's test: the step "
                        "limited by stability, not accuracy), where --method Radau is the tool (default: on; "
                        "--no-stiffness-check integrates a knowingly stiff problem with dop853 all the same)")
    s.add_argument("--tolerance", type=number_argument, default=None, metavar="TOL",
                   help="warn when a first integral drifts by more than TOL (relative, > 0; default "
                        "min(1e3 rtol, 1e-6), 1e-6 for gauss-legendre)")
    s.add_argument("--stabilization", choices=STABILIZATIONS, default=None,
                   help="models with complementary constraints: how the constraint drift is controlled "
                        "(default projection with explicit methods, baumgarte with Radau, BDF, LSODA)")
    s.add_argument("-o", "--out", metavar="FILE", help="write the trajectory to FILE (.csv or .npz), atomically")
    s.add_argument("--plot", metavar="DIR", nargs="?", const="",
                   help="write plots and an animation into DIR (default: MODEL_plots/ after the model file's "
                        "stem, or plots/ for the built-in top); put a bare --plot after the model file")
    s.add_argument("--view", metavar="FILE.html",
                   help="write the 3-D view of the motion: one offline HTML page (three.js inline) to play, scrub "
                        "and turn around (see `lagrangian view`)")
    s.add_argument("--animation", choices=("gif", "mp4", "none"), default="gif",
                   help="the animation --plot writes (default gif; mp4 needs ffmpeg, found on the PATH or "
                        "through the imageio-ffmpeg package)")
    s.add_argument("--reactions", action=argparse.BooleanOptionalAction, default=None,
                   help="add the constraint reactions (e.g. R_O from m γ(G) = P + R_O) as columns R_O_x0... "
                        "(R0 components; default: on, except for a robot derived in the recursive form, where "
                        "the only one is the ground's wrench on the arm and its expanded formula costs seconds)")
    s.add_argument("--progress", action=argparse.BooleanOptionalAction, default=None,
                   help="show a progress bar (default: when standard error is a terminal)")
    s.set_defaults(run=command("simulate"))
