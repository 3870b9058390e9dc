"""The inputs of a motion over time, u_j(t), one panel each (an optimal motion's `OptimalTrajectory.inputs`)."""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path
from typing import Any

from .._atomic import write_atomic_with
from ..errors import OutputError
from ..numerics import Trajectory
from ._mpl import new_figure, suptitle

__all__ = ["plot_inputs", "save_inputs_figure"]


def plot_inputs(trajectory: Trajectory, inputs: Sequence[str], *, fig: Any = None) -> Any:
    """u_j(t) for each name of ``inputs`` (columns of ``trajectory``), one row each; returns the Figure."""
    fig = fig or new_figure(7.0, 1.0 + 1.7 * max(len(inputs), 1), margins=(0.85, 0.15, 0.5, 0.55), hspace=0.15)
    axes = fig.subplots(max(len(inputs), 1), 1, sharex=True, squeeze=False)[:, 0]
    for k, (ax, name) in enumerate(zip(axes, inputs, strict=True)):
        ax.plot(trajectory.t, trajectory.column(name), lw=1.2, color=f"C{k}")
        ax.set_ylabel(name)
        ax.grid(alpha=0.3)
    axes[-1].set_xlabel("t")
    suptitle(fig, f"{trajectory.model_name}: inputs")
    return fig


def save_inputs_figure(trajectory: Trajectory, inputs: Sequence[str], directory: str | Path, *,
                       dpi: float = 110) -> Path:
    """Write ``inputs.png`` (`plot_inputs`) into ``directory``, atomically.

    Parameters
    ----------
    trajectory : Trajectory
        A simulated motion with input columns.
    inputs : sequence of str
        The inputs to draw.
    directory : str or Path
        The folder.
    dpi : float, optional
        The resolution.

    Returns
    -------
    Path
        The path written.
    """
    path = Path(directory) / "inputs.png"
    fig = plot_inputs(trajectory, inputs)
    try:
        write_atomic_with(path, lambda handle: fig.savefig(handle, format="png", dpi=dpi))
    except OSError as exc:
        raise OutputError(f"Cannot write `{path}`: {exc.strerror or exc}.", fix="check the folder") from exc
    return path
