"""``lagrangian report``: its arguments (its work: `lagrangian.cli._report`)."""

from __future__ import annotations

import argparse

from .common import MODEL_HELP, add_point_options, add_set_option, command, number_argument

__all__ = ["SUMMARY", "VERIFY_AUTO_MAX", "register"]

#: Largest number of coordinates for which the Newton–Euler check runs unless asked not to
#: (it takes about 30 s for a 40-link chain, where the rest of the report takes a few seconds).
VERIFY_AUTO_MAX = 12

SUMMARY = "write the derivation step by step, as the course does it (constraints, parameters,\n" \
          "V*, T and U, Q_i, L(q_i), integrals, Newton–Euler check), in HTML, LaTeX or Markdown"


def register(sub: argparse._SubParsersAction) -> None:
    r = sub.add_parser(
        "report", help="write the step-by-step derivation (HTML, LaTeX, PDF or Markdown)",
        description="Write the derivation of a model in the order of the course's 'démarche d'application': "
                    "the principal constraints and why they are perfect, the principal parameters, the virtual "
                    "velocity field, T and U_P with their formulas, each Q_i by virtual power, each L(q_i) with "
                    "its partial derivatives, the complementary equations, the first integrals and the "
                    "Newton-Euler cross-check. HTML is one offline page (MathML); LaTeX compiles with pdflatex; "
                    "Markdown uses $...$ mathematics.",
    )
    r.add_argument("model", nargs="?", help=MODEL_HELP)
    r.add_argument("--lang", choices=("fr", "en"), default="fr", help="language (default: fr, the course's)")
    r.add_argument("--format", choices=("html", "tex", "md", "pdf"), default=None,
                   help="output format (default: from the suffix of -o, else md); pdf compiles the LaTeX with "
                        "pdflatex or lualatex and needs -o")
    r.add_argument("--verify", action=argparse.BooleanOptionalAction, default=None,
                   help=f"include the Newton-Euler cross-check (default: up to {VERIFY_AUTO_MAX} coordinates)")
    r.add_argument("--simulate", type=number_argument, metavar="T_END", default=None,
                   help="add the figures of a motion simulated from the model's initial state to T_END")
    add_set_option(r)
    r.add_argument("--small-motions", action="store_true",
                   help="add the section on the small motions about the point given by --at (or the model's "
                        "[operating_point]): linearized equations, pulsations, stability")
    add_point_options(r, inputs=False, symbolic=False)
    r.add_argument("--view", action=argparse.BooleanOptionalAction, default=True,
                   help="the system in 3-D in the statement, and the motion with --simulate (HTML: interactive, "
                        "LaTeX/PDF: a still picture; default: on)")
    r.add_argument("-o", "--output", metavar="FILE", help="write to FILE (atomically) instead of standard output")
    r.set_defaults(run=command("report"))
