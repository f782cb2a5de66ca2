"""Solids from the meshes of real models: a shell left open where it is hidden, closed.

A modeller often leaves out the faces nobody sees: a column shaft is a fluted tube without its
end discs, which sit on the stylobate and under the capital. Its boundary is a few closed loops
of edges, each running once around a hole; :func:`capped` closes each with one face (the loop
run the other way, as a cut mesh is capped), so the tube becomes the solid it stands for.
A solid that does not cut into convex pieces (a fluted shaft, a curved capital) stands on its
convex hull; :func:`hull_corners` gives a hull with few faces. Both serve the statics' stand-ins
(:mod:`shapegen.statics.standins`), never the derived model, which keeps the leaf as drawn.

>>> from shapegen.geometry.mesh import Mesh
>>> box = Mesh.box((1.0, 2.0, 3.0))
>>> open_box = Mesh(box.vertices, box.faces[1:])   # the bottom left out
>>> open_box.is_closed, capped(open_box).is_closed, round(capped(open_box).signed_volume(), 9)
(False, True, 6.0)
"""

from __future__ import annotations

__all__ = ["HULL_CORNERS", "HULL_FACE_SHARE", "HULL_TRIANGLES", "capped", "hull_corners"]

import numpy as np

from shapegen.errors import GeometryError
from shapegen.geometry.mesh import Mesh
from shapegen.tolerances import COINCIDENT_REL, DIVISION_FLOOR

HULL_TRIANGLES = 256
"""A hull of more triangles than this is thinned by :func:`hull_corners`."""
HULL_CORNERS = 96
"""About how many corners a thinned hull keeps."""
HULL_FACE_SHARE = 0.01
"""A face over this share of a hull's area keeps corners spread around it when it is thinned."""
_FACE_CORNERS = 32  # corners kept around each large face: an inscribed 32-gon of a disc has
# 99.4 % of its area


def capped(mesh: Mesh) -> Mesh | None:
    """``mesh`` with each loop of its boundary closed by a face, or None when its boundary is
    not a set of simple loops (an edge used twice the same way, a vertex where two holes meet)
    or the result is not closed. Kept per distinct mesh: a search judges the same leaves
    again."""
    key = (mesh.vertices.tobytes(), mesh.faces)
    closed = _CAPPED.get(key, _MISSING)
    if closed is _MISSING:
        closed = _capped(mesh)
        if len(_CAPPED) >= _CAPPED_LIMIT:
            del _CAPPED[next(iter(_CAPPED))]  # the oldest entry
        _CAPPED[key] = closed
    return closed


def _capped(mesh: Mesh) -> Mesh | None:
    edges: set[tuple[int, int]] = set()
    for face in mesh.faces:
        for a, b in zip(face, face[1:] + face[:1], strict=True):
            if (a, b) in edges:
                return None  # two faces run the same edge the same way: not one surface
            edges.add((a, b))
    following: dict[int, int] = {}
    for a, b in edges:
        if (b, a) not in edges:
            if b in following:
                return None  # two holes meet at a vertex: no single way round
            following[b] = a  # the cap runs each boundary edge the other way
    if not following:
        return None
    caps = []
    while following:
        start, nxt = following.popitem()
        loop = [start]
        while nxt != start:
            if nxt not in following:
                return None
            loop.append(nxt)
            nxt = following.pop(nxt)
        if len(loop) < 3:
            return None
        caps.append(tuple(loop))
    closed = Mesh(mesh.vertices, list(mesh.faces) + caps)
    return closed if closed.is_closed else None


def hull_corners(points, max_triangles: int = HULL_TRIANGLES, budget: int = HULL_CORNERS):
    """Corners of a convex solid inside the convex hull of ``points`` ``(n, 3)`` (m), with few
    faces: the hull's own corners when it has at most ``max_triangles`` triangles, else about
    ``budget`` of them, spread out (farthest first). Each large face of the hull (over
    :data:`HULL_FACE_SHARE` of its area: the ends a column stands and carries on) keeps corners
    spread around it, so the face stays in its plane, only cut down to an inscribed polygon;
    the rest of the budget goes to the other corners. A stand-in for the statics (a curved
    capital's hull has thousands of faces, which every contact and overlap test pays for),
    never a model's geometry: it lies inside the hull, so a contact through it is never larger
    than the hull's."""
    from scipy.spatial import ConvexHull, QhullError  # loaded when a hull is first needed

    points = np.asarray(points, dtype=float).reshape(-1, 3)
    centre = points.mean(axis=0)
    local = points - centre
    try:
        hull = ConvexHull(local)
    except (QhullError, ValueError):
        raise GeometryError(f"no hull: {len(points)} points flat or collinear") from None
    corners = hull.vertices
    if len(hull.simplices) <= max_triangles:
        return points[corners]
    # the triangles of one face share its plane: group them by their rounded plane
    scale = max(float(np.ptp(local, axis=0).max()), DIVISION_FLOOR)
    planes = np.round(hull.equations / np.array([1.0, 1.0, 1.0, scale]) / COINCIDENT_REL)
    _, face = np.unique(planes, axis=0, return_inverse=True)
    face = face.ravel()
    triangles = local[hull.simplices]
    areas = 0.5 * np.linalg.norm(
        np.cross(triangles[:, 1] - triangles[:, 0], triangles[:, 2] - triangles[:, 0]), axis=1
    )
    face_area = np.bincount(face, areas)
    chosen: list[int] = []
    for big in np.flatnonzero(face_area >= HULL_FACE_SHARE * face_area.sum()):
        on_face = np.unique(hull.simplices[face == big])
        chosen.extend(_spread(local, on_face, [], _FACE_CORNERS).tolist())
    chosen = list(dict.fromkeys(chosen))
    rest = max(budget - len(chosen), 4)
    return points[_spread(local, corners, chosen, len(chosen) + rest)]


def _spread(points: np.ndarray, candidates: np.ndarray, chosen: list[int], count: int):
    """``chosen`` and candidates added farthest first from those already chosen, up to
    ``count`` in all (indices into ``points``)."""
    candidates = np.asarray(candidates)
    picked = list(chosen)
    if len(candidates) + len(picked) <= count:
        return np.unique(np.concatenate([candidates, np.asarray(picked, dtype=int)]))
    if picked:
        gaps = np.min(
            np.linalg.norm(points[candidates][:, None] - points[picked][None], axis=2), axis=1
        )
    else:
        first = int(
            np.argmax(np.linalg.norm(points[candidates] - points[candidates].mean(0), axis=1))
        )
        picked.append(int(candidates[first]))
        gaps = np.linalg.norm(points[candidates] - points[picked[0]], axis=1)
    while len(picked) < count:
        far = int(np.argmax(gaps))
        if gaps[far] <= 0.0:
            break
        picked.append(int(candidates[far]))
        gaps = np.minimum(
            gaps, np.linalg.norm(points[candidates] - points[candidates[far]], axis=1)
        )
    return np.unique(np.asarray(picked, dtype=int))


_CAPPED: dict = {}
_CAPPED_LIMIT = 512
_MISSING = object()
