"""Cutting concave polygon faces into convex ones (CityEngine's ``convexify``).

A concave face is triangulated without new vertices (shapely's constrained Delaunay
triangulation, in the face's own plane), then diagonals are removed while the two pieces they
separate stay convex together (Hertel and Mehlhorn: at most four times the minimum number of
pieces). With ``max_length``, diagonals longer than it are removed first whatever the result,
as op_convexify only applies split lines shorter than its ``maxLength``.
"""

from __future__ import annotations

__all__ = ["convex_faces", "convex_pieces", "hole_free"]

import numpy as np

from shapegen.geometry.frames import face_rotation
from shapegen.geometry.mesh import Mesh
from shapegen.limits import check_clock
from shapegen.tolerances import ROUNDOFF_REL, at_least


def convex_faces(mesh: Mesh, max_length: float | None = None) -> Mesh:
    """``mesh`` with each concave face replaced by convex faces (same vertices)."""
    faces: list[tuple[int, ...]] = []
    for k, face in enumerate(mesh.faces):
        check_clock()
        if len(face) <= 3 or mesh.face(k).is_convex():
            faces.append(face)
            continue
        pieces = convex_pieces(mesh.face_points(k), max_length)
        faces.extend(tuple(face[i] for i in piece) for piece in pieces)
    return Mesh(mesh.vertices, faces)


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
        pieces = convex_pieces(points, hole_sizes=sizes[1:])
        faces.extend(tuple(every[i] for i in piece) for piece in pieces)
    return Mesh(mesh.vertices, faces)


def convex_pieces(
    points: np.ndarray, max_length: float | None = None, hole_sizes=()
) -> list[tuple[int, ...]]:
    """Convex polygons (indices into ``points``, counter-clockwise like the face) covering the
    planar polygon ``points`` ``(n, 3)``; with ``hole_sizes`` the last corners of ``points``
    are the polygon's holes, that many corners each, and the pieces leave them out."""
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
    length = None if max_length is None else float(max_length)
    if length is not None:
        _merge(pieces, flat, lambda a, b, merged: np.linalg.norm(flat[a] - flat[b]) > length)
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
