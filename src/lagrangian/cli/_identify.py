"""``lagrangian identify MODEL DATA.csv --fit m,l [--route ...] [--set g=9.81] [--input F=0] [--guess l=0.4]
[--columns t,theta] [--segments N] [--window 21 --order 4] [--base] [--json] [-o FILE]``.

Fits parameters of MODEL to the motion measured in DATA (a CSV file: a header of names, ``t``,
coordinates, rates ``theta_dot``, accelerations ``theta_ddot``, inputs; ``#`` comment lines
skipped) and prints the estimates with their standard errors, or the versioned JSON document
``lagrangian.identify/1`` (docs/identification.md).  A URDF robot is read with its links'
inertial parameters as parameters (``m_<link>``, ``mx_<link>``, ..., ``Izz_<link>``).
"""

from __future__ import annotations

import argparse
import json
import sys
import warnings

from ..errors import IdentificationError
from ._settings import SettingError, parse_settings, plain_number
from ._source import load_source

__all__ = ["run"]

def _pairs(items: list[str], option: str) -> dict[str, float]:
    out: dict[str, float] = {}
    for item in items:
        name, sep, text = item.partition("=")
        name, text = name.strip(), text.strip()
        if not sep or not name or not text:
            raise SettingError(f"`{option} {item}` is not of the form NAME=VALUE.", fix=f"write e.g. `{option} l=0.5`")
        try:
            value = plain_number(text)
        except ValueError:
            raise SettingError(f"In `{option} {item}`, `{text}` is not a plain decimal number.",
                               fix=f"write the number itself, e.g. `{option} {name}=0.5`") from None
        if name in out:
            raise SettingError(f"`{name}` is given twice with {option}.", fix="give each name once")
        out[name] = value
    return out


def _model(name: str):
    """The model, a URDF with its inertial parameters as parameters."""
    if name.lower().endswith(".urdf"):
        from ..model.urdf import UrdfNote, load_urdf

        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always", UrdfNote)
            model = load_urdf(name, inertial_parameters=True)
        for warning in caught:
            if issubclass(warning.category, UrdfNote):
                sys.stderr.write(f"{warning.message}\n")
        return model
    return load_source(name)


def run(args: argparse.Namespace) -> str:
    from ..identification import SavitzkyGolay, Shooting, identify

    model = _model(args.model)
    values, initial = parse_settings(args.set, model)
    fitted = [name.strip() for name in args.fit.split(",") if name.strip()]
    if not fitted:
        raise IdentificationError("`--fit` names no parameter.", fix="e.g. --fit m,l")
    columns = [c.strip() for c in args.columns.split(",") if c.strip()] if args.columns else None
    shooting = Shooting(segments=args.segments)
    fit = identify(model, args.data, fitted, route=args.route, values=values, inputs=_pairs(args.inputs, "--input"),
                   guess=_pairs(args.guess, "--guess"), initial=initial or None, columns=columns,
                   derivatives=SavitzkyGolay(args.window, args.order), shooting=shooting,
                   deficient="base" if args.base else "error")
    if args.json:
        return json.dumps(fit.to_dict(), indent=2, ensure_ascii=False) + "\n"
    return fit.summary() + "\n"
