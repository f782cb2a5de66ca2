"""The leaves of a lot batch as packed arrays: each lot's extruded footprint, with no object per
lot.

A prism of ``n`` corners has its footprint's corners (``y = 0``) and then the same raised by
the height, and the faces of :func:`~shapegen.geometry.extrude.extrude_faces`: the bottom
``(1, 0, n-1, ..., 2)``, the top ``(n, ..., 2n-1)`` and a quad per edge ``(i, i+1, n+i+1,
n+i)``. A rectangle filling its scope is the box of the extruded scope, its corners in the
order and with the faces of the derivation's box blocks.
"""

from __future__ import annotations

__all__ = ["packed_leaves"]

import numpy as np

from shapegen.engine.batch.lots import BOX, LotBatch
from shapegen.engine.program.leaf_batches import BOX_LEAF_FACES  # the one-shape box leaves
from shapegen.engine.shapes.boxes import FILLING


def packed_leaves(batch: LotBatch, lots) -> dict[str, np.ndarray]:
    """The leaves of ``lots`` (indices of lots the batch derived), in that order: ``vertices``
    ``(V, 3)`` (m, the city's frame), ``vertex_counts``, ``faces`` (vertex numbers within the
    leaf, faces end to end), ``face_sizes``, ``face_counts`` per leaf."""
    lots = np.asarray(lots, dtype=np.int64)
    footprints = batch.footprints
    box = batch.kind[lots] == BOX
    corners = np.where(box, 4, footprints.sizes[lots])
    vertex_counts = np.where(box, 8, 2 * corners)
    face_counts = np.where(box, 6, corners + 2)
    vertex_start = _starts(vertex_counts)
    vertices = np.empty((int(vertex_start[-1]), 3))
    face_sizes_parts, faces_parts = [], []

    prisms = lots[~box]
    if len(prisms):
        n = footprints.sizes[prisms]
        heights = batch.height[prisms]
        offsets = footprints.offsets
        source = np.repeat(offsets[prisms] - _starts(n)[:-1], n) + np.arange(int(n.sum()))
        flat = footprints.points[source]
        rise = np.repeat(heights, n)
        first = vertex_start[:-1][~box]
        bottom = np.repeat(first, n) + (np.arange(int(n.sum())) - np.repeat(_starts(n)[:-1], n))
        top = bottom + np.repeat(n, n)
        vertices[bottom] = np.column_stack([flat[:, 0], np.zeros(len(flat)), flat[:, 1]])
        vertices[top] = np.column_stack([flat[:, 0], rise, flat[:, 1]])
    boxes = lots[box]
    if len(boxes):
        vertices[_box_rows(vertex_start[:-1][box])] = _box_corners(batch, boxes).reshape(-1, 3)

    # faces, leaf by leaf in the order of lots: built per kind, then laid out in order
    sizes_of = np.empty(len(lots), dtype=object)
    faces_of = np.empty(len(lots), dtype=object)
    if len(prisms):
        for where, size, faces in _prism_faces(np.flatnonzero(~box), footprints.sizes[prisms]):
            sizes_of[where], faces_of[where] = size, faces
    box_sizes = np.full(6, 4, dtype=np.int32)
    box_faces = np.array(BOX_LEAF_FACES, dtype=np.int32).ravel()
    for where in np.flatnonzero(box).tolist():
        sizes_of[where], faces_of[where] = box_sizes, box_faces
    face_sizes_parts = list(sizes_of)
    faces_parts = list(faces_of)
    return {
        "vertices": vertices,
        "vertex_counts": vertex_counts,
        "faces": np.concatenate(faces_parts) if faces_parts else np.zeros(0, np.int32),
        "face_sizes": np.concatenate(face_sizes_parts)
        if face_sizes_parts
        else np.zeros(0, np.int32),
        "face_counts": face_counts,
    }


def _prism_faces(where: np.ndarray, sizes: np.ndarray):
    """``(place, face sizes, faces)`` of each prism: one pattern per corner count."""
    for n in np.unique(sizes).tolist():
        j = np.arange(n)
        after = (j + 1) % n
        bottom = (1 - j) % n
        top = n + j
        sides = np.column_stack([j, after, n + after, n + j]).ravel()
        faces = np.concatenate([bottom, top, sides]).astype(np.int32)
        size = np.array([n, n] + [4] * n, dtype=np.int32)
        for place in where[sizes == n].tolist():
            yield place, size, faces


def _box_rows(first: np.ndarray) -> np.ndarray:
    return (first[:, None] + np.arange(8)).ravel()


def _box_corners(batch: LotBatch, lots: np.ndarray) -> np.ndarray:
    """``(m, 8, 3)``: the corners of the boxes of lots that fill their scope, in scope order."""
    footprints = batch.footprints
    corners = np.stack([footprints.corners(k) for k in lots.tolist()])  # (m, 4, 2)
    edge = corners[:, 1] - corners[:, 0]
    x_axis = edge / np.hypot(edge[:, 0], edge[:, 1])[:, None]
    z_axis = np.column_stack([-x_axis[:, 1], x_axis[:, 0]])
    along = np.einsum("mkj,mj->mk", corners, x_axis)
    across = np.einsum("mkj,mj->mk", corners, z_axis)
    low_x, low_z = along.min(axis=1), across.min(axis=1)
    size_x, size_z = along.max(axis=1) - low_x, across.max(axis=1) - low_z
    local = FILLING.corners[None] * np.stack([size_x, batch.height[lots], size_z], axis=1)[:, None]
    local[:, :, 0] += low_x[:, None]
    local[:, :, 2] += low_z[:, None]
    # back to the city's (x, z): along x_axis and z_axis, y as it is
    world = np.empty_like(local)
    world[:, :, 0] = local[:, :, 0] * x_axis[:, None, 0] + local[:, :, 2] * z_axis[:, None, 0]
    world[:, :, 1] = local[:, :, 1]
    world[:, :, 2] = local[:, :, 0] * x_axis[:, None, 1] + local[:, :, 2] * z_axis[:, None, 1]
    return world


def _starts(counts: np.ndarray) -> np.ndarray:
    out = np.zeros(len(counts) + 1, dtype=np.int64)
    np.cumsum(counts, out=out[1:])
    return out
