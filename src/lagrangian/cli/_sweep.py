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
from ..numerics import EventSpec, compile_system, connect_scheduler, ensemble, flip_events, grid
from ._settings import SettingError, parse_settings, plain_number
from ._source import load_source

__all__ = ["parse_grid", "run"]

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
    from ..numerics import contact_model

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
        from ..plotting import require_matplotlib

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
        if opened and client is not None:
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
    from ..numerics import STATUS

    codes, counts = np.unique(ds["status"].values, return_counts=True)
    lines = [f"{model.name}: {g.size} members ({' x '.join(f'{n} {len(v)}' for n, v in axes.items())}), t from "
             f"{args.t_start:g} to {args.t_end:g}, {elapsed:.2f} s",
             "status: " + ", ".join(f"{STATUS[int(c)]} {n}" for c, n in zip(codes, counts, strict=True))]
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
