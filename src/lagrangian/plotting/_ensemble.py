"""Pictures of an ensemble: a 2-D map over two grid axes, or min/max curves over one.

* Two axes: the map of one number per member — by default log10 of the first event time
  (the earliest of the events, e.g. either arm's flip: the double pendulum's flip-time
  map), members without an event drawn in white; without events, log10 of the largest
  first-integral drift.
* One axis: for each coordinate, its smallest and largest value over the run against the
  axis (a bifurcation-style diagram: the top's θ1 and θ2 against the spin).

The Dataset is the one `lagrangian.ensemble` returns (grid dimensions); the file is
written atomically, its format taken from its suffix (.png, .pdf, .svg).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from .._atomic import write_atomic_with
from ..errors import OutputError
from ._mpl import new_figure

__all__ = ["plot_ensemble", "map_quantity"]


def map_quantity(ds) -> tuple[np.ndarray, str]:
    """(values over the grid, label): log10 of the first event time, else log10 of the largest drift."""
    if "event_time" in ds:
        first = np.fmin.reduce(ds["event_time"].values, axis=-1) if ds["event_time"].ndim > len(_axes(ds)) else \
            ds["event_time"].values
        with np.errstate(divide="ignore", invalid="ignore"):
            values = np.log10(first)
        names = ", ".join(str(e) for e in ds["event"].values)
        return values, f"log10 of the first event time ({names})"
    if "drift" in ds:
        with np.errstate(divide="ignore", invalid="ignore"):
            return np.log10(np.fmax.reduce(ds["drift"].values, axis=-1)), "log10 of the largest first-integral drift"
    return ds["t_final"].values, "t reached"


def _axes(ds) -> tuple[str, ...]:
    return tuple(d for d in ds["status"].dims)


def plot_ensemble(ds, path: str | Path) -> Path:
    """Write the map (2 grid axes) or the min/max diagram (1 axis) of ``ds`` to ``path``.

    Parameters
    ----------
    ds : xarray.Dataset
        An ensemble over a grid (`lagrangian.numerics.ensemble`).
    path : str or Path
        The image file.

    Returns
    -------
    Path
        The path written.

    Raises
    ------
    OutputError
        When the ensemble is not a grid of 1 or 2 axes, or the file cannot be written.
    """
    path = Path(path)
    axes = _axes(ds)
    if len(axes) == 2:
        fig = new_figure(7.0, 5.8, margins=(0.9, 1.3, 0.7, 0.5))
        ax = fig.add_subplot(1, 1, 1)
        values, label = map_quantity(ds)
        x, y = ds[axes[1]].values, ds[axes[0]].values
        mesh = ax.pcolormesh(x, y, np.ma.masked_invalid(values), shading="nearest", cmap="viridis")
        fig.colorbar(mesh, ax=ax, label=label)
        ax.set_xlabel(axes[1])
        ax.set_ylabel(axes[0])
        ax.set_title(f"{label}\n(white: none within the run)" if "event" in label else label, fontsize=10)
    elif len(axes) == 1 and axes[0] != "member":
        states = [str(s) for s in ds["state"].values if not str(s).endswith("_dot")]
        fig = new_figure(7.0, 2.0 + 1.6 * len(states), margins=(0.9, 0.3, 0.7, 0.4))
        x = ds[axes[0]].values
        for k, name in enumerate(states):
            ax = fig.add_subplot(len(states), 1, k + 1)
            ax.plot(x, ds["state_min"].sel(state=name).values, ".-", ms=3, label=f"min {name}")
            ax.plot(x, ds["state_max"].sel(state=name).values, ".-", ms=3, label=f"max {name}")
            ax.set_ylabel(name)
            ax.legend(fontsize=8, loc="best")
        ax.set_xlabel(axes[0])
    else:
        raise OutputError(f"A plot of an ensemble needs a grid of 1 or 2 axes (this one has dimensions "
                          f"{', '.join(axes)}).", fix="sweep one or two --grid axes, or plot the Dataset yourself")
    fmt = path.suffix.lstrip(".").lower() or "png"
    try:
        write_atomic_with(path, lambda handle: fig.savefig(handle, format=fmt, dpi=110))
    except (OSError, ValueError) as exc:
        raise OutputError(f"`{path}` could not be written: {exc}", fix="give a .png, .pdf or .svg path in an "
                                                                        "existing folder") from None
    return path
