"""Blocks packed into flat arrays, for vectorised geometry over a whole model (contacts, checks)."""

from __future__ import annotations

__all__ = [
    "GatheredBlocks",
    "PackedBlocks",
    "gather_blocks",
    "malformed_blocks",
    "pack_blocks",
    "packed_from",
]

from dataclasses import dataclass

import numpy as np

from shapegen.errors import GeometryError
from shapegen.model.block import Block
from shapegen.model.polygons import CheckedFaces, checked_faces, face_layout, face_normals


@dataclass(frozen=True)
class PackedBlocks:
    """The geometry of several blocks in flat arrays, for vectorised geometric tests.

    Block ``k`` of the pack is ``model.blocks[index[k]]``; its vertices are
    ``vertices[vertex_start[k]:vertex_start[k + 1]]`` and its faces
    ``face_start[k]:face_start[k + 1]``. Face ``f`` lists the global vertex numbers
    ``corners[corner_start[f]:corner_start[f + 1]]``, counter-clockwise seen from outside.

    Attributes
    ----------
    index
        ``(n,)`` positions in ``model.blocks``.
    vertices
        ``(V, 3)`` all vertices, metres.
    vertex_start, face_start
        ``(n + 1,)`` offsets of each block's vertices and faces.
    corners, corner_start
        Face corner lists (global vertex numbers) and their ``(F + 1,)`` offsets.
    face_block
        ``(F,)`` pack position of each face's block.
    face_normal
        ``(F, 3)`` outward unit normals (Newell's method).
    face_offset
        ``(F,)`` plane offsets ``d`` with ``normal . x = d``, metres.
    face_center
        ``(F, 3)`` mean of each face's vertices, metres.
    lower, upper
        ``(n, 3)`` bounding-box corners, metres.
    """

    index: np.ndarray
    vertices: np.ndarray
    vertex_start: np.ndarray
    face_start: np.ndarray
    corners: np.ndarray
    corner_start: np.ndarray
    face_block: np.ndarray
    face_normal: np.ndarray
    face_offset: np.ndarray
    face_center: np.ndarray
    lower: np.ndarray
    upper: np.ndarray

    @property
    def face_count(self) -> np.ndarray:
        """``(n,)`` number of faces of each block."""
        return np.diff(self.face_start)

    @property
    def vertex_count(self) -> np.ndarray:
        """``(n,)`` number of vertices of each block."""
        return np.diff(self.vertex_start)


def pack_blocks(blocks: list[Block], index: np.ndarray | None = None) -> PackedBlocks:
    """Pack ``blocks`` (or the ones at positions ``index``) into :class:`PackedBlocks`."""
    index = np.arange(len(blocks)) if index is None else np.asarray(index, dtype=np.int64)
    chosen = [blocks[i] for i in index]
    gathered = gather_blocks(chosen)
    _reject_malformed(chosen, gathered)
    return packed_from(index, gathered)


@dataclass(frozen=True)
class GatheredBlocks:
    """Blocks' vertices and faces concatenated as given, before any check (see
    :class:`PackedBlocks` for the names); ``corners`` are each block's own vertex numbers."""

    vertices: np.ndarray
    vertex_count: np.ndarray
    vertex_start: np.ndarray
    face_count: np.ndarray
    face_start: np.ndarray
    corners: np.ndarray
    corner_count: np.ndarray
    corner_start: np.ndarray
    face_block: np.ndarray


def gather_blocks(chosen: list[Block]) -> GatheredBlocks:
    """Concatenate the vertices and faces of ``chosen``; nothing is checked."""
    vertex_count = np.fromiter((len(b.vertices) for b in chosen), dtype=np.int64, count=len(chosen))
    vertices = (
        np.concatenate([b.vertices for b in chosen]) if chosen else np.empty((0, 3), dtype=float)
    )
    # Blocks of one shape share their faces object (a wall's bricks, a file's hulls): its flat
    # layout is worked out once and repeated, instead of walking every face of every block.
    layouts: dict[int, tuple[np.ndarray, np.ndarray]] = {}
    corner_parts, size_parts = [], []
    for block in chosen:
        faces = block.faces
        layout = layouts.get(id(faces))
        if layout is None:
            corners, start = face_layout(
                faces if type(faces) is CheckedFaces else checked_faces(faces)
            )
            layout = layouts[id(faces)] = (corners, np.diff(start))
        corner_parts.append(layout[0])
        size_parts.append(layout[1])
    face_count = np.fromiter(map(len, size_parts), dtype=np.int64, count=len(chosen))
    corner_count = (
        np.concatenate(size_parts).astype(np.int64) if chosen else np.zeros(0, dtype=np.int64)
    )
    corner_start = np.concatenate([[0], np.cumsum(corner_count)]).astype(np.int64)
    return GatheredBlocks(
        vertices=vertices,
        vertex_count=vertex_count,
        vertex_start=np.concatenate([[0], np.cumsum(vertex_count)]),
        face_count=face_count,
        face_start=np.concatenate([[0], np.cumsum(face_count)]),
        corners=(
            np.concatenate(corner_parts).astype(np.int64) if chosen else np.zeros(0, np.int64)
        ),
        corner_count=corner_count,
        corner_start=corner_start,
        face_block=np.repeat(np.arange(len(chosen)), face_count),
    )


def packed_from(index: np.ndarray, gathered: GatheredBlocks) -> PackedBlocks:
    """The :class:`PackedBlocks` of well-formed gathered blocks (finite vertices, faces of at
    least 3 of their block's vertices, at least 4 faces a block)."""
    g = gathered
    vertices, vertex_start, corner_start = g.vertices, g.vertex_start, g.corner_start
    corners = g.corners + np.repeat(vertex_start[:-1][g.face_block], g.corner_count)
    if len(g.face_block):
        normal, center = face_normals(vertices, corners, corner_start)
        lower = np.minimum.reduceat(vertices, vertex_start[:-1], axis=0)
        upper = np.maximum.reduceat(vertices, vertex_start[:-1], axis=0)
    else:
        normal = center = np.empty((0, 3), dtype=float)
        lower = upper = np.empty((len(g.vertex_count), 3), dtype=float)
    return PackedBlocks(
        index=index,
        vertices=vertices,
        vertex_start=vertex_start,
        face_start=g.face_start,
        corners=corners,
        corner_start=corner_start,
        face_block=g.face_block,
        face_normal=normal,
        face_offset=np.einsum("ij,ij->i", normal, center),
        face_center=center,
        lower=lower,
        upper=upper,
    )


def malformed_blocks(gathered: GatheredBlocks) -> np.ndarray:
    """``(n,)`` True for each block that :func:`packed_from` cannot take: a non-finite vertex,
    a face of fewer than 3 corners or naming a vertex its block lacks, fewer than 4 faces."""
    g = gathered
    n = len(g.vertex_count)
    bad = ~np.isfinite(g.vertices).all(axis=1)
    malformed = np.bincount(np.repeat(np.arange(n), g.vertex_count)[bad], minlength=n) > 0
    broken = np.repeat(g.vertex_count[g.face_block], g.corner_count)
    wrong = (g.corners < 0) | (g.corners >= broken)
    malformed[np.repeat(g.face_block, g.corner_count)[wrong]] = True
    malformed[g.face_block[g.corner_count < 3]] = True
    malformed[g.face_count < 4] = True
    return malformed


def _reject_malformed(chosen: list[Block], gathered: GatheredBlocks) -> None:
    """Raise the block's own :class:`GeometryError` for non-finite vertices or broken faces,
    which the vectorised geometry cannot handle."""
    for k in np.flatnonzero(malformed_blocks(gathered)):
        chosen[k].validate()
        raise GeometryError(f"block {chosen[k].id or 'block'!r}: malformed vertices or faces")
