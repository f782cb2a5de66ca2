"""Contact interfaces: where blocks touch each other, a fixed support or the ground plane.

Two blocks touch where a face of one and a face of the other are coplanar, opposite-facing and
overlap; the contact polygon is the intersection of the two (convex) face polygons. The search
runs in three vectorised stages:

1. candidate face pairs from a grid over the faces' centres, normals and plane offsets
   (:mod:`shapegen.statics.face_pairs`); block bounding boxes (:func:`candidate_pairs`, used by the
   overlap checks, :mod:`shapegen.statics.broad_phase`) would pair each voussoir of a fine
   arch with hundreds of others;
2. the exact tests: normals opposite within ``normal_cos``, each face's centre on the other's
   plane within ``planar``;
3. the surviving face pairs are clipped against each other all at once (Sutherland-Hodgman on
   padded 2D polygons, one clip edge at a time for the whole batch), then near-duplicate and
   straight-edge vertices are dropped and slivers below ``area`` discarded.

All tolerances come from ``model.tolerances()``.
"""

from __future__ import annotations

__all__ = [
    "candidate_pairs",
    "facing_face_pairs",
    "find_interfaces",
]


import numpy as np

from shapegen.limits import check_clock
from shapegen.model.model import Model
from shapegen.model.packed import PackedBlocks, pack_blocks
from shapegen.statics.broad_phase import candidate_pairs
from shapegen.statics.face_pairs import facing_face_pairs
from shapegen.statics.interface import GROUND, Interface, tangent_frame
from shapegen.tolerances import Tolerances


def find_interfaces(
    model: Model, tol: Tolerances | None = None, pack: PackedBlocks | None = None
) -> list[Interface]:
    """Every contact polygon between structural blocks, fixed supports and the ground plane.

    Parameters
    ----------
    model
        The block assembly. Non-structural blocks are ignored; contacts between two fixed blocks
        (or a fixed block and the ground) are not reported, since supports need no equilibrium.
    tol
        Absolute tolerances; default ``model.tolerances()`` (scaled to the model's size).
    pack
        The structural blocks already packed (``pack_blocks(model.blocks, structural)``), by
        a caller that packs them for its checks too; packed here when None.

    Returns
    -------
    list[Interface]
        Sorted by ``(first, second)``. Between two free blocks ``first`` is the lower index;
        between a free and a fixed block ``first`` is the free one; ground contacts have
        ``second == GROUND``. ``normal`` is the outward normal of ``first``'s face.
    """
    tol = model.tolerances() if tol is None else tol
    structural = np.array([b.structural for b in model.blocks], dtype=bool)
    if pack is None:
        pack = pack_blocks(model.blocks, np.flatnonzero(structural))
    if len(pack.index) == 0:
        return []
    fixed = np.array([model.blocks[i].fixed for i in pack.index], dtype=bool)

    polygons = list(_block_contacts(pack, fixed, tol))
    if model.ground is not None:
        polygons.append(_ground_contacts(pack, fixed, float(model.ground), tol))
    first = np.concatenate([p[0] for p in polygons])
    second = np.concatenate([p[1] for p in polygons])
    normal = np.concatenate([p[2] for p in polygons])
    points = np.concatenate([p[3] for p in polygons])
    counts = np.concatenate([p[4] for p in polygons])
    face_key = np.concatenate([p[5] for p in polygons])

    order = np.lexsort((face_key, second, first))
    starts = np.concatenate([[0], np.cumsum(counts)])
    # One tangent frame per distinct normal (bit for bit), shared by its interfaces.
    keys = np.ascontiguousarray(normal).view(np.dtype((np.void, 3 * normal.itemsize))).ravel()
    _, representative, which = np.unique(keys, return_index=True, return_inverse=True)
    frames = [tangent_frame(normal[i]) for i in representative.tolist()]
    first, second, which = first[order], second[order], which.ravel()[order]
    interfaces = [
        Interface(a, b, normal[k], *frames[w], points[start:end])
        for k, a, b, w, start, end in zip(
            order.tolist(),
            first.tolist(),
            second.tolist(),
            which.tolist(),
            starts[order].tolist(),
            starts[order + 1].tolist(),
            strict=True,
        )
    ]
    run_start = np.flatnonzero(
        np.concatenate([[True], (first[1:] != first[:-1]) | (second[1:] != second[:-1])])
    )
    return _merge_split_contacts(interfaces, tol, run_start)


# The face pairs clipped at once: their padded polygons (pairs x the most corners of a face
# x 3 coordinates) at most this many bytes, so that faces of many corners facing many others
# (a 300-sided cylinder's caps among 400 000 candidate pairs: 2.7 GiB at once) take bounded
# memory, with the work clock looked at between bands.
_BAND_BYTES = 16 * 2**20


def _block_contacts(pack: PackedBlocks, fixed: np.ndarray, tol: Tolerances):
    """Contact polygons between pairs of packed blocks (not both fixed), in bands of pairs
    (:data:`_BAND_BYTES`): a tuple of arrays for each band, at least one."""
    face_a, face_b = facing_face_pairs(pack, tol)
    block_a, block_b = pack.face_block[face_a], pack.face_block[face_b]
    keep = (block_a != block_b) & ~(fixed[block_a] & fixed[block_b])
    face_a, face_b, block_a, block_b = face_a[keep], face_b[keep], block_a[keep], block_b[keep]
    # A free block always comes first; between two free blocks the lower index does (pack
    # order follows model order).
    swap = fixed[block_a] | (~fixed[block_b] & (block_b < block_a))
    face_a, face_b = np.where(swap, face_b, face_a), np.where(swap, face_a, face_b)

    n_a = pack.face_normal[face_a]
    n_b = pack.face_normal[face_b]
    opposite = np.einsum("ij,ij->i", n_a, n_b) < -tol.normal_cos
    face_a, face_b, n_a, n_b = face_a[opposite], face_b[opposite], n_a[opposite], n_b[opposite]
    # Coplanar: each face's centre lies on the other's plane.
    gap_ab = np.einsum("ij,ij->i", n_a, pack.face_center[face_b]) - pack.face_offset[face_a]
    gap_ba = np.einsum("ij,ij->i", n_b, pack.face_center[face_a]) - pack.face_offset[face_b]
    coplanar = (np.abs(gap_ab) <= tol.planar) & (np.abs(gap_ba) <= tol.planar)
    face_a, face_b = face_a[coplanar], face_b[coplanar]
    corners = np.diff(pack.corner_start)
    width = int(max(corners[face_a].max(initial=3), corners[face_b].max(initial=3)))
    band = max(1, _BAND_BYTES // (width * 3 * 8))
    for start in range(0, max(len(face_a), 1), band):
        check_clock()
        yield _contact_polygons(
            pack, face_a[start : start + band], face_b[start : start + band], tol
        )


def _contact_polygons(pack: PackedBlocks, face_a, face_b, tol: Tolerances) -> tuple:
    """The contact polygons of the coplanar, opposite faces ``face_a[k]``, ``face_b[k]``."""
    normal = pack.face_normal[face_a]
    u, v = _plane_axes(normal)
    subject, subject_count = _project_faces(pack, face_a, u, v)
    clip, clip_count = _project_faces(pack, face_b, u, v)
    # Face b winds counter-clockwise about its own normal, i.e. clockwise in a's frame.
    clip, clip_count = _reverse_polygons(clip, clip_count)
    polygon, count = _clip_convex(subject, subject_count, clip, clip_count, tol.merge)
    polygon, count = _clean_polygons(polygon, count, tol.merge)
    area = _polygon_area(polygon, count)
    keep = (count >= 3) & (area >= tol.area)
    plane = pack.face_offset[face_a][keep]
    points = _lift(polygon[keep], count[keep], u[keep], v[keep], normal[keep], plane)
    face_key = face_a[keep] * (len(pack.face_normal) + 1) + face_b[keep]
    return (
        pack.index[pack.face_block[face_a[keep]]],
        pack.index[pack.face_block[face_b[keep]]],
        normal[keep],
        points,
        count[keep],
        face_key,
    )


def _ground_contacts(pack: PackedBlocks, fixed: np.ndarray, ground: float, tol: Tolerances):
    """Faces of free blocks lying on the ground plane y = ``ground``, facing down."""
    free_face = ~fixed[pack.face_block]
    down = pack.face_normal[:, 1] < -tol.normal_cos
    on_ground = np.abs(pack.face_center[:, 1] - ground) <= tol.planar
    faces = np.flatnonzero(free_face & down & on_ground)
    normal = np.tile([0.0, -1.0, 0.0], (len(faces), 1))
    u, v = _plane_axes(normal)
    polygon, count = _project_faces(pack, faces, u, v)
    polygon, count = _clean_polygons(polygon, count, tol.merge)
    area = _polygon_area(polygon, count)
    keep = (count >= 3) & (area >= tol.area)
    # Lifted onto the ground plane itself: normal . x = -ground there.
    plane = np.full(int(keep.sum()), -ground)
    points = _lift(polygon[keep], count[keep], u[keep], v[keep], normal[keep], plane)
    return (
        pack.index[pack.face_block[faces[keep]]],
        np.full(int(keep.sum()), GROUND, dtype=np.int64),
        normal[keep],
        points,
        count[keep],
        faces[keep],
    )


def _merge_split_contacts(
    interfaces: list[Interface], tol: Tolerances, run_start: np.ndarray
) -> list[Interface]:
    """Join the pieces of one contact that a block with split coplanar faces produces.

    Two convex blocks touch in one convex polygon; when a block's face is given as several
    coplanar polygons (a triangulated mesh) the pieces arrive separately and their union is the
    convex hull of their vertices. ``run_start`` gives where each run of interfaces between the
    same two blocks starts.
    """
    if len(run_start) >= len(interfaces):  # one piece each (or none): nothing to join
        return interfaces
    # scipy.spatial (0.08 s to import) only for a model whose faces come in pieces
    from scipy.spatial import ConvexHull, QhullError

    bounds = [*run_start.tolist(), len(interfaces)]
    out: list[Interface] = []
    for start, stop in zip(bounds[:-1], bounds[1:], strict=True):
        pieces = interfaces[start:stop]
        first, second = pieces[0].first, pieces[0].second
        normal = pieces[0].normal
        if len(pieces) == 1 or any(p.normal @ normal < tol.normal_cos for p in pieces):
            out.extend(pieces)
            continue
        points = np.concatenate([p.vertices for p in pieces])
        t1, t2 = pieces[0].tangent1, pieces[0].tangent2
        plane = points @ normal
        try:
            hull = ConvexHull(np.stack([points @ t1, points @ t2], axis=1))
        except QhullError:
            out.extend(pieces)
            continue
        # 2D hull vertices are counter-clockwise in (t1, t2), hence about t1 x t2 = normal.
        ring = points[hull.vertices]
        ring = ring + np.outer(plane.mean() - plane[hull.vertices], normal)
        out.append(Interface(first, second, normal, t1, t2, ring))
    return out


# ------------------------------------------------------------------------- batched 2D polygon ops
def _plane_axes(normal: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """``(m, 3)`` unit axes u, v with u x v = normal, for projecting onto each plane."""
    helper = np.zeros_like(normal)
    use_x = np.abs(normal[:, 0]) < 0.9
    helper[use_x, 0] = 1.0
    helper[~use_x, 2] = 1.0
    u = np.cross(helper, normal)
    u /= np.linalg.norm(u, axis=1)[:, None]
    v = np.cross(normal, u)
    return u, v


def _project_faces(pack: PackedBlocks, faces: np.ndarray, u: np.ndarray, v: np.ndarray):
    """Faces as padded 2D polygons ``(m, K, 2)`` in the axes (u, v), with vertex counts."""
    count = pack.corner_start[faces + 1] - pack.corner_start[faces]
    width = int(count.max()) if len(faces) else 3
    slot = np.arange(width)
    valid = slot[None, :] < count[:, None]
    corner = pack.corner_start[faces][:, None] + np.where(valid, slot[None, :], 0)
    p = pack.vertices[pack.corners[corner]]
    polygon = np.stack([np.einsum("mkj,mj->mk", p, u), np.einsum("mkj,mj->mk", p, v)], axis=2)
    polygon[~valid] = 0.0
    return polygon, count


def _reverse_polygons(polygon: np.ndarray, count: np.ndarray):
    """The same padded polygons with their winding reversed."""
    width = polygon.shape[1]
    slot = np.arange(width)
    source = np.where(slot[None, :] < count[:, None], count[:, None] - 1 - slot[None, :], slot)
    return np.take_along_axis(polygon, source[:, :, None], axis=1), count


def _cyclic_neighbor(count: np.ndarray, width: int, step: int) -> np.ndarray:
    """Slot index of the next (step 1) or previous (step -1) vertex within each polygon."""
    slot = np.arange(width)[None, :]
    safe = np.maximum(count, 1)[:, None]
    return np.where(slot < count[:, None], (slot + step) % safe, slot)


def _compact(points: np.ndarray, keep: np.ndarray):
    """Move the kept vertices of each row to the front, in order; returns points and counts."""
    order = np.argsort(~keep, axis=1, kind="stable")
    count = keep.sum(axis=1)
    width = max(int(count.max()) if len(count) else 0, 3)
    order = order[:, :width]
    out = np.take_along_axis(points, order[:, :, None], axis=1)
    out[np.arange(width)[None, :] >= count[:, None]] = 0.0
    return out, count


def _clip_convex(subject, subject_count, clip, clip_count, eps: float):
    """Sutherland-Hodgman: each subject polygon clipped by its convex clip polygon (both CCW).

    A vertex within ``eps`` metres of a clip edge counts as inside, so shared edges survive
    without spurious intersection points.
    """
    polygon, count = subject, subject_count.copy()
    for edge in range(clip.shape[1]):
        check_clock()  # a band of faces of hundreds of corners: a pass takes tens of ms
        active = edge < clip_count
        start = clip[:, edge]
        end = clip[np.arange(len(clip)), (edge + 1) % np.maximum(clip_count, 1)]
        direction = end - start
        length = np.linalg.norm(direction, axis=1)
        length = np.where(length > 0, length, 1.0)
        relative = polygon - start[:, None, :]
        distance = (
            direction[:, None, 0] * relative[..., 1] - direction[:, None, 1] * relative[..., 0]
        )
        distance /= length[:, None]
        width = polygon.shape[1]
        valid = np.arange(width)[None, :] < count[:, None]
        distance = np.where(active[:, None], distance, np.inf)
        nxt = _cyclic_neighbor(count, width, 1)
        distance_next = np.take_along_axis(distance, nxt, axis=1)
        polygon_next = np.take_along_axis(polygon, nxt[:, :, None], axis=1)
        inside = distance >= -eps
        inside_next = distance_next >= -eps
        crossing = valid & (inside != inside_next)
        with np.errstate(invalid="ignore", divide="ignore"):
            t = distance / (distance - distance_next)
        t = np.where(crossing, np.clip(t, 0.0, 1.0), 0.0)
        crossing_point = polygon + t[:, :, None] * (polygon_next - polygon)
        # Each subject edge emits its start vertex (if inside) then the crossing (if any).
        emitted = np.stack([polygon, crossing_point], axis=2).reshape(len(polygon), 2 * width, 2)
        keep = np.stack([valid & inside, crossing], axis=2).reshape(len(polygon), 2 * width)
        polygon, count = _compact(emitted, keep)
        count = np.where(count >= 3, count, 0)
    return polygon, count


def _clean_polygons(polygon: np.ndarray, count: np.ndarray, merge: float):
    """Drop near-duplicate vertices and vertices on a straight edge (within ``merge`` metres)."""
    if len(polygon) == 0:
        return polygon, count
    width = polygon.shape[1]
    valid = np.arange(width)[None, :] < count[:, None]
    previous = np.take_along_axis(polygon, _cyclic_neighbor(count, width, -1)[:, :, None], axis=1)
    distinct = np.linalg.norm(polygon - previous, axis=2) > merge
    # A polygon whose vertices all coincide keeps none of them.
    polygon, count = _compact(polygon, valid & distinct)
    width = polygon.shape[1]
    valid = np.arange(width)[None, :] < count[:, None]
    previous = np.take_along_axis(polygon, _cyclic_neighbor(count, width, -1)[:, :, None], axis=1)
    following = np.take_along_axis(polygon, _cyclic_neighbor(count, width, 1)[:, :, None], axis=1)
    chord = following - previous
    offset = polygon - previous
    twice_area = np.abs(chord[..., 0] * offset[..., 1] - chord[..., 1] * offset[..., 0])
    straight = twice_area <= merge * np.linalg.norm(chord, axis=2)
    polygon, count = _compact(polygon, valid & ~straight)
    return polygon, np.where(count >= 3, count, 0)


def _polygon_area(polygon: np.ndarray, count: np.ndarray) -> np.ndarray:
    """Signed areas (positive counter-clockwise) of padded 2D polygons, m^2."""
    if len(polygon) == 0:
        return np.zeros(0)
    following = np.take_along_axis(
        polygon, _cyclic_neighbor(count, polygon.shape[1], 1)[:, :, None], axis=1
    )
    valid = np.arange(polygon.shape[1])[None, :] < count[:, None]
    cross = polygon[..., 0] * following[..., 1] - polygon[..., 1] * following[..., 0]
    return 0.5 * np.where(valid, cross, 0.0).sum(axis=1)


def _lift(polygon, count, u, v, normal, offset) -> np.ndarray:
    """Padded 2D polygons back to 3D points on the planes ``normal . x = offset``, concatenated."""
    valid = np.arange(polygon.shape[1])[None, :] < count[:, None]
    points = (
        polygon[..., 0:1] * u[:, None, :]
        + polygon[..., 1:2] * v[:, None, :]
        + (offset[:, None] * normal)[:, None, :]
    )
    return points[valid].reshape(-1, 3)
