"""extrude(type, distance) in op_extrude's types (face.normal, vertex.normal, world.up,
world.up.flatTop) and the axes the changelog deprecates (world.x, world.y, world.z, x, y, z),
checked on boxes and rings whose solids follow from their coordinates."""

from __future__ import annotations

import math

import numpy as np
import pytest

from shapegen import parse_grammar
from shapegen.statics.standins import statics_model

#: The reference entries each test shows (tools/cga_coverage.py reads this table).
COVERS = {
    "test_extrusion_types_on_the_lot": ("op:extrude",),
    "test_deprecated_world_axes": ("op:extrude",),
    "test_vertex_normals_keep_a_ring_of_faces_joined": ("op:extrude",),
    "test_a_3d_shape_has_every_face_extruded_along_its_own_normal": ("op:extrude",),
    "test_negative_primitive_dimensions_mirror_it_in_place": ("op:primitive",),
    "test_a_roof_on_a_3d_shape_is_built_on_each_face": ("op:roofPyramid",),
    "test_a_name_that_is_no_template_primitive_is_an_asset_in_cga": ("op:i",),
}


def _model(text: str, lot=(12.0, 8.0)):
    return parse_grammar("@StartRule\n" + text, "extrude.cga").build(lot=lot)


def _bounds(model) -> np.ndarray:
    points = np.vstack([b.vertices for b in model.blocks])
    return np.round(np.array([points.min(axis=0), points.max(axis=0)]), 9)


@pytest.mark.parametrize("kind", ["face.normal", "world.up", "world.up.flatTop", "vertex.normal"])
def test_extrusion_types_on_the_lot(kind):
    # a lot faces up: every type gives the 12 x 3 x 8 box of extrude(3)
    typed, plain = _model(f"Lot --> extrude({kind}, 3) X."), _model("Lot --> extrude(3) X.")
    assert np.allclose(_bounds(typed), _bounds(plain))
    assert math.isclose(sum(b.volume for b in typed.blocks), 288.0)
    assert not typed.metadata["warnings"]


@pytest.mark.parametrize(
    ("face", "kind", "low", "high"),
    [
        # the right side (x = 12) pushed 2 m along world x
        ("right", "world.x", (12, 0, 0), (14, 3, 8)),
        ("right", "x", (12, 0, 0), (14, 3, 8)),
        # the back side (z = 0, facing -z) pushed 2 m along world +z: into the mass
        ("back", "world.z", (0, 0, 0), (12, 3, 2)),
        # the top pushed 2 m up: world.y is world.up
        ("top", "world.y", (0, 3, 0), (12, 5, 8)),
        ("top", "y", (0, 3, 0), (12, 5, 8)),
    ],
)
def test_deprecated_world_axes(face, kind, low, high):
    # cga_changelog 2016.0: "The axes x, y, z, world.x, world.y and world.z are deprecated"
    model = _model(f"Lot --> extrude(3) comp(f) {{ {face} : extrude({kind}, 2) X. }}")
    assert np.allclose(_bounds(model), [low, high])
    assert math.isclose(sum(b.volume for b in model.blocks), np.prod(np.subtract(high, low)))
    (warning,) = model.metadata["warnings"]
    assert warning.startswith("extrude.cga:2:") and "deprecated" in warning


def test_vertex_normals_keep_a_ring_of_faces_joined():
    # the four sides of a 12 x 3 x 8 mass as one shape: at each corner the vertex normal is the
    # mean of two side normals, so the corners move 1 m diagonally and each side 1/sqrt(2) m
    # out; the sides stay joined (no internal faces): a ring (12 + 2a) x (8 + 2a) around
    # 12 x 8, 3 m high
    model = _model("Lot --> extrude(3) comp(f) { side = extrude(vertex.normal, 1) X. }")
    a = 1 / math.sqrt(2)
    volume = sum(b.volume for b in model.blocks) + sum(
        abs(_signed_volume(s.vertices, s.faces)) for s in model.surfaces
    )
    assert math.isclose(volume, 3 * ((12 + 2 * a) * (8 + 2 * a) - 96), rel_tol=1e-9)
    points = np.vstack([b.vertices for b in model.blocks] + [s.vertices for s in model.surfaces])
    assert np.allclose(points.min(axis=0), [-a, 0, -a]) and np.allclose(
        points.max(axis=0), [12 + a, 3, 8 + a]
    )


def _signed_volume(vertices, faces) -> float:
    total = 0.0
    for face in faces:
        p = np.asarray(vertices)[list(face)]
        for k in range(1, len(p) - 1):
            total += float(np.dot(p[0], np.cross(p[k], p[k + 1]))) / 6
    return total


def test_a_3d_shape_has_every_face_extruded_along_its_own_normal():
    # op_extrude: "each face polygon ... is taken and extruded along the face normal": a
    # 12 x 3 x 8 mass extruded by 1 m is six prisms, one on each side (internal faces kept)
    model = statics_model(_model("Lot --> extrude(3) extrude(1) X."))  # prisms cut when judged
    sides = 2 * (12 * 8 + 12 * 3 + 8 * 3)
    assert math.isclose(sum(b.volume for b in model.blocks), sides * 1.0)
    assert np.allclose(_bounds(model), [(-1, -1, -1), (13, 4, 9)])
    assert not model.metadata["warnings"]


def test_a_3d_shape_is_not_extruded_in_a_grammar_file():
    with pytest.raises(Exception, match="already 3D"):
        parse_grammar("@StartRule\nLot --> extrude(3) extrude(1) X.", "r.grammar").build(
            lot=(12.0, 8.0)
        )


@pytest.mark.parametrize(
    ("dimensions", "low_y"), [("-2, 3, 4", 0), ("2, -3, -4", -3), ("-2, -3, -4", -3)]
)
def test_negative_primitive_dimensions_mirror_it_in_place(dimensions, low_y):
    # as s() with negative sizes: the cube of the sizes' magnitudes, where the positive one is
    # in x and z, and below y = 0 for a negative height (CityEngine's runtime, PyPRT 1.12, on
    # this lot: x 5..7, z 2..6; y 0..3, or -3..0)
    model = _model(f"Lot --> primitiveCube({dimensions}) X.")
    assert np.allclose(_bounds(model), [(5, low_y, 2), (7, low_y + 3, 6)])
    assert math.isclose(sum(b.volume for b in model.blocks), 24.0)
    assert any("mirrors the primitive" in w for w in model.metadata["warnings"])
    with pytest.raises(Exception, match="dimensions must be >= 0"):
        parse_grammar(f"@StartRule\nLot --> primitiveCube({dimensions}) X.", "r.grammar").build(
            lot=(12.0, 8.0)
        )


def test_a_roof_on_a_3d_shape_is_built_on_each_face():
    # op_roofPyramid: "a pyramid roof perpendicular to each face of the current shape's
    # geometry": six pyramids 1 m high on the faces of a 12 x 3 x 8 mass
    model = statics_model(_model("Lot --> extrude(3) roofPyramid(byHeight, 1) X."))
    sides = 2 * (12 * 8 + 12 * 3 + 8 * 3)
    assert math.isclose(sum(b.volume for b in model.blocks), sides / 3)
    assert np.allclose(_bounds(model), [(-1, -1, -1), (13, 4, 9)])


def test_a_name_that_is_no_template_primitive_is_an_asset_in_cga():
    # CityEngine has no template primitives: i("builtin.cube") (a typo of builtin:cube) is an
    # asset not found, a box and a warning; a .grammar rule refuses the unknown primitive
    model = _model('Lot --> extrude(3) i("builtin.cube") X.')
    assert math.isclose(model.blocks[0].volume, 288.0)
    assert any("'builtin.cube' not found" in w for w in model.metadata["warnings"])
    with pytest.raises(Exception, match="unknown primitive 'builtin.cube'"):
        parse_grammar('@StartRule\nLot --> extrude(3) i("builtin.cube") X.', "r.grammar")


def test_extrude_zero_of_a_face_that_is_not_convex_is_that_face():
    # PyPRT draws extrude(0) of an L-shaped lot as the lot's face: 6 corners, one face
    lot = [(0, 0), (0, 12), (6, 12), (6, 5), (14, 5), (14, 0)]
    model = _model("Lot --> extrude(0)", lot=lot)
    (face,) = model.surfaces
    assert not model.blocks and face.reason == "a face (no volume)"
    assert len(face.vertices) == 6 and len(face.faces) == 1
    assert np.allclose(face.vertices[:, 1], 0.0)
    corners = face.vertices[list(face.faces[0])][:, [0, 2]]
    doubled = np.sum(
        corners[:, 0] * np.roll(corners[:, 1], -1) - np.roll(corners[:, 0], -1) * corners[:, 1]
    )
    assert abs(doubled) / 2 == pytest.approx(6 * 12 + 8 * 5)
    assert doubled < 0  # counter-clockwise seen from above: it faces up, as the lot
