"""Boolean operations of surfaces that are not closed solids (op_boolOp, "Open and closed
operands"): an open mesh (a solid with a face removed, a plane) against a solid or another
open mesh, faces in several planes.

The reference: "Boolean operations are well defined in 2D (planar planes) and in 3D for closed
meshes. In 3D, open operands (planes and meshes with holes) are assumed closed as long as
boundaries are not intersected", and of a plane cutting a cube, "Everything below the plane is
regarded as 'inside' and thus disappears". So here each face of one operand is cut along the
other's surface, and each piece is kept or dropped by the side of the other operand it lies
on. A surface in one plane has the side its normal does not face as its inside, carried on
past its outline ("below the plane"). Any other surface has as its inside the points it winds
round at least half (its generalized winding number: 1 inside a closed solid and 0 outside;
inside a solid with an opening more than a half, outside less, as though the opening were
capped, exactly so for an opening in one plane), which is what "assumed closed" says while the
boundary does not cross the other operand. Where it does, the reference defines no result; the
caller is told (``crossed``) so that it can say so.

Kept, as for closed solids: for ``union`` the pieces of each operand outside the other, for
``intersect`` those inside, for ``subtract`` A's pieces outside B and B's inside A turned
round. A piece of A lying on B's surface is kept where they face the same way (``union``,
``intersect``) or opposite ways (``subtract``); B's pieces lying on A's surface are dropped (A
"specifies which material is used for overlapping geometry").
"""

from __future__ import annotations

__all__ = ["open_boolean"]

import numpy as np

from shapegen.geometry.mesh import Mesh
from shapegen.tolerances import COINCIDENT_REL

_KINDS = ("union", "subtract", "intersect")


def open_boolean(kind: str, a: Mesh, b: Mesh) -> tuple[np.ndarray, np.ndarray, bool]:
    """The result of ``a`` ``kind`` ``b`` as triangles: ``(points (P, 3), triangles (T, 3),
    crossed)``, the triangles wound as the faces they come from (turned round for B's pieces
    of a difference); ``crossed`` is True when the open boundary of one operand crosses the
    other's faces, where the reference defines no result."""
    if kind not in _KINDS:
        raise ValueError(f"unknown Boolean operation {kind!r}")
    size = float(np.ptp(np.vstack([a.vertices, b.vertices]), axis=0).max())
    slack = COINCIDENT_REL * max(1.0, size)
    tris_a, tris_b = _triangles(a), _triangles(b)
    cuts_a, cuts_b = _cuts(tris_a, tris_b, slack)
    flat = (_is_plane(tris_a, slack), _is_plane(tris_b, slack))
    points: list[np.ndarray] = []
    triangles: list[tuple[int, int, int]] = []
    for mine, other, cuts, first in (
        (tris_a, tris_b, cuts_a, True),
        (tris_b, tris_a, cuts_b, False),
    ):
        for k, triangle in enumerate(mine):
            for piece in _pieces(triangle, cuts.get(k, []), slack):
                inner = piece.mean(axis=0) if len(piece) == 3 else _inner_point(piece, triangle)
                side = _side(inner, _normal(triangle), other, slack, flat[1 if first else 0])
                keep, turn = _kept(kind, first, side)
                if keep:
                    _add(points, triangles, piece, turn)
    crossed = _boundary_crosses(a, b, tris_b, slack) or _boundary_crosses(b, a, tris_a, slack)
    if not triangles:
        return np.empty((0, 3)), np.empty((0, 3), dtype=np.int64), crossed
    return np.vstack(points), np.asarray(triangles, dtype=np.int64), crossed


def _kept(kind: str, first: bool, side: str) -> tuple[bool, bool]:
    """Whether a piece on ``side`` ("in", "out", "same", "opposite") of the other operand is
    kept, and whether it is turned round; ``first`` for a piece of A."""
    if side in ("same", "opposite"):
        if not first:
            return False, False
        return (side == "opposite") if kind == "subtract" else (side == "same"), False
    if first:
        return (side == "in") if kind == "intersect" else (side == "out"), False
    if kind == "union":
        return side == "out", False
    return side == "in", kind == "subtract"


# the operands' triangles ------------------------------------------------------------------------


def _triangles(mesh: Mesh) -> np.ndarray:
    """The faces of ``mesh`` as triangles ``(T, 3, 3)``, wound as the faces."""
    out = []
    for k, face in enumerate(mesh.faces):
        ring = mesh.vertices[list(face)]
        holes = mesh.holes[k] if mesh.holes else ()
        if len(ring) == 3 and not holes:
            out.append(ring)
            continue
        out.extend(_face_triangles(ring, [mesh.vertices[list(h)] for h in holes]))
    return np.asarray(out, float).reshape(-1, 3, 3)


def _face_triangles(ring: np.ndarray, holes: list[np.ndarray]) -> list[np.ndarray]:
    """A planar face (outer ``ring``, ``holes``) as triangles wound as the face."""
    import shapely

    normal = _newell(ring)
    length = np.linalg.norm(normal)
    if length == 0:
        return []
    frame = _frame(ring[0], normal / length)
    polygon = shapely.Polygon(_flat(ring, frame), [_flat(h, frame) for h in holes])
    if not polygon.is_valid:
        polygon = polygon.buffer(0)
    out = []
    for triangle in shapely.constrained_delaunay_triangles(polygon).geoms:
        corners = np.asarray(triangle.exterior.coords)[:3]
        if _area2(corners) < 0:
            corners = corners[::-1]
        out.append(_lifted(corners, frame))
    return out


def _newell(ring: np.ndarray) -> np.ndarray:
    nxt = np.roll(ring, -1, axis=0)
    return np.array(
        [
            np.sum((ring[:, 1] - nxt[:, 1]) * (ring[:, 2] + nxt[:, 2])),
            np.sum((ring[:, 2] - nxt[:, 2]) * (ring[:, 0] + nxt[:, 0])),
            np.sum((ring[:, 0] - nxt[:, 0]) * (ring[:, 1] + nxt[:, 1])),
        ]
    )


def _normal(triangle: np.ndarray) -> np.ndarray:
    n = np.cross(triangle[1] - triangle[0], triangle[2] - triangle[0])
    length = np.linalg.norm(n)
    return n / length if length else n


def _frame(origin: np.ndarray, normal: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """``(origin, axes)``: axes' rows u, w, n, right-handed, n the plane's normal."""
    helper = np.eye(3)[int(np.argmin(np.abs(normal)))]
    u = np.cross(helper, normal)
    u /= np.linalg.norm(u)
    return origin, np.array([u, np.cross(normal, u), normal])


def _flat(points: np.ndarray, frame) -> np.ndarray:
    origin, axes = frame
    return (points - origin) @ axes[:2].T


def _lifted(flat: np.ndarray, frame) -> np.ndarray:
    origin, axes = frame
    return origin + flat @ axes[:2]


def _area2(corners: np.ndarray) -> float:
    x, y = corners[:, 0], corners[:, 1]
    return float(np.sum(x * np.roll(y, -1) - np.roll(x, -1) * y))


# cutting the faces along the other operand ----------------------------------------------------


def _cuts(tris_a: np.ndarray, tris_b: np.ndarray, slack: float):
    """``({triangle of A: [segments]}, {triangle of B: [segments]})``: where each triangle
    meets the other operand's triangles."""
    cuts_a: dict[int, list] = {}
    cuts_b: dict[int, list] = {}
    if len(tris_a) == 0 or len(tris_b) == 0:
        return cuts_a, cuts_b
    lo_a, hi_a = tris_a.min(axis=1), tris_a.max(axis=1)
    lo_b, hi_b = tris_b.min(axis=1), tris_b.max(axis=1)
    near = np.all(
        (lo_a[:, None, :] <= hi_b[None, :, :] + slack)
        & (lo_b[None, :, :] <= hi_a[:, None, :] + slack),
        axis=2,
    )
    normals_a = [_normal(t) for t in tris_a]
    normals_b = [_normal(t) for t in tris_b]
    for i, j in zip(*np.nonzero(near), strict=True):
        segment = _meeting(tris_a[i], normals_a[i], tris_b[j], normals_b[j], slack)
        if segment is not None:
            cuts_a.setdefault(int(i), []).append(segment)
            cuts_b.setdefault(int(j), []).append(segment)
    return cuts_a, cuts_b


def _meeting(p, n_p, q, n_q, slack: float):
    """The segment where triangles ``p`` and ``q`` (unit normals ``n_p``, ``n_q``) meet, or None
    (apart, touching at a point, or in one plane)."""
    if not n_p.any() or not n_q.any():
        return None
    d_q = (q - p[0]) @ n_p
    d_p = (p - q[0]) @ n_q
    if np.all(np.abs(d_q) <= slack) or np.all(d_q > slack) or np.all(d_q < -slack):
        return None
    if np.all(d_p > slack) or np.all(d_p < -slack):
        return None
    on_p, on_q = _plane_cut(p, d_p, slack), _plane_cut(q, d_q, slack)
    if on_p is None or on_q is None:
        return None
    line = np.cross(n_p, n_q)
    length = np.linalg.norm(line)
    if length <= slack:
        return None
    line /= length
    t_p, t_q = on_p @ line, on_q @ line
    low = max(t_p.min(), t_q.min())
    high = min(t_p.max(), t_q.max())
    if high - low <= slack:
        return None
    start = on_p[int(np.argmin(t_p))]
    base = float(t_p.min())
    return start + (low - base) * line, start + (high - base) * line


def _plane_cut(triangle: np.ndarray, heights: np.ndarray, slack: float) -> np.ndarray | None:
    """The points where ``triangle`` crosses a plane (its corners' ``heights`` above it)."""
    points = [triangle[k] for k in range(3) if abs(heights[k]) <= slack]
    for k in range(3):
        h0, h1 = heights[k], heights[(k + 1) % 3]
        if (h0 > slack and h1 < -slack) or (h0 < -slack and h1 > slack):
            points.append(triangle[k] + h0 / (h0 - h1) * (triangle[(k + 1) % 3] - triangle[k]))
    return np.asarray(points) if len(points) >= 2 else None


def _pieces(triangle: np.ndarray, segments: list, slack: float) -> list[np.ndarray]:
    """``triangle`` cut along ``segments`` (3D, in its plane): the pieces' rings (3D), wound
    as the triangle."""
    if not segments:
        return [triangle]
    import shapely
    from shapely.ops import polygonize

    normal = _normal(triangle)
    if not normal.any():
        return []
    frame = _frame(triangle[0], normal)
    outline = shapely.Polygon(_flat(triangle, frame))
    reach = 1e3 * slack  # a cut ending on the triangle's edge is carried a hair across it
    lines = [outline.exterior]
    for start, end in segments:
        s, e = _flat(np.array([start, end]), frame)
        step = (e - s) / max(np.linalg.norm(e - s), slack)
        lines.append(shapely.LineString([s - reach * step, e + reach * step]))
    pieces = []
    for polygon in polygonize(shapely.unary_union(lines)):
        inside = polygon.intersection(outline)
        for part in getattr(inside, "geoms", [inside]):
            if part.geom_type != "Polygon" or part.area <= slack * reach:
                continue
            ring = np.asarray(shapely.Polygon(part.exterior).exterior.coords)[:-1]
            if _area2(ring) < 0:
                ring = ring[::-1]
            pieces.append(_lifted(ring, frame))
    return pieces


def _inner_point(piece: np.ndarray, triangle: np.ndarray) -> np.ndarray:
    """A point inside the piece (its ring, 3D, in ``triangle``'s plane)."""
    import shapely

    frame = _frame(triangle[0], _normal(triangle))
    point = shapely.Polygon(_flat(piece, frame)).representative_point()
    return _lifted(np.array([[point.x, point.y]]), frame)[0]


# which side of the other operand a piece lies on ---------------------------------------------


def _side(
    point: np.ndarray, normal: np.ndarray, other: np.ndarray, slack: float, plane: bool
) -> str:
    """ "in" or "out" of ``other`` (triangles) for ``point``, or "same" / "opposite" when it lies
    on ``other``'s surface (by the way ``normal`` faces against it). A surface in one plane
    (``plane``) has the side its normal does not face as its inside; another surface the
    points it winds round at least half (its generalized winding number, 1 inside a closed
    solid, more than a half inside one with openings, which counts as closed)."""
    if len(other) == 0:
        return "out"
    nearest, distance = _closest_points(point, other)
    closest = int(np.argmin(distance))
    if distance[closest] <= 1e3 * slack:
        return "same" if float(_normal(other[closest]) @ normal) > 0 else "opposite"
    if not plane:
        return "in" if _winding_number(point, other) >= 0.5 else "out"
    height = float((point - nearest[closest]) @ _normal(other[0]))
    return "in" if height < 0 else "out"


def _is_plane(triangles: np.ndarray, slack: float) -> bool:
    """Whether all ``triangles`` lie in one plane, facing one way."""
    if len(triangles) == 0:
        return False
    normal = _normal(triangles[0])
    if not normal.any():
        return False
    heights = (triangles.reshape(-1, 3) - triangles[0, 0]) @ normal
    size = max(1.0, float(np.ptp(triangles.reshape(-1, 3), axis=0).max()))
    facing = all(float(_normal(t) @ normal) > 0 for t in triangles if _normal(t).any())
    return facing and float(np.abs(heights).max()) <= COINCIDENT_REL * size * 1e3


def _winding_number(point: np.ndarray, triangles: np.ndarray) -> float:
    """How many times the surface ``triangles`` winds round ``point``: the solid angles of its
    triangles seen from the point (Van Oosterom and Strackee), over 4 pi."""
    a, b, c = (triangles[:, k] - point for k in range(3))
    la, lb, lc = (np.linalg.norm(v, axis=1) for v in (a, b, c))
    volume = np.einsum("ij,ij->i", a, np.cross(b, c))
    below = (
        la * lb * lc
        + np.einsum("ij,ij->i", a, b) * lc
        + np.einsum("ij,ij->i", a, c) * lb
        + np.einsum("ij,ij->i", b, c) * la
    )
    return float(np.sum(2.0 * np.arctan2(volume, below)) / (4.0 * np.pi))


def _closest_points(point: np.ndarray, triangles: np.ndarray):
    """The point of each triangle nearest to ``point`` and its distance."""
    a, b, c = triangles[:, 0], triangles[:, 1], triangles[:, 2]
    n = np.cross(b - a, c - a)
    length = np.linalg.norm(n, axis=1)
    unit = np.divide(n, length[:, None], out=np.zeros_like(n), where=length[:, None] > 0)
    projected = point - np.einsum("ij,ij->i", point - a, unit)[:, None] * unit
    inside = length > 0
    for x, y in ((a, b), (b, c), (c, a)):
        edge_normal = np.cross(y - x, n)  # points out of the triangle
        inside &= np.einsum("ij,ij->i", projected - x, edge_normal) <= 0
    best = projected.copy()
    best_distance = np.where(inside, np.linalg.norm(point - projected, axis=1), np.inf)
    for x, y in ((a, b), (b, c), (c, a)):
        edge = y - x
        span = np.einsum("ij,ij->i", edge, edge)
        t = np.clip(np.einsum("ij,ij->i", point - x, edge) / np.where(span > 0, span, 1), 0, 1)
        q = x + t[:, None] * edge
        d = np.linalg.norm(point - q, axis=1)
        closer = ~inside & (d < best_distance)
        best[closer] = q[closer]
        best_distance = np.where(closer, d, best_distance)
    return best, best_distance


# the open boundary ------------------------------------------------------------------------


def _boundary_crosses(mesh: Mesh, other: Mesh, triangles: np.ndarray, slack: float) -> bool:
    """Whether an edge of ``mesh`` that only one face has (its open boundary) passes through a
    face of ``other`` (``triangles``, its faces' triangles): through its inside, not along it
    nor through its rim, where a boundary lying on the other's surface only touches it."""
    if len(triangles) == 0:
        return False
    edges = _open_edges(mesh, slack)
    rims = [other.vertices[list(face)] for face in other.faces]
    for x, y in edges:
        for hit in _hits(mesh.vertices[x], mesh.vertices[y], triangles, slack):
            if all(
                _ring_distance(hit, rim) > 1e3 * slack for rim in rims if _on_plane(hit, rim, slack)
            ):
                return True
    return False


def _open_edges(mesh: Mesh, slack: float) -> list[tuple[int, int]]:
    """The edges of ``mesh`` that one face has, its vertices that coincide taken as one."""
    keys = np.round(mesh.vertices / slack).astype(np.int64)
    _, first, inverse = np.unique(keys, axis=0, return_index=True, return_inverse=True)
    weld = first[inverse.reshape(-1)]
    count: dict[tuple[int, int], int] = {}
    for face in mesh.faces:
        ring = [int(weld[i]) for i in face]
        for x, y in zip(ring, ring[1:] + ring[:1], strict=True):
            if x != y:
                key = (min(x, y), max(x, y))
                count[key] = count.get(key, 0) + 1
    return [key for key, n in count.items() if n == 1]


def _hits(start, end, triangles: np.ndarray, slack: float) -> np.ndarray:
    """The points where the segment ``start``-``end`` passes through ``triangles`` (crossing
    their planes, not lying in them)."""
    a, b, c = triangles[:, 0], triangles[:, 1], triangles[:, 2]
    n = np.cross(b - a, c - a)
    h0 = np.einsum("ij,ij->i", start - a, n)
    h1 = np.einsum("ij,ij->i", end - a, n)
    scale = np.linalg.norm(n, axis=1) * slack
    across = ((h0 > scale) & (h1 < -scale)) | ((h0 < -scale) & (h1 > scale))
    if not across.any():
        return np.empty((0, 3))
    t = h0[across] / (h0[across] - h1[across])
    hit = start + t[:, None] * (end - start)
    inside = np.ones(len(hit), dtype=bool)
    sub = n[across]
    for x, y in ((a, b), (b, c), (c, a)):
        edge_normal = np.cross(y[across] - x[across], sub)
        inside &= np.einsum("ij,ij->i", hit - x[across], edge_normal) <= 0
    return hit[inside]


def _on_plane(point: np.ndarray, rim: np.ndarray, slack: float) -> bool:
    normal = _newell(rim)
    length = np.linalg.norm(normal)
    return bool(length) and abs(float((point - rim[0]) @ normal)) <= 1e3 * slack * length


def _ring_distance(point: np.ndarray, rim: np.ndarray) -> float:
    """The distance from ``point`` to the nearest edge of the polygon ``rim``."""
    start, end = rim, np.roll(rim, -1, axis=0)
    edge = end - start
    span = np.einsum("ij,ij->i", edge, edge)
    t = np.clip(np.einsum("ij,ij->i", point - start, edge) / np.where(span > 0, span, 1), 0, 1)
    return float(np.linalg.norm(point - (start + t[:, None] * edge), axis=1).min())


def _add(points: list, triangles: list, ring: np.ndarray, turn: bool) -> None:
    """The piece ``ring`` (3D, convex or not) as triangles, turned round if ``turn``."""
    pieces = [ring] if len(ring) == 3 else _face_triangles(ring, [])
    for triangle in pieces:
        start = 3 * len(points)  # each entry of points is one triangle's three corners
        points.append(triangle)
        order = (0, 2, 1) if turn else (0, 1, 2)
        triangles.append(tuple(start + k for k in order))
