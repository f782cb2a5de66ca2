"""Polygon geometry shared by blocks and packed blocks.

:func:`face_normals` is the one face-normal routine of shapegen (Newell's method about each
face's centre); :class:`~shapegen.model.block.Block` and
:func:`~shapegen.model.packed.pack_blocks` both use it.
"""

from __future__ import annotations

__all__ = ["CheckedFaces", "checked_faces", "cross", "face_layout", "face_normals"]

from itertools import chain

import numpy as np


class CheckedFaces(tuple):
    """Polygons as tuples of Python ints (vertex numbers), as :func:`checked_faces` makes them.

    A plain tuple of tuples in every use; its type records that the conversion is done, so a
    mesh or block made from another's faces (a move, a scale, a cut) does not convert them
    again, and it keeps its :func:`face_layout` once worked out."""


def checked_faces(faces) -> CheckedFaces:
    """``faces`` (any iterables of integers) as :class:`CheckedFaces`; returned as they are when
    they already are."""
    if type(faces) is CheckedFaces:
        return faces
    return CheckedFaces(tuple(map(int, face)) for face in faces)


def face_layout(faces: CheckedFaces) -> tuple[np.ndarray, np.ndarray]:
    """The faces as flat arrays: every face's corners one after the other, and the ``(F + 1,)``
    offsets where each face starts (the last is the number of corners). Kept on ``faces``."""
    layout = faces.__dict__.get("layout")
    if layout is None:
        counts = np.fromiter(map(len, faces), dtype=np.intp, count=len(faces))
        start = np.zeros(len(faces) + 1, dtype=np.intp)
        np.cumsum(counts, out=start[1:])
        corners = np.fromiter(chain.from_iterable(faces), dtype=np.intp, count=int(start[-1]))
        corners.setflags(write=False)
        start.setflags(write=False)
        layout = faces.__dict__["layout"] = (corners, start)
    return layout


def face_normals(
    vertices: np.ndarray, corners: np.ndarray, corner_start: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """Outward unit normals and centres of polygons, by Newell's method.

    Parameters
    ----------
    vertices
        ``(V, 3)`` points, metres.
    corners
        Flat vertex numbers of every polygon, counter-clockwise seen from outside.
    corner_start
        ``(F + 1,)`` offsets of each polygon's corners in ``corners``.

    Returns
    -------
    (normals, centres)
        ``(F, 3)`` unit normals (zero for a degenerate polygon) and ``(F, 3)`` corner means (m).
        The cross products are taken about each polygon's centre, so a face far from the origin
        loses no precision to cancellation.
    """
    count = np.diff(corner_start)
    if len(count) == 0:
        return np.empty((0, 3)), np.empty((0, 3))
    p = vertices[corners]
    centre = np.add.reduceat(p, corner_start[:-1], axis=0) / count[:, None]
    p = p - np.repeat(centre, count, axis=0)
    successor = np.arange(len(corners)) + 1
    successor[corner_start[1:] - 1] = corner_start[:-1]  # a face's last corner wraps to its first
    sums = np.add.reduceat(cross(p, p[successor]), corner_start[:-1], axis=0)
    length = np.linalg.norm(sums, axis=1, keepdims=True)
    return np.divide(sums, length, out=np.zeros_like(sums), where=length > 0), centre


def cross(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Row-wise cross products of two ``(n, 3)`` arrays.

    The same products and differences as :func:`numpy.cross`, so the same bits, without its
    axis handling, which costs more than the arithmetic for the few faces of a block.
    """
    a0, a1, a2 = a[:, 0], a[:, 1], a[:, 2]
    b0, b1, b2 = b[:, 0], b[:, 1], b[:, 2]
    out = np.empty((len(a), 3))
    np.subtract(a1 * b2, a2 * b1, out=out[:, 0])
    np.subtract(a2 * b0, a0 * b2, out=out[:, 1])
    np.subtract(a0 * b1, a1 * b0, out=out[:, 2])
    return out
