"""Read and write block models by file extension.

=============  ======================================  ==============================
extension      read                                    write
=============  ======================================  ==============================
``.json``      shapegen-blocks v1                      shapegen-blocks v1
``.glb``       glTF nodes -> blocks                    glTF, one node per block
``.gltf``      glTF nodes -> blocks                    glTF (single file, embedded)
``.obj``       groups / components -> blocks           a group per block
``.ply``       components -> blocks                    the whole mesh
``.stl``       components -> blocks                    the whole mesh
=============  ======================================  ==============================

Writers first build the whole file in memory (:func:`encode_model`), then replace the target
atomically, so a failure never leaves a half-written file.
"""

from __future__ import annotations

__all__ = [
    "READ_SUFFIXES",
    "WRITE_SUFFIXES",
    "read_model",
    "encode_model",
    "write_model",
    "check_output_path",
    "write_bytes_atomic",
]

import importlib
import json
from collections.abc import Callable
from pathlib import Path

from shapegen.errors import InputFormatError
from shapegen.export.atomic import atomic_write, check_writable
from shapegen.export.blocks_json import model_to_dict, read_blocks_json
from shapegen.export.finite import check_writable_numbers
from shapegen.model.model import Model

MESH_READ_SUFFIXES = (".obj", ".gltf", ".glb", ".ply", ".stl")
"""The mesh formats read through trimesh (:func:`shapegen.export.meshes.read_mesh_model`)."""
READ_SUFFIXES = (".json", *MESH_READ_SUFFIXES)


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


def read_model(path: str | Path) -> Model:
    """Read a block model; the format follows the extension (see the module table).

    Raises
    ------
    InputFormatError
        Unknown extension (the message lists the supported ones), missing or malformed file.
    GeometryError
        A degenerate or non-convex block.
    """
    path = Path(path)
    suffix = path.suffix.lower()
    if suffix not in READ_SUFFIXES:
        raise _unknown_format(path, "model", READ_SUFFIXES)
    if suffix == ".json":
        try:
            return read_blocks_json(path)
        except UnicodeDecodeError as exc:
            raise InputFormatError(f"{path}: not UTF-8 text ({exc.reason})") from None
    from shapegen.export.meshes import read_mesh_model

    return read_mesh_model(path)


def check_output_path(path: str | Path) -> Path:
    """The output path, after checking that its extension is writable and its folder exists."""
    path = Path(path)
    suffix = path.suffix.lower()
    if suffix not in _ENCODERS:
        raise _unknown_format(path, "output", WRITE_SUFFIXES)
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


def _unknown_format(path: Path, kind: str, supported) -> InputFormatError:
    """The error for a file whose extension is none of ``supported``."""
    suffix = path.suffix.lower()
    return InputFormatError(
        f"{path}: unknown {kind} format {suffix or '(no extension)'!r};"
        f" supported: {', '.join(supported)}"
    )
