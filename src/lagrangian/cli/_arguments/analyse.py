"""``lagrangian analyse``: its arguments (its work: `lagrangian.cli._analyse`)."""

from __future__ import annotations

import argparse

from .common import MODEL_HELP, add_set_option, command, number_argument

__all__ = ["SUMMARY", "register"]

SUMMARY = "analyse a heavy symmetric top (or any model whose coordinates are all cyclic but one):\n" \
          "U_eff, turning angles, nutation period, precession, apex curve; --simulate checks them"


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser(
        "analyse", help="analyse the motion of a heavy symmetric top",
        description="Eliminate the cyclic coordinates with their momenta (K, H) to get "
                    "E = ½ a(θ) θ̇² + U_eff(θ), then give the turning angles θ1, θ2, the nutation period, "
                    "the mean precession rate, the type of the apex curve (waves, loops, cusps), the "
                    "sleeping-top criterion and the steady precession rates, with the model's values.")
    p.add_argument("model", nargs="?", help=MODEL_HELP)
    add_set_option(p)
    p.add_argument("--simulate", metavar="PERIODS", type=number_argument, nargs="?", const=3.0,
                   help="check θ1, θ2, the nutation period and the mean precession against a simulation over "
                        "PERIODS nutation periods (default 3), the turning points located as events θ̇ = 0")
    p.add_argument("-o", "--output", metavar="FILE", help="write to FILE (atomically) instead of standard output")
    p.set_defaults(run=command("analyse"))
