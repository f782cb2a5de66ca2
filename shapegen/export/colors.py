"""Colours of exported blocks: a stable palette for labels and a ramp for tension.

Colours are RGBA with components in 0..255 (``uint8``), the form trimesh materials take. The
exports and the design page (``shapegen edit``) take their label colours from the one
:data:`LABEL_PALETTE`: a label has the colour its name hashes to (:func:`label_color`), and in
a model whose labels would share one, :func:`label_colors` gives each its own (as the page
does; :func:`display_color` takes that assignment as ``colors``).
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
    "label_colors",
    "model_label_colors",
    "appearance_color",
    "block_label_color",
    "display_color",
    "tension_colors",
    "tension_levels",
]

import zlib
from collections.abc import Iterable, Mapping, Sequence

import numpy as np

from shapegen.tolerances import FORCE_NOISE_REL

# Twelve muted hues (stone-like models stay readable), each at least 20 (CIE76 Delta E) from
# the others and 25 from the tension ramp's reds, the supports' blue and the non-structural
# timber, so that a label never reads as "needs tension" or "support"
# (tests/editor/test_editor_scene.py). The old palette's red lay 9 Delta E from the ramp.
LABEL_PALETTE = np.array(
    [
        [222, 178, 60, 255],  # ochre
        [96, 160, 80, 255],  # green
        [110, 170, 215, 255],  # sky blue
        [235, 137, 52, 255],  # orange
        [50, 150, 150, 255],  # teal
        [160, 105, 190, 255],  # purple
        [195, 215, 95, 255],  # lime
        [40, 110, 70, 255],  # dark green
        [185, 160, 225, 255],  # lavender
        [140, 140, 50, 255],  # olive
        [150, 215, 175, 255],  # mint
        [120, 210, 225, 255],  # cyan
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


def label_colors(labels: Iterable[str]) -> dict[str, np.ndarray]:
    """``label -> RGBA`` for the labels of one model, each its own colour while there are no
    more labels than :data:`LABEL_PALETTE` has colours.

    A label takes the colour its text hashes to (:func:`label_color`, the same in every model
    and every run) unless a label before it (in sorted order) took it; then the next free one.
    """
    taken: set[int] = set()
    colors = {}
    size = len(LABEL_PALETTE)
    for label in sorted(set(labels)):
        slot = zlib.crc32(label.encode("utf-8")) % size
        if len(taken) < size:
            while slot in taken:
                slot = (slot + 1) % size
        taken.add(slot)
        colors[label] = LABEL_PALETTE[slot].copy()
    return colors


def model_label_colors(blocks: Iterable) -> dict[str, np.ndarray]:
    """:func:`label_colors` of the labels that colour blocks (the first label of each
    structural block that is not a support): the design page's colours of a model."""
    return label_colors(
        b.tags[0] for b in blocks if b.tags and b.structural and not b.fixed
    )  # fmt: skip


def block_label_color(
    tags: Sequence[str],
    *,
    fixed: bool,
    structural: bool,
    colors: Mapping[str, np.ndarray] | None = None,
) -> np.ndarray:
    """A block's colour in label mode: supports and non-structural blocks first, then its first
    label (from ``colors``, a model's :func:`model_label_colors`, when given), then the
    unlabelled stone colour."""
    if fixed:
        return SUPPORT.copy()
    if not structural:
        return NON_STRUCTURAL.copy()
    if tags:
        if colors is not None and tags[0] in colors:
            return np.array(colors[tags[0]], dtype=np.uint8)
        return label_color(tags[0])
    return UNLABELLED.copy()


def appearance_color(appearance) -> np.ndarray | None:
    """The RGBA colour a rule gave (``color(...)``, ``material.color``, ``material.opacity``),
    or None when it gave none. CGA colours are sRGB, as glTF's base colour factor."""
    if appearance is None or (appearance.color is None and appearance.opacity == 1.0):
        return None
    rgb = appearance.color if appearance.color is not None else (1.0, 1.0, 1.0)
    return np.round(255 * np.clip([*rgb, appearance.opacity], 0.0, 1.0)).astype(np.uint8)


def display_color(item, colors: Mapping[str, np.ndarray] | None = None) -> np.ndarray:
    """The colour of a block or a surface when no analysis colours it: the rule's colour,
    else (a block) :func:`block_label_color`, or (a surface) its first label's colour or
    :data:`SURFACE`; ``colors`` is the model's :func:`model_label_colors`, which the design
    page shows (without it a label has the colour its name hashes to)."""
    color = appearance_color(getattr(item, "appearance", None))
    if color is not None:
        return color
    if hasattr(item, "fixed"):
        return block_label_color(
            item.tags, fixed=item.fixed, structural=item.structural, colors=colors
        )
    if item.tags and colors is not None and item.tags[0] in colors:
        return np.array(colors[item.tags[0]], dtype=np.uint8)
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
