"""``lagrangian derive``: its arguments (its work: `lagrangian.cli._derive`)."""

from __future__ import annotations

import argparse

from .common import MODEL_HELP, command

__all__ = ["SUMMARY", "register"]

SUMMARY = "derive and print the equations of motion of a model file\n" \
          "(with no file: the course's heavy symmetric top, the Lagrange top)"


def register(sub: argparse._SubParsersAction) -> None:
    d = sub.add_parser(
        "derive", help="derive the equations of motion of a model",
        description="Derive T, U, the generalized forces, the Lagrange equations L(q_i), the first integrals "
                    "and the matrix form M q'' = F of a model, and print them in the course's notation.",
    )
    d.add_argument("model", nargs="?", help=MODEL_HELP)
    fmt = d.add_mutually_exclusive_group()
    fmt.add_argument("--latex", action="store_true", help="print a LaTeX document instead of text")
    fmt.add_argument("--json", action="store_true",
                     help="print the versioned JSON document (schema lagrangian.derive/1, docs/derive-json.md)")
    size = d.add_mutually_exclusive_group()
    size.add_argument("--expanded", action="store_true",
                      help="a robot (recursive form): print every expression of the course's view in full instead "
                           "of ⟨24 terms⟩ (slow: 40–50 s at 7 joints)")
    size.add_argument("--intermediates", action="store_true",
                      help="a robot (recursive form): print T, U, M and F over the named intermediates of the "
                           "recursive Newton–Euler and composite-rigid-body algorithms, and each intermediate")
    d.add_argument("-o", "--output", metavar="FILE", help="write to FILE (atomically) instead of standard output")
    d.set_defaults(run=command("derive"))
