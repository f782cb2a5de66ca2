"""Convex hulls of many small point sets at once: the blocks of a file that gives only vertices.

A model file written by another program (compas, a script) often lists each block's corners and
no faces; :meth:`Block.from_hull` finds the faces with qhull, one block at a time, which costs
about a millisecond a block. Here the blocks of equal vertex count are done together with numpy:
for every triple of a block's points, the plane through them is a face plane when every point of
the block lies on one side of it (within ``COPLANAR_REL`` times the block's size), and the points
on that plane are the face. A face is ordered counter-clockwise about its outward normal exactly
as :meth:`Block.from_hull` orders it.

The result is taken only for a block whose hull is unambiguous: every point is a corner of at
least three faces (no point inside a face or an edge, no duplicate), no point lies near a face
plane without lying on it, and the faces close into one consistently oriented polyhedron
(each edge used once in each direction, V - E + F = 2). Every other block (interior points,
nearly coplanar faces, flat or non-finite input, more than :data:`MAX_BATCHED_VERTICES` points)
is left to :meth:`Block.from_hull`, which gives its hull or its error. For the blocks taken, the
vertices are the points in their given order, as :meth:`Block.from_hull` keeps them, and the
faces are the same polygons, ordered by the same rule; which corner a face starts at (where two
corners are equally far from its centre) and the order of the faces may differ from qhull's.
"""

from __future__ import annotations

__all__ = ["MAX_BATCHED_VERTICES", "batched_hulls", "blocks_from_hulls"]

from collections.abc import Sequence
from itertools import combinations

import numpy as np

from shapegen.model.block import Block
from shapegen.model.polygons import CheckedFaces
from shapegen.tolerances import COLLINEAR_REL, COPLANAR_REL

MAX_BATCHED_VERTICES = 12
"""Blocks of at most this many points go through the batched hull (C(12, 3) = 220 candidate
planes a block); larger point sets go to qhull one by one."""

"""A triple of points spans a plane when twice its triangle's area exceeds this times the
block's size squared (dimensionless); flatter triples are not used as face planes."""

_CLEAR_GAP = 1e4
"""A point off a face plane must lie at least this many times ``COPLANAR_REL`` times the block's
size from it, or the block goes to qhull (which then decides, with its own precision)."""

_TEMPLATES = 4
"""How many blocks' faces are tried on the other blocks of their vertex count before the rest
go through the full search."""

_FIT_CHUNK = 4096
"""Blocks checked against a layout at once (the arrays of a chunk stay in the cache)."""

_CHUNK = 1 << 22
"""About how many point-plane distances are computed at once (memory: 8 bytes each, a few
arrays of them)."""


def blocks_from_hulls(point_sets: Sequence[np.ndarray], fields: Sequence[dict]) -> list[Block]:
    """The blocks :meth:`Block.from_hull` makes of ``point_sets[k]`` with ``**fields[k]``.

    Raises the :class:`~shapegen.errors.GeometryError` of the first block (in order) that
    :meth:`Block.from_hull` refuses.
    """
    hulls = batched_hulls(point_sets)
    blocks = []
    for points, hull, kwargs in zip(point_sets, hulls, fields, strict=True):
        if hull is None:
            blocks.append(Block.from_hull(points, **kwargs))
        else:
            blocks.append(Block(*hull, **kwargs))
    return blocks


def batched_hulls(
    point_sets: Sequence[np.ndarray],
) -> list[tuple[np.ndarray, CheckedFaces] | None]:
    """For each ``(k, 3)`` point set, its hull as the vertices and faces
    :meth:`Block.from_hull` gives it (the points in their given order, as they come back from
    qhull's frame about their mean), or None when the set is left to qhull (see the module's
    notes). Sets with the same faces share one :class:`CheckedFaces` object."""
    out: list[tuple[np.ndarray, CheckedFaces] | None] = [None] * len(point_sets)
    groups: dict[int, list[int]] = {}
    for k, points in enumerate(point_sets):
        n = len(points)
        if 4 <= n <= MAX_BATCHED_VERTICES:
            groups.setdefault(n, []).append(k)
    shared: dict[tuple, CheckedFaces] = {}
    for members in groups.values():
        points = np.stack([np.asarray(point_sets[k], dtype=float) for k in members])
        vertices, layouts = _hulls_of_group(points)
        for k, corners, layout in zip(members, vertices, layouts, strict=True):
            if layout is not None:
                out[k] = (corners, shared.setdefault(layout, CheckedFaces(layout)))
    return out


def _hulls_of_group(points: np.ndarray) -> tuple[np.ndarray, list[tuple | None]]:
    """The vertices and faces (or None) of each of ``points`` ``(B, n, 3)``.

    The blocks of a file are mostly alike (the bricks of a wall): the faces found for one block
    are tried on all the others first, which is a few times cheaper than the search over every
    triple of points; a block they do not fit goes through that search.
    """
    count, n = points.shape[:2]
    finite = np.isfinite(points).all(axis=(1, 2))
    points = np.where(finite[:, None, None], points, 0.0)
    # qhull works about the points' mean (Block.from_hull): the vertices come back from there.
    centre = points.mean(axis=1, keepdims=True)
    local = points - centre
    vertices = local + centre
    layouts: list[tuple | None] = [None] * count
    remaining = np.flatnonzero(finite)
    for _ in range(_TEMPLATES):
        if not len(remaining):
            break
        template = _searched_hulls(local[remaining[:1]])[0]
        if template is None:
            break
        fits = _fits(local[remaining], template)
        if not fits[0]:
            break
        for k in remaining[fits].tolist():
            layouts[k] = template
        remaining = remaining[~fits]
    step = max(1, _CHUNK // (n * len(_triples(n))))
    for start in range(0, len(remaining), step):
        chosen = remaining[start : start + step]
        for k, layout in zip(chosen.tolist(), _searched_hulls(local[chosen]), strict=True):
            layouts[k] = layout
    return vertices, layouts


def _fits(local: np.ndarray, layout: tuple) -> np.ndarray:
    """``(B,)`` True where ``layout`` (the faces of another block with as many points) is the
    hull of the points ``local`` ``(B, n, 3)`` (about their mean), by the criteria of
    :func:`_searched_hulls` with a tenfold margin on the coplanarity: each face's points lie on
    the plane through them, every other point clearly inside it."""
    n = local.shape[1]
    faces = len(layout)
    sizes = np.array([len(face) for face in layout])
    starts = np.concatenate([[0], np.cumsum(sizes)])
    corners = np.array([i for face in layout for i in face])
    successor = np.arange(len(corners)) + 1
    successor[starts[1:] - 1] = starts[:-1]
    corner_face = np.repeat(np.arange(faces), sizes)
    summing = np.zeros((faces, len(corners)))
    summing[corner_face, np.arange(len(corners))] = 1.0
    member = summing @ (corners[:, None] == np.arange(n)) > 0  # (F, n)
    scale = np.ptp(local, axis=1).max(axis=1)
    limit = (COPLANAR_REL * scale)[:, None, None]
    fits = np.empty(len(local), dtype=bool)
    for start in range(0, len(local), _FIT_CHUNK):
        chunk = local[start : start + _FIT_CHUNK]
        a, b = chunk[:, corners], chunk[:, corners[successor]]
        # Newell's normal (the points are about their mean already: no cancellation)
        products = np.stack(
            [
                a[..., 1] * b[..., 2] - a[..., 2] * b[..., 1],
                a[..., 2] * b[..., 0] - a[..., 0] * b[..., 2],
                a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0],
            ],
            axis=-1,
        )
        normal = summing @ products  # (b, F, 3)
        centre = (summing @ a) / sizes[:, None]
        length = np.sqrt(np.einsum("bfd,bfd->bf", normal, normal))
        good = (length > 0).all(axis=1)
        normal /= np.where(length > 0, length, 1.0)[..., None]
        offset = np.einsum("bfd,bfd->bf", normal, centre)
        height = normal @ chunk.transpose(0, 2, 1) - offset[..., None]  # (b, F, n)
        bound = limit[start : start + _FIT_CHUNK]
        on = np.abs(height) <= 0.1 * bound
        inside = height < -_CLEAR_GAP * bound
        fits[start : start + _FIT_CHUNK] = good & np.where(member, on, inside).all(axis=(1, 2))
    return fits & (scale > 0)


def _triples(n: int) -> np.ndarray:
    return np.array(list(combinations(range(n), 3)), dtype=np.intp)


def _searched_hulls(local: np.ndarray) -> list[tuple | None]:
    """The faces of each of the finite point sets ``local`` ``(B, n, 3)`` (about their mean),
    or None where the hull is not clear, by the search over every triple of points."""
    count, n = local.shape[:2]
    ok = np.ones(count, dtype=bool)
    scale = np.ptp(local, axis=1).max(axis=1)
    ok &= scale > 0
    scale = np.where(scale > 0, scale, 1.0)
    tol = COPLANAR_REL * scale

    triples = _triples(n)
    first = local[:, triples[:, 0]]
    normal = np.cross(local[:, triples[:, 1]] - first, local[:, triples[:, 2]] - first)
    length = np.linalg.norm(normal, axis=2)
    spans = length > COLLINEAR_REL * scale[:, None] ** 2
    normal /= np.where(spans, length, 1.0)[..., None]
    height = (
        np.einsum("bmd,bkd->bmk", normal, local)
        - np.einsum("bmd,bmd->bm", normal, first)[..., None]
    )
    limit = tol[:, None, None]
    below = (height <= limit).all(axis=2) & spans  # every point on the inner side: outward
    above = (height >= -limit).all(axis=2) & spans  # ... or every point on the outer side
    ok &= ~(below & above).any(axis=1)  # all points on one plane: flat
    support = below | above
    off = np.abs(height)
    ok &= ~(support[..., None] & (off > limit) & (off < _CLEAR_GAP * limit)).any(axis=(1, 2))
    on = off <= limit

    # One face per distinct set of points on a supporting plane; its plane from the triple
    # that spans it best.
    weights = np.left_shift(1, np.arange(n, dtype=np.int64))
    code = on.astype(np.int64) @ weights
    block, triple = np.nonzero(support)
    key = block.astype(np.int64) << n | code[block, triple]
    order = np.lexsort((-length[block, triple], key))
    key_sorted = key[order]
    head = np.ones(len(order), dtype=bool)
    head[1:] = key_sorted[1:] != key_sorted[:-1]
    best = order[head]
    face_block = block[best]
    face_code = code[block[best], triple[best]]
    sign = np.where(below[block[best], triple[best]], 1.0, -1.0)
    face_normal = normal[block[best], triple[best]] * sign[:, None]
    member = (face_code[:, None] >> np.arange(n)) & 1 == 1  # (F, n)

    # Every point a corner of at least three faces (no point inside a face or an edge).
    corner_faces = np.zeros((count, n), dtype=np.int64)
    np.add.at(corner_faces, face_block, member.astype(np.int64))
    ok &= (corner_faces >= 3).all(axis=1)

    corners, starts = _ordered_corners(local, face_block, face_normal, member)
    ok &= _closed_sphere(count, n, face_block, corners, starts)
    return _layouts(ok, face_block, corners, starts)


def _ordered_corners(
    local: np.ndarray, face_block: np.ndarray, face_normal: np.ndarray, member: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """Each face's points counter-clockwise about its outward normal, starting where
    :func:`shapegen.model.block._hull_polygons` starts: flat corner numbers and face offsets."""
    face, vertex = np.nonzero(member)
    counts = member.sum(axis=1)
    starts = np.concatenate([[0], np.cumsum(counts)])
    p = local[face_block[face], vertex]  # (C, 3)
    centre = np.add.reduceat(p, starts[:-1], axis=0) / counts[:, None]
    relative = p - centre[face]
    distance = np.linalg.norm(relative, axis=1)
    # The farthest point from the centre, the first of equals as np.argmax takes it.
    far = np.lexsort((np.arange(len(face)), -distance, face))
    first_of_face = far[starts[:-1]]
    u = relative[first_of_face] / distance[first_of_face][:, None]
    v = np.cross(face_normal, u)
    angle = np.arctan2(
        np.einsum("ij,ij->i", relative, v[face]), np.einsum("ij,ij->i", relative, u[face])
    )
    order = np.lexsort((angle, face))  # a stable sort: equal angles keep point order
    return vertex[order], starts


def _closed_sphere(
    count: int, n: int, face_block: np.ndarray, corners: np.ndarray, starts: np.ndarray
) -> np.ndarray:
    """``(B,)`` True where the faces close into one oriented polyhedron of genus 0: every
    directed edge used by exactly one face, its reverse by another, and V - E + F = 2."""
    corner_face = np.repeat(np.arange(len(starts) - 1), np.diff(starts))
    successor = np.arange(len(corners)) + 1
    successor[starts[1:] - 1] = starts[:-1]
    tail, head = corners, corners[successor]
    edge_block = face_block[corner_face].astype(np.int64)
    forward = (edge_block * n + tail) * n + head
    backward = (edge_block * n + head) * n + tail
    ok = np.ones(count, dtype=bool)
    unique, counted = np.unique(forward, return_counts=True)
    ok[(unique[counted > 1] // (n * n))] = False  # an edge twice in one direction
    present = np.isin(backward, unique)
    ok[edge_block[~present]] = False  # an edge without its reverse: not closed
    faces = np.bincount(face_block, minlength=count)
    edges = np.bincount(edge_block, minlength=count) // 2
    return ok & (n - edges + faces == 2)


def _layouts(
    ok: np.ndarray, face_block: np.ndarray, corners: np.ndarray, starts: np.ndarray
) -> list[tuple | None]:
    """The faces of each block as a tuple of corner tuples (None where not ``ok``); equal
    layouts (all the bricks of a wall) are made once."""
    count = len(ok)
    face_start = np.searchsorted(face_block, np.arange(count + 1))
    face_count = np.diff(face_start)
    corner_start = starts[face_start]
    sizes = np.diff(starts)
    # One row per block: its face sizes, then its corners, padded with -1.
    width_faces = int(face_count.max(initial=0))
    width_corners = int(np.diff(corner_start).max(initial=0))
    rows = np.full((count, width_faces + width_corners), -1, dtype=np.int16)
    face_slot = np.arange(len(face_block)) - face_start[face_block]
    rows[face_block, face_slot] = sizes
    corner_block = np.repeat(face_block, sizes)
    corner_slot = np.arange(len(corners)) - corner_start[corner_block]
    rows[corner_block, width_faces + corner_slot] = corners
    chosen = np.flatnonzero(ok)
    if not len(chosen):
        return [None] * count
    distinct, which = np.unique(rows[chosen], axis=0, return_inverse=True)
    made = []
    for row in distinct.tolist():
        sizes_of = [s for s in row[:width_faces] if s >= 0]
        flat = row[width_faces:]
        bounds = np.concatenate([[0], np.cumsum(sizes_of)]).tolist()
        made.append(tuple(tuple(flat[a:b]) for a, b in zip(bounds[:-1], bounds[1:], strict=True)))
    out: list[tuple | None] = [None] * count
    for k, index in zip(chosen.tolist(), which.reshape(-1).tolist(), strict=True):
        out[k] = made[index]
    return out
