"""Faces with holes (CityEngine's): a mesh's holes, the prism a holed face extrudes to, and the
hole-free polygons a leaf is made of; every figure against its closed form."""

from __future__ import annotations

import numpy as np
import pytest

from shapegen.geometry.convex import hole_free
from shapegen.geometry.cut import convex_decomposition
from shapegen.geometry.extrude import extrude_faces
from shapegen.geometry.mesh import Mesh

# a 12 x 8 m face (y up, counter-clockwise seen from above) with a 4 x 2 m hole wound the other
# way round, and PyPRT's test face: a 10 x 10 m square with a right triangle of legs 6 m
COURTYARD = Mesh(
    [[0, 0, 8], [12, 0, 8], [12, 0, 0], [0, 0, 0], [4, 0, 3], [8, 0, 3], [8, 0, 5], [4, 0, 5]],
    [(0, 1, 2, 3)],
    [[(4, 5, 6, 7)]],
)
TRIANGLE = Mesh(
    [[0, 0, 0], [0, 0, 10], [10, 0, 10], [10, 0, 0], [2, 0, 2], [8, 0, 8], [2, 0, 8]],
    [(0, 1, 2, 3)],
    [[(4, 5, 6)]],
)
# (face, its area, its outer and inner perimeters, corners outside and inside)
FACES = [
    (COURTYARD, 96.0 - 8.0, 40.0, 12.0, 4, 4),
    (TRIANGLE, 100.0 - 18.0, 40.0, 12.0 + 6.0 * np.sqrt(2.0), 4, 3),
]


@pytest.mark.parametrize("face, area, outer, inner, n_out, n_in", FACES)
def test_a_hole_takes_its_area_off_its_face_and_is_no_face(face, area, outer, inner, n_out, n_in):
    assert face.area() == pytest.approx(area)
    assert (face.n_faces, face.n_holes, face.n_vertices) == (1, 1, n_out + n_in)
    assert face.face_normal(0) @ [0, 1, 0] == pytest.approx(1.0)
    assert not face.is_convex()
    mirrored = face.transformed(np.diag([1.0, 1.0, -1.0]))  # a mirror turns faces and holes
    assert mirrored.area() == pytest.approx(area) and mirrored.face_normal(0)[1] > 0
    whole = face.without_holes()  # the outer ring alone: 12 x 8 and 10 x 10 m
    assert (whole.n_holes, whole.n_vertices) == (0, n_out)
    assert whole.area() == pytest.approx({4: 96.0, 3: 100.0}[n_in])


@pytest.mark.parametrize("face, area, outer, inner, n_out, n_in", FACES)
@pytest.mark.parametrize("height", [10.0, -4.0])
def test_a_holed_face_extrudes_to_a_solid_with_inner_walls(
    face, area, outer, inner, n_out, n_in, height
):
    solid = extrude_faces(face, height)
    h = abs(height)
    assert solid.is_closed
    assert solid.volume() == pytest.approx(area * h)
    assert solid.signed_volume() > 0  # it faces out, extruded up or down
    assert solid.area() == pytest.approx(2 * area + (outer + inner) * h)
    # bottom and top keep the hole; a wall per outer edge, then one per hole edge
    assert (solid.n_vertices, solid.n_faces, solid.n_holes) == (
        2 * (n_out + n_in), 2 + n_out + n_in, 2)  # fmt: skip
    assert [len(rings) for rings in solid.holes] == [1, 1] + [0] * (n_out + n_in)
    walls = solid.face_areas()[2 + n_out :]
    assert walls.sum() == pytest.approx(inner * h)


def test_deleting_the_holes_keeps_the_vertices_the_walls_use():
    solid = extrude_faces(COURTYARD, 10.0).without_holes()
    assert (solid.n_vertices, solid.n_faces, solid.n_holes) == (16, 10, 0)
    assert solid.area() == pytest.approx(2 * 96.0 + 40.0 * 10 + 12.0 * 10)
    face = COURTYARD.without_holes()
    assert (face.n_vertices, face.area()) == (4, pytest.approx(96.0))


@pytest.mark.parametrize("face, area, outer, inner, n_out, n_in", FACES)
def test_a_leaf_s_hole_free_polygons_cover_the_same_surface(face, area, outer, inner, n_out, n_in):
    flat = hole_free(face)
    assert flat.n_holes == 0 and flat.area() == pytest.approx(area)
    assert all(flat.face(k).is_convex() for k in range(flat.n_faces))
    solid = hole_free(extrude_faces(face, 10.0))
    assert solid.is_closed and solid.volume() == pytest.approx(area * 10.0)


@pytest.mark.parametrize("face, area, outer, inner, n_out, n_in", FACES)
def test_the_convex_cut_of_a_holed_solid_fills_it(face, area, outer, inner, n_out, n_in):
    pieces = convex_decomposition(hole_free(extrude_faces(face, 10.0)))
    assert pieces is not None and len(pieces) >= 3  # no convex piece holds a hole
    assert all(piece.is_closed and piece.is_convex(1e-9) for piece in pieces)
    assert sum(piece.volume() for piece in pieces) == pytest.approx(area * 10.0)


def test_cleaning_keeps_a_hole_and_drops_its_repeated_corners():
    repeated = Mesh(
        np.vstack([COURTYARD.vertices, COURTYARD.vertices[4:5]]),
        COURTYARD.faces,
        [[(4, 8, 5, 6, 7)]],
    )
    cleaned = repeated.cleaned()
    assert (cleaned.n_vertices, cleaned.n_holes) == (8, 1)
    assert cleaned.area() == pytest.approx(88.0)


def test_a_hole_must_index_the_vertices():
    with pytest.raises(ValueError, match="does not index"):
        Mesh(COURTYARD.vertices, COURTYARD.faces, [[(4, 5, 99)]])
    with pytest.raises(ValueError, match="lists of holes for 1 faces"):
        Mesh(COURTYARD.vertices, COURTYARD.faces, [[(4, 5, 6)], []])
