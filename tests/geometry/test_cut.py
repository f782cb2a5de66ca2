"""Plane cuts of meshes and the convex pieces of closed ones, against closed-form volumes."""

import numpy as np
import pytest
from polygon_cases import star_polygon
from rotations import about_y

from shapegen.geometry.convex import convex_faces, convex_pieces
from shapegen.geometry.cut import (
    clip_half,
    clip_plane,
    clip_slab,
    convex_decomposition,
    placed_convex_decomposition,
)
from shapegen.geometry.extrude import prism
from shapegen.geometry.mesh import Mesh
from shapegen.geometry.scope_frames import lot_polygon
from shapegen.model.lot import Lot

L_LOT = [(0, 0), (4, 0), (4, -2), (2, -2), (2, -4), (0, -4)]
U_LOT = [(0, 0), (6, 0), (6, -4), (4, -4), (4, -1), (2, -1), (2, -4), (0, -4)]


def _prism(lot, height=3.0):
    _, face = lot_polygon(Lot.polygon(lot))
    return prism(face.vertices, (0, height, 0))


def test_box_slab_is_a_closed_convex_box():
    piece = clip_slab(Mesh.box((4, 2, 2)), 0, 1, 2.5)
    assert piece.is_closed and piece.is_convex()
    assert piece.volume() == pytest.approx(1.5 * 2 * 2)
    low, high = piece.bounds()
    assert np.allclose(low, [1, 0, 0]) and np.allclose(high, [2.5, 2, 2])


@pytest.mark.parametrize(
    "axis, low, high, area",
    # the U (area 18: 6 x 4 less the 2 x 3 notch), local z: 0 the arms' end, 4 the base's side
    [
        (0, 0, 1, 4),
        (0, 0.5, 2.5, 6.5),
        (0, 1, 3.5, 5.5),
        (0, 2, 4, 2),
        (2, 0, 1, 4),
        (2, 0.5, 2.5, 8),
        (2, 1, 3.5, 11),
        (2, 2, 4, 10),
    ],
)
def test_u_prism_slices(axis, low, high, area):
    piece = clip_slab(_prism(U_LOT, 1.0), axis, low, high)
    assert piece.is_closed
    assert piece.volume() == pytest.approx(area)


def test_cut_through_the_arms_leaves_two_closed_parts_and_no_bridge():
    arms = clip_slab(_prism(U_LOT, 1.0), 2, 0, 3)
    assert arms.is_closed and arms.volume() == pytest.approx(12.0)
    # no face spans the gap 2 < x < 4 of the arms
    for k in range(arms.n_faces):
        x = arms.face_points(k)[:, 0]
        assert x.max() <= 2 + 1e-9 or x.min() >= 4 - 1e-9
    assert clip_slab(arms, 0, 2.2, 3.8) is None


def test_open_faces_are_clipped_without_caps():
    square = Mesh.rectangle((4, 0, 2), 1)
    half = clip_half(square, 0, 1, True)
    assert half.n_faces == 1 and not half.is_closed
    assert half.area() == pytest.approx(6.0)


def test_clip_by_a_slanted_plane_halves_a_cube():
    cube = Mesh.box((1, 1, 1))
    normal = np.array([1.0, 1.0, 0.0]) / np.sqrt(2)
    half = clip_plane(cube, normal, float(normal @ [0.5, 0.5, 0.5]), True)
    assert half.is_closed and half.volume() == pytest.approx(0.5)


@pytest.mark.parametrize("lot, count", [(L_LOT, 2), (U_LOT, 3)])
def test_convex_decomposition_of_prisms(lot, count):
    whole = _prism(lot)
    pieces = convex_decomposition(whole)
    assert len(pieces) == count
    assert all(p.is_closed and p.is_convex() for p in pieces)
    assert sum(p.volume() for p in pieces) == pytest.approx(whole.volume())


def test_convexify_faces():
    _, face = lot_polygon(Lot.polygon(U_LOT))
    points, pieces = convex_pieces(face.vertices)
    assert len(pieces) == 3  # a cut from each inner corner along an edge
    assert len(points) == len(face.vertices) + 2  # each meets the outline at a new vertex
    mesh = convex_faces(face)
    assert all(mesh.face(k).is_convex() for k in range(mesh.n_faces))
    assert mesh.area() == pytest.approx(18.0)
    # with maxLength 0.5 every cut is longer (the shortest, 1 m): the face stays whole
    assert convex_faces(face, 0.5).n_faces == 1


def _random_lots(count, seed=1):
    """Simple polygons: corners at sorted angles around the origin, random radii (those that
    cross themselves are skipped)."""
    import shapely

    rng = np.random.default_rng(seed)
    lots = []
    while len(lots) < count:
        points = star_polygon(rng, 1, 5) * [1.0, -1.0]  # counter-clockwise in x, z
        if shapely.LinearRing(points).is_simple and shapely.Polygon(points).area > 0.5:
            lots.append(points.tolist())
    return lots


@pytest.mark.parametrize("lot", _random_lots(20))
def test_slices_of_random_prisms_are_closed_and_add_up(lot):
    whole = _prism(lot, 2.0)
    total = whole.volume()
    assert total == pytest.approx(2.0 * abs(_signed_area(lot)))
    low, high = whole.bounds()
    for axis in (0, 1, 2):
        cuts = np.linspace(low[axis], high[axis], 5)
        pieces = [clip_slab(whole, axis, a, b) for a, b in zip(cuts, cuts[1:], strict=False)]
        pieces = [p for p in pieces if p is not None]
        assert all(p.is_closed for p in pieces)
        assert sum(p.volume() for p in pieces) == pytest.approx(total)
    parts = convex_decomposition(whole)
    assert parts is not None and all(p.is_convex() for p in parts)
    assert sum(p.volume() for p in parts) == pytest.approx(total)


def _signed_area(points):
    x, z = np.asarray(points).T
    return 0.5 * float(np.dot(x, np.roll(z, -1)) - np.dot(z, np.roll(x, -1)))


def test_placed_decomposition_is_the_world_decomposition():
    local = _prism(U_LOT)
    rotation = about_y(30.0)
    origin = np.array([100.0, 5.0, -40.0])
    world = local.transformed(rotation, origin)
    expected = convex_decomposition(world)
    for _ in range(2):  # the second call takes the kept pieces
        placed = placed_convex_decomposition(local, rotation, origin)
        assert len(placed) == len(expected) == 3
        assert all(p.is_closed and p.is_convex() for p in placed)
        assert sorted(p.volume() for p in placed) == pytest.approx(
            sorted(p.volume() for p in expected)
        )
        low = np.min([p.bounds()[0] for p in placed], axis=0)
        assert np.allclose(low, world.bounds()[0])


def test_an_asset_at_another_size_is_cut_once(monkeypatch):
    # a column scaled as a whole (a new diameter on the design page) has the pieces of the
    # first one, scaled: the decomposition is worked out once
    calls = []
    real = convex_decomposition

    def counted(mesh, *args, **kwargs):
        calls.append(mesh)
        return real(mesh, *args, **kwargs)

    monkeypatch.setattr("shapegen.geometry.cut.convex_decomposition", counted)
    monkeypatch.setattr("shapegen.geometry.cut._DECOMPOSED", {})
    shape = _prism(U_LOT, height=2.0)
    for factor, shift in ((1.0, (0, 0, 0)), (2.5, (7, 1, -3)), (0.4, (-2, 0, 5))):
        scaled = Mesh(shape.vertices * factor + shift, shape.faces)
        pieces = placed_convex_decomposition(scaled, np.eye(3), np.zeros(3))
        assert len(pieces) == 3 and all(p.is_closed and p.is_convex() for p in pieces)
        assert sum(p.volume() for p in pieces) == pytest.approx(18 * 2.0 * factor**3)
        low = np.min([p.bounds()[0] for p in pieces], axis=0)
        assert np.allclose(low, scaled.bounds()[0])
    assert len(calls) == 1


def test_asked_not_to_cut_the_answer_is_the_same_before_and_after_a_cut(monkeypatch):
    # a derivation asks only whether a leaf needs a cut: a non-convex prism does, whether or
    # not the statics cut the same shape before; a box never does, and is its own piece
    from shapegen.geometry.cut import NEEDS_CUT

    monkeypatch.setattr("shapegen.geometry.cut._DECOMPOSED", {})
    shape, box = _prism(U_LOT, height=2.0), Mesh.box((1.0, 2.0, 3.0))
    for _ in range(2):  # first with nothing kept, then after the pieces were made
        assert placed_convex_decomposition(shape, np.eye(3), np.zeros(3), cut=False) is NEEDS_CUT
        assert len(placed_convex_decomposition(shape, np.eye(3), np.zeros(3))) == 3
        (whole,) = placed_convex_decomposition(box, np.eye(3), np.zeros(3), cut=False)
        assert whole.volume() == pytest.approx(6.0)


def test_placed_decomposition_of_a_mirrored_scope_faces_out():
    mirror = np.diag([-1.0, 1.0, 1.0])
    pieces = placed_convex_decomposition(_prism(L_LOT), mirror, np.zeros(3))
    assert len(pieces) == 2
    assert all(p.signed_volume() > 0 and p.is_convex() for p in pieces)


def test_clipping_keeps_the_order_of_the_faces_it_does_not_cut():
    box = Mesh.box((4, 2, 2))
    half = clip_half(box, 0, 1, True)
    normals = [tuple(np.round(half.face_normal(k), 9)) for k in range(half.n_faces)]
    # bottom, top, front, right, back, then the cap at x = 1; the left face is gone
    assert normals == [(0, -1, 0), (0, 1, 0), (0, 0, 1), (1, 0, 0), (0, 0, -1), (-1, 0, 0)]
    assert half.is_closed and half.volume() == pytest.approx(3 * 2 * 2)


def _shapes_to_clip():
    """Meshes of a few faces (the Python-float clip) of every kind a split or trim cuts: a
    box, prisms of non-convex lots (closed, capped), their faces (open), a star (bridges)."""
    yield Mesh.box((4.0, 2.0, 3.0))
    for lot in (L_LOT, U_LOT):
        yield _prism(lot)
        _, face = lot_polygon(Lot.polygon(lot))
        yield face
    angles = np.arange(14) * np.pi / 7
    radii = np.where(np.arange(14) % 2 == 0, 3.0, 1.2)
    yield Mesh.polygon(np.column_stack([radii * np.cos(angles), radii * np.sin(angles), 0 * radii]))


@pytest.mark.parametrize("index", range(5))
def test_few_faces_are_clipped_as_the_arrays_clip_them(monkeypatch, index):
    """A mesh of a few faces is clipped in Python floats; the arrays' path (made to take it)
    gives the same faces and the same points, plane by plane, either side, with and without
    a trim's tolerance, at corners and through them."""
    import shapegen.geometry.clip_faces as clip_faces

    mesh = list(_shapes_to_clip())[index]
    low, high = mesh.bounds()
    rng = np.random.default_rng(index)
    planes = [(axis, float(v)) for axis in range(3) for v in mesh.vertices[:, axis]]
    planes += [(int(a), float(rng.uniform(low[a], high[a]))) for a in rng.integers(0, 3, 12)]
    compared = 0
    for axis, value in planes:
        for above in (True, False):
            for tolerance in (None, 1e-6):
                few = clip_half(mesh, axis, value, above, tolerance)
                monkeypatch.setattr(clip_faces, "FEW_FACES", -1)
                arrays = clip_half(mesh, axis, value, above, tolerance)
                monkeypatch.setattr(clip_faces, "FEW_FACES", 16)
                assert (few is None) == (arrays is None)
                if few is None:
                    continue
                assert few.faces == arrays.faces
                assert np.array_equal(few.vertices, arrays.vertices)
                compared += few is not mesh
    assert compared > 10  # some planes cut the mesh
