"""Mesh measures against closed forms."""

import math

import numpy as np
import pytest

from shapegen.geometry.mesh import BOX_FACES, Mesh


def _prism(points, height):
    """A prism over a CCW (seen from +y) polygon in the x-z plane, hand-built."""
    n = len(points)
    bottom = [(x, 0.0, z) for x, z in points]
    top = [(x, height, z) for x, z in points]
    faces = [tuple(reversed(range(n))), tuple(range(n, 2 * n))]
    faces += [(k, (k + 1) % n, n + (k + 1) % n, n + k) for k in range(n)]
    return Mesh(bottom + top, faces)


@pytest.mark.parametrize("size", [(1, 1, 1), (2, 3, 4), (0.1, 7.5, 0.3)])
def test_box_measures(size):
    box = Mesh.box(size)
    sx, sy, sz = size
    assert box.volume() == pytest.approx(sx * sy * sz)
    assert box.area() == pytest.approx(2 * (sx * sy + sy * sz + sx * sz))
    assert box.is_closed and box.is_convex() and box.is_planar() is False
    assert (box.n_vertices, box.n_faces, box.n_edges) == (8, 6, 12)
    assert box.is_rectangular()
    low, high = box.bounds()
    assert low.tolist() == [0, 0, 0] and high.tolist() == [sx, sy, sz]


def test_box_face_order_is_bottom_top_then_sides_from_the_first_edge():
    normals = Mesh.box((2, 3, 4)).face_normals()
    expected = [(0, -1, 0), (0, 1, 0), (0, 0, 1), (1, 0, 0), (0, 0, -1), (-1, 0, 0)]
    assert np.allclose(normals, expected)
    assert len(BOX_FACES) == 6


def test_l_shaped_prism_is_closed_not_convex():
    # An L of area 3 (three unit squares), counter-clockwise seen from +y (x right, z toward -).
    ell = [(0, 0), (0, -2), (1, -2), (1, -1), (2, -1), (2, 0)]
    ell = list(reversed(ell))
    prism = _prism(ell, 2.0)
    assert prism.is_closed
    assert prism.volume() == pytest.approx(6.0)
    assert not prism.is_convex()
    assert not prism.is_rectangular()
    assert prism.face_area(0) == pytest.approx(3.0)
    assert prism.n_edges == 18


def test_open_meshes():
    square = Mesh.rectangle((2, 0, 3), 1)
    assert not square.is_closed and square.volume() == 0.0
    assert square.area() == pytest.approx(6.0)
    assert square.is_planar() and square.is_convex() and square.is_rectangular()
    assert np.allclose(square.face_normal(0), (0, 1, 0))
    # its first edge runs along +x
    first = square.vertices[1] - square.vertices[0]
    assert first[0] > 0 and first[1] == first[2] == 0
    bent = Mesh([(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 1)], [(0, 1, 2, 3)])
    assert not bent.is_planar(0.1) and bent.is_planar(1.0)


def test_concave_polygon_face():
    arrow = Mesh.polygon([(0, 0, 0), (2, 0, 0), (1, 0.5, 0), (2, 1, 0), (0, 1, 0)])
    assert not arrow.is_convex()
    assert arrow.area() == pytest.approx(2.0 - 0.5)


def test_transform_and_mirror_keep_faces_outward():
    box = Mesh.box((1, 2, 3))
    turn = np.array([[0, 0, 1], [0, 1, 0], [-1, 0, 0]], float)
    moved = box.transformed(turn, (5, 0, 0))
    assert moved.volume() == pytest.approx(6.0) and moved.is_convex()
    mirrored = box.scaled((-1, 1, 1))
    assert mirrored.is_convex() and mirrored.volume() == pytest.approx(6.0)
    normals = mirrored.face_normals()
    centres = np.array([mirrored.face_points(k).mean(axis=0) for k in range(6)])
    centre = mirrored.vertices.mean(axis=0)
    assert np.all(np.einsum("ij,ij->i", normals, centres - centre) > 0)
    assert np.allclose(box.reversed().face_normals(), -box.face_normals())


def test_regular_polygon_area_closed_form():
    n, radius = 12, 2.0
    points = [
        (radius * math.cos(2 * math.pi * k / n), 0.0, -radius * math.sin(2 * math.pi * k / n))
        for k in range(n)
    ]
    polygon = Mesh.polygon(points)
    assert polygon.area() == pytest.approx(0.5 * n * radius**2 * math.sin(2 * math.pi / n))
    assert np.allclose(polygon.face_normal(0), (0, 1, 0))


def test_cleaned_merges_duplicates_and_drops_slivers():
    mesh = Mesh(
        [(0, 0, 0), (1, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0), (5, 5, 5)],
        [(0, 1, 2, 3, 4), (1, 2, 2)],
    )
    clean = mesh.cleaned()
    assert clean.n_faces == 1 and clean.n_vertices == 4


def test_bad_face_index_refused():
    with pytest.raises(ValueError, match="does not index"):
        Mesh([(0, 0, 0)], [(0, 1, 2)])


def test_signed_volume_of_a_turned_box_is_negative():
    box = Mesh.box((1, 2, 3))
    assert box.signed_volume() == pytest.approx(6.0)
    assert box.reversed().signed_volume() == pytest.approx(-6.0)
    assert box.reversed().volume() == pytest.approx(6.0)


@pytest.mark.parametrize(
    "faces, closed",
    [
        (BOX_FACES, True),
        (BOX_FACES[:-1], False),  # a hole
        (BOX_FACES + (BOX_FACES[0],), False),  # a face twice: an edge used twice one way
        (tuple(f[::-1] for f in BOX_FACES[:1]) + BOX_FACES[1:], False),  # one face turned
    ],
)
def test_closedness_needs_each_edge_once_each_way(faces, closed):
    assert Mesh(Mesh.box((1, 2, 3)).vertices, faces).is_closed is closed


def test_areas_and_volume_of_a_box_far_from_the_origin():
    box = Mesh.box((2.0, 3.0, 4.0)).transformed(None, (1e6, -2e5, 3e6))
    assert box.face_areas().tolist() == pytest.approx([8, 8, 6, 12, 6, 12])
    assert box.volume() == pytest.approx(24.0, rel=1e-9)


def test_one_face_normal_alone_is_the_whole_meshs_to_the_bit():
    """lone_face_normal sums one face in Python floats: the same bits as the arrays' normals
    of every face, for faces far from the origin, slanted, degenerate, of many corners."""
    rng = np.random.default_rng(7)
    faces, points = [], []
    for count in [3, 4, 5, 6, 7, 8] * 20 + [9, 13, 40]:
        angles = np.sort(rng.uniform(0, 2 * np.pi, count))
        ring = np.column_stack([np.cos(angles), np.sin(angles), rng.normal(0, 0.01, count)])
        ring = ring * rng.uniform(0.5, 30) + rng.uniform(-5e4, 5e4, 3)
        faces.append(tuple(range(len(points), len(points) + count)))
        points.extend(ring.tolist())
    faces.append((0, 0, 1))  # no area: a zero normal
    mesh = Mesh(points, faces)
    alone = [Mesh(points, faces).lone_face_normal(k) for k in range(len(faces))]
    assert np.array_equal(np.array(alone), mesh.face_normals())
    assert not np.any(alone[-1])


def test_sheets_stay_with_the_faces_they_name():
    # a box whose bottom is a sheet apart (a roof's, as comp(e) reads it): moved, turned,
    # scaled, mirrored or turned inside out, each face keeps its sheet; a new mesh of some
    # of its faces starts joined
    box = Mesh.box((2, 3, 4))
    parts = ("bottom",) + ("body",) * 5
    apart = Mesh(box.vertices, box.faces, sheets=parts)
    turn = np.array([[0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]])
    copies = [
        apart.transformed(turn, (1, 2, 3)),
        apart.transformed(np.diag([-1.0, 1.0, 1.0])),
        apart.scaled((2, 2, 2)),
        apart.scaled((-1, 1, 1)),
        apart.moved_to(apart.vertices + 1),
        apart.reversed(),
    ]
    assert all(copy.sheets == parts for copy in copies)
    assert box.sheets == () and apart.subset([0, 1]).sheets == ()
    with pytest.raises(ValueError, match="2 sheets given for 6 faces"):
        Mesh(box.vertices, box.faces, sheets=("a", "b"))
