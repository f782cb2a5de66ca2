"""Extrusion of polygon faces into prisms (CityEngine's ``extrude``).

A face ``v0 ... v(n-1)`` (counter-clockwise about its normal) extruded by ``d`` along a unit
direction gives, as PyPRT does (checked on an extruded 12 x 8 m lot): face 0 the bottom (the face
turned around, starting on its second vertex: ``v1 v0 v(n-1) ... v2``), face 1 the top (the face
moved by ``d``), then one side per edge from the first: ``v(k) v(k+1) v(k+1)' v(k)'``.
A negative distance extrudes backwards; the faces are turned so the prism still faces out.
"""

from __future__ import annotations

__all__ = ["extrude_faces", "prism"]

import numpy as np

from shapegen.geometry.mesh import Mesh, polygon_normal
from shapegen.limits import check_clock


def prism(points: np.ndarray, offset: np.ndarray) -> Mesh:
    """The prism swept by the polygon ``points`` ``(n, 3)`` moved by ``offset`` (m)."""
    p = np.asarray(points, float)
    n = len(p)
    top = p + np.asarray(offset, float)
    bottom_face = (1, 0) + tuple(range(n - 1, 1, -1))
    faces = [bottom_face, tuple(range(n, 2 * n))]
    faces += [(k, (k + 1) % n, n + (k + 1) % n, n + k) for k in range(n)]
    mesh = Mesh.of_valid_faces(np.vstack([p, top]), tuple(faces))
    if float(polygon_normal(p) @ np.asarray(offset, float)) < 0:
        mesh = mesh.reversed()
    return mesh


def extrude_faces(
    mesh: Mesh,
    distance: float,
    direction: np.ndarray | None = None,
    flat_top: bool = False,
) -> Mesh:
    """Every face of ``mesh`` extruded by ``distance`` (m) along its own normal (or along the
    unit ``direction`` for all), the prisms in one mesh in face order (CityEngine's
    ``face.normal`` extrusion: internal faces are kept).

    ``flat_top`` (with a ``direction``: ``world.up.flatTop``) puts every top corner at the same
    height along ``direction``: ``distance`` above the face's lowest corner (below its highest
    for a negative distance), and at least as high as the face's own extent (a zero distance
    gives the flat top at the highest corner)."""
    vertices: list[np.ndarray] = []
    faces: list[tuple[int, ...]] = []
    count = 0
    for k in range(mesh.n_faces):
        check_clock()
        points = mesh.face_points(k)
        if len(points) < 3:
            continue
        if direction is None:
            normal = polygon_normal(points)
            length = float(np.linalg.norm(normal))
            if length == 0:
                continue
            step = normal / length * distance
        else:
            step = np.asarray(direction, float) * distance
        if flat_top and direction is not None:
            piece = _flat_top_prism(points, np.asarray(direction, float), distance)
        else:
            piece = prism(points, step)
        vertices.append(piece.vertices)
        faces.extend(tuple(i + count for i in f) for f in piece.faces)
        count += piece.n_vertices
    if not faces:
        return Mesh(np.empty((0, 3)), ())
    return Mesh.of_valid_faces(np.vstack(vertices), tuple(faces))


def _flat_top_prism(points: np.ndarray, up: np.ndarray, distance: float) -> Mesh:
    heights = points @ up
    low, high = float(heights.min()), float(heights.max())
    if distance >= 0:
        level = max(low + distance, high)
    else:
        level = min(high + distance, low)
    top = points + np.outer(level - heights, up)
    n = len(points)
    bottom_face = (1, 0) + tuple(range(n - 1, 1, -1))
    faces = [bottom_face, tuple(range(n, 2 * n))]
    faces += [(k, (k + 1) % n, n + (k + 1) % n, n + k) for k in range(n)]
    mesh = Mesh(np.vstack([points, top]), faces)
    if float(polygon_normal(points) @ up) * (1 if distance >= 0 else -1) < 0:
        mesh = mesh.reversed()
    return mesh
