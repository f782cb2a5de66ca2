"""Rigid-block statics as a structure: the tension-penalty QP of Whiting et al. 2009.

The measure is ``y / W^2``, the least sum of squared joint tensions that holds every block in
equilibrium, over the squared weight; zero exactly when the assembly stands with compression and
friction alone. A margin shrinks every joint about its centroid (the kern) to ``1 - margin`` of
its size; a tilt of the options (the tilting-table test) turns every load, towards a given
azimuth or the design's worst direction. The adjoint gradient of
:mod:`shapegen.statics.sensitivity` gives the measure's change. The lateral capacity is the
largest tilt at which the design stands (:mod:`shapegen.statics.capacity`).
"""

from __future__ import annotations

__all__ = ["BlockStatics"]

import math
import time
from collections.abc import Sequence

from shapegen.statics.statics_options import Reserve, StaticsOptions
from shapegen.structures.base import Assessment, Design, Structure, StructureArgument
from shapegen.structures.registry import register_structure
from shapegen.tolerances import DEFAULT as DEFAULT_TOLERANCES

# y / W^2 of the last design judged above which the next is judged QP first: five times what the
# QP can prove (QP_PROOF_FACTOR * PHASE_ONE_STOP ** 2 = 2e-6), as a step rarely divides y by five
EXPECT_TENSION_ABOVE = 1e-5


@register_structure
class BlockStatics(Structure):
    """Compression-only, frictional rigid blocks under their own weight and point loads."""

    name = "blocks"
    description = "rigid-block statics: compression-only frictional joints (Whiting et al. 2009)"
    measure_name = "y/W²"
    fails_as = "needs tension"
    options_type = StaticsOptions
    has_gradient = True
    has_capacity = True
    judges_blocks = True
    arguments = {
        "structural": StructureArgument(
            "labels or rule names of the blocks that are structure, separated by commas (the"
            " other blocks ride as load on the body they rest on); empty: every block",
            "",
        ),
        "ignore": StructureArgument(
            "labels or rule names of ornaments, separated by commas: they ride as load on the"
            " body they rest on, without being judged",
            "",
        ),
    }

    options: StaticsOptions
    _stood: tuple[Reserve, object] | None = None  # the last design that stood with a margin
    # margin, measure and analysis of the last design judged
    _last: tuple[Reserve, float, object] | None = None

    def __init__(self, options: StaticsOptions | None = None):
        super().__init__(options)
        # azimuths (degrees) in which designs judged so far fell at the tilt of the options
        self._directions: list[float] = []

    def _options(self, margin: Reserve | float, design: Design) -> StaticsOptions:
        from shapegen.statics.reserve import with_reserve

        # the reserve: joints shrunk and friction lowered (statics/reserve.py)
        options = with_reserve(self.options, margin, design.model.friction)
        # the structure the rule selects (@Structure's structural, ignore), unless the
        # command line selects one
        arguments = self.checked_arguments(design.arguments)
        return options.selecting(arguments["structural"] or None, arguments["ignore"] or None)

    def assess(self, design: Design, *, margin: Reserve | float = 0.0) -> Assessment:
        from shapegen.statics.analysis import analyze  # scipy loads when a design is judged
        from shapegen.statics.standins import statics_model

        margin = Reserve.of(margin)
        stood = self._stood if self._stood is not None and self._stood[0] >= margin else None
        model = statics_model(design.model)  # the same object analyze judges
        options = self._options(margin, design)
        if options.tilted and options.azimuth is None:
            analysis = self._towards_the_worst(model, options)
        else:
            # A search moves in small steps: after a design that needed clear tension the next
            # most likely needs some too, and the QP alone may prove it (expect_tension).
            last = self._last
            analysis = analyze(
                model,
                options,
                stood=stood[1] if stood is not None and stood[1].model is model else None,
                expect_tension=last is not None and last[0] == margin
                and last[1] >= EXPECT_TENSION_ABOVE,
                # the last design's forces start the solves where its joints are these
                warm_start=last[2] if last is not None and last[0] == margin else None,
            )  # fmt: skip
            self._last = (margin, float(analysis.infeasibility_normalized), analysis)
        if analysis.feasible and margin > 0:
            # A search judges with a reserve and reports without one: the forces that stand
            # with the reserve certify the design without another solve.
            self._stood = (margin, analysis)
        return _block_assessment(analysis, margin=margin)

    def reassess(
        self, design: Design, previous: Assessment | None, *, measure_follows: bool = False
    ) -> Assessment:
        # the contacts of unchanged blocks, and the last forces or multipliers as the proof of
        # the verdict, are carried over (statics/incremental.py); the verdict is the full one's
        from shapegen.statics.incremental import reanalyze

        options = self._options(0.0, design)
        if options.tilted and options.azimuth is None:
            return self.assess(design)
        last = previous.block_analysis if previous is not None else None
        if last is None or last.problem is None or last.problem.cache.get("options") != options:
            last = None
        analysis = reanalyze(design.model, options, last, measure_follows=measure_follows)
        return _incremental_assessment(analysis)

    def complete(self, assessment: Assessment) -> Assessment:
        from shapegen.statics.incremental import complete

        if not assessment.pending:
            return assessment
        return _incremental_assessment(complete(assessment.block_analysis))

    def measure_change(self, base: Assessment, moved: Design) -> float | None:
        from shapegen.statics.sensitivity import infeasibility_change

        # the base analysis knows the direction it was tilted towards
        return infeasibility_change(base.detail, moved.model, self._options(base.margin, moved))

    def lateral_capacity(self, design: Design, azimuths: Sequence[float] | None = None):
        from shapegen.statics.capacity import lateral_capacity

        return lateral_capacity(design.model, self._options(0.0, design), azimuths)

    def _towards_the_worst(self, model, options: StaticsOptions):
        """The analysis tilted towards the worst direction of ``model``.

        A search judges many designs: the directions earlier ones fell in are tried first (one
        analysis each); a design that stands in all of them gets the sweep for its own worst
        direction (:func:`~shapegen.statics.multiplier.worst_direction`), which joins them when
        the design falls there. So the search's measure is the largest ``y`` over the
        directions known so far, and a design is only called standing once its own worst
        direction has been checked: the verdict of ``analyze`` with the same tilt.
        """
        from shapegen.statics.analysis import analyze, contacts_and_bodies

        start = time.perf_counter()
        tol = DEFAULT_TOLERANCES.for_size(float(model.size))
        interfaces, bodies = contacts_and_bodies(model, options, tol)
        found = time.perf_counter() - start  # once for every direction: counted in the report
        falling = []
        for azimuth in self._directions:
            tried = analyze(
                model, options.towards(azimuth), interfaces=interfaces, bodies=bodies, check=False
            )
            if not tried.feasible:
                falling.append(tried)
        if falling:
            worst = max(falling, key=_infeasibility)
            worst.worst_direction = True
            worst.timings["interfaces"] += found
            return worst
        analysis = analyze(model, options, interfaces=interfaces, bodies=bodies, check=False)
        analysis.timings["interfaces"] += found
        azimuth = analysis.problem.azimuth if analysis.problem is not None else None
        if not analysis.feasible and azimuth is not None and azimuth not in self._directions:
            self._directions.append(azimuth)
        return analysis


def _infeasibility(analysis) -> float:
    value = analysis.infeasibility_normalized
    return math.inf if math.isnan(value) else value


def _incremental_assessment(analysis) -> Assessment:
    """The assessment (without a margin) of an analysis of ``reanalyze``, pending or not."""
    from shapegen.statics.incremental import pending

    return _block_assessment(analysis, pending=pending(analysis))


def _block_assessment(analysis, **extra) -> Assessment:
    """The assessment of a block analysis: its verdict, measure, status and report."""
    return Assessment(
        structure=BlockStatics.name,
        stands=bool(analysis.feasible),
        measure=float(analysis.infeasibility_normalized),
        status=analysis.status.value,
        section=analysis.to_report(),
        detail=analysis,
        block_analysis=analysis,
        **extra,
    )
