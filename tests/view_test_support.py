"""Helpers of the 3-D view's tests: short runs of the examples, pages in headless Chromium, pixels.

The browser is Debian's ``chromium`` (``make test`` installs it as root), driven over the
DevTools protocol (`lagrangian.view3d._chromium`); ``tests/view3d/conftest.py`` gives one per
test module, and skips the tests that need it, with the reason, where there is none.
"""

from __future__ import annotations

import colorsys
import functools
import io
from pathlib import Path

import numpy as np
from lagrangian_test_support import EXAMPLES_DIR

import lagrangian
from lagrangian.view3d._chromium import Browser


@functools.cache
def motion(name: str, t_end: float, n_out: int, **initial: float):
    """(eom, trajectory) of an example, simulated once per session."""
    eom = lagrangian.derive(lagrangian.load_model(EXAMPLES_DIR / name))
    return eom, lagrangian.simulate(eom, t_end, n_out=n_out, initial=initial or None)


def open_view(browser: Browser, view, folder: Path, *, width: int = 800, height: int = 600):
    """The page of ``view`` in a new tab, once its viewer has mounted."""
    path = folder / "view.html"
    view.save(path)
    page = browser.open(path, width=width, height=height)
    page.wait_for("window.lagrangianView !== undefined")
    return page


def page_messages(page) -> list[str]:
    """The page's console messages, uncaught exceptions and the browser's log entries about it: all of them."""
    return page.console()


def project(camera: dict, point) -> tuple[float, float]:
    """The page pixel where ``point`` (R0) lands, through the page's own camera: clip = P V [x, 1]."""
    p = np.array(camera["projection"]).reshape(4, 4).T  # three.js stores matrices column by column
    v = np.array(camera["view"]).reshape(4, 4).T
    clip = p @ v @ np.append(np.asarray(point, float), 1.0)
    ndc = clip[:3] / clip[3]
    box = camera["canvas"]
    return box["left"] + (ndc[0] + 1) / 2 * camera["width"], box["top"] + (1 - ndc[1]) / 2 * camera["height"]


def pixels(png: bytes) -> np.ndarray:
    from PIL import Image

    return np.asarray(Image.open(io.BytesIO(png)).convert("RGB"))


def hue_at(image: np.ndarray, xy: tuple[float, float], radius: int = 1) -> list[tuple[float, float]]:
    """(hue in degrees, saturation) of the pixels around ``xy``."""
    x, y = round(xy[0]), round(xy[1])
    out = []
    for j in range(y - radius, y + radius + 1):
        for i in range(x - radius, x + radius + 1):
            r, g, b = image[j, i] / 255.0
            h, s, _ = colorsys.rgb_to_hsv(r, g, b)
            out.append((360 * h, s))
    return out


def hue_of(colour: str) -> float:
    r, g, b = (int(colour[k:k + 2], 16) / 255 for k in (1, 3, 5))
    return 360 * colorsys.rgb_to_hsv(r, g, b)[0]


def has_colour(image: np.ndarray, xy: tuple[float, float], colour: str, tolerance: float = 18.0) -> bool:
    """Whether most pixels around ``xy`` have the hue of ``colour`` (shading changes brightness, not hue)."""
    want = hue_of(colour)
    close = [s > 0.3 and min(abs(h - want), 360 - abs(h - want)) <= tolerance for h, s in hue_at(image, xy)]
    return sum(close) >= 6
