"""Where IPOPT starts: a guess of every column at every collocation point, and of T.

* ``"interpolate"`` (default): each column goes linearly from its initial to its final value where
  both are given, stays at the one given otherwise, and is 0 where neither is; rates and
  accelerations are those of the interpolated coordinates where their own values are not given.
* ``"simulate"``: the motion with the inputs off, from the initial state (the initial values given,
  the model's own for the rest), sampled at the collocation points.
* a `Trajectory` (a simulation, or a previous optimum): its columns, read at the same fraction of its
  own time span (so that an optimum of another duration still fits); missing columns interpolated.
* a mapping column → values at the points (or one number).

A warm start (`lagrangian.optimize`'s ``warm_start``) reuses a previous optimum's variables and
multipliers as they are when it has the same layout, else serves as a guess like any `Trajectory`.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import numpy as np

from ..errors import ProblemError
from ..numerics import Trajectory, simulate
from ._layout import resolve_value
from ._transcription import Transcription

__all__ = ["GUESSES", "initial_guess"]

GUESSES = ("interpolate", "simulate")


def _duration(tr: Transcription, guess: Any) -> float:
    """T of the guess: the fixed duration, else ``t_guess``, the guess trajectory's, or the middle of the bounds."""
    problem = tr.problem
    if not problem.free_time:
        return float(problem.t_end) - tr.t0
    if problem.t_guess is not None:
        return float(problem.t_guess)
    if isinstance(guess, Trajectory) and len(guess.t) > 1:
        return float(guess.t[-1] - guess.t[0])
    low, high = tr.lbx[-1], tr.ubx[-1]
    if np.isfinite(high):
        return float((max(low, 0.0) + high) / 2)
    return max(1.0, 2 * float(low))


def _interpolated(tr: Transcription, T: float) -> np.ndarray:
    layout, problem, tau = tr.layout, tr.problem, tr.tau
    Z = np.zeros((layout.width, len(tau)))
    given = np.zeros(layout.width, dtype=bool)
    for k, name in enumerate(layout.names):
        a, b = problem.initial.get(name), problem.final.get(name)
        if a is None and b is None:
            continue
        given[k] = True
        va = resolve_value(a if a is not None else b, layout, tr.values, f"the value of `{name}`")
        vb = resolve_value(b if b is not None else a, layout, tr.values, f"the value of `{name}`")
        Z[k] = va + (vb - va) * tau
    n = layout.n
    for i in range(n):  # q̇ of a line from q0 to q_f, where q̇ is not given itself
        if not given[n + i]:
            Z[n + i] = (Z[i, -1] - Z[i, 0]) / T
    # Inside the bounds: IPOPT moves an interior point method's start inside them anyway.
    low, high = tr.lbx[: Z.size].reshape(len(tau), -1).T, tr.ubx[: Z.size].reshape(len(tau), -1).T
    return np.clip(Z, low, high)


def _from_trajectory(tr: Transcription, traj: Trajectory, base: np.ndarray) -> np.ndarray:
    Z = base.copy()
    if len(traj.t) < 2:
        return Z
    s = (traj.t - traj.t[0]) / (traj.t[-1] - traj.t[0])
    columns = set(traj.columns())
    for k, name in enumerate(tr.layout.names):
        if name in columns:
            Z[k] = np.interp(tr.tau, s, np.asarray(traj.column(name), dtype=float))
    return Z


def initial_guess(tr: Transcription, guess: Any) -> np.ndarray:
    """The vector w0 where IPOPT starts (module docstring)."""
    if isinstance(guess, str) and guess not in GUESSES:
        raise ProblemError(f"Unknown guess `{guess}`.", fix="use \"interpolate\", \"simulate\", a Trajectory or a "
                                                            "mapping column → values")
    T = _duration(tr, guess)
    Z = _interpolated(tr, T)
    if isinstance(guess, Trajectory):
        Z = _from_trajectory(tr, guess, Z)
    elif guess == "simulate":
        Z = _from_trajectory(tr, _simulated(tr, T), Z)
    elif isinstance(guess, Mapping):
        for name, values in guess.items():
            k = tr.layout.index(name, "`guess`")
            row = np.asarray(values, dtype=float)
            if row.ndim == 1 and len(row) == tr.problem.nodes and len(tr.tau) != len(row):
                row = np.interp(tr.tau, np.linspace(0.0, 1.0, len(row)), row)  # given at the nodes only
            try:
                Z[k] = np.broadcast_to(row, Z[k].shape)
            except ValueError:
                raise ProblemError(f"The guess of `{name}` has {row.size} values; give one, or one per node "
                                   f"({tr.problem.nodes}).", symbol=str(name), fix="resample it") from None
    elif guess is not None and not isinstance(guess, str):
        raise ProblemError(f"A guess is \"interpolate\", \"simulate\", a Trajectory or a mapping, not "
                           f"{type(guess).__name__}.", fix="e.g. guess=\"simulate\"")
    return tr.pack(Z, T)


def _simulated(tr: Transcription, T: float) -> Trajectory:
    """The motion with the inputs off from the initial conditions given (the model's for the rest)."""
    layout = tr.layout
    initial = {name: resolve_value(v, layout, tr.values, f"the initial value of `{name}`")
               for name, v in tr.problem.initial.items() if name in layout.names[: 2 * layout.n]}
    return simulate(tr.eom, tr.t0 + T, t_start=tr.t0, initial=initial, parameters=tr.values,
                    t_eval=tr.t0 + tr.tau * T)
