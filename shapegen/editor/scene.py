"""What the page draws besides the blocks' meshes: their colours, the forces, the legend.

The meshes come from ``GET /api/model.glb`` (:func:`shapegen.export.gltf.encode_glb`, one node
per block named by its id); this module gives, per block in the same order, its colour by label
as the exports colour it (:mod:`shapegen.export.colors`: the rule's colour if it gave one, else
its label's, each label of the model its own, none like the tension red) and by the tension it
needs, and the forces of the seed paper's Figure 1:
the resultant of every joint between two blocks and the reaction of every support (the ground,
or a fixed block) on the structure. Arrows are scaled as the glTF's: the largest force is
:data:`~shapegen.export.gltf.ARROW_LENGTH_BLOCKS` times the model's typical block
(:func:`~shapegen.export.gltf.block_size`).
"""

from __future__ import annotations

__all__ = ["scene_data"]

import numpy as np

from shapegen.export.colors import (
    NON_STRUCTURAL,
    SUPPORT,
    TENSION_MAX,
    TENSION_ZERO,
    display_color,
    model_label_colors,
    tension_colors,
    tension_levels,
)
from shapegen.export.gltf import ARROW_LENGTH_BLOCKS, block_size
from shapegen.json_values import finite_or_none
from shapegen.model import Model
from shapegen.statics.interface import GROUND
from shapegen.structures import Assessment
from shapegen.tolerances import FORCE_NOISE_REL


def scene_data(model: Model, assessment: Assessment | None) -> dict:
    """The page's scene description of ``model`` judged by ``assessment`` (plain JSON)."""
    blocks = model.blocks
    fixed = np.array([b.fixed for b in blocks], dtype=bool)
    structural = np.array([b.structural for b in blocks], dtype=bool)
    by_label = model_label_colors(blocks)
    labels = sorted(by_label)
    # as an export colours them, with the model's label colours (each label its own)
    label_colors = [display_color(b, by_label).tolist() for b in blocks]
    analysis = assessment.block_analysis if assessment is not None else None
    tension = None
    tension_rgba = None
    if analysis is not None:
        tension = np.nan_to_num(np.asarray(analysis.block_tension, float).reshape(-1), nan=0.0)
        tension_rgba = tension_colors(tension_levels(analysis), fixed, structural).tolist()
    lows = np.array([b.vertices.min(axis=0) for b in blocks]) if blocks else np.zeros((1, 3))
    highs = np.array([b.vertices.max(axis=0) for b in blocks]) if blocks else np.zeros((1, 3))
    return {
        "blocks": [
            {
                "id": b.id,
                "label": b.tags[0] if b.tags else "",
                "color": label_colors[k],
                "tension": None if tension is None else float(max(tension[k], 0.0)),
                "tension_color": None if tension_rgba is None else tension_rgba[k],
            }
            for k, b in enumerate(blocks)
        ],
        "bounds": [lows.min(axis=0).tolist(), highs.max(axis=0).tolist()],
        "ground": None if model.ground is None else float(model.ground),
        "legend": {
            "labels": [[label, by_label[label].tolist()] for label in labels],
            "support": SUPPORT.tolist(),
            "non_structural": NON_STRUCTURAL.tolist(),
            "tension_zero": TENSION_ZERO.tolist(),
            "tension_max": TENSION_MAX.tolist(),
            "max_tension": None if analysis is None else finite_or_none(analysis.max_tension),
        },
        "forces": _forces(model, analysis),
    }


def _forces(model: Model, analysis) -> dict | None:
    """``joints`` and ``ground`` arrows as ``[x, y, z, fx, fy, fz]`` (point m, force N), and the
    drawing scale ``metres_per_newton``; None without a block analysis."""
    if analysis is None or not len(analysis.interfaces):
        return None
    forces = np.asarray(analysis.resultant_forces, float).reshape(-1, 3)
    points = np.asarray(analysis.resultant_points, float).reshape(-1, 3)
    # the joints number the blocks judged: the model's, then any stand-ins (statics.standins)
    judged = analysis.model if getattr(analysis, "model", None) is not None else model
    fixed = np.array([b.fixed for b in judged.blocks], dtype=bool)
    first = np.array([i.first for i in analysis.interfaces])
    second = np.array([i.second for i in analysis.interfaces])
    second_support = np.where(second == GROUND, True, fixed[np.maximum(second, 0)])
    first_support = fixed[first]
    support = second_support | first_support
    # the force the support exerts on the structure: resultants are on ``second`` from ``first``
    on_structure = np.where(second_support[:, None], -forces, forces)
    magnitude = np.linalg.norm(forces, axis=1)
    drawable = np.isfinite(magnitude) & np.all(np.isfinite(points), axis=1)
    peak = float(magnitude[drawable].max()) if drawable.any() else 0.0
    if peak <= 0:
        return {"joints": [], "ground": [], "metres_per_newton": 0.0, "peak": 0.0}
    drawable &= magnitude > FORCE_NOISE_REL * peak

    def rows(mask: np.ndarray, vectors: np.ndarray) -> list[list[float]]:
        data = np.concatenate([points[mask], vectors[mask]], axis=1)
        return np.round(data, 6).tolist()

    return {
        "joints": rows(drawable & ~support, forces),
        "ground": rows(drawable & support, on_structure),
        "metres_per_newton": ARROW_LENGTH_BLOCKS * block_size(model) / peak,
        "peak": peak,
    }
