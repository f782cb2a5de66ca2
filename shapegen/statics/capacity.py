"""Lateral capacity: the largest tilt at which an assembly still stands, towards given
directions or the worst one.

The figure is the load multiplier of :mod:`shapegen.statics.multiplier` (one linear program per
direction, ``tilt = atan(multiplier)``), then confirmed by the verdict of the tension-penalty
analysis itself (:func:`shapegen.statics.analysis.analyze` with the loads turned): the assembly
must stand half the resolution below the figure and not stand half the resolution above it.
Where the two disagree (a limit within the verdict's tolerance of the program's optimum), the
capacity is found by bisection on the verdict instead, so that what is reported always agrees
with ``analyze --tilt`` to :data:`~shapegen.tolerances.TILT_RESOLUTION_DEG`.

>>> from shapegen.model import Block, Model
>>> tall = Model([Block.box((0, 0, 0), (0.3, 1.0, 0.6))], friction=0.7)
>>> round(lateral_capacity(tall, azimuths=[0]).tilt, 2)     # tips over: atan(0.3 / 1.0)
16.7
"""

from __future__ import annotations

__all__ = ["Capacity", "lateral_capacity"]

import dataclasses
import math
import time
from collections.abc import Sequence
from dataclasses import dataclass, field

from shapegen.statics.analysis import analyze, contacts_and_bodies
from shapegen.statics.assembly import assemble
from shapegen.statics.multiplier import (
    SWEEP_DIRECTIONS,
    DirectionCapacity,
    load_multiplier,
    worst_direction,
)
from shapegen.statics.standins import statics_model
from shapegen.statics.statics_options import StaticsOptions, checked_azimuth
from shapegen.tolerances import DEFAULT as DEFAULT_TOLERANCES
from shapegen.tolerances import TIE_REL, TILT_RESOLUTION_DEG, at_most

# Tilts are judged below this: a multiplier of tan(89.95 deg) = 1146 is as far as a tilt goes.
_HIGHEST_TILT = 90.0 - TILT_RESOLUTION_DEG


@dataclass
class Capacity:
    """The lateral capacity of an assembly.

    Attributes
    ----------
    directions
        One entry per direction, in order of azimuth: the ones asked for, or the sweep and the
        worst direction it led to.
    worst
        The direction of least capacity among them (None when the assembly does not stand
        upright).
    swept
        True when the directions are a sweep (no azimuth was given).
    stands_upright
        The verdict without a tilt; every capacity is None without it.
    seconds
        Time spent, s.
    """

    directions: list[DirectionCapacity]
    worst: DirectionCapacity | None
    swept: bool
    stands_upright: bool
    seconds: float = 0.0
    options: StaticsOptions = field(default_factory=StaticsOptions, repr=False)

    @property
    def tilt(self) -> float | None:
        """The worst direction's critical tilt, degrees (None when it does not stand upright)."""
        return self.worst.tilt if self.worst is not None else None

    @property
    def multiplier(self) -> float | None:
        """``tan`` of :attr:`tilt`: the horizontal load, as a fraction of the weight, that the
        assembly carries in its worst direction (inf when unbounded)."""
        if self.worst is None or self.worst.tilt is None:
            return None
        return math.inf if self.worst.status == "unbounded" else max(self.worst.multiplier, 0.0)

    def to_report(self) -> dict:
        """The ``capacity`` object of a report (plain JSON values)."""
        worst = self.worst.to_report() if self.worst is not None else None
        return {
            "tilt_deg": self.tilt,
            "load_multiplier": worst["load_multiplier"] if worst else None,
            "azimuth_deg": worst["azimuth_deg"] if worst else None,
            "stands_upright": bool(self.stands_upright),
            "directions": [d.to_report() for d in self.directions],
            "sweep": bool(self.swept),
            "resolution_deg": TILT_RESOLUTION_DEG,
            "method": "load-multiplier program, checked by the verdict",
            "seconds": float(self.seconds),
        }


def lateral_capacity(
    model,
    options: StaticsOptions | None = None,
    azimuths: Sequence[float] | None = None,
    *,
    interfaces=None,
    check: bool = True,
    directions: int = SWEEP_DIRECTIONS,
    bodies=None,
) -> Capacity:
    """The largest tilt at which ``model`` stands, towards each of ``azimuths`` (degrees from +x
    towards +z), or over a sweep of ``directions`` directions and the worst of them when
    ``azimuths`` is None or empty.

    The capacity is measured from upright whatever tilt ``options`` carry; their friction,
    pyramid, kern and solver apply (the program itself is solved by Clarabel, or by cvxpy with
    ``solver="cvxpy"``).

    Raises
    ------
    StaticsError
        For a model whose loads are not all vertical (the tilt is then not a horizontal load
        multiplier; :func:`shapegen.statics.tilt.load_direction_problem`), and for the checks
        of :func:`shapegen.statics.checks.check_model`.
    """
    started = time.perf_counter()
    options = dataclasses.replace(options or StaticsOptions(), tilt=0.0, azimuth=None)
    model = statics_model(model)  # leaves kept as drawn stand in, as in analyze
    size = float(model.size)
    interfaces, bodies = contacts_and_bodies(
        model, options, DEFAULT_TOLERANCES.for_size(size), interfaces=interfaces,
        bodies=bodies, check=check,
    )  # fmt: skip
    problem = assemble(
        model, interfaces, friction=options.friction, pyramid=options.pyramid,
        kern=options.kern, length=size, bodies=None if bodies.trivial else bodies,
    )  # fmt: skip
    solver = "cvxpy" if options.solver == "cvxpy" else "clarabel"

    def stands(tilt: float, azimuth: float) -> bool:
        tilted = dataclasses.replace(options, tilt=tilt, azimuth=azimuth)
        return analyze(model, tilted, interfaces=interfaces, bodies=bodies, check=False).feasible

    swept = not azimuths
    upright = analyze(model, options, interfaces=interfaces, bodies=bodies, check=False).feasible
    if not upright:  # no capacity in any direction: nothing to solve
        computed = [
            DirectionCapacity(a, math.nan, "not_upright", "verdict", True)
            for a in dict.fromkeys(checked_azimuth(a) for a in azimuths or ())
        ]
        return Capacity(computed, None, swept, False, time.perf_counter() - started, options)
    if swept:
        worst, computed = worst_direction(model, problem, directions=directions, solver=solver)
        if all(c.azimuth != worst.azimuth for c in computed):
            computed = [*computed, worst]
        checked_azimuths = {worst.azimuth}
    else:
        computed = [
            load_multiplier(model, problem, azimuth, solver=solver)
            for azimuth in dict.fromkeys(checked_azimuth(a) for a in azimuths)
        ]
        checked_azimuths = {c.azimuth for c in computed}
    computed = [_confirmed(c, stands) if c.azimuth in checked_azimuths else c for c in computed]
    computed.sort(key=lambda c: c.azimuth)
    # the sweep's worst direction (checked), or the least of the directions asked for
    candidates = [c for c in computed if c.azimuth in checked_azimuths]
    least = min(c.tilt if c.tilt is not None else math.inf for c in candidates)
    worst = min(
        (
            c
            for c in candidates
            if at_most(c.tilt if c.tilt is not None else math.inf, least, TIE_REL)
        ),
        key=lambda c: c.azimuth,
    )
    return Capacity(computed, worst, swept, True, time.perf_counter() - started, options)


def _confirmed(capacity: DirectionCapacity, stands) -> DirectionCapacity:
    """``capacity`` checked against the verdict half a resolution either side, or found by
    bisection on the verdict when the two disagree."""
    start = time.perf_counter()
    half = TILT_RESOLUTION_DEG / 2
    azimuth = capacity.azimuth
    if capacity.status == "unbounded":
        if stands(_HIGHEST_TILT, azimuth):
            return dataclasses.replace(capacity, checked=True)
    elif capacity.status == "limit":
        tilt = capacity.tilt
        below, above = max(tilt - half, 0.0), tilt + half
        if stands(below, azimuth) and (above >= _HIGHEST_TILT or not stands(above, azimuth)):
            return dataclasses.replace(capacity, checked=True)
    elif capacity.status == "failed":
        pass
    else:  # the verdict stands upright where the program found no upright equilibrium
        if not stands(half, azimuth):
            return dataclasses.replace(capacity, status="limit", multiplier=0.0, checked=True)
    tilt = _bisect(lambda t: stands(t, azimuth), 0.0, _HIGHEST_TILT, TILT_RESOLUTION_DEG)
    seconds = capacity.seconds + time.perf_counter() - start
    if tilt is None:
        return DirectionCapacity(azimuth, math.inf, "unbounded", "bisection", True, seconds)
    return DirectionCapacity(
        azimuth, math.tan(math.radians(tilt)), "limit", "bisection", True, seconds
    )


def _bisect(stands, low: float, high: float, resolution: float) -> float | None:
    """The tilt where ``stands`` turns false, to ``resolution`` (the middle of the last
    bracket), given ``stands(low)``; None when it still stands at ``high``."""
    if stands(high):
        return None
    while high - low > resolution:
        middle = 0.5 * (low + high)
        if stands(middle):
            low = middle
        else:
            high = middle
    return 0.5 * (low + high)
