"""CGA's ``envelope`` on one flat face, as a :class:`~shapegen.geometry.roof_mesh.RoofMesh` in
the face's frame: walls to a base height, then planes sloping inward at each edge's angle (a
skeleton whose edges move at ``cot(angle)``), cut flat at a maximum height, and a face's holes
punched through it as CityEngine's runtime does.
"""

from __future__ import annotations

__all__ = ["envelope"]

import math
from dataclasses import replace

import numpy as np
import shapely
from shapely.geometry import LineString, Polygon

from shapegen.errors import GeometryError
from shapegen.geometry.polygon2d import checked_polygon
from shapegen.geometry.roof_mesh import RoofMesh, Welder, bottom_face, clockwise_rings
from shapegen.geometry.skeleton import straight_skeleton
from shapegen.tolerances import ROUNDOFF_REL


def envelope(polygon, max_height: float, base_heights, angles, holes=()) -> RoofMesh:
    """CGA's ``envelope``: each edge ``k`` a wall up to ``base_heights[k]`` (m), then a plane
    sloping inward at ``angles[k]`` (degrees, 90 = vertical), all cut at ``max_height`` (m).

    The sloped edges must share one base height (the planes then meet along a weighted
    straight skeleton); a vertical edge (90 degrees) is one wall from the face up to the planes,
    whatever its base height, as CityEngine's runtime builds it. ``holes`` (clockwise ``(k, 2)``
    rings) are punched through the envelope built on the outline, as CityEngine's runtime does
    (tests/data/prt_taper_envelope.json): a hole in the bottom, the upper faces cut by the
    hole's outline (a hole of the face where the outline lies inside it), and a vertical wall
    on each of the hole's edges up to the faces above (``envelope.side.inner``). The mesh's
    ``punch_failed`` is True where a hole's edge lies on a crease of the upper faces: CityEngine's
    runtime then warns that punching the holes failed and leaves out every inner wall, and so
    does this (:func:`_punch_fails`).
    """
    p = checked_polygon(polygon)
    n = len(p)
    base = np.asarray(base_heights, float).reshape(n)
    angle = np.asarray(angles, float).reshape(n)
    if not (math.isfinite(max_height) and max_height > 0):
        raise GeometryError(f"envelope's maximum height must be > 0, got {max_height}")
    if not np.all(np.isfinite(base)) or np.any(base < 0):
        raise GeometryError("envelope base heights must be finite numbers >= 0")
    if not np.all((angle > 0) & (angle <= 90)):
        raise GeometryError("envelope angles must be in (0, 90] degrees")
    sloped = angle < 90
    heights = np.unique(np.round(base[sloped], 12))
    if len(heights) > 1:
        raise GeometryError(
            "envelope with different base heights on its sloped sides is not supported "
            f"(got {', '.join(f'{h:g}' for h in heights)} m)"
        )
    start = min(float(heights[0]) if len(heights) else max_height, max_height)
    rings = clockwise_rings(holes)
    welder = Welder(float(max(np.ptp(p, axis=0).max(), max_height)))
    bottom_face(welder, p, "envelope.bottom", rings)
    # every face but the bottom, in the runtime's order (each edge's base wall and slope or its
    # vertical wall, then the top); a hole is punched through those that are not vertical
    faces: list[tuple[np.ndarray, str]] = []
    rise = max_height - start
    if rise <= 0:
        for k in range(n):
            a, b = p[k], p[(k + 1) % n]
            wall = [(*a, 0.0), (*b, 0.0), (*b, start), (*a, start)]
            faces.append((np.array(wall), "envelope.side.base"))
        faces.append((np.array([(x, y, start) for x, y in p]), "envelope.top"))
    else:
        weights = np.where(sloped, 1.0 / np.tan(np.radians(np.where(sloped, angle, 45.0))), 0.0)
        skeleton = straight_skeleton(p, weights=weights, until=rise)
        for k in range(n):
            ids = list(skeleton.faces[k])
            points = np.column_stack([skeleton.nodes[ids], start + skeleton.times[ids]])
            if sloped[k]:
                if start > 0:
                    a, b = p[k], p[(k + 1) % n]
                    wall = [(*a, 0.0), (*b, 0.0), (*b, start), (*a, start)]
                    faces.append((np.array(wall), "envelope.side.base"))
                faces.append((points, "envelope.side.slope"))
            else:  # a vertical edge: its wall from the face up, one face (PyPRT's L)
                if start > 0:
                    foot = np.array([[*points[0, :2], 0.0], [*points[1, :2], 0.0]])
                    points = _without_straight_corners(np.vstack([foot, points[1:], points[:1]]))
                faces.append((points, "envelope.side.slope"))
        for loop in skeleton.fronts:
            ids = list(loop)
            points = np.column_stack([skeleton.nodes[ids], start + skeleton.times[ids]])
            faces.append((points, "envelope.top"))
    failed = False
    if rings:
        failed = _punched(welder, faces, rings)
    else:
        for points, tag in faces:
            welder.face(points, tag)
    return replace(welder.mesh(), punch_failed=failed)


def _without_straight_corners(points: np.ndarray) -> np.ndarray:
    """A ring's corners less those on the line through their neighbours (a wall's corner at
    the base height where the wall goes on straight up), and repeated corners."""
    size = max(1.0, float(np.ptp(points, axis=0).max()))
    step = np.linalg.norm(points - np.roll(points, 1, axis=0), axis=1)
    points = points[step > ROUNDOFF_REL * size]
    keep = []
    m = len(points)
    for k in range(m):
        a, b, c = points[k - 1], points[k], points[(k + 1) % m]
        bent = np.linalg.norm(np.cross(b - a, c - b))
        if bent > ROUNDOFF_REL * size**2:
            keep.append(k)
    return points[keep]


def _plane_height(points: np.ndarray):
    """``(x, y) -> h`` on the plane through a face's ``(x, y, h)`` corners (not vertical)."""
    centre = points.mean(axis=0)
    normal = np.zeros(3)
    for a, b in zip(points, np.roll(points, -1, axis=0), strict=True):  # Newell's sum
        normal += np.cross(a - centre, b - centre)
    return lambda x, y: (
        centre[2] - (normal[0] * (x - centre[0]) + normal[1] * (y - centre[1])) / normal[2]
    )


def _lifted(height):
    """A shapely ring's corners as ``(x, y, h)`` on the plane ``height``."""
    return lambda ring: [(x, y, height(x, y)) for x, y in list(ring.coords)[:-1]]


def _punch_fails(faces, rings: list[np.ndarray], eps: float) -> bool:
    """Whether CityEngine's runtime fails to punch the holes ``rings`` (clockwise) through the
    upper ``faces`` (``(plan, height, tag)``): where an edge of a hole runs along a crease of
    the upper faces (a ridge, the edge of the flat top) for some length from one of the hole's
    convex corners. The rule fits every case of tests/data/prt_taper_envelope.json: it fails
    on two_holes, ridge_hole and top_partial with an edge on the top's edge or a ridge, and on
    the L courtyard where a ridge ends at its corner (3, 10); it does not fail where a ridge
    runs along the middle of an edge (the courtyard) or ends at a concave corner (the L
    courtyard's (3, 3))."""
    creases = [plan.boundary for plan, _, _ in faces]
    if not creases:
        return False
    crease = shapely.union_all(creases).buffer(2 * eps)
    for ring in rings:
        m = len(ring)
        d = np.diff(np.vstack([ring[-1:], ring, ring[:1]]), axis=0)
        turn = d[:-1, 0] * d[1:, 1] - d[:-1, 1] * d[1:, 0]  # at each corner
        convex = [t < 0 for t in turn]  # the hole's own corners, its ring clockwise
        for k in range(m):
            a, b = ring[k], ring[(k + 1) % m]
            along = LineString([a, b]).intersection(crease)
            for piece in getattr(along, "geoms", [along]):
                if piece.length <= 8 * eps:
                    continue
                for corner, is_convex in ((a, convex[k]), (b, convex[(k + 1) % m])):
                    if is_convex and piece.distance(shapely.Point(*corner)) <= 4 * eps:
                        return True
    return False


def _punched(welder: Welder, sides, rings: list[np.ndarray]) -> bool:
    """The envelope's faces ``sides`` (``(points, tag)``), those not vertical cut by the holes
    ``rings``, and a wall on each hole edge up to them; True (and no walls) where
    :func:`_punch_fails`, where CityEngine's runtime fails to punch the holes."""
    eps = welder.eps
    cut = shapely.union_all([Polygon(r) for r in rings])
    faces = []
    for points, tag in sides:
        plan = Polygon(points[:, :2])
        if plan.area <= eps * eps:  # vertical: no hole reaches it
            welder.face(points, tag)
            continue
        height = _plane_height(points)
        faces.append((plan, height, tag))
        if shapely.intersection(plan, cut, grid_size=eps).area <= eps * eps:
            welder.face(points, tag)
            continue
        # on a grid of the welding tolerance: a hole's edge on a face's edge (the skeleton's
        # crease at the maximum height, found to round-off) cuts the face, not holes it
        left = shapely.difference(plan, cut, grid_size=eps)
        for piece in getattr(left, "geoms", [left]):
            if not isinstance(piece, Polygon) or piece.area <= eps * eps:
                continue
            outline = shapely.geometry.polygon.orient(piece, 1.0)  # counter-clockwise, up
            lift = _lifted(height)
            welder.face(lift(outline.exterior), tag, [lift(r) for r in outline.interiors])
    if _punch_fails(faces, rings, eps):
        return True
    edges = [(r[k], r[(k + 1) % len(r)]) for r in rings for k in range(len(r))]
    for a, b in edges:
        line = LineString([a, b])
        d = b - a
        ts = {0.0, 1.0}
        for plan, _, _ in faces:
            crossing = line.intersection(plan.boundary)
            for g in getattr(crossing, "geoms", [crossing]):
                for x, y in getattr(g, "coords", []):
                    ts.add(float(np.dot(np.array([x, y]) - a, d) / np.dot(d, d)))
        top = []
        for t in sorted(ts):
            x, y = a + min(max(t, 0.0), 1.0) * d
            here = shapely.Point(x, y)
            h = [f(x, y) for plan, f, _ in faces if plan.distance(here) <= eps]
            top.append((x, y, max(h)))
        welder.face([(*a, 0.0), (*b, 0.0), *top[::-1]], "envelope.side.inner")
    return False
