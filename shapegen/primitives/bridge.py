"""Suspension bridge parts: ``cable`` (one span of a main cable) and ``suspenders`` (its hangers).

Both are fitted to the scope of one span: x from one support to the next (the span ``K_s = sx``),
y from the deck's top (the scope's bottom) to the tower saddles (the scope's top), z across the
bridge with the cable in the scope's middle plane ``z = sz / 2``.

Every span of a main cable is an arc of the main span's parabola (the same load per metre and the
same horizontal tension, see docs/bridges.md), so a span of width ``K_s`` hangs with the sag

    f_s = f (K_s / K)^2

below the chord joining its two supports, and its centreline is

    y(x) = y_left + (y_right - y_left) x / K_s - 4 f_s x (K_s - x) / K_s^2

with the supports ``drop_left`` and ``drop_right`` metres below the scope's top (0 for a main
span between two towers, more at an anchorage). The cable's section is sized by the cable model:
:func:`shapegen.statics.cables.bridge_cables` gives the governing diameter from the layout and
loading the rule passes in (the same values its ``@Structure("cable", ...)`` hands the cable
structure), unless a ``diameter`` is given.
"""

from __future__ import annotations

__all__ = ["cable", "cable_height", "suspenders", "span_sag"]

import numpy as np

from shapegen.errors import GeometryError, StaticsError
from shapegen.model.block import Block
from shapegen.model.scope import Scope
from shapegen.primitives.prism import prism_blocks
from shapegen.primitives.registry import primitive, require_blocks, require_vertices
from shapegen.statics.cables import GOLDEN_FACTOR, SAFETY_FACTOR, bridge_cables


def span_sag(span: float, main_span: float, sag: float) -> float:
    """Sag (m) of a span of width ``span`` (m) on the parabola of a main span ``main_span`` (m)
    with sag ``sag`` (m): ``sag (span / main_span)^2``."""
    return sag * (span / main_span) ** 2


def cable_height(
    x: np.ndarray | float,
    span: float,
    span_sag_m: float,
    top: float,
    drop_left: float = 0.0,
    drop_right: float = 0.0,
) -> np.ndarray:
    """Height (m, scope frame) of the cable centreline at ``x`` (m from the left support).

    The supports are at ``top - drop_left`` (x = 0) and ``top - drop_right`` (x = span); the
    cable hangs ``span_sag_m`` below their chord at midspan.
    """
    x = np.asarray(x, dtype=float)
    left, right = top - drop_left, top - drop_right
    return left + (right - left) * x / span - 4.0 * span_sag_m * x * (span - x) / span**2


def _span_geometry(owner: str, scope: Scope, main_span: float, sag: float, drops) -> tuple:
    span, top = scope.sx, scope.sy
    if span <= 0 or scope.sz <= 0:
        raise GeometryError(f"primitive {owner!r}: needs a scope with positive width and depth")
    main_span = main_span if main_span > 0 else span
    if sag <= 0:
        raise GeometryError(f"primitive {owner!r}: sag must be positive, got {sag:g} m")
    for name, drop in zip(("drop_left", "drop_right"), drops, strict=True):
        if not 0 <= drop <= top:
            raise GeometryError(
                f"primitive {owner!r}: {name} {drop:g} m must lie between 0 and the scope height "
                f"{top:g} m"
            )
    return span, top, span_sag(span, main_span, sag)


def _sized_diameter(**inputs) -> float:
    """The governing diameter (m) the cable model gives for the bridge's layout and loading."""
    try:
        return bridge_cables(**inputs).diameter
    except StaticsError as exc:  # a loading that cannot be sized: the primitive's own error
        raise GeometryError(f"primitive 'cable': {exc}") from None


@primitive("cable", scope_relative=True)
def cable(
    scope: Scope,
    *,
    sag: float = 0.0,
    main_span: float = 0.0,
    drop_left: float = 0.0,
    drop_right: float = 0.0,
    side_span: float = 0.0,
    diameter: float = 0.0,
    lanes: int = 0,
    tracks: int = 0,
    cables: int = 2,
    golden_factor: float = GOLDEN_FACTOR,
    safety_factor: float = SAFETY_FACTOR,
    segments: int = 48,
    sides: int = 8,
) -> list[Block]:
    """One span of a main cable: ``segments`` straight pieces whose joints lie on the parabola.

    Parameters
    ----------
    sag
        Sag of the main span, m (below the tower saddles).
    main_span
        The main span, m; 0 when this scope is the main span. The span's own sag is
        ``sag (sx / main_span)^2``.
    drop_left, drop_right
        Depth of each support below the scope's top, m.
    side_span
        Each of the bridge's two side spans, m (0: a single span), for the sizing.
    diameter
        Cable diameter, m; 0 (default) sizes it with the cable model from the layout and the
        loading (the governing diameter of the whole cable, main and side spans).
    lanes, tracks, cables, golden_factor, safety_factor
        The loading, as the attrs of rules/suspension_bridge.grammar.
    segments
        Straight pieces along the span (at least 2). A piece's centroid lies ``f_s / segments^2``
        above the parabola (the chord's midpoint offset).
    sides
        Sides of the polygonal cross-section (at least 3), inscribed in the diameter.
    """
    span, top, own_sag = _span_geometry("cable", scope, main_span, sag, (drop_left, drop_right))
    if segments < 2:
        raise GeometryError(f"primitive 'cable': segments {segments} must be at least 2")
    if sides < 3:
        raise GeometryError(f"primitive 'cable': sides {sides} must be at least 3")
    require_blocks("cable", segments, "segments")
    require_vertices("cable", (segments + 1) * sides, "segments x sides")
    if diameter <= 0:
        diameter = _sized_diameter(
            main_span=main_span if main_span > 0 else span,
            sag=sag,
            side_span=side_span,
            lanes=lanes,
            tracks=tracks,
            cables=cables,
            golden_factor=golden_factor,
            safety_factor=safety_factor,
        )
    radius = diameter / 2.0
    x = span * np.arange(segments + 1) / segments
    y = cable_height(x, span, own_sag, top, drop_left, drop_right)
    # Section in the plane x = const, counter-clockwise about +x (from +y towards +z).
    phi = 2.0 * np.pi * np.arange(sides) / sides
    section_y, section_z = radius * np.cos(phi), radius * np.sin(phi)
    pool = np.zeros(((segments + 1) * sides, 3))
    pool[:, 0] = np.repeat(x, sides)
    pool[:, 1] = np.repeat(y, sides) + np.tile(section_y, segments + 1)
    pool[:, 2] = scope.sz / 2.0 + np.tile(section_z, segments + 1)
    rings = [
        (list(range(k * sides, (k + 1) * sides)), list(range((k + 1) * sides, (k + 2) * sides)))
        for k in range(segments)
    ]
    return prism_blocks(scope, pool, rings, tags=("cable",))


@primitive("suspenders", scope_relative=True)
def suspenders(
    scope: Scope,
    *,
    sag: float = 0.0,
    main_span: float = 0.0,
    drop_left: float = 0.0,
    drop_right: float = 0.0,
    spacing: float = 15.0,
    width: float = 0.1,
    min_length: float = 1.0,
) -> list[Block]:
    """Vertical hangers from the deck (the scope's bottom) up to the cable's centreline.

    The span is cut into ``n = max(1, round(sx / spacing))`` equal panels and a hanger stands at
    each of the ``n - 1`` inner panel points, where the cable is at least ``min_length`` above
    the deck (near an anchorage the cable may come down to the deck).

    Parameters
    ----------
    sag, main_span, drop_left, drop_right
        The cable's curve, as for ``cable``.
    spacing
        Nominal distance between hangers, m.
    width
        Side of a hanger's square section, m.
    min_length
        Shortest hanger built, m.
    """
    span, top, own_sag = _span_geometry(
        "suspenders", scope, main_span, sag, (drop_left, drop_right)
    )
    if spacing <= 0 or width <= 0 or min_length <= 0:
        raise GeometryError(
            "primitive 'suspenders': spacing, width and min_length must be positive, got "
            f"{spacing:g}, {width:g}, {min_length:g} m"
        )
    require_blocks("suspenders", span / spacing + 0.5, "span / spacing")
    panels = max(1, round(span / spacing))
    x = span * np.arange(1, panels) / panels
    y = cable_height(x, span, own_sag, top, drop_left, drop_right)
    keep = y >= min_length
    x, y = x[keep], y[keep]
    half, middle = width / 2.0, scope.sz / 2.0
    # Square section counter-clockwise about +y (seen from above: x right, z towards the viewer).
    corners = np.array([[-half, -half], [-half, half], [half, half], [half, -half]])
    pool = np.zeros((len(x) * 8, 3))
    for k, (xk, yk) in enumerate(zip(x, y, strict=True)):
        base = k * 8
        pool[base : base + 4, 0] = xk + corners[:, 0]
        pool[base : base + 4, 2] = middle + corners[:, 1]
        pool[base + 4 : base + 8, 0] = xk + corners[:, 0]
        pool[base + 4 : base + 8, 1] = yk
        pool[base + 4 : base + 8, 2] = middle + corners[:, 1]
    rings = [
        (list(range(8 * k, 8 * k + 4)), list(range(8 * k + 4, 8 * k + 8))) for k in range(len(x))
    ]
    return prism_blocks(scope, pool, rings, tags=("suspender",))
