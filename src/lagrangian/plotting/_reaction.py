"""R_O(t), the reaction at the fixed point, along a trajectory (and the ground's reaction on any group).

The resultant theorem for a group of linked elements in R0 (seed: "m γ(G) = P + R_O"),

    Σ m γ(G/R0) = Σ F_given + R,

gives R = Σ m γ(G) − Σ F_given: for the top, R_O = m γ(G) − P.  The formulas and their
values along a trajectory come from `lagrangian.analysis.reaction_history`; this module
draws them.  A load with no force form (a potential, a given generalized force) has no
resultant to subtract, so no reaction is drawn for such a model.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from ..analysis import ReactionHistory, given_efforts
from ..dynamics import EquationsOfMotion
from ..errors import OutputError
from ..model import GALILEAN_FRAME, Gravity, Vector
from ..numerics import Trajectory, reaction_history_along
from ._geometry import Samples, evaluate, in_R0
from ._labels import words
from ._mpl import new_figure

__all__ = ["reactions_along", "reaction_stem", "weight", "plot_reaction"]


def reactions_along(trajectory: Trajectory, eom: EquationsOfMotion) -> dict[str, ReactionHistory]:
    """Every reaction of the ground (``"R_O"`` for a pin at O) along ``trajectory``, each force (N, 3).

    Parameters
    ----------
    trajectory : Trajectory
        A simulated motion.
    eom : EquationsOfMotion
        Its equations.

    Returns
    -------
    dict of str to ReactionHistory
        By reaction name.

    Raises
    ------
    OutputError
        When the model has no mass, or a load that is not a force (the resultant of the given
        forces is then unknown).
    """
    model = eom.model
    if not model.bodies and not model.particles:
        raise OutputError(f"The model `{model.name}` has no mass, so no reaction.", fix="add a body or a particle")
    _, _, by_power = given_efforts(eom)
    if by_power:
        raise OutputError(
            f"The load `{by_power[0]}` is given by a potential or by generalized forces, not as forces, so the "
            "resultant of the constraint forces cannot be found from the resultant theorem.",
            fix="describe the load as gravity, a force at a point, a spring or a damper to get the reaction")
    return reaction_history_along(eom, trajectory)


def reaction_stem(eom: EquationsOfMotion) -> str:
    """``reaction_O`` when every body is held by the single pin O, else ``reaction``."""
    points = {b.fixed_point for b in eom.model.bodies if b.fixed_point}
    return f"reaction_{points.pop()}" if len(points) == 1 else "reaction"


def weight(trajectory: Trajectory, eom: EquationsOfMotion) -> np.ndarray | None:
    """P = Σ m g over every gravity load, in R0 components (3,), or None without gravity."""
    model = eom.model
    masses = {b.name: b.mass for b in model.bodies} | {p.name: p.mass for p in model.particles}
    total = Vector.zero()
    for load in model.loads:
        if isinstance(load, Gravity):
            for name in load.on or tuple(masses):
                total = total + load.field * masses[name]
    if total.is_zero():
        return None
    return evaluate(eom, trajectory, in_R0(eom, total), Samples.of(trajectory))[0]


def _tex(name: str) -> str:
    """``R_O`` → ``R_{O}``; ``R(→C+P)`` → ``R_{C+P}`` (the group it acts on)."""
    if name.startswith("R_"):
        return f"R_{{{name[2:]}}}"
    inner = name[name.find("→") + 1:].rstrip(")") if "→" in name else ""
    return f"R_{{{inner}}}" if inner else "R"


def _axis_tex(name: str) -> str:
    head = name.rstrip("0123456789")
    tail = name[len(head):]
    return head + (f"_{{{tail}}}" if tail else "")


def plot_reaction(trajectory: Trajectory, eom: EquationsOfMotion, *, ax: Any = None, lang: str = "en") -> Any:
    """R(t) on (x0, y0, z0) and ``|R|`` for each reaction, with the weight's magnitude ``|P|`` for scale.

    Parameters
    ----------
    trajectory : Trajectory
        A simulated motion.
    eom : EquationsOfMotion
        Its equations.
    ax : matplotlib axes, optional
        Axes to draw in; None: a new figure.
    lang : {"en", "fr"}, optional
        The language of the titles and labels.

    Returns
    -------
    matplotlib.figure.Figure
        Its axes hold, for each reaction in turn, R·x0, R·y0, R·z0 and ``|R|`` as lines.
    """
    w = words(lang)
    history = reactions_along(trajectory, eom)
    if ax is None:
        fig = new_figure(8.0, 4.2, margins=(0.75, 0.15, 0.5, 0.4))
        ax = fig.add_subplot()
    else:
        fig = ax.figure
    axes = eom.model.frame(GALILEAN_FRAME).axes
    styles = ("-", "-.", (0, (5, 1, 1, 1)))
    for j, reaction in enumerate(history.values()):
        name = _tex(reaction.name)
        for k in range(3):
            ax.plot(reaction.t, reaction.force[:, k], ls=styles[j % 3], lw=1.2, color=f"C{k}",
                    label=rf"${name} \cdot \vec{{{_axis_tex(axes[k])}}}$")
        ax.plot(reaction.t, np.linalg.norm(reaction.force, axis=1), "k--", lw=1.0, label=rf"$|{name}|$")
    p = weight(trajectory, eom)
    if p is not None:
        ax.axhline(float(np.linalg.norm(p)), color="0.5", ls=":", lw=1.0, label=r"$|P| = |\sum m\,g|$")
    ax.set_xlabel("t (s)")
    ax.set_ylabel(w["force"])
    ax.grid(True, alpha=0.3)
    ax.legend(loc="best", fontsize="small", ncols=2)
    pins = [r for r in history.values() if r.name.startswith("R_")]
    where = (w["reaction at"].format(point=pins[0].point) if len(pins) == len(history) == 1
             else w["reaction ground"])
    sep = " : " if lang == "fr" else ": "
    given = w["given"]
    ax.set_title(rf"{trajectory.model_name}{sep}{where}, $R = \sum m\,\gamma(G) - \sum F_{{\mathrm{{{given}}}}}$",
                 fontsize="medium")
    return fig
