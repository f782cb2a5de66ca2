"""CityEngine's polygon operations on one flat face, in the face's own plane.

A polygon is an ``(n, 2)`` array of vertices in metres, counter-clockwise seen from the face's
front (its normal towards the viewer), edge ``k`` running from vertex ``k`` to ``k + 1``. The
functions are pure and return new arrays:

- :func:`offset` (``offset(d)``): the offset polygon and the border faces, one per edge, with
  mitre corners; inward offsets follow the straight skeleton, so a polygon that shrinks away
  leaves only border faces;
- :func:`setback` (``setback``, ``setbackPerEdge``, ``shapeL/U/O``): each edge set back by its
  own distance (0 keeps it), the strip it sweeps and the remainder;
- :func:`setback_to_area` (``setbackToArea``): the common extra distance that leaves a
  remainder of a given area;
- :func:`inner_rectangle` (``innerRectangle``): the largest rectangle inside the polygon,
  parallel to the axes or to one of its edges, and the remainder.
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
    "setback_to_area",
    "union",
    "inner_rectangle",
]

import math
from dataclasses import dataclass

import numpy as np
import shapely
from shapely.geometry import Polygon as ShapelyPolygon

from shapegen.errors import GeometryError
from shapegen.geometry.skeleton import straight_skeleton
from shapegen.limits import check_clock
from shapegen.tolerances import COINCIDENT_REL, DEFAULT, DIVISION_FLOOR, ROUNDOFF_REL

#: The largest inscribed rectangle's SLSQP stops when its objective (the log of the area) moves
#: by less than this (a solver setting, not a comparison).
RECTANGLE_FTOL = 1e-12


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
    inside = _pieces(shapely.make_valid(ShapelyPolygon(grown)))
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


def setback_to_area(polygon, area: float, selected, min_distances=None, max_distances=None):
    """CGA's ``setbackToArea``: the setback whose remainder has ``area`` (m²).

    The ``selected`` edges (booleans) are set back by ``min_distances + c`` (clamped to
    ``max_distances``) with the common ``c`` >= 0 found by bisection; the others stay.

    Returns
    -------
    (Setback, distances)
    """
    p = checked_polygon(polygon)
    n = len(p)
    selected = np.asarray(selected, dtype=bool).reshape(n)
    low = np.zeros(n) if min_distances is None else np.asarray(min_distances, float).reshape(n)
    high = np.full(n, np.inf) if max_distances is None else np.asarray(max_distances, float)
    total = signed_area(p)
    if not (math.isfinite(area) and 0 < area):
        raise GeometryError(f"setbackToArea needs an area > 0, got {area}")
    if area > total:
        raise GeometryError(f"setbackToArea: the face has {total:.6g} m², less than {area:.6g}")

    def remaining(c: float) -> tuple[float, np.ndarray]:
        d = np.where(selected, np.minimum(low + c, high.reshape(n)), 0.0)
        result = setback(p, np.maximum(d, 0.0))
        return sum(signed_area(r) for r in result.remainder), d

    if remaining(0.0)[0] < area:
        raise GeometryError("setbackToArea: the minimum distances already leave less than the area")
    lo, hi = 0.0, float(np.ptp(p, axis=0).max())
    if remaining(hi)[0] > area:
        raise GeometryError("setbackToArea: the maximum distances leave more than the area")
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        if remaining(mid)[0] > area:
            lo = mid
        else:
            hi = mid
    distances = remaining(0.5 * (lo + hi))[1]
    return setback(p, distances), distances


def _pieces(geometry) -> list[np.ndarray]:
    """Counter-clockwise exterior rings of the polygons in a shapely geometry (holes dropped)."""
    out = []
    for part in getattr(geometry, "geoms", [geometry]):
        if isinstance(part, ShapelyPolygon) and not part.is_empty and part.area > 0:
            ring = np.asarray(part.exterior.coords)[:-1]
            out.append(counter_clockwise(ring))
        elif hasattr(part, "geoms"):
            out.extend(_pieces(part))
    return out


def union(polygons) -> list[np.ndarray]:
    """The union of polygons, as counter-clockwise pieces."""
    merged = shapely.union_all([ShapelyPolygon(p) for p in polygons])
    return _pieces(merged)


def _largest_axis_rectangle(
    polygon: np.ndarray, samples: int, holes=()
) -> tuple[float, np.ndarray]:
    """Largest axis-parallel rectangle inside ``polygon`` (and outside its ``holes``): on a grid
    through its vertices plus ``samples`` evenly spaced lines per axis, then three times on a
    finer grid around the best rectangle's sides (a corner on a slanted edge converges to it):
    ``(area, corners)``."""
    lo, hi = polygon.min(axis=0), polygon.max(axis=0)
    lines = [np.linspace(lo[k], hi[k], samples) for k in (0, 1)]
    best = _grid_rectangle(polygon, *lines, holes=holes)
    step = (hi - lo) / max(samples - 1, 1)
    for _ in range(3):
        if best[1] is None:
            break
        corners = best[1]
        lines = [
            np.concatenate(
                [np.linspace(c - step[k], c + step[k], 17) for c in (corners[0, k], corners[2, k])]
                + [np.linspace(lo[k], hi[k], samples)]
            )
            for k in (0, 1)
        ]
        best = max(best, _grid_rectangle(polygon, *lines, holes=holes), key=lambda b: b[0])
        step = step / 8
    return best


def _convex(p: np.ndarray) -> bool:
    d = np.roll(p, -1, axis=0) - p
    cross = d[:, 0] * np.roll(d[:, 1], -1) - d[:, 1] * np.roll(d[:, 0], -1)
    return bool(np.all(cross >= -ROUNDOFF_REL * float(np.abs(cross).max())))


def _convex_optimum(polygon: np.ndarray, corners: np.ndarray) -> tuple[float, np.ndarray]:
    """The largest axis-parallel rectangle in a convex polygon: maximise log(w) + log(h) with
    its four corners inside every edge's half-plane (a concave problem, solved by SLSQP from the
    grid's answer ``corners``)."""
    from scipy.optimize import minimize

    d = np.roll(polygon, -1, axis=0) - polygon
    inward = np.stack([-d[:, 1], d[:, 0]], axis=1)
    offset = np.einsum("ij,ij->i", inward, polygon)
    rows = []
    for cx, cy in ((0, 0), (1, 0), (0, 1), (1, 1)):  # corner = (x0 + cx w, y0 + cy h)
        rows.append(np.column_stack([inward[:, 0], inward[:, 1], cx * inward[:, 0],
                                     cy * inward[:, 1]]))  # fmt: skip
    a = np.concatenate(rows)
    b = np.tile(offset, 4)
    start = np.array([*corners[0], *(corners[2] - corners[0])])
    scale = float(np.ptp(polygon, axis=0).max())
    result = minimize(
        lambda v: -(math.log(max(v[2], DIVISION_FLOOR)) + math.log(max(v[3], DIVISION_FLOOR))),
        start,
        jac=lambda v: np.array(
            [0.0, 0.0, -1.0 / max(v[2], DIVISION_FLOOR), -1.0 / max(v[3], DIVISION_FLOOR)]
        ),
        constraints=[
            {"type": "ineq", "fun": lambda v: (a @ v - b) / scale, "jac": lambda v: a / scale}
        ],
        method="SLSQP",
        options={"ftol": RECTANGLE_FTOL, "maxiter": 200},
    )
    x0, y0, w, h = result.x
    area = w * h
    if (
        not result.success
        or np.any(a @ result.x - b < -COINCIDENT_REL * scale**2)
        or area <= (np.prod(corners[2] - corners[0]))
    ):
        return float(np.prod(corners[2] - corners[0])), corners
    return float(area), np.array([[x0, y0], [x0 + w, y0], [x0 + w, y0 + h], [x0, y0 + h]])


#: Lines per axis through a polygon's corners that the rectangle search's grid takes at most:
#: its cells (and their shapely boxes) grow as the square of the lines, so a polygon of more
#: corners (a 4096-sided disk) takes this many of its corners' coordinates, evenly spread.
GRID_CORNER_LINES = 256


def _corner_lines(values: np.ndarray) -> np.ndarray:
    values = np.unique(values)
    if len(values) <= GRID_CORNER_LINES:
        return values
    return values[np.linspace(0, len(values) - 1, GRID_CORNER_LINES).round().astype(int)]


def _grid_rectangle(polygon: np.ndarray, xs: np.ndarray, ys: np.ndarray, holes=()):
    """The largest rectangle of the grid's cells inside ``polygon`` (and outside ``holes``):
    ``(area, corners)``. Of equal ones, a face with holes takes the highest (the farthest from
    its first edge), then the leftmost, as CityEngine's runtime does on its four measured ties
    (a courtyard lot both ways round, a block, a turned yard: tests/data/prt_setback_holes.json);
    a face without holes, the first found (of a notched lot's two rectangles CityEngine takes
    the same one whichever corner the lot starts on, so neither rule matches it both ways
    round)."""
    later = bool(len(holes))
    shape = ShapelyPolygon(polygon, [np.asarray(h) for h in holes])
    shapely.prepare(shape)
    lo, hi = polygon.min(axis=0), polygon.max(axis=0)
    corners = np.concatenate([polygon, *holes]) if len(holes) else polygon
    xs = np.unique(np.clip(np.concatenate([_corner_lines(corners[:, 0]), xs]), lo[0], hi[0]))
    ys = np.unique(np.clip(np.concatenate([_corner_lines(corners[:, 1]), ys]), lo[1], hi[1]))
    shrink = COINCIDENT_REL * float(np.ptp(polygon, axis=0).max())
    x0, y0 = np.meshgrid(xs[:-1], ys[:-1])
    x1, y1 = np.meshgrid(xs[1:], ys[1:])
    cells = shapely.box(x0 + shrink, y0 + shrink, x1 - shrink, y1 - shrink)
    inside = shapely.contains(shape, cells) & (x1 - x0 > 2 * shrink) & (y1 - y0 > 2 * shrink)
    best = (0.0, None)
    tie = (-math.inf, -math.inf)  # (top, -left) of the best rectangle, for equal areas
    heights = np.zeros(len(xs) - 1)
    edges = np.concatenate([[0.0], np.cumsum(np.diff(xs))])  # x of each column's left side
    for j in range(len(ys) - 1):
        check_clock()
        # Largest rectangle in the histogram of column heights (m) for rows up to j: a stack of
        # columns with rising heights; a lower column closes the taller ones before it.
        heights = np.where(inside[j], heights + (ys[j + 1] - ys[j]), 0.0)
        stack: list[tuple[int, float]] = []  # (first column, height)
        for i, h in enumerate([*heights, 0.0]):
            first = i
            while stack and stack[-1][1] >= h:
                first, top = stack.pop()
                area = top * (edges[i] - edges[first])
                if area > best[0] or (later and area == best[0] and (ys[j + 1], -xs[first]) > tie):
                    tie = (ys[j + 1], -xs[first])
                    x0, x1, y1 = xs[first], xs[i], ys[j + 1]
                    corners = np.array([[x0, y1 - top], [x1, y1 - top], [x1, y1], [x0, y1]])
                    best = (area, corners)
            if h > 0:
                stack.append((first, h))
    return best


def inner_rectangle(polygon, alignment: str = "scope", samples: int = 48, holes=()):
    """CGA's ``innerRectangle``: the largest rectangle inside ``polygon`` and the remainder.

    ``alignment`` "scope": sides parallel to the axes; "edge": parallel to one of the edges at
    least a quarter as long as the longest (op_innerRectangle: "per outer polygon/hole", so a
    hole's long edges are candidates too). In a convex polygon the rectangle is the exact
    optimum (a concave problem); otherwise the search runs on a grid through the vertices plus
    ``samples`` lines per axis, refined three times around the best rectangle (exact for
    axis-parallel polygons). With ``holes`` (clockwise rings) the rectangle is outside them
    (CityEngine's runtime: tests/data/prt_setback_holes.json).

    Returns
    -------
    (rectangle ``(4, 2)`` counter-clockwise or None, remainder pieces): without holes each
    piece an ``(n, 2)`` polygon, with holes each ``(outline, holes)``.
    """
    p = checked_polygon(polygon)
    rings = [np.asarray(h, dtype=float).reshape(-1, 2) for h in holes]
    if alignment not in ("scope", "edge"):
        raise GeometryError(f"innerRectangle alignment must be scope or edge, got {alignment!r}")
    candidates = [np.eye(2)]
    if alignment == "edge":
        candidates = []
        for ring in (p, *rings):
            d = np.roll(ring, -1, axis=0) - ring
            lengths = np.linalg.norm(d, axis=1)
            for k in np.flatnonzero(lengths >= lengths.max() / 4):
                u = d[k] / lengths[k]
                if ring is not p:  # a hole runs clockwise: its edge's axes as the outline's
                    u = -u
                candidates.append(np.array([u, [-u[1], u[0]]]))  # rows: the rectangle's axes
    best = (0.0, None)
    for axes in candidates:
        turned = p @ axes.T
        lo, hi = turned.min(axis=0), turned.max(axis=0)
        box_area = float(np.prod(hi - lo))
        if rings:
            area, corners = _largest_axis_rectangle(turned, samples, [r @ axes.T for r in rings])
        elif _convex(turned) and abs(signed_area(turned)) >= box_area * (1 - ROUNDOFF_REL):
            # the polygon fills its bounding box: it is the rectangle (a rectangular lot)
            area = box_area
            corners = np.array([[lo[0], lo[1]], [hi[0], lo[1]], [hi[0], hi[1]], [lo[0], hi[1]]])
        elif _convex(turned):  # a coarse grid to start from, then the exact optimum
            lines = [np.linspace(lo[k], hi[k], 16) for k in (0, 1)]
            area, corners = _grid_rectangle(turned, *lines)
            if corners is not None:
                area, corners = _convex_optimum(turned, corners)
        else:
            area, corners = _largest_axis_rectangle(turned, samples)
        if corners is not None and area > best[0]:
            best = (area, corners @ axes, axes, corners)
    rectangle = best[1]
    if rectangle is None:
        return None, (p.copy(),)
    # The remainder, cut along the rectangle's sides extended (left, right, below, above), so
    # that no piece has the rectangle as a hole.
    axes, (x0, y0), (x1, y1) = best[2], best[3][0], best[3][2]
    # a face that crosses itself (a bow tie) is cut as the valid pieces it covers; GEOS refuses
    # to intersect it as it is
    turned = shapely.make_valid(ShapelyPolygon(p @ axes.T, [r @ axes.T for r in rings]))
    far = 2 * float(np.abs(p).max()) + 1
    regions = [
        shapely.box(-far, -far, x0, far),
        shapely.box(x1, -far, far, far),
        shapely.box(x0, -far, x1, y0),
        shapely.box(x0, y1, x1, far),
    ]
    eps = (DEFAULT.merge_rel * float(np.ptp(p, axis=0).max())) ** 0.5
    pieces = []
    for region in regions:
        if rings:
            # on a grid of COINCIDENT_REL, so that a hole's corner that the turned frame leaves
            # a rounding off the cut touches it (GEOS then gives it as a hole, not a pinch)
            grid = COINCIDENT_REL * float(np.ptp(p, axis=0).max())
            cut = shapely.set_precision(turned.intersection(region), grid)
            for outer, inner in _pieces_with_holes(cut):
                if signed_area(outer) > eps * signed_area(p):
                    pieces.append((outer @ axes, tuple(h @ axes for h in inner)))
            continue
        for r in _pieces(turned.intersection(region)):
            if signed_area(r) > eps * signed_area(p):
                pieces.append(counter_clockwise(r @ axes))
    return rectangle, tuple(pieces)


def _without_touch_points(outline: np.ndarray, holes) -> np.ndarray:
    """``outline`` without the corners GEOS adds where a hole touches it: in line with their
    neighbours and on a hole's corner (CityEngine's outline has no corner there:
    tests/data/prt_setback_holes.json, the turned yard)."""
    if not holes or len(outline) <= 3:
        return outline
    corners = np.concatenate(holes)
    scale = float(np.ptp(outline, axis=0).max())
    before, after = np.roll(outline, 1, axis=0), np.roll(outline, -1, axis=0)
    a, b = outline - before, after - before
    cross = np.abs(a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0])
    in_line = cross <= COINCIDENT_REL * scale * np.linalg.norm(b, axis=1)
    on_hole = np.array(
        [np.min(np.linalg.norm(corners - q, axis=1)) <= COINCIDENT_REL * scale for q in outline]
    )
    keep = ~(in_line & on_hole)
    return outline[keep] if keep.sum() >= 3 else outline


def _pieces_with_holes(geometry) -> list[tuple[np.ndarray, tuple[np.ndarray, ...]]]:
    """The polygons of a shapely geometry as ``(outline, holes)``: the outline
    counter-clockwise, the holes clockwise."""
    out = []
    for part in getattr(geometry, "geoms", [geometry]):
        if isinstance(part, ShapelyPolygon) and not part.is_valid:
            # GEOS may give a hole that touches the outline as a shell that touches itself:
            # made valid, it is the outline and the hole
            out.extend(_pieces_with_holes(shapely.make_valid(part)))
        elif isinstance(part, ShapelyPolygon) and not part.is_empty and part.area > 0:
            outline = counter_clockwise(np.asarray(part.exterior.coords)[:-1])
            holes = tuple(
                counter_clockwise(np.asarray(ring.coords)[:-1])[::-1] for ring in part.interiors
            )
            out.append((_without_touch_points(outline, holes), holes))
        elif hasattr(part, "geoms"):
            out.extend(_pieces_with_holes(part))
    return out
