"""How far each vertex of a mesh lies in front of each face's plane: the one check that grows
as faces times vertices, so it is bounded by the work limit ``max_face_vertex_pairs`` and worked
out a band of faces at a time."""

from __future__ import annotations

__all__ = ["height_bands"]

from collections.abc import Iterator

import numpy as np

from shapegen.errors import GeometryError
from shapegen.limits import current_limits, limit_hint

_BAND_NUMBERS = 1 << 21  # heights held at once (16 MiB)


def height_bands(
    normals: np.ndarray, centres: np.ndarray, vertices: np.ndarray
) -> Iterator[np.ndarray]:
    """The heights (m) of ``vertices`` ``(V, 3)`` in front of the planes of unit ``normals``
    ``(F, 3)`` through ``centres`` ``(F, 3)``, as ``(b, V)`` bands of consecutive faces.

    Raises
    ------
    GeometryError
        At once, when ``F x V`` is more than the work limit ``max_face_vertex_pairs``.
    """
    faces, count = len(normals), len(vertices)
    limits = current_limits()
    if faces * count > limits.max_face_vertex_pairs:
        raise GeometryError(
            f"a mesh of {faces} faces and {count} vertices is too large to check for "
            f"convexity: {faces * count} face-vertex pairs, more than "
            f"{limits.max_face_vertex_pairs} " + limit_hint("max_face_vertex_pairs", limits)
        )
    return _bands(normals, centres, vertices)


def _bands(normals, centres, vertices) -> Iterator[np.ndarray]:
    # measured from the first vertex, so that far from the origin no digit is lost
    anchor = vertices[0] if len(vertices) else np.zeros(3)
    points = (vertices - anchor).T
    offsets = np.einsum("fk,fk->f", centres - anchor, normals)
    band = max(1, _BAND_NUMBERS // max(len(vertices), 1))
    for low in range(0, len(normals), band):
        n = normals[low : low + band]
        heights = np.multiply.outer(n[:, 0], points[0])
        heights += np.multiply.outer(n[:, 1], points[1])
        heights += np.multiply.outer(n[:, 2], points[2])
        heights -= offsets[low : low + band, None]
        yield heights
