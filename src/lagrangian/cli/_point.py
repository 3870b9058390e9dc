"""``--at NAME=VALUE``, ``--set``, ``--inputs``, ``--symbolic``: the point of a linearization from the command line.

Shared by ``linearize``, ``modes`` and ``report --small-motions``.  Every coordinate needs a
value, from ``--at`` or from the model's ``[operating_point]`` table (``--at`` wins); rates
default to 0 (dependent speeds are solved from the constraints).  A VALUE is a decimal
number, or a formula in the model grammar (``pi``, ``-v/rR``) read by the model's own safe
parser, never evaluated as Python.
"""

from __future__ import annotations

import argparse
import math
from collections.abc import Sequence
from typing import Any

from ..dynamics import EquationsOfMotion
from ..model.spec import Model
from ._arguments.common import add_parameter_option, add_point_options
from ._settings import SettingError, parse_settings, plain_number

__all__ = ["add_parameter_option", "add_point_options", "full_point", "linearize_from_args", "parse_names", "parse_point", "point_settings"]


def parse_names(values: Sequence[str] | None) -> list[str]:
    """``["tau,f", "g"]`` → ``["tau", "f", "g"]`` (order kept, repeats dropped)."""
    out: list[str] = []
    for item in values or ():
        for name in item.split(","):
            name = name.strip()
            if name and name not in out:
                out.append(name)
    return out


def parse_point(values: Sequence[str], model: Model) -> dict[str, int | float | str]:
    """``["theta=3.14159", "x=0"]`` → ``{"theta": 3.14159, "x": 0.0}`` with the model's names checked.

    A VALUE that is not a decimal number is kept as text for the linearization to read with the
    model grammar (``pi``, ``-v/rR``).

    Raises
    ------
    SettingError
        Bad form, a name that is neither a coordinate nor a rate, a name given twice, a value
        that is not finite.
    """
    coords = [c.name for c in model.coordinates]
    rates = [c + "_dot" for c in coords]
    params = [p.name for p in model.parameters]
    inputs = [getattr(x, "name", str(x)) for x in (getattr(model, "inputs", None) or ())]
    out: dict[str, int | float | str] = {}
    for item in values:
        name, sep, text = item.partition("=")
        name, text = name.strip(), text.strip()
        if not sep or not name or not text:
            raise SettingError(f"`--at {item}` is not of the form NAME=VALUE.", fix="write e.g. `--at theta=0`")
        if name not in coords and name not in rates and name not in inputs:  # an input: its value u0 at the point
            what = " is a parameter, not a coordinate" if name in params else " is not a coordinate or a rate"
            fix = (f"give parameter values with `--set {name}=VALUE`" if name in params else
                   "the coordinates are " + ", ".join(coords) + "; their rates " + ", ".join(rates))
            raise SettingError(f"`{name}` in `--at {item}`{what} of `{model.name}`.", fix=fix)
        if name in out:
            raise SettingError(f"`--at {name}` is given twice.", fix="give each coordinate once")
        value: int | float | str
        try:
            number = plain_number(text)
        except ValueError:
            value = text  # a formula: read by the model grammar in `linearize`
        else:
            if not math.isfinite(number):
                raise SettingError(f"In `--at {item}`, the value {text} is not finite.",
                                   fix=f"give `{name}` a finite value")
            # exact: θ = 0 keeps cos θ = 1, not 1.0, in symbolic matrices
            value = int(number) if number.is_integer() and abs(number) < 2**53 else number
        out[name] = value
    return out


def point_settings(args: argparse.Namespace, model: Model) -> tuple[dict[str, Any], dict[str, float]]:
    """(the point, the parameter values) from ``--at`` and ``--set``, the model's operating point filling in."""
    parameters, initial = parse_settings(args.set, model)
    if initial:
        name = next(iter(initial))
        raise SettingError(f"`--set {name}=...`: `{name}` is a coordinate or a rate; here `--set` gives parameter "
                           "values only.", fix=f"give the point with `--at {name}=VALUE`")
    return full_point(args.at, model), parameters


def full_point(values: Sequence[str], model: Model) -> dict[str, Any]:
    """The point of ``--at`` values, the model's ``[operating_point]`` filling in; every coordinate checked."""
    given = parse_point(values, model)
    table = dict(getattr(model, "operating_point", None) or {})
    point = {**table, **given}
    coords = [c.name for c in model.coordinates]
    missing = [c for c in coords if c not in point]
    if missing:
        where = " (the model's [operating_point] does not give it)" if table else ""
        raise SettingError(
            f"The coordinate{'s' if len(missing) > 1 else ''} " + ", ".join(f"`{c}`" for c in missing)
            + f" of the point {'have' if len(missing) > 1 else 'has'} no value{where}; every coordinate needs one "
              "(rates default to 0).",
            fix="add " + " ".join(f"--at {c}=VALUE" for c in missing)
                + (" (or an [operating_point] table in the model)" if not table else ""))
    return point


def linearize_from_args(args: argparse.Namespace, model: Model, eom: EquationsOfMotion, *,
                        symbolic: Sequence[str] = ()) -> Any:
    """`lagrangian.linearize` at the point of ``args`` (``--at``, ``--set``, ``--inputs``, ``--symbolic``)."""
    from ..analysis import linearize

    point, parameters = point_settings(args, model)
    keep = list(symbolic) + parse_names(getattr(args, "symbolic", None))
    if "all" in keep:
        keep = [p.name for p in model.parameters if p.name not in parameters]
    params = [p.name for p in model.parameters]
    for name in keep:
        if name not in params:
            raise SettingError(f"`--symbolic {name}`: `{name}` is not a parameter of `{model.name}`.",
                               fix="the parameters are " + (", ".join(params) or "(none)"))
        if name in parameters:
            raise SettingError(f"`{name}` is both given a value (`--set`) and kept symbolic.",
                               fix="drop one of the two")
    inputs = getattr(args, "inputs", None)
    names = parse_names(inputs) if inputs is not None else None
    declared = [getattr(x, "name", str(x)) for x in (getattr(model, "inputs", None) or ())]
    for name in names or ():
        if name not in params and name not in declared:
            raise SettingError(f"`--inputs {name}`: `{name}` is neither a parameter nor a declared input of "
                               f"`{model.name}`.",
                               fix="name a parameter used in a load's magnitude, or declare it under [inputs]"
                                   + (" (declared: " + ", ".join(declared) + ")" if declared else ""))
    if getattr(args, "hold", False):  # the inputs not given: those that hold the point (gravity compensation)
        from ..analysis import holding_inputs

        point = {**point, **holding_inputs(eom, point, parameters=parameters, inputs=names)}
    return linearize(eom, point, parameters=parameters, symbolic=tuple(dict.fromkeys(keep)), inputs=names,
                     independent_speeds=tuple(getattr(model, "independent_speeds", None) or ()) or None,
                     dependent_coordinates=tuple(getattr(model, "dependent_coordinates", None) or ()) or None)
