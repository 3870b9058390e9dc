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
from ._settings import SettingError, add_set_option, parse_settings, plain_number
from ._source import MODEL_HELP, load_source

__all__ = ["register", "run"]

SUMMARY = "fit parameters to a measured motion (--fit m,l): estimates, standard errors,\n" \
          "identifiable combinations"


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser(
        "identify", help="fit parameters to a measured motion",
        description="Fit parameters of the model to a measured motion: by the inverse-dynamics regressor (linear "
                    "least squares, base parameters by QR) when every coordinate is measured and the equations are "
                    "linear in the parameters, else by simulating the motion (single or multiple shooting, "
                    "nonlinear least squares with forward sensitivities).")
    p.add_argument("model", help=MODEL_HELP)
    p.add_argument("data", help="the measurements: a CSV file with a header line (t, coordinates, rates NAME_dot, "
                                "accelerations NAME_ddot, inputs)")
    p.add_argument("--fit", required=True, metavar="NAMES", help="the parameters to fit, separated by commas: m,l")
    p.add_argument("--route", choices=("auto", "regressor", "shooting"), default="auto",
                   help="how to fit (default auto: the regressor when it applies)")
    add_set_option(p)
    p.add_argument("--input", dest="inputs", action="append", default=[], metavar="NAME=VALUE",
                   help="the constant value of an input that the data does not hold (repeat for several)")
    p.add_argument("--guess", action="append", default=[], metavar="NAME=VALUE",
                   help="first value of a fitted parameter for shooting (default the model's)")
    p.add_argument("--columns", metavar="NAMES", help="the data columns to use, separated by commas (default all)")
    p.add_argument("--segments", type=int, metavar="N",
                   help="shooting segments (1: single shooting; default about one per 20 samples, at most 20)")
    p.add_argument("--window", type=int, default=21, metavar="W",
                   help="samples of the local polynomial fits that give q' and q'' from q (odd; default 21)")
    p.add_argument("--order", type=int, default=4, metavar="D", help="their degree (default 4)")
    p.add_argument("--base", action="store_true",
                   help="when the parameters are identifiable only in combinations, fit the combinations (the base "
                        "parameters) instead of refusing")
    p.add_argument("--json", action="store_true", help="print the JSON document (schema lagrangian.identify/1)")
    p.add_argument("-o", "--output", metavar="FILE", help="write to FILE (atomically) instead of standard output")
    p.set_defaults(run=run)


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


def _model(name: str):  # type: ignore[no-untyped-def]
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
