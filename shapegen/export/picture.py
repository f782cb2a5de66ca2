"""Offline pictures of a model: the depth-buffered rendering of :mod:`shapegen.export.render`
with a title and a legend drawn around it by matplotlib (no screen needed).

Without an analysis the blocks take the colour their rule gave them (``color(...)``), else
their label colours, and the legend names the labels; with one, they are coloured by the worst
tension they need (grey = none, red = the most, as in the glTF output) and a colour bar gives
the scale in newtons. Surfaces (leaves left out of the statics) are drawn in their rule's
colour or light grey, from both sides. Colours come from :mod:`shapegen.export.colors`.
"""

from __future__ import annotations

__all__ = ["encode_picture", "model_figure", "render_model", "TENSION_LEGEND"]

import io
from collections import Counter
from pathlib import Path

import numpy as np

from shapegen.export.atomic import atomic_write, check_writable
from shapegen.export.colors import (
    NON_STRUCTURAL,
    SUPPORT,
    SURFACE,
    TENSION_MAX,
    TENSION_STEPS,
    TENSION_ZERO,
    UNLABELLED,
    appearance_color,
    display_color,
    label_color,
    model_label_colors,
    tension_colors,
    tension_levels,
)
from shapegen.export.finite import check_writable_numbers
from shapegen.export.render import render_blocks
from shapegen.model.model import Model

TENSION_LEGEND = "tension legend"  # the colour bar's axes label, for tools that look for it
_DPI = 100
_MAX_LABELS = 8  # label entries in a legend; the rest are counted on one line


def render_model(model: Model, path: str | Path, analysis=None, **options) -> None:
    """Write a PNG picture of ``model`` to ``path`` (atomically; the folder is checked first).

    ``options`` are the keywords of :func:`model_figure` (title, elevation, azimuth, size_px,
    bounds, legend).
    """
    target = check_writable(path)
    content = encode_picture(model, analysis, **options)
    with atomic_write(target, "wb") as handle:
        handle.write(content)


def encode_picture(model: Model, analysis=None, **options) -> bytes:
    """PNG bytes of :func:`model_figure`."""
    check_writable_numbers(model, "the picture")
    figure = model_figure(model, analysis, **options)
    buffer = io.BytesIO()
    figure.savefig(buffer, format="png", dpi=_DPI)
    return buffer.getvalue()


def model_figure(
    model: Model,
    analysis=None,
    *,
    title: str | None = None,
    elevation: float = 25.0,
    azimuth: float = -60.0,
    size_px: tuple[int, int] = (800, 600),
    bounds: np.ndarray | None = None,
    legend: bool | None = None,
):
    """A matplotlib ``Figure`` of ``size_px`` pixels: the rendering, a title and a legend.

    Parameters
    ----------
    analysis
        An :class:`~shapegen.statics.Analysis` of the model; its ``block_tension`` (N) colours
        the blocks and the legend is a colour bar in newtons.
    elevation, azimuth
        The view, degrees (y is up; see :func:`shapegen.export.render.view_axes`).
    size_px
        Width and height in pixels (at least 64 x 48).
    bounds
        ``(2, 3)`` lower and upper corners (m, model axes) of the box to frame; default the
        blocks. A fixed box keeps the view still across animation frames.
    legend
        Draw the legend strip on the right: by default with an analysis, and without one when
        the blocks show two colours or more.
    """
    from matplotlib.figure import Figure

    width, height = (int(v) for v in size_px)
    if width < 64 or height < 48:
        raise ValueError(f"a picture of {width} x {height} pixels is too small (64 x 48 at least)")
    if analysis is not None:
        colors, entries, peak = _tension_colors(model, analysis)
    else:
        colors, entries, peak = _label_colors(model), _label_entries(model), None
    surfaces = list(getattr(model, "surfaces", None) or [])
    by_label = model_label_colors(model.blocks)  # a labelled surface as the blocks of its label
    entries = entries + _surface_entries(surfaces)
    if legend is None:
        legend = analysis is not None or len(entries) > 1
    legend_px = max(120, round(0.2 * width)) if legend else 0
    title_px = max(24, round(0.06 * height)) if title else 0
    view_px = (width - legend_px, height - title_px)
    rendering = render_blocks(
        model,
        colors,
        size_px=view_px,
        elevation=elevation,
        azimuth=azimuth,
        bounds=bounds,
        surface_colors=np.array([display_color(s, by_label) for s in surfaces]).reshape(-1, 4),
    )
    figure = Figure(figsize=(width / _DPI, height / _DPI), dpi=_DPI, facecolor="white")
    figure.figimage(rendering.rgb, xo=0, yo=0, origin="upper")
    font = max(8.5, min(11.0, height / 60))
    if title:
        figure.text(view_px[0] / 2 / width, 1 - title_px / 2 / height, title,
                    ha="center", va="center", fontsize=font + 1)  # fmt: skip
    if legend:
        left = view_px[0] / width
        if analysis is not None:
            _tension_bar(figure, left, legend_px / width, peak, font)
        if entries:
            _legend(figure, left, entries, font, below_bar=analysis is not None)
    return figure


def _tension_colors(model: Model, analysis) -> tuple[np.ndarray, list, float]:
    tension = np.asarray(analysis.block_tension, dtype=float).reshape(-1)
    if len(tension) != len(model.blocks):
        raise ValueError(f"the analysis has {len(tension)} block tensions for {len(model.blocks)}")
    levels = tension_levels(analysis)
    fixed = np.array([b.fixed for b in model.blocks], dtype=bool)
    structural = np.array([b.structural for b in model.blocks], dtype=bool)
    peak = float(np.nan_to_num(tension, nan=0.0).max()) if levels.max(initial=0) > 0 else 0.0
    entries = []
    if fixed.any():
        entries.append(("support", SUPPORT))
    if (~structural & ~fixed).any():
        entries.append(("non-structural", NON_STRUCTURAL))
    return tension_colors(levels, fixed, structural), entries, peak


def _label_colors(model: Model) -> np.ndarray:
    """Each block's colour in label mode, each label its own colour, as the design page has."""
    by_label = model_label_colors(model.blocks)
    colors = [display_color(b, by_label) for b in model.blocks]
    return np.array(colors, dtype=np.uint8).reshape(-1, 4)


def _surface_entries(surfaces: list) -> list[tuple[str, np.ndarray | None]]:
    """The legend row of the surfaces painted in the default surface colour."""
    plain = sum(1 for s in surfaces if appearance_color(s.appearance) is None and not s.tags)
    return [("not judged", SURFACE)] if plain else []


def _label_entries(model: Model) -> list[tuple[str, np.ndarray]]:
    """Legend rows in label mode: the labels by how many blocks carry them, then the kinds of
    block that :func:`~shapegen.export.colors.block_label_color` paints apart."""
    painted = [appearance_color(b.appearance) is not None for b in model.blocks]
    labels = Counter(
        b.tags[0]
        for b, own in zip(model.blocks, painted, strict=True)
        if b.tags and b.structural and not b.fixed and not own
    ).most_common()
    by_label = model_label_colors(model.blocks)
    entries = [
        (label, by_label.get(label, label_color(label))) for label, _ in labels[:_MAX_LABELS]
    ]
    if len(labels) > _MAX_LABELS:
        entries.append((f"+{len(labels) - _MAX_LABELS} more labels", None))
    if any(
        b.structural and not b.fixed and not b.tags and not own
        for b, own in zip(model.blocks, painted, strict=True)
    ):
        entries.append(("unlabelled", UNLABELLED))
    if any(b.fixed for b in model.blocks):
        entries.append(("support", SUPPORT))
    if any(not b.structural and not b.fixed for b in model.blocks):
        entries.append(("non-structural", NON_STRUCTURAL))
    return entries


def _tension_bar(figure, left: float, strip: float, peak: float, font: float) -> None:
    """The grey-to-red ramp of :func:`~shapegen.export.colors.tension_colors` as a colour bar
    whose top is the worst block's tension."""
    from matplotlib.cm import ScalarMappable
    from matplotlib.colors import ListedColormap, Normalize

    steps = np.linspace(0.0, 1.0, TENSION_STEPS)[:, None]
    ramp = (TENSION_ZERO + steps * (TENSION_MAX.astype(float) - TENSION_ZERO)) / 255.0
    axes = figure.add_axes((left + 0.12 * strip, 0.42, 0.12 * strip, 0.42), label=TENSION_LEGEND)
    bar = figure.colorbar(
        ScalarMappable(norm=Normalize(0.0, 1.0), cmap=ListedColormap(ramp[:, :3])), cax=axes
    )
    bar.set_ticks([0.0, 0.5, 1.0])
    if peak > 0:
        bar.set_ticklabels(["0", _newtons(peak / 2), _newtons(peak)])
    else:
        bar.set_ticklabels(["0", "", ""])
    bar.ax.tick_params(labelsize=font - 1)
    axes.set_title("tension\nneeded", fontsize=font, loc="left")
    if peak <= 0:
        axes.text(0.0, -0.08, "none: it stands", transform=axes.transAxes, fontsize=font - 1,
                  va="top")  # fmt: skip


def _legend(figure, left: float, entries: list, font: float, *, below_bar: bool) -> None:
    from matplotlib.patches import Patch

    handles = [
        Patch(facecolor=(0, 0, 0, 0), edgecolor=(0, 0, 0, 0), label=name)
        if color is None
        else Patch(facecolor=np.asarray(color) / 255.0, edgecolor=(0.2, 0.2, 0.2), label=name)
        for name, color in entries
    ]
    figure.legend(
        handles=handles,
        loc="upper left" if below_bar else "center left",
        bbox_to_anchor=(left, 0.3 if below_bar else 0.5),
        frameon=False,
        fontsize=font - 1,
        handlelength=1.2,
        borderaxespad=0.3,
    )


def _newtons(force: float) -> str:
    for unit, size in (("MN", 1e6), ("kN", 1e3)):
        if force >= size:
            return f"{force / size:.3g} {unit}"
    return f"{force:.3g} N"
