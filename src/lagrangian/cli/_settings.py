"""``--set NAME=VALUE``: parameter values and initial conditions from the command line.

Shared by the commands that need numbers (``analyse``, ``simulate``, ``verify``).  NAME is
a parameter (``g``), a coordinate for its initial value (``theta``) or a coordinate's rate
(``theta_dot``); VALUE is a plain decimal number read by ``float`` — never an expression.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

from ..errors import LagrangianError
from ..model import SIGN_RELATIONS, sign_problem
from ..model.spec import Model
from ._arguments.common import add_set_option, number_argument, plain_number

__all__ = ["SettingError", "add_set_option", "number_argument", "parse_settings", "plain_number"]


class SettingError(LagrangianError):
    """A ``--set NAME=VALUE`` option that cannot be used: bad form, unknown name, not a number."""


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
            if problem is not None and sign is not None:  # the equations may have been simplified with the sign
                raise SettingError(f"In `--set {item}`: {problem}.",
                                   fix=f"give `{name}` a value {SIGN_RELATIONS[sign]}, or change the sign declared "
                                       "in the model")
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
