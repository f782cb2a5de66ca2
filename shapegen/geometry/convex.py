"""Cutting concave polygon faces into convex ones (CityEngine's ``convexify``).

As measured with CityEngine's runtime (PyPRT 1.12, ``tools/prt_convexify.py``, the parts in
``tests/geometry/prt_convexify.json``): a concave face is cut along the extension of one of the
edges at a reflex corner, from that corner to where the line first meets the outline (a new
vertex there, or the corner it runs into), and each of the two parts is cut again the same way
until none has a reflex corner. Of the possible cuts (each reflex corner, each of its two edges
extended) the shortest is made first; among equal ones the first met walking the part's edges
in order, at each edge its start before its end, wins. The part holding the polygon's first
corner keeps the corners from the first one on; the other starts at the lower-numbered end of
the cut. A part that is cut leaves the list of parts and its two parts go to its end, the one
holding its first corner first. A vertex a later cut puts on an earlier cut is a corner of the
parts on both sides; on a mesh, a new vertex on an edge the face shares with another face is a
corner of that face too. A corner turning inwards by 1 degree or less counts as straight.
``convexify(maxLength)`` makes no cut longer than ``maxLength`` (the shortest cut is longer: the
part stays as it is).

:func:`hole_free` covers a face with holes by convex faces without new vertices (a constrained
triangulation, diagonals removed while the pieces stay convex): the polygons without holes
that blocks, exports and the statics take.
"""

from __future__ import annotations

__all__ = ["convex_faces", "convex_pieces", "hole_free"]

import math

import numpy as np

from shapegen.geometry.mesh import Mesh
from shapegen.geometry.scope_frames import face_rotation
from shapegen.limits import check_clock
from shapegen.tolerances import (
    COINCIDENT_REL,
    RAY_PARALLEL_DET,
    ROUNDOFF_REL,
    SIZE_FLOOR_M,
    at_least,
)

#: A corner turning inwards by no more than this (radians) is straight and is not cut from:
#: CityEngine's runtime leaves a dent of 1 degree and cuts one of 1.05 degrees, on a 10 m and a
#: 100 m face alike (``tools/prt_convexify.py``).
STRAIGHT = math.radians(1.0)


def convex_faces(mesh: Mesh, max_length: float | None = None) -> Mesh:
    """``mesh`` with each concave face replaced by its convex parts; a cut's new vertices are
    appended to the mesh's vertices and are corners of every face whose edge they lie on. A face
    with holes is first covered by convex faces leaving its holes out (:func:`hole_free`: how
    CityEngine cuts a holed face is not measured)."""
    mesh = hole_free(mesh)
    faces: list[tuple[int, ...]] = []
    vertices = list(mesh.vertices)
    for k, face in enumerate(mesh.faces):
        check_clock()
        if len(face) <= 3 or mesh.face(k).is_convex():
            faces.append(face)
            continue
        points, pieces = convex_pieces(mesh.face_points(k), max_length)
        ids = list(face)
        for point in points[len(face) :]:
            ids.append(len(vertices))
            vertices.append(point)
        faces.extend(tuple(ids[i] for i in piece) for piece in pieces)
    corners = np.array(vertices, float).reshape(-1, 3)
    if len(corners) > mesh.n_vertices:
        faces = _with_corners_on_edges(corners, faces, range(mesh.n_vertices, len(corners)))
    return Mesh(corners, faces)


def _with_corners_on_edges(corners: np.ndarray, faces: list, added: range) -> list:
    """``faces`` with each vertex of ``added`` put into the edges it lies inside of."""
    counts = np.array([len(f) for f in faces])
    flat = np.fromiter((i for f in faces for i in f), int, int(counts.sum()))
    starts = np.repeat(np.cumsum(counts) - counts, counts)
    owner = np.repeat(np.arange(len(faces)), counts)
    position = np.arange(len(flat)) - starts
    following = flat[starts + (position + 1) % counts[owner]]
    a, b = corners[flat], corners[following]
    edge = b - a
    square = np.einsum("ij,ij->i", edge, edge)
    near = COINCIDENT_REL * max(float(np.ptp(corners, axis=0).max()), SIZE_FLOOR_M)
    inserts: dict[int, list[tuple[int, float, int]]] = {}
    for w in added:
        check_clock()
        offset = corners[w] - a
        along = np.einsum("ij,ij->i", offset, edge) / np.maximum(square, near * near)
        off = np.linalg.norm(offset - along[:, None] * edge, axis=1)
        reach = along * np.sqrt(square)
        inside = (reach > near) & (np.sqrt(square) - reach > near) & (off <= near)
        inside &= (flat != w) & (following != w)
        for e in np.flatnonzero(inside):
            inserts.setdefault(int(owner[e]), []).append((int(position[e]), float(along[e]), w))
    out = list(faces)
    for k, extra in inserts.items():
        face = faces[k]
        if any(w in face for _, _, w in extra):
            extra = [x for x in extra if x[2] not in face]
        extra.sort()
        corners_of: list[int] = []
        for q, v in enumerate(face):
            corners_of.append(v)
            corners_of += [w for p, _, w in extra if p == q]
        out[k] = tuple(corners_of)
    return out


def hole_free(mesh: Mesh) -> Mesh:
    """``mesh`` with each face that has holes replaced by convex faces covering it but its
    holes (same vertices, no hole left): the same surface, area and volume, in the polygons
    without holes that blocks, exports and the statics' cuts take. A mesh without holes is
    returned as it is."""
    if not mesh.holes:
        return mesh
    faces: list[tuple[int, ...]] = []
    for face, rings in zip(mesh.faces, mesh.holes, strict=True):
        check_clock()
        if not rings:
            faces.append(face)
            continue
        every = list(face) + [i for ring in rings for i in ring]
        points = mesh.vertices[every]
        sizes = [len(face)] + [len(ring) for ring in rings]
        pieces = _holed_pieces(points, sizes[1:])
        faces.extend(tuple(every[i] for i in piece) for piece in pieces)
    return Mesh(mesh.vertices, faces)


def convex_pieces(
    points: np.ndarray, max_length: float | None = None
) -> tuple[np.ndarray, list[tuple[int, ...]]]:
    """The corners and convex parts of the planar polygon ``points`` ``(n, 3)``: the corners are
    ``points`` followed by the new vertices of the cuts, each part indices into them (the
    face's own turning)."""
    points = np.asarray(points, float)
    frame = face_rotation(points)
    flat = ((points - points[0]) @ frame[:, :2]).tolist()
    cutter = _Cutter(flat, points.tolist())
    parts = cutter.parts(list(range(len(flat))), max_length)
    return np.array(cutter.points3).reshape(-1, 3), [tuple(p) for p in cutter.joined(parts)]


class _Cutter:
    """The cuts of one polygon: 2D corners in its plane (the face turning counter-clockwise),
    their 3D points, and the points the cuts add."""

    def __init__(self, flat: list, points3: list):
        self.flat = [tuple(p) for p in flat]
        self.points3 = [tuple(p) for p in points3]
        span = max((abs(c) for p in self.flat for c in p), default=0.0)
        self.size = max(span, SIZE_FLOOR_M)
        self.near = COINCIDENT_REL * self.size
        self.corners = len(self.flat)  # the polygon's own; the cuts' vertices follow

    def parts(self, polygon: list[int], max_length: float | None) -> list[list[int]]:
        """The convex parts, in CityEngine's order: a part that is cut is taken out of the list
        and its two parts (the one holding its first corner first) go to the end."""
        parts, whole = [polygon], [False]
        while not all(whole):
            check_clock()
            k = whole.index(False)
            cut = self._shortest_cut(parts[k])
            if cut is None or (max_length is not None and cut[0] > max_length + self.near):
                whole[k] = True
                continue
            first, second = self._split(parts.pop(k), cut)
            del whole[k]
            parts += [first, second]
            whole += [False, False]
        return parts

    def _reflex(self, polygon: list[int], i: int) -> bool:
        n = len(polygon)
        a, b, c = (self.flat[polygon[k % n]] for k in (i - 1, i, i + 1))
        u, v = (b[0] - a[0], b[1] - a[1]), (c[0] - b[0], c[1] - b[1])
        return math.atan2(u[0] * v[1] - u[1] * v[0], u[0] * v[0] + u[1] * v[1]) < -STRAIGHT

    def _shortest_cut(self, polygon: list[int]) -> tuple[float, int, int, float] | None:
        """(length, corner, edge hit, where along it 0-1) of the cut to make, or None."""
        n = len(polygon)
        best = None
        for j in range(n):
            for corner, back in ((j, (j + 1) % n), ((j + 1) % n, j)):  # its start first
                if not self._reflex(polygon, corner):
                    continue
                a, b = self.flat[polygon[back]], self.flat[polygon[corner]]
                hit = self._cast(polygon, corner, (b[0] - a[0], b[1] - a[1]))
                if hit is not None and (best is None or hit[0] < best[0] - self.near):
                    best = (hit[0], corner, hit[1], hit[2])
        return best

    def _cast(self, polygon: list[int], corner: int, direction) -> tuple[float, int, float] | None:
        """Where the ray from ``corner`` along ``direction`` first meets the outline: (distance,
        edge, where along the edge 0-1)."""
        n = len(polygon)
        length = math.hypot(*direction)
        dx, dy = direction[0] / length, direction[1] / length
        ox, oy = self.flat[polygon[corner]]
        best = None
        for k in range(n):
            if k == corner or (k + 1) % n == corner:
                continue
            ax, ay = self.flat[polygon[k]]
            bx, by = self.flat[polygon[(k + 1) % n]]
            ex, ey = bx - ax, by - ay
            det = ex * dy - ey * dx
            if abs(det) <= RAY_PARALLEL_DET * max(abs(ex) + abs(ey), self.near):
                continue
            wx, wy = ax - ox, ay - oy
            t = (ex * wy - ey * wx) / det  # along the ray
            s = (dx * wy - dy * wx) / det  # along the edge
            slack = self.near / math.hypot(ex, ey)
            if t <= self.near or s < -slack or s > 1 + slack:
                continue
            if best is None or t < best[0] - self.near:
                best = (t, k, min(max(s, 0.0), 1.0))
        return best

    def _split(self, polygon: list[int], cut) -> tuple[list[int], list[int]]:
        _, corner, edge, along = cut
        n = len(polygon)
        a, b = polygon[edge], polygon[(edge + 1) % n]
        reach = along * math.dist(self.flat[a], self.flat[b])
        rest = (1.0 - along) * math.dist(self.flat[a], self.flat[b])
        if reach <= self.near:
            end = edge
        elif rest <= self.near:
            end = (edge + 1) % n
        else:
            pa, pb = self.flat[a], self.flat[b]
            qa, qb = self.points3[a], self.points3[b]
            self.flat.append(tuple(u + along * (v - u) for u, v in zip(pa, pb, strict=True)))
            self.points3.append(tuple(u + along * (v - u) for u, v in zip(qa, qb, strict=True)))
            polygon = [*polygon[: edge + 1], len(self.flat) - 1, *polygon[edge + 1 :]]
            end = edge + 1
            corner += corner > edge
        low, high = min(corner, end), max(corner, end)
        return polygon[: low + 1] + polygon[high:], polygon[low : high + 1]

    def joined(self, parts: list[list[int]]) -> list[list[int]]:
        """The parts with the cuts' vertices that lie inside their edges (a cut ending on an
        earlier cut splits that edge for the parts on both sides)."""
        added = range(self.corners, len(self.flat))
        out = []
        for part in parts:
            own = set(part)
            corners = []
            for q, a in enumerate(part):
                b = part[(q + 1) % len(part)]
                corners.append(a)
                (ax, ay), (bx, by) = self.flat[a], self.flat[b]
                ex, ey = bx - ax, by - ay
                square = ex * ex + ey * ey
                inside = []
                for v in added:
                    if v in own:
                        continue
                    px, py = self.flat[v][0] - ax, self.flat[v][1] - ay
                    t = (px * ex + py * ey) / square
                    if 0.0 < t < 1.0 and abs(px * ey - py * ex) <= self.near * math.sqrt(square):
                        inside.append((t, v))
                corners += [v for _, v in sorted(inside)]
            out.append(corners)
        return out


def _holed_pieces(points: np.ndarray, hole_sizes) -> list[tuple[int, ...]]:
    """Convex polygons (indices into ``points``, counter-clockwise like the face) covering the
    planar polygon ``points`` ``(n, 3)`` but its holes: the last corners of ``points`` are the
    holes, ``hole_sizes`` corners each. Made without new vertices (shapely's constrained
    Delaunay triangulation, then diagonals removed while the two pieces they separate stay
    convex together, Hertel and Mehlhorn)."""
    import shapely  # loaded by the first concave face

    points = np.asarray(points, float)
    outer = len(points) - sum(hole_sizes)
    frame = face_rotation(points[:outer])
    flat = (points - points[0]) @ frame[:, :2]
    rings, first = [], outer
    for size in hole_sizes:
        rings.append(flat[first : first + size])
        first += size
    polygon = shapely.Polygon(flat[:outer], rings)
    if not polygon.is_valid:
        polygon = shapely.make_valid(polygon)
    triangles = shapely.constrained_delaunay_triangles(polygon)
    pieces: list[list[int]] = []
    for triangle in shapely.get_parts(triangles):
        corners = np.asarray(triangle.exterior.coords)[:3]
        ids = [int(np.argmin(np.linalg.norm(flat - c, axis=1))) for c in corners]
        if len(set(ids)) < 3:
            continue
        if _signed_area(flat[ids]) < 0:
            ids.reverse()
        pieces.append(ids)
    if not pieces:
        return [tuple(range(outer))]
    _merge(pieces, flat, lambda a, b, merged: _is_convex(flat[merged]))
    return [tuple(p) for p in pieces]


def _merge(pieces: list[list[int]], flat: np.ndarray, accept) -> None:
    """Remove shared edges (diagonals) between pieces while ``accept(a, b, merged)``."""
    changed = True
    while changed:
        changed = False
        owner: dict[tuple[int, int], int] = {}
        for p, piece in enumerate(pieces):
            for a, b in zip(piece, piece[1:] + piece[:1], strict=True):
                owner[(a, b)] = p
        for (a, b), p in owner.items():
            q = owner.get((b, a))
            if q is None or q == p:
                continue
            merged = _joined(pieces[p], pieces[q], a, b)
            if merged is not None and accept(a, b, merged):
                pieces[p] = merged
                del pieces[q]
                changed = True
                break


def _joined(first: list[int], second: list[int], a: int, b: int) -> list[int] | None:
    """The polygon of ``first`` (with edge a->b) and ``second`` (with b->a) without that edge."""
    i = first.index(b)
    path_first = first[i:] + first[:i]  # b ... a
    j = second.index(a)
    path_second = second[j:] + second[:j]  # a ... b
    if path_first[-1] != a or path_second[-1] != b:
        return None
    merged = path_first[:-1] + path_second[:-1]
    return merged if len(set(merged)) == len(merged) else None


def _signed_area(flat: np.ndarray) -> float:
    x, y = flat[:, 0], flat[:, 1]
    return 0.5 * float(np.dot(x, np.roll(y, -1)) - np.dot(y, np.roll(x, -1)))


def _is_convex(flat: np.ndarray) -> bool:
    edge = np.roll(flat, -1, axis=0) - flat
    turn = (
        edge[:, 0] * np.roll(edge, -1, axis=0)[:, 1] - edge[:, 1] * np.roll(edge, -1, axis=0)[:, 0]
    )
    scale = float(np.abs(flat).max()) or 1.0
    return bool(at_least(turn.min(), 0.0, ROUNDOFF_REL * scale * scale))
