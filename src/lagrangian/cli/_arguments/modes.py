"""``lagrangian modes``: its arguments (its work: `lagrangian.cli._modes`)."""

from __future__ import annotations

import argparse

from .common import MODEL_HELP, add_parameter_option, add_point_options, command

__all__ = ["ANIMATIONS_MAX", "SUMMARY", "register"]

#: Most modes ``--animate`` draws (each GIF takes about a second).
ANIMATIONS_MAX = 6

SUMMARY = "eigenvalues, frequencies, damping ratios and mode shapes about a point, the stability\n" \
          "verdict; --sweep v=0:10:0.01 finds where stability changes, --plot DIR draws them"


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser(
        "modes", help="modes and stability of the small motions, optionally along a parameter",
        description="Linearize about the point (as `lagrangian linearize`), then give each eigenvalue of A with "
                    "its natural frequency, damping ratio, period and mode shape, the pulsations of a "
                    "conservative system (K phi = omega^2 M phi) and the stability verdict with its reason. "
                    "--sweep NAME=a:b:step recomputes the eigenvalues for NAME from a to b and finds where "
                    "stability changes; --plot DIR draws them against NAME, and the mode shapes.")
    p.add_argument("model", nargs="?", help=MODEL_HELP)
    add_point_options(p, symbolic=False)
    add_parameter_option(p)
    p.add_argument("--sweep", metavar="NAME=a:b:step", default=None,
                   help="follow the eigenvalues as the parameter NAME goes from a to b by step (b included)")
    p.add_argument("--plot", metavar="DIR", default=None,
                   help="write eigenvalues.png (with --sweep) and mode_shapes.png into DIR (created when missing)")
    p.add_argument("--animate", action="store_true",
                   help=f"with --plot: also write mode_K.gif, the system moving in each mode K (a conjugate pair "
                        f"once; at most {ANIMATIONS_MAX}), amplitude 0.1")
    p.add_argument("--lang", choices=("en", "fr"), default="en", help="language of the figures (default en)")
    p.add_argument("--json", action="store_true",
                   help="print the versioned JSON document (schema lagrangian.linearize/1, with `modes` and `sweep`)")
    p.add_argument("-o", "--output", metavar="FILE", help="write to FILE (atomically) instead of standard output")
    p.set_defaults(run=command("modes"))
