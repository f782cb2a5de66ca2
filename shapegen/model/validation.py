"""The checks of :meth:`Block.validate` on many blocks at once, on their packed arrays.

:meth:`Block.validate` stays the definition of a sound block; this module only finds faster
which blocks it would reject. Finite vertices, density and face indices are exact tests on the
gathered arrays. Volume and convexity are computed for all blocks together (the divergence
theorem over the face fans, the vertices' heights over the face planes), but in a different
summation order than the block's own properties, so they may differ from them in the last
bits: a block is only cleared when its figures pass with a margin that bounds that round-off.
Every other block (in practice only bad or borderline ones) goes through
:meth:`Block.validate`, which gives the verdict and the message. The verdicts and messages are
therefore exactly the block's own, block by block.
"""

from __future__ import annotations

__all__ = ["first_invalid_block", "validate_blocks"]

from collections.abc import Sequence

import numpy as np

from shapegen.errors import GeometryError
from shapegen.model.block import MAX_DENSITY, Block
from shapegen.model.packed import (
    PackedBlocks,
    gather_blocks,
    malformed_blocks,
    pack_blocks,
    packed_from,
)
from shapegen.model.polygons import cross
from shapegen.tolerances import COORDINATE_ROUNDOFF_REL, DEFAULT, Tolerances

_EPS = float(np.finfo(float).eps)
_PAIRS_AT_ONCE = 1_000_000  # faces x vertices of one block checked with the others


def validate_blocks(blocks: Sequence[Block], tol: Tolerances = DEFAULT) -> None:
    """Raise the :class:`GeometryError` of the first block that :meth:`Block.validate` rejects.

    The same verdict and message as ``for block in blocks: block.validate(tol)``, at a fraction
    of the cost for more than a few blocks.
    """
    invalid = first_invalid_block(blocks, tol)
    if invalid is not None:
        raise invalid[1]


def first_invalid_block(
    blocks: Sequence[Block], tol: Tolerances = DEFAULT
) -> tuple[int, GeometryError] | None:
    """The position of the first block that :meth:`Block.validate` rejects and its error.

    Returns None when every block is sound.
    """
    if not blocks:
        return None
    gathered = gather_blocks(list(blocks))
    density = np.fromiter((b.density for b in blocks), dtype=float, count=len(blocks))
    # a block of many faces and vertices is checked alone: its pairs would crowd the arrays
    large = np.fromiter(
        (len(b.faces) * len(b.vertices) > _PAIRS_AT_ONCE for b in blocks), bool, len(blocks)
    )
    doubtful = malformed_blocks(gathered) | ~((density >= 0) & (density <= MAX_DENSITY)) | large
    sound = np.flatnonzero(~doubtful)
    if len(sound) == len(blocks):
        pack = packed_from(sound, gathered)
    else:  # rare: malformed blocks cannot be packed, so pack the others anew
        pack = pack_blocks(list(blocks), sound)
    if len(sound):
        doubtful[sound[_doubtful_geometry(pack, tol)]] = True
    for k in np.flatnonzero(doubtful):
        try:
            blocks[k].validate(tol)
        except GeometryError as exc:
            return int(k), exc
    return None


def _doubtful_geometry(pack: PackedBlocks, tol: Tolerances) -> np.ndarray:
    """``(n,)`` True for each packed block whose volume or convexity is not clearly sound."""
    vertices, vertex_start, face_block = pack.vertices, pack.vertex_start, pack.face_block
    corners, corner_start, face_start = pack.corners, pack.corner_start, pack.face_start
    # Counts by slicing: np.diff's overhead is most of its cost on a few blocks.
    vertex_count = vertex_start[1:] - vertex_start[:-1]
    face_count = face_start[1:] - face_start[:-1]
    corner_count = corner_start[1:] - corner_start[:-1]
    # The block's reference point is its vertex mean, as in Block._mass_properties.
    reference = np.add.reduceat(vertices, vertex_start[:-1], axis=0) / vertex_count[:, None]
    largest = np.maximum(-pack.lower, pack.upper).max(axis=1)  # X: largest |coordinate|
    radius = np.maximum(pack.upper - reference, reference - pack.lower).max(axis=1)  # R

    # Volume: signed tetrahedra (reference, fan triangle) over every face. Triangle t of face f
    # is corners (corner_start[f], t + 2 f + 1, t + 2 f + 2): a face of c corners has c - 2.
    local = vertices - reference.repeat(vertex_count, axis=0)
    triangle_face = np.arange(len(face_block)).repeat(corner_count - 2)
    second = np.arange(len(triangle_face)) + 2 * triangle_face + 1
    a = local[corners[corner_start[triangle_face]]]
    b = local[corners[second]]
    c = local[corners[second + 1]]
    six_v = np.einsum("ij,ij->i", a, cross(b, c))
    triangle_block = face_block[triangle_face]
    volume = np.bincount(triangle_block, six_v, minlength=len(vertex_count)) / 6.0
    # Bound on how far this and Block.volume can differ: the round-off of the products and sums
    # (~ T^2 eps R^3) and of the two vertex means, scaled by the faces' area (~ n T eps X R^2).
    block_corners = corner_start[face_start]
    triangles = block_corners[1:] - block_corners[:-1] - 2 * face_count
    volume_slack = (
        64 * _EPS * triangles * (triangles + vertex_count) * (largest + radius) * radius**2
    )

    # Convexity: the height of every vertex of a block over every face plane of that block.
    face_vertices = vertex_count[face_block]
    pair_start = np.concatenate([[0], np.cumsum(face_vertices)])
    pair_face = np.arange(len(face_block)).repeat(face_vertices)
    pair_vertex = (
        np.arange(len(pair_face)) + (vertex_start[:-1][face_block] - pair_start[:-1])[pair_face]
    )
    height = (
        np.einsum("ij,ij->i", vertices[pair_vertex], pack.face_normal[pair_face])
        - pack.face_offset[pair_face]
    )
    worst = np.maximum.reduceat(height, pair_start[face_start[:-1]])
    # Heights are sums of terms up to |x| ~ X, each computed to a few eps X.
    convex_slack = 512 * _EPS * largest
    # Written so that a NaN anywhere makes the block doubtful.
    convex = tol.convex + COORDINATE_ROUNDOFF_REL * largest  # as in Block.validate
    clear = (volume > tol.volume + volume_slack) & (worst <= convex - convex_slack)
    return ~clear
