"""``lagrangian sweep MODEL --grid NAME=START:STOP:COUNT ... --t-end T [--event EXPR|flip] --out X.zarr``.

A parameter sweep: every combination of the grid axes is one member of an ensemble
(`lagrangian.ensemble`), integrated in compiled batches on every core, or on a Dask
cluster with ``--scheduler tcp://HOST:8786``.  Per member the summaries are written to a
Zarr store (chunk by chunk: Ctrl-C keeps the finished members, ``--resume`` finishes the
others) or a NetCDF file; ``--plot`` draws the 2-D map (two axes) or the min/max diagram
(one axis).  Grid bounds are plain ASCII decimal numbers, never expressions.
"""

from __future__ import annotations

import argparse
import math
import sys
import time
from pathlib import Path

import numpy as np

from ..dynamics import derive
from ..errors import OutputError
from ..numerics import EventSpec, compile_system, ensemble, flip_events, grid
from ..numerics._ensemble import connect_scheduler
from ._settings import SettingError, add_set_option, number_argument, parse_settings, plain_number
from ._source import MODEL_HELP, load_source

__all__ = ["register", "parse_grid"]

SUMMARY = "integrate a grid of initial states or parameters on every core (or a Dask cluster);\n" \
          "summaries to Zarr/NetCDF, a 2-D map or a min/max diagram with --plot; --resume after Ctrl-C"

#: Most members one sweep may have (a grid typo such as 1e9 points is refused before any work).
MAX_MEMBERS = 10**8


def parse_grid(items: list[str], model) -> dict[str, np.ndarray]:
    """``["theta1=-3.1:3.1:400", ...]`` -> {name: np.linspace(start, stop, count)}.

    Raises
    ------
    SettingError
        Bad form, a bound that is not a plain finite decimal, a count that is not an integer
        >= 1, an unknown or repeated name, or too many members.

    >>> from lagrangian import lagrange_top
    >>> parse_grid(["theta=0.1:0.3:3"], lagrange_top())["theta"].tolist()
    [0.1, 0.2, 0.3]
    """
    known = [p.name for p in model.parameters] + [c.name for c in model.coordinates] + \
        [c.name + "_dot" for c in model.coordinates]
    axes: dict[str, np.ndarray] = {}
    for item in items:
        name, sep, spec = item.partition("=")
        name = name.strip()
        parts = spec.split(":")
        if not sep or not name or len(parts) != 3:
            raise SettingError(f"`--grid {item}` is not of the form NAME=START:STOP:COUNT.",
                               fix="write e.g. `--grid theta1=-3.1:3.1:400`")
        try:
            start, stop = plain_number(parts[0]), plain_number(parts[1])
        except ValueError:
            raise SettingError(f"In `--grid {item}`, the bounds must be plain decimal numbers (expressions are not "
                               "evaluated).", fix="write the numbers themselves, e.g. -3.1:3.1:400") from None
        count_text = parts[2].strip()
        if not (count_text.isascii() and count_text.isdigit()) or int(count_text) < 1:
            raise SettingError(f"In `--grid {item}`, the count `{parts[2]}` must be a whole number >= 1.",
                               fix="e.g. `--grid theta1=-3.1:3.1:400`")
        if not (math.isfinite(start) and math.isfinite(stop)):
            raise SettingError(f"In `--grid {item}`, the bounds must be finite.", fix="give finite bounds")
        if name not in known:
            raise SettingError(f"`{name}` in `--grid {item}` is not a parameter, a coordinate or a coordinate's rate "
                               f"of `{model.name}`.", fix="known names: " + ", ".join(known))
        if name in axes:
            raise SettingError(f"`{name}` is swept twice.", fix="give one --grid per name")
        axes[name] = np.linspace(start, stop, int(count_text))
    if not axes:
        raise SettingError("A sweep needs at least one --grid axis.", fix="e.g. `--grid theta1=-3.1:3.1:100`")
    size = math.prod(len(v) for v in axes.values())
    if size > MAX_MEMBERS:
        raise SettingError(f"The grid has {size} members, more than {MAX_MEMBERS}.",
                           fix="use fewer points, or split the sweep")
    return axes


def register(sub: argparse._SubParsersAction) -> None:
    s = sub.add_parser(
        "sweep", help="integrate a grid of initial states or parameters (an ensemble)",
        description="Integrate one motion per point of a grid over coordinates, rates and parameters, in compiled "
                    "batches on every core (or on a Dask cluster), keeping per member the min, max and final "
                    "state, the first time of each event, the drift of each first integral and a status "
                    "(ok, stopped, blow-up, step-limit, singular). Ctrl-C keeps the finished members in the "
                    "Zarr store; --resume finishes it.")
    s.add_argument("model", nargs="?", help=MODEL_HELP)
    s.add_argument("--grid", action="append", default=[], metavar="NAME=START:STOP:COUNT",
                   help="a grid axis over a coordinate (theta1), a rate (theta1_dot) or a parameter (g); repeatable")
    s.add_argument("--t-end", type=number_argument, default=10.0, metavar="T", help="end time (default 10)")
    s.add_argument("--t-start", type=number_argument, default=0.0, metavar="T0", help="start time (default 0)")
    add_set_option(s)
    s.add_argument("--method", choices=("dop853", "gauss-legendre"), default="dop853")
    s.add_argument("--stiffness-check", action=argparse.BooleanOptionalAction, default=True,
                   help="dop853: stop a member whose equations turn out stiff (status `stiff`) rather than let it "
                        "crawl (default: on)")
    s.add_argument("--rtol", type=number_argument, default=1e-10, help="relative tolerance (default 1e-10)")
    s.add_argument("--atol", type=number_argument, default=1e-10, help="absolute tolerance (default 1e-10)")
    s.add_argument("--dt", type=number_argument, default=None, help="fixed step (gauss-legendre)")
    s.add_argument("--n-out", type=int, default=101, metavar="N",
                   help="output times the summaries are taken over (default 101)")
    s.add_argument("--event", action="append", default=[], metavar="EXPR",
                   help="record the first time EXPR crosses zero (e.g. theta_dot); `flip`: an angle passing ±pi")
    s.add_argument("--stop-when", action="append", default=[], metavar="EXPR",
                   help="end each member at the first zero crossing of EXPR (or `flip`)")
    s.add_argument("--out", metavar="FILE", required=True,
                   help="results: a Zarr store (.zarr) or NetCDF (.nc); for a model with contacts NetCDF or CSV")
    s.add_argument("--min-speed", type=number_argument, default=0.0, metavar="V",
                   help="a model with contacts: count as bounces the impacts with an approach speed >= V")
    s.add_argument("--plot", metavar="IMAGE", help="draw the 2-D map (two axes) or min/max diagram (one axis)")
    s.add_argument("--workers", type=int, default=None, metavar="N", help="local threads (default: every core)")
    s.add_argument("--scheduler", metavar="ADDRESS", help="run on a Dask cluster, e.g. tcp://HOST:8786")
    s.add_argument("--backend", choices=("c", "jax"), default="c",
                   help="c: the compiled batch integrator (default); jax: the JAX export with diffrax, for a GPU "
                        "(pip install 'lagrangian[jax]'; no events, no --scheduler)")
    s.add_argument("--resume", action="store_true", help="finish the pending members of an interrupted --out store")
    s.add_argument("--progress", action=argparse.BooleanOptionalAction, default=None,
                   help="show a progress bar over members (default: when standard error is a terminal)")
    s.set_defaults(run=run)


def _events(texts: list[str], eom, terminal: bool) -> list[EventSpec]:
    out = []
    for text in texts:
        if text.strip() == "flip":
            out += [EventSpec(e.name, e.expression, e.direction, terminal) for e in flip_events(eom)]
        else:
            out.append(EventSpec(text, text, 0, terminal))
    return out


def run(args: argparse.Namespace) -> str:
    model = load_source(args.model)
    axes = parse_grid(args.grid, model)
    parameters, initial = parse_settings(args.set, model)
    twice = sorted(set(axes) & (set(parameters) | set(initial)))
    if twice:
        raise SettingError(f"`{twice[0]}` is both swept and set.", fix="give it once")
    from ..numerics._contact import contact_model

    if contact_model(model) is not None:  # phases switched by impacts: one motion after the other
        from ._impact_sweep import run_impact_sweep

        return run_impact_sweep(args, model, axes, parameters, initial)
    out = Path(args.out)
    if out.suffix not in (".zarr", ".nc"):
        raise OutputError(f"`--out {out}`: a sweep writes a Zarr store (.zarr) or a NetCDF file (.nc).",
                          fix="e.g. --out map.zarr")
    if out.suffix == ".zarr" and out.exists() != bool(args.resume):  # said again, with more, by `ensemble`
        raise OutputError(f"`{out}` already exists." if out.exists() else f"`{out}` does not exist, so there is "
                          "nothing to resume.", fix="add --resume to finish an interrupted sweep in it, or remove it "
                          "/ choose another name" if out.exists() else "run the sweep without --resume first")
    if args.plot:
        from ..plotting._mpl import require_matplotlib

        require_matplotlib()
        if not Path(args.plot).parent.resolve().is_dir():
            raise OutputError(f"`--plot {args.plot}`: its folder does not exist.", fix="create it first")
    if args.workers is not None and args.workers < 1:
        raise SettingError("--workers must be at least 1.", fix="e.g. --workers 2")
    # An unreachable scheduler is said before the model is derived and compiled.
    client, opened = connect_scheduler(args.scheduler) if args.scheduler else (None, False)
    try:
        return _sweep(args, model, axes, parameters, initial, out, client)
    finally:
        if opened:
            client.close()


def _sweep(args, model, axes, parameters, initial, out, client) -> str:
    eom = derive(_with_initial(model, initial))
    events = _events(args.event, eom, False) + _events(args.stop_when, eom, True)
    source = eom if events or args.backend != "c" else compile_system(eom)
    progress = sys.stderr.isatty() if args.progress is None else args.progress
    g = grid(**axes)
    start = time.perf_counter()
    ds = ensemble(source, args.t_end, t_start=args.t_start, initial=g, parameters=parameters or None,
                  method=args.method, rtol=args.rtol, atol=args.atol, stiffness_check=args.stiffness_check,
                  dt=args.dt, n_out=args.n_out, events=events, workers=args.workers, scheduler=client,
                  out=out, resume=args.resume, progress=progress, backend=args.backend)
    elapsed = time.perf_counter() - start
    from ..numerics._batch import STATUS

    codes, counts = np.unique(ds["status"].values, return_counts=True)
    lines = [f"{model.name}: {g.size} members ({' x '.join(f'{n} {len(v)}' for n, v in axes.items())}), t from "
             f"{args.t_start:g} to {args.t_end:g}, {elapsed:.2f} s",
             "status: " + ", ".join(f"{STATUS[int(c)]} {n}" for c, n in zip(codes, counts))]
    if "event_time" in ds:
        for name in ds["event"].values:
            times = ds["event_time"].sel(event=name).values
            hit = np.isfinite(times)
            lines.append(f"event {name}: in {int(hit.sum())} members" +
                         (f", first at t = {np.nanmin(times):.6g}" if hit.any() else ""))
    written = [str(out)]
    if args.plot:
        from ..plotting import plot_ensemble

        written.append(str(plot_ensemble(ds, args.plot)))
    lines.append("wrote " + ", ".join(written))
    return "\n".join(lines) + "\n"


def _with_initial(model, initial: dict[str, float]):
    """The model with the --set initial values and rates as its own: the start of every member not swept."""
    if not initial:
        return model
    from dataclasses import replace

    coordinates = tuple(replace(c, initial=initial.get(c.name, c.initial), rate=initial.get(c.name + "_dot", c.rate))
                        for c in model.coordinates)
    return replace(model, coordinates=coordinates)
