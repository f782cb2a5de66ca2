"""CityEngine's roofs and taper on one flat face, as polygon meshes in the face's frame.

The face is a counter-clockwise ``(n, 2)`` polygon in its own plane (metres); a roof is a
:class:`~shapegen.geometry.roof_mesh.RoofMesh` whose vertices are ``(x, y, h)`` with ``h`` the
height above the face along its normal. Faces are counter-clockwise seen from outside; the
first is the original face turned down (``roof.bottom``), then one face per edge in edge
order, each starting with its edge, as CityEngine builds them:

- :func:`roof_hip`: every edge carries a plane at ``angle``; the planes meet along the
  straight skeleton (height = skeleton time times ``tan(angle)``);
- :func:`roof_gable`: as a hip roof, but the gable edges stay vertical (a weighted skeleton
  with weight 0 on them): the ends of a rectangle's ridge, each wing end of an L;
- :func:`roof_shed`: one plane rising from edge ``index``, vertical sides, a top;
- :func:`roof_pyramid`: the vertex average raised, joined to every edge;
- :func:`taper`: the vertex average raised, joined to every edge.

CGA's ``envelope`` is :func:`shapegen.geometry.envelope.envelope`; ``roofRidge``, two planes
cut along a line rather than a skeleton, is :func:`shapegen.geometry.ridge_roof.roof_ridge`;
the mesh they all make is :mod:`shapegen.geometry.roof_mesh`'s.
"""

from __future__ import annotations

__all__ = [
    "roof_hip",
    "roof_gable",
    "roof_shed",
    "roof_pyramid",
    "taper",
]

import math

import numpy as np
from shapely.geometry import Polygon

from shapegen.errors import GeometryError
from shapegen.geometry.polygon2d import checked_polygon, edge_normals, edges_moved_out, signed_area
from shapegen.geometry.ridges import even_ridge_times
from shapegen.geometry.roof_mesh import RoofMesh, Welder, bottom_face, clockwise_rings, roof_slope
from shapegen.geometry.skeleton import straight_skeleton
from shapegen.tolerances import COSINE_SLACK, DEFAULT, DIVISION_FLOOR, ROUNDOFF_REL


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
    slope = roof_slope(angle, height, float(skeleton.times.max()))
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
    welder = Welder(float(np.ptp(eaves, axis=0).max()))
    bottom_face(welder, polygon, "roof.bottom", holes)
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
    slope = roof_slope(angle, None, float(skeleton.times.max()))
    span = float(np.ptp(polygon, axis=0).max()) + 2 * float(grow.max())
    welder = Welder(span)
    bottom_face(welder, polygon, "roof.bottom", holes)
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
    rings = clockwise_rings(holes)
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
    """Which edges of ``polygon`` are gables (booleans), as CityEngine's runtime picks them
    (tests/data/prt_gables.json).

    With ``index`` (a convex polygon): edges ``index`` and ``index + 2`` (modulo the corners),
    whatever the polygon: a quadrilateral's opposite pair, a hexagon's edges 0 and 2 for index
    0, as PyPRT on lots of 3 to 8 edges.

    Without: a rectangle's gables are its shorter pair; a square's are edges 1 and 3, so that
    its ridge runs along the first edge, whatever the square's turn, first corner or winding.
    Otherwise the ends of the ridges of the polygon without its straight corners: the edges
    whose hip-roof face is a triangle whose apex only that face and its two neighbours reach (a
    ridge's end, however short: 4e-8 m on a 10 m square 1 mm out of square; where more faces
    meet, as at a kite's, a rhombus's, a triangle's or a pointed end's single apex, the roof
    stays hipped there), shortest first, never two neighbours, leaving at least two eaves.
    """
    p = checked_polygon(polygon)
    n = len(p)
    d = np.roll(p, -1, axis=0) - p
    lengths = np.linalg.norm(d, axis=1)
    u = d / lengths[:, None]
    chosen = np.zeros(n, dtype=bool)
    if index is not None:
        k = int(index) % n
        chosen[[k, (k + 2) % n]] = True
        return chosen
    if n == 4 and np.all(np.abs(np.einsum("ij,ij->i", u, np.roll(u, -1, axis=0))) <= COSINE_SLACK):
        tie = DEFAULT.merge_rel * float(lengths.max())
        first = 0 if lengths[0] < lengths[1] - tie else 1  # a tie: the ridge along edge 0
        chosen[[first, first + 2]] = True
        return chosen
    # a corner on a straight run is not one (PyPRT: a 12 x 8 m rectangle with a fifth corner
    # halfway along a long edge keeps the rectangle's gables, a square with one stays hipped);
    # each edge of the run is a gable if the run is
    cross = u[:, 0] * np.roll(u[:, 1], 1) - u[:, 1] * np.roll(u[:, 0], 1)
    straight = (np.abs(cross) <= COSINE_SLACK) & (np.einsum("ij,ij->i", u, np.roll(u, 1, 0)) > 0)
    corners = np.flatnonzero(~straight)
    if len(corners) < 3:
        return chosen
    run = np.searchsorted(corners, np.arange(n), side="right") - 1  # edge -> its run
    ends = _ridge_ends(p[corners])
    return ends[run % len(corners)]


def _ridge_ends(p: np.ndarray) -> np.ndarray:
    """The gables of a polygon without straight corners: the edges whose hip-roof face is a
    triangle at a ridge's end, shortest first, never two neighbours, at least two eaves left."""
    n = len(p)
    lengths = np.linalg.norm(np.roll(p, -1, axis=0) - p, axis=1)
    skeleton = straight_skeleton(p)
    # one point: within merge_rel of the size (a 10 m parallelogram 1 mm out of square has a
    # 4e-8 m ridge, gabled by PyPRT; a rhombus's apex, off by round-off, is one point)
    eps = DEFAULT.merge_rel * max(float(np.ptp(p, axis=0).max()), DIVISION_FLOOR)
    faces = [_distinct(skeleton.nodes[list(face)], eps) for face in skeleton.faces]
    ends = []
    for k, face in enumerate(faces):
        if len(face) != 3:
            continue
        apex = face[2]  # a face starts with its edge
        meeting = sum(bool(np.any(np.linalg.norm(f - apex, axis=1) <= eps)) for f in faces)
        if meeting == 3 < n:  # a triangle's three faces meet at its apex: no ridge, a hip
            ends.append(k)
    chosen = np.zeros(n, dtype=bool)
    for k in sorted(ends, key=lambda k: lengths[k]):
        if chosen[(k - 1) % n] or chosen[(k + 1) % n] or n - chosen.sum() - 1 < 2:
            continue
        chosen[k] = True
    return chosen


def _distinct(points: np.ndarray, eps: float) -> np.ndarray:
    """A face's corners without repeats (consecutive points within ``eps``, first and last)."""
    keep = [q for i, q in enumerate(points) if np.linalg.norm(q - points[i - 1]) > eps]
    return np.array(keep or points[:1]).reshape(-1, 2)


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
    face's edges. ``index`` makes that edge and the one two further on the gables (convex
    faces only, as CityEngine). On a face with ``holes`` CityEngine's runtime makes no gables: the
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
    slope = roof_slope(angle, height, float(reach.max()))
    welder = Welder(float(np.ptp(p, axis=0).max()))
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
    welder = Welder(float(np.ptp(p, axis=0).max()))
    bottom_face(welder, p, bottom)
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
    rise = height if height is not None else roof_slope(angle, None, reach) * reach
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
