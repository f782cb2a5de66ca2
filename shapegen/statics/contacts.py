"""Contact interfaces: where blocks touch each other, a fixed support or the ground plane.

Two blocks touch where a face of one and a face of the other are coplanar, opposite-facing and
overlap; the contact polygon is the intersection of the two (convex) face polygons. The search
runs in three vectorised stages:

1. candidate face pairs from a grid over the faces' centres, normals and plane offsets
   (:func:`facing_face_pairs`); block bounding boxes (:func:`candidate_pairs`, used by the
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
from shapegen.statics.interface import GROUND, Interface, tangent_frame
from shapegen.tolerances import DIVISION_FLOOR, ROUNDOFF_REL, Tolerances

_RADIUS_CLASSES = 12  # faces smaller than 2**-12 of the largest share the last class
_HEMISPHERE = np.array([0.5773, 0.5771, 0.5780])  # generic: no common face is normal to it
# The grid of :func:`_near_pairs` over a face's point (centre / R, normal / delta, offset / W):
# cells of 8 units for the centres, 16 for the normals and 8 for the offset (two points that
# may pair are within 1 unit). Big cells keep a point's window within one cell along most
# coordinates (so few cells are looked into) at the price of more candidates to test: on
# running-bond walls of 2 000 and 10 000 bricks, 10 000 voussoirs of an arch, Cluny and
# Sainte-Chapelle these sizes were the fastest of those tried (cells of 3, 4 and 8 for the
# centres), 3-10 times faster than scipy's KD-tree on the large ones, within 0.7-1.25x of it
# on Cluny and Sainte-Chapelle (about 20 ms; docs/journal/performance.md).
_CELL = np.array([8.0, 8.0, 8.0, 16.0, 16.0, 16.0, 8.0])
# the grid starts at these fractions of a cell: generic, so that exact values common in models
# (a normal's 0 or +-1 / delta) do not fall on a cell's edge
_CELL_START = np.array([0.3183, 0.2718, 0.4142, 0.1732, 0.2236, 0.3606, 0.1414])
# odd 64-bit constants that mix a cell's seven integer coordinates into one key; two cells
# whose keys collide only add candidates, which the exact test then drops
_CELL_MIX = np.array(
    [
        0x9E3779B97F4A7C15,
        0xC2B2AE3D27D4EB4F,
        0x165667B19E3779F9,
        0x27D4EB2F165667C5,
        0x85EBCA77C2B2AE63,
        0xFF51AFD7ED558CCD,
        0xC4CEB9FE1A85EC53,
    ],
    dtype=np.uint64,
)
_GROUP_MIX = np.uint64(0xD6E8FEB86659FD93)
# candidate pairs tested at once by :func:`_near_pairs` (each costs about 120 bytes)
_CANDIDATE_BAND = 2**20


# ------------------------------------------------------------------------------------ face pairs
def facing_face_pairs(pack: PackedBlocks, tol: Tolerances) -> tuple[np.ndarray, np.ndarray]:
    """Pairs of faces that may touch: near-opposite normals, near-equal planes, close centres.

    Block bounding boxes are a poor index for contacts between slender, slanted blocks (the
    boxes of the voussoirs of a fine arch overlap hundreds of others), so the contact search
    indexes faces. Face ``f`` with vertex mean ``c``, unit normal ``n`` and radius ``r`` (largest
    vertex distance from ``c``) becomes the point ``(c / R, n / delta, n . (c - o) / W)`` and a
    possible partner ``g`` the point ``(c / R, -n / delta, -n . (c - o) / W)``, where

    - ``delta = sqrt(2 (1 - normal_cos))`` is the largest ``|n_f + n_g|`` of opposite faces,
    - ``R`` bounds ``r_f + r_g`` (two overlapping faces have centres at most that far apart),
    - ``o`` is the middle of the model and ``W = planar + delta * max|c - o|`` bounds the
      difference of the plane offsets of two coplanar opposite faces.

    Two touching faces are then within distance 1 in the max norm, which a grid of cells finds
    (:func:`_near_pairs`). Faces
    are grouped into radius classes (factors of 2) so that ``R`` stays close to the faces' own
    size, and split by the sign of ``n . h`` (``h`` a fixed generic direction) so that each pair
    is searched for in one order only.

    Returns
    -------
    tuple of numpy.ndarray
        Face numbers ``(f, g)`` with ``f < g``, each unordered pair once: a superset of the
        touching pairs, possibly including pairs within one block.
    """
    corner_count = np.diff(pack.corner_start)
    if len(corner_count) == 0:
        return np.zeros(0, dtype=np.int64), np.zeros(0, dtype=np.int64)
    center, normal = pack.face_center, pack.face_normal
    spread = np.linalg.norm(
        pack.vertices[pack.corners] - np.repeat(center, corner_count, axis=0), axis=1
    )
    radius = np.maximum.reduceat(spread, pack.corner_start[:-1])
    delta = np.sqrt(2.0 * max(1.0 - tol.normal_cos, 0.0)) + ROUNDOFF_REL
    middle = 0.5 * (center.min(axis=0) + center.max(axis=0))
    width = (
        tol.planar + delta * float(np.linalg.norm(center - middle, axis=1).max()) + DIVISION_FLOOR
    )
    offset = np.einsum("ij,ij->i", normal, center - middle) / width
    largest = float(radius.max())
    size_class = np.floor(np.log2(largest / np.maximum(radius, largest * 2.0**-_RADIUS_CLASSES)))
    size_class = np.minimum(size_class, _RADIUS_CLASSES).astype(np.int64)
    # Of two opposite faces one has n . h > -delta and the other n . h < delta.
    side = normal @ _HEMISPHERE
    upward = side > -delta
    downward = side < delta
    classes = [c for c in range(_RADIUS_CLASSES + 1) if np.any(size_class == c)]
    # every pair of classes searched at once: each its own points, told apart by its number
    faces_a, points_a, pair_a, faces_b, points_b, pair_b = [], [], [], [], [], []
    for class_a in classes:
        group_a = np.flatnonzero((size_class == class_a) & upward)
        for class_b in classes:
            group_b = np.flatnonzero((size_class == class_b) & downward)
            if len(group_a) == 0 or len(group_b) == 0:
                continue
            reach = radius[group_a].max() + radius[group_b].max() + tol.planar
            faces_a.append(group_a)
            points_a.append(
                np.hstack([center[group_a] / reach, normal[group_a] / delta, offset[group_a, None]])
            )
            pair_a.append(np.full(len(group_a), len(pair_a)))
            faces_b.append(group_b)
            points_b.append(
                np.hstack(
                    [center[group_b] / reach, -normal[group_b] / delta, -offset[group_b, None]]
                )
            )
            pair_b.append(np.full(len(group_b), len(pair_b)))
    if not faces_a:
        return np.zeros(0, dtype=np.int64), np.zeros(0, dtype=np.int64)
    near_a, near_b = _near_pairs(
        np.concatenate(points_a),
        np.concatenate(points_b),
        np.concatenate(pair_a),
        np.concatenate(pair_b),
    )
    pairs = np.stack([np.concatenate(faces_a)[near_a], np.concatenate(faces_b)[near_b]], axis=1)
    pairs = np.unique(np.sort(pairs, axis=1), axis=0)
    pairs = pairs[pairs[:, 0] != pairs[:, 1]]
    return pairs[:, 0].astype(np.int64), pairs[:, 1].astype(np.int64)


def _cell_keys(cells: np.ndarray, group: np.ndarray) -> np.ndarray:
    """One 64-bit key per row of integer cell coordinates and its group (wrapping: collisions
    are allowed)."""
    mixed = (cells.view(np.uint64) * _CELL_MIX).sum(axis=1, dtype=np.uint64)
    return mixed ^ (group.astype(np.uint64) * _GROUP_MIX)


def _near_pairs(
    points_a: np.ndarray,
    points_b: np.ndarray,
    group_a: np.ndarray | None = None,
    group_b: np.ndarray | None = None,
) -> tuple[np.ndarray, np.ndarray]:
    """Every pair ``(i, j)`` with ``max |points_a[i] - points_b[j]| <= 1`` (seven columns) and
    ``group_a[i] == group_b[j]`` (integer groups; all in one group when None).

    The points of ``b`` are sorted by the key of their grid cell (:data:`_CELL`); the window
    ``[p - 1, p + 1]`` of a point of ``a`` meets one or two cells along each coordinate (the
    cells are at least 2 wide), and the points of ``b`` in each of those cells are candidates,
    kept when they are within the window. This is what a KD-tree's fixed-radius query in the max
    norm returns, pair for pair, without scipy.spatial (whose import costs a command about
    0.08 s).
    """
    if len(points_a) == 0 or len(points_b) == 0:
        return np.zeros(0, dtype=np.int64), np.zeros(0, dtype=np.int64)
    if group_a is None or group_b is None:
        group_a, group_b = np.zeros(len(points_a), np.int64), np.zeros(len(points_b), np.int64)
    start = _CELL_START * _CELL
    cells_b = np.floor((points_b - start) / _CELL).astype(np.int64)
    keys_b = _cell_keys(cells_b, group_b)
    order = np.argsort(keys_b, kind="stable")
    keys_b = keys_b[order]
    # the occupied cells: their keys, where their points start in ``order`` and how many
    starts_b = np.flatnonzero(np.concatenate([[True], keys_b[1:] != keys_b[:-1]]))
    counts_b = np.diff(np.append(starts_b, len(keys_b)))
    keys_b = keys_b[starts_b]
    low = np.floor((points_a - 1.0 - start) / _CELL).astype(np.int64)
    two = np.floor((points_a + 1.0 - start) / _CELL).astype(np.int64) > low
    # the cells looked into: for each point every choice of low or low + 1 along the
    # coordinates where its window meets two cells
    point = np.arange(len(points_a))
    cells = low
    for column in range(points_a.shape[1]):
        more = np.flatnonzero(two[point, column])
        upper = cells[more]
        upper[:, column] += 1
        point = np.concatenate([point, point[more]])
        cells = np.concatenate([cells, upper])
    keys = _cell_keys(cells, group_a[point])
    cell = np.minimum(np.searchsorted(keys_b, keys), len(keys_b) - 1)
    hit = keys_b[cell] == keys
    point, first, count = point[hit], starts_b[cell[hit]], counts_b[cell[hit]]
    found_a, found_b = [], []
    total = np.cumsum(count)
    bands = np.arange(1, int(total[-1]) // _CANDIDATE_BAND + 1 if len(total) else 1)
    bounds = np.searchsorted(total, bands * _CANDIDATE_BAND)
    bounds = np.unique(np.concatenate([[0], bounds, [len(count)]]))
    for lo, hi in zip(bounds[:-1].tolist(), bounds[1:].tolist(), strict=True):
        check_clock()
        n = count[lo:hi]
        i = np.repeat(point[lo:hi], n)
        within = np.arange(len(i)) - np.repeat(np.cumsum(n) - n, n)
        j = order[np.repeat(first[lo:hi], n) + within]
        close = (np.abs(points_a[i] - points_b[j]) <= 1.0).all(axis=1) & (group_a[i] == group_b[j])
        found_a.append(i[close])
        found_b.append(j[close])
    if not found_a:
        return np.zeros(0, dtype=np.int64), np.zeros(0, dtype=np.int64)
    return np.concatenate(found_a), np.concatenate(found_b)


# ------------------------------------------------------------------------------------- interfaces
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
