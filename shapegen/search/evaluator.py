"""One design per parameter vector: build it (when the structure needs a model), judge it, cache.

The gradient of the measure comes from the structure when it gives one (for block statics the
adjoint of :mod:`shapegen.statics.sensitivity`: one QP per gradient, a rebuild and an assembly per
parameter) and from forward differences of whole evaluations otherwise.
"""

from __future__ import annotations

__all__ = ["Evaluation", "Evaluator", "ADJOINT_STEP", "FORWARD_STEP"]

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import numpy as np

from shapegen.errors import GeometryError, GrammarError, StaticsError
from shapegen.model import Model
from shapegen.model.lot import Lot
from shapegen.search.parameters import FreeParameter
from shapegen.structures import Assessment, Design, Reserve, Structure

# Relative step (fraction of a parameter's range) of the finite differences on the geometry and,
# for the forward-difference gradient, on the whole evaluation. The geometry is exact to
# round-off, so a small step is safe there; the QP solution is accurate to ~1e-9, so forward
# differences of the measure need a larger step.
ADJOINT_STEP = 1e-6
FORWARD_STEP = 1e-4


@dataclass
class Evaluation:
    """One design judged at ``theta``."""

    theta: np.ndarray
    design: Design | None
    assessment: Assessment | None
    infeasibility: float  # the structure's measure; inf when the evaluation failed
    feasible: bool
    error: str | None = None

    @property
    def ok(self) -> bool:
        return self.error is None and math.isfinite(self.infeasibility)

    @property
    def model(self) -> Model | None:
        """The design's model if it was built."""
        return self.design.model if self.design is not None and self.design.built else None


class Evaluator:
    """Judges the design at parameter values theta with one structure; counts; caches."""

    def __init__(
        self,
        grammar,
        structure: Structure,
        parameters: Sequence[FreeParameter],
        attrs: Mapping[str, object] | None = None,
        *,
        seed: int = 0,
        lot: Lot | None = None,
        margin: Reserve | float = 0.0,
    ):
        self.grammar = grammar
        self.structure = structure
        self.parameters = list(parameters)
        self.attrs = dict(attrs or {})
        self.seed = seed
        self.lot = Lot.of(lot) if lot is not None else None
        self.margin = Reserve.of(margin)  # the search's own passes as it is
        self.evaluations = 0
        self._cache: dict[tuple, Evaluation] = {}
        self._gradients: dict[tuple, np.ndarray] = {}

    @property
    def lower(self) -> np.ndarray:
        return np.array([p.lower for p in self.parameters])

    @property
    def upper(self) -> np.ndarray:
        return np.array([p.upper for p in self.parameters])

    def named(self, theta: np.ndarray) -> dict[str, float]:
        return {p.name: float(v) for p, v in zip(self.parameters, theta, strict=True)}

    def attrs_at(self, theta: np.ndarray) -> dict[str, object]:
        """Every attr override of the design at ``theta``."""
        return {**self.attrs, **self.named(theta)}

    def design(self, theta: np.ndarray) -> Design:
        """The design at ``theta``: its ``@Structure`` arguments now, its model when asked."""
        attrs = self.attrs_at(theta)
        arguments = (
            self.grammar.structure_arguments(attrs, self.seed, self.lot)
            if self.structure.arguments
            else {}
        )
        return Design(
            arguments, build=lambda: self.grammar.build(attrs=attrs, seed=self.seed, lot=self.lot)
        )

    def evaluate(self, theta: np.ndarray) -> Evaluation:
        """Judge the design at ``theta`` (cached: the methods ask twice for the same point)."""
        theta = np.clip(np.asarray(theta, float), self.lower, self.upper)
        key = tuple(np.round(theta, 15))
        if key in self._cache:
            return self._cache[key]
        try:
            design = self.design(theta)
            assessment = self.structure.assess(design, margin=self.margin)
            self.evaluations += 1
            measure = float(assessment.measure)
            evaluation = Evaluation(theta, design, assessment, measure, bool(assessment.stands))
            if not math.isfinite(measure):
                evaluation.error = f"the {self.structure.name} assessment: {assessment.status}"
        except (GrammarError, GeometryError, StaticsError) as exc:
            message = str(exc).splitlines()[0]
            evaluation = Evaluation(theta, None, None, math.inf, False, message)
        self._cache[key] = evaluation
        return evaluation

    # ------------------------------------------------------------------ gradients
    def gradient(self, theta: np.ndarray, method: str = "adjoint") -> np.ndarray:
        """``d measure / d theta`` (per unit of each parameter); zero where not judged."""
        base = self.evaluate(theta)
        if not base.ok:
            return np.zeros(len(self.parameters))
        key = (tuple(np.round(base.theta, 15)), method)
        if key not in self._gradients:  # the search's scale and its first step ask for the same
            step = self._adjoint if method == "adjoint" else self._forward
            self._gradients[key] = np.array([step(base, j) for j in range(len(self.parameters))])
        return self._gradients[key].copy()

    def _step(self, theta: np.ndarray, j: int, relative: float) -> float:
        h = relative * self.parameters[j].span
        # step inwards at the upper bound so the probe stays within the range
        return -h if theta[j] + h > self.parameters[j].upper else h

    def _forward(self, base: Evaluation, j: int) -> float:
        h = self._step(base.theta, j, FORWARD_STEP)
        probe = base.theta.copy()
        probe[j] += h
        other = self.evaluate(probe)
        if not other.ok:
            return 0.0
        return (other.infeasibility - base.infeasibility) / h

    def _adjoint(self, base: Evaluation, j: int) -> float:
        h = self._step(base.theta, j, ADJOINT_STEP)
        probe = base.theta.copy()
        probe[j] += h
        try:
            change = self.structure.measure_change(base.assessment, self.design(probe))
        except (GrammarError, GeometryError, StaticsError):
            change = None
        if change is None:  # the contacts changed, or no adjoint here: a whole evaluation
            return self._forward(base, j)
        return change / h
