"""The result of a simulation: arrays over time, the monitors, and how the run went.

A `Trajectory` holds only NumPy arrays and plain values (no SymPy), so it can be saved,
plotted or compared without the symbolic engine.  Its layout:

* ``t`` — shape (N,), the output times;
* ``q``, ``qd``, ``qdd`` — shape (N, n): q_i, q̇_i and q̈_i (q̈ from M q̈ = F at each output);
* ``monitors`` — name → shape (N,): every first integral of the model (K, H, the energy
  E = T + U or the Painlevé–Jacobi integral, ...) and ``T``, ``U``;
* ``drift`` — name → the relative drift max|I(t) − I(t0)| / max(|I(t0)|, scale) of each
  first integral, the conservation monitor reported at the end of each run.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field

import numpy as np

__all__ = ["Trajectory", "Event"]


@dataclass(frozen=True)
class Event:
    """One occurrence of an event: its name, its time and the state (q, q̇) there."""

    name: str
    t: float
    q: np.ndarray
    qd: np.ndarray


@dataclass(frozen=True)
class Trajectory:
    """A simulated motion (see the module docstring for the layout).

    Attributes
    ----------
    coordinates : names of q_1..q_n, in the model's order.
    parameters : the parameter values used.
    method : the integrator, e.g. ``"dop853"``.
    steps, rhs_calls : accepted steps and right-hand-side evaluations.
    integrals : names of the monitors that are first integrals (their drift is reported).
    tolerance : the drift tolerance asked for; `warnings` lists the integrals that exceeded it.
    events : the events that occurred, in time order.
    conditioning : the smallest relative pivot of M met during the run (1 for a diagonal
        M, 0 at a singular configuration); below 1e-6 a warning says accuracy may be lost.
    """

    model_name: str
    coordinates: tuple[str, ...]
    parameters: Mapping[str, float]
    t: np.ndarray
    q: np.ndarray
    qd: np.ndarray
    qdd: np.ndarray
    monitors: Mapping[str, np.ndarray]
    integrals: tuple[str, ...]
    drift: Mapping[str, float]
    method: str
    steps: int
    rhs_calls: int
    tolerance: float | None = None
    warnings: tuple[str, ...] = ()
    events: tuple[Event, ...] = ()
    status: str = "completed"
    conditioning: float = 1.0
    extra: Mapping[str, np.ndarray] = field(default_factory=dict)

    def __post_init__(self) -> None:
        n, N = len(self.coordinates), len(self.t)
        for name in ("q", "qd", "qdd"):
            shape = getattr(self, name).shape
            if shape != (N, n):
                raise ValueError(f"Trajectory.{name} has shape {shape}, expected {(N, n)}")

    def __len__(self) -> int:
        return len(self.t)

    def column(self, name: str) -> np.ndarray:
        """One column by name: ``"t"``, a coordinate ``"theta"``, its rate ``"theta_dot"``,
        its acceleration ``"theta_ddot"``, or a monitor (``"K"``, ``"E"``, ``"T"``...)."""
        if name == "t":
            return self.t
        for suffix, array in (("_ddot", self.qdd), ("_dot", self.qd), ("", self.q)):
            if name.endswith(suffix):
                base = name[: len(name) - len(suffix)] if suffix else name
                if base in self.coordinates:
                    return array[:, self.coordinates.index(base)]
        if name in self.monitors:
            return self.monitors[name]
        if name in self.extra:
            return self.extra[name]
        raise KeyError(f"no column `{name}`; columns are {', '.join(self.columns())}")

    def columns(self) -> list[str]:
        """Every column name, in file order."""
        c = self.coordinates
        return ["t", *c, *(f"{x}_dot" for x in c), *(f"{x}_ddot" for x in c), *self.monitors, *self.extra]

    def table(self) -> np.ndarray:
        """All columns as one (N, k) array, in the order of `columns`."""
        return np.column_stack([self.column(name) for name in self.columns()]) + 0.0  # no "-0" in files

    def drift_summary(self) -> str:
        """E.g. ``"E relative drift 3.1e-12, K 1.0e-13, H 0"``."""
        parts = []
        for i, name in enumerate(self.integrals):
            value = self.drift[name]
            text = "0" if value == 0 else f"{value:.1e}"
            parts.append(f"{name} relative drift {text}" if i == 0 else f"{name} {text}")
        return ", ".join(parts)
