"""A mode of small motions as a motion to draw: q(t) = q0 + q̇0 t + ε Re(φ e^{λt}).

The linearization's eigenvector φ gives the independent coordinates' perturbation; the
dependent ones follow by δq = P δq_i (`LinearModel.coordinate_map`); the coordinates that
move steadily at the point (the bicycle's wheels and position) keep moving at q̇0, so the
mode is seen on the steady motion it perturbs.  The result is a `Trajectory`, so the
existing animation and plots draw it.
"""

from __future__ import annotations

import numpy as np

from ..analysis import LinearModel
from ..analysis import to_numpy as _to_numpy
from ..errors import OutputError
from ..numerics import Trajectory

__all__ = ["mode_trajectory"]


def mode_trajectory(lin: LinearModel, index: int = 0, *, amplitude: float = 0.1, periods: float = 2.0,
                    samples: int = 200, **values: float) -> Trajectory:
    """The motion of mode ``index`` (in `LinearModel.modes` order) with largest coordinate amplitude ε.

    A real (non-oscillating) mode is drawn over the time its amplitude takes to change by e
    (or 1 s for a zero eigenvalue) times ``periods``.

    Parameters
    ----------
    lin : LinearModel
        The linearization.
    index : int, optional
        The mode, in `LinearModel.modes` order.
    amplitude : float, optional
        The largest coordinate amplitude ε.
    periods : float, optional
        How many periods to draw.
    samples : int, optional
        The number of output times.
    **values : float
        Values of the symbols ``lin`` keeps symbolic.

    Returns
    -------
    Trajectory
        The linear motion about the point.
    """
    md = lin.modes(**values)
    if not md.modes:
        raise OutputError("This linearization has no mode to draw (every direction is neutral).")
    if not 0 <= index < len(md.modes):
        raise OutputError(f"There is no mode {index}: the modes are numbered 0 to {len(md.modes) - 1}.",
                          fix="choose a mode index in that range")
    mode = md.modes[index]
    lam = mode.eigenvalue
    span = periods * (mode.period if mode.period else (1.0 / abs(lam.real) if lam.real else 1.0))
    t = np.linspace(0.0, span, int(samples))
    coords = lin.eom.coordinates
    subs = lin._values(values)
    P = _to_numpy(lin.coordinate_map, subs) if lin.coordinate_map is not None else np.eye(len(coords))
    phi = np.array([mode.shape.get(c, 0.0) for c in lin.coordinates], dtype=complex)
    scale = amplitude / max(float(np.abs(phi).max(initial=0.0)), 1e-300)
    dq_i = scale * np.real(np.outer(np.exp(lam * t), phi))  # (N, n_i)
    dqd_i = scale * np.real(np.outer(lam * np.exp(lam * t), phi))
    dqdd_i = scale * np.real(np.outer(lam**2 * np.exp(lam * t), phi))
    q0 = np.array([complex(lin.point[c].subs(subs)).real for c in coords])
    qd0 = np.array([complex(lin.point[c + "_dot"].subs(subs)).real for c in coords])
    q = q0 + np.outer(t, qd0) + dq_i @ P.T
    qd = qd0 + dqd_i @ P.T
    qdd = dqdd_i @ P.T
    parameters = {k: float(v) for k, v in lin.values.items()}
    parameters.update({k: float(v) for k, v in values.items()})
    return Trajectory(model_name=f"{lin.eom.model.name}: mode {index}", coordinates=tuple(coords),
                      parameters=parameters, t=t, q=q, qd=qd, qdd=qdd, monitors={}, integrals=(), drift={},
                      method="linear mode", steps=0, rhs_calls=0)
