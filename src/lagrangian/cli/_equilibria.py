"""``lagrangian equilibria MODEL [--set NAME=VALUE] [--range NAME=a:b] [--json] [-o FILE]``.

Every static equilibrium (q̇ = 0, q̈ = 0) of an autonomous model, in closed form with its
condition of existence when SymPy finds one, numerically otherwise (`lagrangian.equilibria`).
Values on the command line are plain decimal numbers, never expressions.
"""

from __future__ import annotations

import argparse
import json
import math

import sympy

from ..analysis import Equilibrium, equilibria
from ..dynamics import derive
from ..output import Notation
from ..output._course import to_sympy
from ._settings import SettingError, add_set_option, parse_settings
from ._source import MODEL_HELP, load_source

__all__ = ["register", "run", "parse_ranges", "SCHEMA"]

SUMMARY = "every static equilibrium (closed form with its condition of existence, or numeric)"
#: Name of the JSON document ``--json`` writes (version 1).
SCHEMA = "lagrangian.equilibria"

_RELATIONS = {sympy.StrictGreaterThan: ">", sympy.GreaterThan: "≥", sympy.StrictLessThan: "<",
              sympy.LessThan: "≤", sympy.Equality: "=", sympy.Unequality: "≠"}


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser(
        "equilibria", help="static equilibria of an autonomous model",
        description="Find every position of equilibrium q* (q̇ = 0, q̈ = 0: F(q*, 0) + Aᵀλ = 0 and the holonomic "
                    "constraints): in closed form when SymPy can, with the condition of existence, and by a "
                    "multi-start numeric search over the coordinates' ranges otherwise. Angles range over (−π, π]; "
                    "other coordinates need --range for the numeric search.")
    p.add_argument("model", nargs="?", help=MODEL_HELP)
    add_set_option(p)
    p.add_argument("--range", dest="range", action="append", default=[], metavar="NAME=a:b",
                   help="where to search coordinate NAME (numbers, a < b), e.g. x=-1:1; repeat for several")
    p.add_argument("--json", action="store_true", help=f"print the JSON document `{SCHEMA}` version 1")
    p.add_argument("-o", "--output", metavar="FILE", help="write the result to FILE (atomically)")
    p.set_defaults(run=run)


def parse_ranges(values: list[str], coordinates: tuple[str, ...]) -> dict[str, tuple[float, float]]:
    """``["x=-1:1"]`` → ``{"x": (-1.0, 1.0)}``, refusing unknown names and bad numbers."""
    out: dict[str, tuple[float, float]] = {}
    for text in values:
        name, sep, span = text.partition("=")
        a, colon, b = span.partition(":")
        name = name.strip()
        if not sep or not colon:
            raise SettingError(f"--range {text}: expected NAME=a:b", fix="e.g. --range x=-1:1")
        if name not in coordinates:
            raise SettingError(f"--range {text}: `{name}` is not a coordinate",
                               fix="coordinates: " + ", ".join(coordinates))
        try:
            lo, hi = float(a), float(b)
        except ValueError:
            raise SettingError(f"--range {text}: the bounds must be numbers", fix="e.g. --range x=-1:1") from None
        if not (math.isfinite(lo) and math.isfinite(hi) and lo < hi):
            raise SettingError(f"--range {text}: the bounds must be finite with a < b", fix="e.g. --range x=-1:1")
        if name in out:
            raise SettingError(f"--range {name} is given twice", fix="give each coordinate's range once")
        out[name] = (lo, hi)
    return out


def run(args: argparse.Namespace) -> str:
    model = load_source(args.model)
    parameters, initial = parse_settings(args.set, model)
    if initial:
        name = sorted(initial)[0]
        raise SettingError(f"--set {name}=...: an equilibrium is found, not given; --set takes parameters only",
                           fix="remove it, or use --range to say where to look")
    ranges = parse_ranges(args.range, tuple(c.name for c in model.coordinates))
    eom = derive(model)
    found = equilibria(eom, parameters=parameters or None, ranges=ranges)
    values = {p.name: parameters.get(p.name, p.value) for p in model.parameters}
    if args.json:
        return json.dumps(_document(model.name, eom.coordinates, values, found), indent=2) + "\n"
    return _text(model.name, eom.coordinates, [p.name for p in model.parameters], found)


def _document(name: str, coordinates: tuple[str, ...], values: dict, found: tuple[Equilibrium, ...]) -> dict:
    return {
        "schema": SCHEMA, "version": 1, "model": name, "coordinates": list(coordinates), "parameters": values,
        "equilibria": [{
            "values": {n: (v if isinstance(v, float) else str(v)) for n, v in e.values.items()},
            "numeric": None if e.numeric is None else {n: e.numeric[n] for n in coordinates if n in e.numeric},
            "closed_form": e.closed_form, "condition": e.condition_text, "exists": e.exists,
            "residual": e.residual, "free": list(e.free),
        } for e in found],
    }


def _text(name: str, coordinates: tuple[str, ...], parameters: list[str], found: tuple[Equilibrium, ...]) -> str:
    n = Notation(list(coordinates), parameters)
    lines = [f"Equilibria of {name} (q̇ = 0, q̈ = 0: F(q, 0) + Aᵀλ = 0)", ""]
    if not found:
        lines.append("  none found in the ranges searched")
    for k, e in enumerate(found, start=1):
        parts = []
        for q in coordinates:
            v = e.values[q]
            if q in e.free:
                parts.append(f"{n.symbol(q)} any")
                continue
            shown = f"{v:.12g}" if isinstance(v, float) else n.text(to_sympy(v))
            x = None if e.numeric is None else e.numeric.get(q)
            if x is not None and not isinstance(v, float) and shown != f"{x:.12g}":
                shown += f" = {x:.12g}"
            parts.append(f"{n.symbol(q)} = {shown}")
        how = "closed form" if e.closed_form else "numeric"
        tail = f"  ({how}" + ("" if e.residual is None else f"; residual {e.residual:.1e}") + ")"
        lines.append(f"  {k}. " + ", ".join(parts) + tail)
        if e.condition is not None:
            verdict = {True: "holds here", False: "does not hold here", None: "undecided without values"}[e.exists]
            lines.append(f"     exists if {_condition(n, e.condition)} ({verdict})")
    return "\n".join(lines) + "\n"


def _condition(n: Notation, cond: sympy.Basic) -> str:
    if isinstance(cond, sympy.And):
        return " and ".join(_condition(n, c) for c in cond.args)
    op = _RELATIONS.get(type(cond))
    if op is None:
        return sympy.sstr(cond)
    plain = {s: sympy.Symbol(s.name) for s in cond.free_symbols}
    return f"{n.text(cond.lhs.xreplace(plain))} {op} {n.text(cond.rhs.xreplace(plain))}"
