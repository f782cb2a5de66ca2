"""Predicates on small polygon rings given as coordinate lists (m): which way they turn, how
often they wind, whether they cross themselves and whether two corners nearly coincide. Plain
Python for the few corners of a footprint, where numpy's calls would cost more than the sums;
numpy for a ring of many corners."""

from __future__ import annotations

__all__ = [
    "chain_loops",
    "chains_between",
    "corners_apart",
    "is_simple",
    "joined_chains",
    "turns_left",
    "winds_once",
    "without_repeats",
]

import math

import numpy as np

from shapegen.tolerances import ROUNDOFF_REL, at_least


def turns_left(ring: list[int], xs: list[float], ys: list[float]) -> bool:
    """The ring turns left or goes straight on at every corner (never back)."""
    ax, ay = xs[ring[-2]], ys[ring[-2]]
    bx, by = xs[ring[-1]], ys[ring[-1]]
    for i in ring:
        cx, cy = xs[i], ys[i]
        turn = (bx - ax) * (cy - by) - (by - ay) * (cx - bx)
        if turn < 0 or (turn == 0 and (bx - ax) * (cx - bx) + (by - ay) * (cy - by) <= 0):
            return False
        ax, ay, bx, by = bx, by, cx, cy
    return True


def corners_apart(xs: list[float], ys: list[float], near: float) -> bool:
    """No two corners within ``near`` (m) of each other along both axes: ones that
    :meth:`Mesh.cleaned` could merge (it merges corners within its round-off, a quarter of
    ``near`` at most, on a grid)."""
    order = sorted(range(len(xs)), key=xs.__getitem__)
    for k, i in enumerate(order):
        x, y = xs[i], ys[i]
        for j in order[k + 1 :]:
            if xs[j] - x > near:
                break
            if abs(ys[j] - y) <= near:
                return False
    return True


def winds_once(xs: list[float], ys: list[float]) -> bool:
    """The ring's edges turn once around (not twice or more, as a star drawn in one stroke)."""
    turning = 0.0
    ax, ay = xs[-2], ys[-2]
    bx, by = xs[-1], ys[-1]
    for cx, cy in zip(xs, ys, strict=True):
        ux, uy, vx, vy = bx - ax, by - ay, cx - bx, cy - by
        turning += math.atan2(ux * vy - uy * vx, ux * vx + uy * vy)
        ax, ay, bx, by = bx, by, cx, cy
    return turning < 3 * math.pi


def is_simple(xs: list[float], ys: list[float], tol: float) -> bool:
    """No two edges of the ring meet but neighbours at their shared corner, none within
    ``tol`` (m) of doing so, and no edge shorter than that."""
    n = len(xs)
    if n > 16:
        return _simple_many(xs, ys, tol)
    edges = []
    for k in range(n):
        ax, ay, bx, by = xs[k - 1], ys[k - 1], xs[k], ys[k]  # edge k - 1
        length = math.hypot(bx - ax, by - ay)
        if length <= tol:
            return False
        edges.append((ax, ay, bx, by, length))
    for k in range(n):
        ax, ay, bx, by, ab = edges[k]
        for m in range(k + 2, n - 1 if k == 0 else n):
            cx, cy, dx, dy, cd = edges[m]
            if (
                max(cx, dx) < min(ax, bx) - tol
                or min(cx, dx) > max(ax, bx) + tol
                or max(cy, dy) < min(ay, by) - tol
                or min(cy, dy) > max(ay, by) + tol
            ):
                continue
            if _segments_meet(ax, ay, bx, by, ab, cx, cy, dx, dy, cd, tol):
                return False
    return True


def _segments_meet(ax, ay, bx, by, ab, cx, cy, dx, dy, cd, tol) -> bool:
    """Segments a-b and c-d (lengths ``ab``, ``cd``) cross or come within ``tol`` of it."""

    def side(px, py, qx, qy, length, rx, ry):
        h = ((qx - px) * (ry - py) - (qy - py) * (rx - px)) / length
        return 0 if abs(h) <= tol else (1 if h > 0 else -1)

    s1, s2 = side(ax, ay, bx, by, ab, cx, cy), side(ax, ay, bx, by, ab, dx, dy)
    s3, s4 = side(cx, cy, dx, dy, cd, ax, ay), side(cx, cy, dx, dy, cd, bx, by)
    if s1 * s2 > 0 or s3 * s4 > 0:
        return False
    if s1 == s2 == 0:  # c-d on a-b's line: they meet where their spans along it overlap
        tx, ty = (bx - ax) / ab, (by - ay) / ab
        c, d = (cx - ax) * tx + (cy - ay) * ty, (dx - ax) * tx + (dy - ay) * ty
        return max(c, d) >= -tol and min(c, d) <= ab + tol
    return True


def _simple_many(xs: list[float], ys: list[float], tol: float) -> bool:
    """:func:`is_simple` for a ring of many corners, all pairs of edges at once."""
    n = len(xs)
    ax, ay = np.array(xs), np.array(ys)
    tx, ty = np.roll(ax, -1) - ax, np.roll(ay, -1) - ay
    length = np.hypot(tx, ty)
    if float(length.min()) <= tol:
        return False
    # side[i, k]: corner k's distance left of edge i's line, and its place along the edge
    side = tx[:, None] * (ay[None, :] - ay[:, None]) - ty[:, None] * (ax[None, :] - ax[:, None])
    side /= length[:, None]
    along = tx[:, None] * (ax[None, :] - ax[:, None]) + ty[:, None] * (ay[None, :] - ay[:, None])
    along /= length[:, None]
    sign = (side > tol).astype(np.int8) - (side < -tol)
    following = np.roll(sign, -1, axis=1)
    straddles = sign * following <= 0  # edge k's corners not both on one side of edge i
    meet = straddles & straddles.T
    # an edge on the other's line meets it only where their spans along the line overlap
    on_line = (sign == 0) & (following == 0)
    span_low = np.minimum(along, np.roll(along, -1, axis=1))
    span_high = np.maximum(along, np.roll(along, -1, axis=1))
    overlap = (span_high >= -tol) & (span_low <= length[:, None] + tol)
    meet &= ~on_line | overlap
    i, k = np.indices((n, n))
    apart = (np.abs(i - k) >= 2) & (np.abs(i - k) != n - 1)
    return not bool((meet & apart).any())


def chain_loops(start: list[float], end: list[float]) -> list[list[int]]:
    """The chains of a polygon cut by a line, closed into loops along the line.

    ``start[c]`` and ``end[c]`` are where chain ``c`` begins and ends along the line (m). The
    chains are taken by their ends in order along the line, and each joins the first chain still
    free whose start is not before its end (by more than round-off), else the first one free;
    the loops come as lists of chain numbers, each from its lowest-numbered chain.
    """
    count = len(start)
    free = sorted(range(count), key=start.__getitem__)
    link: dict[int, int] = {}
    for c in sorted(range(count), key=end.__getitem__):
        choice = next((s for s in free if at_least(start[s], end[c], ROUNDOFF_REL)), free[0])
        free.remove(choice)
        link[c] = choice
    loops, seen = [], set()
    for first in range(count):
        loop, c = [], first
        while c not in seen:
            seen.add(c)
            loop.append(c)
            c = link[c]
        if loop:
            loops.append(loop)
    return loops


def without_repeats(ring: list[int]) -> list[int]:
    """``ring`` (vertex indices) with each run of one index kept once, the closing index that
    repeats the first dropped: a cut's ring as a face lists it."""
    out: list[int] = []
    for i in ring:
        if not out or out[-1] != i:
            out.append(i)
    while len(out) > 1 and out[0] == out[-1]:
        out.pop()
    return out


def chains_between(ring: list[int], on_edges: list[bool]) -> list[list[int]]:
    """``ring`` (vertex indices) cut at its edges lying on a cut plane (``on_edges[k]``: the
    edge from corner ``k`` to ``k + 1``, at least one): the chains between them, each of two or
    more corners, the first beginning after an edge on the plane."""
    n = len(ring)
    start = (on_edges.index(True) + 1) % n
    chains: list[list[int]] = []
    current: list[int] = []
    for step in range(n):
        k = (start + step) % n
        current.append(ring[k])
        if on_edges[k]:
            chains.append(current)
            current = []
    if current:
        chains.append(current)
    return [c for c in chains if len(c) >= 2]


def joined_chains(chains: list[list[int]], position: dict) -> list[tuple[int, ...]]:
    """The polygons that ``chains`` make when joined along the cut (:func:`chain_loops` on the
    ``position`` of each chain's ends along it), repeated indices dropped; each of three or more
    corners."""
    polygons = []
    for loop in chain_loops([position[c[0]] for c in chains], [position[c[-1]] for c in chains]):
        polygon = without_repeats([i for c in loop for i in chains[c]])
        if len(polygon) >= 3:
            polygons.append(tuple(polygon))
    return polygons
