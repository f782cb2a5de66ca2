"""The start shapes of many lots at once: footprints as packed arrays, their checks and frames.

What :func:`~shapegen.geometry.scope_frames.lot_polygon` and
:func:`~shapegen.engine.shape.lot_shape`
do for one polygon, on every lot together: the checks that refuse a lot (fewer than three
corners, a corner not finite or too far, no area, clockwise, crossing itself), the area, and
whether the extruded footprint is a box filling its scope (a rectangle), a convex prism (a
block) or not convex (a solid kept as derived). A lot whose answer is in doubt within a wide
margin of the one-at-a-time derivation's tolerances (a corner that barely turns, an edge almost
of no length, a rectangle at its tolerance) is ``doubtful``: it is derived one at a time.
"""

from __future__ import annotations

__all__ = ["Footprints"]

import numpy as np

from shapegen.limits import LOT_EXTENT_LIMIT_M
from shapegen.tolerances import (
    BATCH_DOUBT_REL,
    COINCIDENT_M,
    COINCIDENT_REL,
    DEFAULT,
    LOT_MERGE_M,
    ROUNDOFF_REL,
    SIZE_FLOOR_M,
)

_BOX_ATOL = COINCIDENT_REL  # lot_shape's rectangle test: corners within this times the size
_STRAIGHT_SINE = BATCH_DOUBT_REL  # a corner turning by less (sine of its angle) is in doubt
_SHORT_EDGE = BATCH_DOUBT_REL  # an edge shorter than this times the footprint's span is in doubt
_CONVEX_REL = DEFAULT.convex_rel  # the derivation's "clearly not convex"
_THIN = BATCH_DOUBT_REL  # a footprint of less area than this times its span squared is in doubt


class Footprints:
    """Lots given as ``points`` ``(P, 2)`` ``(x, z)`` (m) end to end, ``offsets`` ``(n + 1,)``.

    Attributes (one entry per lot)
    ----------
    doubtful, doubt
        Lots the batch leaves to the one-at-a-time derivation, and why (one reason each).
    area
        The footprint's area (m^2), as ``geometry.area()`` of the lot.
    perimeter
        The length of its edges (m).
    span
        The largest extent along x or z (m).
    box
        A rectangle that fills its scope (the derivation's fast path: a box block).
    convex
        Every corner turns left by a clear margin (the extrusion is one convex block).
    reflex
        The farthest a corner lies in front of the line of the edge before it (m; > 0 where
        the footprint is not convex).
    """

    def __init__(self, points: np.ndarray, offsets: np.ndarray):
        self.points = points
        self.offsets = offsets
        count = len(offsets) - 1
        self.count = count
        sizes = np.diff(offsets)
        self.sizes = sizes
        self.doubtful = np.zeros(count, dtype=bool)
        self.doubt = np.array([""] * count, dtype=object)
        self.area = np.zeros(count)
        self.span = np.zeros(count)
        self.perimeter = np.zeros(count)
        self.box = np.zeros(count, dtype=bool)
        self.convex = np.zeros(count, dtype=bool)
        self.reflex = np.zeros(count)
        self._mark(sizes < 3, "a footprint of fewer than 3 corners")
        lots = np.flatnonzero(sizes >= 3)
        if len(lots):
            self._measure(lots)

    def _mark(self, mask: np.ndarray, reason: str) -> None:
        new = mask & ~self.doubtful
        self.doubtful |= new
        self.doubt[new] = reason

    def _measure(self, lots: np.ndarray) -> None:
        """Everything of lots ``lots`` (all of at least 3 corners), computed together."""
        sizes = self.sizes[lots]
        starts = np.zeros(len(lots) + 1, dtype=np.int64)
        np.cumsum(sizes, out=starts[1:])
        if len(lots) == self.count:
            p = self.points
        else:
            shift = np.repeat(self.offsets[lots] - starts[:-1], sizes)
            p = self.points[shift + np.arange(int(starts[-1]))]
        owner = np.repeat(np.arange(len(lots)), sizes)
        finite = np.isfinite(p).all(axis=1)
        p = np.where(finite[:, None], p, 0.0)
        bad = np.bincount(owner, weights=~finite, minlength=len(lots)) > 0
        far = np.bincount(owner, weights=np.abs(p).max(axis=1) > LOT_EXTENT_LIMIT_M,
                          minlength=len(lots)) > 0  # fmt: skip
        first = starts[:-1]
        nxt = np.arange(1, len(p) + 1)
        nxt[starts[1:] - 1] = first
        prev = np.empty_like(nxt)
        prev[nxt] = np.arange(len(p))
        low = np.minimum.reduceat(p, first, axis=0)
        high = np.maximum.reduceat(p, first, axis=0)
        span = (high - low).max(axis=1)
        centre = np.add.reduceat(p, first, axis=0) / sizes[:, None]
        c = p - np.repeat(centre, sizes, axis=0)
        # Newell's y (the world normal is +y for a lot counter-clockwise seen from above)
        twice = np.add.reduceat(c[:, 1] * c[nxt, 0] - c[:, 0] * c[nxt, 1], first)
        floor = ROUNDOFF_REL * np.maximum(span, SIZE_FLOOR_M) ** 2
        edge = p[nxt] - p
        length = np.hypot(edge[:, 0], edge[:, 1])
        incoming = edge[prev]
        # y of (incoming x outgoing) in (x, 0, z): > 0 where the corner turns left seen from +y
        turn = incoming[:, 1] * edge[:, 0] - incoming[:, 0] * edge[:, 1]
        scale = np.maximum(length[prev] * length, SIZE_FLOOR_M**2)
        sine = turn / scale
        reflex = np.maximum.reduceat(-turn / np.maximum(length[prev], SIZE_FLOOR_M), first)
        shortest = np.minimum.reduceat(length, first)
        straightest = np.minimum.reduceat(np.abs(sine), first)
        leftmost = np.minimum.reduceat(sine, first)
        import shapely

        simple = shapely.is_simple(shapely.linearrings(p, indices=owner))
        full = np.zeros(self.count, dtype=bool)

        def mark(mask, reason):
            full[:] = False
            full[lots[mask]] = True
            self._mark(full, reason)

        mark(bad, "a corner that is not a finite number")
        mark(far, "a corner too far from the origin")
        # (the Lot's own test of a flat ring is on its singular values: far below this)
        mark(
            np.abs(twice) <= np.maximum(1e3 * floor, _THIN * span**2),
            "a footprint of (almost) no area",
        )
        mark(twice < 0, "a footprint that runs clockwise")
        mark(~simple, "a footprint that crosses itself")
        short = np.maximum(_SHORT_EDGE * span, 2 * LOT_MERGE_M)  # the Lot merges at LOT_MERGE_M
        mark(shortest <= short, "a repeated corner or a very short edge")
        mark(straightest <= _STRAIGHT_SINE, "a corner that barely turns")
        self.area[lots] = 0.5 * np.abs(twice)
        self.span[lots] = span
        self.perimeter[lots] = np.add.reduceat(length, first)
        self.reflex[lots] = reflex
        self.convex[lots] = leftmost > _STRAIGHT_SINE
        four = np.flatnonzero(sizes == 4)
        if len(four):
            self._boxes(lots[four], p, starts[four], edge, length)

    def _boxes(self, lots, p, starts, edge, length) -> None:
        """Which four-corner lots fill their scope (lot_shape's rectangle test, with a margin)."""
        corners = p[starts[:, None] + np.arange(4)]  # (m, 4, 2)
        x_axis = edge[starts] / length[starts, None]
        z_axis = np.column_stack([-x_axis[:, 1], x_axis[:, 0]])
        along = np.einsum("mkj,mj->mk", corners, x_axis)
        across = np.einsum("mkj,mj->mk", corners, z_axis)
        along -= along.min(axis=1, keepdims=True)
        across -= across.min(axis=1, keepdims=True)
        sx, sz = along.max(axis=1), across.max(axis=1)
        # Mesh.rectangle(size, 1): (0, sz) (sx, sz) (sx, 0) (0, 0)
        want_x = np.column_stack([0 * sx, sx, sx, 0 * sx])
        want_z = np.column_stack([sz, sz, 0 * sz, 0 * sz])
        miss = np.maximum(np.abs(along - want_x).max(axis=1), np.abs(across - want_z).max(axis=1))
        atol = _BOX_ATOL * np.maximum(np.maximum(sx, sz), COINCIDENT_M)
        self.box[lots] = miss <= 0.5 * atol
        full = np.zeros(self.count, dtype=bool)
        full[lots[(miss > 0.5 * atol) & (miss < 2 * atol)]] = True
        self._mark(full, "a rectangle at the tolerance of the test")

    def not_convex_in_doubt(self, heights: np.ndarray) -> np.ndarray:
        """Lots not convex by too small a margin to tell whether the derivation cuts their
        extrusion (``heights`` m): a corner in front of a side by about ``convex_rel`` times
        the prism's size."""
        size = 2.0 * self.span + np.abs(heights)  # above the prism's diagonal in any frame
        return ~self.convex & (self.reflex <= 10 * _CONVEX_REL * size)

    def corners(self, k: int) -> np.ndarray:
        return self.points[self.offsets[k] : self.offsets[k + 1]]
