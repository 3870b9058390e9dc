"""Constraint reactions along a trajectory as named columns: ``R_O_x0``, ``M_R_to_S_z0``...

The reactions come from the Newton–Euler theorems (`analysis.reaction_history`, e.g. R_O from
m γ(G) = P + R_O for the top), evaluated at the trajectory's states, in R0's components; a
stick/slip motion is evaluated phase by phase (`_phases`).  A
transmitted moment gets its columns only when it is not zero along the run.
"""

from __future__ import annotations

import numpy as np

from ..dynamics import EquationsOfMotion
from ._phases import reaction_history_along
from ._trajectory import Trajectory

__all__ = ["reaction_columns_along"]


def _label(name: str) -> str:
    """A column-safe name: R→S becomes R_to_S."""
    return "".join(ch if ch.isalnum() or ch == "_" else "_" for ch in name.replace("→", "to_")).strip("_")


def reaction_columns_along(eom: EquationsOfMotion, trajectory: Trajectory) -> dict[str, np.ndarray]:
    """Each reaction's force (and, when not zero, its moment) at every state, by R0 axis.

    Parameters
    ----------
    eom : EquationsOfMotion
        The equations.
    trajectory : Trajectory
        A simulated motion.

    Returns
    -------
    dict of str to ndarray
        The columns, by name.
    """
    axes = tuple(eom.model.frames[0].axes or ("x0", "y0", "z0"))
    columns: dict[str, np.ndarray] = {}
    for name, history in reaction_history_along(eom, trajectory).items():
        label = _label(name)
        for k, axis in enumerate(axes):
            columns[f"{label}_{axis}"] = history.force[:, k]
        if abs(history.moment).max(initial=0.0) > 1e-9 * (abs(history.force).max(initial=0.0) + 1e-300):
            for k, axis in enumerate(axes):
                columns[f"M_{label}_{axis}"] = history.moment[:, k]
    return columns
