"""Extrusion of polygon faces into prisms (CityEngine's ``extrude``).

A face ``v0 ... v(n-1)`` (counter-clockwise about its normal) extruded by ``d`` along a unit
direction gives, as PyPRT does (checked on an extruded 12 x 8 m lot): face 0 the bottom (the face
turned around, starting on its second vertex: ``v1 v0 v(n-1) ... v2``), face 1 the top (the face
moved by ``d``), then one side per edge from the first: ``v(k) v(k+1) v(k+1)' v(k)'``.
A negative distance extrudes backwards; the faces are turned so the prism still faces out.

A face with holes extrudes to a solid with inner walls, as CityEngine's does (measured with
PyPRT, tests/data/prt_holes.json: a square with a triangular hole gives 14 vertices, 9 faces
and 2 holes): the bottom and the top keep the holes, and after the outer sides come the inner
walls, one per hole edge, hole by hole, facing into the hole.

Several faces extruded along one direction (faces in one plane along their common normal, or
any faces along a world axis) combine: "no internal lamina faces are created" (op_extrude), so
an edge two faces share gets no side; faces in different planes along their own normals are
extruded one by one, internal faces kept. (PyPRT extrudes the border ring of
Building_From_FootprintSMALL's flat roof, six faces, with 12 sides, not 24.)
"""

from __future__ import annotations

__all__ = ["extrude_faces", "prism"]

import numpy as np

from shapegen.geometry.mesh import Mesh, polygon_normal
from shapegen.limits import check_clock
from shapegen.tolerances import COINCIDENT_M, EXTRUDE_JOIN_REL


def prism(points: np.ndarray, offset: np.ndarray, holes=()) -> Mesh:
    """The prism swept by the polygon ``points`` ``(n, 3)`` moved by ``offset`` (m); ``holes``
    the polygon's hole rings ``(m, 3)``, wound against it, which become inner walls."""
    p = np.asarray(points, float)
    n = len(p)
    if len(holes):
        return _holed_prism(p, [np.asarray(h, float) for h in holes], np.asarray(offset, float))
    top = p + np.asarray(offset, float)
    bottom_face = (1, 0) + tuple(range(n - 1, 1, -1))
    faces = [bottom_face, tuple(range(n, 2 * n))]
    faces += [(k, (k + 1) % n, n + (k + 1) % n, n + k) for k in range(n)]
    mesh = Mesh.of_valid_faces(np.vstack([p, top]), tuple(faces))
    if float(polygon_normal(p) @ np.asarray(offset, float)) < 0:
        mesh = mesh.reversed()
    return mesh


def _holed_prism(p: np.ndarray, holes: list[np.ndarray], offset: np.ndarray) -> Mesh:
    """:func:`prism` of a face with holes: the bottom corners (outer ring, then each hole's),
    then the top's in the same order; faces bottom, top, the outer sides, the inner walls."""
    rings, first = [], 0
    for ring in (p, *holes):
        rings.append(tuple(range(first, first + len(ring))))
        first += len(ring)
    count = first
    bottom = np.vstack([p, *holes])

    def turned(ring):
        return (ring[1], ring[0]) + tuple(reversed(ring[2:]))

    faces = [turned(rings[0]), tuple(i + count for i in rings[0])]
    for ring in rings:  # the outer ring's sides, then each hole's walls
        m = len(ring)
        faces += [
            (ring[k], ring[(k + 1) % m], ring[(k + 1) % m] + count, ring[k] + count)
            for k in range(m)
        ]
    holes_of = [()] * len(faces)
    holes_of[0] = tuple(turned(ring) for ring in rings[1:])
    holes_of[1] = tuple(tuple(i + count for i in ring) for ring in rings[1:])
    mesh = Mesh.of_valid_faces(np.vstack([bottom, bottom + offset]), tuple(faces),
                               holes=tuple(holes_of))  # fmt: skip
    if float(polygon_normal(p) @ offset) < 0:
        mesh = mesh.reversed()
    return mesh


def extrude_faces(
    mesh: Mesh,
    distance: float,
    direction: np.ndarray | None = None,
    flat_top: bool = False,
) -> Mesh:
    """Every face of ``mesh`` extruded by ``distance`` (m) along its own normal (or along the
    unit ``direction`` for all), the prisms in one mesh in face order: each face's bottom, top
    and sides. Along one direction (a ``direction``, or faces in one plane) an edge two faces
    share has no side (op_extrude: no internal lamina faces); faces in different planes each
    make a whole prism (CityEngine's ``face.normal`` extrusion: internal faces are kept).

    ``flat_top`` (with a ``direction``: ``world.up.flatTop``) puts every top corner at the same
    height along ``direction``: ``distance`` above the face's lowest corner (below its highest
    for a negative distance), and at least as high as the face's own extent (a zero distance
    gives the flat top at the highest corner)."""
    vertices: list[np.ndarray] = []
    faces: list[tuple[int, ...]] = []
    holes: list[tuple] = []
    count = 0
    if not flat_top:
        combined = _combined_prism(mesh, distance, direction)
        if combined is not None:
            return combined
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
        rings = mesh.holes[k] if mesh.holes else ()
        if flat_top and direction is not None:
            if rings:
                raise ValueError(
                    "extrude(world.up.flatTop) of a face with holes is not supported by shapegen"
                )
            piece = _flat_top_prism(points, np.asarray(direction, float), distance)
        else:
            piece = prism(points, step, [mesh.vertices[list(r)] for r in rings])
        vertices.append(piece.vertices)
        faces.extend(tuple(i + count for i in f) for f in piece.faces)
        if piece.holes:
            holes += [tuple(tuple(i + count for i in r) for r in rs) for rs in piece.holes]
        else:
            holes += [()] * piece.n_faces
        count += piece.n_vertices
    if not faces:
        return Mesh(np.empty((0, 3)), ())
    return Mesh.of_valid_faces(
        np.vstack(vertices), tuple(faces), holes=tuple(holes) if any(holes) else ()
    )


def _combined_prism(mesh: Mesh, distance: float, direction) -> Mesh | None:
    """The faces of ``mesh`` extruded together along one direction (a ``direction``, or their
    common normal when all lie in one plane facing one way), corners at one place made one
    vertex, a side only on an edge no other face runs the other way; None when the faces do
    not extrude together (one face, or faces in different planes along their own normals)."""
    if mesh.n_faces < 2 or any(mesh.holes):
        return None  # faces with holes: their own prisms with inner walls
    points = mesh.vertices
    span = max(float(np.ptp(points, axis=0).max()), COINCIDENT_M)
    merge = EXTRUDE_JOIN_REL * span  # corners this close are one (m)
    if direction is None:
        normals = mesh.face_normals()
        if not np.allclose(normals, normals[0], atol=merge / span):
            return None
        if np.ptp(points @ normals[0]) > merge:
            return None  # parallel faces at different levels: each its own prism
        step = normals[0] * distance
    else:
        step = np.asarray(direction, float) * distance
    keys = np.round(points / merge).astype(np.int64)
    place: dict[tuple, int] = {}
    same = np.array([place.setdefault(tuple(key), i) for i, key in enumerate(keys.tolist())])
    used, number = np.unique(same, return_inverse=True)
    faces = [tuple(int(number[i]) for i in face) for face in mesh.faces]
    runs = {(f[e], f[(e + 1) % len(f)]) for f in faces for e in range(len(f))}
    n = len(used)
    out: list[tuple[int, ...]] = []
    for face in faces:
        corners = len(face)
        out.append((face[1], face[0]) + tuple(face[corners - 1 : 1 : -1]))  # bottom
        out.append(tuple(n + i for i in face))  # top
        for e in range(corners):
            a, b = face[e], face[(e + 1) % corners]
            if (b, a) not in runs:
                out.append((a, b, n + b, n + a))
    base = points[used]
    solid = Mesh.of_valid_faces(np.vstack([base, base + step]), tuple(out))
    if float(polygon_normal(mesh.face_points(0)) @ step) < 0:
        solid = solid.reversed()
    return solid


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
