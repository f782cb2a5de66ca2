"""Offsets, setbacks and inner rectangles against closed-form areas, and the straight skeleton
against hand-built skeletons of rectangles and L-shapes."""

import math

import numpy as np
import pytest
from polygon_cases import star_polygon

from shapegen.errors import GeometryError
from shapegen.geometry import polygon2d as P
from shapegen.geometry.inner_rectangle import inner_rectangle
from shapegen.geometry.setback_pieces import setback_to_area
from shapegen.geometry.skeleton import straight_skeleton

RECT = [(0, 0), (12, 0), (12, 8), (0, 8)]
L_SHAPE = [(0, 0), (10, 0), (10, 4), (6, 4), (6, 10), (0, 10)]  # arms 4 and 6 wide, area 76


def _same_polygon(a, b):
    a, b = np.asarray(a, float), np.asarray(b, float)
    assert len(a) == len(b)
    shift = int(np.argmin(np.linalg.norm(b - a[0], axis=1)))
    np.testing.assert_allclose(np.roll(b, -shift, axis=0), a, atol=1e-9)


def test_skeleton_of_a_rectangle_has_a_ridge_of_length_w_minus_d():
    s = straight_skeleton(RECT)
    _same_polygon(s.face_points(0), [(0, 0), (12, 0), (8, 4), (4, 4)])
    _same_polygon(s.face_points(1), [(12, 0), (12, 8), (8, 4)])
    assert s.times.max() == pytest.approx(4.0)


def test_skeleton_of_an_l_shape():
    s = straight_skeleton(L_SHAPE)
    # The reflex vertex (6, 4) runs to (4, 2), where the 4 m arm ends; the 6 m arm's ridge
    # runs from (3, 3) to (3, 7).
    _same_polygon(s.face_points(3), [(6, 4), (6, 10), (3, 7), (3, 3), (4, 2)])
    _same_polygon(s.face_points(0), [(0, 0), (10, 0), (8, 2), (4, 2), (3, 3)])
    areas = [P.signed_area(s.face_points(k)) for k in range(6)]
    assert sum(areas) == pytest.approx(76.0)
    assert min(areas) > 0


@pytest.mark.parametrize(
    "polygon", [RECT, L_SHAPE, [(0, 0), (4, 0), (4, 4), (0, 4)], [(0, 0), (9, 0), (7, 5), (1, 6)]]
)
def test_skeleton_faces_tile_the_polygon_and_times_are_distances(polygon):
    s = straight_skeleton(polygon)
    p = np.asarray(polygon, float)
    assert sum(P.signed_area(s.face_points(k)) for k in range(len(p))) == pytest.approx(
        P.signed_area(p)
    )
    normals = -P.edge_normals(p)
    for k in range(len(p)):
        for x, y, t in s.face_xyt(k):  # a face's points are as far from its edge as their time
            assert (np.array([x, y]) - p[k]) @ normals[k] == pytest.approx(t, abs=1e-9)


@pytest.mark.parametrize("d", [0.5, 1.0, 3.0])
def test_inward_offset_of_a_rectangle(d):
    o = P.offset(RECT, -d)
    assert len(o.inside) == 1
    assert P.signed_area(o.inside[0]) == pytest.approx((12 - 2 * d) * (8 - 2 * d))
    assert [P.signed_area(b) for b in o.border] == pytest.approx(
        [d * (12 - d), d * (8 - d), d * (12 - d), d * (8 - d)]
    )
    _same_polygon(o.border[0][:2], [(0, 0), (12, 0)])  # each border face starts with its edge


def test_offset_past_the_middle_leaves_only_border_faces():
    o = P.offset(RECT, -5)
    assert o.inside == ()
    assert sum(P.signed_area(b) for b in o.border) == pytest.approx(96)


def test_outward_offset_border_faces_are_clockwise_and_sum_to_the_face():
    o = P.offset(L_SHAPE, 1)
    grown = P.signed_area(o.inside[0])
    # A + P d + (convex - reflex corners) d^2: perimeter 40, 5 convex corners, 1 reflex
    assert grown == pytest.approx(76 + 40 * 1 + (5 - 1) * 1)
    assert all(P.signed_area(b) < 0 for b in o.border)
    assert grown + sum(P.signed_area(b) for b in o.border) == pytest.approx(76)


def test_offset_of_an_l_shape_inward_follows_the_skeleton():
    o = P.offset(L_SHAPE, -1)
    assert P.signed_area(o.inside[0]) == pytest.approx(76 - 40 * 1 + (5 - 1) * 1)
    assert P.signed_area(o.inside[0]) + sum(P.signed_area(b) for b in o.border) == pytest.approx(76)


def test_setback_front_and_left_of_a_rectangle():
    s = P.setback(RECT, [2, 0, 0, 3])
    strips = dict(s.strips)
    assert sorted(strips) == [0, 3]
    assert P.signed_area(strips[0]) == pytest.approx(12 * 2 - 0.5 * 3 * 2)
    assert P.signed_area(strips[3]) == pytest.approx(8 * 3 - 0.5 * 3 * 2)
    assert P.signed_area(s.remainder[0]) == pytest.approx(9 * 6)


def test_a_setback_that_leaves_nothing_keeps_the_face_whole():
    # PyPRT (envelope2002): a 3 m setback of all edges of a 4.8 x 4 m roof is the whole roof
    roof = np.array([(0, 0), (4.8, 0), (4.8, 4), (0, 4)], float)
    s = P.setback(roof, [3, 3, 3, 3])
    assert s.remainder == ()
    ((k, whole),) = s.strips
    assert k == 0 and np.allclose(whole, roof)
    s = P.setback(roof, [0, 5, 0, 0])  # the first set-back edge owns it
    assert [k for k, _ in s.strips] == [1]
    s = P.setback(roof, [1.9, 1.9, 1.9, 1.9])  # something left: strips as before
    assert len(s.strips) == 4 and P.signed_area(s.remainder[0]) == pytest.approx(1.0 * 0.2)


def test_shape_l_is_the_union_of_its_strips():
    s = P.setback(RECT, [2, 0, 0, 3])
    (shape,) = P.union([poly for _, poly in s.strips])
    assert P.signed_area(shape) == pytest.approx(96 - 54)


def test_setback_to_area_of_a_rectangle():
    result, d = setback_to_area(RECT, 24.0, [True] * 4)
    # (12 - 2d)(8 - 2d) = 24
    expected = (10 - math.sqrt(100 - 4 * 18)) / 2  # d² - 10 d + 18 = 0
    assert d == pytest.approx([expected] * 4, rel=1e-9)
    assert P.signed_area(result.remainder[0]) == pytest.approx(24.0)


def test_inner_rectangle_of_a_face_that_crosses_itself():
    """A bow tie (a face of a generated program, its last edge crossing its first at (2, -5.77))
    gives a rectangle inside it and the remainder; GEOS refused to cut it as it is."""
    bow_tie = [(0.0, -5.7735026918962573), (12.0, -5.7735026918962573), (12.0, 0.0),
               (0.0, -6.928203230275509)]  # fmt: skip
    rectangle, rest = inner_rectangle(bow_tie, "scope")
    assert rectangle is not None and rest
    width, height = np.ptp(rectangle, axis=0)
    # the right triangle (2, -5.77) (12, -5.77) (12, 0) of the bow tie: its largest
    # axis-aligned rectangle has half of each leg, a quarter of the legs' product
    assert width * height == pytest.approx(10 * 5.7735026918962573 / 4, rel=0.01)
    assert rectangle[:, 0].min() >= 2.0 and rectangle[:, 1].min() >= -5.7735026918962573 - 1e-9


def test_inner_rectangle_of_an_l_and_a_triangle():
    rectangle, rest = inner_rectangle(L_SHAPE)
    assert P.signed_area(rectangle) == pytest.approx(60)  # the 6 m arm: 6 x 10
    assert sum(P.signed_area(r) for r in rest) == pytest.approx(16)
    rectangle, _ = inner_rectangle([(0, 0), (10, 0), (5, 8)], "edge")
    assert P.signed_area(rectangle) == pytest.approx(20, rel=0.01)  # half the triangle


@pytest.mark.parametrize(
    "call, message",
    [
        (lambda: P.offset([(0, 0), (1, 0)], -1), "at least 3"),
        (lambda: P.offset([(0, 0), (0, 1), (1, 0)], -1), "counter-clockwise"),
        (lambda: P.setback(RECT, [1, 2]), "one distance per edge"),
        (lambda: P.setback(RECT, [1, -1, 0, 0]), ">= 0"),
        (lambda: setback_to_area(RECT, 200, [True] * 4), "less than"),
        (lambda: inner_rectangle(RECT, "diagonal"), "scope or edge"),
    ],
)
def test_bad_input_is_one_clear_error(call, message):
    with pytest.raises(GeometryError, match=message):
        call()


def test_collinear_edges_set_back_by_different_distances_make_a_step():
    s = P.setback([(0, 0), (6, 0), (12, 0), (12, 8), (0, 8)], [1, 3, 0, 0, 0])
    strips = dict(s.strips)
    assert P.signed_area(strips[0]) == pytest.approx(6 * 1)
    assert P.signed_area(strips[1]) == pytest.approx(6 * 3)
    assert P.signed_area(s.remainder[0]) == pytest.approx(96 - 6 - 18)


def _random_polygons(count, seed):
    """Star-shaped simple polygons, every third snapped to a 1 m grid (collinear edges, equal
    lengths, simultaneous events)."""
    import shapely

    rng = np.random.default_rng(seed)
    out = []
    while len(out) < count:
        points = star_polygon(rng, 3, 10)
        if len(out) % 3 == 0:
            points = np.round(points)
        points = P.counter_clockwise(points)
        if len(points) >= 3 and shapely.Polygon(points).is_valid:
            out.append(
                (points, rng.uniform(0, 2, len(points)) * (rng.uniform(size=len(points)) < 0.6))
            )
    return out


@pytest.mark.parametrize("polygon, distances", _random_polygons(40, seed=7))
def test_random_polygons_skeleton_offset_and_setback_tile_the_face(polygon, distances):
    area = P.signed_area(polygon)
    s = straight_skeleton(polygon)
    assert sum(P.signed_area(s.face_points(k)) for k in range(len(polygon))) == pytest.approx(area)
    o = P.offset(polygon, -1.0)
    inside = sum(map(P.signed_area, o.inside))
    assert inside + sum(map(P.signed_area, o.border)) == pytest.approx(area)
    b = P.setback(polygon, distances)
    kept = sum(P.signed_area(r) for r in b.remainder)
    assert kept + sum(P.signed_area(p) for _, p in b.strips) == pytest.approx(area)


# innerRectangle(edge) areas PyPRT reports ("Footprint Area (m2)") for the corpus package
# caseStudy_Tensorflow_simpleRuleDataset (frontSetbackRel = 0) on these lots, given as PyPRT's
# (x, z) corners counter-clockwise seen from above.
PYPRT_INNER_RECTANGLES = [
    ([(0, 0), (0, 8), (12, 8), (12, 0)], 96.0),
    ([(0, 0), (2, 9), (11, 9), (14, 0)], 80.99730002),
    ([(0, 0), (-2, 6), (5, 11), (13, 7), (12, -1)], 96.06602772309196),
]


@pytest.mark.parametrize("lot, area", PYPRT_INNER_RECTANGLES)
def test_inner_rectangle_by_edge_matches_pyprt(lot, area):
    polygon = np.array([(x, -z) for x, z in lot], float)  # the lot's plane seen from +y
    rectangle, rest = inner_rectangle(polygon, "edge")
    # CityEngine's rectangles are a hair smaller than the optimum (3e-5 of the area)
    assert P.signed_area(rectangle) == pytest.approx(area, rel=1e-4)
    assert P.signed_area(rectangle) >= area * (1 - 1e-9)
    sides = np.diff(np.vstack([rectangle, rectangle[:1]]), axis=0)
    assert np.allclose(np.einsum("ij,ij->i", sides, np.roll(sides, -1, axis=0)), 0, atol=1e-9)
    assert P.signed_area(rectangle) + sum(map(P.signed_area, rest)) == pytest.approx(
        P.signed_area(polygon)
    )


# The same package with lots three times larger and frontSetbackRel 0, 10, 25: the rule sets
# the front edge (the longest, once the scope is aligned to it) back by d and reports the
# area of innerRectangle(edge) of the remainder.
PYPRT_SETBACKS = {
    "rect": ([(0, 0), (0, 8), (12, 8), (12, 0)], [(0, 864.0), (3.6, 734.4), (9.0, 540.0)]),
    "trapezoid": (
        [(0, 0), (2, 9), (11, 9), (14, 0)],
        [(0, 728.9946000099998), (4.2, 615.5955266677777), (10.5, 445.4956500100001)],
    ),
    "L": (
        [(0, 0), (0, 10), (4, 10), (4, 4), (10, 4), (10, 0)],
        [(0, 360.0), (3.0, 324.0), (7.5, 269.99655000999996)],
    ),
    "pentagon": (
        [(0, 0), (-2, 6), (5, 11), (13, 7), (12, -1)],
        [(0, 864.6147987467602), (4.459542268145836, 710.4834896384293),
         (11.14885567036459, 474.68487521048553)],
    ),
}  # fmt: skip


@pytest.mark.parametrize("name", sorted(PYPRT_SETBACKS))
def test_front_setback_then_inner_rectangle_matches_pyprt(name):
    lot, cases = PYPRT_SETBACKS[name]
    polygon = P.counter_clockwise(np.array([(3 * x, -3 * z) for x, z in lot], float))
    d = np.roll(polygon, -1, axis=0) - polygon
    longest = int(np.argmax(np.linalg.norm(d, axis=1)))
    normals = P.edge_normals(polygon)
    # front: outward normals in the longest edge's outward quadrant of the aligned scope
    along = d[longest] / np.linalg.norm(d[longest])
    front = (normals @ normals[longest]) > np.abs(normals @ along)
    for distance, area in cases:
        remainder = P.setback(polygon, np.where(front, distance, 0.0)).remainder
        rectangles = [inner_rectangle(r, "edge")[0] for r in remainder]
        largest = max(P.signed_area(r) for r in rectangles)
        assert largest == pytest.approx(area, rel=2e-5)
