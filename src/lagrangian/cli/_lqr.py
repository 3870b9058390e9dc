"""``lagrangian lqr MODEL [--at theta=0 ...] [--set NAME=VALUE] [--inputs F] [--Q SPEC] [--R SPEC] [--json]
[-o feedback.json]``: the LQR state feedback about an equilibrium or a steady motion.

Prints the gain K of u = u* − K (x − x*), the point x* and the inputs u* that hold it, the
weights and the closed-loop eigenvalues; ``--json`` prints the feedback document (schema
``lagrangian.feedback``), which ``-o FILE`` writes (atomically) for ``lagrangian simulate
MODEL --feedback FILE``.  A weight SPEC is a diagonal in state (input) order, ``1,1,10,1``,
or named entries of the identity, ``theta=10,x=2``; a formula is not read.
"""

from __future__ import annotations

import argparse
import json
import math
from typing import Any

from ..dynamics import derive
from ..output import feedback_text
from ._point import parse_names, point_settings
from ._settings import SettingError, plain_number
from ._source import load_source

__all__ = ["parse_weights", "run"]

def parse_weights(spec: str | None, option: str) -> Any:
    """``"1,1,10,1"`` → [1, 1, 10, 1]; ``"theta=10,x=2"`` → {"theta": 10, "x": 2}; None → None.

    Raises
    ------
    SettingError
        A part that is not a plain finite number, or a mix of the two forms.
    """
    if spec is None:
        return None
    parts = [s.strip() for s in spec.split(",") if s.strip()]
    if not parts:
        raise SettingError(f"`{option} {spec}` is empty.", fix=f"e.g. {option} 1,1,10,1 or {option} theta=10")
    named = ["=" in s for s in parts]
    if any(named) and not all(named):
        raise SettingError(f"`{option} {spec}` mixes a diagonal and named weights.",
                           fix=f"give all of them by name ({option} theta=10,x=2) or none ({option} 1,1,10,1)")
    out: dict[str, float] = {}
    values: list[float] = []
    for part in parts:
        name, _, text = part.rpartition("=")
        try:
            value = plain_number(text)
        except ValueError:
            raise SettingError(f"In `{option} {spec}`, `{text}` is not a plain decimal number.",
                               fix=f"write numbers, e.g. {option} theta=10") from None
        if not math.isfinite(value):
            raise SettingError(f"In `{option} {spec}`, `{text}` is not finite.", fix="give finite weights")
        if name:
            out[name.strip()] = value
        else:
            values.append(value)
    return out if any(named) else values


def run(args: argparse.Namespace) -> str:
    from ..analysis import lqr

    model = load_source(args.model)
    eom = derive(model)
    point, parameters = point_settings(args, model)
    inputs = getattr(args, "inputs", None)
    names = parse_names(inputs) if inputs is not None else None
    fb = lqr(eom, point, Q=parse_weights(args.Q, "--Q"), R=parse_weights(args.R, "--R"), inputs=names,
             parameters=parameters)
    if args.json or args.output:
        return json.dumps(fb.to_dict(), indent=2) + "\n"
    return feedback_text(fb)
