"""What every export target prints, and the one interface the targets implement.

The dispatcher (`codegen._export`) derives an `ExportedSymbols` from the equations of motion
M(q, t) q̈ = F(q, q̇, t) once, then hands it to the target asked for, an `AbstractTarget`,
which returns the text of its files.  Everything a target reads lives here, so that no target
imports the dispatcher back: the symbols and their rows, and `cse_lines`, the lines of one
function whose common subexpressions are computed once (SymEngine's ``cse``).
"""

from __future__ import annotations

import abc
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any, ClassVar

import symengine as se

from .._rewrite import MassForcesForm

__all__ = ["AbstractTarget", "ExportedRow", "ExportedSymbols", "cse_lines"]


@dataclass(frozen=True)
class ExportedSymbols:
    """What every target prints: names, defaults, and M, F over private symbols.

    The free symbols of ``M`` and ``F`` are replaced by ``_y<i>`` (y[i], the state), ``_p<k>``
    (p[k], the parameters) and ``_t``, so that no model name can clash with a name of the
    generated code (``numpy``, ``sin``, a C keyword).

    Parameters
    ----------
    name : str
        The model's name, for comments (printable, no comment terminators).
    identifier : str
        A C / Python identifier made from it.
    version : str
        The version of lagrangian that exported it.
    coordinates : tuple of str
        The coordinates' names.
    state : tuple of str
        The state's names (coordinates, then rates).
    parameters : tuple of str
        The parameters' names, in the order of p.
    defaults : tuple of float or None
        Their values in the model.
    M : tuple of SymEngine expressions
        The mass matrix row by row, n*n entries.
    F : tuple of SymEngine expressions
        The right side F.
    y : tuple of SymEngine Symbol
        The private state symbols.
    p : tuple of SymEngine Symbol
        The private parameter symbols.
    t : SymEngine Symbol
        The private time symbol.
    rows : tuple of ExportedRow
        The complementary rows (every target that exports them).
    integrals : tuple of (str, SymEngine expression)
        The C target's first integrals (name, expression), over the private symbols; empty for the
        other targets.
    fast : MassForcesForm, optional
        The C target's M and F in the in-package form, over the private symbols.
    """

    name: str            # the model's name, for comments (printable, no comment terminators)
    identifier: str      # a C / Python identifier made from it
    version: str
    coordinates: tuple[str, ...]
    state: tuple[str, ...]
    parameters: tuple[str, ...]
    defaults: tuple[float | None, ...]
    M: tuple[se.Basic, ...]     # row by row, n*n entries
    F: tuple[se.Basic, ...]
    y: tuple[se.Symbol, ...]
    p: tuple[se.Symbol, ...]
    t: se.Symbol
    # The complementary rows (every target that exports them), then the C target's extras (empty
    # for the others): the first integrals (name, expression) and M, F in the in-package form, all
    # over the private symbols.
    rows: tuple[ExportedRow, ...] = ()
    integrals: tuple[tuple[str, se.Basic], ...] = ()
    fast: MassForcesForm | None = None

    @property
    def n(self) -> int:
        return len(self.coordinates)


@dataclass(frozen=True)
class ExportedRow:
    """One complementary constraint row over the private symbols (`dynamics.ConstraintRow`):
    A q̇ + b = 0 along a motion, A q̈ + c = 0 its derivative, f(q, t) = 0 for a holonomic row
    (``f`` = 0 for a nonholonomic one)."""

    name: str
    kind: str
    multiplier: str
    A: tuple[se.Basic, ...]
    b: se.Basic
    c: se.Basic
    f: se.Basic


def cse_lines(targets: Sequence[str], exprs: Sequence[se.Basic], printer: Any, local: str,
              indent: str, end: str = "", first: int = 0) -> list[str]:
    """``target = expression`` lines for ``exprs``, their common subexpressions (SymEngine's ``cse``)
    first, named ``<local><first>``, ``<local><first + 1>``…; each printed by ``printer`` (a SymPy code
    printer, fed ``_sympy_()`` objects: no text is parsed), indented and ended as the target language wants."""
    replacements, reduced = se.cse(list(exprs)) if exprs else ([], [])
    mapping: dict[se.Basic, se.Basic] = {}
    lines = []
    for k, (sym, value) in enumerate(replacements):
        name = se.Symbol(f"{local}{k + first}")
        lines.append(f"{indent}{name} = {printer.doprint(value.xreplace(mapping)._sympy_())}{end}")
        mapping[sym] = name
    for target, value in zip(targets, reduced, strict=True):
        lines.append(f"{indent}{target} = {printer.doprint(value.xreplace(mapping)._sympy_())}{end}")
    return lines


class AbstractTarget(abc.ABC):
    """A language the equations are exported to (`lagrangian.export`, docs/export.md).

    The contract of a target:

    1. ``name`` is its value of ``export(eom, target, ...)`` and of ``lagrangian export --to``;
    2. ``in_package_form`` is True when it prints the in-package C form of M and F and the first
       integrals: the dispatcher then fills `ExportedSymbols.fast` and ``integrals``, which cost a
       search for the integrals, and leaves them empty otherwise;
    3. `files` returns ``{file name: text}`` and writes nothing: the dispatcher writes the directory
       atomically, and refuses what no target can express (an exact Coulomb contact) beforehand;
    4. a target imports nothing from the dispatcher: what it reads is in this module.
    """

    name: ClassVar[str]
    in_package_form: ClassVar[bool] = False

    @abc.abstractmethod
    def files(self, symbols: ExportedSymbols) -> dict[str, str]:
        """The text of each file of this target for ``symbols``, by file name.

        Parameters
        ----------
        symbols : ExportedSymbols
            What to print.

        Returns
        -------
        dict of str to str
            The text of each file, by file name.
        """
