"""``lagrangian equilibria MODEL [--set NAME=VALUE] [--range NAME=a:b] [--json] [-o FILE]``.

Every static equilibrium (q̇ = 0, q̈ = 0) of an autonomous model, in closed form with its
condition of existence when SymPy finds one, numerically otherwise (`lagrangian.equilibria`).
Values on the command line are plain decimal numbers, never expressions.
"""

from __future__ import annotations

import argparse
import json
import math
from pathlib import Path

import symengine as se
import sympy

from ..analysis import Equilibrium, LinearizationError, bifurcation, equilibria, linearize
from ..dynamics import derive
from ..errors import OutputError
from ..model import CoulombFriction
from ..output import Notation
from ..output._course import to_sympy
from ._arguments.equilibria import SCHEMA
from ._modes import _check_plot_folder as check_plot_folder
from ._modes import parse_sweep
from ._settings import SettingError, parse_settings, plain_number
from ._source import load_source

__all__ = ["SCHEMA", "parse_ranges", "run"]

_RELATIONS = {sympy.StrictGreaterThan: ">", sympy.GreaterThan: "≥", sympy.StrictLessThan: "<",
              sympy.LessThan: "≤", sympy.Equality: "=", sympy.Unequality: "≠"}


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
            lo, hi = plain_number(a), plain_number(b)
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
        name = min(initial)
        raise SettingError(f"--set {name}=...: an equilibrium is found, not given; --set takes parameters only",
                           fix="remove it, or use --range to say where to look")
    ranges = parse_ranges(args.range, tuple(c.name for c in model.coordinates))
    if args.plot and not args.sweep:
        raise SettingError("`--plot` draws the equilibria against a parameter: it needs --sweep.",
                           fix="add e.g. `--sweep Omega=0:10:0.05`")
    swept = parse_sweep(args.sweep, model) if args.sweep else None
    folder = Path(args.plot) if args.plot else None
    if folder is not None:
        check_plot_folder(folder)
    eom = derive(model)
    if swept is not None:
        return _sweep(eom, swept, parameters, folder, args.lang, args.json)
    found = equilibria(eom, parameters=parameters or None, ranges=ranges)
    values = {p.name: parameters.get(p.name, p.value) for p in model.parameters}
    verdicts = [_stability(eom, e, parameters) for e in found]
    if args.json:
        return json.dumps(_document(model.name, eom.coordinates, values, found, verdicts, found.search),
                          indent=2) + "\n"
    text = _text(model.name, eom.coordinates, [p.name for p in model.parameters], found, verdicts)
    text += "\n" + _searched(Notation(list(eom.coordinates), [p.name for p in model.parameters]), found.search)
    if not found:
        # Say why: a closed-form branch may exist at other values (R Ω² > g, |tan α| ≤ f_s).
        absent = [e for e in equilibria(eom, parameters=parameters or None, ranges=ranges, all_branches=True)
                  if e.exists is False and e.condition is not None]
        n = Notation(list(eom.coordinates), [p.name for p in model.parameters])
        for e in absent:
            where = ", ".join(f"{n.symbol(q)} any" if q in e.free else f"{n.symbol(q)} = {n.text(to_sympy(e.values[q]))}"
                              for q in eom.coordinates)
            text += f"  ({where} would be one if {_condition(n, e.condition)}, which does not hold at these values)\n"
    return text


def _stability(eom, e: Equilibrium, parameters: dict) -> tuple[bool | None, str, str] | None:  # type: ignore[no-untyped-def]
    """(stable, verdict, reason) from the linearization at the equilibrium's numeric value, or None (no
    value).  A family ("r any") is linearized at one of its points, its free coordinates at 0 (a shift along
    it is another rest: a zero column of A); a rest where the linearization cannot be made says why (a
    singular mass matrix: the coordinates are singular there)."""
    if e.exists is False:
        return None
    point = _point(eom, e, parameters)
    if point is None:
        return None
    if any(isinstance(load, CoulombFriction) and load.exact for load in eom.model.loads):
        return None, "undecided", ("held by dry friction: Coulomb's law is not differentiable at rest, so no "
                                   "linearization applies; the rest holds while the friction it needs stays in the "
                                   "cone |T| ≤ f_s N.")
    try:
        st = linearize(eom, point, parameters=parameters or None).stability()
    except LinearizationError as exc:
        if "mass matrix M is singular" in exc.message:
            return None, "undecided", ("the mass matrix M is singular here: the coordinates do not describe the "
                                       "motion near this rest (as polar coordinates at r = 0), so neither M q̈ = F "
                                       "nor its linearization decides; study it in other coordinates.")
        return None, "undecided", f"no linearization here: {exc.message}"
    return st.stable, st.verdict, st.reason


def _point(eom, e: Equilibrium, parameters: dict) -> dict[str, float] | None:  # type: ignore[no-untyped-def]
    """The equilibrium's values as numbers, its free coordinates at 0; None without values."""
    numbers = {se.Symbol(p.name): parameters.get(p.name, p.value) for p in eom.model.parameters
               if parameters.get(p.name, p.value) is not None}
    out = {}
    for q in eom.coordinates:
        if q in e.free:
            out[q] = 0.0
            continue
        v = e.numeric.get(q) if e.numeric is not None else e.values.get(q)
        try:
            out[q] = float(v.subs(numbers)) if isinstance(v, se.Basic) else float(v)  # type: ignore[arg-type]
        except (TypeError, ValueError, RuntimeError):
            return None
    return out


def _document(name: str, coordinates: tuple[str, ...], values: dict, found: tuple[Equilibrium, ...],
              verdicts: list, search) -> dict:  # type: ignore[no-untyped-def]
    def bound(x: float) -> float | None:
        return x if math.isfinite(x) else None  # JSON has no infinity: null for an open side

    return {
        "schema": SCHEMA, "version": 1, "model": name, "coordinates": list(coordinates), "parameters": values,
        # What was searched: the list holds what was found there (a rest beyond the starting points' reach, or
        # between them, may be missing: `unbounded` names the coordinates searched without a bound).
        "search": {"closed_form": search.closed_form, "numeric": search.numeric, "skipped": search.skipped,
                   "starts": search.starts,
                   "regions": [{"coordinate": r.coordinate, "kind": r.kind,
                                "bounds": [bound(r.bounds[0]), bound(r.bounds[1])]} for r in search.regions],
                   "unbounded": list(search.unbounded)},
        "equilibria": [{
            "values": {n: (v if isinstance(v, float) else str(v)) for n, v in e.values.items()},
            "numeric": None if e.numeric is None else {n: e.numeric[n] for n in coordinates if n in e.numeric},
            "closed_form": e.closed_form, "condition": e.condition_text, "exists": e.exists,
            "residual": e.residual, "free": list(e.free), "family": e.family,
            "aliases": [{n: a[n] for n in coordinates if n in a} for a in e.aliases],
            "stable": None if v is None else v[0], "stability_verdict": None if v is None else v[1],
            "stability_reason": None if v is None else v[2],
        } for e, v in zip(found, verdicts, strict=True)],
    }


def _text(name: str, coordinates: tuple[str, ...], parameters: list[str], found: tuple[Equilibrium, ...],
          verdicts: list) -> str:
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


def _searched(n: Notation, search) -> str:  # type: ignore[no-untyped-def]
    """What was searched, so that the list is never read as complete when it may not be."""
    how = "closed form (SymPy)" if search.closed_form else "no closed form (SymPy failed)"
    if not search.numeric:
        why = {"values": "a parameter has no value", "continuum": "the closed form gives a family of rests",
               "not asked": "not asked"}.get(search.skipped, "not made")
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


def _sweep(eom, swept, parameters: dict, folder: Path | None, lang: str, as_json: bool) -> str:  # type: ignore[no-untyped-def]
    """The closed-form branches along the parameter: where each appears and changes stability."""
    name, values = swept
    diagram = bifurcation(eom, name, values, parameters=parameters or None)
    n = Notation(list(eom.coordinates), [p.name for p in eom.model.parameters])
    written = []
    if folder is not None:
        from ..plotting import plot_bifurcation, save_figure
        fig = plot_bifurcation(diagram, eom, lang=lang)
        try:
            folder.mkdir(parents=True, exist_ok=True)
        except OSError as exc:
            raise OutputError(f"Cannot create the folder `{folder}`: {exc.strerror or exc}.",
                              fix="check the path and its permissions") from None
        written.append(save_figure(fig, folder / "bifurcation.png"))
    if as_json:
        doc = {"schema": SCHEMA, "version": 1, "model": eom.model.name, "parameter": name,
               "values": [float(v) for v in values],
               "branches": [{"values": {c: str(v) for c, v in b.equilibrium.values.items()},
                             "condition": b.equilibrium.condition_text,
                             "stable": [None if math.isnan(s) else bool(s) for s in b.stable],
                             "changes": [{"value": x, "kind": what} for x, what in b.changes]}
                            for b in diagram.branches]}
        return json.dumps(doc, indent=2) + "\n"
    sym = n.symbol(name)
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
    lines += [f"wrote {p}" for p in written]
    return "\n".join(lines) + "\n"
