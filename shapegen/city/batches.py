"""Batches of lots: what a worker runs as one task, and the two files it writes for them.

A worker runs the lots of a batch one after the other (:func:`run_batch`), then writes, into the
run's store, the batch's buildings and then its records::

    lots/B-KEY.blocks the built lots' blocks and solids, placed in the city, as packed arrays
    lots/B-KEY.json   the records of every lot of the batch (built, failed or timed out)

The record file is written last, so a record file that is there means its whole batch is done,
buildings included: an interrupted run keeps every batch written, and a rerun skips those lots.
``KEY`` is a hash of the batch's lots (ids and inputs). A built lot's record names its building
as ``KEY:N`` (``building``: the batch and the building's place in its ``.blocks``); a lot's
``input`` is the fingerprint of its corners and properties, so a lot that changed is not taken
from an old batch.

Buildings are packed arrays rather than one JSON document per lot: one file per batch, read back
without parsing (the city's glTF of 10 000 buildings is assembled from them in a fraction of a
second). The arrays: ``vertices`` (float64, m), ``vertex_offsets`` per block, ``faces`` (vertex
indices within the block, all faces end to end), ``face_sizes``, ``face_starts`` (into
``faces``), ``face_offsets`` per block (into ``face_sizes``), ``block_offsets`` per building,
``rgba`` per block (the scene's colours: label colours, red where the building does not stand)
and ``flags`` per block (1 fixed, 2 structural, 4 a surface). A closed solid leaf that is
not convex (an extruded L-shaped footprint), kept as derived, and a surface the statics leave
out (a facade made of faces; flags 4) are packed after the building's blocks as one more entry
each, their faces cut into triangles where a fan would not cover them. The file is ``SGBLOCKS`` (8
bytes), the length of a JSON header (8 bytes, little-endian), the header (``{name: [numpy
dtype, shape, offset]}``, offsets from the end of the header) and the arrays' bytes, each at a
multiple of 8: numpy takes each array where it lies, where an ``.npz`` costs milliseconds a
batch to open.
"""

from __future__ import annotations

__all__ = [
    "BATCH_FORMAT",
    "batch_key",
    "block_colors",
    "building_blocks",
    "read_batch_buildings",
    "read_building",
    "read_records",
    "run_batch",
    "write_batch",
]

import hashlib
import json
from collections.abc import Callable, Sequence

import numpy as np

from shapegen.json_values import json_ready
from shapegen.tolerances import ROUNDOFF_REL

BATCH_FORMAT = "shapegen-city-batch"
_MAGIC = b"SGBLOCKS"
_FAILED = np.array([220, 30, 30, 255], dtype=np.uint8)  # a building that does not stand
OPEN = 4  # the flags of a surface drawn but not judged (1 fixed and 2 structural otherwise)


def batch_key(tasks: Sequence) -> str:
    """The file stem of a batch of ``tasks`` (``LotTask``): a hash of their ids and inputs."""
    digest = hashlib.blake2b(digest_size=10)
    for task in tasks:
        digest.update(f"{task.id}\x00{task.input}\x01".encode())
    return f"B-{digest.hexdigest()}"


def run_batch(settings, store, tasks: Sequence, started: Callable[[int], None] | None = None):
    """Run ``tasks`` (a batch of ``LotTask``), write the batch's files into ``store``
    (:class:`~shapegen.city.store.CityStore`) and return its records (without their
    buildings). The lots that the batch derivation implements are derived together
    (:mod:`shapegen.city.batch_derive`, ``derived`` ``"batch"`` in their records); the others
    one after the other (``"shape"``). ``started(k)`` is called as lot ``k`` starts, and with
    ``len(tasks)`` once they are all done (while the files are written). A lot's failure is its
    row; only a store that cannot be written raises."""
    from shapegen.city.batch_derive import derive_batch
    from shapegen.city.work import run_lot

    if started is not None and tasks:
        started(0)
    batched = derive_batch(settings, tasks)
    records, models = [], []
    for k, task in enumerate(tasks):
        record = None if batched is None else batched.records[k]
        if record is None:
            if started is not None:
                started(k)
            record = run_lot(settings, task)
            record["derived"] = "shape"
            if batched is not None:
                record["batch_fallback"] = batched.why.get(k)
        models.append(record.pop("model", None))
        records.append(record)
    if started is not None:
        started(len(tasks))
    write_batch(store, batch_key(tasks), records, models, batched)
    return records


def write_batch(
    store, key: str, records: list[dict], models: Sequence | None = None, batched=None
) -> None:
    """Write a batch's buildings (``models``, a Model or None per record, and the lots that
    ``batched`` (:class:`~shapegen.city.batch_derive.BatchLots`) derived, as its arrays) and
    then its records."""
    built = [(k, model) for k, model in enumerate(models or ()) if model is not None]
    lots = [] if batched is None or batched.leaves is None else batched.lots.tolist()
    if built or lots:
        for index, k in enumerate([k for k, _ in built] + lots):
            records[k]["building"] = f"{key}:{index}"
        stands = [records[k].get("stands") is not False for k, _ in built]
        store.write(f"lots/{key}.blocks", _pack([model for _, model in built], stands, batched))
    # a batch-derived lot's record holds plain values already: only the others are converted
    plain = [r if r.get("derived") == "batch" else json_ready(r) for r in records]
    document = {"format": BATCH_FORMAT, "version": 1, "records": plain}
    try:
        text = json.dumps(document, allow_nan=False, separators=(",", ":"))
    except (TypeError, ValueError):  # not as plain as it should be: convert it all
        text = json.dumps(json_ready(document), allow_nan=False, separators=(",", ":"))
    store.write(f"lots/{key}.json", text.encode("utf-8"))


def read_records(store) -> dict[str, list[dict]]:
    """Every record of the store's batch files: lot id -> its records (a lot may be in the
    batches of several runs). A file that is not a batch's records is passed over (its lots run
    again)."""
    found: dict[str, list[dict]] = {}
    for name in store.list("lots", ".json"):
        data = store.read(name)
        try:
            document = json.loads(data)
            if document.get("format") != BATCH_FORMAT:
                continue
            records = document["records"]
        except (TypeError, ValueError, KeyError, AttributeError):
            continue
        for record in records:
            if isinstance(record, dict) and "id" in record and "status" in record:
                found.setdefault(record["id"], []).append(record)
    return found


def parse_building(record: dict) -> tuple[str, int] | None:
    """The batch key and place of a record's building (None: it has none)."""
    key, _, index = str(record.get("building") or "").rpartition(":")
    return (key, int(index)) if key and index.isdigit() else None


def read_building(store, record: dict, cache: dict | None = None):
    """A lot's building: a Model of its placed blocks and surfaces, and their colours in the
    scene (``(b, 4)`` and ``(s, 4)`` RGBA bytes), or None when it has none or its batch's file is
    missing; ``cache`` (a dict) keeps the last batch read, for many lots in order."""
    from shapegen.model.appearance import Surface
    from shapegen.model.model import Model

    where = parse_building(record)
    if where is None:
        return None
    key, index = where
    cache = {} if cache is None else cache
    if key not in cache:
        cache.clear()
        cache[key] = read_batch_buildings(store, key)
    arrays = cache[key]
    if arrays is None or index >= len(arrays["block_offsets"]) - 1:
        return None
    first, last = arrays["block_offsets"][index : index + 2]
    rgba = arrays["rgba"][first:last]
    open_ = (arrays["flags"][first:last] & OPEN) != 0
    entries = building_blocks(arrays, index)
    blocks = [entry for entry, is_open in zip(entries, open_, strict=True) if not is_open]
    surfaces = [
        Surface(entry.vertices, entry.faces, reason="a surface")
        for entry, is_open in zip(entries, open_, strict=True)
        if is_open
    ]
    return Model(blocks, surfaces=surfaces), rgba[~open_], rgba[open_]


def read_batch_buildings(store, key: str) -> dict[str, np.ndarray] | None:
    """The packed arrays of batch ``key``'s buildings, or None when it has none (or they cannot
    be read)."""
    data = store.read(f"lots/{key}.blocks")
    if data is None or data[:8] != _MAGIC:
        return None
    try:
        size = int.from_bytes(data[8:16], "little")
        header = json.loads(data[16 : 16 + size])
        body = memoryview(data)[16 + size :]
        arrays = {}
        for name, (dtype, shape, offset) in header.items():
            count = int(np.prod(shape))
            array = np.frombuffer(body, dtype=np.dtype(dtype), count=count, offset=offset)
            arrays[name] = array.reshape(shape)
        return arrays
    except (ValueError, TypeError, KeyError):
        return None


def building_blocks(arrays: dict[str, np.ndarray], index: int):
    """The blocks of building ``index`` of a batch's arrays, as a list of Block (ids b0, b1...)."""
    from shapegen.model.block import Block

    first, last = arrays["block_offsets"][index : index + 2]
    blocks = []
    for b in range(first, last):
        v0, v1 = arrays["vertex_offsets"][b : b + 2]
        f0, f1 = arrays["face_offsets"][b : b + 2]
        sizes = arrays["face_sizes"][f0:f1]
        start = int(arrays["face_starts"][f0]) if f1 > f0 else 0
        flat = arrays["faces"][start : start + int(sizes.sum())].tolist()
        faces, at = [], 0
        for size in sizes.tolist():
            faces.append(tuple(flat[at : at + size]))
            at += size
        flags = int(arrays["flags"][b])
        blocks.append(
            Block(
                arrays["vertices"][v0:v1].copy(),
                tuple(faces),
                id=f"b{b - first}",
                fixed=bool(flags & 1),
                structural=bool(flags & 2),
            )
        )
    return blocks


def block_colors(model, *, stands: bool) -> np.ndarray:
    """``(b, 4)`` RGBA bytes of a building's blocks in the city's scene and picture: each in its
    label's colour (the design page's), all red when the building does not stand."""
    return _colors(_drawn(model), stands)


def _colors(drawn: list[tuple], stands: bool) -> np.ndarray:
    from shapegen.export.colors import block_label_color, label_colors

    if not stands:
        return np.repeat(_FAILED[None], len(drawn), axis=0)
    # each label its own colour, as the design page has (export.colors.model_label_colors)
    by_label = label_colors(
        tags[0] for _, _, tags, fixed, structural, _ in drawn if tags and structural and not fixed
    )
    return np.array(
        [
            # a surface (fixed None) opaque, as the model's own files draw it (its label's
            # colour or the surfaces'), not see-through as a block left out of the statics
            _surface_color(tags, by_label)
            if fixed is None
            else block_label_color(tags, fixed=fixed, structural=structural, colors=by_label)
            for _, _, tags, fixed, structural, _ in drawn
        ],
        dtype=np.uint8,
    ).reshape(-1, 4)


def _surface_color(tags, by_label: dict) -> np.ndarray:
    from shapegen.export.colors import SURFACE, label_color

    if not tags:
        return SURFACE
    return by_label[tags[0]] if tags[0] in by_label else label_color(tags[0])


def _drawn(model) -> list[tuple]:
    """``(vertices, faces, tags, fixed, structural, polygons)`` of what a building shows in the
    city: its blocks, then its other leaves as derived (``polygons`` True: faces that may not be
    convex): closed solids that are not convex (cut into convex parts only when judged) and the
    surfaces the statics leave out (a facade made of faces), drawn, not structural; ``fixed``
    is None for those (:data:`OPEN`)."""
    drawn = [(b.vertices, b.faces, b.tags, b.fixed, b.structural, False) for b in model.blocks]
    for surface in getattr(model, "surfaces", None) or ():
        if not surface.faces:
            continue
        solid = surface.solid
        fixed, structural = (None, False) if solid is None else (solid.fixed, solid.structural)
        drawn.append((surface.vertices, surface.faces, surface.tags, fixed, structural, True))
    return drawn


def _fan_ready(solids: list[tuple]) -> list[tuple]:
    """The faces of each ``(vertices, faces)`` in ``solids`` with every polygon that a fan from
    its first corner would not cover (a non-convex one: an L-shaped footprint's caps) cut into
    triangles, the others as they are; all solids of a batch at once: the convex polygons are
    told from the others in one pass (every corner turns the same way about the face's
    normal), and the others are triangulated in one call (constrained Delaunay)."""
    from shapegen.model.polygons import cross, face_layout, face_normals

    layouts = [face_layout(faces) for _, faces in solids]
    vertex_base = _offsets([len(vertices) for vertices, _ in solids])
    face_base = _offsets([len(start) - 1 for _, start in layouts])
    corner_base = _offsets([len(corners) for corners, _ in layouts])
    vertices = np.concatenate([v for v, _ in solids])
    corners = np.concatenate([c + vertex_base[k] for k, (c, _) in enumerate(layouts)])
    start = np.concatenate([[0]] + [s[1:] + corner_base[k] for k, (_, s) in enumerate(layouts)])
    normals, _ = face_normals(vertices, corners, start)
    p = vertices[corners]
    successor = np.arange(1, len(corners) + 1)
    successor[start[1:] - 1] = start[:-1]
    edges = p[successor] - p
    sizes = np.diff(start)
    turns = np.einsum("ij,ij->i", cross(edges, edges[successor]), np.repeat(normals, sizes, axis=0))
    scale = np.maximum.reduceat(np.einsum("ij,ij->i", edges, edges), start[:-1])
    bent = np.flatnonzero(np.minimum.reduceat(turns, start[:-1]) < -ROUNDOFF_REL * scale)
    out = [faces for _, faces in solids]
    if not len(bent):
        return out
    triangles = _triangulated(vertices, corners, start, normals, bent)
    owner = np.searchsorted(face_base, bent, side="right") - 1
    for solid in np.unique(owner).tolist():
        base = int(vertex_base[solid])
        local = dict.fromkeys((bent[owner == solid] - face_base[solid]).tolist())
        faces = []
        for k, face in enumerate(out[solid]):
            if k in local:
                number = int(face_base[solid]) + k
                faces.extend(tuple(i - base for i in t) for t in triangles.get(number, ()))
            else:
                faces.append(face)
        out[solid] = tuple(faces)
    return out


def _triangulated(vertices, corners, start, normals, bent) -> dict[int, list]:
    """Triangles (vertex numbers, turned as their face) of the faces numbered ``bent``, by a
    constrained Delaunay triangulation of each face in the plane of its two axes across its
    normal's largest component; a face that is not a simple polygon is fanned."""
    import shapely

    from shapegen.model.polygons import cross

    pieces = [corners[start[k] : start[k + 1]] for k in bent.tolist()]
    index = np.concatenate(pieces)
    face_of = np.repeat(np.arange(len(bent)), [len(c) for c in pieces])
    axis = np.abs(normals[bent]).argmax(axis=1)[face_of]
    points = vertices[index]
    rows = np.arange(len(index))
    u, v = points[rows, (axis + 1) % 3], points[rows, (axis + 2) % 3]
    polygons = shapely.polygons(shapely.linearrings(np.column_stack([u, v]), indices=face_of))
    keys = zip(face_of.tolist(), u.tolist(), v.tolist(), strict=True)
    at = dict(zip(keys, index.tolist(), strict=True))
    out: dict[int, list] = {}
    valid = shapely.is_valid(polygons)
    for w in np.flatnonzero(~valid).tolist():
        face = pieces[w].tolist()
        out[int(bent[w])] = [(face[0], face[k], face[k + 1]) for k in range(1, len(face) - 1)]
    chosen = np.flatnonzero(valid)
    parts, which = shapely.get_parts(
        shapely.constrained_delaunay_triangles(polygons[chosen]), return_index=True
    )
    corners2d = shapely.get_coordinates(shapely.get_exterior_ring(parts)).reshape(-1, 4, 2)
    found, owners = [], []
    for (a, b, c), w in zip(corners2d[:, :3].tolist(), chosen[which].tolist(), strict=True):
        try:
            found.append([at[(w, x, y)] for x, y in (a, b, c)])
        except KeyError:  # a point GEOS added: cannot be named by a vertex number
            continue
        owners.append(w)
    if not found:
        return out
    triangles = np.array(found)
    i, j, k = (vertices[triangles[:, n]] for n in range(3))
    turned = np.einsum("ij,ij->i", cross(j - i, k - i), normals[bent[owners]]) < 0
    triangles[turned] = triangles[turned][:, ::-1]
    for triangle, w in zip(triangles.tolist(), owners, strict=True):
        out.setdefault(int(bent[w]), []).append(tuple(triangle))
    return out


def _pack(models: Sequence, stands: Sequence[bool], batched=None) -> bytes:
    """The batch file of ``models`` (and of the lots ``batched`` derived, after them)."""
    arrays = _model_arrays(models, stands)
    if batched is not None and batched.leaves is not None and len(batched.lots):
        arrays = _joined(arrays, _batch_arrays(batched))
    header, chunks, offset = {}, [], 0
    for name, array in arrays.items():
        array = np.ascontiguousarray(array)
        header[name] = [array.dtype.str, list(array.shape), offset]
        padding = -array.nbytes % 8
        chunks += [array.tobytes(), b"\x00" * padding]
        offset += array.nbytes + padding
    text = json.dumps(header, separators=(",", ":")).encode()
    text += b" " * (-len(text) % 8)
    return b"".join([_MAGIC, len(text).to_bytes(8, "little"), text, *chunks])


def _batch_arrays(batched) -> dict[str, np.ndarray]:
    """The file's arrays of the leaves a batch derivation packed: one entry per building."""
    leaves = batched.leaves
    count = len(batched.lots)
    return {
        "vertices": leaves["vertices"],
        "vertex_offsets": _offsets(leaves["vertex_counts"]),
        "faces": leaves["faces"].astype(np.int32),
        "face_sizes": leaves["face_sizes"].astype(np.int32),
        "face_starts": _offsets(leaves["face_sizes"])[:-1],
        "face_offsets": _offsets(leaves["face_counts"]),
        "block_offsets": np.arange(count + 1, dtype=np.int64),
        "rgba": batched.rgba,
        "flags": batched.flags,
    }


def _joined(first: dict, second: dict) -> dict[str, np.ndarray]:
    """Two sets of a batch file's arrays, the second's buildings after the first's."""
    out = {}
    for name in ("vertices", "faces", "face_sizes", "rgba", "flags"):
        out[name] = np.concatenate([first[name], second[name]])
    for name, base in (
        ("vertex_offsets", len(first["vertices"])),
        ("face_offsets", len(first["face_sizes"])),
        ("block_offsets", len(first["flags"])),
    ):
        out[name] = np.concatenate([first[name], second[name][1:] + base])
    out["face_starts"] = np.concatenate([first["face_starts"],
                                         second["face_starts"] + len(first["faces"])])  # fmt: skip
    return {name: out[name] for name in first}


def _model_arrays(models: Sequence, stands: Sequence[bool]) -> dict[str, np.ndarray]:
    vertices, faces, face_sizes, rgba, flags = [], [], [], [], []
    block_counts, vertex_counts, face_counts = [], [], []
    buildings = [_drawn(model) for model in models]
    solids = [(k, n) for k, drawn in enumerate(buildings) for n, entry in enumerate(drawn)
              if entry[5]]  # fmt: skip
    if solids:
        ready = _fan_ready([buildings[k][n][:2] for k, n in solids])
        for (k, n), polygons in zip(solids, ready, strict=True):
            buildings[k][n] = (buildings[k][n][0], polygons, *buildings[k][n][2:])
    for drawn, standing in zip(buildings, stands, strict=True):
        block_counts.append(len(drawn))
        if drawn:
            rgba.append(_colors(drawn, standing))
        for block_vertices, block_faces, _, fixed, structural, _ in drawn:
            vertices.append(np.asarray(block_vertices, dtype=float))
            vertex_counts.append(len(block_vertices))
            face_counts.append(len(block_faces))
            for face in block_faces:
                faces.extend(face)
                face_sizes.append(len(face))
            flags.append(OPEN if fixed is None else int(fixed) | 2 * int(structural))
    return {
        "vertices": np.concatenate(vertices) if vertices else np.zeros((0, 3)),
        "vertex_offsets": _offsets(vertex_counts),
        "faces": np.asarray(faces, dtype=np.int32),
        "face_sizes": np.asarray(face_sizes, dtype=np.int32),
        "face_starts": _offsets(face_sizes)[:-1],
        "face_offsets": _offsets(face_counts),
        "block_offsets": _offsets(block_counts),
        "rgba": np.concatenate(rgba).astype(np.uint8) if rgba else np.zeros((0, 4), np.uint8),
        "flags": np.asarray(flags, dtype=np.uint8),
    }


def _offsets(counts: Sequence[int]) -> np.ndarray:
    out = np.zeros(len(counts) + 1, dtype=np.int64)
    np.cumsum(np.asarray(counts, dtype=np.int64), out=out[1:])
    return out
