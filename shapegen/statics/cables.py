"""Main cables of a suspension bridge: load, shape, peak tension and cross-section.

The model of Patow 2012 ("Procedural Modeling of Suspension Bridges"): the deck's weight is a load
``w`` per horizontal metre proportional to the number of lanes, the main cables hang as parabolas
(a catenary is available as an option), and each cable's cross-section is the area of galvanized
bridge strand whose breaking strength is ``safety_factor`` times the cable's peak tension.

Units are SI throughout (m, kg, N, m^2). The strand strength is published in US customary units
(short tons-force per square inch); it is converted once, exactly, in
:data:`STRAND_BREAKING_STRESS`.
docs/bridges.md gives the formulas, the treatment of the side spans and the reproduction of the
paper's Table 2.
"""

from __future__ import annotations

__all__ = [
    "CABLE_SHAPES",
    "GOLDEN_FACTOR",
    "GRAVITY",
    "INCH",
    "POUND_FORCE",
    "SAFETY_FACTOR",
    "SHORT_TON_FORCE",
    "STRAND_BREAKING_STRENGTH",
    "STRAND_BREAKING_STRESS",
    "BridgeLoading",
    "CableSizing",
    "SpanCable",
    "bridge_cables",
    "cable_area",
    "catenary_parameter",
    "round_cable_diameter",
    "size_cables",
]

import math
from dataclasses import dataclass

import numpy as np

from shapegen.errors import GeometryError, StaticsError
from shapegen.model.model import STANDARD_GRAVITY
from shapegen.tolerances import ROUNDOFF_REL

# Solver setting: brentq's absolute tolerance on a cable's half angle (radians).
_HALF_ANGLE_XTOL = 1e-15

GOLDEN_FACTOR = 5300.0
"""Deck mass carried by the cables per metre of bridge and per lane (kg/m per lane)."""

SAFETY_FACTOR = 3.0
"""Ratio of the strand's breaking strength to the cable's peak tension (dimensionless)."""

GRAVITY = STANDARD_GRAVITY
"""Acceleration of gravity (m/s^2), the project's value."""

POUND_FORCE = 4.4482216152605
"""One pound-force in newtons (exact by definition: 0.45359237 kg x 9.80665 m/s^2)."""

INCH = 0.0254
"""One inch in metres (exact by definition)."""

SHORT_TON_FORCE = 2000.0 * POUND_FORCE
"""One short ton-force (2 000 lbf) in newtons."""

STRAND_BREAKING_STRENGTH = 76.669
"""Galvanized bridge strand: breaking strength in short tons-force per square inch of area."""

STRAND_BREAKING_STRESS = STRAND_BREAKING_STRENGTH * SHORT_TON_FORCE / INCH**2
"""The same breaking strength in pascals (N/m^2), about 1.057 GPa."""

CABLE_SHAPES = ("parabola", "catenary")
"""The cable shapes :class:`SpanCable` knows."""


def catenary_parameter(span: float, sag: float) -> float:
    """The parameter ``a`` (m) of the catenary ``y = a (cosh(x / a) - 1)`` with this span and sag.

    Solves ``sag = a (cosh(span / (2 a)) - 1)`` for ``a`` with Brent's method.

    Parameters
    ----------
    span
        Horizontal distance between the two supports, m (> 0).
    sag
        Depth of the lowest point below the supports, m (> 0).

    Returns
    -------
    float
        ``a`` in metres; the horizontal tension is ``a`` times the load per metre of cable.
    """
    ratio = sag / span
    # With u = span / (2 a) the sag ratio is sinh(u/2)^2 / u, which rises from 0 without bound
    # and is at least u / 4, so the root lies below 4 * ratio + 1; the sinh form keeps full
    # precision for the tiny u of a flat cable, where cosh(u) - 1 would cancel.
    from scipy.optimize import brentq  # loaded when a cable is sized

    half_angle = brentq(
        lambda u: math.sinh(u / 2.0) ** 2 / u - ratio,
        ROUNDOFF_REL * ratio,
        4.0 * ratio + 1.0,
        xtol=_HALF_ANGLE_XTOL,
        rtol=4.0 * np.finfo(float).eps,
    )
    return span / (2.0 * half_angle)


@dataclass(frozen=True)
class SpanCable:
    """One cable span hanging between two supports at the same height.

    ``x`` is measured horizontally from the midspan (the lowest point), ``y`` upwards from the
    lowest point, so the supports are at ``x = +-span / 2``, ``y = sag``.

    Attributes
    ----------
    span
        Horizontal distance ``K`` between the supports, m.
    sag
        Depth ``f`` of the lowest point below the supports, m.
    load
        ``w``: for the parabola, the load per horizontal metre (N/m); for the catenary, the load
        per metre along the cable (N/m), the catenary's defining assumption.
    shape
        ``"parabola"`` (default, the paper's model) or ``"catenary"``.
    """

    span: float
    sag: float
    load: float
    shape: str = "parabola"

    def __post_init__(self) -> None:
        if self.shape not in CABLE_SHAPES:
            raise GeometryError(
                f"cable shape {self.shape!r} is not one of {', '.join(CABLE_SHAPES)}"
            )
        if not (math.isfinite(self.span) and self.span > 0.0):
            raise GeometryError(f"cable span must be a positive length in metres, got {self.span}")
        if not (math.isfinite(self.sag) and self.sag > 0.0):
            raise GeometryError(f"cable sag must be a positive length in metres, got {self.sag}")
        if not (math.isfinite(self.load) and self.load > 0.0):
            raise StaticsError(f"cable load must be a positive force per metre, got {self.load}")

    @property
    def sag_ratio(self) -> float:
        """``n = f / K`` (dimensionless)."""
        return self.sag / self.span

    @property
    def catenary_parameter(self) -> float:
        """``a = H / w`` (m) for either shape; for the parabola ``K^2 / (8 f)``."""
        if self.shape == "catenary":
            return catenary_parameter(self.span, self.sag)
        return self.span**2 / (8.0 * self.sag)

    @property
    def horizontal_tension(self) -> float:
        """``H`` (N), the same at every point of the cable: ``w K^2 / (8 f)`` for the parabola."""
        return self.load * self.catenary_parameter

    @property
    def max_tension(self) -> float:
        """Peak tension (N), at the supports.

        Parabola: ``H sqrt(1 + (4 f / K)^2)``. Catenary: ``H cosh(K / (2 a)) = w (a + f)``.
        """
        if self.shape == "catenary":
            return self.load * (self.catenary_parameter + self.sag)
        return self.horizontal_tension * math.sqrt(1.0 + (4.0 * self.sag_ratio) ** 2)

    @property
    def length(self) -> float:
        """Cable length (m) between the supports.

        Parabola: the paper's series ``K (1 + 8/3 n^2)``, accurate to ``O(n^4)``; see
        :attr:`exact_length` for the closed form. Catenary: ``2 a sinh(K / (2 a))``.
        """
        if self.shape == "catenary":
            return self.exact_length
        return self.span * (1.0 + 8.0 / 3.0 * self.sag_ratio**2)

    @property
    def exact_length(self) -> float:
        """Cable length (m) from the closed-form arc length of the shape."""
        if self.shape == "catenary":
            a = self.catenary_parameter
            return 2.0 * a * math.sinh(self.span / (2.0 * a))
        support_slope = 4.0 * self.sag_ratio
        return (
            self.span
            / 2.0
            * (math.sqrt(1.0 + support_slope**2) + math.asinh(support_slope) / support_slope)
        )

    def height(self, x: float | np.ndarray) -> float | np.ndarray:
        """Height ``y`` (m) of the cable above its lowest point at horizontal position ``x`` (m).

        Parabola: ``w x^2 / (2 H)``; catenary: ``a (cosh(x / a) - 1)``.
        """
        x = np.asarray(x, dtype=float)
        a = self.catenary_parameter
        if self.shape == "catenary":
            return 2.0 * a * np.sinh(x / (2.0 * a)) ** 2
        return x**2 / (2.0 * a)

    def slope(self, x: float | np.ndarray) -> float | np.ndarray:
        """``tan(phi) = dy/dx`` (dimensionless) at ``x`` (m): ``8 f x / K^2`` for the parabola."""
        x = np.asarray(x, dtype=float)
        a = self.catenary_parameter
        if self.shape == "catenary":
            return np.sinh(x / a)
        return x / a


@dataclass(frozen=True)
class BridgeLoading:
    """What the main cables of a bridge carry, and the rules for sizing them.

    Attributes
    ----------
    lanes
        Road lanes over all decks.
    tracks
        Railway tracks; each counts as one lane.
    cables
        Number of main cables sharing the load.
    golden_factor
        Deck mass per metre of bridge and per effective lane, kg/m.
    safety_factor
        Breaking strength over peak tension (dimensionless).
    gravity
        m/s^2.
    shape
        ``"parabola"`` or ``"catenary"`` (see :class:`SpanCable`).
    """

    lanes: int
    tracks: int = 0
    cables: int = 2
    golden_factor: float = GOLDEN_FACTOR
    safety_factor: float = SAFETY_FACTOR
    gravity: float = GRAVITY
    shape: str = "parabola"

    def __post_init__(self) -> None:
        if self.lanes < 0 or self.tracks < 0 or self.lanes + self.tracks < 1:
            raise StaticsError(
                f"a bridge needs at least one lane or track, got lanes={self.lanes}, "
                f"tracks={self.tracks}"
            )
        if self.cables < 1:
            raise StaticsError(f"a bridge needs at least one main cable, got cables={self.cables}")
        for name in ("golden_factor", "safety_factor", "gravity"):
            value = getattr(self, name)
            if not (math.isfinite(value) and value > 0.0):
                raise StaticsError(f"bridge {name} must be positive, got {value}")
        if self.shape not in CABLE_SHAPES:
            raise StaticsError(
                f"cable shape {self.shape!r} is not one of {', '.join(CABLE_SHAPES)}"
            )

    @property
    def effective_lanes(self) -> int:
        """Lanes plus tracks."""
        return self.lanes + self.tracks

    @property
    def load_per_metre(self) -> float:
        """Total deck load ``w`` (N per horizontal metre) shared by all the cables."""
        return self.golden_factor * self.effective_lanes * self.gravity

    @property
    def load_per_cable(self) -> float:
        """The share of ``w`` one cable carries (N/m)."""
        return self.load_per_metre / self.cables


def cable_area(max_tension: float, safety_factor: float = SAFETY_FACTOR) -> float:
    """Cross-section (m^2) of bridge strand that breaks at ``safety_factor * max_tension``.

    Parameters
    ----------
    max_tension
        Peak tension of one cable, N.
    safety_factor
        Dimensionless.

    Returns
    -------
    float
        Metallic area in m^2 (``T_break = 76.669 A`` in short tons-force and square inches).
    """
    return safety_factor * max_tension / STRAND_BREAKING_STRESS


def round_cable_diameter(area: float | np.ndarray) -> float | np.ndarray:
    """Diameter (m) of a solid round cable of cross-section ``area`` (m^2): ``sqrt(4 A / pi)``."""
    return np.sqrt(4.0 * np.asarray(area, dtype=float) / np.pi)


@dataclass(frozen=True)
class CableSizing:
    """Main cables sized for one choice of main span and sag. Tensions and areas are per cable.

    Attributes
    ----------
    main_span, sag
        The main span ``K`` and its sag ``f``, m.
    side_span, side_sag
        Each of the two side spans and its sag, m (0 when the main span is the whole length).
    load_per_metre
        Total deck load ``w`` shared by the cables, N per horizontal metre.
    horizontal_tension
        ``H`` of one cable, N; the same in the main and side spans.
    main_span_tension, side_span_tension
        Peak tension of one cable in the main span and in a side span, N.
    main_span_area, side_span_area
        The strand area those tensions need, m^2.
    main_span_diameter
        Diameter for the main span alone (the paper's ``D_direct``), m.
    side_span_diameter
        Diameter for a side span alone, m.
    governing
        ``"main"`` or ``"side"``: which span sizes the cable.
    """

    main_span: float
    sag: float
    side_span: float
    side_sag: float
    load_per_metre: float
    horizontal_tension: float
    main_span_tension: float
    side_span_tension: float
    main_span_area: float
    side_span_area: float
    main_span_diameter: float
    side_span_diameter: float
    governing: str

    @property
    def max_tension(self) -> float:
        """Governing peak tension of one cable, N."""
        return max(self.main_span_tension, self.side_span_tension)

    @property
    def area(self) -> float:
        """Governing cross-section of one cable, ``max(A(main), A(side))``, m^2."""
        return max(self.main_span_area, self.side_span_area)

    @property
    def diameter(self) -> float:
        """Diameter of the governing cross-section, m."""
        return max(self.main_span_diameter, self.side_span_diameter)


def size_cables(
    loading: BridgeLoading, main_span: float, sag: float, length: float | None = None
) -> CableSizing:
    """Size the main cables of a three-span suspension bridge.

    The main span hangs between the two towers; the rest of ``length`` is split into two equal
    side spans, tower to anchorage. Each side-span cable carries the same load per metre and the
    same horizontal tension ``H`` as the main span (the towers take no horizontal force), so it is
    an arc of the same curve: its sag is the main curve's height at half the side span, for the
    parabola ``f_s = f (K_s / K)^2``. The cable is sized by the larger of the two areas.

    Parameters
    ----------
    loading
        Lanes, tracks, cables and sizing rules.
    main_span
        Distance between the towers ``K``, m.
    sag
        Main-span sag ``f`` (height of the tower tops above the lowest point of the cable), m.
    length
        Total length between the anchorages, m; ``None`` (or ``main_span``) for a single span.

    Returns
    -------
    CableSizing
    """
    main = SpanCable(main_span, sag, loading.load_per_cable, loading.shape)
    if length is None:
        length = main_span
    if not math.isfinite(length) or length < main_span * (1.0 - ROUNDOFF_REL):
        raise GeometryError(f"bridge length {length} m is shorter than its main span {main_span} m")
    side_span = max(length - main_span, 0.0) / 2.0
    main_tension = main.max_tension
    main_area = cable_area(main_tension, loading.safety_factor)
    side_sag = side_tension = side_area = 0.0
    if side_span > 0.0:
        side_sag = float(main.height(side_span / 2.0))
        side = SpanCable(side_span, side_sag, loading.load_per_cable, loading.shape)
        side_tension = side.max_tension
        side_area = cable_area(side_tension, loading.safety_factor)
    diameters = round_cable_diameter(np.array([main_area, side_area]))
    return CableSizing(
        main_span=float(main_span),
        sag=float(sag),
        side_span=side_span,
        side_sag=side_sag,
        load_per_metre=loading.load_per_metre,
        horizontal_tension=main.horizontal_tension,
        main_span_tension=main_tension,
        side_span_tension=side_tension,
        main_span_area=main_area,
        side_span_area=side_area,
        main_span_diameter=float(diameters[0]),
        side_span_diameter=float(diameters[1]),
        governing="side" if side_area > main_area else "main",
    )


def bridge_cables(
    *,
    main_span: float,
    sag: float,
    lanes: int,
    side_span: float = 0.0,
    tracks: int = 0,
    cables: int = 2,
    golden_factor: float = GOLDEN_FACTOR,
    safety_factor: float = SAFETY_FACTOR,
) -> CableSizing:
    """Size the main cables of a bridge laid out by its rule file: one main span of
    ``main_span`` between two side spans of ``side_span`` (every main span of a bridge with
    several hangs alike, so one of them sizes the cable).

    The suspension-bridge rule set calls this twice with the same values: the cable primitive to
    draw the section, the cable structure to judge the design; both get what the grammar
    computed, so the geometry and the verdict agree.

    Raises
    ------
    GeometryError, StaticsError
        Naming the input, for a span, sag or loading that cannot be sized.
    """
    for name, value in (("main_span", main_span), ("sag", sag)):
        if not (math.isfinite(value) and value > 0):
            raise GeometryError(f"cable {name} must be a positive length in metres, got {value:g}")
    if not (math.isfinite(side_span) and side_span >= 0):
        raise GeometryError(
            f"side_span {side_span:g} m: the main spans are longer than the bridge (each side"
            " span must be 0 m or more); shorten main_span or lengthen the bridge"
        )
    if sag >= main_span / 2.0:
        raise GeometryError(
            f"cable sag {sag:g} m must be less than half the main span ({main_span / 2.0:g} m)"
        )
    for name, value in (("lanes", lanes), ("tracks", tracks), ("cables", cables)):
        if value != int(value):
            raise StaticsError(f"bridge {name} must be a whole number, got {value!r}")
    loading = BridgeLoading(
        lanes=int(lanes),
        tracks=int(tracks),
        cables=int(cables),
        golden_factor=float(golden_factor),
        safety_factor=float(safety_factor),
    )
    return size_cables(loading, main_span, sag, length=main_span + 2.0 * side_span)
