"""``lagrangian report [MODEL] [--lang fr|en] [--format html|tex|md|pdf] [--simulate T_END] [--set k=v] [-o FILE]``.

The derivation step by step, in the order of the course's "démarche d'application"
(`lagrangian.output.report`).  MODEL is a model file, or a model of the zoo by name
(``zoo:planar_chain:40``, ``zoo:lagrange_top``).  The format is ``--format``, else the
suffix of ``-o FILE``, else Markdown.  The Newton–Euler cross-check is included up to
`VERIFY_AUTO_MAX` coordinates (``--verify`` / ``--no-verify`` decide otherwise);
``--simulate T_END`` adds the figures of a simulated motion (matplotlib needed);
``--small-motions --at theta=0`` the small motions about that point (``[operating_point]`` by
default): the linearized equations, the pulsations and the stability argument; ``--set``
changes parameter values and initial conditions in the report and in the simulation.
With ``-o``, `Report.save` writes the figures of a LaTeX or Markdown report beside it as
PNG files.  The report's notes name ``lagrangian derive MODEL --json`` (with this MODEL) for the
equations that are too long to print in full.
"""

from __future__ import annotations

import argparse
import dataclasses

from ..dynamics import derive
from ..errors import OutputError, SimulationError
from ..model import Model
from ..output import format_for, report
from ._point import add_point_options, full_point
from ._settings import SettingError, add_set_option, number_argument, parse_settings
from ._source import MODEL_HELP, load_source

__all__ = ["register", "run", "VERIFY_AUTO_MAX"]

SUMMARY = "write the derivation step by step, as the course does it (constraints, parameters,\n" \
          "V*, T and U, Q_i, L(q_i), integrals, Newton–Euler check), in HTML, LaTeX or Markdown"

#: Largest number of coordinates for which the Newton–Euler check runs unless asked not to
#: (it takes about 30 s for a 40-link chain, where the rest of the report takes a few seconds).
VERIFY_AUTO_MAX = 12


def _with_settings(model: Model, settings: list[str]) -> tuple[Model, dict[str, float], dict[str, float]]:
    """``model`` with the ``--set`` values as its parameter values and initial conditions."""
    parameters, initial = parse_settings(settings, model)
    if not parameters and not initial:
        return model, parameters, initial
    params = tuple(dataclasses.replace(p, value=parameters[p.name]) if p.name in parameters else p
                   for p in model.parameters)
    coords = tuple(dataclasses.replace(c, initial=initial.get(c.name, c.initial),
                                       rate=initial.get(c.name + "_dot", c.rate)) for c in model.coordinates)
    return dataclasses.replace(model, parameters=params, coordinates=coords), parameters, initial



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
    r.set_defaults(run=run)


def _figures(eom, t_end: float, parameters: dict[str, float], initial: dict[str, float],  # type: ignore[no-untyped-def]
             lang: str) -> tuple[list, object]:
    from ..numerics import simulate
    from ..plotting import applicable_kinds, figure_caption, plot_trajectory

    missing = [c.name for c in eom.model.coordinates if c.initial is None and c.name not in (initial or {})]
    if missing:
        raise SimulationError(f"Cannot simulate: coordinate `{missing[0]}` has no initial value.",
                              fix=f"give it one in the model file, or --set {missing[0]}=VALUE")
    traj = simulate(eom, t_end, initial=initial, parameters=parameters, n_out=801)
    return [(figure_caption(kind, eom, lang), plot_trajectory(traj, eom, kind, lang=lang))
            for kind in applicable_kinds(traj, eom)], traj


def run(args: argparse.Namespace) -> str | None:
    model, parameters, initial = _with_settings(load_source(args.model), args.set)
    eom = derive(model)
    fmt = args.format or (format_for(args.output) if args.output else "md")
    check = args.verify if args.verify is not None else len(eom.coordinates) <= VERIFY_AUTO_MAX
    figures, motion = _figures(eom, args.simulate, parameters, initial, args.lang) if args.simulate is not None \
        else ([], None)
    small = None
    if args.small_motions:
        from ..analysis import linearize

        small = linearize(eom, full_point(args.at, model))
    elif args.at:
        raise SettingError("`--at` gives the point of the small motions, which only `--small-motions` reports.",
                           fix="add --small-motions, or drop --at")
    # The notes name the command that prints every equation in full: lagrangian derive MODEL --json.
    r = report(eom, lang=args.lang, verification=check, figures=figures, source=args.model or "", small_motions=small,
               view=args.view, motion=motion,
               events=motion.events if motion is not None else ())
    if not args.output:
        if fmt == "pdf":
            raise OutputError("A PDF report is written to a file, not to the terminal.",
                              fix="give the file: lagrangian report MODEL --format pdf -o report.pdf")
        return r.render(fmt)
    r.save(args.output, fmt)  # the figures of a .tex or .md report as PNG files beside it
    return None
