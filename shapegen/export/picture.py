"""Offline pictures of a model (matplotlib, no screen needed).

Blocks are drawn as shaded polygons with dark edges so the joints (the stereotomy) stay visible.
With an analysis, blocks are coloured by the worst tension they need (grey = none, red = the most)
and supports are drawn dark.
"""

from __future__ import annotations

__all__ = ["render_model"]

from pathlib import Path

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from mpl_toolkits.mplot3d.art3d import Poly3DCollection  # noqa: E402

from shapegen.export.atomic import atomic_write  # noqa: E402
from shapegen.export.colors import tension_levels  # noqa: E402
from shapegen.model.model import Model  # noqa: E402

_STONE = np.array([0.80, 0.78, 0.72])
_SUPPORT = np.array([0.35, 0.35, 0.38])
_TENSION = np.array([0.85, 0.10, 0.10])
_LIGHT = np.array([-0.3, 0.8, -0.5]) / np.linalg.norm([-0.3, 0.8, -0.5])  # from the viewer's side


def render_model(
    model: Model,
    path: str | Path,
    analysis=None,
    *,
    title: str | None = None,
    elevation: float = 20.0,
    azimuth: float = -60.0,
    size_px: tuple[int, int] = (800, 600),
    bounds: np.ndarray | None = None,
) -> None:
    """Write a PNG picture of ``model`` to ``path`` (atomically).

    Parameters
    ----------
    analysis
        An :class:`~shapegen.statics.Analysis` of the model; its ``block_tension`` (N) colours the
        blocks.
    elevation, azimuth
        View angles, degrees (y is up in the model; the picture shows y vertical).
    size_px
        Width and height in pixels.
    bounds
        ``(2, 3)`` lower and upper corners (m, model axes) of the box to frame; default the
        model's bounding box. A fixed box keeps the view still across animation frames.
    """
    dpi = 100
    fig = plt.figure(figsize=(size_px[0] / dpi, size_px[1] / dpi), dpi=dpi)
    ax = fig.add_subplot(projection="3d")
    tension = None
    if analysis is not None and getattr(analysis, "block_tension", None) is not None:
        tension = tension_levels(analysis)
    elev, azim = np.radians(elevation), np.radians(azimuth)
    # Direction towards the viewer, in model axes (matplotlib's z is the model's y).
    eye = np.array([np.cos(elev) * np.cos(azim), np.sin(elev), -np.cos(elev) * np.sin(azim)])
    polygons, colors = [], []
    for k, block in enumerate(model.blocks):
        base = _SUPPORT if block.fixed else _STONE
        if tension is not None and not block.fixed and tension[k] > 0:
            base = (1 - tension[k]) * _STONE + tension[k] * _TENSION
        for face, normal in zip(block.faces, block.face_normals, strict=True):
            if np.dot(normal, eye) <= 0:  # back faces only confuse matplotlib's depth sort
                continue
            polygons.append(_to_view(block.vertices[list(face)]))
            shade = 0.55 + 0.45 * max(float(np.dot(normal, _LIGHT)), 0.0)
            colors.append(np.clip(base * shade, 0, 1))
    collection = Poly3DCollection(
        polygons, facecolors=colors, edgecolors=(0.15, 0.15, 0.15, 0.8), linewidths=0.3
    )
    ax.add_collection3d(collection)
    if model.blocks or bounds is not None:
        if bounds is not None:
            points = _to_view(np.asarray(bounds, float).reshape(2, 3))
        else:
            points = _to_view(np.vstack([b.vertices for b in model.blocks]))
        lo, hi = points.min(axis=0), points.max(axis=0)
        extent = np.maximum(hi - lo, 0.05 * (hi - lo).max() or 1.0)
        center = (lo + hi) / 2
        for axis_limits, c, e in zip(
            (ax.set_xlim, ax.set_ylim, ax.set_zlim), center, extent, strict=True
        ):
            axis_limits(c - e / 2, c + e / 2)
        ax.set_box_aspect(tuple(extent), zoom=1.0)
    ax.set_proj_type("ortho")
    ax.view_init(elev=elevation, azim=azimuth)
    ax.set_axis_off()
    if title:
        ax.set_title(title)
    fig.tight_layout()
    with atomic_write(path, "wb") as handle:
        fig.savefig(handle, format="png", dpi=dpi)
    plt.close(fig)


def _to_view(points: np.ndarray) -> np.ndarray:
    """Model (x, y up, z) to matplotlib (x, -z, y up): a rotation, so nothing is mirrored."""
    return np.column_stack([points[:, 0], -points[:, 2], points[:, 1]])
