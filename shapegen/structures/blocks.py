"""Rigid-block statics as a structure: the tension-penalty QP of Whiting et al. 2009.

The measure is ``y / W^2``, the least sum of squared joint tensions that holds every block in
equilibrium, over the squared weight; zero exactly when the assembly stands with compression and
friction alone. A margin shrinks every joint about its centroid (the kern) to ``1 - margin`` of
its size. The adjoint gradient of :mod:`shapegen.statics.sensitivity` gives the measure's change.
"""

from __future__ import annotations

__all__ = ["BlockStatics"]

from shapegen.statics.analysis import analyze
from shapegen.statics.options import StaticsOptions
from shapegen.statics.sensitivity import infeasibility_change
from shapegen.structures.base import Assessment, Design, Structure
from shapegen.structures.registry import register_structure


@register_structure
class BlockStatics(Structure):
    """Compression-only, frictional rigid blocks under their own weight and point loads."""

    name = "blocks"
    description = "rigid-block statics: compression-only frictional joints (Whiting et al. 2009)"
    measure_name = "y/W²"
    options_type = StaticsOptions
    has_gradient = True

    options: StaticsOptions
    _stood: tuple[float, object] | None = None  # the last design that stood with a margin

    def _options(self, margin: float) -> StaticsOptions:
        return self.options.shrunk(margin) if margin > 0 else self.options

    def assess(self, design: Design, *, margin: float = 0.0) -> Assessment:
        margin = self.checked_margin(margin)
        stood = self._stood if self._stood is not None and self._stood[0] >= margin else None
        model = design.model
        analysis = analyze(
            model,
            self._options(margin),
            stood=stood[1] if stood is not None and stood[1].model is model else None,
        )
        if analysis.feasible and margin > 0:
            # A search judges with a reserve and reports without one: the forces that stand
            # with the reserve certify the design without another solve.
            self._stood = (margin, analysis)
        return Assessment(
            structure=self.name,
            stands=bool(analysis.feasible),
            measure=float(analysis.infeasibility_normalized),
            status=analysis.status.value,
            section=analysis.to_report(),
            detail=analysis,
            margin=float(margin),
        )

    def measure_change(self, base: Assessment, moved: Design) -> float | None:
        return infeasibility_change(base.detail, moved.model, self._options(base.margin))
