"""``lagrangian sweep``: its arguments (its work: `lagrangian.cli._sweep`)."""

from __future__ import annotations

import argparse

from .common import MODEL_HELP, add_set_option, command, number_argument

__all__ = ["SUMMARY", "register"]

SUMMARY = "integrate a grid of initial states or parameters on every core (or a Dask cluster);\n" \
          "summaries to Zarr/NetCDF, a 2-D map or a min/max diagram with --plot; --resume after Ctrl-C"


def register(sub: argparse._SubParsersAction) -> None:
    s = sub.add_parser(
        "sweep", help="integrate a grid of initial states or parameters (an ensemble)",
        description="Integrate one motion per point of a grid over coordinates, rates and parameters, in compiled "
                    "batches on every core (or on a Dask cluster), keeping per member the min, max and final "
                    "state, the first time of each event, the drift of each first integral and a status "
                    "(ok, stopped, blow-up, step-limit, singular). Ctrl-C keeps the finished members in the "
                    "Zarr store; --resume finishes it.")
    s.add_argument("model", nargs="?", help=MODEL_HELP)
    s.add_argument("--grid", action="append", default=[], metavar="NAME=START:STOP:COUNT",
                   help="a grid axis over a coordinate (theta1), a rate (theta1_dot) or a parameter (g); repeatable")
    s.add_argument("--t-end", type=number_argument, default=10.0, metavar="T", help="end time (default 10)")
    s.add_argument("--t-start", type=number_argument, default=0.0, metavar="T0", help="start time (default 0)")
    add_set_option(s)
    s.add_argument("--method", choices=("dop853", "gauss-legendre"), default="dop853")
    s.add_argument("--stiffness-check", action=argparse.BooleanOptionalAction, default=True,
                   help="dop853: stop a member whose equations turn out stiff (status `stiff`) rather than let it "
                        "crawl (default: on)")
    s.add_argument("--rtol", type=number_argument, default=1e-10, help="relative tolerance (default 1e-10)")
    s.add_argument("--atol", type=number_argument, default=1e-10, help="absolute tolerance (default 1e-10)")
    s.add_argument("--dt", type=number_argument, default=None, help="fixed step (gauss-legendre)")
    s.add_argument("--n-out", type=int, default=101, metavar="N",
                   help="output times the summaries are taken over (default 101)")
    s.add_argument("--event", action="append", default=[], metavar="EXPR",
                   help="record the first time EXPR crosses zero (e.g. theta_dot); `flip`: an angle passing ±pi")
    s.add_argument("--stop-when", action="append", default=[], metavar="EXPR",
                   help="end each member at the first zero crossing of EXPR (or `flip`)")
    s.add_argument("--out", metavar="FILE", required=True, help="results: a Zarr store (.zarr) or NetCDF (.nc); for a model with contacts NetCDF or CSV")
    s.add_argument("--min-speed", type=number_argument, default=0.0, metavar="V",
                   help="a model with contacts: count as bounces the impacts with an approach speed >= V")
    s.add_argument("--plot", metavar="IMAGE", help="draw the 2-D map (two axes) or min/max diagram (one axis)")
    s.add_argument("--workers", type=int, default=None, metavar="N", help="local threads (default: every core)")
    s.add_argument("--scheduler", metavar="ADDRESS", help="run on a Dask cluster, e.g. tcp://HOST:8786")
    s.add_argument("--backend", choices=("c", "jax"), default="c",
                   help="c: the compiled batch integrator (default); jax: the JAX export with diffrax, for a GPU "
                        "(pip install 'lagrangian[jax]'; no events, no --scheduler)")
    s.add_argument("--resume", action="store_true", help="finish the pending members of an interrupted --out store")
    s.add_argument("--progress", action=argparse.BooleanOptionalAction, default=None,
                   help="show a progress bar over members (default: when standard error is a terminal)")
    s.set_defaults(run=command("sweep"))
