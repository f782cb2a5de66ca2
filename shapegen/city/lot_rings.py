"""The outer rings of many GeoJSON polygons at once: what
:func:`shapegen.city.city_lots._rings` does for one feature, for every plain one together.

A plain feature is a ``Polygon`` of one ring whose corners are all pairs of finite numbers (the
common case: every OSM building). Their corners are read into one array, projected in one call,
and checked together: runs of corners closer than the merge distance (a ring with one is left
to the one-feature path, which merges them in order), the span, and the validity, area and turn
of each ring by shapely's vectorised functions on all rings at once. Any other feature (holes,
a MultiPolygon, a corner with a height or not a number) is read by the one-feature path, so a
city reads the same lots either way.
"""

from __future__ import annotations

__all__ = ["plain_rings"]

from itertools import chain

import numpy as np

from shapegen.limits import LOT_EXTENT_LIMIT_M
from shapegen.tolerances import COINCIDENT_REL

_PLAIN_KEYS = frozenset({"type", "coordinates"})


def plain_corners(features: list[dict]) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """``(plain, corners, offsets)``: which features are plain (see module doc), the corners of
    the plain ones end to end as ``(P, 2)`` input coordinates (the closing corner included, as
    written) and where each plain feature's corners start (``(m + 1,)``)."""
    plain = np.zeros(len(features), dtype=bool)
    rings = []
    for k, feature in enumerate(features):
        geometry = feature.get("geometry")
        if type(geometry) is not dict or geometry.get("type") != "Polygon":
            continue
        if not _PLAIN_KEYS.issuperset(geometry):
            continue
        coordinates = geometry.get("coordinates")
        if type(coordinates) is not list or len(coordinates) != 1:
            continue
        ring = coordinates[0]
        if type(ring) is not list or not ring:
            continue
        plain[k] = True
        rings.append(ring)
    corners = list(chain.from_iterable(rings))
    ok = all(type(p) is list and len(p) == 2 for p in corners) and {
        type(v) for p in corners for v in p
    } <= {float, int}
    if not ok:  # a corner of another kind somewhere: find the rings that hold one
        keep = [
            all(
                type(p) is list
                and len(p) == 2
                and type(p[0]) in (float, int)
                and type(p[1]) in (float, int)
                for p in ring
            )  # fmt: skip
            for ring in rings
        ]
        plain[np.flatnonzero(plain)[~np.array(keep, dtype=bool)]] = False
        rings = [ring for ring, good in zip(rings, keep, strict=True) if good]
        corners = list(chain.from_iterable(rings))
    sizes = np.fromiter((len(r) for r in rings), dtype=np.int64, count=len(rings))
    offsets = np.zeros(len(rings) + 1, dtype=np.int64)
    np.cumsum(sizes, out=offsets[1:])
    points = np.array(corners, dtype=float).reshape(-1, 2)
    finite = np.isfinite(points).all(axis=1)
    if not finite.all():  # NaN or inf read from JSON: the one-feature path says so
        owner = np.repeat(np.arange(len(rings)), sizes)
        bad = np.bincount(owner, weights=~finite, minlength=len(rings)) > 0
        plain[np.flatnonzero(plain)[bad]] = False
        good = ~bad[owner]
        points = points[good]
        sizes = sizes[~bad]
        offsets = np.zeros(len(sizes) + 1, dtype=np.int64)
        np.cumsum(sizes, out=offsets[1:])
    return plain, points, offsets


def plain_rings(points, offsets, crs, origin, max_lot_m, min_area_m2):
    """Per plain feature (its corners ``points[offsets[k]:offsets[k + 1]]``), ``(ring, None)``
    for a lot that :func:`shapegen.city.city_lots._rings` finds clean, with the ring it gives (the
    :class:`~shapegen.model.lot.Lot`'s corners, to the bit), ``(empty, problem)`` for a corner
    off the earth, or None: the one-feature path reads that one (corners it merges, a problem
    it words, or any answer near a tolerance of its checks)."""
    import shapely

    from shapegen.readers import geojson
    from shapegen.tolerances import FLAT_REL, LOT_MERGE_M

    count = len(offsets) - 1
    out: list = [None] * count
    sizes = np.diff(offsets)
    owner = np.repeat(np.arange(count), sizes)
    settled = np.zeros(count, dtype=bool)
    if crs.projected:
        points = crs.to_lonlat(points)
        reached = np.bincount(owner, weights=~np.isfinite(points).all(axis=1), minlength=count)
        for k in np.flatnonzero(reached > 0).tolist():
            out[k] = (np.zeros((0, 2)), f"a corner where {crs.name} reaches no longitude/latitude")
            settled[k] = True
    if crs.located:
        outside = (np.abs(points[:, 0]) > 180) | (np.abs(points[:, 1]) > 90)
        outside = (np.bincount(owner, weights=outside, minlength=count) > 0) & ~settled
        why = "a corner outside longitude -180..180 / latitude -90..90"
        for k in np.flatnonzero(outside).tolist():
            out[k] = (np.zeros((0, 2)), why)
        settled |= outside
    local = geojson.local_metres(points, crs.located, origin)
    first, last = offsets[:-1], offsets[1:] - 1
    low = np.minimum.reduceat(local, first, axis=0)
    high = np.maximum.reduceat(local, first, axis=0)
    settled |= (high - low).max(axis=1) > max_lot_m  # the one-feature path words it
    # corners the Lot merges (or nearly): left to it, which merges them in order
    step = np.hypot(*(local[1:] - local[:-1]).T)
    near = np.zeros(len(local), dtype=bool)
    near[1:] = step <= 2 * LOT_MERGE_M
    near[first] = False  # a ring's first corner follows no corner of its own
    closing = np.hypot(*(local[last] - local[first]).T)
    repeated = closing <= 0.5 * LOT_MERGE_M  # the closing corner, as GeoJSON writes it
    settled |= np.bincount(owner, weights=near, minlength=count) > 0
    settled |= (closing > 0.5 * LOT_MERGE_M) & (closing <= 2 * LOT_MERGE_M)
    kept = sizes - repeated
    settled |= kept < 3
    todo = np.flatnonzero(~settled)
    if not len(todo):
        return out
    keep = np.ones(len(local), dtype=bool)
    keep[last[repeated]] = False
    owner_kept = owner[keep]
    chosen = np.isin(owner_kept, todo)
    ring_points = local[keep][chosen] * [1.0, -1.0]  # (x, z) = (east, -north), as the Lot
    ring_sizes = kept[todo]
    starts = np.zeros(len(todo) + 1, dtype=np.int64)
    np.cumsum(ring_sizes, out=starts[1:])
    index = np.repeat(np.arange(len(todo)), ring_sizes)
    clean = np.abs(ring_points).max(axis=1) <= 0.5 * LOT_EXTENT_LIMIT_M
    clean = np.bincount(index, weights=~clean, minlength=len(todo)) == 0
    # the Lot's flatness test (singular values of the centred corners), with a margin
    centre = np.add.reduceat(ring_points, starts[:-1], axis=0) / ring_sizes[:, None]
    c = ring_points - centre[index]
    sxx = np.add.reduceat(c[:, 0] * c[:, 0], starts[:-1])
    szz = np.add.reduceat(c[:, 1] * c[:, 1], starts[:-1])
    sxz = np.add.reduceat(c[:, 0] * c[:, 1], starts[:-1])
    middle, half = 0.5 * (sxx + szz), np.sqrt((0.5 * (sxx - szz)) ** 2 + sxz**2)
    big, small = middle + half, np.maximum(middle - half, 0.0)
    clean &= small > (100 * FLAT_REL) ** 2 * big
    linear = shapely.linearrings(ring_points, indices=index)
    clean &= shapely.is_valid(shapely.polygons(linear))
    x, z = ring_points[:, 0], ring_points[:, 1]
    nxt = np.arange(1, len(x) + 1)
    nxt[starts[1:] - 1] = starts[:-1]
    twice = np.add.reduceat(x * z[nxt] - x[nxt] * z, starts[:-1])
    area = 0.5 * np.abs(twice)
    clean &= (area > 2 * min_area_m2) & (np.abs(twice) > COINCIDENT_REL * big)
    rings = np.split(ring_points, starts[1:-1])
    for j, k in enumerate(todo.tolist()):
        if not clean[j]:
            continue
        ring = rings[j]
        if twice[j] > 0:  # clockwise seen from above: reversed, the first corner kept first
            ring = np.roll(ring[::-1], 1, axis=0)
        out[k] = (ring * [1.0, -1.0], None)
    return out
