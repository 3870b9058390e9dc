"""A stick/slip trajectory taken phase by phase, each phase with the model that holds in it.

With an exact Coulomb contact (`_stickslip`), the motion is sliding one way (friction the
given force −s f N e), stuck (v_s = 0 a complementary constraint whose multiplier is the
friction), or sliding the other way.  The exact law −f N v_s/|v_s| of the model itself is
undefined at v_s = 0, so the Newton–Euler check and the reactions along such a motion are
evaluated with each phase's own equations and put back together in time order.  For any
other trajectory these are `analysis.check_trajectory` and `analysis.reaction_history`.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import replace

import numpy as np

from ..analysis import ReactionHistory, TrajectoryResiduals, check_trajectory, reaction_history
from ..dynamics import EquationsOfMotion
from ._stickslip import _system, exact_contact_model
from ._trajectory import Trajectory

__all__ = ["reaction_history_along", "check_trajectory_along"]


def _phases(eom: EquationsOfMotion, trajectory: Trajectory
            ) -> list[tuple[EquationsOfMotion, np.ndarray, Trajectory]] | None:
    """(phase equations, row mask, rows) for each mode present; None when not a stick/slip motion."""
    model = exact_contact_model(eom)
    if model is None:
        return None
    system = _system(model, "auto")
    name = system.load.name
    mode = trajectory.extra.get(f"mode_{name}")
    if mode is None:
        return None
    out = []
    for s in sorted({int(m) for m in mode}):
        mask = mode == s
        extra = {k: v[mask] for k, v in trajectory.extra.items()}
        if s == 0:  # stuck: the friction is the stick constraint's multiplier
            extra[f"lambda_{system.row}"] = trajectory.extra[f"friction_{name}"][mask]
        rows = replace(trajectory, t=trajectory.t[mask], q=trajectory.q[mask], qd=trajectory.qd[mask],
                       qdd=trajectory.qdd[mask], monitors={k: v[mask] for k, v in trajectory.monitors.items()},
                       extra=extra, events=())
        out.append((system.stuck_eom if s == 0 else system.slip_eom(s), mask, rows))
    return out


def _merge(N: int, parts: list[tuple[np.ndarray, np.ndarray]]) -> np.ndarray:
    """Row arrays of each phase put back at their rows of the whole motion."""
    first = parts[0][1]
    out = np.full((N, *first.shape[1:]), np.nan)
    for mask, values in parts:
        out[mask] = values
    return out


def _common(dicts: list[dict]) -> list[str]:
    return [k for k in dicts[0] if all(k in d for d in dicts)]


def reaction_history_along(eom: EquationsOfMotion, trajectory: Trajectory) -> dict[str, ReactionHistory]:
    """`analysis.reaction_history`, phase by phase for a stick/slip motion (module docstring).

    For such a motion, the reactions listed are those of the principal constraints, which
    every phase has (the stuck phase's own friction reaction is the ``friction_<load>`` column).

    Parameters
    ----------
    eom : EquationsOfMotion
        The equations.
    trajectory : Trajectory
        A simulated motion.

    Returns
    -------
    dict of str to ReactionHistory
        By reaction name.
    """
    phases = _phases(eom, trajectory)
    if phases is None:
        return reaction_history(eom, trajectory)
    each = [(mask, reaction_history(phase_eom, rows)) for phase_eom, mask, rows in phases]
    N = len(trajectory)
    out = {}
    for name in _common([h for _, h in each]):
        first = each[0][1][name]
        out[name] = ReactionHistory(name, first.point, trajectory.t,
                                    _merge(N, [(m, h[name].force) for m, h in each]),
                                    _merge(N, [(m, h[name].moment) for m, h in each]))
    return out


def check_trajectory_along(eom: EquationsOfMotion, trajectory: Trajectory,
                           check: Callable = check_trajectory) -> TrajectoryResiduals:
    """`analysis.check_trajectory`, phase by phase for a stick/slip motion (module docstring).

    Parameters
    ----------
    eom : EquationsOfMotion
        The equations.
    trajectory : Trajectory
        A simulated motion.
    check : callable, optional
        The check run on each phase.

    Returns
    -------
    TrajectoryResiduals
        The residuals, phase after phase.
    """
    phases = _phases(eom, trajectory)
    if phases is None:
        return check(eom, trajectory)
    each = [(mask, check(phase_eom, rows)) for phase_eom, mask, rows in phases]
    N = len(trajectory)
    res = [r for _, r in each]
    reactions = reaction_history_along(eom, trajectory)
    return TrajectoryResiduals(
        t=trajectory.t, coordinates=res[0].coordinates,
        projections=_merge(N, [(m, r.projections) for m, r in each]),
        reactions=reactions,
        resultant={k: _merge(N, [(m, r.resultant[k]) for m, r in each]) for k in _common([r.resultant for r in res])},
        moment={k: _merge(N, [(m, r.moment[k]) for m, r in each]) for k in _common([r.moment for r in res])},
    )
