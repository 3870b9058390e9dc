"""The options several commands share, and the deferred ``run`` of a command.

Light by design: argparse and the standard library only, so that building the parser costs
milliseconds whatever the command (see the package docstring).
"""

from __future__ import annotations

import argparse
import importlib
import math
import re
from collections.abc import Callable

__all__ = [
    "MODEL_HELP",
    "OUTPUT_HELP",
    "add_input_options",
    "add_parameter_option",
    "add_point_options",
    "add_set_option",
    "command",
    "number_argument",
    "plain_number",
]

MODEL_HELP = ("model file (TOML), a robot's URDF file (.urdf), or a zoo model by name: zoo:lagrange_top, "
              "zoo:planar_chain:N, zoo:spatial_chain:N, zoo:relative_chain:N, zoo:serial_arm:N; "
              "default: the seed's Lagrange top")
OUTPUT_HELP = "write to FILE (atomically) instead of standard output"


def command(name: str) -> Callable[[argparse.Namespace], object]:
    """The ``run`` of the module ``cli/_<name>.py``, imported on the first call, not before."""
    def run(args: argparse.Namespace) -> object:
        return importlib.import_module(f"lagrangian.cli._{name}").run(args)

    run.__name__ = run.__qualname__ = f"run_{name}"
    return run


#: A plain decimal number in ASCII: Python's ``float`` also takes ``1_0``, ``٣`` and ``infinity``.
_PLAIN = re.compile(r"[+-]?(?:[0-9]+(?:\.[0-9]*)?|\.[0-9]+)(?:[eE][+-]?[0-9]+)?")


def plain_number(text: str) -> float:
    """``text`` as a float when it is a plain decimal number (``-0.5``, ``1e3``, ``.5``); else ValueError."""
    if not _PLAIN.fullmatch(text.strip()):
        raise ValueError(f"not a plain decimal number: {text!r}")
    return float(text)


def number_argument(text: str) -> float:
    """An argparse ``type`` for a numeric option (``--t-end 10``): a plain, finite decimal number.

    ``float`` alone would take ``1_0``, ``٣``, ``nan`` and ``inf``; the error names the text and
    the form expected, as argparse prints it (``argument --t-end: …``).
    """
    try:
        value = plain_number(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"`{text}` is not a plain decimal number (e.g. 10, -0.5, 1e-3)") from None
    if not math.isfinite(value):
        raise argparse.ArgumentTypeError(f"`{text}` is too large for a double; give a finite number")
    return value


def add_set_option(parser: argparse.ArgumentParser) -> None:
    """Add the repeatable ``--set NAME=VALUE`` option (stored in ``args.set`` as a list of strings)."""
    parser.add_argument(
        "--set", dest="set", action="append", default=[], metavar="NAME=VALUE",
        help="override a parameter value (g=1.62), an initial coordinate (theta=0.3) or an initial rate "
             "(phi_dot=80); repeat for several")


def add_input_options(parser: argparse.ArgumentParser) -> None:
    """``--input`` (repeatable), ``--input-time-column``, ``--feedback`` and ``--switch-at`` (read by `cli._input_option`)."""
    parser.add_argument(
        "--input", dest="input", action="append", default=[], metavar="NAME=VALUE",
        help="what a declared input does: a number (F=2.5), an expression of t, the coordinates, their rates and "
             "the parameters (F='2*sin(3*t)', compiled in), or samples from a CSV file, "
             "F=@FILE[:COLUMN[:zoh|linear|quadratic|cubic]] (column default NAME, interpolation default linear); repeatable; "
             "overrides the model's [controls]")
    parser.add_argument("--input-time-column", default="t", metavar="NAME",
                        help="the time column of the --input CSV files (default t)")
    parser.add_argument("--feedback", metavar="FILE.json",
                        help="close the loop u = u* - K (x - x*) with the feedback `lagrangian lqr ... -o FILE.json` "
                             "wrote (compiled into the right-hand side)")
    parser.add_argument("--switch-at", type=float, metavar="TIME",
                        help="with --feedback: its inputs follow their --input (0 where none) until TIME, then the "
                             "feedback (e.g. a swing-up's table, then the catch)")


def add_point_options(parser: argparse.ArgumentParser, *, inputs: bool = True, symbolic: bool = True) -> None:
    """``--at`` (repeatable), and optionally ``--inputs`` and ``--symbolic``; ``--set`` is added by the caller.

    Read by `cli._point`.
    """
    parser.add_argument(
        "--at", dest="at", action="append", default=[], metavar="NAME=VALUE",
        help="the point: a coordinate's value (theta=3.14159, theta=pi), a rate (psi_dot=10) or a declared "
             "input's value (tau_elbow=0.3); repeat for each coordinate (rates and inputs default to 0); default: "
             "the model's [operating_point]")
    if inputs:
        parser.add_argument(
            "--inputs", dest="inputs", action="append", default=None, metavar="NAME[,NAME...]",
            help="parameters (or declared [inputs]) that become the inputs u, the columns of B (default: the "
                 "model's declared inputs)")
    if symbolic:
        parser.add_argument(
            "--symbolic", dest="symbolic", action="append", default=[], metavar="NAME[,NAME...]",
            help="keep these parameters as symbols in the matrices (A(v)); `all` for every parameter")


def add_parameter_option(parser: argparse.ArgumentParser) -> None:
    """``--set NAME=VALUE`` for parameters only (the point is given with ``--at``); stored in ``args.set``."""
    parser.add_argument(
        "--set", dest="set", action="append", default=[], metavar="NAME=VALUE",
        help="override a parameter value (g=1.62); repeat for several (the point is given with --at)")
