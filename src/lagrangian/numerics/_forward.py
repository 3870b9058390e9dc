"""Jacobians of expressions written over named intermediates, by forward accumulation.

The equations of motion of a kinematic tree are a sequence of named intermediates
w_k = e_k(w_1..w_{k−1}, x) (`lagrangian.dynamics._recursive`), and those of a small model
plain expressions of x.  The derivative of every intermediate with respect to each variable
x_j is itself named, by the chain rule along the sequence (forward accumulation, Griewank &
Walther, *Evaluating Derivatives*, 2nd ed. 2008, §3.1):

    ∂w_k/∂x_j = ∂e_k/∂x_j + Σ_{w_m ∈ e_k} (∂e_k/∂w_m) (∂w_m/∂x_j),

so the Jacobian of the outputs costs a small multiple of the outputs times the number of
variables each intermediate depends on, and nothing is expanded.  Derivatives that vanish
are never formed: an intermediate of the kinematics (a link velocity) has none with respect
to a mass.

The result feeds the C generator (`codegen.c_sequence`): the forward sensitivities of
`_sensitivity` (∂(F − M a)/∂(y, p)) and the identification regressor ∂(M a − F)/∂θ
(`lagrangian.identification._regressor`).
"""

from __future__ import annotations

from collections.abc import Sequence

import symengine as se

__all__ = ["ForwardJacobian", "forward_jacobian"]

_ZERO = se.Integer(0)
_ZERO_TYPE = type(_ZERO)
#: A sum with more terms than this is differentiated term by term: each term holds a few symbols,
#: and differentiating the whole sum once per symbol would be quadratic in its length.
_SPLIT_SUM = 4


class ForwardJacobian:
    """The definitions and Jacobian entries made by `forward_jacobian`.

    Attributes
    ----------
    definitions : (symbol, expression) pairs in the order of computation: the intermediates the
        outputs need, each followed (where it has any) by the named derivatives it makes.
    jacobian : ``jacobian[i][j]`` = ∂outputs[i]/∂variables[j], an expression over ``definitions``.
    """

    def __init__(self, definitions: list[tuple[se.Symbol, se.Basic]], jacobian: list[list[se.Basic]]) -> None:
        self.definitions = definitions
        self.jacobian = jacobian


def _sum(terms: list[se.Basic]) -> se.Basic:
    return se.Add(*terms) if len(terms) > 1 else (terms[0] if terms else _ZERO)


def forward_jacobian(definitions: Sequence[tuple[se.Symbol, se.Basic]], outputs: Sequence[se.Basic],
                     variables: Sequence[se.Symbol]) -> ForwardJacobian:
    """The Jacobian ∂outputs/∂variables through the named intermediates ``definitions`` (module docstring).

    Parameters
    ----------
    definitions : sequence of (SymEngine Symbol, SymEngine expression)
        (symbol, expression) in the order of computation, each expression holding earlier symbols
        and the variables (and other free symbols, held constant).
    outputs : sequence of SymEngine expressions
        Expressions over ``definitions`` and the variables.
    variables : sequence of SymEngine Symbol
        The symbols to differentiate with respect to.

    Returns
    -------
    ForwardJacobian
        Its ``definitions`` start with every given definition the outputs need (in order), the
        named derivatives interleaved after what they follow from.
    """
    index = {v: j for j, v in enumerate(variables)}
    needed = _needed(definitions, outputs)
    tangent: dict[se.Basic, dict[int, se.Basic]] = {}
    out_defs: list[tuple[se.Symbol, se.Basic]] = []
    count = 0

    def grad(expr: se.Basic) -> dict[int, list[se.Basic]]:
        acc: dict[int, list[se.Basic]] = {}
        stack = [expr]
        while stack:
            e = stack.pop()
            if isinstance(e, se.Add) and len(e.args) > _SPLIT_SUM:
                stack.extend(e.args)
                continue
            for s in e.free_symbols:
                j = index.get(s)
                inner = tangent.get(s)
                if j is None and not inner:
                    continue
                d = e.diff(s)
                if type(d) is _ZERO_TYPE:
                    continue
                if j is not None:
                    acc.setdefault(j, []).append(d)
                if inner:
                    for k, ds in inner.items():
                        acc.setdefault(k, []).append(d if ds == 1 else d * ds)
        return acc

    for sym, expr in needed:
        out_defs.append((sym, expr))
        mine: dict[int, se.Basic] = {}
        for j, terms in grad(expr).items():
            value = _sum(terms)
            if type(value) is _ZERO_TYPE:
                continue
            if not (value.is_Number or value.is_Symbol):
                name = se.Dummy(f"d{count}")
                count += 1
                out_defs.append((name, value))
                value = name
            mine[j] = value
        if mine:
            tangent[sym] = mine
    jacobian = []
    for expr in outputs:
        row = [_ZERO] * len(variables)
        for j, terms in grad(expr).items():
            row[j] = _sum(terms)
        jacobian.append(row)
    return ForwardJacobian(out_defs, jacobian)


def _needed(definitions: Sequence[tuple[se.Symbol, se.Basic]],
            outputs: Sequence[se.Basic]) -> list[tuple[se.Symbol, se.Basic]]:
    """The definitions the outputs depend on, in their order."""
    position = {s: k for k, (s, _) in enumerate(definitions)}
    keep: set[int] = set()
    stack = [position[s] for e in outputs for s in e.free_symbols if s in position]
    while stack:
        k = stack.pop()
        if k in keep:
            continue
        keep.add(k)
        stack.extend(position[s] for s in definitions[k][1].free_symbols if s in position)
    return [definitions[k] for k in sorted(keep)]
