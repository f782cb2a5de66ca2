"""The "shapegen-blocks" v1 interchange format (JSON), read; see docs/formats.md.

The bytes come through :func:`shapegen.readers.files.read_model_bytes` (the size limit) and
:func:`~shapegen.readers.files.parse_json_document`; the blocks are read by
:mod:`shapegen.readers.block_entries`, the surfaces by :mod:`shapegen.readers.surface_entries`.
:mod:`shapegen.export.blocks_json` writes the format.
"""

from __future__ import annotations

__all__ = ["FORMAT_NAME", "FORMAT_VERSION", "model_from_dict", "read_blocks_json"]

import gc
from contextlib import contextmanager
from pathlib import Path

from shapegen.errors import GeometryError, InputFormatError, OptionError
from shapegen.limits import current_limits, limit_hint
from shapegen.model.friction import checked_friction
from shapegen.model.model import GRAVITY, Model, PointLoad
from shapegen.readers.block_entries import read_block_entries
from shapegen.readers.files import parse_json_document, read_model_bytes
from shapegen.readers.json_fields import number as _number
from shapegen.readers.json_fields import require as _require
from shapegen.readers.json_fields import vector as _vector
from shapegen.readers.surface_entries import surface_from_entry

FORMAT_NAME = "shapegen-blocks"
FORMAT_VERSION = 1


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
    with _collector_paused():
        document = parse_json_document(read_model_bytes(path), str(path))
        try:
            return model_from_dict(document)
        except (InputFormatError, GeometryError) as exc:
            raise type(exc)(f"{path}: {exc}") from None


@contextmanager
def _collector_paused():
    """Python's cycle collector off while a file is read: the millions of lists a large model
    parses into hold no cycles, yet each one counts towards the next full collection, which walks
    all of them again (a 100 000-block file parsed 3x slower with it on)."""
    enabled = gc.isenabled()
    gc.disable()
    try:
        yield
    finally:
        if enabled:
            gc.enable()


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
    try:
        friction = checked_friction(_number(document.get("friction", 0.7), '"friction"'))
    except OptionError as exc:
        raise InputFormatError(f'"friction": {exc}') from None
    raw_blocks = _require(document, "blocks", "the document")
    if not isinstance(raw_blocks, list):
        raise InputFormatError('"blocks" must be a list')
    limit = current_limits().max_blocks
    if len(raw_blocks) > limit:
        raise InputFormatError(
            f"the model has {len(raw_blocks)} blocks, more than {limit} " + limit_hint("max_blocks")
        )
    blocks = read_block_entries(raw_blocks)
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
    surfaces = [surface_from_entry(entry, k) for k, entry in enumerate(raw_surfaces)]
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
