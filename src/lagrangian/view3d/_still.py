"""A still picture of a scene: Chromium's screenshot of the page, or matplotlib's drawing of the same scene.

The LaTeX and PDF reports, and ``lagrangian view -o view.png``, need a picture, not a page.
Where a Chromium is installed, the page is opened headless (`_chromium`), set to the time
asked for, its controls hidden, and photographed: the picture is the 3-D view itself.  Where
none is (or it cannot start), matplotlib draws the scene's `Wireframe` (`_matplotlib`), the
animation's drawing.
"""

from __future__ import annotations

import tempfile
from pathlib import Path

import numpy as np

from ..errors import OutputError
from ._chromium import Browser, find_chromium
from ._scene import Scene

__all__ = ["still_by_browser", "still_png"]


def still_by_browser(scene: Scene, *, width: int, height: int, time: float | None = None) -> bytes:
    """The page of ``scene`` photographed by headless Chromium at ``time`` (its controls hidden)."""
    from .html import page

    with tempfile.TemporaryDirectory(prefix="lagrangian-still-") as folder:
        path = Path(folder) / "view.html"
        path.write_text(page(scene), encoding="utf-8")
        with Browser() as browser:
            tab = browser.open(path, width=width, height=height)
            tab.wait_for("window.lagrangianView !== undefined")
            tab.evaluate("lagrangianView.controls(false)")
            tab.evaluate(f"lagrangianView.setTime({float(scene.t[0] if time is None else time)!r})")
            return tab.screenshot()


def still_png(scene: Scene, *, width: int = 800, height: int = 600, time: float | None = None,
              browser: bool | None = None) -> bytes:
    """A PNG of ``scene`` at ``time``: by Chromium when there is one (or ``browser=True``), else by matplotlib.

    Parameters
    ----------
    scene : Scene
        The scene.
    width : int, optional
        In pixels.
    height : int, optional
        In pixels.
    time : float, optional
        The time shown (default: the start).
    browser : bool, optional
        True forces Chromium, False matplotlib; None: Chromium when there is one.

    Returns
    -------
    bytes
        The PNG.
    """
    if browser or (browser is None and find_chromium() is not None):
        if find_chromium() is None:
            raise OutputError("No Chromium is installed to photograph the view.",
                              fix="install Chromium (Debian: apt install chromium), or draw it with matplotlib")
        try:
            return still_by_browser(scene, width=width, height=height, time=time)
        except (OutputError, OSError):
            if browser:
                raise
            # A Chromium that cannot start here (no /dev/shm, a sandbox): the same scene, drawn by matplotlib.
    from ._matplotlib import still_matplotlib

    index = 0 if time is None else int(np.argmin(np.abs(scene.t - time)))
    return still_matplotlib(scene, width=width, height=height, index=index)
