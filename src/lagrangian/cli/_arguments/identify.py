"""``lagrangian identify``: its arguments (its work: `lagrangian.cli._identify`)."""

from __future__ import annotations

import argparse

from .common import MODEL_HELP, add_set_option, command

__all__ = ["SUMMARY", "register"]

SUMMARY = "fit parameters to a measured motion (--fit m,l): estimates, standard errors,\n" \
          "identifiable combinations"


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser(
        "identify", help="fit parameters to a measured motion",
        description="Fit parameters of the model to a measured motion: by the inverse-dynamics regressor (linear "
                    "least squares, base parameters by QR) when every coordinate is measured and the equations are "
                    "linear in the parameters, else by simulating the motion (single or multiple shooting, "
                    "nonlinear least squares with forward sensitivities).")
    p.add_argument("model", help=MODEL_HELP)
    p.add_argument("data", help="the measurements: a CSV file with a header line (t, coordinates, rates NAME_dot, "
                                "accelerations NAME_ddot, inputs)")
    p.add_argument("--fit", required=True, metavar="NAMES", help="the parameters to fit, separated by commas: m,l")
    p.add_argument("--route", choices=("auto", "regressor", "shooting"), default="auto",
                   help="how to fit (default auto: the regressor when it applies)")
    add_set_option(p)
    p.add_argument("--input", dest="inputs", action="append", default=[], metavar="NAME=VALUE",
                   help="the constant value of an input that the data does not hold (repeat for several)")
    p.add_argument("--guess", action="append", default=[], metavar="NAME=VALUE",
                   help="first value of a fitted parameter for shooting (default the model's)")
    p.add_argument("--columns", metavar="NAMES", help="the data columns to use, separated by commas (default all)")
    p.add_argument("--segments", type=int, metavar="N",
                   help="shooting segments (1: single shooting; default about one per 20 samples, at most 20)")
    p.add_argument("--window", type=int, default=21, metavar="W",
                   help="samples of the local polynomial fits that give q' and q'' from q (odd; default 21)")
    p.add_argument("--order", type=int, default=4, metavar="D", help="their degree (default 4)")
    p.add_argument("--base", action="store_true",
                   help="when the parameters are identifiable only in combinations, fit the combinations (the base "
                        "parameters) instead of refusing")
    p.add_argument("--json", action="store_true", help="print the JSON document (schema lagrangian.identify/1)")
    p.add_argument("-o", "--output", metavar="FILE", help="write to FILE (atomically) instead of standard output")
    p.set_defaults(run=command("identify"))
