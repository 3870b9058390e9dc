"""The scene as lines, dots and circles over the frames: what the matplotlib animation draws.

Each part of the `Scene` becomes its outline, placed by its carrier's pose at each frame: a rod
its segment, a disk its circle and a spoke fixed in the body (which shows the spin), a
cylinder its axis and end circles, a box or a mesh the edges of its box, a particle's sphere a
dot; links, springs and dampers join their tracks; the ground's points are marked; the traced
points leave trails.  So the GIF and the 3-D page draw the same shapes at the same places.

A motion whose points all stay in one plane is drawn in 2D, in that plane, with the page's
vertical against gravity when gravity lies in the plane (a pendulum in (y0, z0), z0 up); a
disk across the plane, which only shows spin, is then left out.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ._scene import Scene, _matrices

__all__ = ["PLANAR", "Wireframe", "wireframe"]

#: Smallest/largest singular value of the centred point cloud below which it is a plane.
PLANAR = 1e-9
_CIRCLE = np.linspace(0, 2 * np.pi, 49)
_BOX_EDGES = [(0, 1), (1, 3), (3, 2), (2, 0), (4, 5), (5, 7), (7, 6), (6, 4), (0, 4), (1, 5), (2, 6), (3, 7)]


@dataclass(frozen=True)
class Wireframe:
    """Arrays over F frames, in R0 components (3D) or in the plane's (2D).

    Parameters
    ----------
    t : ndarray of shape (F,)
        The frame times.
    lines : tuple of (str, str, ndarray)
        (name, colour, (F, k, d)) polylines (NaN rows break a polyline: a box's edges).
    dots : tuple of (str, str, ndarray)
        (name, colour, (F, d)).
    springs : tuple of ndarray
        Each (F, 2, d).
    fixed : ndarray of shape (p, d)
        The fixed points.
    axes : tuple of ndarray
        Each (F, 3, 2, d): a frame's three axes.
    disks : tuple of (str, ndarray)
        (colour, (F, m, d)) closed curves.
    spokes : tuple of ndarray
        Each (F, 2, d).
    plane : ndarray of shape (2, 3), optional
        The matrix whose rows are the page's axes in R0 (2D), else None.
    plane_names : (str, str)
        Such as ("y0", "z0").
    trails : tuple of ndarray
        Each (F, d): the paths of the traced points.
    axis_names : (str, str, str)
        The names of R0's axes.
    """

    t: np.ndarray
    lines: tuple[tuple[str, str, np.ndarray], ...]
    dots: tuple[tuple[str, str, np.ndarray], ...]
    springs: tuple[np.ndarray, ...]
    fixed: np.ndarray
    axes: tuple[np.ndarray, ...] = ()
    disks: tuple[tuple[str, np.ndarray], ...] = ()
    spokes: tuple[np.ndarray, ...] = ()
    plane: np.ndarray | None = None
    plane_names: tuple[str, str] = ("", "")
    trails: tuple[np.ndarray, ...] = field(default=())
    axis_names: tuple[str, str, str] = ("x0", "y0", "z0")

    @property
    def dimension(self) -> int:
        return 3 if self.plane is None else 2

    def bounds(self) -> tuple[np.ndarray, np.ndarray]:
        """Lower and upper corners of everything drawn, each (d,).

        Returns
        -------
        lower : ndarray of shape (d,)
            The lower corner of everything drawn.
        upper : ndarray of shape (d,)
            The upper corner.
        """
        d = self.dimension
        clouds = [a.reshape(-1, d) for _, _, a in self.lines] + [a for _, _, a in self.dots]
        clouds += [a.reshape(-1, d) for a in (*self.springs, *self.axes, *self.spokes)]
        clouds += [a.reshape(-1, d) for _, a in self.disks]
        clouds.append(self.fixed.reshape(-1, d) if self.fixed.size else np.zeros((1, d)))
        pts = np.concatenate(clouds)
        return np.nanmin(pts, axis=0), np.nanmax(pts, axis=0)


def _apply(frames: np.ndarray, local: np.ndarray) -> np.ndarray:
    """Points (m, 3) of a part's frame at each of its poses (F, 4, 4): (F, m, 3)."""
    return np.einsum("fij,mj->fmi", frames[:, :3, :3], local) + frames[:, None, :3, 3]


def _outline(kind: str, size: tuple[float, ...], mesh_vertices: np.ndarray | None) -> dict[str, list[np.ndarray]]:
    """A part's outline in its own axes: ``lines``, ``disks`` (closed curves) and ``spokes``."""
    if kind == "rod":
        h = size[1] / 2
        return {"lines": [np.array([[0, 0, -h], [0, 0, h]])]}
    if kind in ("disk", "cylinder"):
        r, h = size[0], size[1] / 2
        ring = np.column_stack([r * np.cos(_CIRCLE), r * np.sin(_CIRCLE), np.zeros_like(_CIRCLE)])
        spoke = np.array([[0, 0, 0], [r, 0, 0]])
        if kind == "disk":
            return {"disks": [ring], "spokes": [spoke]}
        return {"disks": [ring + [0, 0, -h], ring + [0, 0, h]], "spokes": [spoke + [0, 0, h]],
                "lines": [np.array([[0, 0, -h], [0, 0, h]])]}
    if kind in ("box", "mesh"):
        if kind == "box":
            lo, hi = -np.array(size) / 2, np.array(size) / 2
        else:
            lo, hi = mesh_vertices.min(axis=0), mesh_vertices.max(axis=0)  # type: ignore[union-attr]
        corners = np.array([[(lo, hi)[i][0], (lo, hi)[j][1], (lo, hi)[k][2]]
                            for i in (0, 1) for j in (0, 1) for k in (0, 1)])
        path = []
        for a, b in _BOX_EDGES:
            path += [corners[a], corners[b], [np.nan] * 3]
        return {"lines": [np.array(path[:-1])]}
    return {}


def wireframe(scene: Scene, *, view: str = "auto", run: int = 0) -> Wireframe:
    """The outlines of ``scene`` at its frames (`Wireframe`).

    Parameters
    ----------
    scene : Scene
        The scene.
    view : {"auto", "2d", "3d"}, optional
        ``"auto"`` (2D when planar), ``"2d"``, ``"3d"``.
    run : int, optional
        The run.

    Returns
    -------
    Wireframe
        The outlines.
    """
    world = scene.world(run)
    points = scene.runs[run].points.astype(float) + np.array(scene.runs[run].offset)
    lines, dots, disks, spokes = [], [], [], []
    for k, part in enumerate(scene.parts):
        if part.source in ("hinge", "ball"):
            continue  # joints are the 3-D view's detail
        frames = world[:, k]
        if part.kind == "sphere" or part.kind == "cone":
            dots.append((part.owner, part.color, frames[:, :3, 3]))
            continue
        outline = _outline(part.kind, part.size, part.mesh.vertices if part.mesh is not None else None)
        for line in outline.get("lines", []):
            lines.append((part.owner, part.color, _apply(frames, line)))
        for ring in outline.get("disks", []):
            disks.append((part.color, _apply(frames, ring)))
        for spoke in outline.get("spokes", []):
            spokes.append(_apply(frames, spoke))
    springs = []
    for link in scene.links:
        segment = np.stack([points[:, link.a], points[:, link.b]], axis=1)
        if link.kind == "rod":
            lines.append((link.name, link.color, segment))
        else:
            springs.append(segment)
    fixed = np.array([points[0, k] for k, tr in enumerate(scene.tracks) if tr.fixed]).reshape(-1, 3)
    axes = []
    poses = scene.runs[run].poses.astype(float)
    for triad in scene.triads:
        if triad.carrier >= poses.shape[1] or scene.carriers[triad.carrier].frame == "R0":
            continue
        frames = _matrices(poses[:, triad.carrier, :])
        origin = frames[:, :3, :3] @ np.array(triad.position) + frames[:, :3, 3] + np.array(scene.runs[run].offset)
        ends = origin[:, None, :] + 0.6 * triad.length * np.transpose(frames[:, :3, :3], (0, 2, 1))
        axes.append(np.stack([np.broadcast_to(origin[:, None, :], ends.shape), ends], axis=2))
    trails = tuple(points[:, k] for k in scene.traces)
    shape = Wireframe(scene.t, tuple(lines), tuple(dots), tuple(springs), fixed, tuple(axes), tuple(disks),
                      tuple(spokes), None, ("", ""), trails, scene.axis_names)
    if view == "3d":
        return shape
    return _flatten(shape, np.array(scene.up), force=view == "2d")


def _name(v: np.ndarray, names: tuple[str, ...]) -> str:
    k = int(np.argmax(np.abs(v)))
    if abs(abs(v[k]) - 1) > 1e-9:
        return ""
    return ("" if v[k] > 0 else "−") + names[k]


def _plane(points: np.ndarray, up: np.ndarray, names: tuple[str, ...]) -> tuple[np.ndarray, tuple[str, str]] | None:
    """The page's axes (2 × 3) when every point lies in one plane, else None."""
    points = points[np.all(np.isfinite(points), axis=1)]
    if len(points) < 3:
        return None
    centred = points - points.mean(axis=0)
    _, s, vt = np.linalg.svd(centred, full_matrices=False)
    if len(s) < 3 or s[-1] > PLANAR * s[0]:
        return None
    gravity = -up
    normal = vt[2]
    if s[1] <= PLANAR * s[0]:  # all on one line (or one point): the plane holding it and gravity
        line = vt[0] if s[0] > 0 else np.eye(3)[0]
        across = np.cross(line, gravity)
        if np.linalg.norm(across) < 1e-9:
            e = np.eye(3)[int(np.argmin(np.abs(line)))]
            across = e - (e @ line) * line
        normal = across / np.linalg.norm(across)
    k = int(np.argmax(np.abs(normal)))
    if abs(abs(normal[k]) - 1) < 1e-9:  # a plane of R0's axes: use them exactly
        normal = np.eye(3)[k]
    if abs(gravity @ normal) < 1e-9:
        vertical = up
    else:
        others = [i for i in range(3) if i != k]
        guess = np.eye(3)[others[1]] if abs(abs(normal[k]) - 1) < 1e-9 else vt[1]
        vertical = guess - (guess @ normal) * normal
        if np.linalg.norm(vertical) < 1e-9:
            vertical = np.cross(normal, vt[0])
        vertical = vertical / np.linalg.norm(vertical)
    right = np.cross(vertical, normal)
    j = int(np.argmax(np.abs(right)))
    if right[j] < 0:
        right = -right
    return np.array([right, vertical]), (_name(right, names), _name(vertical, names))


def _flatten(shape: Wireframe, up: np.ndarray, *, force: bool) -> Wireframe:
    """``shape`` in its plane when it has one (or ``force``): a disk across the plane is left out."""
    cloud = np.concatenate([a.reshape(-1, 3) for _, _, a in shape.lines] + [a for _, _, a in shape.dots]
                           + [a.reshape(-1, 3) for a in shape.springs] + [shape.fixed.reshape(-1, 3)]
                           + [np.zeros((0, 3))])
    decorated = np.concatenate([cloud] + [a.reshape(-1, 3) for _, a in shape.disks]
                               + [a.reshape(-1, 3) for a in shape.spokes])
    found = _plane(decorated, up, shape.axis_names) or _plane(cloud, up, shape.axis_names)
    if found is None:
        if not force:
            return shape
        finite = cloud[np.all(np.isfinite(cloud), axis=1)]
        _, _, vt = np.linalg.svd(finite - finite.mean(axis=0), full_matrices=False)
        plane, names = vt[:2], ("", "")
    else:
        plane, names = found
    normal = np.cross(plane[0], plane[1])
    finite = cloud[np.all(np.isfinite(cloud), axis=1)]
    origin = finite[0] if len(finite) else np.zeros(3)
    scale = max(float(np.ptp(finite, axis=0).max()) if len(finite) else 0.0, 1e-300)

    def flat(a: np.ndarray) -> np.ndarray:
        return a @ plane.T

    def in_plane(a: np.ndarray) -> bool:
        a = a.reshape(-1, 3)
        return bool(np.nanmax(np.abs((a - origin) @ normal)) <= PLANAR * 1e3 * scale)

    kept = [(c, d) for c, d in shape.disks if in_plane(d)]
    kept_spokes = [sp for sp in shape.spokes if in_plane(sp)] if kept else []
    return Wireframe(shape.t, tuple((n, c, flat(a)) for n, c, a in shape.lines),
                     tuple((n, c, flat(a)) for n, c, a in shape.dots), tuple(flat(a) for a in shape.springs),
                     flat(shape.fixed) if shape.fixed.size else np.zeros((0, 2)), (),
                     tuple((c, flat(d)) for c, d in kept), tuple(flat(sp) for sp in kept_spokes), plane, names,
                     tuple(flat(a) for a in shape.trails), shape.axis_names)
