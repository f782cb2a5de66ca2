"""Colours of exported blocks: a stable palette for labels and a ramp for tension.

Colours are RGBA with components in 0..255 (``uint8``), the form trimesh materials take.
"""

from __future__ import annotations

__all__ = [
    "LABEL_PALETTE",
    "UNLABELLED",
    "SUPPORT",
    "NON_STRUCTURAL",
    "RESULTANT",
    "SURFACE",
    "TENSION_ZERO",
    "TENSION_MAX",
    "TENSION_STEPS",
    "label_color",
    "appearance_color",
    "block_label_color",
    "display_color",
    "tension_colors",
    "tension_levels",
]

import zlib
from collections.abc import Sequence

import numpy as np

from shapegen.tolerances import FORCE_NOISE_REL

# Ten well-separated hues (muted, so that stone-like models stay readable).
LABEL_PALETTE = np.array(
    [
        [78, 121, 167, 255],
        [242, 142, 43, 255],
        [89, 161, 79, 255],
        [237, 201, 72, 255],
        [176, 122, 161, 255],
        [118, 183, 178, 255],
        [255, 157, 167, 255],
        [156, 117, 95, 255],
        [186, 176, 172, 255],
        [225, 87, 89, 255],
    ],
    dtype=np.uint8,
)
UNLABELLED = np.array([205, 198, 185, 255], dtype=np.uint8)  # sandstone
SUPPORT = np.array([60, 90, 160, 255], dtype=np.uint8)  # blue: fixed blocks
NON_STRUCTURAL = np.array([170, 140, 100, 110], dtype=np.uint8)  # translucent timber
RESULTANT = np.array([20, 20, 20, 255], dtype=np.uint8)  # near-black arrows
SURFACE = np.array([188, 196, 204, 255], dtype=np.uint8)  # light slate: surfaces, not judged
TENSION_ZERO = np.array([160, 160, 160, 255], dtype=np.uint8)  # neutral grey
TENSION_MAX = np.array([220, 30, 30, 255], dtype=np.uint8)  # red
TENSION_STEPS = 32  # the ramp is quantised so a large model needs few materials


def label_color(label: str) -> np.ndarray:
    """The palette colour of ``label``: the same label always gets the same colour.

    The choice hashes the label text (CRC-32), so it does not depend on the order in which labels
    appear in a model or on Python's per-process string hashing.
    """
    return LABEL_PALETTE[zlib.crc32(label.encode("utf-8")) % len(LABEL_PALETTE)].copy()


def block_label_color(tags: Sequence[str], *, fixed: bool, structural: bool) -> np.ndarray:
    """A block's colour in label mode: supports and non-structural blocks first, then its first
    label, then the unlabelled stone colour."""
    if fixed:
        return SUPPORT.copy()
    if not structural:
        return NON_STRUCTURAL.copy()
    if tags:
        return label_color(tags[0])
    return UNLABELLED.copy()


def appearance_color(appearance) -> np.ndarray | None:
    """The RGBA colour a rule gave (``color(...)``, ``material.color``, ``material.opacity``),
    or None when it gave none. CGA colours are sRGB, as glTF's base colour factor."""
    if appearance is None or (appearance.color is None and appearance.opacity == 1.0):
        return None
    rgb = appearance.color if appearance.color is not None else (1.0, 1.0, 1.0)
    return np.round(255 * np.clip([*rgb, appearance.opacity], 0.0, 1.0)).astype(np.uint8)


def display_color(item) -> np.ndarray:
    """The colour of a block or a surface when no analysis colours it: the rule's colour,
    else (a block) :func:`block_label_color`, or (a surface) its first label's colour or
    :data:`SURFACE`."""
    color = appearance_color(getattr(item, "appearance", None))
    if color is not None:
        return color
    if hasattr(item, "fixed"):
        return block_label_color(item.tags, fixed=item.fixed, structural=item.structural)
    return label_color(item.tags[0]) if item.tags else SURFACE.copy()


def tension_levels(analysis) -> np.ndarray:
    """``(nb,)`` in [0, 1]: each block's worst tension relative to the worst block's.

    All zero when the analysis says the model stands, and tensions below
    :data:`~shapegen.tolerances.FORCE_NOISE_REL` of the total weight count as zero, so that the
    round-off of a standing model is never painted as tension.
    """
    tension = np.nan_to_num(np.asarray(analysis.block_tension, dtype=float), nan=0.0)
    tension = tension.reshape(-1).clip(min=0.0)
    if getattr(analysis, "feasible", False):
        return np.zeros_like(tension)
    weight = float(getattr(analysis, "total_weight", 0.0) or 0.0)
    tension[tension <= FORCE_NOISE_REL * weight] = 0.0
    peak = float(tension.max()) if tension.size else 0.0
    return tension / peak if peak > 0 else np.zeros_like(tension)


def tension_colors(levels: np.ndarray, fixed: np.ndarray, structural: np.ndarray) -> np.ndarray:
    """``(n, 4)`` colours on the grey-to-red ramp.

    Parameters
    ----------
    levels
        ``(n,)`` tension levels in [0, 1] (see :func:`tension_levels`).
    fixed, structural
        ``(n,)`` booleans: supports get :data:`SUPPORT`, non-structural blocks
        :data:`NON_STRUCTURAL`.

    The ramp runs from :data:`TENSION_ZERO` at 0 to :data:`TENSION_MAX` at 1 in
    :data:`TENSION_STEPS` steps.
    """
    fraction = np.clip(np.asarray(levels, dtype=float), 0.0, 1.0)
    fraction = np.round(fraction * (TENSION_STEPS - 1)) / (TENSION_STEPS - 1)
    ramp = TENSION_ZERO + fraction[:, None] * (TENSION_MAX.astype(float) - TENSION_ZERO)
    colors = np.round(ramp).astype(np.uint8)
    colors[np.asarray(structural, dtype=bool) == 0] = NON_STRUCTURAL
    colors[np.asarray(fixed, dtype=bool)] = SUPPORT
    return colors
