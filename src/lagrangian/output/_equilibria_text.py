"""Equilibria as terminal text: what ``lagrangian equilibria`` prints, for library users too (`equilibria_text`,
`bifurcation_text`).

Each rest with its values (a numeric root at k π/d named so), closed form or numeric, its aliases,
its condition of existence and its stability verdict, then what was searched, so that the list is
never read as complete when it may not be; with ``--sweep``, each closed-form branch against the
parameter and where it appears or changes stability.  The rests come from
`lagrangian.analysis.equilibria` and `lagrangian.analysis.bifurcation`; this module only writes them.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import TYPE_CHECKING

import sympy

from ._course import to_sympy
from ._notation import Notation

if TYPE_CHECKING:
    from ..analysis import BifurcationDiagram, Equilibria, Equilibrium, EquilibriumSearch
    from ..dynamics import EquationsOfMotion

__all__ = ["Verdict", "bifurcation_text", "equilibria_text"]

#: One rest's stability: (stable or None when undecided, the verdict, its reason); None without a verdict.
Verdict = tuple[bool | None, str, str] | None

_RELATIONS = {sympy.StrictGreaterThan: ">", sympy.GreaterThan: "≥", sympy.StrictLessThan: "<",
              sympy.LessThan: "≤", sympy.Equality: "=", sympy.Unequality: "≠"}


def equilibria_text(eom: EquationsOfMotion, found: Equilibria, verdicts: Sequence[Verdict] | None = None, *,
                    absent: Sequence[Equilibrium] = ()) -> str:
    """What ``lagrangian equilibria`` prints: the rests ``found`` by `lagrangian.analysis.equilibria`.

    And where it searched.

    Parameters
    ----------
    eom : EquationsOfMotion
        The equations the rests are of (their coordinates and parameters name the symbols).
    found : Equilibria
        From `lagrangian.analysis.equilibria`.
    verdicts : sequence of Verdict, optional
        Each rest's `Verdict`, in the order of ``found`` (the CLI's from `linearize`); None: none
        shown.
    absent : sequence of Equilibrium, optional
        Closed-form rests whose condition of existence does not hold at these values, each written
        with its condition (``equilibria(..., all_branches=True)`` those with ``exists is False``).

    Returns
    -------
    str
        The text.

    Examples
    --------
    >>> import lagrangian
    >>> eom = lagrangian.derive(lagrangian.load_model("examples/bead_rotating_hoop.toml"))  # doctest: +SKIP
    >>> print(lagrangian.output.equilibria_text(eom, lagrangian.equilibria(eom)))          # doctest: +SKIP
    """
    parameters = [p.name for p in eom.model.parameters]
    n = Notation(list(eom.coordinates), parameters)
    chosen = [None] * len(found) if verdicts is None else list(verdicts)
    text = _rests(eom.model.name, eom.coordinates, parameters, found, chosen)
    text += "\n" + _searched(n, found.search)
    for e in absent:
        where = ", ".join(f"{n.symbol(q)} any" if q in e.free else f"{n.symbol(q)} = {n.text(to_sympy(e.values[q]))}"
                          for q in eom.coordinates)
        text += f"  ({where} would be one if {_condition(n, e.condition)}, which does not hold at these values)\n"
    return text


def bifurcation_text(eom: EquationsOfMotion, diagram: BifurcationDiagram) -> str:
    """What ``lagrangian equilibria --sweep`` prints: the branches of rests along the parameter.

    Each closed-form branch of rests in ``diagram`` (from `lagrangian.analysis.bifurcation`) and the
    parameter's values where it appears, disappears, gains or loses stability, or its stability over
    the whole range when nothing changes.

    Parameters
    ----------
    eom : EquationsOfMotion
        The equations the rests are of (their coordinates and parameters name the symbols).
    diagram : BifurcationDiagram
        From `lagrangian.analysis.bifurcation`.

    Returns
    -------
    str
        The text, one paragraph per branch.

    Examples
    --------
    >>> import numpy as np, lagrangian
    >>> from lagrangian.analysis import bifurcation
    >>> eom = lagrangian.derive(lagrangian.load_model("examples/bead_rotating_hoop.toml"))          # doctest: +SKIP
    >>> print(lagrangian.output.bifurcation_text(eom, bifurcation(eom, "Omega", np.arange(1, 8.5, 0.5))))  # doctest: +SKIP
    """
    n = Notation(list(eom.coordinates), [p.name for p in eom.model.parameters])
    values = diagram.values
    sym = n.symbol(diagram.parameter)
    lines = [(f"Equilibria of {eom.model.name} against {sym} from {values[0]:g} to {values[-1]:g} "
              f"({len(values)} values)"), ""]
    for k, b in enumerate(diagram.branches, start=1):
        parts = ", ".join(f"{n.symbol(c)} = {n.text(to_sympy(v))}" for c, v in b.equilibrium.values.items())
        lines.append(f"  {k}. {parts}")
        if not b.changes:
            state = {1.0: "stable", 0.0: "unstable"}
            kinds = {state.get(float(s), "undecided") for s in b.stable if not math.isnan(s)} or {"absent"}
            lines.append(f"     {' / '.join(sorted(kinds))} over the whole range")
        for x, what in b.changes:
            lines.append(f"     {sym} = {x:.12g}: {what}")
    return "\n".join(lines) + "\n"


def _rests(name: str, coordinates: tuple[str, ...], parameters: list[str], found: Sequence[Equilibrium],
           verdicts: Sequence[Verdict]) -> str:
    n = Notation(list(coordinates), parameters)
    lines = [f"Equilibria of {name} (q̇ = 0, q̈ = 0: F(q, 0) + Aᵀλ = 0)", ""]
    if not found:
        lines.append("  none found in the ranges searched")
    for k, (e, stab) in enumerate(zip(found, verdicts, strict=True), start=1):
        parts = []
        for q in coordinates:
            v = e.values[q]
            if q in e.free:
                parts.append(f"{n.symbol(q)} any")
                continue
            shown = _numeric(v) if isinstance(v, float) else n.text(to_sympy(v))
            x = None if e.numeric is None else e.numeric.get(q)
            if x is not None and not isinstance(v, float) and shown != f"{x:.12g}":
                shown += f" = {x:.12g}"
            parts.append(f"{n.symbol(q)} = {shown}")
        how = "closed form" if e.closed_form else "numeric"
        tail = f"  ({how}" + ("" if e.residual is None else f"; residual {e.residual:.1e}") + ")"
        if e.family:
            tail += (f"; one point of a {e.family}-parameter family of rests through it: the static equations' "
                     "Jacobian is singular there")
        lines.append(f"  {k}. " + ", ".join(parts) + tail)
        for alias in e.aliases:
            same = ", ".join(f"{n.symbol(q)} = {_numeric(alias[q])}" for q in coordinates if q in alias)
            lines.append(f"     also {same}: the same configuration (every body in the same place)")
        if e.condition is not None:
            verdict = {True: "holds here", False: "does not hold here", None: "undecided without values"}[e.exists]
            lines.append(f"     exists if {_condition(n, e.condition)} ({verdict})")
        if stab is not None:
            lines.append(f"     {stab[1]}: {stab[2]}")
    return "\n".join(lines) + "\n"


def _searched(n: Notation, search: EquilibriumSearch) -> str:
    """What was searched, so that the list is never read as complete when it may not be."""
    how = "closed form (SymPy)" if search.closed_form else "no closed form (SymPy failed)"
    if not search.numeric:
        why = {"values": "a parameter has no value", "continuum": "the closed form gives a family of rests",
               "not asked": "not asked"}.get(search.skipped or "", "not made")
        return f"Searched: {how}; no numeric search ({why}).\n"
    if not search.regions:
        return f"Searched: {how}; every coordinate is free, none is left to search numerically.\n"
    where = []
    for r in search.regions:
        a, b = r.bounds
        q = n.symbol(r.coordinate)
        if r.kind == "angle":
            where.append(f"{q} over (−π, π]")
        elif r.kind == "scales":
            where.append(f"{q} from 0 and ±10⁻³ … ±10³ and the parameters' values (no range declared)")
        else:
            given = "given" if r.kind == "range" else "declared"
            span = f"[{_bound(a)}, {_bound(b)}]"
            where.append(f"{q} over the {given} range {span}" + ("" if all(map(math.isfinite, r.bounds)) else
                                                              ", from starting points over every scale"))
    text = f"Searched: {how}, then numerically from {search.starts} starting points: " + "; ".join(where) + "."
    if search.unbounded:
        names = ", ".join(n.symbol(q) for q in search.unbounded)
        first = search.unbounded[0]
        text += (f" A rest beyond the starting points' reach may be missing ({names} without a bound: "
                 f"--range {first}=a:b searches an interval).")
    else:
        text += " A numeric search can miss a rest between its starting points."
    return text + "\n"


def _bound(x: float) -> str:
    return "−∞" if x == -math.inf else "+∞" if x == math.inf else f"{x:.6g}".replace("-", "−")


def _numeric(x: float) -> str:
    """A numeric root: −0 as 0, and a root at k π/d (d ≤ 12) to 1e-12 named so (−π/2 = −1.57079632679)."""
    x += 0.0  # −0.0 → 0.0
    if abs(x) < 1e-15:  # a numeric root at 0, to rounding
        return "0"
    value = f"{x:.12g}"
    ratio = sympy.nsimplify(x / math.pi, rational=True, tolerance=1e-12) if x else sympy.Integer(0)
    if x and isinstance(ratio, sympy.Rational) and 0 < ratio.q <= 12 and abs(float(ratio) * math.pi - x) <= 1e-12:
        num, den = abs(ratio.p), ratio.q
        text = ("−" if ratio < 0 else "") + ("" if num == 1 else str(num)) + "π" + ("" if den == 1 else f"/{den}")
        return f"{text} = {value}"
    return value


def _condition(n: Notation, cond: sympy.Basic) -> str:
    if isinstance(cond, sympy.And):
        return " and ".join(_condition(n, c) for c in cond.args)
    op = _RELATIONS.get(type(cond))
    if op is None:
        return sympy.sstr(cond)
    plain = {s: sympy.Symbol(s.name) for s in cond.free_symbols}
    return f"{n.text(cond.lhs.xreplace(plain))} {op} {n.text(cond.rhs.xreplace(plain))}"
