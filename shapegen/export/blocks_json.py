"""The "shapegen-blocks" v1 interchange format (JSON); see docs/formats.md."""

from __future__ import annotations

__all__ = [
    "FORMAT_NAME",
    "FORMAT_VERSION",
    "model_to_dict",
    "model_from_dict",
    "read_blocks_json",
    "write_blocks_json",
]

import json
import math
from pathlib import Path

import numpy as np

from shapegen.errors import GeometryError, InputFormatError
from shapegen.export.atomic import atomic_write
from shapegen.export.surfaces import appearance_from_entry, surface_from_entry, surfaces_of
from shapegen.json_values import json_ready
from shapegen.limits import current_limits, limit_hint
from shapegen.model.block import DEFAULT_DENSITY, Block
from shapegen.model.model import GRAVITY, Model, PointLoad
from shapegen.readers.files import parse_json_document, read_model_bytes

FORMAT_NAME = "shapegen-blocks"
FORMAT_VERSION = 1


def model_to_dict(model: Model) -> dict:
    """The model as a shapegen-blocks v1 document (plain JSON types).

    A model derived from a grammar also records its ``structure``: the name of what judges it
    and the ``@Structure`` arguments of this design, so ``shapegen analyze`` judges the file as
    the report that came with it did.
    """
    document = {
        "format": FORMAT_NAME,
        "version": FORMAT_VERSION,
        "units": "m",
        "up": "y",
        "gravity": [float(g) for g in model.gravity],
        "ground": None if model.ground is None else float(model.ground),
        "friction": float(model.friction),
        "blocks": [_block_entry(block) for block in model.blocks],
        "loads": [
            {"block": load.block, "force": load.force.tolist(), "point": load.point.tolist()}
            for load in model.loads
        ],
    }
    surfaces = surfaces_of(model)
    if surfaces:
        document["surfaces"] = [surface.to_dict() for surface in surfaces]
    structure = (model.metadata or {}).get("structure")
    if structure:
        document["structure"] = json_ready(structure)
    return document


def _block_entry(block: Block) -> dict:
    entry = block.to_dict()
    look = block.appearance.to_dict() if block.appearance is not None else {}
    if look:
        entry["appearance"] = json_ready(look)
    return entry


def write_blocks_json(model: Model, path: str | Path) -> None:
    """Write the model atomically as shapegen-blocks JSON."""
    document = model_to_dict(model)
    with atomic_write(path) as handle:
        json.dump(document, handle, indent=1, allow_nan=False)
        handle.write("\n")


MAX_JSON_DEPTH = 32
"""Deepest nesting of arrays and objects kept from a model file as they are (the
``"structure"`` arguments): reports and exports walk them recursively."""


def _depth_over(document: object, limit: int) -> bool:
    """True when ``document`` nests arrays and objects more than ``limit`` deep (no recursion)."""
    level = [document]
    for _ in range(limit + 1):
        level = [
            child
            for value in level
            if isinstance(value, list | dict)
            for child in (value.values() if isinstance(value, dict) else value)
        ]
        if not level:
            return False
    return True


def read_blocks_json(path: str | Path) -> Model:
    """Read a shapegen-blocks JSON file; errors name the file and the offending entry."""
    path = Path(path)
    document = parse_json_document(read_model_bytes(path), str(path))
    try:
        return model_from_dict(document)
    except (InputFormatError, GeometryError) as exc:
        raise type(exc)(f"{path}: {exc}") from None


def model_from_dict(document: object) -> Model:
    """Build a model from a parsed shapegen-blocks document. Unknown keys are ignored."""
    if not isinstance(document, dict):
        raise InputFormatError("the top level must be a JSON object")
    if document.get("format") != FORMAT_NAME:
        raise InputFormatError(f'"format" must be "{FORMAT_NAME}", got {document.get("format")!r}')
    version = document.get("version")
    if version != FORMAT_VERSION:
        raise InputFormatError(f'unsupported "version" {version!r}; this reader knows version 1')
    if document.get("units", "m") != "m":
        raise InputFormatError(f'"units" must be "m", got {document.get("units")!r}')
    if document.get("up", "y") != "y":
        raise InputFormatError(f'"up" must be "y", got {document.get("up")!r}')
    gravity = _vector(document.get("gravity", list(GRAVITY)), '"gravity"')
    ground = document.get("ground", 0.0)
    if ground is not None:
        ground = _number(ground, '"ground"')
    friction = _number(document.get("friction", 0.7), '"friction"')
    if friction < 0:
        raise InputFormatError(f'"friction" must be >= 0, got {friction}')
    raw_blocks = _require(document, "blocks", "the document")
    if not isinstance(raw_blocks, list):
        raise InputFormatError('"blocks" must be a list')
    limit = current_limits().max_blocks
    if len(raw_blocks) > limit:
        raise InputFormatError(
            f"the model has {len(raw_blocks)} blocks, more than {limit} " + limit_hint("max_blocks")
        )
    blocks = [_block(entry, k) for k, entry in enumerate(raw_blocks)]
    raw_loads = document.get("loads", [])
    if not isinstance(raw_loads, list):
        raise InputFormatError('"loads" must be a list')
    loads = [_load(entry, k) for k, entry in enumerate(raw_loads)]
    raw_surfaces = document.get("surfaces", [])
    if not isinstance(raw_surfaces, list):
        raise InputFormatError('"surfaces" must be a list')
    if len(raw_surfaces) > limit:
        raise InputFormatError(
            f"the model has {len(raw_surfaces)} surfaces, more than {limit} "
            + limit_hint("max_blocks")
        )
    surfaces = [
        surface_from_entry(entry, k, _points, _number, _strings)
        for k, entry in enumerate(raw_surfaces)
    ]
    model = Model(blocks, loads, gravity=gravity, ground=ground, friction=friction)
    model.surfaces = surfaces
    structure = document.get("structure")
    if structure is not None:
        if not (
            isinstance(structure, dict)
            and isinstance(structure.get("name"), str)
            and isinstance(structure.get("arguments", {}), dict)
        ):
            raise InputFormatError(
                '"structure" must be an object {"name": "...", "arguments": {...}}'
            )
        if _depth_over(structure, MAX_JSON_DEPTH):
            raise InputFormatError(f'"structure" nests deeper than {MAX_JSON_DEPTH} levels')
        model.metadata["structure"] = {
            "name": structure["name"],
            "arguments": dict(structure.get("arguments", {})),
        }
    model.validate()
    return model


def _block(entry: object, k: int) -> Block:
    where = f"blocks[{k}]"
    if not isinstance(entry, dict):
        raise InputFormatError(f"{where} must be an object")
    block_id = entry.get("id", f"b{k}")
    if not isinstance(block_id, str) or not block_id:
        raise InputFormatError(f'{where}: "id" must be a non-empty string')
    where = f"block {block_id!r}"
    vertices = _points(_require(entry, "vertices", where), f'{where}: "vertices"')
    kwargs = dict(
        id=block_id,
        density=_number(entry.get("density", DEFAULT_DENSITY), f'{where}: "density"'),
        fixed=_boolean(entry.get("fixed", False), f'{where}: "fixed"'),
        structural=_boolean(entry.get("structural", True), f'{where}: "structural"'),
        tags=_strings(entry.get("tags", []), f'{where}: "tags"'),
        rule_path=_strings(entry.get("rule_path", []), f'{where}: "rule_path"'),
        appearance=appearance_from_entry(entry.get("appearance"), where, _number),
        body=entry.get("body", ""),
    )
    if not isinstance(kwargs["body"], str):
        raise InputFormatError(f'{where}: "body" must be a string')
    if kwargs["density"] < 0:
        raise InputFormatError(f'{where}: "density" must be >= 0')
    faces = entry.get("faces")
    if faces is None:
        return Block.from_hull(vertices, **kwargs)
    if not isinstance(faces, list) or not all(
        isinstance(f, list) and all(isinstance(i, int) and not isinstance(i, bool) for i in f)
        for f in faces
    ):
        raise InputFormatError(f'{where}: "faces" must be a list of lists of vertex indices')
    n = len(vertices)
    for face in faces:
        if len(face) < 3 or min(face) < 0 or max(face) >= n:
            raise InputFormatError(
                f"{where}: face {face} must list at least 3 indices in 0..{n - 1}"
            )
    return Block(vertices, _outward(vertices, faces), **kwargs)


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


def _load(entry: object, k: int) -> PointLoad:
    where = f"loads[{k}]"
    if not isinstance(entry, dict):
        raise InputFormatError(f"{where} must be an object")
    block = _require(entry, "block", where)
    if not isinstance(block, str):
        raise InputFormatError(f'{where}: "block" must be a block id (a string)')
    force = _vector(_require(entry, "force", where), f'{where}: "force"')
    point = _vector(_require(entry, "point", where), f'{where}: "point"')
    return PointLoad(block, force, point)


def _require(entry: dict, key: str, where: str):
    if key not in entry:
        raise InputFormatError(f'{where}: missing required key "{key}"')
    return entry[key]


def _number(value: object, where: str) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise InputFormatError(f"{where} must be a finite number, got {_shown(value)}")
    try:
        number = float(value)
    except OverflowError:  # an int beyond float range, from a caller's own dict
        number = math.inf
    if not math.isfinite(number):
        raise InputFormatError(f"{where} must be a finite number, got {_shown(value)}")
    return number


def _shown(value: object) -> str:
    """A value for a message, cut short (a file may hold a 5 000-digit number)."""
    if isinstance(value, int) and not isinstance(value, bool) and abs(value) >= 10**20:
        return f"an integer of {round(value.bit_length() * 0.30103)} digits"
    try:
        text = repr(value)
    except ValueError:  # holds an int too long to print
        return f"a {type(value).__name__} holding a number too long to print"
    return text if len(text) <= 60 else text[:57] + "..."


def _boolean(value: object, where: str) -> bool:
    if not isinstance(value, bool):
        raise InputFormatError(f"{where} must be true or false, got {value!r}")
    return value


def _strings(value: object, where: str) -> tuple[str, ...]:
    if not isinstance(value, list) or not all(isinstance(s, str) for s in value):
        raise InputFormatError(f"{where} must be a list of strings")
    return tuple(value)


def _vector(value: object, where: str) -> np.ndarray:
    if not isinstance(value, list) or len(value) != 3:
        raise InputFormatError(f"{where} must be a list of 3 numbers")
    return np.array([_number(v, where) for v in value])


def _points(value: object, where: str) -> np.ndarray:
    if not isinstance(value, list) or not value:
        raise InputFormatError(f"{where} must be a non-empty list of [x, y, z] points")
    return np.array([_vector(p, where) for p in value])
