"""``lagrangian verify``: its arguments (its work: `lagrangian.cli._verify`)."""

from __future__ import annotations

import argparse

from .common import MODEL_HELP, add_set_option, command, number_argument

__all__ = ["SUMMARY", "register"]

SUMMARY = "check the Lagrange equations against the Newton–Euler theorems (symbolically,\n" \
          "and along a simulated motion with --simulate); print the constraint reactions"


def register(sub: argparse._SubParsersAction) -> None:
    v = sub.add_parser(
        "verify", help="check the Lagrange equations by Newton-Euler",
        description="Project the resultant and moment theorems of every body on the directions of each "
                    "coordinate (the partial velocities) and show that they give the Lagrange equations "
                    "L(q_i), term for term; print the constraint reactions from the resultant theorem. With "
                    "--simulate, also evaluate the theorems along a simulated motion.",
    )
    v.add_argument("model", nargs="?", help=MODEL_HELP)
    v.add_argument("--simulate", type=number_argument, metavar="T_END", default=None,
                   help="also check along a motion simulated from t = 0 to T_END (--set changes its values)")
    add_set_option(v)
    v.add_argument("--n-out", type=int, default=201, metavar="N", help="states checked with --simulate (default 201)")
    v.add_argument("-o", "--output", metavar="FILE", help="write the report to FILE (atomically)")
    v.set_defaults(run=command("verify"))
