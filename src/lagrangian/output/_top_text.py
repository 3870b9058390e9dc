"""The analysis of a top as terminal text, in the course's notation: what ``lagrangian analyse`` prints.

`top_analysis_text` writes `lagrangian.analysis.analyse_top`'s result (first integrals, cyclic rates,
effective potential, turning angles, nutation period, steady precession, sleeping top) and
`simulation_check_text` the comparison of `lagrangian.numerics.simulation_check`; this module only
writes them.
"""

from __future__ import annotations

import math
import re
from typing import TYPE_CHECKING

import sympy

from ..analysis import first_integrals
from ._notation import Notation
from ._text import literal

if TYPE_CHECKING:
    from ..analysis import TopAnalysis
    from ..dynamics import EquationsOfMotion
    from ..numerics import SimulationCheck

__all__ = ["simulation_check_text", "top_analysis_text"]

DOT = "\u0307"  # combining dot above: psi_dot → ψ̇


def simulation_check_text(check: SimulationCheck, eom: EquationsOfMotion) -> str:
    """What ``lagrangian analyse --simulate`` adds: the analysis against a simulation, value by value.

    With the largest difference (`lagrangian.numerics.simulation_check`).

    Parameters
    ----------
    check : SimulationCheck
        The comparison.
    eom : EquationsOfMotion
        The equations (their notation).

    Returns
    -------
    str
        The text.
    """
    n = Notation(eom.coordinates, [p.name for p in eom.model.parameters])
    lines = ["", (f"Check against a simulation (DOP853, rtol = atol = 1e-12, t from 0 to {_num(check.t_end)} s; "
                  "turning points located as events):")]
    if check.note:
        lines.append(f"  {check.note}")
    for name, value, sims, diff, unit in check.rows:
        shown = _names_in_greek(n, eom.coordinates, name).replace("_dot", DOT)
        got = ", ".join(_num(x) for x in sims) or "none"
        lines.append(f"  {shown}: analysis {_num(value)} {unit}; simulation {got}  (largest difference {diff:.1e})")
    return "\n".join(lines) + "\n"


def _num(x: float) -> str:
    return f"{x:.9g}"


def _angle(x: float) -> str:
    return f"{x:.12f} rad = {math.degrees(x):.6f}°"


def _wrap(text: str) -> str:
    """A denominator or factor in parentheses unless it is a single symbol."""
    return text if text.replace("²", "").isalnum() else f"({text})"


def _cubic_formula(n: Notation, an: TopAnalysis) -> str:
    top = an.top
    assert top is not None
    red = an.reduction
    A = _wrap(n.text(top.A))
    mga = sympy.expand(top.mga._sympy_())
    sign, mga = ("+", -mga) if mga.could_extract_minus_sign() else ("−", mga)
    K = n.symbol(red.momenta[red.cyclic.index(red.precession)])
    if red.spin is not None:
        H = n.symbol(red.momenta[red.cyclic.index(red.spin)])
        momentum = f"({K} − {H} u)/{A}"
    else:
        momentum = f"{K}/{A}"
    return f"f(u) = (2E' {sign} 2 {n.text(mga)} u)(1 − u²)/{A} − ({momentum})²"


def _values_block(n: Notation, an: TopAnalysis, eom: EquationsOfMotion) -> list[str]:
    units = {p.name: f" {p.unit}" if p.unit else "" for p in eom.model.parameters}
    out = ["Values: " + ", ".join(f"{n.symbol(k)} = {_num(v)}{units[k]}" for k, v in an.parameters.items())]
    q = ", ".join(f"{n.symbol(c)} = {_num(an.initial[c])}" for c in eom.coordinates)
    qd = ", ".join(f"{n.symbol(c + '_dot')} = {_num(an.initial[c + '_dot'])}" for c in eom.coordinates)
    out.append(f"Initial state: {q};  {qd}")
    return out


def _nutation_block(n: Notation, an: TopAnalysis) -> list[str]:
    red = an.reduction
    th, E = n.symbol(red.coordinate), red.energy_name
    nut = an.nutation
    if nut is None:
        return ["", _names_in_greek(n, red.cyclic + (red.coordinate,), an.notes[0])]
    lines = ["", f"Turning angles ({'U_eff'}({th}) = {E}):",
             f"  {th}1 = {_angle(nut.theta1)}", f"  {th}2 = {_angle(nut.theta2)}"]
    if an.cubic is not None:
        c = an.cubic
        spin = f" − {n.symbol(red.momenta[red.cyclic.index(red.spin)])}²/(2C)" if red.spin else ""
        lines += [f"  with u = cos{th}, u̇² = {_cubic_formula(n, an)[7:]}",
                  f"    E' = {E}{spin}{' − U0' if an.top and an.top.values[3] else ''} = {_num(c.reduced_energy)}; "
                  f"roots u = " + ", ".join(_num(u) for u in c.roots),
                  (f"    the two in [−1, 1] around cos{th}0 give {th}1 = {c.theta1:.12f}, {th}2 = {c.theta2:.12f} "
                   f"(difference from the root-finding on U_eff: "
                   f"{max(abs(c.theta1 - nut.theta1), abs(c.theta2 - nut.theta2)):.1e} rad)")]
    if nut.steady:
        lines.append(f"Steady precession: {th} stays at {th}1 = {th}2; small oscillations about it have the period "
                     f"T = {_num(nut.period)} s")
    else:
        lines.append(f"Nutation period: T = 2 ∫ d{th}/{n.symbol(red.coordinate + '_dot')} over [{th}1, {th}2] "
                     f"= {_num(nut.period)} s")
        if an.cubic is not None:
            c = an.cubic
            how = f"4K(k)/sqrt(|α|(u3 − u1)), k² = {c.modulus:.9g}" if c.modulus is not None else "2π/sqrt(−c2)"
            lines.append(f"  closed form (elliptic integral): T = {how} = {_num(c.period)} s "
                         f"(relative difference {abs(c.period / nut.period - 1):.1e})")
    prec = red.precession
    others = [c for c in red.cyclic if c != prec]
    mean = f"Mean precession rate: ⟨{n.symbol(prec + '_dot')}⟩ = {_num(nut.mean_rates[prec])} rad/s"
    if others:
        mean += "  (" + ", ".join(f"⟨{n.symbol(c + '_dot')}⟩ = {_num(nut.mean_rates[c])}" for c in others) + ")"
    lines.append(mean)
    reason = _names_in_greek(n, red.cyclic + (red.coordinate,), nut.apex_reason.replace("_dot", DOT))
    lines.append(f"Apex curve: {nut.apex_curve} — {reason}")
    return lines


def _sleeping_block(n: Notation, an: TopAnalysis) -> list[str]:
    red = an.reduction
    th = n.symbol(red.coordinate)
    lines = []
    theta0 = an.initial[red.coordinate]
    for s in an.sleeping:
        where = "0" if s.theta == 0 else "π"
        verdict = {True: "stable", False: "unstable", None: "undecided at second order"}[s.stable]
        if s.spin is not None:
            title = f"Sleeping top ({th} = {where}: spinning with its axis {'up' if s.theta == 0 else 'down'})"
        else:
            title = f"Equilibrium on the axis ({th} = {where}, with the momenta that position allows)"
        lines += ["", title + ":", (f"  U_eff''({where}) = {_text(n, s.stiffness, red)} = {_num(s.stiffness_value)}: "
                                    f"{verdict}")]
        if s.criterion is not None and s.spin is not None:
            lhs, rhs = s.criterion
            rel = ">" if lhs > rhs else ("<" if lhs < rhs else "=")
            formula = "4 A m g a" if s.theta == 0 else "−4 A m g a"
            lines.append(f"  C²ω² = {_num(lhs)} {rel} {formula} = {_num(rhs)}  (ω = H/C = {_num(s.spin)} rad/s"
                         + (f"; critical spin ω_c = {_num(s.critical_spin)} rad/s)" if s.critical_spin else ")"))
        near = abs(math.remainder(theta0 - s.theta, 2 * math.pi)) < 0.1
        same = " with the same spin" if s.spin is not None else ""
        lines.append("  " + (
            f"Applies to this motion: {th}0 = {_num(theta0)} is near {where}, so this decides whether {th} stays "
            f"near {where}." if near else
            f"For a motion started at {th} = {where}{same}; this one starts at {th}0 = {_num(theta0)}."))
    return lines


def _text(n: Notation, expr, red) -> str:
    """A sum written θ-free momentum terms first (H²/(2C)), then the other momentum terms, then the rest."""
    momenta = set(red.momentum_symbols)
    parts = list(expr.args) if expr.is_Add else [expr]

    def rank(term) -> int:
        symbols = term.free_symbols
        if symbols & momenta:
            return 0 if red.symbol not in symbols else 1
        return 2

    return n.sum(sorted(parts, key=rank))


def _names_in_greek(n: Notation, coordinates: tuple[str, ...], text: str) -> str:
    for name in coordinates:
        text = re.sub(rf"(?<![A-Za-z0-9_]){re.escape(name)}([12])(?![A-Za-z0-9])", n.symbol(name) + r"\1", text)
        text = re.sub(rf"(?<![A-Za-z0-9_]){re.escape(name)}(?![A-Za-z0-9])", literal(n.symbol(name)), text)
    return text


def top_analysis_text(an: TopAnalysis, eom: EquationsOfMotion) -> str:
    """What ``lagrangian analyse`` prints: `lagrangian.analysis.analyse_top`'s result in the course's notation.

    Parameters
    ----------
    an : TopAnalysis
        The analysis.
    eom : EquationsOfMotion
        The equations (their notation).

    Returns
    -------
    str
        The text.

    Examples
    --------
    >>> import lagrangian
    >>> eom = lagrangian.derive(lagrangian.load_model("examples/lagrange_top.toml"))          # doctest: +SKIP
    >>> print(lagrangian.output.top_analysis_text(lagrangian.analyse_top(eom), eom))        # doctest: +SKIP
    """
    red = an.reduction
    n = Notation(eom.coordinates, [p.name for p in eom.model.parameters] + list(red.momenta) + [red.energy_name])
    th = n.symbol(red.coordinate)
    cyc = ", ".join(n.symbol(c) for c in red.cyclic)
    lines = [f"{eom.model.name} — analysis of the motion ({cyc} cyclic; {th} remaining)", ""]
    lines += _values_block(n, an, eom)
    lines += ["", "First integrals (values at t = 0):"]
    integrals = {f.name: f for f in first_integrals(eom)}
    for name in (*red.momenta, red.energy_name):
        f = integrals[name]
        why = f"   ({n.symbol(f.coordinate)} cyclic)" if f.coordinate else ""
        lines.append(f"  {name} = {n.text(f.expression)} = {_num(an.constants[name])}{why}")
    lines += ["", f"Cyclic rates solved from {', '.join(red.momenta)}:"]
    lines += [f"  {n.symbol(c + '_dot')} = {_text(n, r, red)}" for c, r in an.rates.items()]
    lines += ["", (f"Effective potential: {red.energy_name} = ½ {_wrap(n.text(an.inertia))} "
                   f"{n.symbol(red.coordinate + '_dot')}² + U_eff({th})"),
              f"  U_eff({th}) = {_text(n, an.effective_potential, red)}"]
    lines += _nutation_block(n, an)
    if an.steady is not None:
        rates = an.steady.rates
        pd = n.symbol(red.precession + "_dot")
        spin = f", same {red.momenta[red.cyclic.index(red.spin)]}" if red.spin else ""
        lines += ["", f"Steady precession at {th} = {_num(an.steady.theta)} ({n.symbol(red.coordinate + '_dot')} = 0"
                      f"{spin}): " + (f"{pd} = {_num(rates[0])} or {_num(rates[1])} rad/s" if rates else
                                      "none (the quadratic in the precession rate has no real root: spin too slow)")]
    lines += _sleeping_block(n, an)
    notes = [x for x in an.notes if an.nutation is not None or x != an.notes[0]]
    if notes:
        lines += [""] + [f"Note: {x}" for x in notes]
    return "\n".join(lines) + "\n"
