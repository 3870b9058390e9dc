"""``lagrangian equilibria``: its arguments (its work: `lagrangian.cli._equilibria`)."""

from __future__ import annotations

import argparse

from .common import MODEL_HELP, add_set_option, command

__all__ = ["SCHEMA", "SUMMARY", "register"]

#: Name of the JSON document ``--json`` writes (version 1).
SCHEMA = "lagrangian.equilibria"

SUMMARY = "every static equilibrium (closed form with its condition of existence, or numeric)"


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser(
        "equilibria", help="static equilibria of an autonomous model",
        description="Find every position of equilibrium q* (q̇ = 0, q̈ = 0: F(q*, 0) + Aᵀλ = 0 and the holonomic "
                    "constraints): in closed form when SymPy can, with the condition of existence, and by a "
                    "multi-start numeric search over the coordinates' ranges otherwise. Angles range over (−π, π]; "
                    "other coordinates need --range for the numeric search.")
    p.add_argument("model", nargs="?", help=MODEL_HELP)
    add_set_option(p)
    p.add_argument("--range", dest="range", action="append", default=[], metavar="NAME=a:b",
                   help="where to search coordinate NAME (numbers, a < b), e.g. x=-1:1; repeat for several")
    p.add_argument("--sweep", metavar="NAME=a:b:step", default=None,
                   help="follow the closed-form equilibria and their stability as parameter NAME goes from a to b; "
                        "print where a branch appears or changes stability (a pitchfork)")
    p.add_argument("--plot", metavar="DIR", default=None,
                   help="with --sweep: write DIR/bifurcation.png (q* against NAME, solid stable, dashed unstable)")
    p.add_argument("--lang", choices=("en", "fr"), default="en", help="language of the figure (default en)")
    p.add_argument("--json", action="store_true", help=f"print the JSON document `{SCHEMA}` version 1")
    p.add_argument("-o", "--output", metavar="FILE", help="write the result to FILE (atomically)")
    p.set_defaults(run=command("equilibria"))
