"""Meshes out: OBJ, PLY and STL files of block models (they are read back by
:mod:`shapegen.readers.meshes`); PLY and STL through trimesh, imported only for them.

:func:`encode_obj` (a group per block, the blocks' own polygon faces, full precision),
:func:`encode_ply` and :func:`encode_stl` (the whole model as one triangle mesh).
"""

from __future__ import annotations

__all__ = [
    "block_triangles",
    "model_mesh",
    "encode_obj",
    "encode_ply",
    "encode_stl",
]

import re
from typing import TYPE_CHECKING

import numpy as np

from shapegen.export.colors import appearance_color
from shapegen.export.surfaces import face_triangles, surfaces_of
from shapegen.model.block import Block
from shapegen.model.model import Model
from shapegen.readers.surface_entries import SURFACE_GROUP

if TYPE_CHECKING:
    import trimesh


# ---------------------------------------------------------------------------------- writing
def block_triangles(block: Block) -> np.ndarray:
    """``(t, 3)`` vertex indices of the block's faces cut into fans (faces are convex polygons)."""
    triangles = [
        (face[0], face[i], face[i + 1]) for face in block.faces for i in range(1, len(face) - 1)
    ]
    return np.array(triangles, dtype=np.int64).reshape(-1, 3)


def model_mesh(model: Model) -> trimesh.Trimesh:
    """All blocks as one triangle mesh; blocks keep separate vertices, so each is one component."""
    import trimesh  # only PLY and STL need it: its import is most of a small build's run

    if not model.blocks:
        return trimesh.Trimesh(np.zeros((0, 3)), np.zeros((0, 3), dtype=np.int64), process=False)
    counts = np.array([len(block.vertices) for block in model.blocks])
    starts = np.concatenate([[0], np.cumsum(counts)[:-1]])
    vertices = np.concatenate([block.vertices for block in model.blocks])
    triangles = np.concatenate(
        [block_triangles(block) + start for block, start in zip(model.blocks, starts, strict=True)]
    )
    return trimesh.Trimesh(vertices, triangles, process=False)


def encode_obj(model: Model) -> bytes:
    """Wavefront OBJ text: a group named by block id per block, its polygon faces as they are,
    then a group ``surface:<id>`` per surface (read back as a surface, not a block).

    Coordinates are written with 17 significant digits, so reading the file back gives the same
    float64 values; a surface's polygons are written as triangles. A block or surface whose
    rule gave it a colour has it on its vertices (``v x y z r g b``, the common extension
    MeshLab, Blender and trimesh read).
    """
    lines = ["# shapegen block model (metres, y up); one group per block"]
    offset = 1  # OBJ indices are 1-based and global to the file
    items = [(block.id, block) for block in model.blocks]
    items += [(SURFACE_GROUP + surface.id, surface) for surface in surfaces_of(model)]
    for name, item in items:
        if not item.faces:
            continue
        lines.append(f"g {_obj_name(name)}")
        color = appearance_color(item.appearance)
        rgb = "" if color is None else " " + " ".join(f"{c / 255:.4g}" for c in color[:3])
        lines.extend(f"v {x:.17g} {y:.17g} {z:.17g}{rgb}" for x, y, z in item.vertices)
        # A surface's polygons may be non-convex, which readers would fan wrongly: triangles.
        faces = item.faces if isinstance(item, Block) else face_triangles(item.vertices, item.faces)
        lines.extend("f " + " ".join(str(i + offset) for i in face) for face in faces)
        offset += len(item.vertices)
    return ("\n".join(lines) + "\n").encode("utf-8")


def encode_ply(model: Model) -> bytes:
    """Binary PLY of the whole model as one triangle mesh."""
    return model_mesh(model).export(file_type="ply")


def encode_stl(model: Model) -> bytes:
    """Binary STL of the whole model as one triangle mesh."""
    return model_mesh(model).export(file_type="stl")


def _obj_name(block_id: str) -> str:
    # OBJ group names end at whitespace.
    return re.sub(r"\s+", "_", block_id) or "block"
