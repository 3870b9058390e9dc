"""An animation of the bodies and particles of a model along a trajectory (GIF, or MP4 with ffmpeg).

Frames are drawn by blitting on an Agg canvas: the axes, the grid and the fixed points
are drawn once, and each frame redraws only what moves (about 10 ms a frame at 400 ×
400 pixels).  A GIF is assembled by Pillow (as matplotlib's ``PillowWriter`` does) and
written atomically; an MP4 goes through matplotlib's ``FFMpegWriter`` when ffmpeg exists.
"""

from __future__ import annotations

import math
import os
import re
import tempfile
from pathlib import Path
from typing import Any

import numpy as np

from .._atomic import write_atomic_with
from ..dynamics import EquationsOfMotion
from ..errors import OutputError
from ..numerics import Trajectory
from ._mpl import require_matplotlib
from ._scene import Scene, build_scene

__all__ = ["animate", "render_frames", "FORMATS"]

#: Animation formats, by file suffix.
FORMATS = (".gif", ".mp4")
#: Colours of a body frame's axes x, y, z.
AXIS_COLOURS = ("tab:red", "tab:green", "tab:blue")


def _time_format(times: np.ndarray) -> str:
    """Enough decimals that consecutive frame times print differently."""
    step = float(np.min(np.diff(times))) if len(times) > 1 else 1.0
    decimals = max(2, int(math.ceil(-math.log10(step))) + 1) if step > 0 else 2
    return f"t = {{:.{min(decimals, 12)}f}} s"


def _math(name: str) -> str:
    """``"y0"`` → ``"$y_0$"``, ``"−x0"`` → ``"$-x_0$"`` (an axis name as mathtext)."""
    if not name:
        return ""
    return "$" + re.sub(r"([A-Za-z]+)(\d+)", r"\1_{\2}", name.replace("−", "-")) + "$"


class _Renderer:
    """Owns a figure whose moving artists are updated and blitted frame by frame."""

    def __init__(self, scene: Scene, *, title: str, size: float, dpi: float, trail: int,
                 elev: float, azim: float) -> None:
        require_matplotlib()
        from matplotlib.backends.backend_agg import FigureCanvasAgg
        from matplotlib.figure import Figure

        self.scene, self.trail = scene, trail
        self.fig = fig = Figure(figsize=(size, size), dpi=dpi)
        self.canvas = FigureCanvasAgg(fig)
        three = scene.dimension == 3
        self.ax = ax = fig.add_subplot(projection="3d") if three else fig.add_subplot()
        lo, hi = scene.bounds()
        centre, half = (lo + hi) / 2, max(float(np.max(hi - lo)) / 2, 1e-9) * 1.12
        if three:
            ax.set_xlim(centre[0] - half, centre[0] + half)
            ax.set_ylim(centre[1] - half, centre[1] + half)
            ax.set_zlim(centre[2] - half, centre[2] + half)
            ax.set_box_aspect((1, 1, 1))
            ax.view_init(elev=elev, azim=azim)
            ax.set_xlabel(_math(scene.axis_names[0]))
            ax.set_ylabel(_math(scene.axis_names[1]))
            ax.set_zlabel(_math(scene.axis_names[2]))
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
            right, up = scene.plane_names
            ax.set_xlabel(_math(right))
            ax.set_ylabel(_math(up))
            fig.subplots_adjust(left=0.14, right=0.97, bottom=0.1, top=0.92)
        ax.set_title(title, fontsize="medium")
        if scene.fixed.size:
            ax.plot(*scene.fixed.T, "k^", ms=7)
        self.moving: list[tuple[Any, Any]] = []  # (artist, function of the frame index -> data)

        def line(data_of, **style):  # type: ignore[no-untyped-def]
            first = data_of(0)
            artist = ax.plot(*first.T, **style)[0]
            self.moving.append((artist, data_of))

        for k, trail_path in enumerate(scene.trails):
            if trail > 0:
                line(lambda i, a=trail_path: a[max(0, i - trail): i + 1], color="0.6", lw=0.8, alpha=0.8)
        for a in scene.springs:
            line(lambda i, a=a: a[i], color="tab:olive", lw=1.5, ls="--")
        for a in scene.disks:
            line(lambda i, a=a: a[i], color="tab:purple", lw=1.2)
        for a in scene.spokes:
            line(lambda i, a=a: a[i], color="tab:purple", lw=1.5)
        for k, (_, a) in enumerate(scene.lines):
            line(lambda i, a=a: a[i], color=f"C{k % 10}", lw=3.0, marker="o", ms=3.5, solid_capstyle="round")
        for a in scene.axes:
            for k in range(3):
                line(lambda i, a=a, k=k: a[i, k], color=AXIS_COLOURS[k], lw=1.5)
        for _, a in scene.dots:
            line(lambda i, a=a: a[i][None, :], ls="", marker="o", ms=9, color="k")
        place = dict(transform=ax.transAxes, fontsize="medium", va="top", ha="left")
        self.text = (ax.text2D if three else ax.text)(0.02, 0.98, "", **place)
        self.time_format = _time_format(scene.t)
        self._background = None

    def _set(self, i: int) -> None:
        three = self.scene.dimension == 3
        for artist, data_of in self.moving:
            data = data_of(i)
            if three:
                artist.set_data_3d(data[:, 0], data[:, 1], data[:, 2])
            else:
                artist.set_data(data[:, 0], data[:, 1])
        self.text.set_text(self.time_format.format(self.scene.t[i]))

    def _artists(self) -> list[Any]:
        return [a for a, _ in self.moving] + [self.text]

    def rgba(self, i: int) -> np.ndarray:
        """Frame ``i`` as an (H, W, 4) uint8 array, drawn by blitting."""
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
        """Set frame ``i`` for a writer that redraws the whole figure."""
        self._set(i)


def _validate(frames: int, fps: float) -> None:
    if isinstance(frames, bool) or not isinstance(frames, (int, np.integer)) or frames < 2:
        raise OutputError(f"An animation needs at least 2 frames, not {frames!r}.", fix="use frames >= 2, e.g. 100")
    if not (isinstance(fps, (int, float)) and fps > 0 and math.isfinite(fps)):
        raise OutputError(f"The frame rate {fps!r} is not a positive number.", fix="use fps > 0, e.g. 25")


def render_frames(trajectory: Trajectory, eom: EquationsOfMotion, *, frames: int = 100, size: float = 5.0,
                  dpi: float = 80, view: str = "auto", trail: int | None = None, elev: float = 20.0,
                  azim: float = -60.0) -> tuple[_Renderer, Scene]:
    """The renderer and scene of an animation of ``frames`` frames evenly spaced in time."""
    _validate(frames, 1.0)
    if len(trajectory.t) < 2:
        raise OutputError("The trajectory has fewer than 2 samples, so there is no motion to animate.",
                          fix="simulate over a time span with at least 2 output times")
    if view not in ("auto", "2d", "3d"):
        raise OutputError(f"Unknown view `{view}`.", fix="use auto, 2d or 3d")
    times = np.linspace(trajectory.t[0], trajectory.t[-1], int(frames))
    scene = build_scene(trajectory, eom, times, view=view)
    trail = int(frames) // 3 if trail is None else int(trail)
    renderer = _Renderer(scene, title=trajectory.model_name, size=size, dpi=dpi, trail=trail, elev=elev,
                         azim=azim)
    return renderer, scene


def animate(trajectory: Trajectory, eom: EquationsOfMotion, path: str | Path, *, frames: int = 100,
            fps: float = 25.0, size: float = 5.0, dpi: float = 80, view: str = "auto", trail: int | None = None,
            elev: float = 20.0, azim: float = -60.0) -> Path:
    """Write an animation of the motion to ``path`` (``.gif``, or ``.mp4`` when ffmpeg is installed).

    Parameters
    ----------
    frames : number of frames, evenly spaced over the trajectory's time span.
    fps : frames per second of the file.
    size, dpi : figure size in inches and resolution (5 in × 80 dpi = 400 × 400 pixels).
    view : ``"auto"`` (2D for a planar motion), ``"2d"`` or ``"3d"``.
    trail : past frames of each centre of mass's path to show (default a third of them).
    elev, azim : the 3D viewpoint in degrees.

    Returns
    -------
    Path
        ``path``, written atomically (an existing file is replaced only by a complete one).

    Raises
    ------
    OutputError
        Bad options, an unknown suffix, MP4 without ffmpeg, or a file that cannot be written.
    """
    path = Path(path)
    suffix = path.suffix.lower()
    if suffix not in FORMATS:
        raise OutputError(f"`{path.name}`: animations are written as {' or '.join(FORMATS)}.",
                          fix="name the file with the .gif suffix (or .mp4 with ffmpeg installed)")
    _validate(frames, fps)
    if suffix == ".mp4":
        from matplotlib import animation as mpl_animation

        if not mpl_animation.writers.is_available("ffmpeg"):
            raise OutputError("Writing an MP4 needs ffmpeg, which is not installed.",
                              fix="install ffmpeg, or write a .gif")
    renderer, scene = render_frames(trajectory, eom, frames=frames, size=size, dpi=dpi, view=view, trail=trail,
                                    elev=elev, azim=azim)
    try:
        if suffix == ".gif":
            _write_gif(renderer, len(scene.t), fps, path)
        else:
            _write_mp4(renderer, len(scene.t), fps, path, dpi)
    except OSError as exc:
        raise OutputError(f"Cannot write the animation `{path}`: {exc.strerror or exc}.",
                          fix="check that the folder exists and is writable; any older file is unchanged") from None
    return path


def _write_gif(renderer: _Renderer, count: int, fps: float, path: Path) -> None:
    from PIL import Image

    rgba = [renderer.rgba(i) for i in range(count)]
    frames = [Image.fromarray(a).convert("RGB") for a in rgba]
    # One palette for every frame, made from the first, middle and last ones: no colour
    # flicker between frames, and about 5x faster than Pillow quantizing each frame.
    width, height = frames[0].size
    sample = Image.new("RGB", (width, 3 * height))
    for j, k in enumerate((0, count // 2, count - 1)):
        sample.paste(frames[k], (0, j * height))
    palette = sample.quantize(colors=255, method=Image.Quantize.MEDIANCUT)
    # Pillow maps a colour to a palette entry through a coarse lookup table, so the white
    # background would come out light grey: white gets the last entry, and its pixels are
    # set to it exactly.
    colours = (palette.getpalette() or [])[: 3 * 255]
    colours += [0, 0, 0] * (255 - len(colours) // 3) + [255, 255, 255]
    palette.putpalette(colours)
    images = []
    for frame, a in zip(frames, rgba):
        index = np.array(frame.quantize(palette=palette, dither=Image.Dither.NONE))
        index[a.view(np.uint32)[..., 0] == 0xFFFFFFFF] = 255
        image = Image.fromarray(index)  # mode L; putpalette makes it P
        image.putpalette(colours)
        images.append(image)
    duration = max(int(round(1000 / fps)), 10)
    write_atomic_with(path, lambda handle: images[0].save(handle, format="GIF", save_all=True,
                                                          append_images=images[1:], duration=duration, loop=0))


def _write_mp4(renderer: _Renderer, count: int, fps: float, path: Path, dpi: float) -> None:
    from matplotlib.animation import FFMpegWriter

    fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".mp4", dir=path.parent)
    os.close(fd)
    try:
        writer = FFMpegWriter(fps=fps)
        with writer.saving(renderer.fig, tmp, dpi):
            for i in range(count):
                renderer.full(i)
                writer.grab_frame()
        os.replace(tmp, path)
    except BaseException:
        try:
            os.unlink(tmp)
        except FileNotFoundError:
            pass
        raise
