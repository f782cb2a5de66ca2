"""Write block models by file extension (:mod:`shapegen.readers.models` reads them).

=============  ==============================
extension      write
=============  ==============================
``.json``      shapegen-blocks v1
``.glb``       glTF, one node per block
``.gltf``      glTF (single file, embedded)
``.obj``       a group per block
``.ply``       the whole mesh
``.stl``       the whole mesh
=============  ==============================

Writers first build the whole file in memory (:func:`encode_model`), then replace the target
atomically, so a failure never leaves a half-written file.
"""

from __future__ import annotations

__all__ = [
    "WRITE_SUFFIXES",
    "encode_model",
    "write_model",
    "check_output_path",
    "write_bytes_atomic",
]

import importlib
import json
from collections.abc import Callable
from pathlib import Path

from shapegen.export.atomic import atomic_write, check_writable
from shapegen.export.blocks_json import model_to_dict
from shapegen.export.finite import check_writable_numbers
from shapegen.model.model import Model
from shapegen.readers.models import unknown_format


def _encode_json(model: Model, analysis=None) -> bytes:
    text = json.dumps(model_to_dict(model), indent=1, allow_nan=False)
    return (text + "\n").encode("utf-8")


def _encoder(module: str, name: str, takes_analysis: bool) -> Callable[..., bytes]:
    """The encoder ``module.name``, its module (and trimesh behind it) imported when a file of
    its format is first written."""

    def encode(model: Model, analysis=None) -> bytes:
        function = getattr(importlib.import_module(module), name)
        return function(model, analysis) if takes_analysis else function(model)

    return encode


_ENCODERS: dict[str, Callable[..., bytes]] = {
    ".json": _encode_json,
    ".glb": _encoder("shapegen.export.gltf", "encode_glb", True),
    ".gltf": _encoder("shapegen.export.gltf", "encode_gltf", True),
    ".obj": _encoder("shapegen.export.meshes", "encode_obj", False),
    ".ply": _encoder("shapegen.export.meshes", "encode_ply", False),
    ".stl": _encoder("shapegen.export.meshes", "encode_stl", False),
}
WRITE_SUFFIXES = tuple(_ENCODERS)
_FLOAT32_SUFFIXES = (".glb", ".gltf", ".ply", ".stl")  # formats whose coordinates are float32


def check_output_path(path: str | Path) -> Path:
    """The output path, after checking that its extension is writable and its folder exists."""
    path = Path(path)
    suffix = path.suffix.lower()
    if suffix not in _ENCODERS:
        raise unknown_format(path, "output", WRITE_SUFFIXES)
    return check_writable(path)


def encode_model(model: Model, path: str | Path, analysis=None) -> bytes:
    """The bytes :func:`write_model` would write to ``path`` (format from its extension).

    ``analysis`` is used by glTF output (colours by tension, resultant arrows); other formats
    ignore it.
    """
    path = check_output_path(path)
    suffix = path.suffix.lower()
    check_writable_numbers(model, str(path), float32=suffix in _FLOAT32_SUFFIXES)
    return _ENCODERS[suffix](model, analysis=analysis)


def write_model(model: Model, path: str | Path, analysis=None) -> None:
    """Write ``model`` to ``path`` atomically, in the format its extension names."""
    content = encode_model(model, path, analysis)
    write_bytes_atomic(path, content)


def write_bytes_atomic(path: str | Path, content: bytes) -> None:
    """Replace ``path`` with ``content`` (temporary file + rename)."""
    with atomic_write(path, "wb") as handle:
        handle.write(content)
