"""CGA's ``innerRectangle``: the largest rectangle inside a polygon (and outside its holes),
parallel to the axes or to one of its edges, and the remainder cut along its sides.

A polygon is an ``(n, 2)`` array of vertices in metres, counter-clockwise, as in
:mod:`shapegen.geometry.polygon2d`. In a convex polygon without holes the rectangle is the exact
optimum (a concave problem, solved by SLSQP); otherwise a grid search through the corners,
refined around the best rectangle.
"""

from __future__ import annotations

__all__ = ["inner_rectangle"]

import math

import numpy as np
import shapely
from shapely.geometry import Polygon as ShapelyPolygon

from shapegen.errors import GeometryError
from shapegen.geometry.polygon2d import (
    checked_polygon,
    counter_clockwise,
    polygon_pieces,
    signed_area,
)
from shapegen.limits import check_clock
from shapegen.tolerances import COINCIDENT_REL, DEFAULT, DIVISION_FLOOR, ROUNDOFF_REL

#: The largest inscribed rectangle's SLSQP stops when its objective (the log of the area) moves
#: by less than this (a solver setting, not a comparison).
RECTANGLE_FTOL = 1e-12


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
        for r in polygon_pieces(turned.intersection(region)):
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
