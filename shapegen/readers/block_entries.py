"""The "blocks" of a shapegen-blocks document, read all at once.

:func:`entry_block` reads one entry and is the definition of what an entry may hold and of the
message for each mistake. :func:`read_block_entries` reads a whole list to the same blocks and
the same first error, without the per-block numpy work: each entry's own fields are still
checked one by one, but the vertices of all entries are converted to arrays together, the
hulls of blocks given only by their vertices come from the batched search of
:mod:`shapegen.model.hulls` (qhull for what it leaves), and the faces given are turned outward
in one pass. An entry the bulk checks have any doubt about is read by :func:`entry_block`, in
its place in the order, so the first bad entry raises the error it always did.
"""

from __future__ import annotations

__all__ = ["entry_block", "read_block_entries"]

from itertools import chain

import numpy as np

from shapegen.errors import InputFormatError
from shapegen.model.block import DEFAULT_DENSITY, Block
from shapegen.model.hulls import batched_hulls
from shapegen.model.polygons import CheckedFaces, cross
from shapegen.readers.json_fields import boolean, number, points, require, strings
from shapegen.readers.surface_entries import appearance_from_entry


def entry_block(entry: object, k: int) -> Block:
    """The block of ``blocks[k]``; errors name the entry (its id once it has one)."""
    where, vertices_value, kwargs, faces = _entry_fields(entry, k)
    vertices = points(vertices_value, f'{where}: "vertices"')
    kwargs = kwargs()
    if faces is None:
        return Block.from_hull(vertices, **kwargs)
    _check_faces(faces, len(vertices), where)
    return Block(vertices, _outward(vertices, faces), **kwargs)


def _entry_fields(entry: object, k: int):
    """The entry's name for messages, its raw vertices, a function that checks and returns its
    other fields as :class:`Block` keywords, and its raw faces (or None)."""
    where = f"blocks[{k}]"
    if not isinstance(entry, dict):
        raise InputFormatError(f"{where} must be an object")
    block_id = entry.get("id", f"b{k}")
    if not isinstance(block_id, str) or not block_id:
        raise InputFormatError(f'{where}: "id" must be a non-empty string')
    where = f"block {block_id!r}"
    vertices = require(entry, "vertices", where)

    def keywords() -> dict:
        kwargs = dict(
            id=block_id,
            density=number(entry.get("density", DEFAULT_DENSITY), f'{where}: "density"'),
            fixed=boolean(entry.get("fixed", False), f'{where}: "fixed"'),
            structural=boolean(entry.get("structural", True), f'{where}: "structural"'),
            tags=strings(entry.get("tags", []), f'{where}: "tags"'),
            rule_path=strings(entry.get("rule_path", []), f'{where}: "rule_path"'),
            appearance=appearance_from_entry(entry.get("appearance"), where),
            body=entry.get("body", ""),
        )
        if not isinstance(kwargs["body"], str):
            raise InputFormatError(f'{where}: "body" must be a string')
        if kwargs["density"] < 0:
            raise InputFormatError(f'{where}: "density" must be >= 0')
        return kwargs

    return where, vertices, keywords, entry.get("faces")


def _check_faces(faces: object, n: int, where: str) -> None:
    if not isinstance(faces, list) or not all(
        isinstance(f, list) and all(isinstance(i, int) and not isinstance(i, bool) for i in f)
        for f in faces
    ):
        raise InputFormatError(f'{where}: "faces" must be a list of lists of vertex indices')
    for face in faces:
        if len(face) < 3 or min(face) < 0 or max(face) >= n:
            raise InputFormatError(
                f"{where}: face {face} must list at least 3 indices in 0..{n - 1}"
            )


def _outward(vertices: np.ndarray, faces: list[list[int]]) -> tuple[tuple[int, ...], ...]:
    """Orient each face of a convex block so its normal points away from the block's interior."""
    # About the vertex mean: far from the origin (x = 1e10) the cross products of raw
    # coordinates would cancel to noise and turn faces the wrong way.
    local = vertices - vertices.mean(axis=0)
    oriented = []
    for face in faces:
        p = local[face]
        normal = np.cross(p, np.roll(p, -1, axis=0)).sum(axis=0)
        outward = np.dot(normal, p.mean(axis=0)) >= 0
        oriented.append(tuple(face) if outward else tuple(reversed(face)))
    return tuple(oriented)


def read_block_entries(raw_blocks: list) -> list[Block]:
    """The blocks of a document's ``"blocks"`` list: the same blocks, and the same first error,
    as ``[entry_block(entry, k) for k, entry in enumerate(raw_blocks)]``."""
    count = len(raw_blocks)
    doubtful = np.zeros(count, dtype=bool)
    fields: list = [None] * count
    for k, entry in enumerate(raw_blocks):
        fields[k] = _plain_fields(entry, k)
        if fields[k] is None:
            doubtful[k] = True
    vertices = _vertex_arrays(raw_blocks, fields, doubtful)
    given = [k for k in range(count) if not doubtful[k] and fields[k][2] is not None]
    hull_of = [k for k in range(count) if not doubtful[k] and fields[k][2] is None]
    hulls = dict(zip(hull_of, batched_hulls([vertices[k] for k in hull_of]), strict=True))
    faces = dict(
        zip(given, _outward_many([vertices[k] for k in given], [fields[k][2] for k in given]),
            strict=True)
    )  # fmt: skip
    blocks = []
    for k in range(count):
        if doubtful[k]:
            blocks.append(entry_block(raw_blocks[k], k))
            continue
        kwargs = fields[k][1]
        if k in faces:
            blocks.append(Block(vertices[k], faces[k], **kwargs))
        elif hulls[k] is not None:
            blocks.append(Block(*hulls[k], **kwargs))
        else:
            blocks.append(Block.from_hull(vertices[k], **kwargs))
    return blocks


def _plain_fields(entry: object, k: int):
    """``(raw vertices, Block keywords, raw faces or None)`` of an entry whose fields are
    plainly sound, the vertices only checked for their shape (a non-empty list of lists of
    three); None at any doubt, and the entry is then read by :func:`entry_block`. The same tests
    as :func:`_entry_fields` and :func:`_check_faces`, written inline: this runs once a block."""
    if type(entry) is not dict:
        return None
    get = entry.get
    block_id = entry["id"] if "id" in entry else f"b{k}"
    value = get("vertices")
    if type(block_id) is not str or not block_id or type(value) is not list or not value:
        return None
    for point in value:
        if type(point) is not list or len(point) != 3:
            return None
    density = get("density", DEFAULT_DENSITY)
    if type(density) is int:
        try:
            density = float(density)
        except OverflowError:
            return None
    if type(density) is not float or not (0.0 <= density <= _LARGEST):
        return None
    fixed, structural, body = get("fixed", False), get("structural", True), get("body", "")
    if type(fixed) is not bool or type(structural) is not bool or type(body) is not str:
        return None
    tags, rule_path = get("tags", _NONE), get("rule_path", _NONE)
    if type(tags) is not list or type(rule_path) is not list:
        return None
    for text in chain(tags, rule_path):
        if type(text) is not str:
            return None
    appearance = get("appearance")
    if appearance is not None:
        try:
            appearance = appearance_from_entry(appearance, f"block {block_id!r}")
        except InputFormatError:
            return None
    faces = get("faces")
    if faces is not None:
        if type(faces) is not list:
            return None
        n = len(value)
        for face in faces:
            if type(face) is not list or len(face) < 3:
                return None
            for i in face:
                if type(i) is not int or not 0 <= i < n:
                    return None
    kwargs = {
        "id": block_id,
        "density": density,
        "fixed": fixed,
        "structural": structural,
        "tags": tuple(tags),
        "rule_path": tuple(rule_path),
        "appearance": appearance,
        "body": body,
    }
    return value, kwargs, faces


_NONE: list = []
_LARGEST = float(np.finfo(float).max)


def _vertex_arrays(raw_blocks: list, fields: list, doubtful: np.ndarray) -> list:
    """The ``(k, 3)`` vertex array of each sound entry (None for the others); an entry whose
    coordinates are not all finite numbers is marked ``doubtful``."""
    arrays: list = [None] * len(raw_blocks)
    groups: dict[int, list[int]] = {}
    for k, value in enumerate(fields):
        if value is not None:
            groups.setdefault(len(value[0]), []).append(k)
    for members in groups.values():
        nested = [fields[k][0] for k in members]
        kinds = set(map(type, chain.from_iterable(chain.from_iterable(nested))))
        if kinds <= {float, int}:
            try:
                stacked = np.array(nested, dtype=float)
            except (OverflowError, ValueError):
                stacked = None
        else:
            stacked = None
        if stacked is None:  # rare: find the entries at fault one by one
            for k in members:
                try:
                    arrays[k] = points(fields[k][0], "")
                except InputFormatError:
                    doubtful[k] = True
            continue
        finite = np.isfinite(stacked).all(axis=(1, 2))
        for k, array, ok in zip(members, stacked, finite.tolist(), strict=True):
            if ok:
                arrays[k] = array
            else:
                doubtful[k] = True
    return arrays


def _outward_many(vertices: list[np.ndarray], faces: list[list[list[int]]]) -> list[tuple]:
    """:func:`_outward` of many blocks in one pass; equal results share one
    :class:`CheckedFaces`."""
    if not vertices:
        return []
    vertex_count = np.array([len(v) for v in vertices])
    vertex_start = np.concatenate([[0], np.cumsum(vertex_count)])
    stacked = np.concatenate(vertices)
    means = np.add.reduceat(stacked, vertex_start[:-1], axis=0) / vertex_count[:, None]
    local = stacked - np.repeat(means, vertex_count, axis=0)
    face_count = np.array([len(f) for f in faces])
    flat_faces = list(chain.from_iterable(faces))
    sizes = np.fromiter(map(len, flat_faces), dtype=np.intp, count=len(flat_faces))
    starts = np.concatenate([[0], np.cumsum(sizes)])
    face_block = np.repeat(np.arange(len(faces)), face_count)
    corners = np.fromiter(chain.from_iterable(flat_faces), dtype=np.intp, count=int(starts[-1]))
    corners = corners + np.repeat(vertex_start[:-1][face_block], sizes)
    p = local[corners]
    successor = np.arange(len(corners)) + 1
    successor[starts[1:] - 1] = starts[:-1]
    normal = np.add.reduceat(cross(p, p[successor]), starts[:-1], axis=0)
    centre = np.add.reduceat(p, starts[:-1], axis=0) / sizes[:, None]
    outward = np.einsum("ij,ij->i", normal, centre) >= 0
    shared: dict[tuple, CheckedFaces] = {}
    out = []
    position = 0
    keep = outward.tolist()
    for block_faces in faces:
        oriented = tuple(
            tuple(face) if keep[position + j] else tuple(reversed(face))
            for j, face in enumerate(block_faces)
        )
        position += len(block_faces)
        out.append(shared.setdefault(oriented, CheckedFaces(oriented)))
    return out
