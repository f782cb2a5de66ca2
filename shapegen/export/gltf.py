"""glTF 2.0 output (.glb and single-file .gltf): one node per block, named by its id, and one
per surface.

Each block node carries ``extras``: ``role`` ("block"), ``labels``, ``rule_path``, ``density``
(kg/m^3), ``fixed``, ``structural``, the rule's ``appearance`` if it set one and, with an
analysis, ``tension`` (N). Each surface (a leaf drawn but left out of the statics: a face, an
open or non-convex mesh) is a node with ``role`` "surface", ``structural`` false, its
``reason``, ``labels``, ``rule_path`` and ``appearance``, and a double-sided material. The
scene ``extras`` hold the model settings (gravity, ground, friction, loads) so that shapegen
reads its own files back completely. Without an analysis the blocks take the colour their rule
gave (``color(...)``, ``material.color``/``opacity``: the base colour factor of their
material), else their first label's; with one, their worst tension on a grey-to-red ramp, and
the interface resultants are drawn as arrows in one extra node (``role`` "resultants").
Surfaces keep their rule's colour either way. glTF is y-up and in metres, like shapegen, so
coordinates are written unchanged. See docs/formats.md.
"""

from __future__ import annotations

__all__ = [
    "ARROW_LENGTH_BLOCKS",
    "ARROW_WIDTH_BLOCKS",
    "RESULTANTS_NODE",
    "Arrows",
    "block_size",
    "model_document",
    "resultant_arrows",
    "encode_glb",
    "encode_gltf",
]

from typing import NamedTuple

import numpy as np

from shapegen.export.blocks_json import load_entries, model_settings
from shapegen.export.colors import (
    RESULTANT,
    display_color,
    model_label_colors,
    tension_colors,
    tension_levels,
)
from shapegen.export.gltf_document import GltfDocument
from shapegen.export.meshes import block_triangles
from shapegen.export.surfaces import face_triangles, surfaces_of
from shapegen.json_values import json_ready
from shapegen.limits import check_clock
from shapegen.model.model import Model
from shapegen.readers.surface_entries import SURFACE_ROLE
from shapegen.tolerances import FORCE_NOISE_REL

# Arrows are scaled to the blocks, not to the model: on a 2 km bridge a share of the model's
# size made arrows 300 m long over blocks of a few metres.
ARROW_LENGTH_BLOCKS = 1.0  # the largest resultant arrow, in block sizes (see block_size)
ARROW_WIDTH_BLOCKS = 0.05  # arrow shaft width, in block sizes
RESULTANTS_NODE = "shapegen:resultants"


class Arrows(NamedTuple):
    """The resultant arrows as one triangle mesh."""

    vertices: np.ndarray  # (n, 3)
    faces: np.ndarray  # (t, 3) vertex indices


def model_document(model: Model, analysis=None) -> GltfDocument:
    """The model as a glTF document, a node per block and per surface.

    Parameters
    ----------
    model
        The block model.
    analysis
        An ``Analysis`` of this model (from :func:`shapegen.statics.analyze`) or None. With it,
        blocks are coloured by ``analysis.block_tension`` and the resultants are drawn as arrows.
    """
    document = GltfDocument(extras=_scene_extras(model, analysis))
    n = len(model.blocks)
    fixed = np.array([b.fixed for b in model.blocks], dtype=bool)
    structural = np.array([b.structural for b in model.blocks], dtype=bool)
    tension = None
    if analysis is not None:
        tension = np.asarray(analysis.block_tension, dtype=float).reshape(-1)
        if len(tension) != n:
            raise ValueError(f"the analysis has {len(tension)} block tensions for {n} blocks")
        colors = tension_colors(tension_levels(analysis), fixed, structural)
    else:  # each label its own colour, as the design page shows the model
        by_label = model_label_colors(model.blocks)
        colors = np.array([display_color(b, by_label) for b in model.blocks], dtype=np.uint8)
        colors = colors.reshape(-1, 4)
    for k, block in enumerate(model.blocks):
        check_clock()
        extras = {
            "role": "block",
            "labels": list(block.tags),
            "rule_path": list(block.rule_path),
            "density": block.density,
            "fixed": block.fixed,
            "structural": block.structural,
        }
        look = block.appearance.to_dict() if block.appearance is not None else {}
        if look:
            extras["appearance"] = json_ready(look)
        if tension is not None:
            extras["tension"] = float(tension[k]) if np.isfinite(tension[k]) else 0.0
        document.add_mesh(block.id, block.vertices, block_triangles(block), colors[k], extras)
    _add_surfaces(document, model, model_label_colors(model.blocks))
    if analysis is not None:
        arrows, newtons_per_metre, count = resultant_arrows(model, analysis)
        if arrows is not None:
            extras = {"role": "resultants", "count": count, "newtons_per_metre": newtons_per_metre}
            document.add_mesh(RESULTANTS_NODE, arrows.vertices, arrows.faces, RESULTANT, extras)
    return document


def _add_surfaces(document: GltfDocument, model: Model, by_label: dict) -> None:
    """One node per surface with triangles; named by its id (made unique among the nodes); a
    labelled surface in its label's colour among the blocks' (``by_label``)."""
    used = {block.id for block in model.blocks}
    for surface in surfaces_of(model):
        check_clock()
        triangles = face_triangles(surface.vertices, surface.faces)
        if len(triangles) == 0:
            continue
        name = surface.id
        while name in used:
            name = "surface:" + name
        used.add(name)
        extras = {
            "role": SURFACE_ROLE,
            "structural": False,
            "reason": surface.reason,
            "labels": list(surface.tags),
            "rule_path": list(surface.rule_path),
        }
        look = surface.appearance.to_dict() if surface.appearance is not None else {}
        if look:
            extras["appearance"] = json_ready(look)
        color = display_color(surface, by_label)
        document.add_mesh(name, surface.vertices, triangles, color, extras, double_sided=True)


def encode_glb(model: Model, analysis=None) -> bytes:
    """Binary glTF (.glb) bytes of :func:`model_document`."""
    return model_document(model, analysis).glb()


def encode_gltf(model: Model, analysis=None) -> bytes:
    """Single-file glTF (.gltf) bytes: JSON with the buffer embedded as base64."""
    return model_document(model, analysis).gltf()


def resultant_arrows(model: Model, analysis) -> tuple[Arrows | None, float, int]:
    """The interface resultants as thin arrows, merged into one mesh.

    Each arrow lies along the force that ``first`` exerts on ``second`` and is centred on the
    resultant's point of application; its length is proportional to the force, the largest being
    :data:`ARROW_LENGTH_BLOCKS` times the model's :func:`block_size`.

    Returns
    -------
    mesh, newtons_per_metre, count
        The arrows (None when there is no force to draw), the force scale in N per metre of arrow
        length, and the number of arrows.
    """
    forces = np.asarray(analysis.resultant_forces, dtype=float).reshape(-1, 3)
    points = np.asarray(analysis.resultant_points, dtype=float).reshape(-1, 3)
    magnitude = np.linalg.norm(forces, axis=1)
    drawable = np.isfinite(magnitude) & np.all(np.isfinite(points), axis=1)
    peak = float(magnitude[drawable].max()) if drawable.any() else 0.0
    if peak <= 0:
        return None, 0.0, 0
    drawable &= magnitude > FORCE_NOISE_REL * peak
    size = block_size(model)
    metres_per_newton = ARROW_LENGTH_BLOCKS * size / peak
    length = magnitude[drawable] * metres_per_newton
    direction = forces[drawable] / magnitude[drawable, None]
    start = points[drawable] - 0.5 * length[:, None] * direction
    template_vertices, template_faces = _arrow_template()
    width = ARROW_WIDTH_BLOCKS * size
    frames = _frames(direction)  # (n, 3, 3), columns u, v, direction
    local = (
        template_vertices[None, :, :]
        * np.stack([np.full_like(length, width), np.full_like(length, width), length], axis=1)[
            :, None, :
        ]
    )
    vertices = np.einsum("nij,nmj->nmi", frames, local) + start[:, None, :]
    m = len(template_vertices)
    faces = template_faces[None, :, :] + (m * np.arange(len(length)))[:, None, None]
    arrows = Arrows(vertices.reshape(-1, 3), faces.reshape(-1, 3))
    return arrows, 1.0 / metres_per_newton, int(len(length))


def block_size(model: Model) -> float:
    """The typical size of the model's blocks, metres: the median over its structural blocks
    (all blocks when none is) of the edge of a cube of the block's volume."""
    chosen = [b for b in model.blocks if b.structural] or model.blocks
    if not chosen:
        return 1.0
    return float(np.median(np.cbrt([max(b.volume, 0.0) for b in chosen]))) or 1.0


def _arrow_template(sides: int = 6) -> tuple[np.ndarray, np.ndarray]:
    """A unit arrow along +z from z = 0 to z = 1: a prism shaft of width 1 and a pyramid head."""
    angle = 2 * np.pi * np.arange(sides) / sides
    ring = np.stack([np.cos(angle), np.sin(angle)], axis=1)
    head_start = 0.75
    shaft_bottom = np.column_stack([0.5 * ring, np.zeros(sides)])
    shaft_top = np.column_stack([0.5 * ring, np.full(sides, head_start)])
    head_base = np.column_stack([1.5 * ring, np.full(sides, head_start)])
    tip = np.array([[0.0, 0.0, 1.0]])
    bottom_center = np.array([[0.0, 0.0, 0.0]])
    vertices = np.concatenate([shaft_bottom, shaft_top, head_base, tip, bottom_center])
    i = np.arange(sides)
    j = (i + 1) % sides
    b, t, h = 0, sides, 2 * sides
    tip_index, center_index = 3 * sides, 3 * sides + 1
    faces = np.concatenate(
        [
            np.stack([b + i, b + j, t + j], axis=1),  # shaft sides
            np.stack([b + i, t + j, t + i], axis=1),
            np.stack([t + i, t + j, h + j], axis=1),  # ring under the head
            np.stack([t + i, h + j, h + i], axis=1),
            np.stack([h + i, h + j, np.full(sides, tip_index)], axis=1),  # head
            np.stack([b + j, b + i, np.full(sides, center_index)], axis=1),  # bottom cap
        ]
    )
    return vertices, faces


def _frames(direction: np.ndarray) -> np.ndarray:
    """``(n, 3, 3)`` rotations whose third column is each unit ``direction``."""
    helper_axis = np.where(
        (np.abs(direction[:, 0]) < 0.9)[:, None], np.array([1.0, 0.0, 0.0]), [0.0, 1.0, 0.0]
    )
    u = np.cross(direction, helper_axis)
    u /= np.linalg.norm(u, axis=1, keepdims=True)
    v = np.cross(direction, u)
    return np.stack([u, v, direction], axis=2)


def _scene_extras(model: Model, analysis) -> dict:
    extras = {**model_settings(model), "loads": load_entries(model)}
    structure = (model.metadata or {}).get("structure")
    if structure:
        extras["structure"] = json_ready(structure)
    if analysis is not None:
        extras["analysis"] = {
            key: json_ready(getattr(analysis, key, None))
            for key in (
                "status",
                "feasible",
                "infeasibility",
                "infeasibility_normalized",
                "max_tension",
                "total_weight",
            )
        }
    return extras
