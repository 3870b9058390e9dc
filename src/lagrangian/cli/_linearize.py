"""``lagrangian linearize MODEL --at theta=3.14159 [--at x=0] [--set NAME=VALUE] [--inputs tau] [--symbolic v]
[--json] [-o FILE]``: the equations of motion linearized about an equilibrium or a steady motion.

Prints M, D, G, K, N (M δq̈ + (D + G) δq̇ + (K + N) δq = B u) and the state space ẋ = A x + B u,
with the eigenvalues and the stability verdict when every parameter has a value; ``--json``
prints the versioned document ``lagrangian.linearize`` (docs/small-motions.md).
"""

from __future__ import annotations

import argparse
import json

from .. import __version__
from ..dynamics import derive
from ..output import linearize_document
from ._linear_text import render_linearization
from ._point import add_parameter_option, add_point_options, linearize_from_args
from ._source import MODEL_HELP, load_source

__all__ = ["register", "run"]

SUMMARY = "linearize about an equilibrium or a steady motion (--at theta=0):\n" \
          "M, D, G, K, N, the state space A, B, eigenvalues and the stability verdict"


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser(
        "linearize", help="linearize the equations about an equilibrium or a steady motion",
        description="Linearize M q'' = F about a point where the motion is steady (every coordinate given a value "
                    "with --at or by the model's [operating_point]; rates 0 unless given): the second-order form "
                    "M dq'' + (D + G) dq' + (K + N) dq = B u (D, K symmetric; G gyroscopic, N circulatory, both "
                    "skew) and the state space x' = A x + B u. A point that is not an equilibrium or a steady "
                    "motion is refused, with its residual force. Models with complementary constraints are "
                    "reduced to independent coordinates and speeds (the choice is printed).")
    p.add_argument("model", nargs="?", help=MODEL_HELP)
    add_point_options(p)
    add_parameter_option(p)
    p.add_argument("--hold", action="store_true",
                   help="the inputs not given with --at take the values that hold the point at rest (a robot's "
                        "gravity-compensating joint torques), printed with the point")
    p.add_argument("--json", action="store_true",
                   help="print the versioned JSON document (schema lagrangian.linearize/1, docs/small-motions.md)")
    p.add_argument("-o", "--output", metavar="FILE", help="write to FILE (atomically) instead of standard output")
    p.set_defaults(run=run)


def run(args: argparse.Namespace) -> str:
    model = load_source(args.model)
    eom = derive(model)
    lin = linearize_from_args(args, model, eom)
    stability = modes = None
    if not lin.symbols:
        stability, modes = lin.stability(), lin.modes()
    if args.json:
        doc = linearize_document(lin, source=model.source, package_version=__version__, stability=stability,
                                 modes=modes)
        return json.dumps(doc, indent=2, ensure_ascii=False) + "\n"
    return render_linearization(lin, stability, modes)
