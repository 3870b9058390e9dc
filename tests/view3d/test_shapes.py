"""The shapes a model does not declare are inferred from its inertia: checked against the inertia by hand.

Each inferred solid is homogeneous, so its size gives back the moments it was made from by the
textbook formulas written here (a rod A = m l²/12, a disk C = m r²/2, a cylinder
A = m (3r² + h²)/12, a sphere 2/5 m R², a box m (b² + c²)/12).
"""

from __future__ import annotations

import numpy as np
import pytest
from lagrangian_test_support import EXAMPLES_DIR

import lagrangian
from lagrangian import ModelBuilder
from lagrangian.view3d import view
from lagrangian.view3d._infer import solid_of_inertia


def _parts(scene, owner, source="inertia"):
    return [p for p in scene.parts if p.owner == owner and p.source == source]


def _axis(part) -> np.ndarray:
    """The part's own z axis, in its carrier's frame (from its quaternion x, y, z, w)."""
    x, y, z, w = part.rotation
    return np.array([2 * (x * z + y * w), 2 * (y * z - x * w), 1 - 2 * (x * x + y * y)])


def test_double_pendulum_rods_have_the_length_of_their_inertia():
    model = lagrangian.load_model(EXAMPLES_DIR / "double_pendulum.toml")
    scene = view(model).scene
    values = model.parameter_values
    for body, m, l in (("S1", "m1", "l1"), ("S2", "m2", "l2")):
        (rod,) = _parts(scene, body)
        assert rod.kind == "rod"
        a = values[m] * values[l] ** 2 / 12  # the model's A at G
        assert rod.size[1] == pytest.approx(np.sqrt(12 * a / values[m]))  # A = m l²/12
        assert rod.size[1] == pytest.approx(values[l])  # ...the rod from hinge to hinge
        assert abs(_axis(rod) @ [0, 0, 1]) == pytest.approx(1.0)  # along z1, z2: the rods' direction
    hinges = [p for p in scene.parts if p.source == "hinge"]
    assert len(hinges) == 2 and all(abs(_axis(h)[0]) == pytest.approx(1.0) for h in hinges)  # about x0


def test_top_disk_radius_is_that_of_its_moment_c():
    model = lagrangian.lagrange_top()
    scene = view(model).scene
    v = model.parameter_values
    (disk,) = _parts(scene, "S")
    assert disk.kind == "disk"
    assert v["m"] * disk.size[0] ** 2 / 2 == pytest.approx(v["C"])  # C = m r²/2
    assert abs(_axis(disk) @ [0, 0, 1]) == pytest.approx(1.0)  # across its axis z
    # The axle: from O through G (OG = a z) to the apex, past the disk; the apex is traced.
    (stem,) = _parts(scene, "S", "points")
    half = stem.size[1] / 2
    start = np.array(stem.position) - half * _axis(stem)
    end = np.array(stem.position) + half * _axis(stem)
    np.testing.assert_allclose(start, [0, 0, -v["a"]], atol=1e-12)  # O, seen from G on the body's frame
    assert end @ [0, 0, 1] > disk.size[0] / 2 and np.allclose(end[:2], 0, atol=1e-12)  # beyond G, on z
    (tip,) = [t for t in scene.tracks if t.kind == "tip"]
    assert scene.traces == (scene.track(tip.name),)
    np.testing.assert_allclose(scene.runs[0].points[0, scene.track(tip.name)],
                               scene.runs[0].points[0, scene.track("S")] * (v["a"] + end[2]) / v["a"], atol=1e-6)


def test_rolling_coin_is_a_disk_of_its_radius():
    model = lagrangian.load_model(EXAMPLES_DIR / "rolling_coin.toml")
    (disk,) = _parts(view(model).scene, "S")
    v = model.parameter_values
    assert disk.kind == "disk" and disk.size[0] == pytest.approx(v["r"])  # C = m r²/2 with C = m r²/2 given
    assert abs(_axis(disk)[1]) == pytest.approx(1.0)  # the coin's axle is y of its frame


def _free_body(diagonal, matrix=None):
    b = ModelBuilder("solid")
    b.parameter("m", 2.0)
    b.coordinate("x", initial=0.0)
    b.coordinate("alpha", initial=0.0)
    b.frame("R1", "R0", rotation=("alpha", "z"))
    inertia = {"at": "G", "frame": "R1"}
    inertia.update({"matrix": matrix} if matrix else {"diagonal": diagonal})
    b.body("S", frame="R1", mass="m", center="x*R0.x", inertia=inertia)
    return b.build()


def test_a_body_of_revolution_is_the_cylinder_of_its_moments():
    a, c = 0.5, 0.09  # A > C: elongated
    (cyl,) = _parts(view(_free_body([a, a, c])).scene, "S")
    r, h = cyl.size
    assert cyl.kind == "cylinder"
    assert 2.0 * r ** 2 / 2 == pytest.approx(c)  # C = m r²/2
    assert 2.0 * (3 * r ** 2 + h ** 2) / 12 == pytest.approx(a)  # A = m (3r² + h²)/12
    assert abs(_axis(cyl)[2]) == pytest.approx(1.0)


def test_three_equal_moments_without_an_axis_are_a_sphere():
    (ball,) = _parts(view(_free_body([0.2, 0.2, 0.2])).scene, "S")
    assert ball.kind == "sphere" and 2 / 5 * 2.0 * ball.size[0] ** 2 == pytest.approx(0.2)


def test_three_different_moments_are_the_box_of_the_same_inertia():
    matrix = [[0.30, -0.04, 0.0], [-0.04, 0.22, 0.03], [0.0, 0.03, 0.12]]
    (box,) = _parts(view(_free_body(None, matrix)).scene, "S")
    assert box.kind == "box"
    sides = np.array(box.size)
    # Its inertia along its own axes, m (b² + c²)/12..., turned back to the body's frame, is the model's.
    own = 2.0 / 12 * np.diag([sides[1] ** 2 + sides[2] ** 2, sides[0] ** 2 + sides[2] ** 2,
                              sides[0] ** 2 + sides[1] ** 2])
    x, y, z, w = box.rotation
    turn = np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
                     [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
                     [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]])
    np.testing.assert_allclose(turn @ own @ turn.T, matrix, atol=1e-12)


def test_point_masses_and_springs():
    model = lagrangian.load_model(EXAMPLES_DIR / "cart_pendulum.toml")
    scene = view(model).scene
    assert {p.owner: p.kind for p in scene.parts} == {"C": "sphere", "P": "sphere"}
    kinds = sorted(k.kind for k in scene.links)
    assert kinds == ["rod", "spring"]
    (rod,) = [k for k in scene.links if k.kind == "rod"]
    assert {scene.tracks[rod.a].name, scene.tracks[rod.b].name} == {"C", "P"}  # the pendulum hangs from the cart
    (wall,) = [t for t in scene.tracks if t.fixed]
    assert wall.name == "W"  # the spring's anchor on the ground


def test_no_mass_no_solid():
    assert solid_of_inertia(np.zeros(3), np.eye(3), 1.0) is None
    assert solid_of_inertia(np.array([0.0, 1.0, 1.0]), np.eye(3), 0.0) is None
