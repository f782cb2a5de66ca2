"""setback_pieces on polygons CityEngine's runtime was not measured on: random star-shaped
polygons (reflex corners, edges kept, three branches, sometimes a hole) whose pieces must cover
the face once, no piece overlapping another or the remainder (the measured cases are in
tests/cga/test_cga_setback_pieces.py)."""

from __future__ import annotations

import numpy as np
import pytest
import shapely
from shapely.geometry import Polygon

from shapegen.geometry.polygon2d import setback, signed_area
from shapegen.geometry.setback_pieces import setback_pieces


def _random_faces(count: int, seed: int = 1):
    rng = np.random.default_rng(seed)
    made = 0
    while made < count:
        n = int(rng.integers(3, 12))
        angles = np.sort(rng.uniform(0, 2 * np.pi, n))
        radii = rng.uniform(3, 10, n)
        points = np.column_stack([np.cos(angles) * radii, np.sin(angles) * radii])
        if made % 3 == 0:  # whole metres: edges in line, right angles
            points = np.round(points)
        keep = [0] + [i for i in range(1, n) if np.linalg.norm(points[i] - points[i - 1]) > 1e-6]
        points = points[keep]
        if len(points) < 3 or not Polygon(points).is_valid or signed_area(points) <= 1:
            continue
        n = len(points)
        distances = rng.choice([0, 0.5, 1, 2, 3], n)
        owner = rng.integers(0, 3, n)
        groups = [[k for k in range(n) if owner[k] == g and distances[k] > 0] for g in range(3)]
        holes = []
        centre = points.mean(axis=0)
        hole = centre + np.array([[-0.5, -0.5], [-0.5, 0.5], [0.5, 0.5], [0.5, -0.5]])
        if made % 4 == 0 and Polygon(points).contains(Polygon(hole)):
            holes = [hole]
        made += 1
        yield points, holes, distances, groups


def _area(piece) -> float:
    outer, holes = piece
    return Polygon(outer, holes).area


@pytest.mark.parametrize("case", list(_random_faces(150)), ids=lambda c: f"{len(c[0])}-gon")
def test_the_pieces_cover_the_face_once(case):
    points, holes, distances, groups = case
    skeleton = setback(points, distances)
    strips = sum(signed_area(s) for _, s in skeleton.strips)
    if abs(strips + sum(map(signed_area, skeleton.remainder)) - signed_area(points)) > 1e-6:
        pytest.skip("the straight skeleton's strips do not tile this face")
    result = setback_pieces(points, holes, distances, groups)
    pieces = [p for group in result.groups for p in group] + list(result.remainder)
    face = Polygon(points, holes).area
    assert all(Polygon(outer, inner).is_valid for outer, inner in pieces)
    assert sum(map(_area, pieces)) == pytest.approx(face, rel=1e-9, abs=1e-9)
    union = shapely.union_all([Polygon(outer, inner) for outer, inner in pieces])
    assert union.area == pytest.approx(face, rel=1e-9, abs=1e-9)
