"""Block model files read by their extension.

=============  ======================================
extension      read
=============  ======================================
``.json``      shapegen-blocks v1 (:mod:`~shapegen.readers.blocks_json`)
``.glb``       glTF nodes -> blocks (:mod:`~shapegen.readers.meshes`)
``.gltf``      glTF nodes -> blocks
``.obj``       groups / components -> blocks
``.ply``       components -> blocks
``.stl``       components -> blocks
=============  ======================================

Every file is read through :func:`shapegen.readers.files.read_model_bytes`, within the size
limit; :mod:`shapegen.export.model_io` writes the same formats.
"""

from __future__ import annotations

__all__ = ["MESH_READ_SUFFIXES", "READ_SUFFIXES", "read_model", "unknown_format"]

from pathlib import Path

from shapegen.errors import InputFormatError
from shapegen.model.model import Model
from shapegen.readers.blocks_json import read_blocks_json

MESH_READ_SUFFIXES = (".obj", ".gltf", ".glb", ".ply", ".stl")
"""The mesh formats read through trimesh (:func:`shapegen.readers.meshes.read_mesh_model`)."""
READ_SUFFIXES = (".json", *MESH_READ_SUFFIXES)


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
        raise unknown_format(path, "model", READ_SUFFIXES)
    if suffix == ".json":
        try:
            return read_blocks_json(path)
        except UnicodeDecodeError as exc:
            raise InputFormatError(f"{path}: not UTF-8 text ({exc.reason})") from None
    from shapegen.readers.meshes import read_mesh_model

    return read_mesh_model(path)


def unknown_format(path: Path, kind: str, supported) -> InputFormatError:
    """The error for a file whose extension is none of ``supported``."""
    suffix = path.suffix.lower()
    return InputFormatError(
        f"{path}: unknown {kind} format {suffix or '(no extension)'!r};"
        f" supported: {', '.join(supported)}"
    )
