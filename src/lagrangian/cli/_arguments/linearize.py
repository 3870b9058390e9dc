"""``lagrangian linearize``: its arguments (its work: `lagrangian.cli._linearize`)."""

from __future__ import annotations

import argparse

from .common import MODEL_HELP, add_parameter_option, add_point_options, command

__all__ = ["SUMMARY", "register"]

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
    p.set_defaults(run=command("linearize"))
