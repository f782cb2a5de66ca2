"""One OBJ reader for the polygons of assets, lots and PyPRT initial shapes: faces kept whole,
the OBJ index forms read, and a broken file is one line naming the file and the line, the same
from each door."""

from __future__ import annotations

import numpy as np
import pytest

from shapegen.errors import GeometryError, InputFormatError
from shapegen.readers.obj import obj_polygons

# an L-shaped face (not convex) and a triangle, with texture and normal indices, a comment, a
# group and a material line; the triangle's corners counted back from the last vertex
TEXT = """# an L and a triangle
mtllib x.mtl
o L
v 0 0 0
v 4 0 0
v 4 0 1
v 1 0 1
v 1 0 3
v 0 0 3
vt 0 0
vn 0 1 0
usemtl stone
f 1/1/1 2/1/1 3/1/1 4/1/1 5/1/1 6/1/1
v 9 0 9
v 10 0 9
v 10 0 10
f -3 -2//1 -1
"""

BROKEN = [
    ("v 0 0\nv 1 0 0\nv 1 0 1\nf 1 2 3\n", ":1: a vertex needs x y z numbers"),
    ("v 0 0 x\n", ":1: a vertex needs x y z numbers"),
    ("v 0 0 0\nv 1 0 0\nv 1 0 1\nf 1 two 3\n", ":4: bad face corner 'two'"),
    ("v 0 0 0\nf 1 2 3\n", ":2: the face names vertex 2, which is not defined"),
    ("v 0 0 0\nv 1 0 0\nf 1 2 -3\n", ":3: the face names vertex -3, which is not defined"),
    ("v 0 0 0\nv 1 0 0\nv 1 0 1\nf 1 2 0\n", ":4: the face names vertex 0, which is not defined"),
]


def test_faces_are_kept_whole_in_every_index_form():
    vertices, faces = obj_polygons(TEXT, "x.obj")
    assert vertices.shape == (9, 3)
    assert faces == [[0, 1, 2, 3, 4, 5], [6, 7, 8]]  # six corners: not fanned into triangles
    assert np.array_equal(vertices[faces[1]][:, [0, 2]], [[9, 9], [10, 9], [10, 10]])


@pytest.mark.parametrize(("text", "line"), BROKEN)
def test_a_broken_file_is_one_line_naming_its_place(text, line):
    with pytest.raises(InputFormatError) as caught:
        obj_polygons(text, "x.obj")
    assert str(caught.value) == "x.obj" + line


@pytest.mark.parametrize(("text", "line"), BROKEN)
def test_each_door_gives_the_readers_line(tmp_path, text, line):
    import shapegen.prt as pyprt
    from shapegen.engine.project.asset_files import load_asset
    from shapegen.prt.initial_shapes import footprint
    from shapegen.readers.lot_sources import lot_from_obj

    path = tmp_path / "x.obj"
    path.write_text(text)
    with pytest.raises(GeometryError) as asset:
        load_asset(path)
    assert str(asset.value) == f"asset {path}{line}"
    with pytest.raises(InputFormatError) as lot:
        lot_from_obj(path)
    assert str(lot.value) == f"--lot {path}{line}"
    with pytest.raises(InputFormatError) as shape:
        footprint(pyprt.InitialShape(str(path)))
    assert str(shape.value) == f"{path}{line}"


def test_the_lot_is_the_first_face_and_the_asset_every_face(tmp_path):
    from shapegen.engine.project.asset_files import load_asset
    from shapegen.readers.lot_sources import lot_from_obj

    path = tmp_path / "x.obj"
    path.write_text(TEXT)
    lot = lot_from_obj(path)
    assert len(lot.corners) == 6  # the L, whole
    assert load_asset(path).n_faces == 2


def test_a_line_ending_in_a_backslash_goes_on_on_the_next():
    # the OBJ format's continuation line, as envelope2002's glass_door.obj writes long faces
    text = "v 0 0 0\nv 1 0 0 \\\n\nv 1 0 1\nv 0 0 1\nf 1 2 \\\n 3 \\\n 4\nf 1 2 x\n"
    with pytest.raises(InputFormatError, match=r"^x.obj:9: bad face corner 'x'$"):
        obj_polygons(text, "x.obj")
    vertices, faces = obj_polygons(text.rsplit("f 1 2 x", 1)[0], "x.obj")
    assert len(vertices) == 4 and faces == [[0, 1, 2, 3]]


def test_texture_coordinates_materials_and_libraries_are_read_per_face_corner():
    from shapegen.readers.obj import obj_surface

    text = (
        "mtllib a.mtl b.mtl\nv 0 0 0\nv 1 0 0\nv 1 0 1\nv 0 0 1\n"
        "vt 0 0\nvt 1 0 0\nvt 1 1\nvt 0 1\n"
        "f 1 2 3\n"  # before any usemtl, without coordinates
        "usemtl red brick\nf 1/1/1 2/2/1 3/-2/1 4/-1/1\n"
        "f 1//1 3//1 4//1\n"  # normals only
        "f 1/1 2/2 3\n"  # a corner without: the face has none
    )
    surface = obj_surface(text, "a.obj")
    assert surface.libraries == ["a.mtl", "b.mtl"]
    assert surface.face_materials == ["", "red brick", "red brick", "red brick"]
    assert surface.face_uvs[0] is None and surface.face_uvs[2] is None
    assert surface.face_uvs[3] is None
    assert surface.face_uvs[1].tolist() == [[0, 0], [1, 0], [1, 1], [0, 1]]
    assert obj_polygons(text, "a.obj")[1] == surface.faces


@pytest.mark.parametrize(
    ("text", "words"),
    [
        ("v 0 0 0\nv 1 0 0\nv 0 0 1\nvt 0 0\nf 1/1 2/2 3/1\n", "a.obj:5: the face names texture"),
        ("vt 0 x\n", "a.obj:1: a texture coordinate needs u v numbers"),
    ],
)
def test_a_broken_texture_coordinate_is_one_line_naming_the_place(text, words):
    from shapegen.readers.obj import obj_surface

    with pytest.raises(InputFormatError, match=words):
        obj_surface(text, "a.obj")
    obj_polygons(text, "a.obj")  # the positions alone do not read them
