"""Surfaces (the leaves drawn but not judged) for the exporters: triangles, colours, the
left-out summary of a report (their shapegen-blocks JSON entries are read by
:mod:`shapegen.readers.surface_entries`).

A :class:`~shapegen.model.appearance.Surface`'s faces are planar polygons that may be
non-convex (an L-shaped lot, a roof plane); they are cut into triangles by a constrained
Delaunay triangulation (shapely), convex ones simply fanned.
"""

from __future__ import annotations

__all__ = [
    "face_triangles",
    "left_out_summary",
    "solids",
    "solids_volume",
    "surfaces_of",
]

from collections import Counter

import numpy as np

from shapegen.limits import check_clock
from shapegen.model.appearance import Surface
from shapegen.model.model import Model
from shapegen.tolerances import ROUNDOFF_REL


def surfaces_of(model: Model) -> list[Surface]:
    """The model's surfaces, each with an id (``s0``, ``s1``... for those without one)."""
    surfaces = list(getattr(model, "surfaces", None) or [])
    for k, surface in enumerate(surfaces):
        if not surface.id:
            surface.id = f"s{k}"
    return surfaces


def left_out_summary(model: Model) -> dict:
    """How many leaves of the derivation the statics leave out, and why.

    Returns ``{"leaves": n, "by_reason": {reason: count, ...}}``, the reasons in decreasing
    count (``"a face (no volume)"``, ``"not convex"``...): the model's surfaces but its solids
    kept as derived, which the statics cut into convex parts when they judge (:func:`solids`).
    """
    reasons = Counter(s.reason or "not a block" for s in surfaces_of(model) if s.solid is None)
    return {"leaves": sum(reasons.values()), "by_reason": dict(reasons.most_common())}


def solids(model: Model) -> int:
    """How many solid leaves the model keeps as derived (surfaces with a
    :class:`~shapegen.model.appearance.SolidLeaf`): closed ones that are not convex, and
    inserts cut open at trim planes; the statics cut each into convex parts of one body when
    they judge."""
    return sum(1 for s in getattr(model, "surfaces", None) or () if s.solid is not None)


def solids_volume(model: Model) -> float:
    """Total volume of the solids the model keeps as derived (:func:`solids`), m^3: each closed
    mesh's by the divergence theorem (an insert drawn open at its cut: the solid its caps
    close)."""
    from shapegen.geometry.mesh import Mesh

    total = 0.0
    for s in getattr(model, "surfaces", None) or ():
        if s.solid is None:
            continue
        local = s.solid.local
        if local is not None and not Mesh(s.vertices, s.faces).is_closed:
            total += abs(local.signed_volume())  # a rigid placement keeps it
        else:
            total += Mesh(s.vertices, s.faces).signed_volume()
    return float(total)


def face_triangles(vertices: np.ndarray, faces) -> np.ndarray:
    """``(t, 3)`` vertex indices of triangles covering the planar polygons ``faces``, each
    turned as its polygon (counter-clockwise seen from its front).

    Convex polygons are fanned from their first corner; a non-convex one is triangulated in
    its own plane (constrained Delaunay), so no triangle leaves the polygon. A polygon with no
    area gives no triangle.
    """
    vertices = np.asarray(vertices, dtype=float).reshape(-1, 3)
    out: list[tuple[int, int, int]] = []
    for face in faces:
        check_clock()
        face = [int(i) for i in face]
        if len(face) < 3:
            continue
        if len(face) == 3:
            out.append((face[0], face[1], face[2]))
            continue
        points = vertices[face]
        normal = _newell(points)
        norm = float(np.linalg.norm(normal))
        if norm == 0.0:
            continue
        plane = _plane_coordinates(points, normal / norm)
        if _is_convex(plane):
            out.extend((face[0], face[k], face[k + 1]) for k in range(1, len(face) - 1))
        else:
            out.extend(_triangulated(plane, face))
    return np.array(out, dtype=np.int64).reshape(-1, 3)


def _newell(points: np.ndarray) -> np.ndarray:
    following = np.roll(points, -1, axis=0)
    return np.cross(points - points.mean(axis=0), following - points.mean(axis=0)).sum(axis=0)


def _plane_coordinates(points: np.ndarray, normal: np.ndarray) -> np.ndarray:
    """2D coordinates of ``points`` in their plane, axes ``u, v`` with ``u x v = normal`` (so a
    polygon counter-clockwise about ``normal`` stays counter-clockwise)."""
    helper = np.array([1.0, 0.0, 0.0]) if abs(normal[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
    u = np.cross(helper, normal)
    u /= np.linalg.norm(u)
    v = np.cross(normal, u)
    centred = points - points.mean(axis=0)
    return np.stack([centred @ u, centred @ v], axis=1)


def _is_convex(plane: np.ndarray) -> bool:
    edges = np.roll(plane, -1, axis=0) - plane
    turns = (
        edges[:, 0] * np.roll(edges, -1, axis=0)[:, 1] - edges[:, 1] * np.roll(edges, -1, 0)[:, 0]
    )
    scale = float(np.abs(turns).max(initial=0.0))
    return bool((turns >= -ROUNDOFF_REL * scale).all())


def _triangulated(plane: np.ndarray, face: list[int]) -> list[tuple[int, int, int]]:
    index = {tuple(p): face[k] for k, p in enumerate(plane.tolist())}
    import shapely  # loaded by the first concave face to draw

    polygon = shapely.Polygon(plane)
    if not polygon.is_valid:  # self-touching: fan it rather than drop it
        return [(face[0], face[k], face[k + 1]) for k in range(1, len(face) - 1)]
    out = []
    for triangle in shapely.get_parts(shapely.constrained_delaunay_triangles(polygon)):
        corners = np.asarray(triangle.exterior.coords)[:3]
        try:
            a, b, c = (index[tuple(p)] for p in corners.tolist())
        except KeyError:  # a point GEOS added: cannot be named by a vertex index
            continue
        (ux, uy), (vx, vy) = corners[1] - corners[0], corners[2] - corners[0]
        turn = ux * vy - uy * vx
        out.append((a, b, c) if turn > 0 else (a, c, b))
    return out
