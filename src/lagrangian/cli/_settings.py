"""``--set NAME=VALUE``: parameter values and initial conditions from the command line.

Shared by the commands that need numbers (``analyse``, ``simulate``, ``verify``).  NAME is
a parameter (``g``), a coordinate for its initial value (``theta``) or a coordinate's rate
(``theta_dot``); VALUE is a plain decimal number read by ``float`` — never an expression.
"""

from __future__ import annotations

import argparse
import math
import re
from collections.abc import Sequence

from ..errors import LagrangianError
from ..model._assumptions import SIGN_RELATIONS, sign_problem
from ..model.spec import Model

__all__ = ["SettingError", "add_set_option", "parse_settings"]


class SettingError(LagrangianError):
    """A ``--set NAME=VALUE`` option that cannot be used: bad form, unknown name, not a number."""


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


def _known(model: Model) -> tuple[list[str], list[str], list[str]]:
    params = [p.name for p in model.parameters]
    coords = [c.name for c in model.coordinates]
    return params, coords, [c + "_dot" for c in coords]


def parse_settings(values: Sequence[str] | None, model: Model) -> tuple[dict[str, float], dict[str, float]]:
    """Split ``["theta=0.3", "phi_dot=80", "g=1.62"]`` into (parameters, initial) dictionaries.

    Parameters
    ----------
    values : the ``--set`` strings, each ``NAME=VALUE``.
    model : the model whose names are allowed.

    Returns
    -------
    parameters : {parameter name: value}.
    initial : {coordinate name or ``<coordinate>_dot``: value}.

    Raises
    ------
    SettingError
        A string without ``=``, a VALUE that is not a finite decimal number, a NAME that is
        neither a parameter, a coordinate nor a coordinate's rate, or a NAME given twice.

    Examples
    --------
    >>> from lagrangian import lagrange_top
    >>> parse_settings(["theta=0.3", "phi_dot=80", "g=1.62"], lagrange_top())
    ({'g': 1.62}, {'theta': 0.3, 'phi_dot': 80.0})
    """
    params, coords, rates = _known(model)
    parameters: dict[str, float] = {}
    initial: dict[str, float] = {}
    for item in values or ():
        name, sep, text = item.partition("=")
        name, text = name.strip(), text.strip()
        if not sep or not name or not text:
            raise SettingError(f"`--set {item}` is not of the form NAME=VALUE.",
                               fix="write e.g. `--set theta=0.3` (no spaces around `=` needed)")
        try:
            value = plain_number(text)
        except ValueError:
            raise SettingError(f"In `--set {item}`, `{text}` is not a number; VALUE must be a plain decimal "
                               "number (expressions are not evaluated).",
                               fix=f"write the number itself, e.g. `--set {name}=0.3`") from None
        if not math.isfinite(value):
            raise SettingError(f"In `--set {item}`, the value {text} is not finite.",
                               fix=f"give `{name}` a finite value")
        if name in parameters or name in initial:
            raise SettingError(f"`{name}` is set twice.", fix="give each name once")
        if name in params:
            sign = next(p.sign for p in model.parameters if p.name == name)
            problem = sign_problem(name, sign, value)
            if problem is not None:  # the equations may have been simplified with the sign
                raise SettingError(f"In `--set {item}`: {problem}.",
                                   fix=f"give `{name}` a value {SIGN_RELATIONS[sign]}, or change the sign declared "
                                       "in the model")  # type: ignore[index]
            parameters[name] = value
        elif name in coords or name in rates:
            initial[name] = value
        else:
            raise SettingError(
                f"`{name}` in `--set {item}` is not a parameter, a coordinate or a coordinate's rate of "
                f"`{model.name}`.",
                fix="known names: parameters " + (", ".join(params) or "(none)") + "; coordinates "
                    + ", ".join(coords) + "; rates " + ", ".join(rates))
    return parameters, initial
