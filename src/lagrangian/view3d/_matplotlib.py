"""The scene drawn by matplotlib: the frames of the GIF/MP4 animation, and the still where no browser is.

`Renderer` owns a figure whose moving artists are updated and blitted frame by frame on an Agg
canvas: the axes, the grid and the ground's points are drawn once, and each frame redraws only
what moves (about 10 ms a frame at 400 × 400 pixels).  What it draws is the `Wireframe` of the
scene (`_wireframe`): each body in its colour of the 3-D page.
"""

from __future__ import annotations

import io
import math
import re
from typing import Any

import numpy as np

from .._matplotlib import require_matplotlib
from ._scene import Scene
from ._wireframe import Wireframe, wireframe

__all__ = ["AXIS_COLOURS", "Renderer", "still_matplotlib"]

#: Colours of a body frame's axes x, y, z (those of the 3-D page's triads).
AXIS_COLOURS = ("#d62728", "#2ca02c", "#1f77b4")


def _time_format(times: np.ndarray) -> str:
    """Enough decimals that consecutive frame times print differently."""
    step = float(np.min(np.diff(times))) if len(times) > 1 else 1.0
    decimals = max(2, math.ceil(-math.log10(step)) + 1) if step > 0 else 2
    return f"t = {{:.{min(decimals, 12)}f}} s"


def _math(name: str) -> str:
    """``"y0"`` → ``"$y_0$"``, ``"−x0"`` → ``"$-x_0$"`` (an axis name as mathtext)."""
    if not name:
        return ""
    return "$" + re.sub(r"([A-Za-z]+)(\d+)", r"\1_{\2}", name.replace("−", "-")) + "$"


class Renderer:
    """A figure showing ``shape`` (a `Wireframe`) frame by frame; `rgba` gives a frame's pixels.

    Parameters
    ----------
    shape : Wireframe
        What to draw.
    title : str
        The figure's title.
    size : float
        The figure's height in inches.
    dpi : float
        Its resolution.
    trail : int
        Past frames of each traced path to show.
    elev : float
        The 3D viewpoint's elevation, in degrees.
    azim : float
        The 3D viewpoint's azimuth, in degrees.
    width : float, optional
        The figure's width in inches (default: ``size``).
    """

    def __init__(self, shape: Wireframe, *, title: str, size: float, dpi: float, trail: int,
                 elev: float, azim: float, width: float | None = None) -> None:
        require_matplotlib()
        from matplotlib.backends.backend_agg import FigureCanvasAgg
        from matplotlib.figure import Figure

        self.scene, self.trail = shape, trail
        self.fig = fig = Figure(figsize=(width or size, size), dpi=dpi)
        self.canvas = FigureCanvasAgg(fig)
        three = shape.dimension == 3
        # Axes3D or plain Axes, as `three` says: the methods used below are those of the one made.
        ax: Any = fig.add_subplot(projection="3d") if three else fig.add_subplot()
        self.ax = ax
        lo, hi = shape.bounds()
        centre, half = (lo + hi) / 2, max(float(np.max(hi - lo)) / 2, 1e-9) * 1.12
        if three:
            ax.set_xlim(centre[0] - half, centre[0] + half)
            ax.set_ylim(centre[1] - half, centre[1] + half)
            ax.set_zlim(centre[2] - half, centre[2] + half)
            ax.set_box_aspect((1, 1, 1))
            ax.view_init(elev=elev, azim=azim)
            ax.set_xlabel(_math(shape.axis_names[0]))
            ax.set_ylabel(_math(shape.axis_names[1]))
            ax.set_zlabel(_math(shape.axis_names[2]))
            origin = np.zeros(3)
            for k in range(3):  # R0's triad at O, static
                end = origin + 0.25 * half * np.eye(3)[k]
                ax.plot(*np.stack([origin, end]).T, color="0.55", lw=1.0)
            fig.subplots_adjust(left=0.0, right=0.95, bottom=0.03, top=0.93)
        else:
            ax.set_xlim(centre[0] - half, centre[0] + half)
            ax.set_ylim(centre[1] - half, centre[1] + half)
            ax.set_aspect("equal")
            ax.grid(True, alpha=0.3)
            right, up = shape.plane_names
            ax.set_xlabel(_math(right))
            ax.set_ylabel(_math(up))
            fig.subplots_adjust(left=0.14, right=0.97, bottom=0.1, top=0.92)
        ax.set_title(title, fontsize="medium")
        if shape.fixed.size:
            ax.plot(*shape.fixed.T, "k^", ms=7)
        self.moving: list[tuple[Any, Any]] = []  # (artist, function of the frame index -> data)

        def line(data_of, **style):
            first = data_of(0)
            artist = ax.plot(*first.T, **style)[0]
            self.moving.append((artist, data_of))

        for trail_path in shape.trails:
            if trail > 0:
                line(lambda i, a=trail_path: a[max(0, i - trail): i + 1], color="0.6", lw=0.8, alpha=0.8)
        for a in shape.springs:
            line(lambda i, a=a: a[i], color="tab:olive", lw=1.5, ls="--")
        for colour, a in shape.disks:
            line(lambda i, a=a: a[i], color=colour, lw=1.2)
        for a in shape.spokes:
            line(lambda i, a=a: a[i], color="0.25", lw=1.5)
        for _, colour, a in shape.lines:
            line(lambda i, a=a: a[i], color=colour, lw=3.0, marker="o", ms=3.5, solid_capstyle="round")
        for a in shape.axes:
            for k in range(3):
                line(lambda i, a=a, k=k: a[i, k], color=AXIS_COLOURS[k], lw=1.5)
        for _, colour, a in shape.dots:
            line(lambda i, a=a: a[i][None, :], ls="", marker="o", ms=9, color=colour)
        place = {"transform": ax.transAxes, "fontsize": "medium", "va": "top", "ha": "left"}
        self.text = (ax.text2D if three else ax.text)(0.02, 0.98, "", **place)
        self.time_format = _time_format(shape.t)
        self._background = None

    def _set(self, i: int) -> None:
        three = self.scene.dimension == 3
        for artist, data_of in self.moving:
            data = data_of(i)
            if three:
                artist.set_data_3d(data[:, 0], data[:, 1], data[:, 2])
            else:
                artist.set_data(data[:, 0], data[:, 1])
        self.text.set_text(self.time_format.format(self.scene.t[i]) if len(self.scene.t) > 1 else "")

    def _artists(self) -> list[Any]:
        return [a for a, _ in self.moving] + [self.text]

    def rgba(self, i: int) -> np.ndarray:
        """Frame ``i`` as an (H, W, 4) uint8 array, drawn by blitting.

        Parameters
        ----------
        i : int
            The frame.

        Returns
        -------
        ndarray of shape (H, W, 4), uint8
            Its pixels.
        """
        if self._background is None:
            for a in self._artists():
                a.set_visible(False)
            self.canvas.draw()
            self._background = self.canvas.copy_from_bbox(self.fig.bbox)
            for a in self._artists():
                a.set_visible(True)
        self._set(i)
        self.canvas.restore_region(self._background)
        for a in self._artists():
            self.ax.draw_artist(a)
        return np.array(self.canvas.buffer_rgba())

    def full(self, i: int) -> None:
        """Set frame ``i`` for a writer that redraws the whole figure.

        Parameters
        ----------
        i : int
            The frame.
        """
        self._set(i)


def still_matplotlib(scene: Scene, *, width: int, height: int, index: int = 0) -> bytes:
    """Frame ``index`` of ``scene`` drawn by matplotlib, as PNG bytes of about ``width`` × ``height`` pixels."""
    from PIL import Image

    dpi = 100.0
    renderer = Renderer(wireframe(scene), title=scene.title, size=height / dpi, width=width / dpi, dpi=dpi,
                        trail=index, elev=20.0, azim=-60.0)
    pixels = renderer.rgba(index)
    buffer = io.BytesIO()
    Image.fromarray(pixels).convert("RGB").save(buffer, format="PNG")
    return buffer.getvalue()
