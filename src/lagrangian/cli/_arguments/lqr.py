"""``lagrangian lqr``: its arguments (its work: `lagrangian.cli._lqr`)."""

from __future__ import annotations

import argparse

from .common import MODEL_HELP, add_parameter_option, add_point_options, command

__all__ = ["SUMMARY", "register"]

SUMMARY = "the LQR state feedback u = u* - K (x - x*) about an equilibrium (--at theta=0):\n" \
          "gains, closed-loop eigenvalues; -o feedback.json for simulate --feedback"


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser(
        "lqr", help="the LQR state feedback about an equilibrium or a steady motion",
        description="Linearize about the point (--at, or the model's [operating_point]; the inputs not given take "
                    "the values that hold it), then minimize the integral of dx' Q dx + du' R du: the gain K of "
                    "u = u* - K (x - x*), from the continuous algebraic Riccati equation. A pair (A, B) that is not "
                    "stabilizable is refused, naming the mode the inputs cannot move.")
    p.add_argument("model", nargs="?", help=MODEL_HELP)
    add_point_options(p, symbolic=False)
    add_parameter_option(p)
    p.add_argument("--Q", dest="Q", metavar="SPEC",
                   help="state weights: a diagonal in state order (1,1,10,1) or named entries of the identity "
                        "(theta=10,x=2); default the identity")
    p.add_argument("--R", dest="R", metavar="SPEC", help="input weights, likewise (default the identity)")
    p.add_argument("--json", action="store_true",
                   help="print the feedback document (schema lagrangian.feedback/1) that -o writes")
    p.add_argument("-o", "--output", metavar="FILE",
                   help="write the feedback document to FILE (atomically), for `simulate --feedback FILE`")
    p.set_defaults(run=command("lqr"))
