"""The result of a simulation: arrays over time, the monitors, and how the run went.

A `Trajectory` holds only NumPy arrays and plain values (no SymPy), so it can be saved,
plotted or compared without the symbolic engine.  Its layout:

* ``t`` — shape (N,), the output times;
* ``q``, ``qd``, ``qdd`` — shape (N, n): q_i, q̇_i and q̈_i (q̈ from M q̈ = F at each output);
* ``monitors`` — name → shape (N,): every first integral of the model (K, H, the energy
  E = T + U or the Painlevé–Jacobi integral, ...) and ``T``, ``U``;
* ``drift`` — name → the relative drift max|I(t) − I(t0)| / S of each first integral, the
  conservation monitor reported at the end of each run; ``scales`` — name → S.

The scale S (`drift_scale`) is physical, so that an integral that starts near 0 (the
energy of a pendulum released horizontally, K of a top launched at θ = π/2) does not turn
round-off into a huge "relative" drift:

    S = max(|I(t0)|, max_t |I(t)|, max_t m(t)),

with m(t) the magnitude of the terms that I is a sum of: |T| + |U| for the energy (or
Jacobi) integral, Σ_j |M_kj q̇_j| + |p_k − Σ_j M_kj q̇_j| for the momentum p_k = ∂T/∂q̇_k.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from .._display import render

__all__ = ["Trajectory", "Event", "drift_scale", "relative_drift", "conservation"]


def drift_scale(values: np.ndarray, magnitude: np.ndarray | None = None) -> float:
    """S = max(|I(t0)|, max|I(t)|, max m(t)) (module docstring); 1 when all of them are 0."""
    values = np.asarray(values, dtype=float)
    if len(values) == 0:
        return 1.0
    scale = float(np.max(np.abs(values)))
    if magnitude is not None and len(magnitude):
        scale = max(scale, float(np.max(np.abs(magnitude))))
    return scale if scale > 0 and np.isfinite(scale) else 1.0


def relative_drift(values: np.ndarray, scale: float) -> np.ndarray:
    """|I(t) − I(t0)| / S, shape (N,): the drift of a first integral along the run."""
    values = np.asarray(values, dtype=float)
    if len(values) == 0:
        return values
    return np.abs(values - values[0]) / scale


def conservation(monitors: Mapping[str, np.ndarray], integrals: Sequence[str], *,
                 momenta: Mapping[str, int], M: np.ndarray | None, qd: np.ndarray
                 ) -> tuple[dict[str, float], dict[str, float]]:
    """(drift, scale) of every first integral: the one place where the drift is computed.

    Parameters
    ----------
    monitors : name → values over the run (the integrals, and ``T``, ``U``: ``T_total``,
        ``U_total`` when an integral is named T or U).
    integrals : the names of the first integrals among the monitors.
    momenta : integral name → index k of the coordinate whose momentum p_k = ∂T/∂q̇_k it is;
        the other integrals are energy-like (energy, Jacobi integral).
    M : the mass matrices along the run, shape (N, n, n) (None: momentum terms unknown).
    qd : q̇ along the run, shape (N, n).
    """
    T = monitors.get("T_total" if "T" in integrals else "T")
    U = monitors.get("U_total" if "U" in integrals else "U")
    drift: dict[str, float] = {}
    scales: dict[str, float] = {}
    for name in integrals:
        values = np.asarray(monitors[name], dtype=float)
        magnitude = None
        if name in momenta:
            if M is not None and len(values):
                terms = M[:, momenta[name], :] * qd
                magnitude = np.sum(np.abs(terms), axis=1) + np.abs(values - np.sum(terms, axis=1))
        elif T is not None and U is not None:
            magnitude = np.abs(T) + np.abs(U)
        scales[name] = drift_scale(values, magnitude)
        drift[name] = float(np.max(relative_drift(values, scales[name]), initial=0.0))
    return drift, scales


@dataclass(frozen=True)
class Event:
    """One occurrence of an event: its name, its time and the state (q, q̇) there.

    Parameters
    ----------
    name : str
        The event's name.
    t : float
        Its time.
    q : ndarray of shape (n,)
        The coordinates there.
    qd : ndarray of shape (n,)
        The rates there.
    """

    name: str
    t: float
    q: np.ndarray
    qd: np.ndarray


@dataclass(frozen=True)
class Trajectory:
    """A simulated motion (see the module docstring for the layout).

    Parameters
    ----------
    model_name : str
        The model's name.
    coordinates : tuple of str
        The names of q_1..q_n, in the model's order.
    parameters : mapping of str to float
        The parameter values used.
    t : ndarray of shape (N,)
        The output times.
    q : ndarray of shape (N, n)
        The coordinates q_i at each output.
    qd : ndarray of shape (N, n)
        The rates q̇_i at each output.
    qdd : ndarray of shape (N, n)
        The accelerations q̈_i at each output, from M q̈ = F.
    monitors : mapping of str to ndarray
        Name → shape (N,): every first integral of the model and ``T``, ``U``.
    integrals : tuple of str
        The names of the monitors that are first integrals (their drift is reported).
    drift : mapping of str to float
        The relative drift max|I(t) − I(t0)| / S of each first integral.
    method : str
        The integrator, e.g. ``"dop853"``.
    steps : int
        Accepted steps.
    rhs_calls : int
        Right-hand-side evaluations.
    tolerance : float, optional
        The drift tolerance (asked for, or the method's default); `warnings` lists the integrals that
        exceeded it.
    warnings : tuple of str
        What the run warns about.
    events : tuple of Event
        The events that occurred, in time order.
    status : str
        ``"completed"``, or why the run stopped.
    conditioning : float
        The smallest relative pivot of M met during the run (1 for a diagonal M, 0 at a singular
        configuration); below 1e-6 a warning says accuracy may be lost.
    extra : mapping of str to ndarray
        Further columns (reactions, multipliers), name → shape (N,).
    scales : mapping of str to float
        The scale S of each first integral's drift (module docstring).
    range_exits : tuple of RangeExit
        Where the motion left a declared coordinate range or broke a sign the derivation used
        (`lagrangian.numerics._ranges.RangeExit`), each also in `warnings`.
    sensitivity_names : tuple of str
        The parameters and initial values (``"theta(t0)"``) whose sensitivities are in `extra`
        (``simulate(..., sensitivities=...)``), in the order asked.
    quaternion_drift : mapping of str to float
        For a model with free bodies (integrated on unit quaternions, `numerics._free_simulate`):
        body → the largest ``|1 − |e||`` of its quaternion e met along the run, before each
        projection back on ``|e| = 1``.
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
    scales: Mapping[str, float] = field(default_factory=dict)
    range_exits: tuple[Any, ...] = ()
    sensitivity_names: tuple[str, ...] = ()
    quaternion_drift: Mapping[str, float] = field(default_factory=dict)

    def __post_init__(self) -> None:
        n, N = len(self.coordinates), len(self.t)
        for name in ("q", "qd", "qdd"):
            shape = getattr(self, name).shape
            if shape != (N, n):
                raise ValueError(f"Trajectory.{name} has shape {shape}, expected {(N, n)}")

    def __len__(self) -> int:
        return len(self.t)

    def column(self, name: str) -> np.ndarray:
        """One column by name.

        Parameters
        ----------
        name : str
            ``"t"``, a coordinate ``"theta"``, its rate ``"theta_dot"``, its acceleration
            ``"theta_ddot"``, or a monitor (``"K"``, ``"E"``, ``"T"``...).

        Returns
        -------
        ndarray of shape (N,)
            The column.
        """
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

    def sensitivity(self, name: str) -> np.ndarray:
        """The sensitivity ∂y(t)/∂x for the parameter or initial value ``name``.

        Column i is ∂y_i/∂x at each output time, the columns ``d(theta)/d(l)``... of the table
        (``simulate(..., sensitivities=[...])``).

        Parameters
        ----------
        name : str
            A name of `sensitivity_names`.

        Returns
        -------
        ndarray of shape (N, 2n)
            ∂y/∂x, y = (q, q̇).
        """
        if name not in self.sensitivity_names:
            raise KeyError(f"no sensitivity to `{name}`; computed: {', '.join(self.sensitivity_names) or 'none'} "
                           "(simulate(..., sensitivities=[...]))")
        states = [*self.coordinates, *(c + "_dot" for c in self.coordinates)]
        return np.column_stack([self.extra[f"d({s})/d({name})"] for s in states])

    def columns(self) -> list[str]:
        """Every column name, in file order.

        Returns
        -------
        list of str
            The names.
        """
        c = self.coordinates
        return ["t", *c, *(f"{x}_dot" for x in c), *(f"{x}_ddot" for x in c), *self.monitors, *self.extra]

    def table(self) -> np.ndarray:
        """All columns as one (N, k) array, in the order of `columns`.

        Returns
        -------
        ndarray of shape (N, k)
            The table.
        """
        return np.column_stack([self.column(name) for name in self.columns()]) + 0.0  # no "-0" in files

    def relative_drift(self, name: str) -> np.ndarray:
        """The relative drift ``|I(t) − I(t0)| / S`` of the first integral ``name`` (module docstring).

        Parameters
        ----------
        name : str
            A first integral.

        Returns
        -------
        ndarray of shape (N,)
            The drift; its maximum is ``drift[name]``.
        """
        values = self.monitors[name]
        scale = self.scales[name] if name in self.scales else drift_scale(values)
        return relative_drift(values, scale)

    # -- Jupyter (IPython's display protocol: drawn by the output stage, `lagrangian._display`) -------
    def _repr_html_(self) -> str:
        """A short summary table: time span, method, each coordinate's first and last value, drifts."""
        return render(self, "html")

    def _repr_markdown_(self) -> str:
        return render(self, "markdown")

    def _repr_latex_(self) -> str:
        return render(self, "latex")

    def drift_summary(self) -> str:
        """The drift of each first integral in a line, e.g. ``"E relative drift 3.1e-12, K 1.0e-13, H 0"``.

        Returns
        -------
        str
            The line.
        """
        parts = []
        for i, name in enumerate(self.integrals):
            value = self.drift[name]
            text = "0" if value == 0 else f"{value:.1e}"
            parts.append(f"{name} relative drift {text}" if i == 0 else f"{name} {text}")
        if self.quaternion_drift:
            parts.append("quaternion norm drift " + ", ".join(f"{body} {value:.1e}" for body, value
                                                              in self.quaternion_drift.items()))
        return ", ".join(parts)
