"""CityEngine's polygon operations on one flat face, in the face's own plane.

A polygon is an ``(n, 2)`` array of vertices in metres, counter-clockwise seen from the face's
front (its normal towards the viewer), edge ``k`` running from vertex ``k`` to ``k + 1``. The
functions are pure and return new arrays:

- :func:`offset` (``offset(d)``): the offset polygon and the border faces, one per edge, with
  mitre corners; inward offsets follow the straight skeleton, so a polygon that shrinks away
  leaves only border faces;
- :func:`setback` (``setback``, ``setbackPerEdge``, ``shapeL/U/O``): each edge set back by its
  own distance (0 keeps it), the strip it sweeps and the remainder.

The pieces CityEngine gives each branch of a setback, and ``setbackToArea``, are
:mod:`shapegen.geometry.setback_pieces`'; the largest rectangle inside a polygon
(``innerRectangle``) is :mod:`shapegen.geometry.inner_rectangle`'s.
"""

from __future__ import annotations

__all__ = [
    "Offset",
    "Setback",
    "signed_area",
    "checked_polygon",
    "edges_moved_out",
    "counter_clockwise",
    "edge_normals",
    "offset",
    "offset_with_holes",
    "setback",
    "union",
    "polygon_pieces",
]

import math
from dataclasses import dataclass

import numpy as np
import shapely
from shapely.geometry import Polygon as ShapelyPolygon

from shapegen.errors import GeometryError
from shapegen.geometry.skeleton import straight_skeleton
from shapegen.tolerances import DEFAULT, DIVISION_FLOOR, ROUNDOFF_REL


@dataclass(frozen=True)
class Offset:
    """The result of :func:`offset`: ``inside`` polygons and one ``border`` face per edge."""

    inside: tuple[np.ndarray, ...]
    border: tuple[np.ndarray, ...]
    inside_holes: tuple[tuple[np.ndarray, ...], ...] = ()
    """With holes (:func:`offset_with_holes`): each inside polygon's holes, clockwise."""


@dataclass(frozen=True)
class Setback:
    """The result of :func:`setback`.

    Attributes
    ----------
    strips
        ``(edge index, polygon)`` for every edge set back by more than nothing, in edge order.
    remainder
        What is left of the polygon (several pieces when the setback cuts it in two).
    """

    strips: tuple[tuple[int, np.ndarray], ...]
    remainder: tuple[np.ndarray, ...]


def signed_area(polygon) -> float:
    """Signed area (m²): positive when counter-clockwise."""
    p = np.asarray(polygon, dtype=float)
    x, y = p[:, 0], p[:, 1]
    return 0.5 * float(np.dot(x, np.roll(y, -1)) - np.dot(y, np.roll(x, -1)))


def checked_polygon(polygon) -> np.ndarray:
    p = np.asarray(polygon, dtype=float).reshape(-1, 2)
    if len(p) < 3 or not np.all(np.isfinite(p)):
        raise GeometryError(f"a polygon needs at least 3 finite vertices, got {len(p)}")
    if signed_area(p) <= 0:
        raise GeometryError("the polygon is not counter-clockwise or has no area")
    return p


def counter_clockwise(polygon) -> np.ndarray:
    """The polygon with repeated vertices dropped, turned counter-clockwise if it was not."""
    p = np.asarray(polygon, dtype=float).reshape(-1, 2)
    eps = DEFAULT.merge_rel * max(float(np.ptp(p, axis=0).max()), DIVISION_FLOOR)
    keep = [q for k, q in enumerate(p) if np.linalg.norm(q - p[k - 1]) > eps]
    p = np.array(keep).reshape(-1, 2)
    return p if signed_area(p) >= 0 else p[::-1].copy()


def edge_normals(polygon) -> np.ndarray:
    """``(n, 2)`` outward unit normals of the edges of a counter-clockwise polygon."""
    p = np.asarray(polygon, dtype=float)
    d = np.roll(p, -1, axis=0) - p
    d /= np.linalg.norm(d, axis=1)[:, None]
    return np.stack([d[:, 1], -d[:, 0]], axis=1)


def edges_moved_out(polygon: np.ndarray, distances: np.ndarray) -> np.ndarray:
    """Each edge moved outward by its distance; vertices where neighbouring lines meet (mitre)."""
    normals = edge_normals(polygon)
    out = []
    n = len(polygon)
    for k in range(n):
        a, b = (k - 1) % n, k
        na, nb = normals[a], normals[b]
        ca = na @ polygon[k] + distances[a]
        cb = nb @ polygon[k] + distances[b]
        det = na[0] * nb[1] - na[1] * nb[0]
        if abs(det) < ROUNDOFF_REL:
            out.append(polygon[k] + na * distances[a])
        else:
            out.append(np.array([ca * nb[1] - cb * na[1], na[0] * cb - nb[0] * ca]) / det)
    return np.array(out)


def offset(polygon, distance: float) -> Offset:
    """CGA's ``offset(distance)`` on one polygon.

    Negative ``distance`` (m) shrinks: the inside polygons are the straight skeleton's
    wavefront, and border face ``k`` is the part of the polygon edge ``k`` sweeps
    (counter-clockwise, starting with the edge). Positive grows: the inside polygon has its
    edges moved outward with mitre corners, and border face ``k`` runs from the original edge to
    the moved one, clockwise, so that inside plus border faces is the original face in both
    cases (CityEngine's convention).
    """
    p = checked_polygon(polygon)
    d = float(distance)
    if not math.isfinite(d):
        raise GeometryError(f"offset distance must be a finite number, got {distance}")
    if d == 0:
        return Offset((p.copy(),), ())
    if d < 0:
        skeleton = straight_skeleton(p, until=-d)
        border = tuple(skeleton.face_points(k) for k in range(len(p)))
        return Offset(tuple(skeleton.front_points()), border)
    grown = edges_moved_out(p, np.full(len(p), d))
    if not np.isfinite(grown).all():  # a corner's mitre past a float's range
        raise GeometryError(f"offset({d:g}) moves the polygon's corners past any finite number")
    border = tuple(
        np.array([p[k], p[(k + 1) % len(p)], grown[(k + 1) % len(p)], grown[k]])
        for k in range(len(p))
    )
    inside = polygon_pieces(shapely.make_valid(ShapelyPolygon(grown)))
    return Offset(tuple(inside) if inside else (grown,), border)


def offset_with_holes(polygon, holes, distance: float) -> Offset:
    """:func:`offset` of a polygon (counter-clockwise) with ``holes`` (clockwise rings inside
    it): every ring's edges move by ``distance`` (m) away from the face, the holes' as the
    outer ring's (op_offset: a negative distance shrinks the face, so it widens the holes).
    The inside is the moved outer ring with the moved holes; border face ``k`` of each ring,
    outer ring first, then each hole's, runs along the ring's edge ``k`` and its moved copy
    (counter-clockwise for a negative distance, clockwise for a positive one, as
    :func:`offset` has them). So CityEngine's runtime gives a courtyard lot's ``offset(-1)``
    (tests/data/prt_holes.json: 9 faces, 1 hole).

    Raises :class:`GeometryError` when the offset changes the face's shape (a ring that
    vanishes or turns over, rings that meet): the straight skeleton of a polygon with holes
    that such an offset needs is not built."""
    p = checked_polygon(polygon)
    rings = [p] + [np.asarray(h, dtype=float).reshape(-1, 2) for h in holes]
    d = float(distance)
    if not math.isfinite(d):
        raise GeometryError(f"offset distance must be a finite number, got {distance}")
    if d == 0:
        return Offset((p.copy(),), (), (tuple(r.copy() for r in rings[1:]),))
    moved = [edges_moved_out(ring, np.full(len(ring), d)) for ring in rings]
    for ring, new in zip(rings, moved, strict=True):
        turned = (np.roll(ring, -1, axis=0) - ring) * (np.roll(new, -1, axis=0) - new)
        if not np.isfinite(new).all() or (turned.sum(axis=1) <= 0).any():
            raise GeometryError(
                f"offset({d:g}) of a face with holes makes a ring vanish or turn over: not "
                "supported by shapegen"
            )
    inside = ShapelyPolygon(moved[0], moved[1:])
    if not inside.is_valid or not inside.area > 0:
        raise GeometryError(
            f"offset({d:g}) of a face with holes makes its rings meet: not supported by shapegen"
        )
    border = tuple(
        np.array([ring[k], ring[(k + 1) % len(ring)], new[(k + 1) % len(ring)], new[k]])
        for ring, new in zip(rings, moved, strict=True)
        for k in range(len(ring))
    )
    return Offset((moved[0],), border, (tuple(moved[1:]),))


def setback(polygon, distances) -> Setback:
    """Set each edge ``k`` of ``polygon`` back by ``distances[k]`` (m, >= 0; 0 keeps it).

    The strip of edge ``k`` is the part of the polygon its line sweeps while moving inward
    (a weighted straight skeleton's face: corners between two moving edges are mitred, an edge
    that stays put is slid along), counter-clockwise starting with the edge.

    Distances that leave nothing (no remainder) do not cut the polygon: it is one strip, of its
    first set-back edge. So CityEngine's runtime does: in PyPRT's model of the envelope2002
    package, a 3 m setback of all four edges of a 4.8 x 4 m roof gives the whole roof as one
    shape (its offset ring and inner face follow the roof's 4 edges).
    """
    p = checked_polygon(polygon)
    d = np.asarray(distances, dtype=float).reshape(-1)
    if len(d) != len(p):
        raise GeometryError(f"setback needs one distance per edge ({len(p)}), got {len(d)}")
    if not np.all(np.isfinite(d)) or np.any(d < 0):
        raise GeometryError("setback distances must be finite numbers >= 0")
    if not np.any(d > 0):
        return Setback((), (p.copy(),))
    skeleton = straight_skeleton(p, weights=d, until=1.0)
    eps = DEFAULT.merge_rel * float(np.ptp(p, axis=0).max())
    strips = []
    for k in range(len(p)):
        if d[k] > 0:
            face = skeleton.face_points(k)
            if len(face) >= 3 and signed_area(face) > eps**2:
                strips.append((k, face))
    remainder = [r for r in skeleton.front_points() if signed_area(r) > eps**2]
    if not remainder:
        return Setback(((int(np.argmax(d > 0)), p.copy()),), ())
    return Setback(tuple(strips), tuple(remainder))


def polygon_pieces(geometry) -> list[np.ndarray]:
    """Counter-clockwise exterior rings of the polygons in a shapely geometry (holes dropped)."""
    out = []
    for part in getattr(geometry, "geoms", [geometry]):
        if isinstance(part, ShapelyPolygon) and not part.is_empty and part.area > 0:
            ring = np.asarray(part.exterior.coords)[:-1]
            out.append(counter_clockwise(ring))
        elif hasattr(part, "geoms"):
            out.extend(polygon_pieces(part))
    return out


def union(polygons) -> list[np.ndarray]:
    """The union of polygons, as counter-clockwise pieces."""
    merged = shapely.union_all([ShapelyPolygon(p) for p in polygons])
    return polygon_pieces(merged)
