"""A batch of lots derived together (:mod:`shapegen.engine.batch`) and their records and
buildings made from its arrays, with no model object per lot.

A city batch whose buildings are derived, not judged nor searched, goes to
:func:`~shapegen.engine.batch.derive_lots` first: the footprints of its lots packed end to end,
each lot's seed and attrs (its properties over the run's). Each lot the batch derives gets the
record :func:`~shapegen.city.work.run_lot` would give it (``derived`` ``"batch"``), and its
building the arrays the batch file holds (:mod:`shapegen.city.batches`): the extruded
footprint as a block, or as a solid whose caps are cut into triangles, all solids of the batch
in one constrained Delaunay call. The other lots (the rule or the footprint outside what the
batch implements) are left to ``run_lot``, one at a time (``derived`` ``"shape"``).
"""

from __future__ import annotations

__all__ = ["BatchLots", "derive_batch"]

import time
from collections import Counter
from dataclasses import dataclass, field
from itertools import chain

import numpy as np

_HOLED = "a lot with holes (a courtyard)"


@dataclass
class BatchLots:
    """What the batch derived of a city batch's tasks: ``records`` (None for a lot left to the
    one-at-a-time path), the packed ``leaves`` of the built ones (``lots``: their places in the
    tasks, in the leaves' order), their colours and flags, and why each other lot was left to
    the one-at-a-time path (``why``: task place -> reason)."""

    records: list
    lots: np.ndarray
    leaves: dict | None = None
    rgba: np.ndarray | None = None
    flags: np.ndarray | None = None
    reasons: Counter = field(default_factory=Counter)
    why: dict = field(default_factory=dict)


def derive_batch(settings, tasks) -> BatchLots | None:
    """The lots of ``tasks`` that the batch derives, or None when the run's settings keep every
    lot on the one-at-a-time path (judged, searched, or a rule that does not compile here)."""
    if settings.search is not None or settings.analyze:
        return None
    from shapegen.city.work import _grammar, _peak_rss_mib, lot_extents, lot_seed, new_record
    from shapegen.engine.batch import derive_lots

    started = time.perf_counter()
    try:
        grammar = _grammar(settings)
    except Exception:  # noqa: BLE001 - each lot's own run says what it is
        return None
    names = set(grammar.program.attr_nodes)
    shared = dict(settings.attrs)
    usable, overrides, mapped = [], [], []
    holed = 0
    for k, task in enumerate(tasks):
        if task.problem is not None or len(task.ring) < 3:
            continue
        if task.holes:  # the batch's footprints are single rings
            holed += 1
            continue
        given, named = shared, []
        for name, value in task.properties.items():
            if name in names and value is not None:
                if isinstance(value, list | dict):
                    break  # its run_lot records the error
                if given is shared:
                    given = dict(shared)
                given[name] = value
                named.append(name)
        else:
            usable.append(k)
            overrides.append(given)
            mapped.append(named)
    out = BatchLots([None] * len(tasks), np.zeros(0, dtype=np.int64))
    out.why = dict.fromkeys(range(len(tasks)), "a lot that cannot be built or a bad property")
    for k, task in enumerate(tasks):
        if task.holes and task.problem is None and len(task.ring) >= 3:
            out.why[k] = _HOLED
    if not usable:
        out.reasons[_HOLED] += holed
        return out
    rings = [tasks[k].ring for k in usable]
    sizes = np.fromiter((len(r) for r in rings), dtype=np.int64, count=len(rings))
    try:
        points = np.array(list(chain.from_iterable(rings)), dtype=float).reshape(-1, 2)
    except (TypeError, ValueError):
        out.why = dict.fromkeys(range(len(tasks)), "corners that are not pairs of numbers")
        return out
    points[:, 1] = -points[:, 1]  # city_lot: (east, north) -> (x, z)
    offsets = np.zeros(len(usable) + 1, dtype=np.int64)
    np.cumsum(sizes, out=offsets[1:])
    seeds = [lot_seed(tasks[k].id, settings.seed) for k in usable]
    batch = derive_lots(grammar, points, offsets, seeds, overrides, settings.limits)
    out.reasons = batch.reasons
    if holed:
        out.reasons[_HOLED] += holed
    kept = _material_ok(batch)
    for j, k in enumerate(usable):
        if kept[j]:
            del out.why[k]
        else:
            out.why[k] = batch.why[j] or "a density, structural or fixed a block does not take"
    derived = np.flatnonzero(kept)
    if not len(derived):
        return out
    from shapegen.engine.batch.lots import SOLID

    widths, depths, rectangles = lot_extents(points, offsets)
    solid = batch.kind == SOLID
    seconds = (time.perf_counter() - started) / len(usable)
    peak = _peak_rss_mib()
    warnings = list(batch.warnings)
    for j in derived.tolist():
        k = usable[j]
        task = tasks[k]
        record = new_record(task.id, seeds[j])
        record.update(
            input=task.input,
            status="ok",
            blocks=0 if solid[j] else 1,
            solids=1 if solid[j] else 0,
            left_out=0,
            warnings=[*task.warnings, *warnings],
            from_properties=list(mapped[j]),
            footprint="rectangle" if rectangles[j] else "polygon",
            lot=[float(widths[j]), float(depths[j])],
            seconds=seconds,
            peak_rss_mib=peak,
            derived="batch",
        )
        out.records[k] = record
    out.lots = np.asarray([usable[j] for j in derived.tolist()], dtype=np.int64)
    out.leaves = _drawn_leaves(batch, derived, solid[derived])
    out.rgba, out.flags = _colors_and_flags(batch, derived)
    return out


def _material_ok(batch) -> np.ndarray:
    """Lots the batch derived whose density, structural and fixed are what a block takes (the
    one-at-a-time derivation says what is wrong with the others)."""
    import math

    kept = ~batch.fallback
    good: dict[int, bool] = {}
    for j in np.flatnonzero(kept).tolist():
        values = batch.values[j]
        ok = good.get(id(values))
        if ok is None:
            density = values.get("density")
            ok = good[id(values)] = (
                type(density) is float
                and math.isfinite(density)
                and density >= 0
                and type(values.get("structural")) is bool
                and type(values.get("fixed")) is bool
            )
        kept[j] = ok
    if (kept != ~batch.fallback).any():
        batch.reasons["a density, structural or fixed a block does not take"] += int(
            ((~batch.fallback) & ~kept).sum()
        )
    return kept


def _colors_and_flags(batch, derived: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Each leaf's colour in the city's scene (a building that stands, no labels) and flags."""
    from shapegen.export.colors import block_label_color

    rgba = np.empty((len(derived), 4), dtype=np.uint8)
    flags = np.empty(len(derived), dtype=np.uint8)
    cache: dict[int, tuple] = {}
    for i, j in enumerate(derived.tolist()):
        values = batch.values[j]
        found = cache.get(id(values))
        if found is None:
            fixed, structural = values["fixed"], values["structural"]
            color = block_label_color((), fixed=fixed, structural=structural, colors={})
            found = cache[id(values)] = (color, int(fixed) | 2 * int(structural))
        rgba[i], flags[i] = found
    return rgba, flags


def _drawn_leaves(batch, derived: np.ndarray, solid: np.ndarray) -> dict:
    """The packed leaves of ``derived``, the caps of the solids cut into triangles (their faces
    in place of each cap, as the city's packer draws a face that is not convex)."""
    from shapegen.engine.batch.leaves import packed_leaves

    leaves = packed_leaves(batch, derived)
    if not solid.any():
        return leaves
    triangles = _cap_triangles(batch, derived[solid])
    if triangles is None:
        return leaves
    # rebuild the face lists of the solids: bottom triangles, top triangles, then the sides
    counts, sizes, faces = leaves["face_counts"], leaves["face_sizes"], leaves["faces"]
    face_at = np.zeros(len(counts) + 1, dtype=np.int64)
    np.cumsum(counts, out=face_at[1:])
    corner_at = np.zeros(len(sizes) + 1, dtype=np.int64)
    np.cumsum(sizes, out=corner_at[1:])
    new_sizes, new_faces, new_counts = [], [], counts.copy()
    which = np.flatnonzero(solid)
    spot = dict(zip(which.tolist(), range(len(which)), strict=True))
    for i in range(len(counts)):
        f0, f1 = face_at[i], face_at[i + 1]
        if i not in spot:
            new_sizes.append(sizes[f0:f1])
            new_faces.append(faces[corner_at[f0] : corner_at[f1]])
            continue
        cap = triangles[spot[i]]
        n = int(sizes[f0])
        top = cap[:, ::-1] + n  # the top looks up: the same triangles turned, raised
        sides = faces[corner_at[f0 + 2] : corner_at[f1]]
        new_sizes.append(np.concatenate([np.full(2 * len(cap), 3, np.int32), sizes[f0 + 2 : f1]]))
        new_faces.append(np.concatenate([cap.ravel(), top.ravel(), sides]).astype(np.int32))
        new_counts[i] = 2 * len(cap) + (f1 - f0 - 2)
    leaves["face_sizes"] = np.concatenate(new_sizes)
    leaves["faces"] = np.concatenate(new_faces)
    leaves["face_counts"] = new_counts
    return leaves


def _cap_triangles(batch, lots: np.ndarray) -> list | None:
    """Per lot of ``lots``, ``(t, 3)`` corner numbers of its footprint cut into triangles,
    turned as its bottom face (looking down); None when a triangulation names a point that is
    not a corner (then the packer's general path draws them)."""
    import shapely

    footprints = batch.footprints
    sizes = footprints.sizes[lots]
    starts = np.zeros(len(lots) + 1, dtype=np.int64)
    np.cumsum(sizes, out=starts[1:])
    source = np.repeat(footprints.offsets[lots] - starts[:-1], sizes) + np.arange(int(starts[-1]))
    p = footprints.points[source]
    owner = np.repeat(np.arange(len(lots)), sizes)
    polygons = shapely.polygons(shapely.linearrings(p, indices=owner))
    parts, which = shapely.get_parts(shapely.constrained_delaunay_triangles(polygons),
                                     return_index=True)  # fmt: skip
    corners = shapely.get_coordinates(shapely.get_exterior_ring(parts)).reshape(-1, 4, 2)[:, :3]
    # find each triangle corner among its footprint's corners: (owner, x, z) as one sort key
    keys = _keys(owner, p)
    order = np.argsort(keys, kind="stable")
    wanted = _keys(np.repeat(which, 3), corners.reshape(-1, 2))
    at = np.searchsorted(keys[order], wanted)
    at = np.minimum(at, len(order) - 1)
    found = order[at]
    if not (keys[found] == wanted).all():
        return None
    local = (found - starts[owner[found]]).reshape(-1, 3)
    # turned to look down (-y): in (x, z), y of (b - a) x (c - a) < 0
    a, b, c = (corners[:, n] for n in range(3))
    ab, ac = b - a, c - a
    up = ab[:, 1] * ac[:, 0] - ab[:, 0] * ac[:, 1] > 0
    local[up] = local[up][:, ::-1]
    split = np.searchsorted(which, np.arange(1, len(lots)))
    return np.split(local, split)


def _keys(owner: np.ndarray, xz: np.ndarray) -> np.ndarray:
    rows = np.empty(len(owner), dtype=[("o", "<i8"), ("x", "<f8"), ("z", "<f8")])
    rows["o"], rows["x"], rows["z"] = owner, xz[:, 0] + 0.0, xz[:, 1] + 0.0
    return rows.view(np.dtype((np.void, 24))).ravel()
