"""Checks that a block model can be analysed: sound blocks, no overlaps, every block supported.

:func:`check_model` runs before the statics solve and raises one clear error naming the blocks
at fault, instead of letting a broken model produce a meaningless infeasibility.
"""

from __future__ import annotations

__all__ = [
    "check_model",
    "check_interpenetration",
    "check_ground",
    "check_support",
    "overlapping_pairs",
]

import numpy as np

from shapegen.errors import GeometryError, StaticsError
from shapegen.geometry.graphs import connected_components
from shapegen.limits import check_clock
from shapegen.model.model import Model
from shapegen.model.packed import PackedBlocks, pack_blocks
from shapegen.statics.contacts import candidate_pairs
from shapegen.statics.interface import GROUND, Interface
from shapegen.tolerances import Tolerances

_LISTED_IDS = 5  # ids named in a message before "and N more"
_SAT_ENTRIES_PER_CHUNK = 4_000_000  # (pair, face, vertex) heights per chunk, ~32 MB


def check_model(
    model: Model,
    interfaces: list[Interface],
    tol: Tolerances | None = None,
    bodies=None,
    pack: PackedBlocks | None = None,
) -> None:
    """Raise if ``model`` cannot be analysed with ``interfaces`` (from ``find_interfaces``);
    ``tol`` defaults to ``model.tolerances()``.

    With ``bodies`` (:class:`~shapegen.statics.bodies.Bodies`), blocks that overlap are parts
    of one body (no error), a body is supported through any of its parts, and the blocks left
    out of the statics (ornaments riding as load) need no support. ``pack``: blocks a caller
    already packed, used when they are the ones checked.

    Raises
    ------
    GeometryError
        A degenerate, non-finite or non-convex block, duplicate ids (``model.validate()``), two
        interpenetrating blocks, or a free block reaching below the ground plane.
    StaticsError
        No support at all, or free blocks with no chain of contacts to a support.
    """
    model.validate()
    tol = model.tolerances() if tol is None else tol
    structural = np.flatnonzero([b.structural for b in model.blocks])
    has_fixed = any(model.blocks[i].fixed for i in structural)
    has_free = not all(model.blocks[i].fixed for i in structural)
    if model.ground is None and has_free and not has_fixed:
        raise StaticsError(
            "the model has no support: no ground plane (ground is null) and no fixed "
            "structural block"
        )
    if bodies is not None:
        structural = np.flatnonzero(bodies.body >= 0)
    if pack is None or not np.array_equal(pack.index, structural):
        pack = pack_blocks(model.blocks, structural)
    check_ground(model, pack, tol)
    if bodies is None:
        check_interpenetration(model, pack, tol)
    check_support(model, interfaces, bodies)


def check_ground(model: Model, pack: PackedBlocks, tol: Tolerances) -> None:
    """Raise :class:`GeometryError` for a free structural block reaching below the ground."""
    if model.ground is None or len(pack.index) == 0:
        return
    free = np.array([not model.blocks[i].fixed for i in pack.index], dtype=bool)
    depth = float(model.ground) - pack.lower[:, 1]
    below = np.flatnonzero(free & (depth > tol.planar))
    if len(below):
        worst = below[np.argmax(depth[below])]
        others = f" ({len(below) - 1} more blocks also do)" if len(below) > 1 else ""
        raise GeometryError(
            f"block {model.blocks[pack.index[worst]].id!r} reaches {depth[worst]:.3g} m below "
            f"the ground plane y = {float(model.ground):g}{others}"
        )


def check_interpenetration(model: Model, pack: PackedBlocks, tol: Tolerances) -> None:
    """Raise :class:`GeometryError` naming the first two blocks that overlap in volume.

    Candidate pairs come from the bounding boxes; a pair is dismissed when a face plane of either
    block separates the two (within ``tol.planar``), which covers blocks touching face to face.
    manifold3d measures the intersection volume of the rest; an overlap above
    ``tol.penetration_rel`` times the smaller volume is an error. Two fixed blocks may overlap
    (supports carry no equilibrium).
    """
    fixed = np.array([model.blocks[i].fixed for i in pack.index], dtype=bool)
    for a, b, overlap, _ in _overlaps(model, pack, tol, fixed):
        block_a, block_b = model.blocks[pack.index[a]], model.blocks[pack.index[b]]
        raise GeometryError(
            f"blocks {block_a.id!r} and {block_b.id!r} interpenetrate ({overlap:.3g} m^3 overlap)"
        )


def overlapping_pairs(
    model: Model, pack: PackedBlocks, tol: Tolerances
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Every pair of packed blocks that overlap in volume, as :func:`check_interpenetration`
    judges it (two fixed blocks included).

    Returns
    -------
    pairs, volumes, centroids
        ``(k, 2)`` pack positions (lower first), ``(k,)`` intersection volumes (m^3) and
        ``(k, 3)`` their centroids (m).
    """
    found = list(_overlaps(model, pack, tol, np.zeros(len(pack.index), dtype=bool), True))
    pairs = np.array([(a, b) for a, b, _, _ in found], dtype=np.int64).reshape(-1, 2)
    volumes = np.array([v for _, _, v, _ in found], dtype=float)
    return pairs, volumes, np.array([c for *_, c in found], dtype=float).reshape(-1, 3)


def _overlaps(model: Model, pack: PackedBlocks, tol: Tolerances, fixed: np.ndarray, centroid=False):
    """``(a, b, volume, centroid)`` for each pair of packed blocks, not both ``fixed``, whose
    intersection volume is above ``tol.penetration_rel`` of the smaller block's, in order of
    the pairs; the intersection's centroid (m) only with ``centroid``, else None."""
    pairs = candidate_pairs(pack.lower, pack.upper, 0.0)
    if len(pairs) == 0:
        return
    pairs = pairs[~(fixed[pairs[:, 0]] & fixed[pairs[:, 1]])]
    # Cheap first pass: the face of each block that looks most towards the other one is the
    # separating plane of most neighbours in an assembly (the joints of an arch).
    pairs = pairs[~_separated_by_facing_face(pack, pairs[:, 0], pairs[:, 1], tol.planar)]
    pairs = pairs[~_separated_by_facing_face(pack, pairs[:, 1], pairs[:, 0], tol.planar)]
    pairs = pairs[~_separated_by_face(pack, pairs[:, 0], pairs[:, 1], tol.planar)]
    suspects = pairs[~_separated_by_face(pack, pairs[:, 1], pairs[:, 0], tol.planar)]
    if len(suspects) == 0:
        return
    from manifold3d import Manifold  # only needed when boxes and face planes cannot decide

    # manifold3d's precision is relative to the largest coordinate: work about the middle of
    # the blocks in question; each block's solid is made once, however many pairs it is in
    center = 0.5 * (pack.lower[suspects].min(axis=(0, 1)) + pack.upper[suspects].max(axis=(0, 1)))
    solids: dict[int, Manifold] = {}

    def solid(k: int) -> Manifold:
        if k not in solids:
            solids[k] = Manifold.hull_points(model.blocks[pack.index[k]].vertices - center)
        return solids[k]

    for a, b in suspects.tolist():
        check_clock()  # blocks all overlapping are n^2 / 2 intersections of 1-2 ms each
        block_a, block_b = model.blocks[pack.index[a]], model.blocks[pack.index[b]]
        common = solid(a) ^ solid(b)
        overlap = common.volume()
        # an empty intersection is no overlap, even of blocks of no volume (a 1e-320 m face)
        if overlap > 0 and overlap > tol.penetration_rel * min(block_a.volume, block_b.volume):
            yield a, b, overlap, _centroid(common) + center if centroid else None


def _centroid(solid) -> np.ndarray:
    """The centroid of a manifold3d solid (divergence theorem over its triangles), m."""
    mesh = solid.to_mesh()
    points = np.asarray(mesh.vert_properties, float)[:, :3]
    corners = points[np.asarray(mesh.tri_verts, dtype=np.int64)]
    six_volume = np.einsum("ij,ij->i", corners[:, 0], np.cross(corners[:, 1], corners[:, 2]))
    total = six_volume.sum()
    if total == 0:
        return points.mean(axis=0)
    return (six_volume[:, None] * corners.sum(axis=1)).sum(axis=0) / (4.0 * total)


def _separated_by_face(pack: PackedBlocks, a: np.ndarray, b: np.ndarray, slack: float):
    """``(m,)`` True where some face plane of block ``a[p]`` has all of ``b[p]`` on its far side.

    ``slack`` metres of penetration are allowed. Faces and vertices are padded to the largest
    block's counts (padding faces never separate, padding vertices repeat the first vertex) and
    the pairs are processed in chunks to bound memory.
    """
    normals, offsets = _padded_faces(pack)
    vertices = _padded_vertices(pack)
    out = np.zeros(len(a), dtype=bool)
    # pairs in order of their work, each chunk padded only to its own largest blocks: one
    # block of 400 faces (an asset's hull) must not pad every pair of boxes to its size
    faces, points = pack.face_count[a], pack.vertex_count[b]
    order = np.argsort(faces * points, kind="stable")
    start = 0
    while start < len(a):
        width_f, width_v = int(faces[order[start]]), int(points[order[start]])
        stop = start + 1
        while stop < len(a):
            f = max(width_f, int(faces[order[stop]]))
            v = max(width_v, int(points[order[stop]]))
            if (stop + 1 - start) * f * v > _SAT_ENTRIES_PER_CHUNK:
                break
            width_f, width_v, stop = f, v, stop + 1
        chosen = order[start:stop]
        pa, pb = a[chosen], b[chosen]
        # height[p, f, v]: signed distance of vertex v of b beyond face f of a.
        height = (
            np.matmul(normals[pa, :width_f], vertices[pb, :width_v].transpose(0, 2, 1))
            - offsets[pa, :width_f][:, :, None]
        )
        out[chosen] = np.any(height.min(axis=2) >= -slack, axis=1)
        start = stop
    return out


def _separated_by_facing_face(pack: PackedBlocks, a: np.ndarray, b: np.ndarray, slack: float):
    """Like :func:`_separated_by_face`, trying only the face of ``a`` most aligned with the
    direction from ``a``'s vertex mean to ``b``'s (a quarter of the work)."""
    normals, offsets = _padded_faces(pack)
    vertices = _padded_vertices(pack)
    middle = (
        np.add.reduceat(pack.vertices, pack.vertex_start[:-1], axis=0)
        / np.maximum(pack.vertex_count, 1)[:, None]
    )
    out = np.zeros(len(a), dtype=bool)
    chunk = max(1, _SAT_ENTRIES_PER_CHUNK // (normals.shape[1] + vertices.shape[1]))
    for start in range(0, len(a), chunk):
        pa, pb = a[start : start + chunk], b[start : start + chunk]
        toward = middle[pb] - middle[pa]
        alignment = np.einsum("mfk,mk->mf", normals[pa], toward)
        alignment[~np.isfinite(offsets[pa])] = -np.inf  # padding faces
        best = np.argmax(alignment, axis=1)[:, None]
        normal = np.take_along_axis(normals[pa], best[:, :, None], axis=1)[:, 0]
        offset = np.take_along_axis(offsets[pa], best, axis=1)[:, 0]
        height = np.einsum("mvk,mk->mv", vertices[pb], normal) - offset[:, None]
        out[start : start + chunk] = height.min(axis=1) >= -slack
    return out


def _padded_faces(pack: PackedBlocks) -> tuple[np.ndarray, np.ndarray]:
    """``(n, F, 3)`` face normals and ``(n, F)`` offsets; padding faces have offset +inf."""
    count = pack.face_count
    width = int(count.max()) if len(count) else 1
    slot = np.arange(width)[None, :]
    valid = slot < count[:, None]
    face = np.where(valid, pack.face_start[:-1, None] + slot, 0)
    normals = np.where(valid[:, :, None], pack.face_normal[face], 0.0)
    offsets = np.where(valid, pack.face_offset[face], np.inf)
    return normals, offsets


def _padded_vertices(pack: PackedBlocks) -> np.ndarray:
    """``(n, V, 3)`` block vertices, short blocks padded with their first vertex."""
    count = pack.vertex_count
    width = int(count.max()) if len(count) else 1
    slot = np.arange(width)[None, :]
    index = pack.vertex_start[:-1, None] + np.where(slot < count[:, None], slot, 0)
    return pack.vertices[index]


class _Stranded(Exception):
    """The free blocks with no chain of contacts to a support (``blocks``), for a caller that
    lets them ride as load."""

    def __init__(self, blocks: np.ndarray):
        super().__init__(f"{len(blocks)} blocks touch no support")
        self.blocks = blocks


def stranded_blocks(model: Model, interfaces: list[Interface], bodies) -> np.ndarray:
    """Positions of the free blocks of ``bodies`` with no chain of contacts to a support."""
    import dataclasses

    try:
        check_support(model, interfaces, dataclasses.replace(bodies, unsupported="ride"))
    except _Stranded as stranded:
        return stranded.blocks
    return np.zeros(0, dtype=np.int64)


def check_support(model: Model, interfaces: list[Interface], bodies=None) -> None:
    """Raise :class:`StaticsError` naming free structural blocks with no path to a support.

    The graph has one node per block plus one for the ground; fixed blocks and the ground are
    supports; every interface is an edge. With ``bodies``, the parts of a body are joined,
    and only the blocks in the statics (``bodies.body >= 0``) count.
    """
    n = len(model.blocks)
    support = n  # the node standing for the ground plane; fixed blocks are joined to it
    first = np.array([i.first for i in interfaces], dtype=np.int64)
    second = np.array([i.second for i in interfaces], dtype=np.int64)
    second = np.where(second == GROUND, support, second)
    fixed = np.flatnonzero([b.fixed and b.structural for b in model.blocks])
    free = np.array([b.structural and not b.fixed for b in model.blocks] + [False], dtype=bool)
    rows, cols = [first, fixed], [second, np.full(len(fixed), support)]
    if bodies is not None:
        inside = np.append(bodies.body >= 0, True)
        keep = inside[first] & inside[second]
        rows[0], cols[0] = first[keep], second[keep]
        parts = np.flatnonzero(bodies.body >= 0)
        leader = np.full(bodies.count, n, dtype=np.int64)
        np.minimum.at(leader, bodies.body[parts], parts)
        rows.append(parts)
        cols.append(leader[bodies.body[parts]])
        free[:n] &= bodies.body >= 0
    rows, cols = np.concatenate(rows), np.concatenate(cols)
    _, label = connected_components(n + 1, rows, cols)
    stranded = np.flatnonzero(free & (label != label[support]))
    if len(stranded) == 0:
        return
    if bodies is not None and bodies.unsupported == "ride":
        raise _Stranded(stranded)
    group = stranded[label[stranded] == label[stranded[0]]]
    names = ", ".join(repr(model.blocks[k].id) for k in group[:_LISTED_IDS])
    if len(group) > _LISTED_IDS:
        names += f" and {len(group) - _LISTED_IDS} more"
    if len(group) == 1:
        subject = f"block {names} touches"
    else:
        subject = f"blocks {names} ({len(group)} blocks) touch"
    others = ""
    other_groups = len(np.unique(label[stranded])) - 1
    if other_groups:
        others = (
            f"; {other_groups} more unsupported group{'s' if other_groups > 1 else ''} "
            f"({len(stranded) - len(group)} blocks)"
        )
    raise StaticsError(f"{subject} no support through any chain of contacts{others}")
