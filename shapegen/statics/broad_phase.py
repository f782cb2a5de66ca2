"""Pairs of blocks whose bounding boxes overlap or touch: the broad phase of the overlap checks.

Boxes are put in the cells of a uniform grid about twice the size of a typical box, and only
boxes sharing a cell are compared, so a wall of n bricks costs about 8 n comparisons. A sweep
along one axis, which this replaces, compares each brick of a wall with every brick of the
other courses above and below it (n^1.5: 5 s for 100 000 bricks). Boxes spanning many cells (a
slab under everything) are compared with all boxes directly; when they are many, or the grid
would be too fine to index, the sweep is used after all. The result is the same set of pairs
either way.
"""

from __future__ import annotations

__all__ = ["candidate_pairs"]

import numpy as np

_PAIRS_PER_CHUNK = 2_000_000  # bounds the memory of one sweep step (~50 MB of index arrays)
_CELLS_PER_BOX = 64  # a box over more cells is compared with every box directly
_LARGE_BOXES = 256  # more such boxes than this: the sweep instead
_GRID_KEYS = 2**62  # the grid's cells must be numbered within int64
_ENTRIES_PER_CHUNK = 250_000  # (cell, box) entries paired at once
_PAIRS_PER_BOX = 64  # more same-cell pairs than this per box on average: the sweep instead


def candidate_pairs(lower: np.ndarray, upper: np.ndarray, padding: float = 0.0) -> np.ndarray:
    """Pairs of boxes that overlap or touch.

    Parameters
    ----------
    lower, upper
        ``(n, 3)`` box corners, metres.
    padding
        Boxes closer than ``padding`` metres count as touching.

    Returns
    -------
    numpy.ndarray
        ``(m, 2)`` integer pairs ``(i, j)`` with ``i < j``, sorted lexicographically.
    """
    lower = np.asarray(lower, dtype=float).reshape(-1, 3)
    upper = np.asarray(upper, dtype=float).reshape(-1, 3)
    n = len(lower)
    if n < 2:
        return np.empty((0, 2), dtype=np.int64)
    pairs = _grid_pairs(lower, upper, padding)
    if pairs is None:
        pairs = _sweep_pairs(lower, upper, padding)
    pairs.sort(axis=1)
    pairs = np.unique(pairs[:, 0] * n + pairs[:, 1])
    return np.stack([pairs // n, pairs % n], axis=1)


def _overlapping(lower, upper, a, b, padding) -> np.ndarray:
    return np.all((lower[a] <= upper[b] + padding) & (lower[b] <= upper[a] + padding), axis=1)


def _grid_pairs(lower, upper, padding) -> np.ndarray | None:
    """The overlapping pairs found through a grid (unsorted, each at least once), or None when
    the boxes do not suit one."""
    n = len(lower)
    reach = upper + padding
    if not (np.isfinite(lower).all() and np.isfinite(reach).all()):
        return None
    extent = reach - lower
    cell = 2.0 * np.median(extent, axis=0)
    span_all = reach.max(axis=0) - lower.min(axis=0)
    cell = np.where(cell > 0, cell, np.maximum(span_all, 1.0))
    origin = lower.min(axis=0)
    # A box covers the cells its closed interval [lower, upper + padding] meets: two boxes that
    # overlap or touch (with padding) meet in at least one cell. Equal coordinates give equal
    # cells, so touching boxes are never split by rounding.
    first = np.floor((lower - origin) / cell).astype(np.int64)
    last = np.floor((reach - origin) / cell).astype(np.int64)
    shape = last.max(axis=0) + 1
    if float(np.prod(shape.astype(float))) >= _GRID_KEYS:
        return None
    span = last - first + 1
    covered = span.prod(axis=1)
    large = np.flatnonzero(covered > _CELLS_PER_BOX)
    if len(large) > _LARGE_BOXES:
        return None
    small = np.flatnonzero(covered <= _CELLS_PER_BOX)

    # One (cell, box) entry for every cell a small box covers.
    count = covered[small]
    box = np.repeat(small, count)
    within = np.arange(int(count.sum())) - np.repeat(np.cumsum(count) - count, count)
    sx, sy = span[box, 0], span[box, 1]
    cx = first[box, 0] + within % sx
    cy = first[box, 1] + (within // sx) % sy
    cz = first[box, 2] + within // (sx * sy)
    key = (cx * shape[1] + cy) * shape[2] + cz
    order = np.lexsort((box, key))
    key, box = key[order], box[order]
    # Pairs within each cell: each entry with the entries after it in its cell.
    cell_end = np.searchsorted(key, key, side="right")
    after = cell_end - np.arange(len(key)) - 1
    if int(after.sum()) > _PAIRS_PER_BOX * n:  # crowded cells (boxes of very unequal sizes)
        return None
    found = []
    for start in range(0, len(key), _ENTRIES_PER_CHUNK):
        rows = np.arange(start, min(start + _ENTRIES_PER_CHUNK, len(key)))
        reps = after[rows]
        position_a = np.repeat(rows, reps)
        run_start = np.cumsum(reps) - reps
        position_b = position_a + 1 + np.arange(int(reps.sum())) - np.repeat(run_start, reps)
        a, b = box[position_a], box[position_b]
        keep = _overlapping(lower, upper, a, b, padding)
        found.append(np.stack([a[keep], b[keep]], axis=1))
    everyone = np.arange(n)
    for k in large.tolist():
        keep = _overlapping(lower, upper, np.full(n, k), everyone, padding)
        keep[k] = False
        found.append(np.stack([np.full(int(keep.sum()), k), everyone[keep]], axis=1))
    return np.concatenate(found) if found else np.empty((0, 2), dtype=np.int64)


def _sweep_pairs(lower, upper, padding) -> np.ndarray:
    """The overlapping pairs by sort-and-sweep along the most selective axis."""
    n = len(lower)
    # Sweep along the axis whose projections overlap least: a wall in the xy plane sweeps
    # along x or y, never along its thickness (which would pair every block with every other).
    best = None
    for axis in range(3):
        order = np.argsort(lower[:, axis], kind="stable")
        sorted_lower = lower[order, axis]
        end = np.searchsorted(sorted_lower, upper[order, axis] + padding, side="right")
        count = np.maximum(end - np.arange(n) - 1, 0)
        total = int(count.sum())
        if best is None or total < best[0]:
            best = (total, order, count)
    _, order, count = best

    found = []
    cumulative = np.cumsum(count)
    start = 0
    while start < n:
        # Positions [start, stop) produce at most _PAIRS_PER_CHUNK sweep pairs (at least one row).
        base = cumulative[start - 1] if start else 0
        stop = int(np.searchsorted(cumulative, base + _PAIRS_PER_CHUNK, side="right"))
        stop = min(max(stop, start + 1), n)
        rows = np.arange(start, stop)
        reps = count[start:stop]
        position_a = np.repeat(rows, reps)
        run_start = np.cumsum(reps) - reps
        position_b = position_a + 1 + np.arange(int(reps.sum())) - np.repeat(run_start, reps)
        a = order[position_a]
        b = order[position_b]
        overlap = _overlapping(lower, upper, a, b, padding)
        found.append(np.stack([a[overlap], b[overlap]], axis=1))
        start = stop
    return np.concatenate(found)
