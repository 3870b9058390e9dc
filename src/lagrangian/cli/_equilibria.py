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

from ..analysis import Equilibrium, LinearizationError, bifurcation, equilibria, linearize
from ..dynamics import derive
from ..errors import OutputError
from ..model import CoulombFriction
from ..output import bifurcation_text, equilibria_text
from ._arguments.equilibria import SCHEMA
from ._modes import _check_plot_folder as check_plot_folder
from ._modes import parse_sweep
from ._settings import SettingError, parse_settings, plain_number
from ._source import load_source

__all__ = ["SCHEMA", "parse_ranges", "run"]

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
    absent = []
    if not found:
        # Say why: a closed-form branch may exist at other values (R Ω² > g, |tan α| ≤ f_s).
        absent = [e for e in equilibria(eom, parameters=parameters or None, ranges=ranges, all_branches=True)
                  if e.exists is False and e.condition is not None]
    return equilibria_text(eom, found, verdicts, absent=absent)


def _stability(eom, e: Equilibrium, parameters: dict) -> tuple[bool | None, str, str] | None:
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


def _point(eom, e: Equilibrium, parameters: dict) -> dict[str, float] | None:
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
              verdicts: list, search) -> dict:
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


def _sweep(eom, swept, parameters: dict, folder: Path | None, lang: str, as_json: bool) -> str:
    """The closed-form branches along the parameter: where each appears and changes stability."""
    name, values = swept
    diagram = bifurcation(eom, name, values, parameters=parameters or None)
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
    return bifurcation_text(eom, diagram) + "".join(f"wrote {p}\n" for p in written)
