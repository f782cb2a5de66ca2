"""Search for the main span and sag of a suspension bridge (Patow 2012, Powell's method).

The designer gives the bridge's length, its lanes, tracks and cables, the shortest acceptable main
span (the distance between the shores) and the largest acceptable cable diameter. Powell's method
moves the main span and the sag to shrink the governing cable diameter of
:func:`shapegen.statics.cables.size_cables`, and, as in the paper, stops at the first evaluation
whose diameter is under the maximum: the answer is the first acceptable design met on the way,
not the thinnest cable possible.
"""

from __future__ import annotations

__all__ = ["BridgeSearchResult", "search_span_and_sag"]

import math
from dataclasses import dataclass

import numpy as np
from scipy.optimize import minimize

from shapegen.errors import GeometryError
from shapegen.statics.cables import BridgeLoading, CableSizing, size_cables

MIN_SAG_RATIO = 1e-3
"""Lower bound of the sag ratio f / K (dimensionless), far flatter than any real cable."""

MAX_SAG_RATIO = 0.5 * (1.0 - 1e-9)
"""Upper bound of the sag ratio: the paper's sag < span / 2, kept strict."""


@dataclass(frozen=True)
class BridgeSearchResult:
    """Outcome of :func:`search_span_and_sag`.

    Attributes
    ----------
    span
        Main span found, m.
    sag
        Main-span sag found, m.
    diameter
        Governing cable diameter at that design, m.
    iterations
        Powell iterations begun, the one in which the search stopped included.
    evaluations
        Cable sizings evaluated.
    stopped_early
        True when the search stopped at the first design whose diameter is under the maximum.
    converged
        True when Powell's method met its own convergence test (then no design under the
        maximum was met, and ``span``, ``sag`` are its best point).
    sizing
        The full cable sizing at ``span``, ``sag``.
    message
        One line saying how the search ended.
    """

    span: float
    sag: float
    diameter: float
    iterations: int
    evaluations: int
    stopped_early: bool
    converged: bool
    sizing: CableSizing
    message: str


class _AcceptableDesign(Exception):
    """Raised from the objective to stop Powell's method at the first acceptable design."""


def search_span_and_sag(
    loading: BridgeLoading,
    *,
    length: float,
    min_span: float,
    max_diameter: float,
    initial_span: float | None = None,
    initial_sag_ratio: float = 0.1,
    max_sag_ratio: float = MAX_SAG_RATIO,
    xtol: float = 1e-4,
    ftol: float = 1e-6,
    max_evaluations: int = 2000,
    main_spans: int = 1,
) -> BridgeSearchResult:
    """Find a main span and sag whose cables are no thicker than ``max_diameter``.

    The search variables are ``span / length`` and the sag ratio ``n = sag / span``, both of order
    one; the paper's bounds ``min_span <= span <= length`` and ``0 < sag < span / 2`` then become
    a box, which Powell's method (``scipy.optimize.minimize(method="Powell", bounds=...)``)
    respects. The objective is the governing diameter (m).

    Parameters
    ----------
    loading
        Lanes, tracks, cables and sizing rules.
    length
        Bridge length between the anchorages, m; the longest possible main span.
    min_span
        Shortest acceptable main span (the distance between the shores), m.
    max_diameter
        Largest acceptable cable diameter, m.
    initial_span
        Starting main span, m; default ``length`` (the towers start at the ends of the bridge
        and the search moves them inwards).
    initial_sag_ratio
        Starting sag / span, dimensionless; default 1/10, the middle of the usual 1/8 to 1/12.
    max_sag_ratio
        Upper bound of sag / span, at most 1/2 (then kept just under it, as the paper's
        ``sag < span / 2``).
    xtol, ftol
        Powell's tolerances on the (dimensionless) variables and the relative change of the
        diameter.
    max_evaluations
        Limit on cable sizings.
    main_spans
        Number of equal main spans (towers - 1). With several, the main span is at most
        ``length / main_spans`` and the side spans share ``length - main_spans * span``; the
        cable is sized as for one main span between two such side spans (every main span
        hangs alike, and the towers balance the horizontal pulls).

    Returns
    -------
    BridgeSearchResult
    """
    if not (math.isfinite(length) and length > 0.0):
        raise GeometryError(f"bridge length must be a positive length in metres, got {length}")
    if int(main_spans) != main_spans or main_spans < 1:
        raise GeometryError(
            f"the number of main spans must be a whole number >= 1, got {main_spans}"
        )
    longest = length / main_spans
    if not (math.isfinite(min_span) and 0.0 < min_span <= longest * (1.0 + 1e-12)):
        raise GeometryError(
            f"minimum main span {min_span} m must be positive and at most the bridge length "
            f"{length} m" + (f" / {main_spans} main spans" if main_spans > 1 else "")
        )
    min_span = min(min_span, longest)
    if not (math.isfinite(max_diameter) and max_diameter > 0.0):
        raise GeometryError(f"maximum cable diameter must be positive, got {max_diameter} m")
    if initial_span is None:
        initial_span = longest
    if not min_span <= initial_span <= longest:
        raise GeometryError(
            f"initial main span {initial_span} m is outside [{min_span}, {longest}] m"
        )
    if not MIN_SAG_RATIO < max_sag_ratio <= 0.5:
        raise GeometryError(
            f"maximum sag ratio {max_sag_ratio} is outside ({MIN_SAG_RATIO}, 0.5]: the sag must "
            "stay under half the span"
        )
    max_sag_ratio = min(max_sag_ratio, MAX_SAG_RATIO)
    if not MIN_SAG_RATIO <= initial_sag_ratio <= max_sag_ratio:
        raise GeometryError(
            f"initial sag ratio {initial_sag_ratio} is outside [{MIN_SAG_RATIO}, {max_sag_ratio}]"
        )

    evaluations = 0
    iterations = 0
    first_acceptable: list[CableSizing] = []

    def design(x: np.ndarray) -> tuple[float, float]:
        span = float(np.clip(x[0], min_span / longest, 1.0)) * longest
        return span, span * float(np.clip(x[1], MIN_SAG_RATIO, max_sag_ratio))

    def sized(span: float, sag: float) -> CableSizing:
        # One main span with the side spans of the whole bridge on either side of it.
        return size_cables(loading, span, sag, length=max(length - (main_spans - 1) * span, span))

    def diameter(x: np.ndarray) -> float:
        nonlocal evaluations
        evaluations += 1
        sizing = sized(*design(x))
        if sizing.diameter < max_diameter:
            first_acceptable.append(sizing)
            raise _AcceptableDesign
        return sizing.diameter

    def count_iteration(xk: np.ndarray) -> None:
        nonlocal iterations
        iterations += 1

    start = np.array([initial_span / longest, initial_sag_ratio])
    bounds = [(min_span / longest, 1.0), (MIN_SAG_RATIO, max_sag_ratio)]
    try:
        outcome = minimize(
            diameter,
            start,
            method="Powell",
            bounds=bounds,
            callback=count_iteration,
            options={"xtol": xtol, "ftol": ftol, "maxfev": max_evaluations},
        )
    except _AcceptableDesign:
        sizing = first_acceptable[0]
        return BridgeSearchResult(
            span=sizing.main_span,
            sag=sizing.sag,
            diameter=sizing.diameter,
            iterations=iterations + 1,
            evaluations=evaluations,
            stopped_early=True,
            converged=False,
            sizing=sizing,
            message=(
                f"stopped at evaluation {evaluations}: diameter {sizing.diameter:.3f} m is "
                f"under the maximum {max_diameter:.3f} m"
            ),
        )
    sizing = sized(*design(outcome.x))
    state = "converged" if outcome.success else "did not converge"
    return BridgeSearchResult(
        span=sizing.main_span,
        sag=sizing.sag,
        diameter=sizing.diameter,
        iterations=int(outcome.nit),
        evaluations=evaluations,
        stopped_early=False,
        converged=bool(outcome.success),
        sizing=sizing,
        message=(
            f"{state} after {int(outcome.nit)} iterations without reaching the maximum "
            f"diameter {max_diameter:.3f} m; thinnest cable found {sizing.diameter:.3f} m"
        ),
    )
