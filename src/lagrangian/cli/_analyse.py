"""``lagrangian analyse [MODEL.toml] [--set NAME=VALUE ...] [-o FILE]``: the top analysed as a textbook does."""

from __future__ import annotations

import argparse
import math

from ..analysis import analyse_top
from ..dynamics import derive
from ..errors import SimulationError
from ..numerics import simulation_check
from ..output import simulation_check_text, top_analysis_text
from ._settings import parse_settings
from ._source import load_source

__all__ = ["run"]


def run(args: argparse.Namespace) -> str:
    model = load_source(args.model)
    parameters, initial = parse_settings(args.set, model)
    eom = derive(model)
    analysis = analyse_top(eom, parameters=parameters, initial=initial)
    text = top_analysis_text(analysis, eom)
    if args.simulate is not None:
        if not (math.isfinite(args.simulate) and args.simulate > 0):
            raise SimulationError(f"--simulate {args.simulate:g}: the number of nutation periods must be positive.",
                                  fix="e.g. --simulate 3")
        text += simulation_check_text(simulation_check(eom, analysis, periods=args.simulate), eom)
    return text
