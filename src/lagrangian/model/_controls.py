"""The ``[controls]`` table: a control law for the declared inputs, in the model grammar.

::

    [inputs]
    F = { unit = "N" }

    [parameters]
    k1 = 40.0
    k2 = 12.0

    [controls]              # u = expression of t, the coordinates, their rates and the parameters
    F = "-k1*x - k2*x_dot"

Each key is a declared input; each value an expression (read by the safe grammar of `_expr`)
of t, the coordinates, ``<coordinate>_dot`` and the parameters — never another input, whose
law would then hide a loop.  `simulate` runs the law (compiled into the right-hand side)
unless its ``inputs=`` names that input; `derive`, `linearize` and the first integrals do not
use it (they see the inputs as symbols).
"""

from __future__ import annotations

import dataclasses
from collections.abc import Mapping, Sequence
from typing import TYPE_CHECKING

import symengine as se

from .spec import Coordinate, Parameter

if TYPE_CHECKING:  # pragma: no cover
    from ._assemble import Assembler, Raw

__all__ = ["build_controls"]


def build_controls(asm: Assembler, raw: Raw | None, parameters: Sequence[Parameter],
                   coordinates: Sequence[Coordinate]) -> tuple[tuple[str, se.Basic], ...]:
    """The checked ``controls`` of the model: (input name, expression), in file order.

    Raises
    ------
    ModelError
        With the file and line of the offending key: a name that is not a declared input, a
        value that is not an expression, an expression that uses another input or an unknown name.
    """
    if raw is None:
        return ()
    values = raw.data["values"]
    if not isinstance(values, Mapping):
        raise asm.error(raw, f"[controls] must map inputs to expressions, not `{values}`", symbol="controls",
                        fix='e.g. [controls] F = "-k1*x - k2*x_dot"')
    inputs = [p.name for p in parameters if p.input]
    allowed = {p.symbol for p in parameters if not p.input} | {se.Symbol("t")}
    allowed |= {c.symbol for c in coordinates} | {c.rate_symbol for c in coordinates}
    out: list[tuple[str, se.Basic]] = []
    for key, value in values.items():
        if key not in inputs:
            what = "a parameter" if key in {p.name for p in parameters} else "not a declared input"
            raise asm.error(raw, f"`{key}` in [controls] is {what}; a control law gives a declared input",
                            symbol=str(key), key=key,
                            fix=("declare it under [inputs] and use it in a load" if not inputs else
                                 "give laws for the inputs: " + ", ".join(inputs)))
        if isinstance(value, bool) or not isinstance(value, (str, int, float)):
            raise asm.error(raw, f"the law of `{key}` in [controls] must be an expression in quotes or a number, "
                            f"not `{value}`", symbol=str(key), key=key, fix=f'e.g. {key} = "-k1*x - k2*x_dot"')
        item = dataclasses.replace(raw, kind="control", name=str(key))
        expr = asm.expr(item, "the law", value, key=key)
        bad = sorted(str(s) for s in expr.free_symbols if s not in allowed)
        if bad:
            raise asm.error(raw, f"the law of `{key}` in [controls] uses the input `{bad[0]}`; a law is written with "
                            "t, the coordinates, their rates and the parameters", symbol=bad[0], key=key,
                            fix="write the other input's law into this one, or make it a parameter")
        out.append((str(key), expr))
    return tuple(out)


