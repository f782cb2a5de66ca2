"""The "shapegen-blocks" v1 interchange format (JSON), written; see docs/formats.md.

It is read back by :mod:`shapegen.readers.blocks_json`, which owns the format's name and
version."""

from __future__ import annotations

__all__ = ["load_entries", "model_settings", "model_to_dict", "write_blocks_json"]

import json
from pathlib import Path

from shapegen.export.atomic import atomic_write
from shapegen.export.surfaces import surfaces_of
from shapegen.json_values import json_ready
from shapegen.model.block import Block
from shapegen.model.model import Model
from shapegen.readers.blocks_json import FORMAT_NAME, FORMAT_VERSION


def model_to_dict(model: Model) -> dict:
    """The model as a shapegen-blocks v1 document (plain JSON types).

    A model derived from a grammar also records its ``structure``: the name of what judges it
    and the ``@Structure`` arguments of this design, so ``shapegen analyze`` judges the file as
    the report that came with it did.
    """
    document = {
        **model_settings(model),
        "blocks": [_block_entry(block) for block in model.blocks],
        "loads": load_entries(model),
    }
    surfaces = surfaces_of(model)
    if surfaces:
        document["surfaces"] = [surface.to_dict() for surface in surfaces]
    structure = (model.metadata or {}).get("structure")
    if structure:
        document["structure"] = json_ready(structure)
    return document


def model_settings(model: Model) -> dict:
    """The format, units and the model's gravity, ground and friction, as a shapegen-blocks
    document (and a glTF scene's extras) begin."""
    return {
        "format": FORMAT_NAME,
        "version": FORMAT_VERSION,
        "units": "m",
        "up": "y",
        "gravity": [float(g) for g in model.gravity],
        "ground": None if model.ground is None else float(model.ground),
        "friction": float(model.friction),
    }


def load_entries(model: Model) -> list[dict]:
    """The model's point loads as shapegen-blocks entries (N, m)."""
    return [
        {"block": load.block, "force": load.force.tolist(), "point": load.point.tolist()}
        for load in model.loads
    ]


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
