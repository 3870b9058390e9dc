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
from typing import TYPE_CHECKING

from ..dynamics import derive
from ..errors import OutputError, SimulationError
from ..model import Model
from ..output import format_for, report
from ._arguments.report import VERIFY_AUTO_MAX
from ._point import full_point
from ._settings import SettingError, parse_settings
from ._source import load_source

if TYPE_CHECKING:
    from ..numerics import Trajectory

__all__ = ["VERIFY_AUTO_MAX", "run"]



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



def _figures(eom, t_end: float, parameters: dict[str, float], initial: dict[str, float],
             lang: str) -> tuple[list, Trajectory]:
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
