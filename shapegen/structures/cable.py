"""Suspension-bridge cables as a structure: the cable model of Patow 2012.

The rule file computes the bridge's layout and hands the cable model what it needs through its
start rule's annotation::

    @Structure("cable", main_span = main_span, sag = sag, side_span = side_span,
               lanes = lanes, tracks = tracks, cables = cables,
               golden_factor = golden_factor, safety_factor = safety_factor,
               max_cable_diameter = max_cable_diameter)

The design stands when the governing cable diameter is at most ``max_cable_diameter``; the
measure is the squared relative excess ``max(0, d / d_max - 1)^2``. Its square root is affine in
``d`` above the limit, so a derivative-free search on it follows the paper's search on the
diameter itself. The verdict needs no geometry: a search judges a bridge from these arguments
alone and builds the model once, at the end. With a margin the limit is ``(1 - margin) d_max``.
"""

from __future__ import annotations

__all__ = ["CableModel"]

import math

from shapegen.errors import GeometryError, OptionError
from shapegen.statics.cables import GOLDEN_FACTOR, SAFETY_FACTOR, bridge_cables
from shapegen.statics.statics_options import Reserve
from shapegen.structures.base import (
    Assessment,
    Design,
    Structure,
    StructureArgument,
    figure_text,
)
from shapegen.structures.registry import register_structure
from shapegen.tolerances import ROUNDOFF_REL


@register_structure
class CableModel(Structure):
    """Main cables sized by their peak tension against the largest acceptable diameter."""

    name = "cable"
    description = "suspension-bridge main cables sized by their peak tension (Patow 2012)"
    measure_name = "(d/d_max - 1)²"
    fails_as = "cables too thick"
    needs_model = False
    arguments = {
        "main_span": StructureArgument("each main span, tower to tower, m"),
        "sag": StructureArgument("sag of the main span below the saddles, m"),
        "side_span": StructureArgument("each of the two side spans, m", 0.0),
        "lanes": StructureArgument("road lanes over all decks"),
        "tracks": StructureArgument("railway tracks (each loads like a lane)", 0),
        "cables": StructureArgument("main cables sharing the load", 2),
        "golden_factor": StructureArgument("deck mass per metre and lane, kg/m", GOLDEN_FACTOR),
        "safety_factor": StructureArgument("breaking strength over peak tension", SAFETY_FACTOR),
        "max_cable_diameter": StructureArgument("largest acceptable cable diameter, m"),
        "min_span": StructureArgument(
            "shortest acceptable main span (the shores' distance), m", 0.0
        ),
    }

    @classmethod
    def summary(cls, section):
        return [
            (
                "cable diameter",
                f"{figure_text(section.get('cable_diameter'))} m (allowed"
                f" {figure_text(section.get('allowed_diameter'))} m, governing:"
                f" {section.get('governing')})",
            ),
            ("max tension", f"{figure_text(section.get('max_tension'))} N per cable"),
            *super().summary(section),
        ]

    @classmethod
    def panel(cls, section):
        def metres(key: str, digits: int) -> str:
            return f"{section[key]:.{digits}f} m"

        def millimetres(key: str) -> str:
            return f"{section[key] * 1000:.0f} mm"

        tension = float(section["max_tension"])
        return {
            "title": "Cable sizing",
            "rows": [
                ["main span", metres("main_span", 1)],
                ["sag", metres("sag", 1)],
                ["cable diameter", millimetres("cable_diameter")],
                ["allowed", millimetres("allowed_diameter")],
                ["governed by", str(section["governing"])],
                ["largest cable tension", f"{tension / 1e3:.4g} kN" if abs(tension) >= 1e3
                 else f"{tension:.4g} N"],
            ],
        }  # fmt: skip

    def assess(self, design: Design, *, margin: Reserve | float = 0.0) -> Assessment:
        margin = Reserve.of(margin)
        values = self.checked_arguments(design.arguments)
        limit = values.pop("max_cable_diameter")
        min_span = values.pop("min_span")
        if isinstance(limit, bool) or not isinstance(limit, int | float) or not limit > 0:
            raise OptionError(f"max_cable_diameter must be a positive length, got {limit!r}")
        numbers = {}
        for name, value in values.items():
            if isinstance(value, bool) or not isinstance(value, int | float):
                raise OptionError(f"@Structure('cable') argument {name!r} must be a number")
            numbers[name] = value
        if isinstance(min_span, bool) or not isinstance(min_span, int | float):
            raise OptionError("@Structure('cable') argument 'min_span' must be a number")
        if numbers["main_span"] < min_span * (1.0 - ROUNDOFF_REL):
            raise GeometryError(
                f"main_span {numbers['main_span']:g} m is shorter than min_span {min_span:g} m"
                " (the distance between the shores)"
            )
        sizing = bridge_cables(**numbers)
        allowed = float(limit) * (1.0 - margin)
        excess = sizing.diameter / allowed - 1.0
        stands = sizing.diameter <= allowed
        section = {
            "main_span": sizing.main_span,
            "sag": sizing.sag,
            "side_span": sizing.side_span,
            "cable_diameter": sizing.diameter,
            "main_span_diameter": sizing.main_span_diameter,
            "side_span_diameter": sizing.side_span_diameter,
            "governing": sizing.governing,
            "cable_area": sizing.area,
            "max_tension": sizing.max_tension,
            "horizontal_tension": sizing.horizontal_tension,
            "load_per_metre": sizing.load_per_metre,
            "max_cable_diameter": float(limit),
            "allowed_diameter": allowed,
        }
        return Assessment(
            structure=self.name,
            stands=bool(stands),
            measure=0.0 if stands else (excess**2 if math.isfinite(excess) else math.inf),
            status="optimal",
            section=section,
            detail=sizing,
            margin=margin,
        )
