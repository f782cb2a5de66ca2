"""Roofs against closed-form volumes and ridges, and CityEngine's face layout (checked with
PyPRT on the Building_From_FootprintSMALL package: one roof face per edge, starting with it)."""

import json
import math
from pathlib import Path

import numpy as np
import pytest

from shapegen.errors import GeometryError
from shapegen.geometry import roofs as R
from shapegen.geometry.envelope import envelope
from shapegen.geometry.mesh import Mesh
from shapegen.geometry.polygon2d import signed_area
from shapegen.geometry.ridge_roof import roof_ridge

RECT = [(0, 0), (12, 0), (12, 8), (0, 8)]
L_SHAPE = [(0, 0), (10, 0), (10, 4), (4, 4), (4, 10), (0, 10)]  # both arms 4 wide, area 64


def _ridge(mesh, height):
    top = mesh.vertices[np.isclose(mesh.vertices[:, 2], height)]
    return top


@pytest.mark.parametrize("w, d, angle", [(12, 8, 45), (12, 8, 30), (20, 5, 60), (6, 6, 40)])
def test_hip_roof_of_a_rectangle(w, d, angle):
    t = math.tan(math.radians(angle))
    h = d / 2 * t
    mesh = R.roof_hip([(0, 0), (w, 0), (w, d), (0, d)], angle)
    assert mesh.vertices[:, 2].max() == pytest.approx(h)
    ridge = _ridge(mesh, h)
    assert np.ptp(ridge[:, 0]) == pytest.approx(w - d)  # ridge length w - d
    assert mesh.volume() == pytest.approx(h * d * (3 * w - d) / 6)
    assert mesh.tags == ("roof.bottom",) + ("roof.top",) * 4


@pytest.mark.parametrize("w, d, angle", [(12, 8, 45), (12, 8, 20), (5, 9, 35)])
def test_gable_roof_of_a_rectangle_is_a_prism(w, d, angle):
    t = math.tan(math.radians(angle))
    mesh = R.roof_gable([(0, 0), (w, 0), (w, d), (0, d)], angle)
    short = min(w, d)
    assert mesh.volume() == pytest.approx(max(w, d) * short**2 * t / 4)
    assert mesh.vertices[:, 2].max() == pytest.approx(short / 2 * t)
    assert mesh.tags.count("roof.side") == 2  # the gables: the short edges


def test_gable_index_chooses_the_gable_edges():
    mesh = R.roof_gable(RECT, 45, index=0)  # edge 0 (12 m) and its opposite are the gables
    assert mesh.tags == ("roof.bottom", "roof.side", "roof.top", "roof.side", "roof.top")
    assert mesh.volume() == pytest.approx(8 * 12**2 / 4)


def test_hip_and_gable_roofs_of_an_l_shape():
    # As PyPRT builds them: hip ridges (2,2)-(8,2) and (2,2)-(2,8) at height 2; the gable
    # ridges run to the wing ends.
    hip = R.roof_hip(L_SHAPE, 45)
    top = hip.vertices[np.isclose(hip.vertices[:, 2], 2)]
    assert sorted(map(tuple, np.round(top[:, :2], 9))) == [(2, 2), (2, 8), (8, 2)]
    # Two 4 m wide arms: each a hip-ended prism, minus the overlap counted twice.
    arm = 2 * 4 * (3 * 10 - 4) / 6  # hip roof of a 10 x 4 rectangle, h = 2
    assert hip.volume() == pytest.approx(2 * arm - 4 * 4 * 2 / 3)  # the corner pyramid twice
    gable = R.roof_gable(L_SHAPE, 45)
    assert gable.tags.count("roof.side") == 2
    ends = gable.vertices[np.isclose(gable.vertices[:, 2], 2)][:, :2]
    assert sorted(map(tuple, np.round(ends, 9))) == [(2, 2), (2, 10), (10, 2)]


def test_roof_faces_start_with_their_edges_as_cityengine():
    mesh = R.roof_hip(RECT, 45)
    p = np.asarray(RECT, float)
    for k, face in enumerate(mesh.faces[1:]):
        first, second = mesh.vertices[face[0]], mesh.vertices[face[1]]
        np.testing.assert_allclose(first, [*p[k], 0])
        np.testing.assert_allclose(second, [*p[(k + 1) % 4], 0])


def test_rectangle_roofs_are_closed_convex_solids():
    for mesh in (
        R.roof_hip(RECT, 45),
        R.roof_gable(RECT, 45),
        R.roof_pyramid(RECT, 45),
        R.roof_shed(RECT, 20),
    ):
        edges = {}
        for face in mesh.faces:
            for a, b in zip(face, face[1:] + face[:1], strict=True):
                edges[(a, b)] = edges.get((a, b), 0) + 1
        assert all(edges.get((b, a)) == 1 for a, b in edges)  # every edge used once each way
        centre = mesh.vertices.mean(axis=0)
        for face in mesh.faces:  # every vertex behind every face plane
            q = mesh.vertices[list(face)]
            normal = np.cross(q[1] - q[0], q[2] - q[0])
            assert np.all((mesh.vertices - q[0]) @ normal <= 1e-9)
            assert (centre - q[0]) @ normal < 0


def test_shed_pyramid_and_taper_volumes():
    t = math.tan(math.radians(15))
    assert R.roof_shed(RECT, 15).volume() == pytest.approx(12 * 8 * 8 * t / 2)
    shed = R.roof_shed(RECT, 15, index=1)  # rising from the 8 m edge at x = 12
    assert shed.vertices[:, 2].max() == pytest.approx(12 * t)
    assert R.roof_pyramid(RECT, 45).volume() == pytest.approx(96 * 4 / 3)  # apex 4 m above
    assert R.roof_pyramid(RECT, height=3).volume() == pytest.approx(96)
    assert R.taper(L_SHAPE, 5).volume() == pytest.approx(64 * 5 / 3)
    assert R.taper(L_SHAPE, -5).volume() == pytest.approx(64 * 5 / 3)


def test_by_height_and_overhang():
    hip = R.roof_hip(RECT, height=2)
    assert hip.vertices[:, 2].max() == pytest.approx(2)
    gable = R.roof_gable(RECT, 30, overhang_x=1, overhang_y=0.5)
    z = gable.vertices[:, 2]
    assert z.min() == pytest.approx(-0.5)  # 1 m down a 30 degree slope
    assert z.max() == pytest.approx(4 * math.tan(math.radians(30)))
    xy = gable.vertices[:, :2]
    assert xy[:, 0].min() == pytest.approx(-0.5)
    assert xy[:, 1].min() == pytest.approx(-math.cos(math.radians(30)))
    bottom = gable.vertices[list(gable.faces[0])]
    assert signed_area(bottom[::-1, :2]) == pytest.approx(96)  # the face itself stays


def test_negative_overhangs_set_the_eaves_in():
    hip = R.roof_hip(RECT, 45, overhang=-1)  # the same planes, cut 1 m up the slope
    z = hip.vertices[:, 2]
    assert z.max() == pytest.approx(4)
    assert z[z > 0].min() == pytest.approx(math.sin(math.radians(45)))
    gable = R.roof_gable(RECT, 45, overhang_y=-1)  # the roof faces 1 m short of the 8 m edges
    for face, tag in zip(gable.faces, gable.tags, strict=True):
        corners = gable.vertices[list(face)]
        if tag == "roof.top":
            assert np.ptp(corners[:, 0]) == pytest.approx(10)
        if tag == "roof.side":  # the gables stay on the face's edges (PyPRT's parthenon)
            assert np.ptp(corners[:, 0]) == pytest.approx(0)
            assert corners[0, 0] in (pytest.approx(0), pytest.approx(12))
            assert corners[:, 2].max() == pytest.approx(4)
    assert sorted(gable.tags).count("roof.side") == 2


@pytest.mark.parametrize(
    "call, message",
    [
        (lambda: R.roof_hip(RECT, 95), "between -90 and 90"),
        (lambda: R.roof_hip(RECT, 45, overhang=-7), "larger than the face"),
        (lambda: R.roof_gable(RECT, 45, overhang_y=float("inf")), "finite"),
        (lambda: R.roof_hip(RECT, height=2, overhang=1), "byAngle"),
        (lambda: R.taper(RECT, float("nan")), "finite"),
    ],
)
def test_bad_input_is_one_clear_error(call, message):
    with pytest.raises(GeometryError, match=message):
        call()


PYPRT = json.loads((Path(__file__).parent / "pyprt_roofs.json").read_text())["roofs"]


@pytest.mark.parametrize("key", sorted(PYPRT))
def test_roofs_match_pyprt(key):
    """CityEngine's roofs of a rectangle, a trapezoid and two L-shapes (the rule rescales them
    to 4 m high, so heights are compared after the same rescaling)."""
    form, _ = key.split("/")
    lot = np.array(PYPRT[key]["lot"], float).reshape(-1, 3)
    polygon = np.column_stack([lot[:, 0], -lot[:, 2]])  # the top face's plane, seen from +y
    build = {
        "hip": lambda p: R.roof_hip(p, 45),
        "gable": lambda p: R.roof_gable(p, 45, index=0),
        "shed": lambda p: R.roof_shed(p, 15),
        "pyramid": lambda p: R.roof_pyramid(p, 45),
    }[form]
    mesh = build(polygon)
    v = mesh.vertices
    ours = np.column_stack([v[:, 0], 10 + 4 * v[:, 2] / v[:, 2].max(), -v[:, 1]])
    theirs = np.array([p for face in PYPRT[key]["faces"] for p in face])
    distance = np.linalg.norm(ours[:, None] - theirs[None], axis=2)
    assert distance.min(axis=1).max() < 1e-5  # every vertex of ours is one of theirs
    assert distance.min(axis=0).max() < 1e-5  # and the other way round
    assert len(mesh.faces) - 1 == len(PYPRT[key]["faces"])  # one roof face per edge


def test_envelope_of_a_rectangle():
    # candler's ventilation: walls to 0.45 m, 45 degree slopes, cut at 0.6 m: a prism and a
    # prismatoid h/6 (A_bottom + A_top + 4 A_middle).
    mesh = envelope(RECT, 0.6, [0.45] * 4, [45] * 4)
    h = 0.15
    prismatoid = h / 6 * (96 + (12 - 2 * h) * (8 - 2 * h) + 4 * (12 - h) * (8 - h))
    assert mesh.volume() == pytest.approx(96 * 0.45 + prismatoid)
    assert mesh.tags.count("envelope.top") == 1
    # the front (edge 0) alone slopes, from 3 m: a wedge cut off a 10 m box
    mesh = envelope(RECT, 10, [3, 0, 0, 0], [45, 90, 90, 90])
    assert mesh.volume() == pytest.approx(96 * 10 - 12 * 7 * 7 / 2)
    # below the cut the slopes meet in a hip roof
    mesh = envelope(RECT, 10, [3] * 4, [45] * 4)
    assert mesh.volume() == pytest.approx(96 * 3 + 4 * 8 * (3 * 12 - 8) / 6)


def test_envelope_refuses_different_sloped_base_heights():
    with pytest.raises(GeometryError, match="different base heights"):
        envelope(RECT, 10, [3, 2, 3, 3], [45] * 4)


def test_roof_ridge():
    # a ridge along x halfway across: on a rectangle it is the gable roof along x
    assert roof_ridge(RECT, 45).volume() == pytest.approx(12 * 8**2 / 4)
    deep = roof_ridge([(0, 0), (4, 0), (4, 12), (0, 12)], 45)  # across the long side
    assert deep.vertices[:, 2].max() == pytest.approx(6)
    assert deep.volume() == pytest.approx(4 * 12 * 6 / 2)
    # an L: planes from y = 0 and y = 10, the outline lifted onto them, closed
    ridge = roof_ridge(L_SHAPE, height=5)
    edges = {}
    for face in ridge.faces:
        for a, b in zip(face, face[1:] + face[:1], strict=True):
            edges[(a, b)] = edges.get((a, b), 0) + 1
    assert all(edges.get((b, a)) == 1 for a, b in edges)
    assert ridge.vertices[:, 2].max() == pytest.approx(5)
    # volume: the L's two arms under the two planes (heights y and 10 - y, ridge y = 5)
    expected = 10 * 4 * 2 + 4 * (1 / 2) * (4 + 5) * 1 + 4 * 5 * 5 / 2
    assert ridge.volume() == pytest.approx(expected)


# A polygon's straight skeleton with holes, by its defining property: every point of edge k's
# face is reached by the wavefront of edge k when it lies as far from k's line as its time
# (weights 1), and the faces tile the polygon less its holes.
HOLED = {
    # a square ring 3 m wide all round: every face a trapezoid up to t = 1.5 m
    "square ring": ([(0, 0), (10, 0), (10, 10), (0, 10)], [[(3, 3), (3, 7), (7, 7), (7, 3)]], 1.5),
    # 12 x 8 m with a 4 x 2 m courtyard: 4 m beside it (t = 2), 3 m before and behind it
    "courtyard": ([(0, 0), (12, 0), (12, 8), (0, 8)], [[(4, 3), (4, 5), (8, 5), (8, 3)]], 2.0),
    # two courtyards, the wavefronts of the holes meeting between them
    "two holes": (
        [(0, 0), (20, 0), (20, 10), (0, 10)],
        [[(3, 3), (3, 7), (7, 7), (7, 3)], [(12, 4), (12, 6), (16, 6), (16, 4)]],
        None,
    ),
}


@pytest.mark.parametrize("name", HOLED)
def test_the_straight_skeleton_of_a_polygon_with_holes(name):
    from shapegen.geometry.skeleton import straight_skeleton

    outline, holes, highest = HOLED[name]
    rings = [np.array(outline, float)] + [np.array(h, float) for h in holes]
    skeleton = straight_skeleton(rings[0], holes=rings[1:])
    edges = [(r[k], r[(k + 1) % len(r)]) for r in rings for k in range(len(r))]
    assert len(skeleton.faces) == len(edges)
    total = 0.0
    for k, (a, b) in enumerate(edges):
        xyt = skeleton.face_xyt(k)
        u = (b - a) / np.linalg.norm(b - a)
        inward = np.array([-u[1], u[0]])
        assert (xyt[:, :2] - a) @ inward == pytest.approx(xyt[:, 2], abs=1e-9)
        assert np.allclose(xyt[:2, :2], [a, b])  # the face starts with its edge
        total += signed_area(xyt[:, :2])
    area = signed_area(rings[0]) + sum(signed_area(h) for h in rings[1:])
    assert total == pytest.approx(area)
    if highest is not None:
        assert skeleton.times.max() == pytest.approx(highest)


def test_a_hip_roof_keeps_the_holes_and_a_gable_roof_on_them_is_a_hip_roof():
    outline, holes, _ = HOLED["courtyard"]
    hip = R.roof_hip(outline, 30, holes=holes)
    # the bottom keeps its hole; a roof face on each of the 4 + 4 edges
    assert hip.holes[0] and len(hip.holes[0][0]) == 4 and len(hip.faces) == 9
    assert hip.volume() == pytest.approx(43.782395, abs=1e-6)  # tests/data/prt_holes.json
    gable = R.roof_gable(outline, 30, holes=holes)
    assert np.allclose(gable.vertices, hip.vertices) and gable.faces == hip.faces
    with pytest.raises(GeometryError, match="even roof"):
        R.roof_hip(outline, 30, even=True, holes=holes)


def test_a_holed_hip_roof_overhangs_the_outline_and_into_the_holes():
    # every plane carried on 1 m (on the slope) past its edge: in plan g = cos(30) m out from
    # the outline and into the courtyard, so the planes cover (12 + 2g)(8 + 2g) less
    # (4 - 2g)(2 - 2g) in plan, over cos(30) on the slope
    outline, holes, _ = HOLED["courtyard"]
    g = math.cos(math.radians(30))
    mesh = R.roof_hip(outline, 30, overhang=1, holes=holes)
    planes = sum(
        Mesh(mesh.vertices, [f]).area()
        for f, t in zip(mesh.faces, mesh.tags, strict=True)
        if t == "roof.top"
    )
    plan = (12 + 2 * g) * (8 + 2 * g) - (4 - 2 * g) * (2 - 2 * g)
    assert planes == pytest.approx(plan / g)
    assert mesh.vertices[:, 2].min() == pytest.approx(-0.5)  # the eaves 1 m down the slope
