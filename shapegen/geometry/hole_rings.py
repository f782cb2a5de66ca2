"""The holes of a mesh's faces as index rings: checked, turned, cleaned, closed.

:class:`~shapegen.geometry.mesh.Mesh` keeps its holes as ``holes``: ``()`` for a mesh without
any, else per face a tuple of hole rings, each a tuple of vertex indices wound against its face
(as PyPRT's ``InitialShape(..., holes)`` gives them). The functions here work on those index
rings (and the vertices where a measure needs them) for the mesh's methods.
"""

from __future__ import annotations

__all__ = [
    "checked_holes",
    "cleaned_rings",
    "hole_vectors",
    "outer_rings_only",
    "reversed_holes",
    "turned",
]

import numpy as np


def checked_holes(holes, n_faces: int, n_vertices: int) -> tuple:
    """``holes`` (one sequence of hole rings per face, or empty) as ``Mesh.holes``: ``()``
    when no face has a hole, else a tuple per face of tuples of vertex-index tuples. Raises
    ``ValueError`` for a list of the wrong length or a ring that does not index the vertices."""
    if not holes:
        return ()
    rings = tuple(tuple(tuple(int(i) for i in ring) for ring in face) for face in holes)
    if len(rings) != n_faces:
        raise ValueError(f"{len(rings)} lists of holes for {n_faces} faces")
    for face in rings:
        for ring in face:
            if len(ring) < 3 or min(ring) < 0 or max(ring) >= n_vertices:
                raise ValueError(f"a hole {ring} does not index the mesh's {n_vertices} vertices")
    return rings if any(rings) else ()


def turned(ring: tuple[int, ...]) -> tuple[int, ...]:
    """The ring turned around, starting on its second vertex (``v1 v0 v(n-1) ... v2``), so its
    first edge stays on the same segment, run the other way: as an extruded lot's bottom, and
    as PyPRT turns envelope2002's floors with ``reverseNormals()`` (their new bottom's first
    edge orders the interior walls' splits)."""
    if len(ring) < 3:
        return tuple(reversed(ring))
    return (ring[1], ring[0]) + tuple(reversed(ring[2:]))


def reversed_holes(holes: tuple) -> tuple:
    """``holes`` with every ring turned around, as its face is."""
    return tuple(tuple(turned(ring) for ring in rings) for rings in holes)


def hole_vectors(vertices: np.ndarray, holes: tuple, n_faces: int) -> np.ndarray:
    """``(F, 3)``: each face's holes' Newell vectors summed (twice their area along their
    normal: wound against their face, they take the holes' area off the face's)."""
    out = np.zeros((n_faces, 3))
    for k, rings in enumerate(holes):
        for ring in rings:
            p = vertices[list(ring)]
            p = p - p.mean(axis=0)
            out[k] += np.cross(p, np.roll(p, -1, axis=0)).sum(axis=0)
    return out


def outer_rings_only(faces) -> tuple[list[int], tuple[tuple[int, ...], ...]]:
    """The vertices the faces' outer rings use (in their order) and the faces renumbered to
    them: what is left when the holes are closed (CityEngine's ``deleteHoles``)."""
    used: set[int] = {i for face in faces for i in face}
    order = sorted(used)
    index = {old: new for new, old in enumerate(order)}
    return order, tuple(tuple(index[i] for i in face) for face in faces)


def cleaned_rings(remap: list[int], faces, holes):
    """The faces and holes with each vertex replaced by ``remap[vertex]`` (merged vertices),
    repeated corners dropped, a ring left with fewer than three corners dropped (a face's
    holes with it), the vertices renumbered in the order they are used. Returns the used
    vertices (old indices), the faces and the holes."""

    def ring_of(indices):
        ring: list[int] = []
        for i in indices:
            j = remap[i]
            if not ring or ring[-1] != j:
                ring.append(j)
        while len(ring) > 1 and ring[0] == ring[-1]:
            ring.pop()
        return ring if len(ring) >= 3 else None

    used: dict[int, int] = {}
    out_faces, out_holes = [], []
    for face, rings in zip(faces, holes, strict=True):
        ring = ring_of(face)
        if ring is None:
            continue
        out_faces.append(tuple(used.setdefault(i, len(used)) for i in ring))
        kept = (ring_of(r) for r in rings)
        out_holes.append(tuple(tuple(used.setdefault(i, len(used)) for i in r) for r in kept if r))
    return list(used), out_faces, out_holes
