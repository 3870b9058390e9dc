"""One C function from named intermediates and outputs: the emitter of the generated derivatives.

`c_function` writes ``signature { ... }`` whose body reads the model's symbols from arrays
(q_i from ``y[i]``, a parameter from ``p[k]``...), defines the named intermediates it needs in
order and assigns the outputs, common subexpressions shared (`_cprint.c_sequence`).  Every
model symbol is first renamed to a private one (``_v3``), so that the names SymEngine's ``cse``
invents (``x0``, ``x1``...) cannot collide with a parameter of the same name.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence

import symengine as se

from ..errors import DerivationError
from ._cprint import c_sequence

__all__ = ["c_function"]


def c_function(signature: str, definitions: Sequence[tuple[se.Symbol, se.Basic]],
               outputs: Sequence[tuple[str, se.Basic]], reads: Mapping[se.Basic, str], what: str) -> str:
    """The C text of ``signature`` computing ``outputs``.

    Parameters
    ----------
    signature : str
        The C signature, e.g. ``"static void f(double t, const double *y, const double *p, double *out)"``.
    definitions : sequence of (SymEngine Symbol, SymEngine expression)
        Named intermediates (symbol, expression), in the order of computation.
    outputs : sequence of (str, SymEngine expression)
        (C target such as ``"out[3]"``, expression).
    reads : mapping of SymEngine expression to str
        Each model symbol the expressions may hold → the C expression that reads it (``"y[0]"``).
    what : str
        What the expressions are, for the error about a symbol that has no value.

    Returns
    -------
    str
        The function's C text.

    Raises
    ------
    DerivationError
        When an expression holds a symbol that is neither read nor defined.
    """
    private: dict[se.Basic, se.Symbol] = {}
    header: list[str] = []
    for k, sym in enumerate(reads):
        private[sym] = se.Symbol(f"_v{k}")
    defined = {sym for sym, _ in definitions}
    used: set[se.Basic] = set()

    def rename(expr: se.Basic) -> se.Basic:
        expr = expr if isinstance(expr, se.Basic) else se.Integer(0) + expr
        free = expr.free_symbols
        unknown = [s for s in free if s not in private and s not in defined]
        if unknown:
            raise DerivationError(f"{what} contains `{unknown[0]}`, which is neither a coordinate, a rate, a "
                                  "parameter nor t.", fix="declare it as a parameter of the model")
        mapping = {s: private[s] for s in free if s in private}
        used.update(mapping)
        return expr.xreplace(mapping) if mapping else expr

    defs = [(sym, rename(e)) for sym, e in definitions]
    outs = [(target, rename(e)) for target, e in outputs]
    names: dict[se.Basic, str] = {sym: f"_w{k}" for k, (sym, _) in enumerate(definitions)}
    names.update({p: str(p) for p in private.values()})
    body = c_sequence(defs, outs, names)
    for sym, text in reads.items():
        if sym in used:
            header.append(f"    const double {private[sym]} = {text};")
    return signature + " {\n" + "\n".join([*header, *body]) + "\n}\n"
