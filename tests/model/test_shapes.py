"""Declared shapes (``[shapes]``, ``shape = {...}``, URDF ``<visual>``): read, placed, and refused with file and line."""

from __future__ import annotations

import struct
from pathlib import Path

import numpy as np
import pytest
from lagrangian_test_support import EXAMPLES_DIR, example_text

import lagrangian
from lagrangian.cli.main import main
from lagrangian.errors import ModelError
from lagrangian.view3d import view

PENDULUM = example_text("double_pendulum.toml")


def _model(folder: Path, shapes: str, name: str = "m.toml") -> Path:
    path = folder / name
    path.write_text(PENDULUM + "\n[shapes]\n" + shapes + "\n", encoding="utf-8")
    return path


def _line_of(path: Path, text: str) -> int:
    return next(k for k, line in enumerate(path.read_text().splitlines(), 1) if text in line)


def _binary_stl(path: Path, triangles: np.ndarray) -> None:
    with path.open("wb") as f:
        f.write(b"\0" * 80 + struct.pack("<I", len(triangles)))
        for tri in triangles:
            f.write(struct.pack("<12fH", 0, 0, 0, *tri.reshape(-1), 0))


def test_declared_shapes_replace_the_inferred_ones(tmp_path):
    path = _model(tmp_path, 'S1 = { kind = "box", size = [0.1, 0.1, "l1"], color = "steelblue", opacity = 0.5 }\n'
                            'S2 = [{ kind = "rod", between = ["A", "S2"], radius = 0.02 },\n'
                            '      { kind = "sphere", radius = "l2/8", center = "-l2/2*R2.z", color = [1, 0.5, 0] }]')
    model = lagrangian.load_model(path)
    assert [(s.on, s.kind) for s in model.shapes] == [("S1", "box"), ("S2", "rod"), ("S2", "sphere")]
    scene = view(model).scene
    box, rod, ball = [p for p in scene.parts if p.source == "declared"]
    assert box.color == "#4682b4" and box.opacity == 0.5 and box.size == pytest.approx((0.1, 0.1, 1.0))
    assert rod.size[1] == pytest.approx(0.4)  # from A to G2: half of l2
    assert ball.color == "#ff8000" and ball.size == pytest.approx((0.1,))
    # The ball is at the rod's free end: G2 − l2/2 z2, i.e. −l2/2 z2 from G2 on the body's frame.
    assert ball.position == pytest.approx((0.0, 0.0, -0.4))
    assert not [p for p in scene.parts if p.source == "inertia"]


def test_a_shape_inside_a_body_table(tmp_path):
    text = PENDULUM.replace('fixed_point = "O"', 'fixed_point = "O"\nshape = { kind = "cylinder", radius = 0.03, '
                                                  'length = "l1", axis = "z" }')
    path = tmp_path / "m.toml"
    path.write_text(text, encoding="utf-8")
    (shape,) = lagrangian.load_model(path).shapes
    assert shape.on == "S1" and shape.kind == "cylinder" and shape.frame == "R1"


@pytest.mark.parametrize("shapes, message", [
    ('S3 = { kind = "sphere", radius = 1 }', "`S3`, which is not a body or a particle"),
    ('S1 = { kind = "sphere", radius = 1, color = "bluish" }', "`bluish` is not a colour"),
    ('S1 = { kind = "sphere", radius = 1, color = [2, 0, 0] }', "not three numbers in [0, 1]"),
    ('S1 = { kind = "cube" }', "has kind `cube`"),
    ('S1 = { kind = "sphere", radius = 1, height = 2 }', "a sphere has no key `height`"),
    ('S1 = { kind = "sphere", radius = "-l1" }', "is -1: a size is a positive number"),
    ('S1 = { kind = "sphere", radius = "theta1" }', "depends on `theta1`"),
    ('S1 = { kind = "sphere", radius = "__import__(\'os\')" }', "radius"),
    ('S1 = { kind = "sphere", radius = 1, opacity = 3 }', "not a number in [0, 1]"),
    ('S1 = { kind = "rod", between = ["O", "Z"] }', "unknown point `Z`"),
    ('S1 = { kind = "mesh", mesh = "nope.stl" }', "does not exist"),
    ('S1 = { kind = "mesh", mesh = "part.step" }', "whose format the view cannot read"),
])
def test_bad_shapes_are_refused_at_their_line(tmp_path, shapes, message):
    path = _model(tmp_path, shapes)
    with pytest.raises(ModelError) as info:
        lagrangian.load_model(path)
    assert message in info.value.message
    assert info.value.file == str(path) and info.value.line == _line_of(path, shapes.split(" =")[0] + " =")


def test_a_huge_mesh_is_refused_before_it_is_read(tmp_path):
    huge = tmp_path / "huge.stl"
    with huge.open("wb") as f:  # a sparse file: 40 MB that take no room
        f.truncate(40 * 2**20)
    path = _model(tmp_path, 'S1 = { kind = "mesh", mesh = "huge.stl" }')
    with pytest.raises(ModelError, match="40 MB, more than the 32 MB") as info:
        lagrangian.load_model(path)
    assert info.value.line == _line_of(path, "S1 =")


@pytest.mark.parametrize("content, message", [
    (b"solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 zero\n", "`zero` is not a number (line 4 of the mesh)"),
    (b"\xff\xfe garbage that is no STL", "neither a binary STL"),
    (b"solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nendloop\nendfacet\n", "three vertices"),
])
def test_a_malformed_mesh_is_an_error_at_the_shape_when_viewed(tmp_path, content, message):
    (tmp_path / "part.stl").write_bytes(content)
    path = _model(tmp_path, 'S1 = { kind = "mesh", mesh = "part.stl" }')
    model = lagrangian.load_model(path)  # found and not too large: read when drawn
    with pytest.raises(ModelError) as info:
        view(model)
    assert message in info.value.message and "part.stl" in info.value.message
    assert info.value.file == str(path) and info.value.line == _line_of(path, "S1 =")


def test_a_mesh_is_placed_and_scaled(tmp_path):
    tri = np.array([[[0, 0, 0], [1000, 0, 0], [0, 1000, 0]]], dtype=float)
    _binary_stl(tmp_path / "part.stl", tri)
    path = _model(tmp_path, 'S1 = { kind = "mesh", mesh = "part.stl", scale = 0.001, from = "O", color = "red" }')
    (part,) = [p for p in view(lagrangian.load_model(path)).scene.parts if p.kind == "mesh"]
    assert part.mesh.vertices.max() == pytest.approx(1.0)  # millimetres to metres
    assert part.position == pytest.approx((0.0, 0.0, 0.5))  # O seen from G1 = −l1/2 z1: +l1/2 on z1
    assert part.color == "#ff0000"


def test_the_command_line_says_file_line_and_fix(tmp_path, capsys):
    path = _model(tmp_path, 'S1 = { kind = "sphere", radius = 1, color = "bluish" }')
    assert main(["view", str(path), "-o", str(tmp_path / "v.html")]) == 2
    err = capsys.readouterr().err
    assert f"{path}:{_line_of(path, 'S1 =')}: error:" in err and "tip:" in err
    assert not (tmp_path / "v.html").exists()


def test_urdf_visuals_become_shapes_of_the_bodies_that_carry_their_links():
    model = lagrangian.load_model(EXAMPLES_DIR / "rrr_arm.urdf")
    got = {(s.on, s.kind): s for s in model.shapes}
    assert set(got) == {("R0", "box"), ("column", "cylinder"), ("upper_arm", "box"), ("forearm", "cylinder"),
                        ("forearm", "sphere")}  # the load, fixed to the forearm, is drawn on it
    assert got["column", "cylinder"].color == "#1f78b5"  # <material name="blue"/>, declared at the top
    # rpy = (0, π/2, 0): the cylinder's z turned onto the forearm's x (columns: the shape's axes in the frame).
    np.testing.assert_allclose(got["forearm", "cylinder"].rotation, [[0, 0, 1], [0, 1, 0], [-1, 0, 0]], atol=1e-12)
    scene = view(model).scene
    (load,) = [p for p in scene.parts if p.kind == "sphere" and p.source == "declared"]
    # The load sits 0.4 m along the forearm from the elbow; the forearm's G is at 0.24 m (merged masses).
    assert load.position == pytest.approx((0.16, 0.0, 0.0))


def test_urdf_mesh_paths_resolve_and_missing_ones_are_noted(tmp_path):
    (tmp_path / "pkg" / "meshes").mkdir(parents=True)
    _binary_stl(tmp_path / "pkg" / "meshes" / "a.stl", np.array([[[0, 0, 0], [1, 0, 0], [0, 1, 0]]], dtype=float))
    urdf = (tmp_path / "pkg" / "urdf")
    urdf.mkdir()
    robot = urdf / "r.urdf"
    robot.write_text("""<robot name="r"><link name="base"/>
  <link name="arm"><visual><geometry><mesh filename="package://pkg/meshes/a.stl"/></geometry></visual>
    <visual><geometry><mesh filename="package://pkg/meshes/missing.stl"/></geometry></visual>
    <inertial><mass value="1"/><inertia ixx="0.1" ixy="0" ixz="0" iyy="0.1" iyz="0" izz="0.1"/></inertial></link>
  <joint name="j" type="continuous"><parent link="base"/><child link="arm"/><axis xyz="0 0 1"/></joint>
</robot>""", encoding="utf-8")
    with pytest.warns(lagrangian.model.urdf.UrdfNote, match="missing.stl.*does not exist.*not drawn"):
        model = lagrangian.load_model(robot)
    (shape,) = model.shapes
    assert shape.kind == "mesh" and Path(shape.mesh) == (tmp_path / "pkg" / "meshes" / "a.stl").resolve()
