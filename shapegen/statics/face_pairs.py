"""Candidate face pairs of a contact search: faces that may touch, found on a grid.

Two faces can touch only if their centres are close (within their sizes), their normals
opposite and their planes at the same offset. Each face becomes a point of (centre, normal,
offset) scaled by those bounds, and :func:`near_pairs` finds every pair of points within one
unit of each other in the max norm on a hashed grid of cells, in numpy, so that ``analyze`` needs
no KD-tree (scipy.spatial's import alone cost 0.13 s a process). Faces are taken by size class
(each class's radius bounds its centres' distance), every pair of classes in one pass.
:func:`facing_face_pairs` is the first stage of :func:`shapegen.statics.contacts.find_interfaces`.
"""

from __future__ import annotations

__all__ = ["facing_face_pairs", "near_pairs"]

import numpy as np

from shapegen.limits import check_clock
from shapegen.model.packed import PackedBlocks
from shapegen.tolerances import DIVISION_FLOOR, ROUNDOFF_REL, Tolerances

_RADIUS_CLASSES = 12  # faces smaller than 2**-12 of the largest share the last class
_HEMISPHERE = np.array([0.5773, 0.5771, 0.5780])  # generic: no common face is normal to it
# The grid of :func:`near_pairs` over a face's point (centre / R, normal / delta, offset / W):
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
# candidate pairs tested at once by :func:`near_pairs` (each costs about 120 bytes)
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
    (:func:`near_pairs`). Faces
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
    near_a, near_b = near_pairs(
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


def near_pairs(
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
