"""Declared ranges and sign assumptions, checked along a simulated motion.

A coordinate declared with ``range = [lower, upper]`` is expected to stay there, and the
equations may have been simplified with it (|x + L| = x + L where x ≥ −L,
`lagrangian.model._assumptions`).  After a run, each coordinate is compared with its bounds
(evaluated with the run's parameter values), and each sign the derivation relied on
(``eom.assumptions``) is evaluated along the output grid: where one fails, the trajectory
gets a warning naming the coordinate (or the assumption), the first output time outside,
the value there and the farthest value reached, and a `RangeExit` record (saved with the
trajectory's metadata, ``range_exits``).  Past that time the simplified equations may no
longer be the system's.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass

import numpy as np
import symengine as se

from ..model import SignFact, range_text
from ..model.spec import Model
from ._trajectory import Trajectory

__all__ = ["RangeExit", "watch_ranges"]


@dataclass(frozen=True, slots=True)
class RangeExit:
    """Where a motion first left a declared range (``kind="range"``) or broke a sign the
    derivation used (``kind="assumption"``).

    ``name`` is the coordinate, or the expression of the assumption (``L + x``); ``bounds`` the
    declared range (``[-0.5, 0.5]``) or the relation (``L + x ≥ 0``); ``t`` and ``value`` the first
    output time outside and the value there; ``extreme`` the farthest value reached (and its
    time ``t_extreme``).
    """

    kind: str
    name: str
    bounds: str
    t: float
    value: float
    t_extreme: float
    extreme: float

    def as_dict(self) -> dict[str, object]:
        return dataclasses.asdict(self)

    @property
    def message(self) -> str:
        what = (f"coordinate `{self.name}` left its declared range {self.bounds}" if self.kind == "range"
                else f"the assumption {self.bounds} that the derivation used no longer holds")
        return (f"{what} at t = {self.t:.6g} ({self.name} = {self.value:.6g}; farthest {self.extreme:.6g} at "
                f"t = {self.t_extreme:.6g}): past there the equations simplified with it may not be the system's")


def _first_exit(kind: str, name: str, bounds: str, t: np.ndarray, values: np.ndarray, outside: np.ndarray,
                excess: np.ndarray) -> RangeExit | None:
    if not outside.any():
        return None
    first = int(np.argmax(outside))
    worst = int(np.argmax(np.where(outside, excess, -np.inf)))
    return RangeExit(kind, name, bounds, float(t[first]), float(values[first]), float(t[worst]),
                     float(values[worst]))


def watch_ranges(model: Model, traj: Trajectory, facts: tuple[SignFact, ...] = ()) -> Trajectory:
    """``traj`` with a warning and a `RangeExit` for each declared range it leaves and each used sign it breaks."""
    ranged = [c for c in model.coordinates if c.range is not None]
    if (not ranged and not facts) or len(traj.t) == 0:
        return traj
    given = {p.name: p.value for p in model.parameters if p.value is not None} | dict(traj.parameters)
    values = {se.Symbol(k): float(v) for k, v in given.items()}
    exits: list[RangeExit] = []
    for c in ranged:
        k = traj.coordinates.index(c.name)
        q = traj.q[:, k]
        lower, upper = (None if b is None else float(b.subs(values)) for b in c.range)  # type: ignore[union-attr]
        below = q < lower if lower is not None else np.zeros(len(q), bool)
        above = q > upper if upper is not None else np.zeros(len(q), bool)
        excess = np.maximum(np.where(below, (lower or 0.0) - q, 0.0), np.where(above, q - (upper or 0.0), 0.0))
        bounds = range_text(c.range)  # type: ignore[arg-type]
        hit = _first_exit("range", c.name, bounds, traj.t, q, below | above, excess)
        if hit is not None:
            exits.append(hit)
    if facts:
        q_symbols = [se.Symbol(name) for name in traj.coordinates]
        p_symbols = list(values)
        numeric = se.Lambdify([*q_symbols, *p_symbols], [f.expression for f in facts], cse=True)
        table = np.column_stack([traj.q, np.tile(list(values.values()), (len(traj.t), 1))])
        u = np.asarray(numeric(table), dtype=float).reshape(len(traj.t), len(facts))
        for j, fact in enumerate(facts):
            signed = fact.sign * u[:, j]
            outside = ~(signed >= 0)
            hit = _first_exit("assumption", str(fact.expression), f"{fact.expression} {fact.relation} 0", traj.t,
                              u[:, j], outside, -signed)
            if hit is not None:
                exits.append(hit)
    if not exits:
        return traj
    return dataclasses.replace(traj, warnings=traj.warnings + tuple(e.message for e in exits),
                               range_exits=traj.range_exits + tuple(exits))
