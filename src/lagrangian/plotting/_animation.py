"""An animation of the bodies and particles of a model along a trajectory (GIF, or MP4 with ffmpeg).

What it draws is the scene of the 3-D view (`lagrangian.view3d`): the same shapes, colours,
links and traces, as the outlines of its `Wireframe`, so the animation and the 3-D page cannot
disagree.  Frames are drawn by blitting on an Agg canvas (`lagrangian.view3d._matplotlib`); a
GIF is assembled by Pillow (as matplotlib's ``PillowWriter`` does) and written atomically; an
MP4 goes through matplotlib's ``FFMpegWriter`` when ffmpeg exists.
"""

from __future__ import annotations

import math
import os
import tempfile
from pathlib import Path

import numpy as np

from .._atomic import write_atomic_with
from ..dynamics import EquationsOfMotion
from ..errors import OutputError
from ..numerics import Trajectory
from ..view3d import Renderer, Wireframe
from ._geometry import Samples

__all__ = ["animate", "render_frames", "motion_scene", "FORMATS"]

#: Animation formats, by file suffix.
FORMATS = (".gif", ".mp4")

def _validate(frames: int, fps: float) -> None:
    if isinstance(frames, bool) or not isinstance(frames, (int, np.integer)) or frames < 2:
        raise OutputError(f"An animation needs at least 2 frames, not {frames!r}.", fix="use frames >= 2, e.g. 100")
    if not (isinstance(fps, (int, float)) and fps > 0 and math.isfinite(fps)):
        raise OutputError(f"The frame rate {fps!r} is not a positive number.", fix="use fps > 0, e.g. 25")


def motion_scene(trajectory: Trajectory, eom: EquationsOfMotion, times: np.ndarray, *, view: str = "auto") -> Wireframe:
    """The outlines of the 3-D view's scene at ``times`` (the state at each by interpolating q between the
    trajectory's samples, then every position from q, so a rod keeps its length)."""
    from ..view3d import Motion, build_scene, wireframe

    samples = Samples.at(trajectory, times)
    values = {p.name: p.value for p in eom.model.parameters if p.value is not None}
    values.update(trajectory.parameters)
    motion = Motion(trajectory.model_name, samples.t, samples.q, samples.qd)
    scene = build_scene(eom.model, [motion], {k: float(v) for k, v in values.items()}, max_frames=len(times))
    return wireframe(scene, view=view)


def render_frames(trajectory: Trajectory, eom: EquationsOfMotion, *, frames: int = 100, size: float = 5.0,
                  dpi: float = 80, view: str = "auto", trail: int | None = None, elev: float = 20.0,
                  azim: float = -60.0) -> tuple[Renderer, Wireframe]:
    """The renderer and scene of an animation of ``frames`` frames evenly spaced in time."""
    _validate(frames, 1.0)
    if len(trajectory.t) < 2:
        raise OutputError("The trajectory has fewer than 2 samples, so there is no motion to animate.",
                          fix="simulate over a time span with at least 2 output times")
    if view not in ("auto", "2d", "3d"):
        raise OutputError(f"Unknown view `{view}`.", fix="use auto, 2d or 3d")
    times = np.linspace(trajectory.t[0], trajectory.t[-1], int(frames))
    scene = motion_scene(trajectory, eom, times, view=view)
    trail = int(frames) // 3 if trail is None else int(trail)
    renderer = Renderer(scene, title=trajectory.model_name, size=size, dpi=dpi, trail=trail, elev=elev,
                        azim=azim)
    return renderer, scene


def animate(trajectory: Trajectory, eom: EquationsOfMotion, path: str | Path, *, frames: int = 100,
            fps: float = 25.0, size: float = 5.0, dpi: float = 80, view: str = "auto", trail: int | None = None,
            elev: float = 20.0, azim: float = -60.0) -> Path:
    """Write an animation of the motion to ``path`` (``.gif``, or ``.mp4`` when ffmpeg is installed).

    Parameters
    ----------
    trajectory : Trajectory
        A simulated motion.
    eom : EquationsOfMotion
        Its equations.
    path : str or Path
        The file to write: ``.gif``, or ``.mp4`` when ffmpeg is installed.
    frames : int, optional
        The number of frames, evenly spaced over the trajectory's time span.
    fps : float, optional
        Frames per second of the file.
    size : float, optional
        The figure's size in inches (5 in × 80 dpi = 400 × 400 pixels).
    dpi : float, optional
        Its resolution.
    view : {"auto", "2d", "3d"}, optional
        ``"auto"`` (2D for a planar motion), ``"2d"`` or ``"3d"``.
    trail : int, optional
        Past frames of each centre of mass's path to show (default a third of them).
    elev : float, optional
        The 3D viewpoint's elevation, in degrees.
    azim : float, optional
        The 3D viewpoint's azimuth, in degrees.

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


def _write_gif(renderer: Renderer, count: int, fps: float, path: Path) -> None:
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
    for frame, a in zip(frames, rgba, strict=True):
        index = np.array(frame.quantize(palette=palette, dither=Image.Dither.NONE))
        index[a.view(np.uint32)[..., 0] == 0xFFFFFFFF] = 255
        image = Image.fromarray(index)  # mode L; putpalette makes it P
        image.putpalette(colours)
        images.append(image)
    duration = max(int(round(1000 / fps)), 10)
    write_atomic_with(path, lambda handle: images[0].save(handle, format="GIF", save_all=True,
                                                          append_images=images[1:], duration=duration, loop=0))


def _write_mp4(renderer: Renderer, count: int, fps: float, path: Path, dpi: float) -> None:
    from matplotlib.animation import FFMpegWriter

    fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".mp4", dir=path.parent)
    os.close(fd)
    try:
        # ffmpeg's -r takes a fractional rate; matplotlib's stub says int
        writer = FFMpegWriter(fps=fps)  # type: ignore[arg-type]
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
