"""Stage 7 — the 3-D view: a model at rest or in motion, in one offline HTML page (three.js inline).

``view(traj, eom)`` (or ``view(model)`` at rest) returns a `View`: ``html()``, ``save(path)``,
``png()``, and it displays itself in Jupyter.  Its `Scene` — carriers and their poses, parts,
tracks, links, triads, arcs, arrows — is the one description that the page and the matplotlib
animation (`lagrangian.plotting.animate`) both draw; `lagrangian.view3d.html` writes the page (or a
fragment of it, for the report).  See ``docs/view.md``.
"""

from ._build import Motion as Motion
from ._build import build_scene as build_scene

# Shared with plotting and the report: the scene drawn by matplotlib, as a wireframe, as a still image.
from ._matplotlib import Renderer as Renderer
from ._scene import Scene as Scene
from ._still import still_png as still_png
from ._view import View as View
from ._view import view as view
from ._wireframe import Wireframe as Wireframe
from ._wireframe import wireframe as wireframe

__all__ = [
           "Motion",
           "Renderer",
           "Scene",
           "View",
           "Wireframe",
           "build_scene",
           "still_png",
           "view",
           "wireframe",
]
