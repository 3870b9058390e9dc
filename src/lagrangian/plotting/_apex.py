"""The path of a body axis's tip on the unit sphere, and the classic nutation figure.

For the heavy symmetric top the tip of z moves between two circles of the sphere,
θ = θ1 and θ = θ2 (the turning angles, roots of the cubic in u = cosθ), tracing waves,
loops or cusps (Goldstein §5.7; seed, Mouvement de Lagrange).  The circles come from
`lagrangian.analysis` when its top analysis applies to the model, and otherwise from the
extreme θ reached in the simulation (the figure says which).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from ..dynamics import EquationsOfMotion
from ..errors import LagrangianError
from ..numerics import Trajectory
from ._geometry import apex_path, axis_angles, default_axis
from ._labels import words
from ._mpl import new_figure, suptitle

__all__ = ["TurningAngles", "turning_angles", "plot_apex_sphere", "plot_nutation"]

#: Largest |θ_axis − q_k| (rad) for which the axis's θ is taken to be the coordinate q_k,
#: so that the top analysis's θ1, θ2 (angles of q_k) are the circles of this axis.
SAME_ANGLE = 1e-9


@dataclass(frozen=True)
class TurningAngles:
    """The turning angles θ1 ≤ θ2 of the nutation and where they come from.

    Parameters
    ----------
    theta1 : float
        The smaller turning angle θ1, in rad.
    theta2 : float
        The larger turning angle θ2, in rad.
    source : str
        ``"analysis"`` or ``"simulation"``.
    """

    theta1: float
    theta2: float
    source: str

    @property
    def caption(self) -> str:
        return self.caption_in("en")

    def caption_in(self, lang: str) -> str:
        """Where θ1 and θ2 come from, in ``lang``.

        Parameters
        ----------
        lang : {"en", "fr"}
            The language.

        Returns
        -------
        str
            The caption.
        """
        return words(lang)["roots" if self.source == "analysis" else "extremes"]


def _analysed(trajectory: Trajectory, eom: EquationsOfMotion, theta: np.ndarray) -> TurningAngles | None:
    """θ1, θ2 from the top analysis, when it exists and applies, and its θ is this axis's θ."""
    try:
        from ..analysis import analyse_top  # written alongside; absent in older trees
    except ImportError:
        return None
    matches = [k for k in range(trajectory.q.shape[1])
               if len(theta) and np.max(np.abs(trajectory.q[:, k] - theta)) <= SAME_ANGLE]
    if not matches:
        return None
    initial = {}
    for k, name in enumerate(trajectory.coordinates):
        initial[name] = float(trajectory.q[0, k])
        initial[name + "_dot"] = float(trajectory.qd[0, k])
    try:
        result = analyse_top(eom, parameters=dict(trajectory.parameters), initial=initial)
    except LagrangianError:
        return None
    t1, t2 = sorted((float(result.theta1), float(result.theta2)))
    return TurningAngles(t1, t2, "analysis")


def turning_angles(trajectory: Trajectory, eom: EquationsOfMotion, theta: np.ndarray | None = None) -> TurningAngles:
    """The turning angles θ1, θ2 of the axis followed by `apex_path` (from the analysis when possible, else the run).

    Parameters
    ----------
    trajectory : Trajectory
        A simulated motion.
    eom : EquationsOfMotion
        Its equations.
    theta : ndarray, optional
        The axis' angle from z0 along the run, when already computed.

    Returns
    -------
    TurningAngles
        The turning angles and their source.
    """
    if theta is None:
        theta = axis_angles(apex_path(trajectory, eom))[1]
    found = _analysed(trajectory, eom, theta)
    if found is not None:
        return found
    return TurningAngles(float(np.min(theta)), float(np.max(theta)), "simulation")


def _axis_title(eom: EquationsOfMotion, body: str | None, axis: str | None, lang: str = "en") -> str:
    name, default = default_axis(eom, body)
    return words(lang)["tip"].format(axis=axis or default, body=name)


def plot_apex_sphere(trajectory: Trajectory, eom: EquationsOfMotion, *, body: str | None = None,
                     axis: str | None = None, ax: Any = None, lang: str = "en") -> Any:
    """The tip of a body axis on a wireframe unit sphere, in 3D, with the θ1 and θ2 circles.

    Parameters
    ----------
    trajectory : Trajectory
        A simulated motion.
    eom : EquationsOfMotion
        Its equations.
    body : str, optional
        The body whose axis is followed (default: `default_axis`).
    axis : str, optional
        ``"x"``, ``"y"`` or ``"z"`` of the body's frame.
    ax : matplotlib 3D axes, optional
        Axes to draw in; None: a new figure.
    lang : {"en", "fr"}, optional
        The language of the titles and labels.

    Returns
    -------
    matplotlib.figure.Figure
        Its 3D axes hold the path as the first line whose data are the tip's (x0, y0, z0).
    """
    w = words(lang)
    tip = apex_path(trajectory, eom, body, axis)
    _, theta = axis_angles(tip)
    angles = turning_angles(trajectory, eom, theta)
    if ax is None:
        fig = new_figure(6.0, 6.0, margins=(0.0, 0.3, 0.1, 0.55))
        ax = fig.add_subplot(projection="3d")
    else:
        fig = ax.figure
    ax.plot(tip[:, 0], tip[:, 1], tip[:, 2], color="C3", lw=1.2, label=w["tip path"], zorder=5)
    u, v = np.meshgrid(np.linspace(0, 2 * np.pi, 37), np.linspace(0, np.pi, 19))
    ax.plot_wireframe(np.cos(u) * np.sin(v), np.sin(u) * np.sin(v), np.cos(v), color="0.75", lw=0.4,
                      rstride=1, cstride=1)
    ring = np.linspace(0, 2 * np.pi, 181)
    for value, style in ((angles.theta1, "--"), (angles.theta2, ":")):
        ax.plot(np.sin(value) * np.cos(ring), np.sin(value) * np.sin(ring), np.full_like(ring, np.cos(value)),
                style, color="C0", lw=1.0)
    ax.plot([0, 0], [0, 0], [-1.15, 1.15], color="k", lw=0.8)
    ax.text(0, 0, 1.2, "$z_0$")
    if len(tip):
        ax.scatter(*tip[0], color="k", s=12, label="t = 0", depthshade=False)
    ax.set_xlim(-1, 1)
    ax.set_ylim(-1, 1)
    ax.set_zlim(-1, 1)
    ax.set_box_aspect((1, 1, 1))
    ax.set_xlabel("$x_0$")
    ax.set_ylabel("$y_0$")
    ax.set_zlabel("$z_0$")
    ax.view_init(elev=25, azim=-60)
    ax.legend(loc="upper left", fontsize="small")
    ax.set_title(w["sphere"].format(tip=_axis_title(eom, body, axis, lang)) + "\n"
                 + w["circles"].format(t1=angles.theta1, t2=angles.theta2)
                 + f" ({w['analysis' if angles.source == 'analysis' else 'simulation']})", fontsize="medium")
    return fig


def plot_nutation(trajectory: Trajectory, eom: EquationsOfMotion, *, body: str | None = None,
                  axis: str | None = None, fig: Any = None, lang: str = "en") -> Any:
    """The classic nutation figure: the tip seen from above z0, and θ against ψ.

    The tip is drawn in polar coordinates (radius θ, angle ψ − 90°); both panels show the θ1 and θ2
    circles (lines).

    Parameters
    ----------
    trajectory : Trajectory
        A simulated motion.
    eom : EquationsOfMotion
        Its equations.
    body : str, optional
        The body whose axis is followed (default: `default_axis`).
    axis : str, optional
        ``"x"``, ``"y"`` or ``"z"`` of the body's frame.
    fig : matplotlib.figure.Figure, optional
        A figure to draw in; None: a new one.
    lang : {"en", "fr"}, optional
        The language of the titles and labels.

    Returns
    -------
    matplotlib.figure.Figure
        Axes 0 (polar): first line = (ψ − π/2, θ in degrees); axes 1: first line = (ψ, θ), degrees.
    """
    w = words(lang)
    tip = apex_path(trajectory, eom, body, axis)
    psi, theta = axis_angles(tip)
    angles = turning_angles(trajectory, eom, theta)
    fig = fig or new_figure(11.0, 5.2, margins=(0.3, 0.2, 0.6, 0.85), wspace=0.25)
    polar = fig.add_subplot(1, 2, 1, projection="polar")
    flat = fig.add_subplot(1, 2, 2)
    deg = np.degrees
    polar.plot(psi - np.pi / 2, deg(theta), color="C3", lw=1.0)
    flat.plot(deg(psi), deg(theta), color="C3", lw=1.0)
    ring = np.linspace(0, 2 * np.pi, 361)
    for value, style, name in ((angles.theta1, "--", r"$\theta_1$"), (angles.theta2, ":", r"$\theta_2$")):
        polar.plot(ring, np.full_like(ring, deg(value)), style, color="C0", lw=1.0, label=name)
        flat.axhline(deg(value), ls=style, color="C0", lw=1.0, label=f"{name} = {deg(value):.4g}°")
    top = min(180.0, 1.15 * max(deg(angles.theta2), float(deg(theta).max()) if len(theta) else 0.0))
    polar.set_rlim(0, max(top, 1e-3))
    polar.set_title(w["above"], fontsize="medium")
    polar.legend(loc="lower left", fontsize="small", bbox_to_anchor=(-0.1, -0.12))
    flat.set_xlabel(w["psi axis"])
    flat.set_ylabel(w["theta axis"])
    flat.invert_yaxis()  # θ grows downwards from z0, as on the sphere seen from the side
    flat.grid(True, alpha=0.3)
    flat.legend(loc="best", fontsize="small")
    flat.set_title(angles.caption_in(lang), fontsize="medium")
    sep = " : " if lang == "fr" else ": "
    suptitle(fig, trajectory.model_name + sep + w["nutation"].format(tip=_axis_title(eom, body, axis, lang)))
    return fig
