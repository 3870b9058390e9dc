"""Declared inputs u and the default operating point of linearization.

Two tables of a model file serve small motions::

    [inputs]                    # symbols used like parameters, the columns of B
    tau = { description = "hip torque", unit = "N*m" }

    [operating_point]           # the default point: q = q*, q̇ = q̇* (constants)
    phi = 0
    thetaR_dot = "-v/rR"
    independent = ["phi_dot", "delta_dot"]   # independent speeds (optional)
    dependent = ["theta"]                    # dependent coordinates (optional)

An input is a `Parameter` with ``input=True`` and value 0 (the input off, so that
`simulate` and the energy checks keep working), and must be used by some load: an input
no load uses would give a zero column of B, almost always a typo.  The values of the
operating point are read by the safe grammar of `_expr` and must be constant: they may
name parameters, never a coordinate, a rate, an input or t.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Mapping, Sequence
from typing import TYPE_CHECKING, Any

import symengine as se

from ..errors import ModelError
from .spec import Coordinate, Load, Location, Model, Parameter
from .vectors import Vector

if TYPE_CHECKING:  # pragma: no cover
    from ._assemble import Assembler, Raw

__all__ = ["check_inputs_used", "build_operating_point", "load_symbols"]


def load_symbols(load: Load) -> set[se.Basic]:
    """Every free symbol of the expressions of ``load`` (its magnitude, its geometry)."""
    out: set[se.Basic] = set()

    def visit(value: Any) -> None:
        if isinstance(value, Vector):
            out.update(value.free_symbols())
        elif isinstance(value, se.Basic):
            out.update(value.free_symbols)
        elif isinstance(value, tuple):
            for v in value:
                visit(v)

    for f in dataclasses.fields(load):
        visit(getattr(load, f.name))
    return out


def check_inputs_used(model: Model) -> None:
    """Refuse a declared input that no load uses (its column of B would be zero).

    Raises
    ------
    ModelError
        Naming the input, where it was declared, and the fix.
    """
    used: set[se.Basic] = set()
    for load in model.loads:
        used |= load_symbols(load)
    for p in model.parameters:
        if p.input and p.symbol not in used:
            where = model.where("input", p.name)
            raise ModelError(
                f"input `{p.name}` is used by no load, so it would act on nothing (a zero column of B)",
                symbol=p.name, file=where.file, line=where.line,
                fix=f"use `{p.name}` in the magnitude of a load (e.g. motor = {{ torque = \"{p.name}*R1.z\", "
                f"on = \"S\" }}), or remove it from [inputs]",
            )


def build_operating_point(asm: Assembler, raw: Raw | None, parameters: Sequence[Parameter],
                          coordinates: Sequence[Coordinate]) -> dict[str, Any]:
    """The checked ``operating_point``, ``independent_speeds`` and ``dependent_coordinates`` of the model.

    Raises
    ------
    ModelError
        With the file and line of the offending key: an unknown name, a value that is not
        constant (it uses a coordinate, a rate, an input or t), a bad list.
    """
    if raw is None:
        return {}
    coords = [c.name for c in coordinates]
    rates = [c.rate_symbol.name for c in coordinates]
    constants = {p.symbol for p in parameters if not p.input}
    values = raw.data["values"]
    if not isinstance(values, Mapping):
        raise asm.error(raw, f"the operating point must map coordinates to values, not `{values}`",
                        symbol="operating_point", fix='e.g. operating_point({"theta": 0, "x_dot": "v"})')
    point: list[tuple[str, se.Basic]] = []
    for key, value in values.items():
        if key not in coords and key not in rates:
            raise asm.error(raw, f"`{key}` in the operating point is not a coordinate nor the rate of one",
                            symbol=str(key), key=key,
                            fix="give coordinates (" + ", ".join(coords) + ") or their rates ("
                            + ", ".join(rates) + ")")
        if isinstance(value, (bool, list, tuple, dict)) or value is None:
            raise asm.error(raw, f"the value of `{key}` in the operating point must be a number or an "
                            f"expression in quotes, not `{value}`", symbol=str(key), key=key,
                            fix=f'e.g. {key} = 0 or {key} = "v/r"')
        item = dataclasses.replace(raw, kind="operating point", name=str(key))
        expr = asm.expr(item, "the value", value, key=key)
        moving = sorted(str(s) for s in expr.free_symbols if s not in constants)
        if moving:
            bad = moving[0]
            what = ("the time" if bad == "t" else "an input" if bad in {p.name for p in parameters} else
                    "a rate" if bad in rates else "a coordinate")
            raise asm.error(raw, f"the value of `{key}` in the operating point uses {what} `{bad}`; an "
                            "operating point is constant", symbol=bad, key=key,
                            fix="write it with numbers and parameters only (solve the coordinates' values first)")
        point.append((str(key), expr))
    independent = _names(asm, raw, "independent", rates, "rate", 'e.g. independent = ["phi_dot", "delta_dot"]')
    dependent = _names(asm, raw, "dependent", coords, "coordinate", 'e.g. dependent = ["theta"]')
    return {"operating_point": tuple(point), "independent_speeds": independent,
            "dependent_coordinates": dependent}


def _names(asm: Assembler, raw: Raw, key: str, allowed: list[str], what: str, example: str) -> tuple[str, ...]:
    value = raw.data[key]
    if value is None:
        return ()
    if isinstance(value, str) or not isinstance(value, Sequence):
        raise asm.error(raw, f"`{key}` in the operating point must be a list of names, not `{value}`",
                        symbol=key, key=key, fix=example)
    seen: list[str] = []
    for name in value:
        if not isinstance(name, str) or name not in allowed:
            raise asm.error(raw, f"`{name}` in `{key}` of the operating point is not a {what} name",
                            symbol=str(name), key=key,
                            fix=f"list {what} names among " + ", ".join(allowed) + f" ({example})")
        if name in seen:
            raise asm.error(raw, f"`{name}` is listed twice in `{key}` of the operating point", symbol=name,
                            key=key, fix=f"list `{name}` once")
        seen.append(name)
    return tuple(seen)


def located(source: str | None, line: int | None, keys: Mapping[str, tuple[int, int]]) -> Location:
    """A `Location` of the ``[operating_point]`` table with the line and value column of each key."""
    return Location(source, line, tuple((k, ln, col) for k, (ln, col) in keys.items()))
