"""Mesh files read as data: STL (binary, ASCII), OBJ, COLLADA — triangles where the file puts them, bad files refused."""

from __future__ import annotations

import struct

import numpy as np
import pytest

from lagrangian.errors import ModelError
from lagrangian.model import Location
from lagrangian.view3d._mesh import read_mesh

WHERE = Location("robot.toml", 7)


def _triangles(mesh) -> set[tuple[tuple[float, ...], ...]]:
    """Each triangle as its three corners, rotated to start at the smallest (the order of a file is free)."""
    out = set()
    for tri in mesh.vertices[mesh.triangles].astype(float).round(6):
        corners = [tuple(c) for c in tri]
        k = corners.index(min(corners))
        out.add(tuple(corners[k:] + corners[:k]))
    return out


SQUARE = {((0.0, 0.0, 0.0), (1.0, 0.0, 0.0), (1.0, 1.0, 0.0)), ((0.0, 0.0, 0.0), (1.0, 1.0, 0.0), (0.0, 1.0, 0.0))}


def test_binary_and_ascii_stl(tmp_path):
    corners = np.array([[[0, 0, 0], [1, 0, 0], [1, 1, 0]], [[0, 0, 0], [1, 1, 0], [0, 1, 0]]], dtype=np.float32)
    binary = tmp_path / "b.stl"
    binary.write_bytes(b"solid looks like text" + b"\0" * 59 + struct.pack("<I", 2)
                       + b"".join(struct.pack("<12fH", 0, 0, 1, *t.reshape(-1), 0) for t in corners))
    ascii_ = tmp_path / "a.stl"
    ascii_.write_text("solid s\n" + "".join("facet normal 0 0 1\nouter loop\n" + "".join(
        f"vertex {x} {y} {z}\n" for x, y, z in t) + "endloop\nendfacet\n" for t in corners) + "endsolid s\n")
    for path in (binary, ascii_):
        mesh = read_mesh(path, WHERE, "the mesh")
        assert _triangles(mesh) == SQUARE
        assert len(mesh.vertices) == 4  # shared corners once


def test_obj_polygons_are_fans_and_negative_indices_count_back(tmp_path):
    path = tmp_path / "q.obj"
    path.write_text("# a square\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvn 0 0 1\nf 1//1 2//1 3//1 4//1\n"
                    "v 0 0 2\nf -1 1 2\n")
    mesh = read_mesh(path, WHERE, "the mesh")
    assert _triangles(mesh) == SQUARE | {((0.0, 0.0, 0.0), (1.0, 0.0, 0.0), (0.0, 0.0, 2.0))}


DAE = """<?xml version="1.0"?>
<COLLADA xmlns="http://www.collada.org/2005/11/COLLADASchema" version="1.4.1">
  <asset><unit meter="0.01"/><up_axis>Y_UP</up_axis></asset>
  <library_effects><effect id="e"><profile_COMMON><technique sid="c"><phong>
    <diffuse><color>1 0 0 1</color></diffuse></phong></technique></profile_COMMON></effect></library_effects>
  <library_materials><material id="red"><instance_effect url="#e"/></material></library_materials>
  <library_geometries><geometry id="g"><mesh>
    <source id="p"><float_array id="pa" count="12">0 0 0 100 0 0 100 100 0 0 100 0</float_array>
      <technique_common><accessor source="#pa" count="4" stride="3"/></technique_common></source>
    <vertices id="v"><input semantic="POSITION" source="#p"/></vertices>
    <polylist count="1" material="m"><input semantic="VERTEX" source="#v" offset="0"/>
      <vcount>4</vcount><p>0 1 2 3</p></polylist>
  </mesh></geometry></library_geometries>
  <library_visual_scenes><visual_scene id="s"><node><translate>0 0 100</translate>
    <instance_geometry url="#g"><bind_material><technique_common>
      <instance_material symbol="m" target="#red"/></technique_common></bind_material></instance_geometry>
  </node></visual_scene></library_visual_scenes>
</COLLADA>"""


def test_collada_in_metres_z_up_placed_by_its_node(tmp_path):
    path = tmp_path / "part.dae"
    path.write_text(DAE)
    mesh = read_mesh(path, WHERE, "the mesh")
    # Centimetres → metres; the node moves it 1 m along the file's z; y up becomes z up: (x, y, z) ↦ (x, −z, y).
    # The square x, y ∈ [0, 1] at z = 1 m of the file is the square x, z ∈ [0, 1] at y = −1 m.
    assert _triangles(mesh) == {((0.0, -1.0, 0.0), (1.0, -1.0, 0.0), (1.0, -1.0, 1.0)),
                                ((0.0, -1.0, 0.0), (1.0, -1.0, 1.0), (0.0, -1.0, 1.0))}
    assert mesh.groups == ((0, 2, "#ff0000"),)


@pytest.mark.parametrize("name, content, message", [
    ("e.dae", '<?xml version="1.0"?><!DOCTYPE c [<!ENTITY a "aaaa">]><COLLADA>&a;</COLLADA>', "entity"),
    ("t.dae", "<COLLADA><library_geometries>", "not well formed"),
    ("x.dae", "<robot/>", "not <COLLADA>"),
    ("f.obj", "v 0 0 0\nv 1 0 0\nf 1 2 9\n", "vertex 9, which is not defined before it (line 3 of the mesh)"),
    ("n.obj", "v 0 0 nan\n", "not a finite number (line 1 of the mesh)"),
    ("e.obj", "# nothing\n", "holds no triangle"),
])
def test_bad_meshes_are_refused_with_the_shape_that_names_them(tmp_path, name, content, message):
    path = tmp_path / name
    path.write_text(content)
    with pytest.raises(ModelError) as info:
        read_mesh(path, WHERE, "the mesh of `S`")
    assert message in info.value.message and "the mesh of `S`" in info.value.message
    assert (info.value.file, info.value.line) == ("robot.toml", 7)
