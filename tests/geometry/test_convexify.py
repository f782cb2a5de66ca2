"""``convexify`` against CityEngine's runtime: the parts PyPRT 1.12 gives on the lots of
``prt_convexify.json`` (which says how they were measured, by tools/prt_convexify.py)."""

import json
from pathlib import Path

import numpy as np
import pytest

from shapegen.geometry.convex import convex_faces, convex_pieces
from shapegen.geometry.mesh import Mesh

MEASURED = json.loads((Path(__file__).parent / "prt_convexify.json").read_text())
LOTS = [row for row in MEASURED["lots"] if "before" not in row]
SOLIDS = {row["name"]: row for row in MEASURED["lots"] if "before" in row}
NEAR = 2e-4  # m: the measured corners are rounded to 0.1 mm


def _face(outline) -> np.ndarray:
    """The outline as PyPRT's initial shape, (x, 0, z), its normal up (as the tool made it)."""
    points = np.array([[x, 0.0, z] for x, z in outline])
    x, z = points[:, 0], points[:, 2]
    twice = float(np.dot(x, np.roll(z, -1)) - np.dot(z, np.roll(x, -1)))
    return points if twice < 0 else points[::-1]


def _area(corners) -> float:
    x, z = np.asarray(corners, float).T
    return 0.5 * abs(float(np.dot(x, np.roll(z, -1)) - np.dot(z, np.roll(x, -1))))


def _same_corners(ours, theirs) -> bool:
    """The same corners in the same order from the same first one."""
    return len(ours) == len(theirs) and bool(np.all(np.abs(np.subtract(ours, theirs)) <= NEAR))


@pytest.mark.parametrize("row", LOTS, ids=[row["name"] for row in LOTS])
def test_convexify_gives_cityengines_parts(row):
    points, pieces = convex_pieces(_face(row["outline"]), row["max_length"])
    ours = [[(points[i][0], points[i][2]) for i in piece] for piece in pieces]
    theirs = row["parts"]
    assert len(ours) == len(theirs)
    assert [_area(p) for p in ours] == pytest.approx([_area(p) for p in theirs], abs=1e-3)
    # the parts in CityEngine's order, each from CityEngine's first corner on
    for mine, measured in zip(ours, theirs, strict=True):
        assert _same_corners(mine, measured), (mine, measured)


def test_the_candler_roof_is_cut_through_both_concave_corners():
    """A T like candler's RoofPlanePartRectangular: one cut along the line through both
    concave corners, so the cross bar is one rectangle (the measured T lot)."""
    row = next(r for r in LOTS if r["name"] == "T")
    points, pieces = convex_pieces(_face(row["outline"]), None)
    bar = [p for p in pieces if len(p) == 6]
    assert len(pieces) == 2 and len(bar) == 1
    corners = points[list(bar[0])][:, [0, 2]]
    assert corners.min(axis=0) == pytest.approx([0, 6]) and corners.max(axis=0) == pytest.approx(
        [12, 10]
    )
    assert _area(corners) == pytest.approx(48.0)


def test_a_new_vertex_is_a_corner_of_the_neighbouring_face_too():
    """An extruded L, convexified: the top's cut ends on the top edge of a wall, the bottom's on
    the bottom edge of another; CityEngine gives those walls the new vertex as a corner."""
    row = SOLIDS["L extruded"]
    outline = row["outline"]
    height = 5.0
    n = len(outline)
    bottom = [(x, 0.0, z) for x, z in outline]
    top = [(x, height, z) for x, z in outline]
    faces = [tuple(range(n)), tuple(range(2 * n - 1, n - 1, -1))]
    faces += [(i, (i + 1) % n, (i + 1) % n + n, i + n) for i in range(n)]  # the walls
    mesh = convex_faces(Mesh(np.array(bottom + top), faces))

    def corner_sets(faces_corners):
        return sorted(sorted(tuple(round(c, 3) + 0.0 for c in p) for p in f) for f in faces_corners)

    ours = corner_sets([mesh.vertices[list(f)] for f in mesh.faces])
    assert ours == corner_sets(row["parts"])
    assert sum(mesh.face(k).area() for k in range(mesh.n_faces)) == pytest.approx(
        2 * 64.0 + height * 40.0
    )


def test_max_length_leaves_a_part_whose_shortest_cut_is_longer():
    row = next(r for r in LOTS if r["name"] == "L maxLength 3")
    points, pieces = convex_pieces(_face(row["outline"]), 3.0)
    assert len(pieces) == 1 and len(points) == len(row["outline"])
    assert len(convex_pieces(_face(row["outline"]), 4.5)[1]) == 2  # the cut is 4 m long
