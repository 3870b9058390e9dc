"""``lagrangian sweep`` for a model with unilateral contacts: impact outcomes over the grid.

A contact model is not integrated in batches (its phases are switched by impacts), so its sweep
runs `lagrangian.numerics.impact_sweep`: one motion per grid point, and per member the impacts,
the bounces (``--min-speed``), the first impact, the rest time t_∞, the lift-offs and the
energy the impacts took.  ``--out`` writes them as NetCDF (``.nc``) or CSV (``.csv``, one row
per member), atomically; ``--plot`` draws them against a single axis.
"""

from __future__ import annotations

import argparse
import io
import itertools
import time
from pathlib import Path
from typing import Any

import numpy as np

from .._atomic import write_atomic, write_atomic_with
from ..errors import OutputError
from ..numerics import OUTCOMES, ImpactSweep, impact_sweep
from ._settings import SettingError

__all__ = ["SUFFIXES", "run_impact_sweep"]

SUFFIXES = (".nc", ".csv")


def _check(args: argparse.Namespace, axes: dict[str, np.ndarray], out: Path) -> None:
    if out.suffix not in SUFFIXES:
        raise OutputError(f"`--out {out}`: the impact sweep of a model with contacts writes NetCDF (.nc) or CSV "
                          "(.csv).", fix="e.g. --out bounces.csv")
    refused = [name for name, given in (("--scheduler", args.scheduler), ("--resume", args.resume),
                                        ("--event", args.event), ("--stop-when", args.stop_when)) if given]
    if args.backend != "c":
        refused.append("--backend jax")
    if args.method != "dop853" or args.dt is not None:
        refused.append("--method/--dt")
    if refused:
        raise SettingError(f"{refused[0]} is not available for a model with unilateral contacts (its motions are "
                           "integrated one after the other, phase by phase).", fix=f"leave {refused[0]} out")
    if args.plot and len(axes) != 1:
        raise SettingError("--plot draws an impact sweep along one axis.", fix="give one --grid, or leave --plot out")


def _csv(result: ImpactSweep) -> str:
    buffer = io.StringIO()
    names = list(result.axes)
    buffer.write(f"# lagrangian impact sweep, min_speed = {result.min_speed:.17g}\n")
    buffer.write(",".join(names + list(OUTCOMES) + ["status"]) + "\n")
    for index in itertools.product(*(range(len(v)) for v in result.axes.values())):
        row = [f"{result.axes[n][i]:.17g}" for n, i in zip(names, index, strict=True)]
        row += [f"{getattr(result, k)[index]:.17g}" for k in OUTCOMES]
        row.append('"' + str(result.status[index]).replace('"', "'") + '"')
        buffer.write(",".join(row) + "\n")
    return buffer.getvalue()


def _plot(result: ImpactSweep, path: str) -> str:
    from ..plotting import new_figure

    (name, values), = result.axes.items()
    fig = new_figure(7.0, 5.0, hspace=0.35)
    top, bottom = fig.add_subplot(2, 1, 1), fig.add_subplot(2, 1, 2)
    top.plot(values, result.impacts, "o-", label="impacts")
    if result.min_speed > 0:
        top.plot(values, result.bounces, "s-", label=f"bounces (|ġ⁻| ≥ {result.min_speed:g})")
    top.set_ylabel("count")
    top.legend()
    bottom.plot(values, result.rest_time, "o-", color="C2")
    bottom.set_ylabel("rest time t∞")
    bottom.set_xlabel(name)
    fig.savefig(path)
    return path


def run_impact_sweep(args: argparse.Namespace, model: Any, axes: dict[str, np.ndarray],
                     parameters: dict[str, float], initial: dict[str, float]) -> str:
    """The sweep of a model with contacts (module docstring); the text printed."""
    out = Path(args.out)
    _check(args, axes, out)
    start = time.perf_counter()
    result = impact_sweep(model, axes, args.t_end, parameters=parameters or None, initial=initial or None,
                          min_speed=args.min_speed, rtol=args.rtol, atol=args.atol, t_start=args.t_start,
                          stiffness_check=args.stiffness_check)
    elapsed = time.perf_counter() - start
    if out.suffix == ".csv":
        write_atomic(out, _csv(result))
    else:
        ds = result.to_dataset()
        write_atomic_with(out, lambda f: f.write(ds.to_netcdf()))
    ok = int(np.sum(result.status == "ok"))
    lines = [(f"{model.name}: {result.status.size} members ({' x '.join(f'{n} {len(v)}' for n, v in axes.items())}), "
             f"t from {args.t_start:g} to {args.t_end:g}, {elapsed:.2f} s; {ok} ok")]
    if len(axes) == 1:
        (name, values), = axes.items()
        lines.append(f"{name:>12}  impacts  bounces  rest time")
        for k, v in enumerate(values):
            lines.append(f"{v:12.6g}  {result.impacts[k]:7.0f}  {result.bounces[k]:7.0f}  {result.rest_time[k]:.9g}")
    written = [str(out)]
    if args.plot:
        written.append(_plot(result, args.plot))
    lines.append("wrote " + ", ".join(written))
    return "\n".join(lines) + "\n"
