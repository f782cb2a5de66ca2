"""Solids from the meshes of real models: a shell left open where it is hidden, closed.

A modeller often leaves out the faces nobody sees: a column shaft is a fluted tube without its
end discs, which sit on the stylobate and under the capital. Its boundary is a few closed loops
of edges, each running once around a hole; :func:`capped` closes each with one face (the loop
run the other way, as a cut mesh is capped), so the tube becomes the solid it stands for.

>>> import numpy as np

from shapegen.geometry.mesh import Mesh
>>> box = Mesh.box((1.0, 2.0, 3.0))
>>> open_box = Mesh(box.vertices, box.faces[1:])   # the bottom left out
>>> open_box.is_closed, capped(open_box).is_closed, round(capped(open_box).signed_volume(), 9)
(False, True, 6.0)
"""

from __future__ import annotations

__all__ = ["capped", "placed_hull"]

import numpy as np

from shapegen.geometry.mesh import Mesh


def capped(mesh: Mesh) -> Mesh | None:
    """``mesh`` with each loop of its boundary closed by a face, or None when its boundary is
    not a set of simple loops (an edge used twice the same way, a vertex where two holes meet)
    or the result is not closed. Kept per distinct mesh, as the hulls are: every open leaf of a
    build asks, and an asset placed many times is the same mesh in its scope."""
    key = (mesh.vertices.tobytes(), mesh.faces)
    closed = _CAPPED.get(key, _MISSING)
    if closed is _MISSING:
        closed = _capped(mesh)
        if len(_CAPPED) >= _HULLS_LIMIT:
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


def placed_hull(mesh: Mesh, rotation, origin):
    """The convex hull of ``mesh`` (scope coordinates) as a block, moved by ``rotation`` and
    ``origin`` into world coordinates. Hulls are kept per distinct mesh (a temple's columns
    insert one asset many times), as :func:`~shapegen.geometry.cut.placed_convex_decomposition`
    keeps its pieces."""
    from shapegen.model.block import Block

    key = (mesh.vertices.tobytes(), mesh.faces)
    hull = _HULLS.get(key)
    if hull is None:
        hull = Block.from_hull(mesh.vertices)
        if len(_HULLS) >= _HULLS_LIMIT:
            del _HULLS[next(iter(_HULLS))]  # the oldest entry
        _HULLS[key] = hull
    return hull.transformed(np.asarray(rotation, float), np.asarray(origin, float))


_HULLS: dict = {}
_HULLS_LIMIT = 512
_CAPPED: dict = {}
_MISSING = object()
