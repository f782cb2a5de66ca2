"""CityEngine's roofs and taper on one flat face, as polygon meshes in the face's frame.

The face is a counter-clockwise ``(n, 2)`` polygon in its own plane (metres); a roof is a
:class:`RoofMesh` whose vertices are ``(x, y, h)`` with ``h`` the height above the face along
its normal. Faces are counter-clockwise seen from outside; the first is the original face
turned down (``roof.bottom``), then one face per edge in edge order, each starting with its
edge, as CityEngine builds them:

- :func:`roof_hip`: every edge carries a plane at ``angle``; the planes meet along the
  straight skeleton (height = skeleton time times ``tan(angle)``);
- :func:`roof_gable`: as a hip roof, but the gable edges stay vertical (a weighted skeleton
  with weight 0 on them): the ends of a rectangle's ridge, each wing end of an L;
- :func:`roof_shed`: one plane rising from edge ``index``, vertical sides, a top;
- :func:`roof_pyramid`: the vertex average raised, joined to every edge;
- :func:`taper`: the vertex average raised, joined to every edge;
- :func:`envelope`: walls to a base height, then planes sloping inward at each edge's angle
  (a skeleton whose edges move at ``cot(angle)``), cut flat at a maximum height.

CGA's ``roofRidge``, two planes cut along a line rather than a skeleton, is
:func:`shapegen.geometry.ridge_roof.roof_ridge`.
"""

from __future__ import annotations

__all__ = [
    "RoofMesh",
    "roof_hip",
    "roof_gable",
    "roof_shed",
    "roof_pyramid",
    "taper",
    "envelope",
]

import math
from dataclasses import dataclass, replace

import numpy as np
import shapely
from shapely.geometry import LineString, Polygon

from shapegen.errors import GeometryError
from shapegen.geometry.polygon2d import checked_polygon, edge_normals, edges_moved_out, signed_area
from shapegen.geometry.ridges import even_ridge_times
from shapegen.geometry.skeleton import straight_skeleton
from shapegen.tolerances import DEFAULT, DIVISION_FLOOR, ROUNDOFF_REL


@dataclass(frozen=True)
class RoofMesh:
    """A polygon mesh in a face's frame.

    Attributes
    ----------
    vertices
        ``(m, 3)`` points ``(x, y, h)``, metres; ``h`` along the face's normal.
    faces
        Vertex-index tuples, counter-clockwise seen from outside.
    tags
        One CityEngine component tag per face (``roof.bottom``, ``roof.top``, ``roof.side``...).
    holes
        ``()``, or per face its hole rings (:attr:`~shapegen.geometry.mesh.Mesh.holes`).
    """

    vertices: np.ndarray
    faces: tuple[tuple[int, ...], ...]
    tags: tuple[str, ...]
    holes: tuple = ()
    punch_failed: bool = False  # envelope: its holes not punched (:func:`envelope`)

    def volume(self) -> float:
        """Enclosed volume (m³) by the divergence theorem (meaningful for a closed mesh)."""
        total = 0.0
        for face in self.faces:
            p = self.vertices[list(face)]
            for k in range(1, len(p) - 1):
                total += float(np.dot(p[0], np.cross(p[k], p[k + 1]))) / 6.0
        return total


class _Welder:
    """Collects points and faces, one index per distinct point."""

    _NEAR = [(i, j, k) for i in (-1, 0, 1) for j in (-1, 0, 1) for k in (-1, 0, 1)]

    def __init__(self, size: float):
        self.eps = DEFAULT.merge_rel * max(size, DIVISION_FLOOR) * 10
        self.points: list[np.ndarray] = []
        self.faces: list[tuple[int, ...]] = []
        self.tags: list[str] = []
        self.holes: list[tuple[tuple[int, ...], ...]] = []
        self.cells: dict[tuple[int, int, int], list[int]] = {}  # grid of cell size eps

    def index(self, point) -> int:
        point = np.asarray(point, dtype=float)
        cell = tuple(int(c) for c in np.floor(point / self.eps))
        for di, dj, dk in self._NEAR:  # a point within eps lies in this cell or a neighbour
            for k in self.cells.get((cell[0] + di, cell[1] + dj, cell[2] + dk), ()):
                if np.abs(self.points[k] - point).max() <= self.eps:
                    return k
        self.points.append(point)
        self.cells.setdefault(cell, []).append(len(self.points) - 1)
        return len(self.points) - 1

    def ring(self, points) -> tuple[int, ...]:
        ids: list[int] = []
        for p in points:
            k = self.index(p)
            if not ids or ids[-1] != k:
                ids.append(k)
        while len(ids) > 1 and ids[0] == ids[-1]:
            ids.pop()
        return tuple(ids)

    def face(self, points, tag: str, holes=()) -> None:
        ids = self.ring(points)
        if len(ids) >= 3:
            self.faces.append(ids)
            self.tags.append(tag)
            rings = (self.ring(hole) for hole in holes)
            self.holes.append(tuple(r for r in rings if len(r) >= 3))

    def mesh(self) -> RoofMesh:
        holes = tuple(self.holes) if any(self.holes) else ()
        return RoofMesh(
            np.array(self.points).reshape(-1, 3), tuple(self.faces), tuple(self.tags), holes
        )


def _bottom(welder: _Welder, polygon: np.ndarray, tag: str, holes=()) -> None:
    welder.face([(x, y, 0.0) for x, y in polygon[::-1]], tag,
                [[(x, y, 0.0) for x, y in ring[::-1]] for ring in holes])  # fmt: skip


def _rings(holes) -> list[np.ndarray]:
    """A face's holes as clockwise ``(k, 2)`` rings (m)."""
    out = []
    for ring in holes:
        ring = np.asarray(ring, dtype=float).reshape(-1, 2)
        out.append(ring[::-1] if signed_area(ring) > 0 else ring)
    return out


def _slope(angle: float | None, height: float | None, reach: float) -> float:
    """tan of the roof planes: from an angle (degrees) or from a height over ``reach`` (m)."""
    if height is not None:
        if not math.isfinite(height):
            raise GeometryError(f"a roof height must be a finite number, got {height}")
        return height / reach if reach > 0 else 0.0
    if angle is None or not math.isfinite(angle) or not -90 < angle < 90:
        raise GeometryError(f"a roof angle must be between -90 and 90 degrees, got {angle}")
    return math.tan(math.radians(angle))


def _skeleton_roof(
    polygon: np.ndarray,
    weights: np.ndarray,
    angle: float | None,
    height: float | None,
    grow: np.ndarray,
    drop: float,
    even: bool,
    side_tags: list[str],
    holes: list[np.ndarray] = (),
) -> RoofMesh:
    if holes and even:  # PyPRT levels some ridges of a holed face, by a rule not traced
        raise GeometryError("an even roof (even = true) on a face with holes is not supported")
    if holes and np.all(grow > 0):
        return _overhung_holed_roof(polygon, weights, angle, grow, side_tags, holes)
    eaves, hole_eaves = polygon, list(holes)
    if np.any(grow):  # overhangs (negative ones set the eaves in)
        n = len(polygon)
        eaves = edges_moved_out(polygon, grow[:n])
        turned = np.einsum("ij,ij->i", edge_normals(eaves), edge_normals(polygon)) < 0
        if signed_area(eaves) <= 0 or np.any(turned) or not _simple(eaves):
            raise GeometryError("the roof's negative overhang is larger than the face")
        # a negative overhang sets a hole's eaves out, away from the hole
        hole_eaves = []
        for ring in holes:
            moved = edges_moved_out(ring, grow[n : n + len(ring)])
            n += len(ring)
            turned = np.einsum("ij,ij->i", edge_normals(moved), edge_normals(ring)) < 0
            if signed_area(moved) >= 0 or np.any(turned) or not _simple(moved[::-1]):
                raise GeometryError("the roof's overhang closes a hole of the face")
            hole_eaves.append(moved)
        if hole_eaves and not _simple(eaves, [r[::-1] for r in hole_eaves]):
            raise GeometryError("the roof's overhang makes the face's holes meet its outline")
    skeleton = straight_skeleton(eaves, weights=weights, holes=hole_eaves)
    slope = _slope(angle, height, float(skeleton.times.max()))
    times = skeleton.times
    if even:  # each ridge level, at its nodes' average height (non-planar faces, as CityEngine)
        eps = DEFAULT.merge_rel * max(float(np.ptp(eaves, axis=0).max()), DIVISION_FLOOR) * 10
        times = even_ridge_times(skeleton, -edge_normals(eaves), eps)
    # a gable stays on the face's edge when the roof overhangs (op_roofGable: the roof faces
    # overlap the eaves and the gables; PyPRT's parthenon, overhangY = -1.38 m, keeps its
    # pediments on the cornice's ends while its roof planes stop 1.38 m short of them)
    gables = [k for k, tag in enumerate(side_tags) if tag == "roof.side"]
    plain = None
    if gables and eaves is not polygon:
        plain = straight_skeleton(polygon, weights=weights)
    welder = _Welder(float(np.ptp(eaves, axis=0).max()))
    _bottom(welder, polygon, "roof.bottom", holes)
    for k in range(len(skeleton.faces)):
        if plain is not None and k in gables:
            ids = list(plain.faces[k])
            points = np.column_stack([plain.nodes[ids], plain.times[ids] * slope])
        else:
            ids = list(skeleton.faces[k])
            points = np.column_stack([skeleton.nodes[ids], times[ids] * slope - drop])
        welder.face(points, side_tags[k])
    return welder.mesh()


def _overhung_holed_roof(
    polygon: np.ndarray,
    weights: np.ndarray,
    angle: float,
    grow: np.ndarray,
    side_tags: list[str],
    holes: list[np.ndarray],
) -> RoofMesh:
    """A roof on a face with holes overhanging by ``grow`` (m, in plan), as PyPRT's: each plane
    of the face's roof carried past its edge (into the hole for a hole's edge) to the edge's
    line moved out by ``grow`` between its corners' bisectors, or to their meeting point where
    that comes first (the L courtyard's 1 m arms at 0.87 m); overhangs may overlap there."""
    skeleton = straight_skeleton(polygon, weights=weights, holes=holes)
    slope = _slope(angle, None, float(skeleton.times.max()))
    span = float(np.ptp(polygon, axis=0).max()) + 2 * float(grow.max())
    welder = _Welder(span)
    _bottom(welder, polygon, "roof.bottom", holes)
    start = 0
    for ring in [polygon, *holes]:
        m = len(ring)
        moved = edges_moved_out(ring, grow[start : start + m])
        for i in range(m):
            a, b = ring[i], ring[(i + 1) % m]
            ea, eb = moved[i], moved[(i + 1) % m]
            inner = [(*skeleton.nodes[q], skeleton.times[q] * slope)
                     for q in skeleton.faces[start + i][2:]]  # fmt: skip
            if (eb - ea) @ (b - a) > 0:  # the eave: the edge moved out, mitred
                d = float(grow[start + i]) * slope
                eave = [(*ea, -d), (*eb, -d)]
            else:  # the corners' bisectors meet first: the plane ends in a point
                tip = _meeting(a, ea, b, eb)
                u = (b - a) / np.linalg.norm(b - a)
                depth = float((tip - a) @ np.array([u[1], -u[0]]))  # out from the edge
                eave = [(*tip, -depth * slope)]
            welder.face([*eave, *inner], side_tags[start + i])
        start += m
    return welder.mesh()


def _meeting(a, ea, b, eb) -> np.ndarray:
    """Where the line from ``a`` through ``ea`` meets the line from ``b`` through ``eb``."""
    da, db = ea - a, eb - b
    det = da[0] * db[1] - da[1] * db[0]
    if abs(det) <= ROUNDOFF_REL * float(np.dot(da, da) + np.dot(db, db)):
        return 0.5 * (ea + eb)
    s = ((b - a)[0] * db[1] - (b - a)[1] * db[0]) / det
    return a + s * da


def roof_hip(
    polygon,
    angle: float | None = None,
    *,
    height: float | None = None,
    overhang: float = 0.0,
    even: bool = False,
    holes=(),
) -> RoofMesh:
    """A hip roof: a plane at ``angle`` (degrees) on every edge, meeting along the skeleton.

    ``height`` (m) instead of ``angle`` gives the highest ridge that height. ``overhang`` (m,
    measured on the roof plane) extends the roof faces beyond the edges and below the face.
    ``holes`` (rings inside the polygon) stay holes of the bottom, their edges carrying planes
    after the outline's, as CityEngine's runtime builds them (tests/data/prt_roofs.json).
    """
    p = checked_polygon(polygon)
    rings = _rings(holes)
    grow, drop = _overhang(angle, height, overhang)
    n = len(p) + sum(map(len, rings))
    return _skeleton_roof(
        p, np.ones(n), angle, height, np.full(n, grow), drop, even, ["roof.top"] * n, rings
    )


def _overhang(angle, height, overhang) -> tuple[float, float]:
    if not math.isfinite(overhang):
        raise GeometryError(f"a roof overhang must be a finite number, got {overhang}")
    if overhang == 0:
        return 0.0, 0.0
    if angle is None:
        raise GeometryError("a roof overhang needs the roof's angle (byAngle)")
    a = math.radians(angle)
    return overhang * math.cos(a), overhang * math.sin(a)


def gable_edges(polygon, index: int | None = None) -> np.ndarray:
    """Which edges of ``polygon`` are gables (booleans).

    With ``index`` (a convex polygon): the edges parallel within 45 degrees to edge ``index``.
    Otherwise the ends of the ridges: the edges whose hip-roof face is a triangle, shortest
    first, never two neighbours, leaving at least two eaves.
    """
    p = checked_polygon(polygon)
    n = len(p)
    d = np.roll(p, -1, axis=0) - p
    lengths = np.linalg.norm(d, axis=1)
    u = d / lengths[:, None]
    if index is not None:
        k = int(index) % n
        return np.abs(u @ u[k]) >= math.cos(math.radians(45)) - ROUNDOFF_REL
    skeleton = straight_skeleton(p)
    triangles = [k for k in range(n) if len(skeleton.face_points(k)) == 3]
    chosen = np.zeros(n, dtype=bool)
    for k in sorted(triangles, key=lambda k: lengths[k]):
        if chosen[(k - 1) % n] or chosen[(k + 1) % n] or n - chosen.sum() - 1 < 2:
            continue
        chosen[k] = True
    return chosen


def roof_gable(
    polygon,
    angle: float | None = None,
    *,
    height: float | None = None,
    overhang_x: float = 0.0,
    overhang_y: float = 0.0,
    even: bool = False,
    index: int | None = None,
    holes=(),
) -> RoofMesh:
    """A gable roof: planes at ``angle`` (degrees) on the eaves, vertical gables on the ends.

    ``overhang_x`` (m, on the roof plane) extends the roof faces beyond the eaves,
    ``overhang_y`` (m) beyond the gables (negative: short of them); the gables stay on the
    face's edges. ``index`` makes the edges parallel to that edge the gables (convex faces
    only, as CityEngine). On a face with ``holes`` CityEngine's runtime makes no gables: the
    roof is :func:`roof_hip`'s with ``overhang_x`` on every edge (tests/data/prt_roofs.json,
    every lot, angle and overhang).
    """
    if len(holes):  # overhang_y is not used there (PyPRT's roofGable(30, 1, 0.5) is (30, 1, 1))
        return roof_hip(polygon, angle, height=height, overhang=overhang_x, even=even, holes=holes)
    p = checked_polygon(polygon)
    if index is not None and not gable_index_applies(p):
        index = None
    gables = gable_edges(p, index)
    grow_x, drop = _overhang(angle, height, overhang_x)
    if not math.isfinite(overhang_y):
        raise GeometryError(f"a roof overhang must be a finite number, got {overhang_y}")
    grow = np.where(gables, overhang_y, grow_x)
    weights = np.where(gables, 0.0, 1.0)
    tags = ["roof.side" if g else "roof.top" for g in gables]
    return _skeleton_roof(p, weights, angle, height, grow, drop, even, tags)


def gable_index_applies(polygon, holes=()) -> bool:
    """Whether roofGable's ``index`` orients this face's gables: on a convex face without holes
    only (op_roofGable; PyPRT warns "Gable roof: can not apply index!" on others)."""
    if len(holes):
        return False
    p = checked_polygon(polygon)
    d = np.roll(p, -1, axis=0) - p
    cross = d[:, 0] * np.roll(d[:, 1], -1) - d[:, 1] * np.roll(d[:, 0], -1)
    return bool(np.all(cross >= -ROUNDOFF_REL * float(np.abs(cross).max())))


def _simple(p: np.ndarray, holes=()) -> bool:
    from shapely.geometry import Polygon

    return bool(Polygon(p, holes).is_valid)


def roof_shed(
    polygon,
    angle: float | None = None,
    *,
    height: float | None = None,
    index: int = 0,
    holes=(),
) -> RoofMesh:
    """A shed roof: one plane through edge ``index`` rising inward at ``angle`` (degrees).

    ``height`` (m) instead of ``angle`` makes the highest point that high. Vertical side faces
    close it (``roof.side.outer``); a side of zero height is left out. ``holes`` (clockwise
    rings inside the polygon) stay holes of the bottom and the roof, with walls of their own
    (``roof.side.inner``), as CityEngine's runtime builds them (tests/data/prt_holes.json).
    """
    p = checked_polygon(polygon)
    n = len(p)
    k = int(index) % n
    inward = -edge_normals(p)[k]
    reach = (p - p[k]) @ inward
    slope = _slope(angle, height, float(reach.max()))
    welder = _Welder(float(np.ptp(p, axis=0).max()))
    rings = [np.asarray(r, dtype=float).reshape(-1, 2) for r in holes]
    welder.face([(x, y, 0.0) for x, y in p[::-1]], "roof.bottom",
                [[(x, y, 0.0) for x, y in r[::-1]] for r in rings])  # fmt: skip
    walls = [(p, "roof.side.outer"), *((r, "roof.side.inner") for r in rings)]
    heights = [((ring - p[k]) @ inward) * slope for ring, _ in walls]
    lifted = [[(*q, z) for q, z in zip(ring, h, strict=True)]
              for (ring, _), h in zip(walls, heights, strict=True)]  # fmt: skip
    # the roof face first, then the walls: a split's cap on the shed then begins at the roof
    # face's cut, as PyPRT's saltbox has it (Building_From_FootprintSMALL: its gable on the cap,
    # by the cap's last edge, runs across the shed's low edge)
    welder.face(lifted[0], "roof.top", lifted[1:])
    for (ring, name), h in zip(walls, heights, strict=True):
        m = len(ring)
        for e in range(m):
            a, b = e, (e + 1) % m
            welder.face([(*ring[a], 0.0), (*ring[b], 0.0), (*ring[b], h[b]), (*ring[a], h[a])],
                        name)  # fmt: skip
    return welder.mesh()


def _apex_roof(p: np.ndarray, apex: np.ndarray, rise: float, bottom: str, side: str):
    welder = _Welder(float(np.ptp(p, axis=0).max()))
    _bottom(welder, p, bottom)
    top = (*apex, rise)
    for e in range(len(p)):
        welder.face([(*p[e], 0.0), (*p[(e + 1) % len(p)], 0.0), top], side)
    return welder.mesh()


def roof_pyramid(polygon, angle: float | None = None, *, height: float | None = None):
    """A pyramid roof: the vertex average raised and joined to every edge.

    By angle (degrees), the line from the first edge's midpoint to the apex makes that angle
    with the face, as PyPRT's (tests/data/prt_roofs.json: the L's apex, 3.8538 m at 30 degrees,
    is 6.675 m from the midpoint, 6.667 m from the edge's line).
    """
    p = checked_polygon(polygon)
    apex = p.mean(axis=0)
    reach = float(np.linalg.norm(apex - 0.5 * (p[0] + p[1])))
    rise = height if height is not None else _slope(angle, None, reach) * reach
    return _apex_roof(p, apex, float(rise), "roof.bottom", "roof.top")


def taper(polygon, height: float) -> RoofMesh:
    """CGA's ``taper(height)``: the face's vertex average raised by ``height`` (m), joined to
    every edge (``taper.bottom``, ``taper.side``). The vertex average, not the area centroid,
    as CityEngine's runtime (tests/data/prt_taper_envelope.json: the L lot's apex at
    (6.667, 5.667), its vertices' mean; its area centroid is (5.5, 4.5))."""
    p = checked_polygon(polygon)
    if not math.isfinite(height):
        raise GeometryError(f"taper height must be a finite number, got {height}")
    mesh = _apex_roof(p, p.mean(axis=0), float(height), "taper.bottom", "taper.side")
    if height < 0:  # downward: turn every face so they still face outward
        mesh = RoofMesh(mesh.vertices, tuple(f[::-1] for f in mesh.faces), mesh.tags)
    return mesh


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
    rings = _rings(holes)
    welder = _Welder(float(max(np.ptp(p, axis=0).max(), max_height)))
    _bottom(welder, p, "envelope.bottom", rings)
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


def _punched(welder: _Welder, sides, rings: list[np.ndarray]) -> bool:
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
