"""Impact outcomes against a parameter or an initial value: one simulated motion per grid point.

For a model with unilateral contacts, `impact_sweep` runs the contacts' route (`run_contact`) at every point of a
grid (parameters, coordinates, rates: the names of `lagrangian sweep`'s ``--grid``) and keeps what
the contacts did: the impacts, the bounces (impacts faster than ``min_speed``), the time of the
first impact, the accumulation time t_∞ where the impacts came to rest, the lift-offs, and the
energy the impacts took.  The bouncing ball's sweep over e gives t_∞ = √(2h₀/g)(1 + e)/(1 − e) and,
with ``min_speed`` v_min, 1 + ⌊ln(v_min/v₁)/ln e⌋ bounces (v₁ = √(2 g h₀)), the approach speeds
being v₁ e^{k−1}.  A member whose run fails keeps its error as its status; the others go on.

`lagrangian.sweep(model, "e", values, t_end=...)` is this sweep along one axis (the same name
sweeps a linearization's eigenvalues when given a `LinearModel`).
"""

from __future__ import annotations

import itertools
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..errors import SimulationError
from ._contact import contact_model, contact_system, run_contact
from ._contact_switch import ContactEvent
from ._options import SimulationOptions

__all__ = ["OUTCOMES", "ImpactSweep", "impact_sweep"]

#: The outcomes kept per member, each an array over the grid.
OUTCOMES = ("impacts", "bounces", "first_impact", "rest_time", "liftoffs", "energy_lost")


@dataclass(frozen=True)
class ImpactSweep:
    """What the contacts did at each point of a grid (module docstring).

    Parameters
    ----------
    axes : mapping of str to ndarray
        Name → values of each grid axis, in order; every outcome has the shape of the grid.
    impacts : ndarray
        Impacts resolved before t_end (simultaneous ones count once), up to the accumulation.
    bounces : ndarray
        Those whose approach speed ``|ġ⁻|`` was at least ``min_speed``.
    first_impact : ndarray
        The time of the first impact (NaN: none).
    rest_time : ndarray
        The time t_∞ where an accumulation of impacts came to rest (NaN: none before t_end).
    liftoffs : ndarray
        Lift-offs of closed contacts.
    energy_lost : ndarray
        Σ (E⁻ − E⁺) over the impacts and the accumulation.
    status : ndarray
        "ok", or the error that stopped the member.
    min_speed : float
        The approach speed from which an impact counts as a bounce.
    """

    axes: Mapping[str, np.ndarray]
    impacts: np.ndarray
    bounces: np.ndarray
    first_impact: np.ndarray
    rest_time: np.ndarray
    liftoffs: np.ndarray
    energy_lost: np.ndarray
    status: np.ndarray
    min_speed: float = 0.0

    @property
    def shape(self) -> tuple[int, ...]:
        return tuple(len(v) for v in self.axes.values())

    def to_dataset(self) -> Any:
        """The outcomes as an `xarray.Dataset` over the grid's axes (``pip install 'lagrangian[ensemble]'``).

        Returns
        -------
        xarray.Dataset
            One variable per outcome, over the grid's axes.
        """
        import xarray as xr

        dims = tuple(self.axes)
        data = {name: (dims, getattr(self, name)) for name in OUTCOMES}
        data["status"] = (dims, self.status.astype(str))
        return xr.Dataset(data, coords={k: np.asarray(v) for k, v in self.axes.items()},
                          attrs={"min_speed": self.min_speed, "format": "lagrangian.impact_sweep"})


def _outcome(events: Sequence, min_speed: float) -> tuple[int, int, float, float, int, float]:
    impacts = [e for e in events if isinstance(e, ContactEvent) and e.kind == "impact"]
    times: dict[float, float] = {}
    for e in impacts:
        times[e.t] = max(times.get(e.t, 0.0), abs(e.speed))
    lost = {e.t: e.energy_before - e.energy_after for e in events
            if isinstance(e, ContactEvent) and e.kind in ("impact", "rest")}
    rest = [e.t for e in events if isinstance(e, ContactEvent) and e.kind == "rest"]
    return (len(times), sum(1 for v in times.values() if v >= min_speed), min(times, default=float("nan")),
            min(rest, default=float("nan")),
            sum(1 for e in events if isinstance(e, ContactEvent) and e.kind == "liftoff"),
            float(sum(lost.values())))


def impact_sweep(source, axes: Mapping[str, Sequence[float] | np.ndarray], t_end: float, *,
                 parameters: Mapping[str, float] | None = None, initial: Mapping[str, float] | None = None,
                 min_speed: float = 0.0, progress: bool = False, **options: Any) -> ImpactSweep:
    """Simulate the contact model ``source`` at every point of the grid ``axes`` (module docstring).

    Parameters
    ----------
    source : str or Path or Model or EquationsOfMotion
        A model file, `Model` or its equations, with unilateral contacts.
    axes : mapping of str to sequence of float
        Name → values; a name is a parameter, a coordinate or a rate (``z_dot``).
    t_end : float
        The end of each run.
    parameters : mapping of str to float, optional
        Parameter values for every member (not swept).
    initial : mapping of str to float, optional
        Initial values for every member (not swept).
    min_speed : float, optional
        The approach speed from which an impact counts as a bounce.
    progress : bool, optional
        True for a progress bar on standard error.
    **options
        `simulate`'s options for the contacts' route (``rtol``, ``atol``, ``rest``...).

    Returns
    -------
    ImpactSweep
        The outcomes over the grid.

    Raises
    ------
    SimulationError
        A model without contacts, an unknown or repeated name, an empty axis.
    """
    model = contact_model(source)
    if model is None:
        raise SimulationError("An impact sweep needs a model with unilateral contacts.",
                              fix="declare a contact ({ unilateral = \"g\", restitution = \"e\" }), or sweep a "
                                  "linearization with lagrangian.sweep(linearize(...), ...)")
    names = [p.name for p in model.parameters]
    coordinates = [c.name for c in model.coordinates]
    known = names + coordinates + [c + "_dot" for c in coordinates]
    grid = {}
    for name, values in axes.items():
        if name not in known:
            raise SimulationError(f"`{name}` is not a parameter, a coordinate or a rate of `{model.name}`.",
                                  fix="sweep one of " + ", ".join(known))
        if name in (parameters or {}) or name in (initial or {}):
            raise SimulationError(f"`{name}` is both swept and set.", fix="give it once")
        array = np.asarray(values, dtype=float).ravel()
        if not array.size or not np.isfinite(array).all():
            raise SimulationError(f"The values of `{name}` must be finite, and at least one.",
                                  fix="e.g. numpy.linspace(0.1, 0.9, 9)")
        grid[name] = array
    if not grid:
        raise SimulationError("An impact sweep needs at least one axis.", fix='e.g. {"e": numpy.linspace(0.1, 0.9, 9)}')
    contact_system(model, options.get("backend", "auto"))  # derived and compiled once, before the members
    shape = tuple(len(v) for v in grid.values())
    out = {name: np.full(shape, np.nan) for name in OUTCOMES}
    status = np.full(shape, "ok", dtype=object)
    members = list(itertools.product(*(range(n) for n in shape)))
    for done, index in enumerate(members):
        point = {name: float(grid[name][i]) for name, i in zip(grid, index, strict=True)}
        p = dict(parameters or {}) | {k: v for k, v in point.items() if k in names}
        y0 = dict(initial or {}) | {k: v for k, v in point.items() if k not in names}
        try:
            traj = run_contact(model, SimulationOptions(t_end, parameters=p, initial=y0, n_out=2, **options))
        except SimulationError as exc:
            status[index] = exc.message
            continue
        for name, value in zip(OUTCOMES, _outcome(traj.events, min_speed), strict=True):
            out[name][index] = value
        if progress:
            from ._progress import progress_bar

            progress_bar((done + 1) / len(members), t_end)
    return ImpactSweep(grid, out["impacts"], out["bounces"], out["first_impact"], out["rest_time"], out["liftoffs"],
                       out["energy_lost"], status, float(min_speed))
