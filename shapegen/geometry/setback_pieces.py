"""CityEngine's ``setback`` pieces: each branch's part of the set-back band, as faces that may
have holes, and the remainder, on a face that may have holes.

:func:`shapegen.geometry.polygon2d.setback` gives the straight skeleton's strip of each edge and
the remainder. CityEngine's runtime does not hand out those strips (measured with PyPRT 1.12,
tests/data/prt_setback.json):

- the edges a branch selects give one region, their strips joined: ``all`` on a rectangle is a
  ring, one face with a hole; ``front | side`` gives the front strip and a U-shaped face;
  pieces that do not touch are faces of their own (``:`` one shape each, ``=`` one shape);
- where strips of edges of two branches meet, the branch written first takes the corner
  whole: ``left | back`` on a 12 x 8 m lot gives left 2 x 8 m and back 10 x 2 m,
  ``back | left`` back 12 x 2 m and left 2 x 6 m; at a reflex corner the first branch's band
  runs on across the other edge's strip (the L lot's ``back`` piece reaches down to the other
  edge's set-back line);
- a face's holes are not set back: each hole stays a hole of the piece around it (the band or
  the remainder), and where a hole cuts the remainder in two there are two pieces;
- the original corners (of the outline and of the holes) that lie on a piece's edge are
  corners of that piece (the L lot's reflex corner on its back piece and its remainder).

So a branch's region is the band of each of its edges (the parallel strip, d deep, as long as
the edge's skeleton strip reaches along it) within the whole set-back area, less what the
branches before it took.
"""

from __future__ import annotations

__all__ = ["Piece", "SetbackPieces", "setback_pieces", "setback_to_area"]

import math
from dataclasses import dataclass

import numpy as np
import shapely
from shapely.errors import GEOSException
from shapely.geometry import Polygon as ShapelyPolygon
from shapely.geometry.polygon import orient

from shapegen.errors import GeometryError
from shapegen.geometry.polygon2d import checked_polygon, setback, signed_area
from shapegen.tolerances import DEFAULT

Piece = tuple[np.ndarray, tuple[np.ndarray, ...]]
"""A face: its outer ring (counter-clockwise ``(k, 2)``) and its holes (clockwise)."""


@dataclass(frozen=True)
class SetbackPieces:
    """The result of :func:`setback_pieces`.

    Attributes
    ----------
    groups
        For each group of edges (a branch), in the order given, its pieces.
    remainder
        What is left of the face, its pieces with the holes inside them.
    """

    groups: tuple[tuple[Piece, ...], ...]
    remainder: tuple[Piece, ...]


def setback_pieces(polygon, holes, distances, groups) -> SetbackPieces:
    """Set each edge ``k`` of ``polygon`` (counter-clockwise, with clockwise ``holes``) back by
    ``distances[k]`` (m, >= 0) and give each group of edges (lists of edge indices, the
    branches in the order written) its part of the band, as CityEngine's runtime does (see the
    module's description). The holes are not set back."""
    p = checked_polygon(polygon)
    rings = [np.asarray(h, dtype=float).reshape(-1, 2) for h in holes]
    d = np.asarray(distances, dtype=float).reshape(-1)
    base = setback(p, d)
    size = float(np.ptp(p, axis=0).max())
    eps = DEFAULT.merge_rel * max(1.0, size) * 1e3
    corners = np.concatenate([p, *rings]) if rings else p
    owner = {k: g for g, edges in enumerate(groups) for k in edges}
    out: list[list[Piece]] = [[] for _ in groups]
    if not base.strips:  # nothing set back: the face is the remainder
        return SetbackPieces(tuple(() for _ in groups), ((p.copy(), tuple(rings)),))
    if not base.remainder:  # nothing left: the face is one piece, of its first set-back edge
        k = base.strips[0][0]
        if k in owner:
            out[owner[k]].append((p.copy(), tuple(rings)))
        return SetbackPieces(tuple(map(tuple, out)), ())
    outline = ShapelyPolygon(p)
    inner = shapely.union_all([ShapelyPolygon(r) for r in base.remainder])
    hole_area = shapely.union_all([ShapelyPolygon(r) for r in rings]) if rings else None
    strips = dict(base.strips)
    chosen = [[k for k in edges if d[k] > 0 and k in strips] for edges in groups]
    strip_areas = {k: shapely.make_valid(ShapelyPolygon(strip)) for k, strip in strips.items()}
    band_area = outline.difference(inner)
    if abs(band_area.area - (outline.area - inner.area)) > eps * max(outline.length, 1.0):
        # GEOS's difference can miss a remainder that runs along the outline (an edge that
        # stays put); the skeleton's strips make the same band
        band_area = shapely.union_all(list(strip_areas.values()))
    try:
        regions = _regions(
            chosen, band_area, lambda k: _band(p, k, d[k], strips[k]).union(strip_areas[k])
        )  # the strip too: where the skeleton's strip reaches past the band (a split event)
    except GEOSException:
        regions = None
    if regions is None or not _tiles(regions, band_area, eps):
        # the booleans of nearly touching bands went wrong (seen on random polygons with
        # reflex corners): each branch takes its edges' skeleton strips, which tile the band
        try:
            regions = _regions(chosen, band_area, strip_areas.__getitem__)
        except GEOSException as exc:
            raise GeometryError(f"setback: the pieces cannot be cut ({exc})") from None
        if not _tiles(regions, band_area, eps):
            raise GeometryError("setback: its pieces do not cover the set-back band once")
    for g, region in enumerate(regions):
        if region is None:
            continue
        if hole_area is not None:
            region = region.difference(hole_area)
        moved = sorted(chosen[g])  # a 0 edge's line starts no piece
        pieces = (_piece(part, corners, eps, p) for part in _polygons(region, eps))
        out[g] = [_started(piece, p, moved, d) for piece in pieces if piece is not None]
    if hole_area is None:
        remainder = tuple((_with_corners(r, corners, eps), ()) for r in base.remainder)
    else:
        remainder = tuple(_remainder_with_holes(base.remainder, rings, hole_area, corners, eps))
    return SetbackPieces(tuple(map(tuple, out)), remainder)


def _regions(chosen: list[list[int]], band_area, area_of) -> list:
    """Each group's region: the union of ``area_of(k)`` over its edges within the band, less
    what the groups before it took (None for a group without a set-back edge)."""
    regions: list = []
    taken = None
    for edges in chosen:
        if not edges:
            regions.append(None)
            continue
        region = shapely.union_all([area_of(k) for k in edges]).intersection(band_area)
        if taken is not None:
            region = region.difference(taken)
        taken = region if taken is None else taken.union(region)
        regions.append(region)
    return regions


def _tiles(regions: list, band_area, eps: float) -> bool:
    """Whether the regions cover no more of the band than it has (they do not overlap)."""
    total = sum(r.area for r in regions if r is not None)
    return total <= band_area.area + eps * max(band_area.length, 1.0)


def _band(p: np.ndarray, k: int, depth: float, strip: np.ndarray):
    """Edge ``k``'s band: the strip between its line and the line ``depth`` inside, as long
    along the edge as its skeleton strip reaches (its sides exact: past a reflex corner even
    the edge's own line runs inside the face)."""
    a, b = p[k], p[(k + 1) % len(p)]
    u = (b - a) / np.linalg.norm(b - a)
    n = np.array([-u[1], u[0]])  # inward: the polygon is counter-clockwise
    along = (strip - a) @ u
    lo, hi = float(along.min()), float(along.max())
    return ShapelyPolygon([a + lo * u, a + hi * u, a + hi * u + depth * n, a + lo * u + depth * n])


def _polygons(geometry, eps: float) -> list[ShapelyPolygon]:
    """The polygons of a shapely result, slivers (less than ``eps`` wide) dropped."""
    out = []
    for part in getattr(geometry, "geoms", [geometry]):
        if isinstance(part, ShapelyPolygon):
            if not part.is_empty and part.area > eps * max(part.length, 1.0):
                out.append(orient(part, 1.0))
        elif hasattr(part, "geoms"):
            out.extend(_polygons(part, eps))
    return out


def _clean(ring: np.ndarray, corners: np.ndarray, eps: float) -> np.ndarray:
    """``ring`` without repeated points and without corners in a straight line that are not
    original corners of the face (a boolean's seams), with the original corners that lie on
    its edges added."""
    points = [q for i, q in enumerate(ring) if np.linalg.norm(q - ring[i - 1]) > eps]
    changed = True
    while changed and len(points) > 3:
        changed = False
        for i in range(len(points)):
            prev, q, nxt = points[i - 1], points[i], points[(i + 1) % len(points)]
            seam = _on_segment(q, prev, nxt, eps) and not _is_corner(q, corners, eps)
            if seam or _spike(prev, q, nxt, eps):
                del points[i]
                changed = True
                break
    return _with_corners(np.array(points), corners, eps)


def _deduplicated(ring: np.ndarray, eps: float) -> np.ndarray:
    """``ring`` without corners repeated one after the other."""
    return np.array([q for i, q in enumerate(ring) if np.linalg.norm(q - ring[i - 1]) > eps])


def _with_corners(ring: np.ndarray, corners: np.ndarray, eps: float) -> np.ndarray:
    """``ring`` with the original ``corners`` that lie inside its edges added, in order."""
    out = []
    n = len(ring)
    for i in range(n):
        a, b = ring[i], ring[(i + 1) % n]
        out.append(a)
        on = [
            c for c in corners
            if _on_segment(c, a, b, eps)
            and np.linalg.norm(c - a) > eps and np.linalg.norm(c - b) > eps
        ]  # fmt: skip
        out.extend(sorted(on, key=lambda c, a=a: float(np.linalg.norm(c - a))))
    return np.array(out)


def _spike(prev, q, nxt, eps: float) -> bool:
    """Whether the ring runs out to ``q`` and straight back (a boolean's zero-wide spike)."""
    a, b = q - prev, nxt - q
    la, lb = float(np.linalg.norm(a)), float(np.linalg.norm(b))
    if la <= eps or lb <= eps:
        return True
    return abs(float(a[0] * b[1] - a[1] * b[0])) <= eps * max(la, lb) and float(a @ b) < 0


def _on_segment(q, a, b, eps: float) -> bool:
    ab = b - a
    length = float(np.linalg.norm(ab))
    if length <= eps:
        return False
    t = float((q - a) @ ab) / length
    off = abs(float(ab[0] * (q - a)[1] - ab[1] * (q - a)[0])) / length
    return -eps <= t <= length + eps and off <= eps


def _is_corner(q, corners: np.ndarray, eps: float) -> bool:
    return bool((np.linalg.norm(corners - q, axis=1) <= eps).any())


def _piece(part: ShapelyPolygon, corners: np.ndarray, eps: float, outline=None) -> Piece | None:
    """A shapely polygon as a piece, its rings cleaned (:func:`_clean`): the outer ring with
    the corners of the face's ``outline`` (all ``corners`` when not given), the holes with all
    the face's corners, as PyPRT's pieces have them (a hole of the face on the edge of a
    piece's outer ring adds no corner to it, one on the edge of a piece's hole does)."""
    outer = _clean(
        np.asarray(part.exterior.coords)[:-1], corners if outline is None else outline, eps
    )
    holes = [_clean(np.asarray(r.coords)[:-1], corners, eps) for r in part.interiors]
    holes = [ring for ring in holes if len(ring) >= 3]
    if len(outer) >= 3:
        cleaned = ShapelyPolygon(outer, holes)
        if not cleaned.is_valid or abs(cleaned.area - part.area) > eps * max(part.length, 1.0):
            # cleaning a sliver's corner made the rings cross: the boolean's rings as they are
            outer = _deduplicated(np.asarray(part.exterior.coords)[:-1], eps)
            holes = [_deduplicated(np.asarray(r.coords)[:-1], eps) for r in part.interiors]
    if len(outer) < 3 or signed_area(outer) <= eps * eps:
        return None
    return outer, tuple(holes)


def _started(piece: Piece, p: np.ndarray, edges: list[int], d: np.ndarray) -> Piece:
    """``piece`` with its outer ring starting where it runs along the first of ``edges`` (the
    set-back ones of its branch) it touches, as the edge runs, its holes where they run back
    along that edge's set-back line (as PyPRT's pieces start)."""
    outer, holes = piece
    n = len(p)
    for k in edges:
        a, b = p[k], p[(k + 1) % n]
        start = _run_along(outer, a, b, same_direction=True)
        if start is not None:
            u = (b - a) / np.linalg.norm(b - a)
            shift = d[k] * np.array([-u[1], u[0]])
            turned = []
            for hole in holes:
                i = _run_along(hole, a + shift, b + shift, same_direction=False)
                turned.append(hole if i is None else np.roll(hole, -i, axis=0))
            return np.roll(outer, -start, axis=0), tuple(turned)
    return piece


def _run_along(ring: np.ndarray, a, b, same_direction: bool) -> int | None:
    """The first corner of ``ring`` whose edge lies on the line through ``a`` and ``b``,
    running the same way (or the other way), or None."""
    u = (b - a) / np.linalg.norm(b - a)
    scale = max(1.0, float(np.abs(ring).max()))
    tol = DEFAULT.convex_rel * scale  # a corner this near a line is on it, as on a plane
    n = len(ring)
    for i in range(n):
        q, r = ring[i], ring[(i + 1) % n]
        v = r - q
        length = float(np.linalg.norm(v))
        if length <= tol:
            continue
        off_q = abs(float(u[0] * (q - a)[1] - u[1] * (q - a)[0]))
        off_r = abs(float(u[0] * (r - a)[1] - u[1] * (r - a)[0]))
        facing = float(v @ u) / length
        if off_q <= tol and off_r <= tol and (facing > 0.5 if same_direction else facing < -0.5):
            # the start of the run: step back over edges on the same line
            j = i
            for _ in range(n):
                prev = ring[j - 1]
                if abs(float(u[0] * (prev - a)[1] - u[1] * (prev - a)[0])) > tol:
                    break
                j = (j - 1) % n
            return j
    return None


def _strictly_inside(piece: ShapelyPolygon, hole: ShapelyPolygon, eps: float) -> bool:
    """Whether ``hole`` lies inside ``piece`` without touching its outline."""
    return piece.contains(hole) and piece.exterior.distance(hole) > eps


def _remainder_with_holes(remainder, rings, hole_area, corners, eps) -> list[Piece]:
    """The remainder's pieces less the face's holes: a hole inside a piece is its hole as
    the face had it; a hole across its edge cuts it (shapely's result)."""
    out: list[Piece] = []
    for ring in remainder:
        piece = ShapelyPolygon(ring)
        inside = [h for h in rings if _strictly_inside(piece, ShapelyPolygon(h), eps)]
        meeting = sum(piece.intersects(ShapelyPolygon(h)) for h in rings)
        if meeting == len(inside):  # no hole across the piece's outline
            out.append((_with_corners(ring, corners, eps), tuple(h.copy() for h in inside)))
            continue
        for part in _polygons(piece.difference(hole_area), eps):
            made = _piece(part, corners, eps)
            if made is not None:
                out.append(made)
    return out


def setback_to_area(
    polygon, area: float, selected, min_distances=None, max_distances=None, holes=()
):
    """CGA's ``setbackToArea``: the setback whose remainder has ``area`` (m²).

    The ``selected`` edges (booleans) are set back by ``min_distances + c`` (clamped to
    ``max_distances``) with the common ``c`` >= 0 found by bisection; the others stay. With
    ``holes`` (clockwise rings, not set back) a remainder's area is its pieces' less the holes
    they keep (:func:`setback_pieces`; CityEngine's runtime:
    a 12 x 8 m lot with a 4 x 2 m hole set back to 40 m² leaves a 48 m² ring around the hole,
    tests/data/prt_setback_holes.json). With no edge selected nothing is set back (the runtime
    gives the whole face as the remainder).

    Returns
    -------
    (Setback of the outline, distances)
    """
    p = checked_polygon(polygon)
    n = len(p)
    rings = [np.asarray(h, dtype=float).reshape(-1, 2) for h in holes]
    selected = np.asarray(selected, dtype=bool).reshape(n)
    low = np.zeros(n) if min_distances is None else np.asarray(min_distances, float).reshape(n)
    high = np.full(n, np.inf) if max_distances is None else np.asarray(max_distances, float)
    total = signed_area(p) + sum(map(signed_area, rings))
    if not (math.isfinite(area) and 0 < area):
        raise GeometryError(f"setbackToArea needs an area > 0, got {area}")
    if area > total:
        raise GeometryError(f"setbackToArea: the face has {total:.6g} m², less than {area:.6g}")
    if not selected.any():
        return setback(p, np.zeros(n)), np.zeros(n)

    def distances(c: float) -> np.ndarray:
        return np.where(selected, np.maximum(np.minimum(low + c, high.reshape(n)), 0.0), 0.0)

    def remaining(c: float) -> float:
        if not rings:
            return sum(signed_area(r) for r in setback(p, distances(c)).remainder)
        pieces = setback_pieces(p, rings, distances(c), [list(np.flatnonzero(selected))])
        return sum(
            signed_area(outer) + sum(map(signed_area, inner)) for outer, inner in pieces.remainder
        )

    if remaining(0.0) < area:
        raise GeometryError("setbackToArea: the minimum distances already leave less than the area")
    lo, hi = 0.0, float(np.ptp(p, axis=0).max())
    if remaining(hi) > area:
        raise GeometryError("setbackToArea: the maximum distances leave more than the area")
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        if remaining(mid) > area:
            lo = mid
        else:
            hi = mid
    found = distances(0.5 * (lo + hi))
    return setback(p, found), found
